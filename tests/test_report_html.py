"""report.html (issue 25, item 1): one self-contained page per output folder, with the inputs
and where each came from, the assumptions, the warnings, every figure, the tables and the
published figures beside ours; opened in a real headless browser where one is installed."""
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import warnings
from html.parser import HTMLParser
from pathlib import Path

import pytest

from toothfem import cad, cli
from toothfem.report import html as report_html

#: The browsers looked for, by command name, then Debian's path.
BROWSERS = ("chromium", "chromium-browser", "google-chrome")
DEBIAN_CHROMIUM = Path("/usr/bin/chromium")
#: Seconds one headless browser run may take (a cold start takes about 1 s here).
BROWSER_TIMEOUT_S = 60
#: Headless Chromium without a sandbox (CI runs as root), network features or a profile
#: of the user's.
BROWSER_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--no-default-browser-check")
#: Virtual time [ms] the page gets before the DOM is dumped: the load event and the probe
#: run inside it.
VIRTUAL_TIME_MS = 3000
#: Profile points per tooth of the fast geometry run (the page shows the drawing, not them).
COARSE_POINTS = 16
#: The test-time probe (never shipped: the page has no script): after the load event it
#: writes what the page shows into a <pre>, which the dumped DOM carries out.
PROBE = """<script>
addEventListener('load', () => {
  const empty = [...document.querySelectorAll('section')].filter(s => {
    const c = s.cloneNode(true); c.querySelector('h2')?.remove();
    return !c.textContent.trim() && !c.querySelector('img'); }).map(s => s.id);
  const out = document.createElement('pre'); out.id = 'toothfem-probe';
  out.textContent = JSON.stringify({
    images: document.images.length,
    broken: [...document.images].filter(i => !i.complete || i.naturalWidth === 0)
                                .map(i => i.alt),
    empty: empty, height: document.documentElement.scrollHeight,
    none: document.body.innerText.match(/\\bNone\\b[^\\n]{0,60}/g) || []});
  document.body.appendChild(out);
});
</script>"""


@pytest.fixture(scope="module")
def folders(cases_dir, tmp_path_factory, sine_run):
    """``run --no-fem`` and ``geometry`` of the sine prototype (the fastest shipped case),
    each under its own command line as the console script has it: the run is the session's
    (conftest's sine_run, which tests/test_cli.py reads too); the geometry's profiles
    coarse and STEP left out (neither is on the page, and they take seconds)."""
    base = tmp_path_factory.mktemp("html")
    out = {"run": sine_run[0], "geometry": base / "geometry"}
    case = str(cases_dir / "sine_prototype.toml")
    args = ["geometry", case, "--points-per-tooth", str(COARSE_POINTS),
            "--out", str(out["geometry"])]
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(cad, "step_available", lambda: False)
        mp.setattr(sys, "argv", ["/usr/bin/toothfem", *args])
        assert cli.main(args) == 0
    return out


class _Page(HTMLParser):
    """Every tag's attributes, and the text and pictures of each <section>."""

    def __init__(self):
        super().__init__()
        self.tags, self.sections, self._open, self._in_h2 = [], {}, None, False

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append((tag, attrs))
        if tag == "section":
            self._open = attrs.get("id", f"section-{len(self.sections)}")
            self.sections[self._open] = {"text": "", "images": 0}
        elif tag == "h2":
            self._in_h2 = True
        elif tag == "img" and self._open:
            self.sections[self._open]["images"] += 1

    def handle_endtag(self, tag):
        if tag == "section":
            self._open = None
        elif tag == "h2":
            self._in_h2 = False

    def handle_data(self, data):
        if self._open and not self._in_h2:
            self.sections[self._open]["text"] += data


def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8"))
    page.close()
    return page


@pytest.mark.parametrize("command", ["run", "geometry"])
def test_report_is_one_self_contained_page(folders, command):
    """The page parses; it names nothing outside itself (no http(s), every picture a data:
    URI that decodes to a PNG, no script); every section says something; the header names
    toothfem's version, the date and the command line."""
    path = folders[command] / "report.html"
    page = _parse(path)
    text = path.read_text(encoding="utf-8")
    for tag, attrs in page.tags:
        for name in ("src", "href"):
            assert not re.match(r"^\s*(https?:)?//", attrs.get(name) or "", re.I), (tag, attrs)
    assert not [t for t, _ in page.tags if t in ("script", "link", "iframe", "object")]
    images = [a["src"] for t, a in page.tags if t == "img"]
    assert images and len(images) == len(list(folders[command].rglob("*.png")))
    for src in images:
        head, _, data = src.partition(",")
        assert head == "data:image/png;base64"
        assert base64.b64decode(data, validate=True).startswith(b"\x89PNG\r\n\x1a\n")
    assert {"warnings", "assumptions", "inputs", "files"} <= set(page.sections)
    for ident, s in page.sections.items():
        assert s["text"].strip() or s["images"], f"section {ident} is empty"
    assert f"toothfem {command}" in text and "0.1.0" in text
    assert re.search(r"<dt>date</dt><dd>\d{4}-\d\d-\d\dT", text)
    shown = re.search(r"<dt>command</dt><dd>([^<]*)</dd>", text).group(1)
    assert shown.startswith(f"toothfem {command} ") and "--out" in shown
    marker = (folders[command] / ".toothfem-result").read_text().splitlines()
    assert "report.html" in marker[1:]               # written inside the atomic folder


def test_report_tells_where_each_input_came_from(folders, cases_dir):
    """Declared values with their comments and ASSUMPTION reasons, defaults with the
    schema's source, the run's warnings, and the published figures beside ours with
    'no reason recorded' where the code states none."""
    page = _parse(folders["run"] / "report.html")
    inputs = page.sections["inputs"]["text"]
    assert re.search(r"face_width_mm\s*8\.0\s*mm\s*declared", inputs)
    assert re.search(r"hardness_HV\s*700\.0\s*HV\s*default\s*hardness of the flanks[^;]*; "
                     r"60 HRC by the ASTM E140 conversion table", inputs)
    assert re.search(r"density_kg_m3\s*7850\.0\s*kg/m³\s*declared\s*ASSUMPTION\s*"
                     r"ASSUMPTION \(steel\)", inputs)
    assumptions = page.sections["assumptions"]["text"]
    assert "output_mechanism.pin_count (line" in assumptions and "not given" in assumptions
    assert "thermal.ambient_C = 20.0 (default)" in assumptions
    assert "[published]" not in inputs                # figures to compare, not inputs
    published = page.sections["published"]["text"]
    assert "efficiency_computed" in published and "no reason recorded" in published
    efficiency = json.loads((folders["run"] / "efficiency.json").read_text())
    for w in efficiency["analytic"]["warnings"]:
        assert w["message"] in page.sections["warnings"]["text"]


def test_markdown_is_escaped_and_a_missing_picture_is_said(tmp_path):
    """Markup in a report's Markdown is shown as text, never run; a picture the folder
    lacks is said in words, never a broken image; a Python warning shown while the
    command runs is on the page."""
    (tmp_path / "report.md").write_text("# t\n\n## Part\n\n<script>alert(1)</script> and "
                                        "![gone](gone.png) [away](https://example.org/x)\n")
    with pytest.warns(RuntimeWarning), report_html.warnings_kept():
        warnings.warn("a cache that cannot be written", RuntimeWarning, stacklevel=1)
        path = report_html.write_report(tmp_path, command="test")
    text = path.read_text(encoding="utf-8")
    assert "<script>" not in text and "&lt;script&gt;" in text
    assert "<img" not in text and "[figure gone.png is not in the folder]" in text
    assert 'href="https://' not in text and "a cache that cannot be written" in text
    with pytest.raises(report_html.ToothfemError, match="folder = "):
        report_html.write_report(tmp_path / "none", command="test")


def test_case_file_comments_and_units_are_read_as_written(tmp_path):
    """A '#' inside a string is not a comment; an indented comment line continues the one
    above; a comment line after the keys is a note of the section; arrays of tables are
    numbered; units come from the keys' suffixes."""
    path = tmp_path / "c.toml"
    path.write_text('[case]\nname = "a # b"  # the name\n\n[lubricant]   # ASSUMPTION\n'
                    'lubrication = "grease"  # first part;\n'
                    '                        # continued\n# a note\n\n'
                    '[[measured]]\nefficiency = 0.9\n[[measured]]\n'
                    'efficiency = 0.8   # ASSUMPTION: read off a chart\n')
    text = report_html.read_case_text(path)
    assert text.keys["case.name"].text == "the name"
    assert text.keys["lubricant.lubrication"].text == "first part; continued"
    assert text.sections["lubricant"].text == "ASSUMPTION a note"
    assert {"measured[0].efficiency", "measured[1].efficiency"} <= text.declared
    assert text.keys["measured[1].efficiency"].line == 12
    assert [report_html.unit_of(k) for k in ("vogel_B_C", "pin_count", "kinematic_"
                                             "viscosity_mm2_s", "drag_torque_Nmm")] == \
        ["°C", "", "mm²/s", "N mm"]


def _browser():
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    return str(DEBIAN_CHROMIUM) if DEBIAN_CHROMIUM.exists() else None


def _headless(browser, profile: Path, *args) -> subprocess.CompletedProcess:
    """One headless run, its profile and home (Chromium's NSS database) under ``profile``."""
    env = {**os.environ, "HOME": str(profile)}
    return subprocess.run([browser, *BROWSER_FLAGS, f"--user-data-dir={profile}", *args],
                          capture_output=True, text=True, timeout=BROWSER_TIMEOUT_S,
                          stdin=subprocess.DEVNULL, env=env)


def test_report_opens_in_a_headless_browser(folders, tmp_path):
    """Chromium opens the run's page from the file system: a screenshot is taken, the
    console says nothing (nothing refused or missing), no picture is broken (naturalWidth
    0), no section is empty and the text a reader sees never says Python's None. The page
    is opened as a copy with a test-time probe (PROBE: the page itself has no script, and
    its policy would refuse one) whose findings the dumped DOM carries out."""
    browser = _browser()
    if browser is None:
        pytest.skip("no headless browser: chromium, chromium-browser or google-chrome "
                    "(Debian: apt-get install chromium; .ci/run installs it)")
    page = folders["run"] / "report.html"
    probed, shot = tmp_path / "probed.html", tmp_path / "report.png"
    text = page.read_text(encoding="utf-8")
    probed.write_text(text.replace(report_html.CSP, report_html.CSP
                                   + "; script-src 'unsafe-inline'")
                      .replace("</body>", PROBE + "</body>"), encoding="utf-8")
    r = _headless(browser, tmp_path / "profile", "--enable-logging=stderr", "--v=0",
                  f"--virtual-time-budget={VIRTUAL_TIME_MS}", f"--screenshot={shot}",
                  "--window-size=1280,4000", "--dump-dom", probed.as_uri())
    assert r.returncode == 0, r.stderr[-2000:]
    console = [line for line in r.stderr.splitlines() if ":CONSOLE" in line]
    assert not console, console
    assert shot.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    import matplotlib.image

    pixels = matplotlib.image.imread(shot)
    assert pixels.shape[:2] == (4000, 1280) and pixels.std() > 0.05     # not blank
    found = re.search(r'<pre id="toothfem-probe">(.*?)</pre>', r.stdout, re.S)
    assert found, r.stderr[-2000:]
    probe = json.loads(found.group(1).replace("&quot;", '"').replace("&amp;", "&"))
    assert probe["images"] == len(list(folders["run"].rglob("*.png")))
    assert probe["broken"] == [] and probe["empty"] == []
    assert probe["none"] == []                       # never Python's None on the page
    assert probe["height"] > 4000                    # the whole report, not a stub


#: Python's None as a page's text would show it (an unset value printed as is).
PY_NONE = re.compile(r"\bNone\b")


def _page_text(path: Path) -> str:
    page = _parse(path)
    return "\n".join(s["text"] for s in page.sections.values())


@pytest.mark.parametrize("command", ["run", "geometry"])
def test_no_python_none_on_the_page(folders, command):
    """An unset value reads as what it means, never as Python's None (the schema's
    "(None: bare pins)", an assumed record's value None, an empty warnings list)."""
    text = _page_text(folders[command] / "report.html")
    assert not PY_NONE.findall(text), [line for line in text.splitlines()
                                       if PY_NONE.search(line)][:5]


def test_unset_values_read_as_what_they_mean():
    assert report_html.spoken("a roller sleeve on each pin (None: bare pins)") == \
        "a roller sleeve on each pin (not set: bare pins)"
    assert report_html.spoken("none: minimised") == "none: minimised"     # English, kept
    assert report_html.missing("supports.carrier_stiffness_Nm_per_arcmin") == \
        "not set (a rigid carrier)"
    assert report_html.missing("output_mechanism.roller_radius_mm") == "not set (bare pins)"
    assert report_html.missing("x.anything_mm") == "not set"
    said = report_html.folder_assumptions({"stiffness.json": {"supports": {
        "carrier_stiffness_Nm_per_arcmin": {"value": None, "assumed": True}}}})
    assert said == [("stiffness.json › supports › carrier_stiffness_Nm_per_arcmin",
                     "assumed (not in the case): value = not set (a rigid carrier)")]
    assert "None" not in report_html._warnings_html({}, [])


def test_a_tolerance_page_lists_the_limits_its_percentiles_pass(cases_dir, tmp_path):
    """The tolerance ensemble's page: each limit its nominal or a percentile passes is in
    the warnings (P90 above the allowable contact stress, with its source), the limits
    checked are in its results, and no Python None anywhere (bare pins, preload, holes)."""
    import dataclasses

    from tests.test_tolerance_report import synthetic
    from toothfem.case import load_case
    from toothfem.report.tolerance import write_tolerance
    from toothfem.tolerance_result import check_limits

    case_file = cases_dir / "cycloid_khv.toml"
    case = load_case(case_file)
    r = synthetic()
    found, drawn = check_limits(r, case.to_si())
    write_tolerance(dataclasses.replace(r, warnings=tuple(found), limits=drawn), tmp_path)
    path = report_html.write_report(tmp_path, case, command="tolerance", case_file=case_file)
    page = _parse(path)
    warned = page.sections["warnings"]["text"]
    assert "P90 of 40 built reducers" in warned and "above the limit 1500 MPa" in warned
    assert "material.allowable_contact_stress_MPa" in warned
    assert any("against the allowable 1500 MPa" in s["text"] for s in page.sections.values())
    text = _page_text(path)
    assert not PY_NONE.findall(text), [line for line in text.splitlines()
                                       if PY_NONE.search(line)][:5]
    assert "bearings.main_preload_N = not set (ASSUMPTION 2 % of the row's C0) (default)" \
        in page.sections["assumptions"]["text"]
