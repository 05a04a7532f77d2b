"""mypy over the package as it installs: every folder of pyproject.toml's package-dir
mapping read under its package's name (geometry/ as toothfem.geometry, ...).

mypy finds modules by their folders and cannot follow setuptools' mapping (nor the import
hook of an editable install), so this names each source file's module for it; the
options are mypy's own, from ``[tool.mypy]``, and any given here
(``python tools/typecheck.py --check-untyped-defs``).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

from mypy import build
from mypy.errors import CompileError
from mypy.main import process_options
from mypy.modulefinder import BuildSource

try:
    import tomllib
except ModuleNotFoundError:         # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]


def package_dirs() -> dict[str, str]:
    """{package: folder} of pyproject.toml's ``[tool.setuptools] package-dir``."""
    cfg = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    return dict(cfg["tool"]["setuptools"]["package-dir"])


def module_files() -> list[tuple[str, Path]]:
    """(module, path) of every source file of the mapped packages, each once: a folder
    that is mapped on its own is read under its own package, not its parent's."""
    mapping = package_dirs()
    mapped = {(ROOT / folder).resolve() for folder in mapping.values()}
    out = []
    for package, folder in sorted(mapping.items()):
        base = (ROOT / folder).resolve()
        for path in sorted(base.rglob("*.py")):
            inner = [p for p in path.parents if p != base and base in p.parents]
            if any(p in mapped for p in inner):
                continue
            rel = path.relative_to(base).with_suffix("")
            parts = [p for p in rel.parts if p != "__init__"]
            out.append((".".join([package, *parts]), path))
    return out


def main(argv: list[str] | None = None) -> int:
    """Type-check; print mypy's messages; 0 when clean, 1 with errors, 2 if it cannot."""
    os.chdir(ROOT)                  # paths in messages relative to the checkout
    _, options = process_options(list(argv or []), require_targets=False)
    files = module_files()
    sources = [BuildSource(str(p.relative_to(ROOT)), m) for m, p in files]
    try:
        result = build.build(sources, options)
    except CompileError as exc:
        print("\n".join(exc.messages))
        return 2
    for line in result.errors:
        print(line)
    errors = sum(": error:" in e for e in result.errors)
    if errors:
        print(f"Found {errors} errors (checked {len(files)} source files)")
        return 1
    print(f"Success: no issues found in {len(files)} source files")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
