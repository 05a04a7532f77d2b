"""Sparse direct solves of a body's stiffness: one factorisation, block right-hand sides.

The stiffness of a supported body is symmetric positive definite, so it factorises as
P K P^T = L D L^T with no pivoting. Two operations are needed:

* :meth:`Factor.solve`: displacements K^-1 B for dense block loads B (n, k);
* :meth:`Factor.flexibility`: the condensed flexibility B^T K^-1 B of sparse unit loads B
  (a handful of dofs each), per block of columns. Only the forward substitution is needed,
  B^T K^-1 B = W^T D^-1 W with W = L^-1 P B, and W is zero outside the rows that the
  elimination tree reaches from B's nonzero rows (Gilbert & Peierls 1988; Davis, *Direct
  Methods for Sparse Linear Systems*, SIAM 2006, sec. 3.2 and 4.1). The solve runs on that
  sub-triangle alone, for each set of loads that share rows (one pin's contact window of a
  disc: 1.7k of its 68k rows, where all the windows together reach 19k).

Backends, chosen by availability in the order of :data:`BACKENDS` (fastest first, measured
on the pin-housing disc and pin; README "Faster solves"), or forced by the ``backend``
argument or the environment variable ``TOOTHFEM_SOLVER``:

* ``"cholmod"``: CHOLMOD's Cholesky through scikit-sparse 0.4 (optional extra ``[fast]``,
  needs the SuiteSparse library, e.g. Debian's ``libsuitesparse-dev``);
* ``"superlu"``: SciPy's SuperLU, always installed; symmetric mode with a minimum degree
  ordering on K^T + K and no pivoting (the diagonal of an SPD matrix is a valid pivot), so
  the factor is L (D L^T) with the same row and column order.

Both give results equal to 1e-10 relative (tests/test_linsolve.py).

Evaluated on the same matrices and not kept (disc of 68k dofs with 729 loads, each
against SuperLU in the same run): MKL PARDISO through pypardiso (factorisation alike,
block solves 2.5x slower on one thread, and a 200 MB MKL wheel); MUMPS through
python-mumps on Debian's sequential MUMPS (factorisation 10x and solves 15x slower);
CHOLMOD's supernodal mode (slower triangular solves than its simplicial mode on these 2D
meshes); SuperLU with COLAMD (twice the fill of the minimum degree on K^T + K).
"""
from __future__ import annotations

import contextlib
import functools
import os
import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ToothfemError

if TYPE_CHECKING:
    from scipy.sparse import csc_matrix

#: Environment variable that forces a backend (tests, benchmarks).
BACKEND_ENV = "TOOTHFEM_SOLVER"
#: Backends, fastest first.
BACKENDS = ("cholmod", "superlu")


def _cholmod():
    """scikit-sparse's CHOLMOD module if the 0.4 API is installed (0.5 renamed it), else
    None."""
    try:
        from sksparse import cholmod
    except ImportError:
        return None
    return cholmod if hasattr(cholmod, "Factor") and hasattr(cholmod, "cholesky") else None


@functools.cache
def _blas_threads():
    """The BLAS libraries loaded (found once: each search reads the process's memory map)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


_LIMITED = threading.local()


@contextlib.contextmanager
def one_blas_thread():
    """Context in which BLAS runs on one thread. The sparse solves call BLAS on small
    supernodal blocks and the contact solves on systems of tens to hundreds of unknowns:
    a second thread gains little there, and on a busy machine (or beside other workers)
    its waiting costs up to 20x (measured on 2 cores at load 7: a 400 x 400 dense solve
    took 8 ms on one thread, 163 ms on two). Re-entrant: inside another such context it
    costs nothing (a limit set per contact solve took a tenth of a sampled cycle).

    Yields
    ------
    None
        Control, with BLAS limited to one thread until the context exits.
    """
    if getattr(_LIMITED, "depth", 0):
        _LIMITED.depth += 1
        try:
            yield
        finally:
            _LIMITED.depth -= 1
        return
    with _blas_threads().limit(limits=1, user_api="blas"):
        _LIMITED.depth = 1
        try:
            yield
        finally:
            _LIMITED.depth = 0


def available_backends() -> tuple[str, ...]:
    """The backends that import here.

    Returns
    -------
    tuple of str
        Names from :data:`BACKENDS`, fastest first ("superlu" always).
    """
    return tuple(b for b in BACKENDS if b == "superlu" or _cholmod() is not None)


def choose_backend(backend: str | None = None) -> str:
    """``backend`` if given, else ``$TOOTHFEM_SOLVER`` if set, else the fastest available.

    Parameters
    ----------
    backend : str or None
        One of :data:`BACKENDS`, or None.

    Returns
    -------
    str
        The backend's name.

    Raises
    ------
    ToothfemError
        For an unknown name or a backend that is not installed.
    """
    name = backend or os.environ.get(BACKEND_ENV, "") or available_backends()[0]
    if name not in BACKENDS:
        raise ToothfemError(f"solver backend = {name!r} is not one of {list(BACKENDS)}")
    if name not in available_backends():
        raise ToothfemError(f"solver backend = {name!r} is not installed here (available: "
                            f"{list(available_backends())}; see the README, 'Faster solves')")
    return name


def factorize(matrix, backend: str | None = None) -> Factor:
    """Factorise an SPD sparse matrix with the chosen backend.

    Parameters
    ----------
    matrix : sparse (n, n)
        Symmetric positive definite (a held body's stiffness).
    backend : str or None
        As for :func:`choose_backend`.

    Returns
    -------
    Factor
        The factorisation.

    Raises
    ------
    ToothfemError
        For an unknown or missing backend, or when SuperLU pivots off the diagonal.
    """
    from scipy.sparse import csc_matrix

    matrix = csc_matrix(matrix)
    name = choose_backend(backend)
    with one_blas_thread():
        return _cholmod_factor(matrix) if name == "cholmod" else _superlu_factor(matrix)


#: Columns solved at once on the full-solve route (bounds memory to chunk x n doubles).
SOLVE_CHUNK = 64
#: Columns of W = L^-1 P B solved at once on the forward route (whole blocks): bounds the
#: parts' W and the dense rows they share (a few MB for a disc's contact windows).
FORWARD_CHUNK = 256
#: Flop rate of the dense products W^T D^-1 W (BLAS 3) over that of the sparse triangular
#: solves, in the cost model of :meth:`Factor.flexibility` (measured here: about 10).
DENSE_SPEEDUP = 10.0


@dataclass(frozen=True)
class Triangle:
    """A lower triangular factor T of P K P^T = T diag(1/weights) T^T: ``lower`` T (n, n)
    CSC with sorted indices, ``weights`` (n,) > 0, ``order`` (n,) with (P B)[i] =
    B[order[i]], ``unit`` whether T's diagonal is one (what is stored there is then not
    read), ``parent`` (n,) the elimination tree (-1 at a root). Then B^T K^-1 B =
    V^T diag(weights) V with V = T^-1 P B: T = L and weights = 1/D for P K P^T = L D L^T."""
    lower: csc_matrix
    weights: np.ndarray
    order: np.ndarray
    unit: bool
    parent: np.ndarray


class Factor:
    """P K P^T = L D L^T of an SPD matrix (n, n).

    ``solve(rhs)`` is the backend's full solve; ``triangle()`` the factor as a
    :class:`Triangle`, extracted from the backend at each call and not kept (it would
    double the factor's memory, e.g. for the 22 bodies of a detailed solve).

    Parameters
    ----------
    backend : str
        The backend's name (:data:`BACKENDS`).
    n : int
        Order of the matrix.
    solve : callable
        Dense (n, k) right-hand sides -> K^-1 rhs (n, k).
    triangle : callable
        () -> (lower, weights, order, unit), the fields of :class:`Triangle` but the tree.
    """

    def __init__(self, backend, n, solve, triangle):
        self.backend = backend
        self.shape = (n, n)
        self._solve = solve
        self._triangle = triangle

    def triangle(self) -> Triangle:
        """The factor's arrays, extracted now.

        Returns
        -------
        Triangle
            The lower factor, sorted, with weights, order and elimination tree.

        Raises
        ------
        ToothfemError
            When a pivot is not positive (the matrix is not positive definite).
        """
        lower, weights, order, unit = self._triangle()
        if not np.all(np.asarray(weights) > 0):
            raise ToothfemError("a pivot of the factorisation is not positive: the stiffness "
                                "is not positive definite (is the body held?)")
        lower = lower.tocsc()
        lower.sort_indices()
        return Triangle(lower, np.asarray(weights, float), np.asarray(order), unit,
                        _etree_parent(lower))

    def solve(self, rhs) -> np.ndarray:
        """K^-1 rhs.

        Parameters
        ----------
        rhs : array_like
            Dense (n,) or (n, k).

        Returns
        -------
        numpy.ndarray
            The solution, the shape of ``rhs``.
        """
        rhs = np.asarray(rhs, float)
        with one_blas_thread():
            if rhs.ndim == 1:
                return self._solve(rhs[:, None])[:, 0]
            return self._solve(np.ascontiguousarray(rhs))

    def flexibility(self, loads, blocks=None, coupling=None):
        """B^T K^-1 B for sparse ``loads`` B (n, k).

        By the forward substitution on the rows B reaches (module docstring) when that is
        the cheaper way, else by full solves in chunks of :data:`SOLVE_CHUNK` columns: the
        forward route pays nnz(L_RR) k_R for the solve of each set of k_R columns that share
        rows, on the rows R they reach (:func:`_plan`), and |R| sum(k_i^2) / DENSE_SPEEDUP
        for the products W_i^T D^-1 W_i, the full route 2 nnz(L) k (loads spread over the
        whole body favour it).

        Parameters
        ----------
        loads : sparse (n, k)
        blocks : sequence of column counts summing to k, or None
        coupling : sparse (k, k) or None
            Nonzero where two loads act on coupled unknowns, e.g. |B|^T |K| |B| (nodal
            loads on neighbouring nodes share no row but reach nearly the same rows): the
            forward route solves the columns linked by it, or by shared rows, together.

        Returns
        -------
        (k, k) array, symmetric; or, with ``blocks``, the list of the diagonal blocks
        (k_i, k_i), the cross terms between blocks being neither computed nor stored.

        Raises
        ------
        ToothfemError
            When ``blocks`` do not sum to k.
        """
        from scipy.sparse import csc_matrix

        loads = csc_matrix(loads)
        n, k = loads.shape
        counts = [k] if blocks is None else [int(b) for b in blocks]
        if sum(counts) != k:
            raise ToothfemError(f"blocks sum to {sum(counts)}, loads have {k} columns")
        tri = self.triangle()
        inv = np.empty(n, int)
        inv[tri.order] = np.arange(n)
        pb = csc_matrix((loads.data, inv[loads.indices], loads.indptr), shape=(n, k))
        plan = _plan(tri, pb, counts, coupling)
        nnz = np.diff(tri.lower.indptr)
        forward = sum(sum(int(np.sum(nnz[p.rows])) * p.columns.size for p in g.parts)
                      + _union(g).size * sum(c * c for c in g.counts) / DENSE_SPEEDUP
                      for g in plan)
        with one_blas_thread():
            if forward < 2 * tri.lower.nnz * k:
                out = _forward(tri, pb, plan)
            else:
                out = self._by_solves(loads, counts)
        return out[0] if blocks is None else out

    def _by_solves(self, loads, counts):
        out, start = [], 0
        for c in counts:
            blk = np.empty((c, c))
            for i in range(0, c, SOLVE_CHUNK):
                b = loads[:, start + i:start + min(i + SOLVE_CHUNK, c)]
                blk[:, i:i + b.shape[1]] = loads[:, start:start + c].T @ self.solve(b.toarray())
            out.append(0.5 * (blk + blk.T))
            start += c
        return out


@dataclass(frozen=True)
class _Part:
    """Columns of the loads that share nonzero rows (indices into the loads' columns), and
    the rows of T^-1 P B they reach by the elimination tree (sorted)."""
    columns: np.ndarray
    rows: np.ndarray


@dataclass(frozen=True)
class _Group:
    """Whole blocks of at most FORWARD_CHUNK columns from ``start``, split into parts."""
    start: int
    counts: list
    parts: list


def _plan(tri: Triangle, pb, counts, coupling=None) -> list:
    """The groups of whole blocks (:func:`_groups`) and, in each, the parts of its columns
    linked by shared rows or by ``coupling`` (:func:`_linked_columns`) with their reach:
    loads far apart on a body (one pin's contact window each) reach only their own branches
    of the elimination tree and the top separators, a sixth of the rows all of them reach
    together on a cycloid disc, so each part is solved on its own rows."""
    from scipy.sparse import csr_matrix

    parent = tri.parent.tolist()        # list items: a fast walk in Python
    coupling = None if coupling is None else csr_matrix(coupling)
    out, start = [], 0
    for group in _groups(counts, FORWARD_CHUNK):
        width = sum(group)
        block = pb[:, start:start + width]
        links = None if coupling is None else \
            coupling[start:start + width][:, start:start + width]
        parts = [_Part(start + cols, _reach(parent, np.unique(block[:, cols].indices)))
                 for cols in _linked_columns(block, links)]
        out.append(_Group(start, group, parts))
        start += width
    return out


def _union(group: _Group) -> np.ndarray:
    """The rows its parts reach together."""
    return np.unique(np.concatenate([p.rows for p in group.parts] + [np.empty(0, int)]))


def _linked_columns(b, links=None) -> list:
    """Column index sets of ``b`` (n, k) connected through shared nonzero rows or the
    nonzeros of ``links`` (k, k)."""
    from scipy.sparse.csgraph import connected_components

    pattern = (b != 0).astype(np.int8)
    graph = pattern.T @ pattern
    if links is not None:
        graph = graph + (links != 0).astype(np.int8)
    count, labels = connected_components(graph, directed=False)
    return [np.flatnonzero(labels == i) for i in range(count)]


def _forward(tri: Triangle, pb, plan):
    """The diagonal blocks of V^T diag(weights) V, V = T^-1 P B, group by group of the
    ``plan`` (:func:`_plan`): each part's columns solved on the sub-triangle of its rows
    (:func:`_gram` then forms the blocks)."""
    from scipy.sparse.linalg import spsolve_triangular

    scale = np.sqrt(tri.weights)        # V^T diag(weights) V = (V s)^T (V s)
    out = []
    for group in plan:
        solved = []
        for part in group.parts:
            if part.rows.size == 0:     # an empty load: V is zero there
                continue
            rows, sub = _sub_triangle(tri, part.rows)
            v = spsolve_triangular(sub, pb[:, part.columns][rows].toarray(), lower=True,
                                   unit_diagonal=tri.unit, overwrite_A=True,
                                   overwrite_b=True)
            solved.append((rows, part.columns - group.start, v * scale[rows, None]))
        out += _gram(solved, group.counts, tri.lower.shape[0])
    return out


def _gram(solved, counts, n):
    """The diagonal blocks (sizes ``counts``) of V^T V for V (n, sum(counts)) given by parts
    ``solved`` = [(rows, columns, values (rows, columns))], each part's columns zero off its
    rows. The rows one part alone reaches add that part's own V_p^T V_p; the rows several
    parts reach (the top separators) are gathered into one dense V_S whose V_S^T V_S
    couples the parts: on a detailed cycloid disc (860 loads at 20 pins) V_S has a tenth
    of the rows of V (bounds V_S to |S| x FORWARD_CHUNK doubles on the cycle route)."""
    from scipy.linalg.blas import dsyrk

    def syrk(v):    # V^T V by the symmetric rank-k update (half the flops of the product)
        upper = dsyrk(1.0, np.asfortranarray(v.T), trans=0)
        return np.triu(upper) + np.triu(upper, 1).T

    width = sum(counts)
    reached = np.bincount(np.concatenate([r for r, _, _ in solved] + [np.empty(0, int)]),
                          minlength=n)
    shared = np.flatnonzero(reached > 1)
    at_shared = np.full(n, -1)
    at_shared[shared] = np.arange(shared.size)
    v_s = np.zeros((shared.size, width))
    edges = np.cumsum([0] + list(counts))
    block_of = np.searchsorted(edges, np.arange(width), side="right") - 1
    out = [None] * len(counts)
    own = []
    for rows, cols, v in solved:
        here = at_shared[rows]
        v_s[np.ix_(here[here >= 0], cols)] = v[here >= 0]
        own.append((cols, syrk(v[here < 0])))
    for b, (lo, hi) in enumerate(zip(edges[:-1], edges[1:])):
        out[b] = syrk(v_s[:, lo:hi])
    for cols, g in own:
        for b in np.unique(block_of[cols]):
            sel = np.flatnonzero(block_of[cols] == b)
            out[b][np.ix_(cols[sel] - edges[b], cols[sel] - edges[b])] += g[np.ix_(sel, sel)]
    return out


def _reach(parent: list, start) -> np.ndarray:
    """Rows of T^-1 b reached from the rows ``start`` of b: their ancestors in the
    elimination tree ``parent`` (Davis 2006, Thm 4.1), sorted."""
    mark = np.zeros(len(parent), bool)
    for s in start.tolist():
        while s >= 0 and not mark[s]:
            mark[s] = True
            s = parent[s]
    return np.flatnonzero(mark)


def _sub_triangle(tri: Triangle, rows):
    """(rows, T[rows][:, rows] in CSC): the rows as given when T's columns there have no
    entry outside them (a factor that stores padding zeros may break that closure), else
    every row (still exact)."""
    from scipy.sparse import csc_matrix

    n = tri.lower.shape[0]
    cols = tri.lower[:, rows]
    at_row = np.full(n, -1)
    at_row[rows] = np.arange(rows.size)
    index = at_row[cols.indices]
    if np.any(index < 0):
        return np.arange(n), tri.lower.copy()
    return rows, csc_matrix((cols.data, index, cols.indptr), shape=(rows.size, rows.size))


def _groups(counts, limit) -> list:
    """Consecutive runs of ``counts`` whose sums stay within ``limit`` (a larger count
    alone)."""
    out: list[list] = []
    cur: list = []
    for c in counts:
        if cur and sum(cur) + c > limit:
            out.append(cur)
            cur = []
        cur.append(c)
    return out + [cur] if cur else out


def _etree_parent(lower) -> np.ndarray:
    """Parent of each column in the elimination tree of a lower factor (sorted CSC): the row
    of its first entry below the diagonal, -1 at a root."""
    n = lower.shape[0]
    start, stop = lower.indptr[:-1], lower.indptr[1:]
    cols = np.arange(n)
    diag_first = (stop > start) & (lower.indices[np.minimum(start, lower.nnz - 1)] == cols)
    below = start + diag_first
    parent = np.full(n, -1)
    has = below < stop
    parent[has] = lower.indices[below[has]]
    return parent


def _superlu_factor(matrix) -> Factor:
    from scipy.sparse import csc_matrix
    from scipy.sparse.linalg import splu

    # minimum degree on K^T + K in symmetric mode: half the fill of COLAMD on these FE
    # matrices (5.3M against 9.5M nonzeros for the 68k-dof disc); no pivoting (SPD)
    lu = splu(matrix, permc_spec="MMD_AT_PLUS_A",
              options=dict(SymmetricMode=True, DiagPivotThresh=0.0))
    if not np.array_equal(lu.perm_r, lu.perm_c):
        raise ToothfemError("SuperLU pivoted off the diagonal: the stiffness is not "
                            "positive definite (is the body held?)")
    # U = D L^T: L = U^T D^-1 from U alone (its transpose comes sorted; SuperLU's L would
    # need a sort, and U its diagonal all the same). SuperLU keeps U once handed out: the
    # Body's memory grows by half the factor after its first flexibility.
    def triangle():
        upper = lu.U
        d = upper.diagonal()
        scaled = csc_matrix((upper.data / d[upper.indices], upper.indices, upper.indptr),
                            shape=upper.shape)     # D^-1 U = L^T (a new array: U is kept)
        return scaled.T.tocsc(), 1 / d, np.argsort(lu.perm_r), True
    return Factor("superlu", matrix.shape[0], lu.solve, triangle)


def _cholmod_factor(matrix) -> Factor:
    cholmod = _cholmod()
    # simplicial L D L^T: its triangular solves beat the supernodal ones on these 2D
    # meshes (measured, README "Faster solves")
    f = cholmod.cholesky(matrix, mode="simplicial")

    def triangle():
        # L and D packed in one matrix (D on the diagonal): the unit-diagonal solve
        # reads no diagonal (L_D() would split them at the cost of two sparse sums)
        packed = f.LD()
        return packed, 1 / packed.diagonal(), f.P(), True
    return Factor("cholmod", matrix.shape[0], f.solve_A, triangle)
