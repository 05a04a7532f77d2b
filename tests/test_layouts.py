"""The layouts (toothfem/layouts/, toothfem/layout.py, docs/architecture.md "Adding a
layout"): every layout is complete, each shipped case finds its layout and drive, a
layout pickles as itself, a new layout is one object in the list, and nothing outside the
layouts and fem/drives/ branches on the drive kind."""
from __future__ import annotations

import dataclasses
import pickle
import re
from pathlib import Path

import pytest

from toothfem.case import load_case
from toothfem.errors import CaseError
from toothfem.fem.drives import drive_for
from toothfem.layout import Layout
from toothfem import layouts as ly

ROOT = Path(__file__).resolve().parents[1]
CASES = sorted((ROOT / "cases").glob("*.toml"))
#: The parts of a layout: every field that is not its description.
PARTS = ("drive", "ratio", "case_checks", "case_template", "derived_rows", "loss_model",
         "envelope", "bearing_set", "eccentric_loads", "main_row_force", "drawing",
         "cad_parts")


def test_every_layout_has_every_part():
    names = [x.name for x in ly.LAYOUTS]
    assert len(set(names)) == len(names) == 3
    fields = {f.name for f in dataclasses.fields(Layout)}
    assert set(PARTS) <= fields
    for layout in ly.LAYOUTS:
        assert all(callable(getattr(layout, p)) for p in PARTS if p != "case_template")
        assert layout.case_template is not None
        assert layout.label and layout.stage_section and layout.tolerance_keys
        assert layout.required_sections, f"layout {layout.name!r} names no case drive"
        assert ly.layout_named(layout.name) is layout
        # a Dask worker's copy is the same object (pickled by reference)
        assert pickle.loads(pickle.dumps(layout)) is layout


def test_shipped_cases_cover_every_layout_and_agree_with_their_drive():
    seen = set()
    for path in CASES:
        case = load_case(path)
        layout = case.layout
        assert layout is ly.layout_of(case) is case.to_si().layout
        drive = drive_for(case)
        assert drive.layout is layout
        assert drive.kind == layout.stage_section
        # the design keys set fields the stage's SI geometry has
        stage = getattr(case.to_si(), layout.stage_section)
        for key, (field, factor) in layout.design_keys.items():
            assert hasattr(stage.geometry, field) and factor > 0, (layout.name, key, field)
        # a case and its drive pickle with their layout
        si = pickle.loads(pickle.dumps(case.to_si()))
        assert si.layout is layout and pickle.loads(pickle.dumps(drive)).layout is layout
        seen.add(layout)
    assert seen == set(ly.LAYOUTS), f"no shipped case of {set(ly.LAYOUTS) - seen}"


def test_layout_of_refuses_an_unknown_drive():
    class Odd:
        drive = "harmonic"
    with pytest.raises(CaseError, match=r"case.drive = 'harmonic' is not one of"):
        ly.layout_of(Odd())
    with pytest.raises(CaseError, match=r"layout 'harmonic' is not one of"):
        ly.layout_named("harmonic")


def test_adding_a_layout_is_one_object_in_the_list(monkeypatch):
    """The add-a-layout recipe of docs/architecture.md: a Layout (here the K-H-V one's
    parts under another name) placed in LAYOUTS is found by every consumer, which asks
    the case's layout, without another edit."""
    khv = ly.layout_named("cycloid")
    new = dataclasses.replace(khv, name="harmonic", label="a harmonic drive (probe)",
                              required_sections={"harmonic": ("flexspline",)},
                              ratio=lambda case: 100.0)
    monkeypatch.setattr(ly, "LAYOUTS", ly.LAYOUTS + (new,))
    assert "harmonic" in ly.case_drives()

    class HarmonicCase:
        drive, flexspline = "harmonic", object()
    assert ly.layout_of(HarmonicCase()) is new
    assert ly.layout_of(HarmonicCase()).ratio(HarmonicCase()) == 100.0


#: What a branch on the drive kind looks like in source (outside fem/drives/): a test of
#: the kind or the 2K-V flag, a table keyed by the kind (other than the registry's own
#: RECORDS), a case's drive name compared.
BRANCH = re.compile(r"\btwo_stage\b|\bdrive\.(kind|layout)\s*(==|!=|in\b)"
                    r"|\b[A-Z_]+\[\s*(drive\.kind|drive\.layout|\w+\.drive)\s*\]"
                    r"|\bdrive\s*(==|!=|in)\s*[\"'(]|\.drive\s*(==|!=|in\b)|\bkhv\b"
                    r"|\bdrives\s*=\s*\(")


def test_no_branch_on_the_drive_kind_outside_the_layouts():
    found = []
    for folder in ("toothfem", "geometry", "fem", "efficiency"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            # the layouts and the drives they build are where the kinds are told apart
            if rel.startswith(("fem/drives/", "toothfem/layouts/")):
                continue
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                code = line.split("#", 1)[0]
                if BRANCH.search(code):
                    found.append(f"{rel}:{i}: {line.strip()}")
    assert not found, ("branches on the drive kind outside the layouts and drives:\n"
                       + "\n".join(found))


def test_each_drive_keeps_the_fe_contracts():
    """The cycle solver and the detailed result of every shipped drive are what
    fem/contracts.py says (mypy checks the Drive interface against them; this checks the
    objects the drives really return)."""
    import dataclasses

    from toothfem.fem.contracts import CycleSolver
    from toothfem.fem.cycloid_fe.detailed import DetailedResult as CycloidDetailed
    from toothfem.fem.sine_fe.detailed import DetailedResult as SineDetailed
    for path in CASES:
        drive = drive_for(load_case(path))
        solver = drive.cycle_solver(4, cache=False)        # built lazily: no tables yet
        assert isinstance(solver, CycleSolver), (path.name, type(solver))
    for cls in (CycloidDetailed, SineDetailed):
        names = {f.name for f in dataclasses.fields(cls)}
        assert {"load_sharing", "dofs"} <= names
        assert isinstance(getattr(cls, "member_body"), property)
        assert isinstance(getattr(cls, "member_displacement"), property)
