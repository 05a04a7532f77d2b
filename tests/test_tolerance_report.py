"""The tolerance ensemble's report (toothfem/report/tolerance.py): labels that name the model
and the positions, both tails of the backlash, efficiencies told from 100 %, the limits
checked on the nominal design and on each percentile, titles that never break a tolerance
zone, histograms whose marks all lie inside their axes (or are arrows at the edge), integer
count axes, and "no scatter" where no one-tolerance run varies. Synthetic ensembles: no
ring is solved."""
from __future__ import annotations

import json

import numpy as np
import pytest

from toothfem.case import load_case
from toothfem.report import pyplot, wrap
from toothfem.report import tolerance as report
from toothfem.tolerance import LOADS_SYSTEM
from toothfem.quantities import ALONE_OVER_ALL
from toothfem.tolerance_result import OUTPUTS, ToleranceResult, check_limits, output_labels
from toothfem.report.tolerance import write_tolerance

#: Settings of a synthetic ensemble (as tolerance_analysis writes them).
SETTINGS = {"samples": 40, "seed": 0, "positions": 36, "pairing_period_pitches": 870,
            "share_samples": 10, "distribution": "normal", "distributions": {},
            "tolerances_mm": {"pin_position_mm": 0.005, "pin_diameter_lower_mm": -0.005,
                              "crank_hole_position_mm": 0.005, "disc_profile_mm": 0.003},
            "operating_speed_rpm": 1500.0, "operating_output_torque_Nm": 40.0,
            "rated_torque_Nm": 40.0, **LOADS_SYSTEM,
            "nominal_total_efficiency_analytic_loads_pct": 75.2}


def synthetic(n: int = 40, *, ph=(1450.0, 120.0), nominal_ph=548.0, film=None, **kw):
    """A ToleranceResult of ``n`` made-up rings: the pressure normal around ``ph``, a
    tooth force far from its nominal, the fewest contacts 1 or 2, a backlash around 0, a
    mesh efficiency near 100 %; the one-tolerance runs never vary the fewest contacts."""
    rng = np.random.default_rng(1)
    samples = {k: rng.normal(10, 1, n) for k in OUTPUTS}
    samples["max_force_N"] = rng.normal(1133, 5, n)
    samples["max_ph_MPa"] = rng.normal(*ph, n)
    samples["contacts_min"] = np.where(np.arange(n) % 10 == 0, 2.0, 1.0)
    samples["backlash_arcmin"] = rng.normal(0.0, 0.05, n)
    samples["mesh_efficiency_pct"] = 99.996 + rng.normal(0, 0.0005, n)
    nominal = {k: float(np.mean(v)) for k, v in samples.items()}
    nominal.update(max_force_N=660.0, max_ph_MPa=nominal_ph, mesh_efficiency_pct=99.997)
    names = ("pin_position", "disc_profile")
    shares = {m: {k: 0.5 for k in OUTPUTS} for m in names}
    shares[ALONE_OVER_ALL] = {k: 1.0 for k in OUTPUTS}
    for m in (*names, ALONE_OVER_ALL):
        shares[m]["contacts_min"] = 0.0
    args = dict(case_name="c", drive="cycloid", contact_name="pin", contacts_name="pins",
                samples=samples, nominal=nominal, shares=shares, settings=dict(SETTINGS),
                film_ratio=film or {})
    args.update(kw)
    return ToleranceResult(**args)


@pytest.fixture(scope="module")
def khv(cases_dir):
    return load_case(cases_dir / "cycloid_khv.toml")


# -- labels ---------------------------------------------------------------------------------

def test_labels_name_the_model_and_the_positions():
    """The system model's labels say it, with the positions over the pairing period, the
    worst over every disc and the first disc's loads for the efficiency; a drive of one
    planet has no "any" or "first" of them."""
    system = output_labels("pin", "pins", "disc")
    assert system["contacts_min"][0] == ("fewest pins in contact on one disc at a position "
                                         "(system model, positions over the pairing period)")
    assert system["max_force_N"][0].startswith("largest pin force on any disc (system model")
    assert system["total_efficiency_pct"][0] == (
        "total efficiency (the system model's loads of the first disc, every disc taken "
        "alike)")
    planet = output_labels("tooth", "teeth", "planet", members=1)
    assert planet["max_force_N"][0].startswith("largest tooth force on the planet (system")
    assert "first" not in planet["mesh_efficiency_pct"][0]
    assert set(OUTPUTS) == set(system)
    assert synthetic().outputs() == system


def test_report_md_says_the_model_and_why_the_nominal_differs(tmp_path):
    summary = write_tolerance(synthetic(), tmp_path)
    md = (tmp_path / "report.md").read_text()
    assert "Every output is the system model's" in md
    assert "`toothfem contact`'s" in md and "`toothfem run`'s efficiency" in md
    assert "75.20 % with the analytic loads" in md
    assert summary["outputs"]["contacts_min"][0] in md


# -- percentiles and numbers ----------------------------------------------------------------

def test_backlash_gives_both_tails():
    """Interference (below zero) and play are both bad: P10 and P90 (and P1, P99)."""
    r = synthetic()
    pct = r.percentiles()
    assert list(pct["backlash_arcmin"]) == ["P50", "P10", "P90", "P1", "P99"]
    assert list(pct["max_force_N"]) == ["P50", "P90", "P99"]
    rows = {label: cells for label, _, cells in report.summary_rows(r.summary(), r.outputs())}
    cell = rows[r.outputs()["backlash_arcmin"][0]][report.TAIL_COLUMNS[1]]
    assert cell.startswith("P10 ") and "(low side); P90 " in cell and cell.endswith("(high side)")
    assert "P10 the interference side, P90 the play side" in r.outputs()["backlash_arcmin"][0]


def test_efficiencies_near_100_keep_their_decimals():
    assert report.number_format([99.997, 99.9962], "%") == ".4f"
    assert report.number_format([71.43, 70.5], "%") == ".3f"
    assert report.number_format([1598.0], "MPa") == ".4g"
    r = synthetic()
    rows = {label: cells for label, _, cells in report.summary_rows(r.summary(), r.outputs())}
    assert rows[r.outputs()["mesh_efficiency_pct"][0]]["nominal"] == "99.9970"   # not "100"


# -- limits -----------------------------------------------------------------------------------

def test_limits_are_checked_on_the_nominal_and_each_percentile(khv, monkeypatch):
    """The nominal design and every percentile given go through toothfem.limits'
    contact_pressure (no second check): a P90 above the 1500 MPa allowable is a warning
    with its value, the limit, its source and which figure it is; a nominal below is
    none; the percentile too small for the sample (P99 of 40) is not checked."""
    from toothfem import limits

    seen = []
    real = limits.contact_pressure
    monkeypatch.setattr(limits, "contact_pressure",
                        lambda where, ph, material: seen.append((where, ph)) or
                        real(where, ph, material))
    r = synthetic()
    found, drawn = check_limits(r, khv.to_si())
    pct = r.percentiles()["max_ph_MPa"]
    assert [ph for _, ph in seen] == [548.0, pct["P50"]["value"], pct["P90"]["value"]]
    assert "nominal design" in seen[0][0] and "P90 of 40 built reducers" in seen[2][0]
    assert all(isinstance(w, limits.Exceeded) for w in found)
    hot = [w for w in found if "Hertz" in w.quantity]
    assert [w.value for w in hot] == [pytest.approx(pct["P90"]["value"])]
    assert hot[0].limit == pytest.approx(1500.0)
    assert "material.allowable_contact_stress_MPa" in hot[0].source
    assert "P90 of 40 built reducers (95 % interval" in hot[0].quantity
    assert drawn["max_ph_MPa"][0]["value"] == pytest.approx(1500.0)


def test_a_nominal_above_the_allowable_is_a_warning_too(khv):
    found, _ = check_limits(synthetic(ph=(2500.0, 50.0), nominal_ph=2588.0), khv.to_si())
    hot = [w for w in found if "Hertz" in w.quantity]
    assert [w.quantity.split(", ")[-1].split(" (")[0] for w in hot] == [
        "the nominal design", "P50 of 40 built reducers", "P90 of 40 built reducers"]


def test_film_ratio_and_rating_are_checked(cases_dir, khv):
    """The lowest film ratio's low-side percentiles (a ring not below 1 counts as not
    below), and the operating torque against the case's rating."""
    n = 40
    film = {"the mesh contacts": {"nominal": 0.05,
                                  "samples": np.r_[np.full(30, 0.5), np.full(10, np.inf)]}}
    r = synthetic(film=film)
    found, _ = check_limits(r, khv.to_si())
    films = [w for w in found if w.quantity.startswith("film ratio")]
    assert [(w.quantity.split(", ")[-1], w.value, w.limit) for w in films] == [
        ("the nominal design", 0.05, 0.1), (f"P50 of {n} built reducers", 0.5, 1.0),
        (f"P10 of {n} built reducers", 0.5, 1.0)]
    assert r.summary()["film_ratio_lowest"]["the mesh contacts"] == {
        "nominal": 0.05, "P50": 0.5, "P10": 0.5}
    # above the rating: the RV paper's point, 1524 N m against 412
    rv = load_case(cases_dir / "rv_paper_example.toml").to_si()
    over = synthetic(settings={**SETTINGS, "operating_output_torque_Nm": 1524.0})
    torque = [w for w in check_limits(over, rv)[0] if w.quantity == "output torque"]
    assert torque and torque[0].limit == pytest.approx(412.0)


def test_warnings_reach_summary_json_and_report_md(khv, tmp_path):
    r = synthetic()
    found, drawn = check_limits(r, khv.to_si())
    import dataclasses
    r = dataclasses.replace(r, warnings=tuple(found), limits=drawn)
    write_tolerance(r, tmp_path)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert [w["message"] for w in summary["warnings"]] == [str(w) for w in found]
    md = (tmp_path / "report.md").read_text()
    assert "## Limits checked" in md and "## Warnings" in md
    assert "against the allowable 1500 MPa (material.allowable_contact_stress_MPa)" in md


# -- pictures -----------------------------------------------------------------------------------

def test_titles_break_between_zones_and_name_the_operating_point():
    title = report.histograms_title({**SETTINGS, "case": "c"})
    for width in (30, 45, 110):
        lines = wrap(title, width).split("\n")
        for zone in ("pin diameter lower -0.005 mm", "crank hole position 0.005 mm",
                     "disc profile 0.003 mm"):
            assert any(zone in line for line in lines), (width, lines)
    assert "operating point 40 N m output, 1500 rpm input" in title
    shares = wrap(report.shares_title({**SETTINGS, "case": "c"}), 40)
    assert any("10 built reducers" in line for line in shares.split("\n"))
    assert "a ranking" in shares


def _drawn(ax):
    """x of every vertical line and the texts of the annotations of an axes."""
    xs = [line.get_xdata()[0] for line in ax.get_lines() if len(line.get_xdata())]
    notes = [t.get_text() for t in ax.texts]
    return xs, notes


def test_histogram_marks_lie_inside_or_are_edge_arrows(khv):
    """The nominal tooth force 660 N far left of rings at 1130 N is an arrow at the edge,
    not a crushed axis; every line drawn lies inside the x-limits with a margin; the
    allowable is drawn on the pressure's; the count axes have integer ticks."""
    from matplotlib.ticker import MaxNLocator

    r = synthetic()
    _, drawn = check_limits(r, khv.to_si())
    import dataclasses
    r = dataclasses.replace(r, limits=drawn)
    fig = report.histograms(r, r.outputs(), "t")
    try:
        axes = dict(zip(r.outputs(), fig.axes))
        force = axes["max_force_N"]
        lo, hi = force.get_xlim()
        assert lo > 1000 and any(t.startswith("nominal 660") for t in _drawn(force)[1])
        for k, ax in axes.items():
            x0, x1 = ax.get_xlim()
            for x in _drawn(ax)[0]:
                assert x0 < x < x1, (k, x, x0, x1)
                assert min(x - x0, x1 - x) >= 0.02 * (x1 - x0), k
            assert isinstance(ax.yaxis.get_major_locator(), MaxNLocator)
            assert ax.yaxis.get_major_locator()._integer, k
        assert axes["contacts_min"].xaxis.get_major_locator()._integer
        ph = axes["max_ph_MPa"]
        assert any(abs(x - 1500.0) < 1e-9 for x in _drawn(ph)[0])
        assert any("allowable 1500 MPa" in t.get_text() for t in ph.get_legend().get_texts())
    finally:
        pyplot().close(fig)


def test_a_row_without_scatter_says_so():
    r = synthetic()
    fig = report.shares(r, r.outputs(), "t")
    try:
        notes = [t.get_text() for t in fig.axes[0].texts]
        assert any(t.startswith("no scatter with any tolerance alone (10 reducers each)")
                   for t in notes)
    finally:
        pyplot().close(fig)
    md = report.markdown({**r.summary(), "share_samples": 10}, r.outputs())
    assert "| no scatter | no scatter |" in md


def test_a_counts_percentile_is_a_count():
    """The fewest pins in contact of 7 and 8 in equal numbers: P50 7 (the low side), never
    7.5."""
    r = synthetic()
    r.samples["contacts_min"][:] = np.r_[np.full(20, 7.0), np.full(20, 8.0)]
    pct = r.percentiles()["contacts_min"]
    assert pct["P50"]["value"] == 7.0 and pct["P10"]["value"] == 7.0
