"""The public API carries numpydoc sections (issue 10, item 7).

Walks toothfem, toothfem.geometry, toothfem.fem and toothfem.efficiency with importlib and
inspect. Every public function, method and hand-written constructor defined in the project
(names without a leading underscore, in modules without one) whose signature has parameters
other than ``self``/``cls`` needs a ``Parameters`` section, and every one that returns
something (return annotation other than None; without an annotation, a ``return <value>``
in its body) needs a ``Returns`` (or, for a generator, ``Yields``) section. Dataclass
records are exempt here: their fields are their documentation (the generated ``__init__``
has no docstring of its own).

Run ``python tests/test_docstrings.py`` to list what is missing (``--all``: in the
allow-listed modules too).
"""
from __future__ import annotations

import ast
import dataclasses
import importlib
import inspect
import pkgutil
import re
import textwrap


ROOTS = ("toothfem", "toothfem.geometry", "toothfem.fem", "toothfem.efficiency")

#: Dunder methods that are checked; the others (__post_init__, __repr__, __eq__, __len__,
#: __iter__, __getitem__, ...) follow Python's protocol and say nothing a reader needs.
CHECKED_DUNDERS = ("__init__", "__call__")

# Not checked, by rule: properties (documented as attributes: one summary line with the
# unit, numpydoc's convention) and the __init__ that @dataclass writes (the record's fields,
# named with their units, are its documentation; see the module docstring).

_SECTION = r"^[ \t]*{}[ \t]*\r?\n[ \t]*-{{3,}}[ \t]*$"


def _has_section(doc, *names) -> bool:
    return any(re.search(_SECTION.format(n), doc or "", re.M) for n in names)


def _public_modules():
    """Every module of the four packages without a leading underscore in its name."""
    names = set()
    for root in ROOTS:
        pkg = importlib.import_module(root)
        names.add(root)
        for info in pkgutil.walk_packages(pkg.__path__, prefix=root + "."):
            names.add(info.name)
    return sorted(n for n in names if not any(part.startswith("_") for part in n.split(".")))


def _returns_value(func) -> tuple[bool, bool]:
    """(returns a value, is a generator) from the annotation, else from the body."""
    ann = inspect.signature(func).return_annotation
    if inspect.isgeneratorfunction(func):
        return True, True
    if ann is not inspect.Signature.empty:
        return ann not in (None, "None"), False
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(func)))
    except (OSError, TypeError, SyntaxError):
        return False, False
    body = tree.body[0]
    stack = list(body.body)
    while stack:
        node = stack.pop()
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef, ast.Lambda)):
            continue
        if isinstance(node, ast.Return) and node.value is not None and not (
                isinstance(node.value, ast.Constant) and node.value.value is None):
            return True, False
        stack.extend(ast.iter_child_nodes(node))
    return False, False


def _has_params(func, method: bool) -> bool:
    params = list(inspect.signature(func).parameters)
    if method and params and params[0] in ("self", "cls"):
        params = params[1:]
    return bool(params)


def _generated(func) -> bool:
    """True for a function without source (the ``__init__`` @dataclass writes)."""
    try:
        inspect.getsource(func)
    except (OSError, TypeError):
        return True
    return False


def _callables(modname):
    """(qualified name, function, is a method, class docstring or None) of a module."""
    module = importlib.import_module(modname)
    for name, obj in vars(module).items():
        if name.startswith("_") or getattr(obj, "__module__", None) != modname:
            continue
        obj = inspect.unwrap(obj) if callable(obj) and not inspect.isclass(obj) else obj
        if inspect.isfunction(obj):
            yield f"{modname}.{name}", obj, False, None
        elif inspect.isclass(obj):
            for attr, raw in vars(obj).items():
                if attr.startswith("_") and attr not in CHECKED_DUNDERS:
                    continue
                func = raw.__func__ if isinstance(raw, (staticmethod, classmethod)) else raw
                func = inspect.unwrap(func) if callable(func) else func
                if not inspect.isfunction(func) or func.__module__ != modname:
                    continue
                if attr == "__init__" and dataclasses.is_dataclass(obj) and _generated(func):
                    continue
                method = not isinstance(raw, staticmethod)
                class_doc = obj.__doc__ if attr == "__init__" else None
                yield f"{modname}.{name}.{attr}", func, method, class_doc


def gaps(modnames):
    """Every public callable of ``modnames`` lacking a section it needs, as
    'name: section' lines."""
    out = []
    for modname in modnames:
        for qual, func, method, class_doc in _callables(modname):
            doc = (func.__doc__ or "") + "\n" + (class_doc or "")
            if _has_params(func, method) and not _has_section(doc, "Parameters"):
                out.append(f"{qual}: Parameters")
            returns, gen = _returns_value(func)
            if returns and qual.rsplit(".", 1)[-1] != "__init__" and not _has_section(
                    doc, "Yields" if gen else "Returns", "Returns"):
                out.append(f"{qual}: {'Yields' if gen else 'Returns'}")
    return out


def missing():
    """:func:`gaps` of every public module (every one is documented: the allow-list of
    issue 10 emptied and went)."""
    return gaps(_public_modules())


def test_public_api_has_numpydoc_sections():
    found = missing()
    assert not found, (f"{len(found)} public callables lack numpydoc sections:\n"
                       + "\n".join(found))


def _documented(x: float, *, flag=False) -> float:
    """A summary.

    Parameters
    ----------
    x : float
        A value [m].
    flag : bool
        Unused.

    Returns
    -------
    float
        ``x`` [m].
    """
    return x


def _undocumented(x, y=None):
    """A summary without sections."""
    if y is None:
        return x
    return None


def _no_value(x) -> None:
    """Returns nothing: no Returns section needed, but Parameters are."""


def test_checker_tells_documented_from_undocumented():
    """The helpers the walk uses, on functions of known state."""
    assert _has_section(_documented.__doc__, "Parameters")
    assert _has_section(_documented.__doc__, "Returns")
    assert not _has_section(_undocumented.__doc__, "Parameters")
    assert _returns_value(_documented) == (True, False)
    assert _returns_value(_undocumented) == (True, False)      # no annotation: the body
    assert _returns_value(_no_value) == (False, False)
    assert _has_params(_no_value, method=False)
    assert not _has_params(lambda self: None, method=True)


if __name__ == "__main__":
    import sys

    everything = "--all" in sys.argv
    for line in gaps(_public_modules()) if everything else missing():
        print(line)
