"""One registration record per layout (fem/drives/registry.py, docs/architecture.md):
every layout provides every part, the consumers ask the record, and nothing outside
fem/drives/ branches on the drive kind."""
from __future__ import annotations

import importlib
import pkgutil
import re
from pathlib import Path

import pytest

import toothfem
from toothfem.case import load_case
from toothfem.errors import CaseError
from toothfem.fem.drives import DRIVES, drive_for
from toothfem.fem.drives import registry as reg

ROOT = Path(__file__).resolve().parents[1]
CASES = sorted((ROOT / "cases").glob("*.toml"))


def _import_everything():
    """Every module of the package: each provider registers its parts on import."""
    for m in pkgutil.walk_packages(toothfem.__path__, "toothfem."):
        importlib.import_module(m.name)


def test_every_layout_provides_every_part():
    _import_everything()
    assert set(reg.RECORDS) == set(DRIVES)          # each layout has its Drive class
    for name, record in reg.RECORDS.items():
        assert record.name == name
        missing = sorted(set(reg.PARTS) - set(record.parts))
        assert not missing, f"layout {name!r} lacks the parts {missing}"
        assert all(callable(record.part(p)) for p in reg.PARTS)
        assert record.label and record.stage_section and record.tolerance_keys
        assert record.required_sections, f"layout {name!r} names no case drive"


def test_shipped_cases_cover_every_layout_and_agree_with_their_drive():
    seen = set()
    for path in CASES:
        case = load_case(path)
        name = reg.layout_name(case)
        assert name == reg.layout_name(case.to_si())     # Case and CaseSI alike
        drive = drive_for(case)
        assert drive.layout == name and drive.record is reg.RECORDS[name]
        assert drive.kind == drive.record.stage_section
        # the design keys set fields the stage's SI geometry has
        stage = getattr(case.to_si(), drive.record.stage_section)
        for key, (field, factor) in drive.record.design_keys.items():
            assert hasattr(stage.geometry, field) and factor > 0, (name, key, field)
        seen.add(name)
    assert seen == set(reg.RECORDS), f"no shipped case of {set(reg.RECORDS) - seen}"


def test_layout_name_refuses_an_unknown_drive():
    class Odd:
        drive = "harmonic"
    with pytest.raises(CaseError, match=r"case.drive = 'harmonic' is not one of"):
        reg.layout_name(Odd())


def test_a_missing_part_is_named_with_its_provider():
    record = reg.DriveRecord(name="probe", label="a probe", stage_section="cycloid",
                             tolerance_keys=())
    with pytest.raises(KeyError, match="layout 'probe' has no part 'loss_model'.*"
                                       "toothfem.efficiency.drive_losses"):
        record.part("loss_model")


def test_provide_refuses_unknown_parts_layouts_and_a_second_provider():
    with pytest.raises(ValueError, match="part 'nonsense'"):
        reg.provide("nonsense", "rv")
    with pytest.raises(ValueError, match="not among"):
        reg.provide("drawing", "harmonic")
    with pytest.raises(ValueError, match="provided twice"):
        reg.provide("drawing", "rv")(lambda drive, case_name: None)


def test_adding_a_layout_is_one_record_plus_its_parts(monkeypatch):
    """The add-a-drive recipe of docs/architecture.md: a new record is incomplete until
    each part of PARTS is provided; providing them completes it and the consumers (which
    ask the record) reach them without another edit."""
    _import_everything()
    new = reg.DriveRecord(name="harmonic", label="a harmonic drive (probe)",
                          stage_section="flexspline", tolerance_keys=("tooth_profile_mm",),
                          required_sections={"harmonic": ("flexspline",)})
    monkeypatch.setitem(reg.RECORDS, "harmonic", new)
    assert set(reg.PARTS) - set(new.parts) == set(reg.PARTS)
    for part in reg.PARTS:
        reg.provide(part, "harmonic")(lambda *a, _p=part: _p)
    assert set(new.parts) == set(reg.PARTS)
    assert "harmonic" in reg.case_drives()

    class HarmonicCase:
        drive, flexspline = "harmonic", object()
    assert reg.record_of(HarmonicCase()).part("loss_model")() == "loss_model"


#: What a branch on the drive kind looks like in source (outside fem/drives/): a test of
#: the kind or the 2K-V flag, a table keyed by the kind (other than the registry's own
#: RECORDS), a case's drive name compared.
BRANCH = re.compile(r"\btwo_stage\b|\bdrive\.(kind|layout)\s*(==|!=|in\b)"
                    r"|\b(?!RECORDS\b)[A-Z_]+\[\s*(drive\.kind|drive\.layout|\w+\.drive)\s*\]"
                    r"|\bdrive\s*(==|!=|in)\s*[\"'(]|\.drive\s*(==|!=|in\b)|\bkhv\b"
                    r"|\bdrives\s*=\s*\(")


def test_no_branch_on_the_drive_kind_outside_the_drives():
    found = []
    for folder in ("toothfem", "geometry", "fem", "efficiency"):
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            # fem/drives/ is where the layouts live
            if rel.startswith("fem/drives/"):
                continue
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                code = line.split("#", 1)[0]
                if BRANCH.search(code):
                    found.append(f"{rel}:{i}: {line.strip()}")
    assert not found, "branches on the drive kind outside fem/drives/:\n" + "\n".join(found)


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
