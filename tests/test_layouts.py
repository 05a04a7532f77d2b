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
        assert isinstance(cls.member_body, property)
        assert isinstance(cls.member_displacement, property)


#: The 2K-V/K-H-V flag the output path replaced (fem/system/paths.py): none of it in the
#: system model and the drives (the layouts choose the path; only paths.py names a path's
#: class in a test of its type).
FLAG = re.compile(r"\btwo_stage\b|\bkhv\b|\bfirst_teeth\b|\bKHV_NAMES\b"
                  r"|isinstance\([^)]*\b(Cranks|PinsInHoles)\b")


def test_no_layout_flag_in_the_system_model_and_the_drives():
    found = []
    for folder in ("fem/system", "fem/drives"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if FLAG.search(line.split("#", 1)[0]):
                    found.append(f"{path.relative_to(ROOT).as_posix()}:{i}: {line.strip()}")
    assert not found, "a layout flag instead of the output path:\n" + "\n".join(found)


def test_each_drive_keeps_the_output_path_contract():
    """Every shipped drive's path is an OutputPath the layout chose (K-H-V and the sine
    pair: pins in holes; RV: cranks), complete (no abstract member left), a frozen record
    that pickles as itself (it is part of the drive's hash), naming every part it renames
    among GROUPS and every bearing once, and the source of the drive's train."""
    from toothfem.fem.system.parts import GROUPS
    from toothfem.fem.system.paths import Cranks, OutputPath, PinsInHoles
    kinds = {"cycloid": PinsInHoles, "rv": Cranks, "sine": PinsInHoles}
    for case_path in CASES:
        case = load_case(case_path)
        try:
            drive = drive_for(case)
        except CaseError:                  # an RV train without its disc (the RV paper's)
            continue
        path = drive.path
        assert isinstance(path, OutputPath) and not type(path).__abstractmethods__
        assert type(path) is kinds[drive.layout.name], case_path.name
        assert pickle.loads(pickle.dumps(path)) == path and {path: 1}[path] == 1
        assert set(path.group_names) <= set(GROUPS)
        k = 3
        names = {path.BEARING.format(k=a + 1, j=b + 1) for a in range(k) for b in range(k)}
        assert len(names) == (k * k if type(path) is Cranks else k)   # one shaft on the axis
        assert drive.speeds() == path.speeds(*_teeth(drive))
        orders = drive.te_orders()
        for name, q in path.te_orders(drive.speeds()):      # the path's orders named there
            (key,) = [k for k in orders if name in k.split(" = ")]
            assert orders[key] == pytest.approx(q, rel=1e-9)


def _teeth(drive) -> tuple:
    """(moving, fixed) teeth of a drive's stage."""
    if drive.kind == "sine":
        return drive.pair.planet_teeth, drive.pair.ring_teeth
    return drive.stage.lobe_count, drive.geometry.pin_count


def test_a_2kv_and_a_khv_system_differ_only_through_their_path(cases_dir):
    """The pin-housing drive's discs on its cranks and on the K-H-V case's output pins:
    one CycloidSystem without a layout flag, whose shafts, coordinates, element names and
    groups, contacts, friction sources and train all come from the drive's path (equal
    pin springs, no FE: fast)."""
    from toothfem.fem.system.friction import PathFriction
    from toothfem.fem.system.parts import GROUPS
    from toothfem.fem.system.paths import Cranks, PinsInHoles
    case = load_case(cases_dir / "cycloid_pinhousing.toml")
    rv = drive_for(case)
    om = load_case(cases_dir / "cycloid_khv.toml").to_si().output_mechanism
    khv = dataclasses.replace(rv, path=PinsInHoles(om))
    assert isinstance(rv.path, Cranks) and khv.stage is rv.stage
    supports = rv.supports(case.to_si().supports)
    fr = PathFriction(pin_disc=0.1, pin_groove=0.1, bearing=0.002, output_pin=0.05)
    states = {}
    for d in (rv, khv):
        s = d.system_model(supports, 4, cache=False, pin_spring_m_per_N=1e-9)
        path = d.path
        assert s.path is path and not hasattr(s, "khv")
        assert (s.cranks, s.r_c) == path.shafts(d)
        for k in range(s.cranks):
            assert all(name in s.coords.index for name in path.shaft_coordinates(k))
        elements = s._elements(0.0)
        assert {e.group for e in elements} - {"carrier"} == \
            {path.group_names.get(g, g) for g in GROUPS} - (
                set() if path.shaft_elements(s, 0) else {"spur mesh"})
        assert {e.name for e in elements} >= {n for row in s.bearing_names for n in row}
        st = s.solve(100.0, 1, friction=fr)
        states[type(path)] = st
        assert (st.output_pin_force_N is None) == (not path.contacts(s, 0.0, 1.0))
        assert set(st.friction_Nm) >= {s.group("crank bearings"), s.group("support bearings")}
        assert st.disc_torque_Nm.sum() == pytest.approx(d.members_torque(100.0), rel=1e-6)
    a, b = states[Cranks], states[PinsInHoles]
    assert "eccentric bearing disc 1" in b.bearing_force_N and \
        "crank bearing 1 disc 1" in a.bearing_force_N
    assert set(b.paths_rad) - set(a.paths_rad) == {
        "eccentric bearings", "input bearings", "input shaft bending", "input shaft torsion",
        "output pins", "output pins clearance"}
    assert "output pins" in b.friction_Nm and "output pins" not in a.friction_Nm
