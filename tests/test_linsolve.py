"""The sparse solver interface (fem.linsolve) and the vectorised P2 stiffness.

Reference: SciPy's SuperLU with its default options (no use of fem.linsolve), on a real
body of the project: the pin of the pin-housing drive with a coarse load patch (b_ref =
0.4 mm keeps its mesh small), held over its outer half. Every available backend must give
the reference's displacements and flexibilities to 1e-10 relative (round-off of a
well-conditioned direct solve is ~1e-13 here; the margin covers other orderings).
"""
import numpy as np
import pytest
from scipy.sparse.linalg import splu

from toothfem import ToothfemError, load_case
from toothfem.fem import cycloid_fe as cf
from toothfem.fem import linsolve
from toothfem.fem.drives import drive_for
from toothfem.fem.elastic import lame_parameters, stiffness_matrix

#: Agreement between backends and SuperLU (relative to the largest entry).
BACKEND_RTOL = 1e-10
#: The vectorised stiffness against scikit-fem's assembly: same integrals, exact
#: quadratures of different order, so round-off only.
ASSEMBLY_RTOL = 1e-12


@pytest.fixture(scope="module")
def pin_problem(cases_dir):
    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    model = drive_for(case).fe_model(pin_structure="conventional")
    pin = cf.PinModel(model.geometry.pin_radius_m, model.youngs_modulus, model.poisson_ratio,
                      2e-4, model.plane)
    body = pin.body
    pts = pin.radius * np.stack([-np.cos(pin.angles), -np.sin(pin.angles)])
    loads = cf.patch_loads(body, "outer", pts, -pts / pin.radius, pin.b_ref)
    free, _ = body._dofs
    k = body.stiffness[free][:, free].tocsc()
    b = loads.tocsr()[free].tocsc()
    ref = b.T @ splu(k).solve(b.toarray())
    return k, b, 0.5 * (ref + ref.T)


def _rel(a, b):
    return np.max(np.abs(a - b)) / np.max(np.abs(b))


@pytest.mark.parametrize("backend", linsolve.available_backends())
def test_backend_equals_superlu_on_a_real_body(pin_problem, backend):
    k, b, ref = pin_problem
    f = linsolve.factorize(k, backend)
    assert f.backend == backend
    u = f.solve(b.toarray())
    assert _rel(b.T @ u, ref) < BACKEND_RTOL
    assert _rel(f.solve(b[:, 3].toarray()[:, 0]), u[:, 3]) < BACKEND_RTOL    # one vector
    assert _rel(f.flexibility(b), ref) < BACKEND_RTOL
    sizes = [10, 1, 26]
    blocks = f.flexibility(b, sizes)
    edges = np.cumsum([0] + sizes)
    for blk, lo, hi in zip(blocks, edges[:-1], edges[1:]):
        assert blk.shape == (hi - lo, hi - lo)
        assert _rel(blk, ref[lo:hi, lo:hi]) < BACKEND_RTOL


@pytest.mark.parametrize("backend", linsolve.available_backends())
def test_both_routes_of_the_flexibility_agree(pin_problem, backend):
    """The forward substitution on the reached rows and the full solves give one result
    (the cost model picks one; both are exercised here)."""
    k, b, ref = pin_problem
    f = linsolve.factorize(k, backend)
    assert _rel(f._by_solves(b.tocsc(), [b.shape[1]])[0], ref) < BACKEND_RTOL
    tri = f.triangle()
    inv = np.empty(k.shape[0], int)
    inv[tri.order] = np.arange(k.shape[0])
    from scipy.sparse import csc_matrix

    pb = csc_matrix((b.data, inv[b.indices], b.indptr), shape=b.shape)
    plan = linsolve._plan(tri, pb, [b.shape[1]])
    assert linsolve._union(plan[0]).size < k.shape[0]   # the loads reach part of the factor only
    assert _rel(linsolve._forward(tri, pb, plan)[0], ref) < BACKEND_RTOL


def test_vectorised_stiffness_equals_scikit_fem(cases_dir):
    from skfem import asm
    from skfem.models.elasticity import linear_elasticity

    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    model = drive_for(case).fe_model(pin_structure="conventional")
    body = cf.PinModel(model.geometry.pin_radius_m, model.youngs_modulus,
                       model.poisson_ratio, 2e-4, model.plane).body
    lam, mu = lame_parameters(model.youngs_modulus, model.poisson_ratio, "strain")
    ref = asm(linear_elasticity(lam, mu), body.basis)
    assert abs(stiffness_matrix(body.basis, lam, mu) - ref).max() / abs(ref).max() \
        < ASSEMBLY_RTOL


def test_backend_is_chosen_by_argument_then_environment(monkeypatch):
    assert "superlu" in linsolve.available_backends()
    monkeypatch.delenv(linsolve.BACKEND_ENV, raising=False)
    assert linsolve.choose_backend() == linsolve.available_backends()[0]
    monkeypatch.setenv(linsolve.BACKEND_ENV, "superlu")
    assert linsolve.choose_backend() == "superlu"
    assert linsolve.choose_backend(linsolve.available_backends()[0]) \
        == linsolve.available_backends()[0]
    with pytest.raises(ToothfemError, match="solver backend = 'umfpack' is not one of"):
        linsolve.choose_backend("umfpack")
    monkeypatch.setenv(linsolve.BACKEND_ENV, "nope")
    with pytest.raises(ToothfemError, match="'nope'"):
        linsolve.choose_backend()


def test_blocks_must_cover_the_columns(pin_problem):
    k, b, _ = pin_problem
    with pytest.raises(ToothfemError, match="blocks sum to 5"):
        linsolve.factorize(k, "superlu").flexibility(b, [5])
