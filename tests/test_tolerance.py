"""Tolerances through the contact model (issue 12): the [tolerances] section, the deviations'
gap shifts against the exact geometry, the meshing-period relabelling, the one-period
sampling checked against perturbed FE meshes, and `toothfem tolerance` end to end."""
import dataclasses
import json
import math

import numpy as np
import pytest

from toothfem.case import load_case, parse_case, case_to_dict
from toothfem.cli import main
from toothfem.errors import CaseError
from toothfem.fem.cycloid_fe import CycleSolver, solve_detailed
from toothfem.fem.cycloid_fe.built_stage import deviation_gaps
from toothfem.fem.cycloid_fe.model import _positions
from toothfem.fem.deviations import CycloidDeviation, SineDeviation, in_zone, only
from toothfem.fem.drives import drive_for
from toothfem.geometry import cycloid as cy, cycloid_distance as cyd, cycloid_mesh as cym
from toothfem.geometry.vectors import rotate
from toothfem.tolerance import tolerance_analysis
from toothfem.quantities import ALONE_OVER_ALL


#: The ensembles here fill every pitch's tables from 3 sampled pitches (the default 13 is
#: verified against re-meshed rings in tests/test_system_rings.py): the fill's accuracy is
#: not what these tests check, and 3 cold factorisations instead of 13 keep the suite's
#: time (the samples travel with the ensemble's setup to the Dask workers).
FEW_PITCH_SAMPLES = 3


@pytest.fixture(autouse=True)
def few_pitch_samples(monkeypatch):
    from toothfem import tolerance
    monkeypatch.setattr(tolerance, "PITCH_SAMPLES", FEW_PITCH_SAMPLES)


@pytest.fixture(scope="module")
def pinhousing(cases_dir):
    return load_case(cases_dir / "cycloid_pinhousing.toml")


def _with(case, **tol):
    d = case_to_dict(case)
    d["tolerances"] = {**d.get("tolerances", {}), **tol}
    return d


# -- the case section ---------------------------------------------------------------------

def test_shipped_cases_carry_tolerances(cases_dir):
    for name in ("cycloid_pinhousing", "rv40e", "sine_prototype"):
        tol = load_case(cases_dir / f"{name}.toml").to_si().tolerances
        assert tol.active(), name


@pytest.mark.parametrize("key, value, words", [
    ("pin_position_mm", -0.001, "tolerances.pin_position_mm = -0.001 is outside the valid "
                                "range [0, 0.1]"),
    ("pin_position_mm", "0.005", "tolerances.pin_position_mm"),
    ("distribution", "triangular", "tolerances.distribution = 'triangular' is not one of"),
    ("pin_diameter_lower_mm", 0.002, "tolerances.pin_diameter_lower_mm = 0.002"),
])
def test_bad_tolerances_refused_naming_the_key(pinhousing, key, value, words):
    with pytest.raises(CaseError, match="^" + words.replace("[", r"\[").replace("(", r"\(")
                       .replace(".", r"\.")):
        parse_case(_with(pinhousing, **{key: value}))


def test_tolerance_of_a_missing_part_refused(cases_dir):
    sine = load_case(cases_dir / "sine_prototype.toml")
    with pytest.raises(CaseError, match="tolerances.pin_position_mm = 0.005 applies to a "
                                        "cycloid stage"):
        parse_case(_with(sine, pin_position_mm=0.005))


def test_only_keeps_one_tolerance(pinhousing):
    tol = pinhousing.to_si().tolerances
    one = only(tol, "pin_diameter")
    assert one.active() == ["pin_diameter"]
    assert one.pin_diameter_lower_m == tol.pin_diameter_lower_m


def test_uniform_zone_fills_the_circle_evenly():
    """Uniform over a true-position zone: radius^2 uniform on [0, (T/2)^2] (mean r^2 = T^2/8,
    sampling error of 2e4 draws about 0.4 %: 2 % allowed)."""
    pts = in_zone(np.random.default_rng(3), 0.01, 20000, "uniform")
    r2 = np.sum(pts ** 2, axis=0)
    assert r2.max() <= 0.005 ** 2
    assert np.mean(r2) == pytest.approx(0.01 ** 2 / 8, rel=0.02)


# -- the gap shifts against the exact geometry --------------------------------------------

def _exact_gap(model, phi, pins, psi_guess, dev):
    """Distance from each (moved, resized) pin to the (moved) disc profile, less its radius."""
    g = model.geometry
    c = cym.pin_centres(g)[:, pins] + dev.pin_offset[:, pins]
    centre, rot = cym.disc_pose(g, [phi])
    centre = centre[:, 0] + dev.eccentricity * np.array([math.cos(phi), math.sin(phi)])
    local = rotate(c - centre[:, None], -rot[0]) - dev.member_offset[:, None]
    psi, _ = cyd.foot_point(g.generating(), local, psi_guess)
    foot = cy.working_profile(g.generating(), psi)
    return np.hypot(*(local - foot)) - g.pin_radius_m - dev.pin_radius[pins]


@pytest.mark.parametrize("pitch", [0, 7, 55])
def test_gap_shifts_match_the_exact_geometry(pinhousing, pitch):
    """First order in deviations of ~5 um on a 100 mm drive: the neglected terms are of
    order d^2/r_z ~ 10 nm; 30 nm allowed. ``pitch`` periods on, pin j + m takes pin j's
    place (the kinematics agree exactly)."""
    drive = drive_for(pinhousing)
    model = drive.fe_model()
    g = model.geometry
    zb, za = g.pin_count, drive.stage.lobe_count
    rng = np.random.default_rng(1)
    dev = CycloidDeviation(pin_offset=rng.normal(0, 3e-6, (2, zb)),
                           pin_radius=rng.normal(0, 2e-6, zb), profile=np.zeros((za, 2)),
                           member_offset=rng.normal(0, 3e-6, 2), eccentricity=2e-6)
    phi = 0.3 * drive.period_rad
    (q,), _ = _positions(model, [phi])
    (q_m,), _ = _positions(model, [phi + pitch * drive.period_rad])
    assert np.array_equal(q_m.pins, (q.pins + pitch) % zb)
    np.testing.assert_allclose(q_m.gap, q.gap, atol=1e-12)
    shift = deviation_gaps(model, q, dev, pitch)
    psi = q.psi + 2 * math.pi * pitch / za
    zero = CycloidDeviation.zero(zb, za)
    exact = _exact_gap(model, phi + pitch * drive.period_rad, q_m.pins, psi, dev) \
        - _exact_gap(model, phi + pitch * drive.period_rad, q_m.pins, psi, zero)
    assert np.max(np.abs(shift)) > 3e-6             # the deviations matter
    np.testing.assert_allclose(shift, exact, atol=3e-8)


def test_profile_deviation_closes_its_own_flank(pinhousing):
    """Material added on lobe l's flank closes exactly the gaps of the contacts on it."""
    drive = drive_for(pinhousing)
    model = drive.fe_model()
    za = drive.stage.lobe_count
    (q,), _ = _positions(model, [0.0])
    zero = CycloidDeviation.zero(drive.geometry.pin_count, za)
    lobe = int(np.floor(np.mod(q.psi[3], 2 * math.pi) * za / (2 * math.pi)))
    col = int(q.arm[3] > 0)
    prof = np.zeros((za, 2))
    prof[lobe, col] = 1e-6
    shift = deviation_gaps(model, q, dataclasses.replace(zero, profile=prof))
    assert shift[3] == pytest.approx(-1e-6)
    assert np.count_nonzero(shift) == 1


# -- the sampled contact against FE meshes with the pins moved ----------------------------

@pytest.mark.slow
def test_gap_shifts_against_remeshed_pins(pinhousing, fe_cache):
    """Three rings with pins moved (normal, 5 um zone) and resized (0 to -2 um), solved by
    the cycle mode with the nominal influence tables and gap shifts, and by the detailed
    mode with the pins moved and resized in its meshes: the same pins carry load, and the
    largest pin force agrees within 2 % (the issue's bar; measured 0.2-1.96 %, the cycle
    mode's own agreement with the detailed mode at the nominal geometry being 0.5 %: the
    Hertz local approach on b_ref patches, docs/derivations.md 6)."""
    drive = drive_for(pinhousing)
    model = drive.fe_model(pin_structure="conventional")
    phis = drive.positions(36)[[0, 13]]
    solver = CycleSolver(model, phis, cache=fe_cache)
    torque = drive.member_torque(pinhousing.to_si().declared_output_torque_Nm())
    zb, za = drive.geometry.pin_count, drive.stage.lobe_count
    for seed in (1, 2, 3):
        rng = np.random.default_rng(seed)
        dev = CycloidDeviation(pin_offset=rng.normal(0, 5e-6 / 6, (2, zb)),
                               pin_radius=rng.uniform(-2e-6, 0, zb),
                               profile=np.zeros((za, 2)), member_offset=np.zeros(2))
        cycle = solver.solve(torque, deviation=dev)
        for p, phi in enumerate(phis):
            fe = solve_detailed(model, phi, torque, deviation=dev, force_margin=8)
            f_fe, f_c = fe.load_sharing.force[0], cycle.force[p]
            assert np.array_equal(f_fe > 0, f_c > 0), (seed, p)
            assert np.max(f_fe) == pytest.approx(np.max(f_c), rel=0.02), (seed, p)


@pytest.mark.slow
def test_sine_pitches_are_periodic(cases_dir):
    """The sine pair solved a whole number of meshing periods on (hat tables of every
    tooth: exact) gives the same forces as at pitch 0 (1e-9 of the largest: round-off)."""
    case = load_case(cases_dir / "sine_prototype.toml")
    drive = drive_for(case)
    solver = drive.cycle_solver(6)
    torque = drive.member_torque(case.to_si().declared_output_torque_Nm())
    a = solver.solve(torque)
    b = solver.solve(torque, pitches=np.array([5, 17, 301, 2, 9, 44]))
    np.testing.assert_allclose(b.force, a.force, atol=1e-9 * a.force.max())
    np.testing.assert_allclose(b.transmission_error, a.transmission_error, rtol=1e-9)
    dev = SineDeviation.zero(drive.pair.planet_teeth, drive.pair.ring_teeth)
    c = solver.solve(torque, deviation=dataclasses.replace(dev, eccentricity=3e-6))
    assert c.contacts_per_position.mean() > a.contacts_per_position.mean()   # deeper mesh


# -- the ensemble --------------------------------------------------------------------------

@pytest.mark.slow
def test_ensemble_is_seeded_and_physical(pinhousing, tmp_path):
    """Same seed, same numbers, also when the run was stopped after three rings and
    resumed from the rings it kept on disk; a 5 um pin zone on the unmodified
    (zero-clearance) disc concentrates the load: the largest pin force rises above the
    nominal's and fewer pins carry; efficiencies stay within (0, 100) %; the one-tolerance
    shares sum to one."""
    from toothfem.output import resumable_dir

    kw = dict(samples=6, seed=11, positions=12, share_samples=4, progress=False,
              overrides={"disc_profile_mm": 0.0, "crank_hole_position_mm": 0.0,
                         "pin_circle_radius_mm": 0.0, "eccentricity_mm": 0.0})
    a = tolerance_analysis(pinhousing, **kw)
    with pytest.raises(KeyboardInterrupt), resumable_dir(tmp_path / "tol", "ab12") as points:
        record = points.record

        def stop_after_three(point, output):
            record(point, output)
            if len(points.done) == 3:
                raise KeyboardInterrupt
        points.record = stop_after_three
        tolerance_analysis(pinhousing, points=points, **kw)
    with resumable_dir(tmp_path / "tol", "ab12") as points:
        assert len(points.done) == 3
        solved = []
        record = points.record
        points.record = lambda point, output: (solved.append(point), record(point, output))
        b = tolerance_analysis(pinhousing, points=points, **kw)
    assert len(solved) == 1 + 6 + 2 * 4 - 3 and not set(solved) & {"0", "1", "2"}
    for k in a.samples:
        np.testing.assert_array_equal(a.samples[k], b.samples[k])
    assert np.all(a.samples["max_force_N"] > a.nominal["max_force_N"])
    assert np.all(a.samples["contacts_min"] < a.nominal["contacts_min"])
    assert np.all((a.samples["total_efficiency_pct"] > 0)
                  & (a.samples["total_efficiency_pct"] < 100))
    assert np.all(a.samples["lost_motion_arcmin"] > 0)
    names = [n for n in a.shares if n != ALONE_OVER_ALL]
    assert sorted(names) == ["pin_diameter", "pin_position"]
    for k in a.samples:
        assert sum(a.shares[n][k] for n in names) == pytest.approx(1.0)


def test_ensemble_refuses_bad_input(pinhousing):
    with pytest.raises(CaseError, match="samples = 0 is outside the valid range"):
        tolerance_analysis(pinhousing, samples=0)
    with pytest.raises(CaseError, match=r"seed = -1 is outside the valid range \[0, "):
        tolerance_analysis(pinhousing, seed=-1)
    with pytest.raises(CaseError, match="samples = 'many' must be an integer"):
        tolerance_analysis(pinhousing, samples="many")
    with pytest.raises(CaseError, match="tolerances.pin_zone_mm is not a known key"):
        tolerance_analysis(pinhousing, overrides={"pin_zone_mm": 0.01})
    with pytest.raises(CaseError, match="tolerances.pin_position_mm = -1"):
        tolerance_analysis(pinhousing, overrides={"pin_position_mm": -1.0})
    zero = {f: 0.0 for f in ("pin_position_mm", "pin_diameter_lower_mm",
                             "pin_diameter_upper_mm", "pin_circle_radius_mm",
                             "disc_profile_mm", "eccentricity_mm", "crank_hole_position_mm")}
    with pytest.raises(CaseError, match=r"\[tolerances\] has no nonzero zone"):
        tolerance_analysis(pinhousing, overrides=zero)


@pytest.mark.slow
def test_tolerance_command_writes_its_folder(cases_dir, tmp_path, capsys):
    out = tmp_path / "tol"
    code = main(["tolerance", str(cases_dir / "cycloid_pinhousing.toml"), "--samples", "8",
                 "--share-samples", "4", "--positions", "12", "--out", str(out)])
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["files"]) == {"samples.csv", "summary.json", "histograms.png",
                                     "shares.png", "report.md"}
    assert all((out / f).stat().st_size > 0 for f in summary["files"])
    rows = (out / "samples.csv").read_text().splitlines()
    assert len(rows) == 9 and rows[0].startswith("sample,max_force_N")
    md = (out / "report.md").read_text()
    assert ("| largest pin force on any disc (system model, positions over the pairing "
            "period) [N] |") in md
    assert "## Limits checked" in md
    assert isinstance(summary["warnings"], list)


def test_tolerance_command_refuses_bad_samples(cases_dir, tmp_path, capsys):
    code = main(["tolerance", str(cases_dir / "cycloid_pinhousing.toml"), "--samples", "0",
                 "--out", str(tmp_path / "x")])
    assert code == 2
    assert "samples = 0 is outside the valid range [1, 100000]" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


@pytest.mark.slow
def test_workers_give_the_same_ensemble(pinhousing):
    """Two Dask workers and one process give the same rings and numbers (draws on the
    driver, results in sample order)."""
    kw = dict(samples=6, seed=5, positions=12, share_samples=0, progress=False,
              overrides={"disc_profile_mm": 0.0})
    one = tolerance_analysis(pinhousing, workers=1, **kw)
    two = tolerance_analysis(pinhousing, workers=2, **kw)
    for k in one.samples:
        np.testing.assert_array_equal(one.samples[k], two.samples[k])
    assert one.shares == {}                 # share_samples=0: no one-tolerance runs


def test_a_scheduler_that_is_not_there_is_one_line():
    from toothfem.cluster import dask_client
    from toothfem.errors import ToothfemError

    with pytest.raises(ToothfemError, match="scheduler = 'not an address': no Dask "
                                            "scheduler there"), dask_client("not an address", None):
        pass


# -- modification design -------------------------------------------------------------------

def test_with_keys_sets_a_table_and_keeps_comments():
    from toothfem.case import with_keys

    text = ("[cycloid]            # the disc\npin_count = 40\nrotation_modification_deg = 0.0"
            "  # none\n\n[operating]\ninput_speed_rpm = 100\n")
    out = with_keys(text, "cycloid", {"rotation_modification_deg": 0.0125,
                                      "equidistant_modification_mm": 2e-5})
    assert "[cycloid]            # the disc\n" in out
    assert "rotation_modification_deg = 0.0125   # toothfem design" in out
    assert "equidistant_modification_mm = 2e-05   # toothfem design" in out
    assert out.index("equidistant_modification_mm") < out.index("[operating]")
    assert "input_speed_rpm = 100" in out
    with pytest.raises(CaseError, match=r"no \[sine\] table"):
        with_keys(text, "sine", {"x": 1.0})


def test_design_needs_its_section(cases_dir):
    from toothfem.design import design_analysis

    sine = load_case(cases_dir / "sine_prototype.toml")
    with pytest.raises(CaseError, match=r"\[design\] section is required"):
        design_analysis(sine)


@pytest.mark.slow
def test_design_meets_its_targets_or_says_by_how_much(pinhousing, monkeypatch, tmp_path):
    """A short search (8 Sobol points, 8 refinements) on the pin-housing drive meets a
    2 arcmin backlash with at least 4 pins, its winner verified with its own tables (the
    case's tables with the winner's gaps give the same pressure within 1 %: micrometre
    modifications change the gaps, not the compliance); a target no modification in the
    bounds meets is refused naming it and the shortfall."""
    from toothfem import design as ds

    monkeypatch.setattr(ds, "DOE_POINTS", 8)
    monkeypatch.setattr(ds, "REFINE_EVALUATIONS", 8)
    case = dataclasses.replace(pinhousing, design=dataclasses.replace(
        pinhousing.design, percentile=None, max_backlash_arcmin=2.0))
    res = ds.design_analysis(case, positions=12, progress=False)
    assert res.best.feasible and res.best.backlash_arcmin <= 2.0
    assert res.best.contacts_min >= 4
    c = res.check
    assert c["max_ph_MPa"] == pytest.approx(c["search_tables_max_ph_MPa"], rel=0.01)
    assert c["backlash_arcmin"] == pytest.approx(c["search_tables_backlash_arcmin"],
                                                 rel=0.01)
    from toothfem.report.design import write_design
    summary = write_design(res, tmp_path, "[cycloid]\npin_count = 40\n")
    assert (tmp_path / "tradeoff.png").stat().st_size > 0
    assert summary["best"]["feasible"]
    assert "rotation_modification_deg = " in (tmp_path / "best_case.toml").read_text()
    strict = dataclasses.replace(case, design=dataclasses.replace(
        case.design, max_backlash_arcmin=0.01, min_contacts=30))
    with pytest.raises(CaseError, match=r"no modification within the \[design\] bounds meets"
                                        r" the targets: the closest .* misses "):
        ds.design_analysis(strict, positions=12, progress=False)


def test_each_tolerance_may_have_its_own_distribution(pinhousing):
    """`pin_position_distribution = "uniform"` beside a normal section: the pins stay in
    their zone (uniform never leaves it, where a 3-sigma 2D normal leaves it for 1.1 % of
    draws: with 40 pins x 200 rings, about 90), the other tolerances stay normal (the disc
    flanks pass their +-limit for 0.27 % of 16 000 draws)."""
    case = parse_case(_with(pinhousing, pin_position_distribution="uniform",
                            pin_circle_radius_mm=0.0))
    tol = case.to_si().tolerances
    assert tol.distribution_of("pin_position") == "uniform"
    assert tol.distribution_of("disc_profile") == "normal"
    drive = drive_for(case)
    rng = np.random.default_rng(2)
    devs = [drive.sample_deviation(tol, rng) for _ in range(200)]
    reach = np.concatenate([np.hypot(*d.pin_offset) for d in devs])
    assert np.max(reach) <= 0.5 * tol.pin_position_m
    assert np.max(reach) > 0.45 * tol.pin_position_m          # the zone is filled
    profile = np.concatenate([d.profile.ravel() for d in devs])
    assert np.max(np.abs(profile)) > tol.disc_profile_m


def test_percentile_intervals_cover_and_refuse_too_few_rings():
    """The distribution-free interval of a percentile holds the true value at least about
    95 % of the time (400 normal samples of 100: the binomial's discreteness makes it
    conservative; below 91 % would be 4 sigma off); P99 is not given from 200 rings (it
    needs 368), P10/P90 need 36."""
    from scipy.stats import norm

    from toothfem.tolerance_result import percentile_ci, rings_needed

    assert (rings_needed(0.5), rings_needed(0.9), rings_needed(0.1), rings_needed(0.99)) == \
        (6, 36, 36, 368)
    rng = np.random.default_rng(3)
    truth = norm.ppf(0.9)
    hits = 0
    for _ in range(400):
        lo, hi = percentile_ci(rng.normal(size=100), 0.9)["ci"]
        hits += lo <= truth <= hi
    assert hits / 400 > 0.91
    few = percentile_ci(rng.normal(size=200), 0.99)
    assert few["value"] is None and few["ci"] is None and few["rings_needed"] == 368


def test_percentiles_on_the_unfavourable_side():
    """Fewest contacts and efficiencies by P10/P1 (low is worse), the rest by P90/P99."""
    from toothfem.report.tolerance import TAIL_COLUMNS, summary_rows
    from toothfem.tolerance_result import OUTPUTS, ToleranceResult

    rng = np.random.default_rng(0)
    samples = {k: rng.normal(10, 1, size=50) for k in OUTPUTS}
    result = ToleranceResult(case_name="c", drive="cycloid", contact_name="pin",
                             contacts_name="pins", samples=samples,
                             nominal={k: 10.0 for k in OUTPUTS}, shares={}, settings={})
    pct = result.percentiles()
    assert list(pct["contacts_min"]) == ["P50", "P10", "P1"]
    assert list(pct["total_efficiency_pct"]) == ["P50", "P10", "P1"]
    assert list(pct["max_force_N"]) == ["P50", "P90", "P99"]
    assert pct["max_force_N"]["P90"]["value"] > pct["max_force_N"]["P50"]["value"]
    assert pct["contacts_min"]["P10"]["value"] < pct["contacts_min"]["P50"]["value"]
    rows = dict((label, cells) for label, _, cells in summary_rows(result.summary(), OUTPUTS))
    force = rows[OUTPUTS["max_force_N"][0]]
    assert force[TAIL_COLUMNS[1]].startswith("P90 ") and "[" in force[TAIL_COLUMNS[1]]
    assert force[TAIL_COLUMNS[2]] == "P99: needs 368 reducers"


# -- the design report: nominal and percentile told apart ------------------------------------

def _search(percentile=90.0, samples=8):
    """A made-up search: 34 candidates that meet the targets around 1565 MPa, one far
    point at 2236 MPa, the best at P90 0.73 arcmin / 1564 MPa, as drawn 0.58 / 986."""
    from toothfem.design import Candidate, DesignResult

    rng = np.random.default_rng(0)
    mod = {"equidistant_modification_mm": 0.0118, "move_distance_modification_mm": -0.0032,
           "rotation_modification_deg": -0.0166}
    cands = [Candidate(modification=mod, backlash_arcmin=float(b), max_ph_MPa=float(p),
                       contacts_min=4.0, feasible=True)
             for b, p in zip(rng.uniform(0.1, 0.98, 34), rng.uniform(1564, 1600, 34))]
    cands += [Candidate(modification=mod, backlash_arcmin=-1.3, max_ph_MPa=2236.0,
                        contacts_min=6.0, feasible=False),
              Candidate(modification=mod, backlash_arcmin=5.0, max_ph_MPa=1600.0,
                        contacts_min=4.0, feasible=False)]
    best = Candidate(modification=mod, backlash_arcmin=0.7312, max_ph_MPa=1563.9,
                     contacts_min=4.0, feasible=True)
    cands.append(best)
    targets = {"max_backlash_arcmin": 1.0, "min_contacts": 4, "max_ph_MPa": None,
               "percentile": percentile, "samples": samples}
    check = {"max_ph_MPa": 986.0, "contacts_min": 6.0, "backlash_arcmin": 0.5824,
             "search_tables_max_ph_MPa": 985.6, "search_tables_contacts_min": 6.0,
             "search_tables_backlash_arcmin": 0.5824}
    return DesignResult(case_name="c", targets=targets, candidates=cands, best=best,
                        datasheet={"rated_torque_Nm": 167.0}, check=check, case=None,
                        output_torque_Nm=167.0, member_torque_Nm=88.8,
                        limits={"max_ph_MPa": [{"name": "allowable", "value": 1500.0,
                                                "unit": "MPa", "source": "s"}]})


def test_design_percentile_says_when_it_has_no_interval():
    from toothfem.design import percentile_interval

    few = percentile_interval({"percentile": 90.0, "samples": 8})
    assert not few["has_interval"] and few["rings_needed"] == 36
    assert few["text"].startswith("P90 of 8 built reducers: no 95 % interval (a P90 needs 36")
    assert percentile_interval({"percentile": 90.0, "samples": 40})["has_interval"]
    assert percentile_interval({"percentile": None, "samples": 8}) is None


def test_design_report_tells_nominal_from_percentile():
    """The printed table and report.md put the design as drawn (nominal) beside its P90,
    the P90's column saying it has no 95 % interval from 8 reducers."""
    from toothfem.report import design as report

    summary = {**_search().summary(), "evaluations": 37}
    rows = {what: cols for what, _, cols in report.summary_rows(summary)}
    pc = "P90 of 8 reducers (no 95 % interval: needs 36)"
    assert rows["backlash"] == {report.NOMINAL_COLUMN: 0.5824, pc: 0.7312}
    assert rows["max P_h"] == {report.NOMINAL_COLUMN: 986.0, pc: 1563.9}
    md = report.markdown(summary)
    assert "**The percentile has no 95 % confidence interval**" in md
    assert "| the same design as drawn (nominal, its own FE tables) |" in md
    assert "| best, P90 of 8 built reducers: no 95 % interval" in md


def test_tradeoff_zooms_on_the_feasible_and_marks_the_rest():
    """The right panel is the window of the candidates that meet the targets (not the
    2236 MPa outlier's scale); the points outside it are counted in its title; the star's
    legend entry has the P90 figures and the nominal's its own."""
    from toothfem.report import design as report, pyplot

    fig = report.tradeoff(_search())
    try:
        full, zoom = fig.axes[:2]
        lo, hi = zoom.get_ylim()
        assert 1500 < lo < 1564 and 1600 < hi < 1700
        assert full.get_ylim()[1] > 2236
        title = zoom.get_title().replace("\n", " ")
        assert "1 above (to 2236 MPa)" in title and "the best as drawn below" in title
        labels = [t.get_text().replace("\n", " ") for t in zoom.get_legend().get_texts()]
        assert any(x.startswith("best, P90 of 8 built reducers: no 95 % interval")
                   and "backlash 0.731 arcmin, P_h 1564 MPa" in x for x in labels)
        assert any("as drawn (nominal" in x and "P_h 986 MPa" in x for x in labels)
        assert any(x.startswith("allowable P_h 1500 MPa") for x in labels)
    finally:
        pyplot().close(fig)
