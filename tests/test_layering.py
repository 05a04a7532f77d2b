"""Imports run one way (docs/architecture.md): geometry -> fem -> efficiency ->
efficiency.loop -> the pieces the layouts are built from -> the layouts -> the top
(toothfem's case, pipeline, reports, commands), at module and at function level, the base
modules open to every layer; and no private name crosses a package boundary."""
from __future__ import annotations

import ast
import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import typecheck  # noqa: E402  (tools/typecheck.py: the package's modules by the mapping)
#: Every layer may import these (exceptions, ranges, limits, SI records, units, progress).
BASE = {"toothfem.errors", "toothfem.limits", "toothfem.case_checks", "toothfem.leftovers",
        "toothfem.bars", "toothfem.layout",
        "toothfem.signals", "toothfem.si", "toothfem.units"}
#: Layer of a module by its package prefix (the longest prefix wins): the cores, the
#: layouts above them (toothfem/layouts/, which take the cores' pieces), the top above.
LAYERS = {"toothfem.geometry": 0, "toothfem.fem": 1, "toothfem.efficiency": 2,
          "toothfem.efficiency.loop": 3, "toothfem.layouts": 5, "toothfem": 6}
#: The top's modules that the layouts are built from (a case section, a template's rules,
#: a drawing, the CAD bodies): below the layouts, so they never import one.
PIECES = {"toothfem.case_sections": 4, "toothfem.case_running": 4, "toothfem.case_template": 4,
          "toothfem.cycloid_template": 4, "toothfem.cad": 4,
          "toothfem.cad_parts": 4, "toothfem.report.plots": 4, "toothfem.report": 4}


def _modules():
    """(module name, path, is __init__) of every source file of the package, by
    pyproject.toml's package-dir mapping (the same reading as tools/typecheck.py)."""
    for module, path in typecheck.module_files():
        yield module, path, path.name == "__init__.py"


def _layer(module: str) -> int:
    if module in PIECES:
        return PIECES[module]
    best = max((p for p in LAYERS if module == p or module.startswith(p + ".")), key=len)
    return LAYERS[best]


def _package(module: str, is_init: bool) -> str:
    return module if is_init else module.rpartition(".")[0]


def _imports(tree):
    """(node, absolute-or-relative target, names) of every import outside a TYPE_CHECKING
    block."""
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(n) for b in node.body for n in ast.walk(b))
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.ImportFrom):
            yield node, node.module or "", node.level, [a.name for a in node.names]
        elif isinstance(node, ast.Import):
            for a in node.names:
                yield node, a.name, 0, []


def _resolve(package: str, target: str, level: int) -> str:
    if level == 0:
        return target
    base = package.split(".")
    base = base[:len(base) - (level - 1)]
    return ".".join(base + ([target] if target else []))


def test_imports_run_one_way_and_keep_private_names_home():
    wrong, private = [], []
    for module, path, is_init in _modules():
        package = _package(module, is_init)
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node, target, level, names in _imports(tree):
            full = _resolve(package, target, level)
            if not full.startswith("toothfem"):
                continue
            candidates = [full] + [f"{full}.{n}" for n in names]
            own = any(c in BASE for c in candidates) or full == "toothfem"
            if not own and _layer(full) > _layer(module):
                wrong.append(f"{module}:{node.lineno} imports {full} (layer {_layer(full)} "
                             f"above {_layer(module)})")
            for n in names:
                if n.startswith("_") and not n.startswith("__") and full != package \
                        and not full.startswith(package + "."):
                    private.append(f"{module}:{node.lineno} imports {full}.{n}")
    assert not wrong, "imports against the layers:\n" + "\n".join(wrong)
    assert not private, "private names across packages:\n" + "\n".join(private)


def _graph():
    """module -> the modules it imports (module and function level, TYPE_CHECKING aside)."""
    mods = {m: (path, is_init) for m, path, is_init in _modules()}
    graph: dict[str, set] = {m: set() for m in mods}
    for module, (path, is_init) in mods.items():
        package = _package(module, is_init)
        for _node, target, level, names in _imports(ast.parse(path.read_text("utf-8"))):
            full = _resolve(package, target, level)
            subs = [f"{full}.{n}" for n in names if f"{full}.{n}" in mods]
            for dst in subs or ([full] if full in mods else []):
                if dst != module:
                    graph[module].add(dst)
    return graph


def test_no_import_cycles():
    """Strongly connected groups of more than one module (Tarjan): none. A package's
    __init__ importing its own submodules is the package's face, not a cycle, unless a
    submodule imports the __init__ back."""
    graph = _graph()
    index, low, stack, on, groups, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    import sys
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10000))
    for v in graph:
        if v not in index:
            visit(v)
    assert not groups, "import cycles:\n" + "\n".join(" <-> ".join(g) for g in groups)


def test_the_mapping_lists_every_package_and_nothing_is_a_link():
    """pyproject.toml's packages are exactly the folders with an __init__.py under the
    mapped folders (a new subpackage not listed would be missing from the wheel), and no
    file or folder of the package is a symbolic link (the checkout, the editable install
    and the wheel import the same files)."""
    cfg = typecheck.tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    listed = set(cfg["tool"]["setuptools"]["packages"])
    found = {m for m, _, is_init in _modules() if is_init}
    assert listed == found, f"listed only: {listed - found}; not listed: {found - listed}"
    links = [p for folder in typecheck.package_dirs().values()
             for p in (ROOT / folder).rglob("*") if p.is_symlink()]
    assert not links, f"symbolic links in the package: {links}"
    assert not any(os.path.islink(ROOT / f) for f in typecheck.package_dirs().values())
