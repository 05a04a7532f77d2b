"""The case schema (architecture issue, item 1): every key's unit, range, default and the
default's source declared once, in the sections' field metadata; docs/case_schema.md is
generated from it; report.html reads it from the package. Under ``make test-wheel`` these
tests run against the installed wheel, so the wheel's schema is compared with the checkout's
document and every shipped case's page must still show every default's source."""
from __future__ import annotations

import html
import re
import sys
from pathlib import Path

import pytest

from toothfem import case_schema
from toothfem.case import load_case
from toothfem.report import html as report_html
from toothfem.report.inputs import NO_SOURCE, case_inputs

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "case_schema.md"
CASES = sorted((ROOT / "cases").glob("*.toml"))
sys.path.insert(0, str(ROOT / "tools"))
import typecheck  # noqa: E402  (tools/typecheck.py: the package's modules by the mapping)


def test_the_doc_is_what_the_schema_writes():
    """The committed docs/case_schema.md has the tables the schema writes (``make schema``
    rewrites them; the prose between them is kept), one block per table of a case file."""
    text = DOC.read_text(encoding="utf-8")
    assert case_schema.render(text) == text, "docs/case_schema.md is out of date: make schema"
    blocks = [m.group("section") for m in case_schema.BLOCK.finditer(text)]
    assert blocks == [name for name, _ in case_schema.tables()]
    for row in case_schema.schema().values():
        assert f"| `{row.key}` |" in text, row.dotted


def test_render_refuses_a_block_too_many_or_too_few():
    text = DOC.read_text(encoding="utf-8")
    with pytest.raises(ValueError, match=r"missing \['design'\]"):
        case_schema.render(text.replace("<!-- schema: design -->", "<!-- design -->"))
    with pytest.raises(ValueError, match=r"unknown \['gears'\]"):
        case_schema.render(text + "\n<!-- schema: gears -->\n<!-- /schema -->\n")
    extra = "\n<!-- schema: friction -->\n<!-- /schema -->\n"
    with pytest.raises(ValueError, match=r"doubled \['friction'\]"):
        case_schema.render(text + extra)


def test_every_default_has_a_source():
    """A key with a default says where it comes from (a source, ASSUMPTION with its reason,
    or what 0 means); a default of None says what it stands for; a required key has no
    default to source. Units follow the key's suffix."""
    rows = case_schema.schema().values()
    assert {r.section for r in rows} == {name for name, _ in case_schema.tables()}
    for r in rows:
        if r.required:
            assert not r.source, f"{r.dotted} is required: a source of no default"
            continue
        assert r.source.strip(), f"{r.dotted} = {r.default!r} has no source"
        if r.default is None:
            assert r.unset.strip(), f"{r.dotted}: what its default of None stands for"
        assert "\n" not in r.source, r.dotted
    units = {r.dotted: r.unit for r in rows}
    assert units["material.hardness_HV"] == "HV" and units["cycloid.pin_count"] == ""
    assert units["thermal.heat_transfer_W_m2K"] == "W/(m² K)"
    assert units["lubricant.vogel_B_C"] == "°C"


def test_ranges_and_defaults_read_as_written():
    s = case_schema.schema()
    assert s["material.poisson_ratio"].valid == "[0, 0.5)"
    assert s["cycloid.pin_count"].valid == "integer in [4, 400]"
    assert s["lubricant.lubrication"].valid.startswith('one of "oil_bath", "oil_mist"')
    assert s["case.drive"].valid == 'one of "cycloid", "rv", "sine"'
    assert s["bearings.main_preload_N"].valid == "[0, 1e+07]"
    assert s["friction.boundary_coefficient"].default_text == "0.1"
    assert s["thermal.mounting"].default_text == '"free"'
    assert s["supports.carrier_stiffness_Nm_per_arcmin"].default_text == "none: a rigid carrier"
    assert s["sine.module_mm"].default_text == "required"


@pytest.mark.parametrize("path", CASES, ids=[p.stem for p in CASES])
def test_every_shipped_case_shows_every_defaults_source(path, tmp_path):
    """The inputs table of each shipped case: every key it holds is in the schema, with the
    schema's unit; every default is shown with its source, in the rows and on the page
    report.html writes (from the package: the wheel's page equals the checkout's)."""
    case = load_case(path)
    text = report_html.read_case_text(path)
    rows = case_inputs(case, text)
    schema = case_schema.schema()
    defaults = [r for r in rows if r.declared is False]
    assert defaults and any(r.declared for r in rows)
    for r in rows:
        spec = schema[re.sub(r"\[\d+\]", "", r.key)]
        assert r.unit == spec.unit, r.key
    for r in defaults:
        assert r.source and r.note != NO_SOURCE, r.key
        assert r.source in r.note, r.key
    page = report_html.render(tmp_path, case, command="test", case_file=path)
    inputs = page[page.index('<section id="inputs">'):]
    inputs = inputs[:inputs.index("</section>")]
    for r in defaults:
        assert html.escape(r.source, quote=True) in inputs, r.key
    assert NO_SOURCE not in inputs


def test_the_package_reads_nothing_beside_its_source():
    """No module of the package finds a file from its own location (``__file__``,
    ``parents[...]``): what the package needs at run time is in the package, so an installed
    wheel behaves as the checkout."""
    found = [f"{module} ({path.name})" for module, path in typecheck.module_files()
             if re.search(r"__file__|\.parents\[", path.read_text(encoding="utf-8"))]
    assert not found, found
