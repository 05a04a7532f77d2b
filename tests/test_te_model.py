"""The model side of TE and hysteresis recordings (efficiency/loop/te/model.py,
synthetic_model.py; the system model's crank errors, stiffness scales and forced
deformations, fem/system; docs/te_model.md). Rigid bodies on equal contact springs (no
FE: fast) except the one run marked slow."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from toothfem.case import load_case
from toothfem.efficiency.loop.te.model import (Effects, RecordingModel, model_recordings,
                                               te_orders)
from toothfem.efficiency.loop.te.synthetic_model import (Noise, sweep, write_atomic,
                                                         write_synthetic_recordings)
from toothfem.errors import CaseError
from toothfem.fem.datasheet.sheet import datasheet
from toothfem.fem.datasheet.twist import ARCMIN, ARCSEC
from toothfem.fem.drives import drive_for
from toothfem.fem.system import elements as el
from toothfem.fem.system.datasheet import SystemTwist, system_te
from toothfem.fem.system.solve import ContactSet, Element, solve
from toothfem.geometry.cycloid_mesh import pin_centres

#: Equal contact springs of the fast models [m/N] (a pin contact's order of magnitude).
SPRING = 2e-9
#: Every part but the pins rigid (the kinematic limit of the backlash).
ALL_RIGID = ("crank bearings", "support bearings", "crankshaft bending",
             "crankshaft torsion", "spur mesh")


@pytest.fixture(scope="module")
def rv(cases_dir):
    """The shipped RV-40E without its equidistant modification (4.5 um of play, sized for
    the built reducers): the effects below are measured from flanks that touch."""
    case = load_case(cases_dir / "rv40e.toml")
    return dataclasses.replace(case, cycloid=dataclasses.replace(
        case.cycloid, equidistant_modification_mm=0.0))


@pytest.fixture(scope="module")
def khv(cases_dir):
    return load_case(cases_dir / "cycloid_khv.toml")


@pytest.fixture(scope="module")
def rv_model(rv):
    """rv40e on equal springs, 2 positions a pitch (the TE over all 39 pitches in 0.3 s)."""
    return RecordingModel(rv, positions=2, cache=False, pin_spring_m_per_N=SPRING)


def springs(case, n=4, **options):
    """The system model on equal pin springs and a rigid carrier (the mechanics below)."""
    drive = drive_for(case)
    supports = dataclasses.replace(drive.supports(case.to_si().supports),
                                   carrier_stiffness_Nm_per_rad=None)
    return drive.system_model(supports, n, cache=False, pin_spring_m_per_N=SPRING, **options)


# -- the solver's forced deformation ------------------------------------------------------

def test_forced_deformation_is_an_initial_strain():
    """One body between two linear springs, the first forced by an offset o: equilibrium
    u = -k1 o / (k1 + k2) (the springs in parallel against the strain), both laws (a linear
    law assembled once, a nonlinear one evaluated per step: a Scaled wrapper); the work
    balance counts the bodies' part of the deformation, so Q u still adds up."""
    k1, k2, o = 3e8, 1e8, 2e-6
    for law in (el.linear([[k1]]), el.Scaled(el.linear([[k1]]), 1.0)):
        elems = [Element("a", "a", np.array([[1.0]]), law, offset=np.array([o])),
                 Element("b", "b", np.array([[1.0]]), el.linear([[k2]]))]
        far = ContactSet("far", "far", np.array([1.0]), np.array([[1.0]]))   # never closes
        eq = solve(1, elems, [far], np.array([0.0]), active0={"far": np.array([False])},
                   rate=False)
        assert eq.u[0] == pytest.approx(-k1 * o / (k1 + k2), rel=1e-9)
        assert eq.element_deformation["a"][0] == pytest.approx(o * k2 / (k1 + k2), rel=1e-9)
        assert sum(eq.work.values()) == pytest.approx(0.0, abs=1e-9 * k1 * o * o)


def test_zero_crank_errors_solve_as_the_drawing(rv):
    """A deviation whose crank errors are zero gives the nominal solve bit for bit, and
    Effects() gives no deviation at all."""
    s = springs(rv)
    zero = dataclasses.replace(s.drive.nominal_deviation(), crank_eccentricity_m=(0.0, 0.0),
                               crank_phase_rad=(0.4, 0.1))
    for p in range(4):
        a, b = s.solve(412.0, p), s.solve(412.0, p, deviation=zero)
        assert a.twist_rad == b.twist_rad
        assert np.array_equal(a.pin_force_N, b.pin_force_N)
    assert Effects().deviation(s.drive) is None and Effects().geometry(s.drive) is None


def test_equal_crank_errors_are_the_eccentricity_error(rv):
    """2K-V: the same error on every crank (one phase) moves each disc by de u(phi_j) with
    no bearing deformed, which is what the deviation's ``eccentricity`` does to the pins'
    gaps: twist, disc torques and pin forces agree to the solver's tolerance (1e-9)."""
    s = springs(rv)
    nom = s.drive.nominal_deviation()
    cranks = dataclasses.replace(nom, crank_eccentricity_m=(5e-6, 5e-6))
    ecc = dataclasses.replace(nom, eccentricity=5e-6)
    for p in range(4):
        a, b = s.solve(412.0, p, deviation=cranks), s.solve(412.0, p, deviation=ecc)
        assert a.twist_rad == pytest.approx(b.twist_rad, rel=1e-9)
        assert a.disc_torque_Nm == pytest.approx(b.disc_torque_Nm, rel=1e-9)
        assert a.pin_force_N == pytest.approx(b.pin_force_N, rel=1e-6,
                                              abs=1e-6 * a.pin_force_N.max())
        # the paths still add up to the twist with forced deformations
        assert sum(a.paths_rad.values()) == pytest.approx(a.twist_rad, rel=1e-9)


def test_khv_crank_error_also_closes_the_output_pins(khv):
    """K-H-V: the disc's move de also closes its output-pin holes by de (the holes orbit
    the pins at the eccentricity), which ``eccentricity`` leaves out; with the holes
    widened by de the crank error is the eccentricity error again (1e-9)."""
    de = 5e-6
    om = khv.output_mechanism
    wide = dataclasses.replace(khv, output_mechanism=dataclasses.replace(
        om, hole_radius_mm=om.hole_radius_mm + de * 1e3))
    a, b, c = springs(khv), springs(wide), springs(khv)
    ecc = dataclasses.replace(a.drive.nominal_deviation(), eccentricity=de)
    crank = dataclasses.replace(b.drive.nominal_deviation(), crank_eccentricity_m=(de,))
    for p in range(4):
        t_ecc = a.solve(40.0, p, deviation=ecc).twist_rad
        assert b.solve(40.0, p, deviation=crank).twist_rad == pytest.approx(t_ecc, rel=1e-9)
        # on the drawn holes the output pins interfere by de: far from the eccentricity's
        assert abs(c.solve(40.0, p, deviation=crank).twist_rad / t_ecc - 1) > 0.1


# -- the period, the orders ----------------------------------------------------------------

def test_periods_of_the_effects(rv, khv):
    """rv40e: the holes' period Za = 39 pitches; a crank's error repeats per turn of the
    crank against the carrier (Za pitches); a pin's after Zb, so with the holes Zb Za; one
    radius change of every pin changes none. K-H-V: the eccentric on the axis adds none."""
    d = drive_for(rv)
    nom = d.nominal_deviation()
    assert d.deviation_period_pitches(None) == 39
    assert d.crank_period_pitches() == 39
    assert d.deviation_period_pitches(dataclasses.replace(
        nom, crank_eccentricity_m=(1e-6, 0.0))) == 39
    radius = np.zeros(40)
    radius[3] = 1e-6
    assert d.deviation_period_pitches(dataclasses.replace(nom, pin_radius=radius)) == 1560
    assert d.deviation_period_pitches(Effects(pin_radius_m=2e-6).deviation(d)) == 39
    k = drive_for(khv)
    assert k.deviation_period_pitches(Effects(crank_eccentricity_m=(3e-6,)).deviation(k)) == 29


def test_te_orders_are_the_drives(rv):
    """The spectrum's names are the drive's own; a 2K-V crank turns against the carrier Zb
    = 40 times per output revolution (its own errors' order), the entry the drive names
    after the pins' passing."""
    orders = te_orders(rv)
    assert orders == drive_for(rv).te_orders()
    d = drive_for(rv)
    w = d.speeds()
    crank_vs_carrier = abs(w["crank"] - w["output"]) / abs(w["output"])
    assert crank_vs_carrier == pytest.approx(40.0, rel=1e-12)
    assert any(abs(q - 40.0) < 1e-9 for q in orders.values())


# -- the TE and the loop of the recording model --------------------------------------------

def test_nominal_model_te_is_system_te(rv, rv_model):
    """Without friction the model's TE is the datasheet's (``system_te`` at the same
    sampled pitches), exactly; with the case's friction it is the datasheet's TE at the
    output torque plus the running losses (the efficiency model's, as a torque on the
    output); its loop is the datasheet's, exactly."""
    te, = rv_model.te(Effects(friction_scale=0.0), (412.0,), samples=5)
    ref, _, _ = system_te(rv_model.drive, rv_model.supports, 412.0, samples=5, per_pitch=2,
                          cache=False, pin_spring_m_per_N=SPRING)
    back, _, _ = system_te(rv_model.drive, rv_model.supports, -412.0, samples=5, per_pitch=2,
                           cache=False, pin_spring_m_per_N=SPRING)
    assert np.array_equal(te.te_forward_rad, ref.te_rad)
    assert np.array_equal(te.te_backward_rad, back.te_rad)
    assert np.array_equal(te.output_angle_rad, ref.output_angle_rad)
    running, = rv_model.te(Effects(), (412.0,), samples=5)
    loss = rv_model.running_loss_torque_Nm(412.0, Effects())
    assert 0.05 * 412 < loss < 0.25 * 412          # an RV-40E's 80-95 % efficiency
    ref_f, _, _ = system_te(rv_model.drive, rv_model.supports, 412.0 + loss, samples=5,
                            per_pitch=2, cache=False, pin_spring_m_per_N=SPRING)
    assert np.array_equal(running.te_forward_rad, ref_f.te_rad)
    assert running.width_arcsec > te.width_arcsec
    loop = rv_model.hysteresis(Effects())
    sheet = datasheet(SystemTwist(rv_model.system(0), friction=rv_model.friction), 412.0,
                      steps=4)
    assert loop.lost_motion_arcmin == sheet.lost_motion_arcmin
    assert loop.rigidity_Nm_per_arcmin == sheet.rigidity_Nm_per_arcmin
    # the staircase's branches: the falling one from +T to -T, the rising one back
    assert loop.falling_torque_Nm[0] == 412.0 and loop.falling_torque_Nm[-1] == -412.0
    assert loop.rising_torque_Nm[0] == -412.0 and loop.rising_torque_Nm[-1] == 412.0
    assert np.all(loop.falling_twist_arcmin >= np.interp(
        loop.falling_torque_Nm, loop.rising_torque_Nm, loop.rising_twist_arcmin) - 1e-12)


def test_the_running_width_at_zero_torque_is_the_friction(rv_model):
    """At zero output torque the running reducer's path still carries its no-load losses
    (churning, seals, bearings' viscous moments): the model's width there is twice their
    twist, not zero as the frictionless TE of a case without play gives (issue 39). The
    friction factor scales it."""
    bare, = rv_model.te(Effects(friction_scale=0.0), (0.0,), samples=5)
    run, = rv_model.te(Effects(), (0.0,), samples=5)
    twice, = rv_model.te(Effects(friction_scale=2.0), (0.0,), samples=5)
    assert abs(bare.width_arcsec) < 0.01
    drag = rv_model.running_loss_torque_Nm(0.0, Effects())
    assert drag > 0
    assert run.width_arcsec > 1.0
    assert twice.width_arcsec > 1.5 * run.width_arcsec


def test_one_eccentric_ripples_at_the_crank_order(rv_model):
    """rv40e, all 39 pitches: a 5 um error of one eccentric (crank 1 at disc 1) turns the
    output once per turn of the crank against the carrier: the TE's harmonic at order 40
    per output revolution grows from 0.003 to 6.9 arcsec (equal springs; 8.3 on the
    30 mm crank circle the case had before it was sized: 8.3 x 30/36 = 6.9, the error's
    turn over the crank circle). The whole crank's error (both its eccentrics, 180 deg apart) pushes the two
    discs opposite ways: their turns cancel at order 40 (below 0.01 arcsec) and the
    split between the discs ripples there instead (+-13 % of the torque on the sized
    RV-40E's stiff crank bearings; +-5 % on the 20 mm holes it had before)."""
    # the elastic states at 412 N m (friction_scale 0: the running losses left out)
    one = Effects(crank_eccentricity_m=((5e-6, 0.0), (0.0, 0.0)), friction_scale=0.0)
    crank = Effects(crank_eccentricity_m=(5e-6, 0.0), crank_phase_rad=(0.3, 0.0),
                    friction_scale=0.0)
    nominal, single, whole = (rv_model.te(e, (412.0,), samples=39)[0]
                              for e in (Effects(friction_scale=0.0), one, crank))
    assert nominal.period_pitches == 39 and nominal.period_output_rad == pytest.approx(
        2 * math.pi / 40)
    assert nominal.amplitude_arcsec(40) < 0.01
    assert single.amplitude_arcsec(40) == pytest.approx(8.3 * 30 / 36, rel=0.02)
    assert single.amplitude_arcsec(40, -1) == pytest.approx(8.3 * 30 / 36, rel=0.02)
    assert whole.amplitude_arcsec(40) < 0.01
    share = whole.share_forward[0]
    ripple = 2 * np.abs(np.fft.rfft(share - share.mean())) / share.size
    assert ripple[1] == pytest.approx(0.128, rel=0.05)           # order 40: the first
    assert np.argmax(ripple) == 1
    assert np.max(nominal.share_forward) == pytest.approx(0.5, abs=1e-9)
    # a few sampled pitches and the Fourier fill give the same harmonic (1 %)
    assert rv_model.te(one, (412.0,), samples=7)[0].amplitude_arcsec(40) == pytest.approx(
        single.amplitude_arcsec(40), rel=0.01)


def test_khv_eccentric_error_adds_no_ripple(khv):
    """K-H-V: the eccentric sits on the input shaft's axis, so its error turns with it and
    looks alike at every position: no ripple at the crank's order (Zb = 30 against the
    output), only the level (the output pins bind, above); the period stays 29 pitches."""
    m = RecordingModel(khv, positions=2, cache=False, pin_spring_m_per_N=SPRING)
    nom, err = (m.te(e, (40.0,), samples=29)[0]
                for e in (Effects(), Effects(crank_eccentricity_m=(3e-6,),
                                             crank_phase_rad=(1.0,))))
    assert err.period_pitches == 29
    assert err.amplitude_arcsec(30) == pytest.approx(nom.amplitude_arcsec(30), abs=0.01)
    assert abs(err.te_forward_arcsec.mean() - nom.te_forward_arcsec.mean()) > 1.0


def test_crank_bearing_play_widens_the_loop(rv_model):
    """10 um of crank-bearing play: lost motion and hysteresis loss grow by about the
    play's turn of the discs (0.19 arcmin of backlash on equal springs, 10 um over the
    36 mm crank circle and the discs' lever), the TE rises."""
    nom, play = rv_model.hysteresis(), rv_model.hysteresis(Effects(crank_bearing_play_m=10e-6))
    assert nom.backlash_arcmin == pytest.approx(0.0, abs=1e-4)
    assert play.backlash_arcmin > 0.15
    assert play.lost_motion_arcmin > nom.lost_motion_arcmin + 0.5
    assert play.hysteresis_loss_arcmin > nom.hysteresis_loss_arcmin + 0.2
    a, = rv_model.te(Effects(), (412.0,), samples=3)
    b, = rv_model.te(Effects(crank_bearing_play_m=10e-6), (412.0,), samples=3)
    assert b.te_forward_arcsec.mean() > a.te_forward_arcsec.mean() + 10
    assert b.width_arcsec > a.width_arcsec


def test_profile_clearance_gives_its_closing_angle(rv):
    """An equidistant modification of 10 um on the nominal tables: the TE's width at zero
    torque (forward less backward, each the clearance's closing from its side) is the
    2K-V closing angle 2 d / (e (Za + 1 + z_s/z_p)) (issue 21), 1.311 arcmin; 0.5 % (the
    closed form is the continuous minimum of the discrete pins' gaps)."""
    m = RecordingModel(rv, positions=4, cache=False, pin_spring_m_per_N=1e-14,
                       rigid=ALL_RIGID)
    # no running losses: the width at zero torque is the clearance's alone
    te, = m.te(Effects(equidistant_modification_m=1e-5, friction_scale=0.0), (0.0,),
               samples=1)
    d = m.drive
    closed = 2e-5 / (d.geometry.eccentricity_m * (d.stage.lobe_count + 1 + 12 / 36)) / ARCMIN
    assert closed == pytest.approx(1.3113, abs=1e-3)
    assert te.width_arcsec / 60 == pytest.approx(closed, rel=5e-3)


def test_stiffness_scale_is_the_part_made_stiffer(rv):
    """A scale s on the mesh with equal springs c is springs c/s, and on linear crank
    bearings k is 2k: the same solve (1e-9). Unknown parts are refused."""
    a = springs(rv, stiffness_scale={"mesh": 2.0})
    drive = drive_for(rv)
    sup = dataclasses.replace(drive.supports(rv.to_si().supports),
                              carrier_stiffness_Nm_per_rad=None)      # as springs()
    b = drive.system_model(sup, 4, cache=False, pin_spring_m_per_N=SPRING / 2)
    c = springs(rv, crank_bearing_stiffness_N_per_m=5e8,
                stiffness_scale={"crank bearings": 2.0})
    d = springs(rv, crank_bearing_stiffness_N_per_m=1e9)
    for p in range(2):
        assert a.solve(412.0, p).twist_rad == pytest.approx(b.solve(412.0, p).twist_rad,
                                                            rel=1e-9)
        assert c.solve(412.0, p).twist_rad == pytest.approx(d.solve(412.0, p).twist_rad,
                                                            rel=1e-9)
    assert c.variant(stiffness_scale={}).solve(412.0, 0).twist_rad > d.solve(412.0, 0).twist_rad
    with pytest.raises(CaseError, match="not parts of the model"):
        springs(rv, stiffness_scale={"housing": 2.0})
    with pytest.raises(CaseError, match="> 0"):
        springs(rv, stiffness_scale={"mesh": 0.0})


def test_effects_refused_in_one_line(rv):
    """Crank errors of another shape, pins of another count, negative friction scale."""
    m = RecordingModel(rv, positions=2, cache=False, pin_spring_m_per_N=SPRING)
    with pytest.raises(CaseError, match="one value per crank"):
        m.te(Effects(crank_eccentricity_m=(1e-6, 0.0, 0.0)), (100.0,), samples=1)
    with pytest.raises(CaseError, match="one per pin"):
        Effects(pin_radius_m=np.zeros(7) + 1e-6).deviation(m.drive)
    with pytest.raises(CaseError, match=">= 0"):
        Effects(friction_scale=-1.0)
    with pytest.raises(CaseError, match=">= 0"):
        m.te(Effects(), (-5.0,))


def test_pin_errors_run_over_the_revolution(rv_model):
    """A pin's radius error stretches the period to an output revolution (1560 pitches),
    sampled and filled; an oversize pin set alike on every pin keeps the period."""
    radius = np.zeros(40)
    radius[0] = 3e-6
    te, = rv_model.te(Effects(pin_radius_m=radius), (412.0,), samples=5)
    assert te.period_pitches == 1560
    assert te.period_output_rad == pytest.approx(2 * math.pi)
    uniform, = rv_model.te(Effects(pin_radius_m=1e-6), (412.0,), samples=3)
    assert uniform.period_pitches == 39


def test_model_recordings_one_call(rv):
    """model_recordings: the loop and the TE at each torque (0: the clearance's closing
    from each side, so forward and backward differ by the backlash)."""
    rec = model_recordings(rv, Effects(crank_bearing_play_m=5e-6), (0.0, 412.0), positions=2,
                           te_samples=3, cache=False,
                           system_options={"pin_spring_m_per_N": SPRING})
    assert [t.output_torque_Nm for t in rec.te] == [0.0, 412.0]
    assert rec.te[0].width_arcsec > 0
    assert rec.loop.effects.crank_bearing_play_m == 5e-6


# -- synthetic recordings -------------------------------------------------------------------

def test_atomic_write_leaves_no_temporary(tmp_path):
    p = write_atomic(tmp_path / "a.csv", "x\n1\n")
    assert p.read_text() == "x\n1\n"
    assert sorted(q.name for q in tmp_path.iterdir()) == ["a.csv"]


def test_sweep_repeats_the_period(rv_model):
    """A sweep of two revolutions is the period's TE repeated, at the model's grid."""
    te, = rv_model.te(Effects(), (412.0,), samples=3)
    angle, values = sweep(te, 1, 2)
    n = te.output_angle_rad.size
    assert angle.size == 2 * 40 * n
    assert np.allclose(np.diff(angle), angle[1])
    assert np.array_equal(values[:n], te.te_forward_rad)
    assert np.array_equal(values[5 * n:6 * n], te.te_forward_rad)


def test_synthetic_recordings_read_back(rv_model, tmp_path):
    """Both TE shapes and the staircase, with a crank's error undeclared and the encoder
    noise: headers say synthetic, the effect and its true value, the noise and each
    file's offset; the re-zeroed file carries its extra offset; the files' TE less their
    offsets is the model's within the noise; the rig reader takes every file and its
    figures are the model's (width within 0.1 arcsec, lost motion within 1 %)."""
    from toothfem.efficiency.loop import te as rig
    effects = Effects(crank_eccentricity_m=(5e-6, 0.0), crank_phase_rad=(0.3, 0.0))
    noise = Noise(rezero_at=1, rezero_offset_arcsec=300.0, seed=3)
    rec = write_synthetic_recordings(tmp_path, rv_model.case, effects, (103.0, 412.0),
                                     model=rv_model, noise=noise, te_samples=5, revolutions=1)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["hysteresis.csv", "te_103Nm.csv", "te_412Nm.csv", "te_long.csv"]
    head = rec.te_files[1].read_text().splitlines()[:9]
    assert head[0].startswith("# synthetic:")
    assert "# effect: crank_eccentricity_m = [5e-06, 0.0]; crank_phase_rad = [0.3, 0.0]" in head
    assert any(h.startswith("# noise: white Gaussian encoder noise 1 arcsec rms") for h in head)
    assert "# output_torque_Nm: 412" in head and "# oil_temp_C: 40" in head
    assert head[-1] == "output_angle_deg,te_forward_arcsec,te_backward_arcsec"
    assert rec.te_offsets_arcsec[1] > 200                 # the re-zeroed file
    data = np.loadtxt(rec.te_files[1], delimiter=",", comments="#", skiprows=9)
    model = rec.te[1]
    n = model.te_forward_arcsec.size
    resid = data[:n, 1] - rec.te_offsets_arcsec[1] - model.te_forward_arcsec
    assert abs(resid.mean()) < 0.2 and resid.std() == pytest.approx(1.0, rel=0.1)
    long = np.genfromtxt(rec.long_file, delimiter=",", comments="#", skip_header=8)
    assert set(long[:, 1]) == {1.0, -1.0} and set(long[:, 2]) == {103.0, 412.0}
    hyst = np.genfromtxt(rec.hysteresis_file, delimiter=",", comments="#", skip_header=8)
    assert hyst.shape == (rec.loop.torque_Nm.size * 20, 3) and set(hyst[:, 2]) == {1.0, -1.0}
    read = rig.read_te_recordings([str(p) for p in rec.te_files], progress=False)
    assert not read.refused
    rows = rig.te_figures(read, named_orders=rv_model.te_orders()).rows()
    for row, te in zip(sorted(rows, key=lambda r: r["output_torque_Nm"]), rec.te):
        assert row["width_arcsec"] == pytest.approx(te.width_arcsec, abs=0.1)
    loops = rig.read_hysteresis_recordings([str(rec.hysteresis_file)],
                                           rated_torque_Nm=rv_model.rated_torque_Nm,
                                           progress=False)
    got = loops.figures[0].summary()
    assert got["lost_motion_arcmin"] == pytest.approx(rec.loop.lost_motion_arcmin, rel=0.01)
    assert got["torsional_rigidity_Nm_per_arcmin"] == pytest.approx(
        rec.loop.rigidity_Nm_per_arcmin, rel=0.01)


@pytest.mark.slow
def test_one_eccentric_with_the_fe(cases_dir):
    """The FE tables (7 sampled pitches, 4 positions; about a minute on a cold cache): a
    5 um error of one eccentric gives 6.9 arcsec at order 40 on rv40e (as on equal
    springs), and 10 um of crank-bearing play raises the lost motion from the case's 0.847
    arcmin (its 4.5 um modification's play included: the stiffness command's figure) to
    1.82 arcmin (regressions, 1 %)."""
    m = RecordingModel(load_case(cases_dir / "rv40e.toml"))
    te, = m.te(Effects(crank_eccentricity_m=((5e-6, 0.0), (0.0, 0.0)),
                       crank_phase_rad=((0.3, 0.0), (0.0, 0.0))))
    assert te.amplitude_arcsec(40) == pytest.approx(8.3 * 30 / 36, rel=0.02)
    assert m.hysteresis().lost_motion_arcmin == pytest.approx(0.847, rel=0.01)
    play = m.hysteresis(Effects(crank_bearing_play_m=10e-6))
    assert play.lost_motion_arcmin == pytest.approx(1.822, rel=0.01)
    assert te.te_forward_arcsec.mean() * ARCSEC == pytest.approx(
        te.te_forward_rad.mean())


# -- an eccentric's phase and the pin ring's orders (issue 24, item 4) ---------------------

def test_an_eccentric_errors_direction_shows_in_the_rows(rv_model):
    """5 um on one eccentric along it (radial) and across it (its phase), on equal
    springs: the same first harmonic at the crank's order against the carrier (40)
    within 2 %, but the hysteresis width differs by 8 times a rig's sigma on it (0.1
    arcsec, docs/te_rig.md) and the second harmonic by more than one (0.02 arcsec) -
    the phase is observable from amplitudes, so the catalog fits it (with the FE tables
    the second harmonic differs by 0.36 arcsec: 0.99 against 0.63)."""
    def run(direction):
        e = np.zeros((2, 2))
        p = np.zeros((2, 2))
        e[0, 0], p[0, 0] = 5e-6, direction
        return rv_model.te(Effects(crank_eccentricity_m=e, crank_phase_rad=p), (412.0,))[0]
    radial, across = run(0.0), run(math.pi / 2)
    assert across.amplitude_arcsec(40) == pytest.approx(radial.amplitude_arcsec(40), rel=0.02)
    assert abs(across.amplitude_arcsec(80) - radial.amplitude_arcsec(80)) > 0.02
    assert abs(across.width_arcsec - radial.width_arcsec) > 0.5


def test_eccentric_effect_is_its_radial_and_tangential_parts(rv_model):
    """The catalog's eccentric effect: (radial, tangential) [um] -> the model's size and
    direction from the eccentric's (3, 4) -> 5 um at atan2(4, 3); the other eccentrics
    stay as drawn."""
    from toothfem.efficiency.loop.te.effects import catalog, effects_of

    eff = {e.name: e for e in catalog(rv_model)}["eccentric_error_1_2"]
    assert [p.name for p in eff.parameters] == ["radial_error_um", "tangential_error_um"]
    got = effects_of(eff.model_options((3.0, 4.0)), 2, 2)
    want = np.zeros((2, 2))
    want[0, 1] = 5e-6
    np.testing.assert_allclose(got.crank_eccentricity_m, want, atol=1e-18)
    assert got.crank_phase_rad[0, 1] == pytest.approx(math.atan2(4.0, 3.0))


def test_pin_ring_orders_move_the_pins(rv_model):
    """``pin_ring_offsets``: pin j moved by cos(h theta_j) radially or along +theta; order
    1 radial with order 1 tangential of the opposite phase (sin) is the ring moved whole;
    an order below 1 and an unknown key are refused in one line."""
    drive = rv_model.drive
    c = drive.pin_ring_offsets(2, radial_m=1e-6)
    theta = 2 * math.pi * np.arange(40) / 40          # pin 0 on +x, pins counter-clockwise
    radial = np.stack([np.cos(theta), np.sin(theta)])
    np.testing.assert_allclose(c, 1e-6 * radial * np.cos(2 * theta), atol=1e-18)
    # a rigid move (d, 0): radial d cos(theta), tangential -d sin(theta) = d cos(theta + pi/2)
    along = np.stack([-np.sin(theta), np.cos(theta)])
    move = drive.pin_ring_offsets(1, radial_m=2e-6) - 2e-6 * along * np.sin(theta)
    np.testing.assert_allclose(move, np.tile([[2e-6], [0.0]], (1, 40)), atol=1e-18)
    with pytest.raises(CaseError, match="pin ring order = 0"):
        drive.pin_ring_offsets(0, radial_m=1e-6)
    with pytest.raises(CaseError, match="'radial2'"):
        Effects(pin_ring_m={"radial2": 1e-6})
    with pytest.raises(CaseError, match=r"pin_ring_m\['radial_2'\]"):
        Effects(pin_ring_m={"radial_2": float("nan")})


def test_te_samples_follow_the_effects(rv_model):
    """The TE's default sampling: the model's few pitches as drawn or with crank errors,
    a pin ring's orders 4 (2 Zb + h) + 1 (329 pitches for ovality on RV-40E), single
    pins the whole revolution (1560)."""
    off = np.zeros((2, 40))
    off[0, 3] = 1e-6
    assert rv_model.default_samples(Effects(), 39) == rv_model.te_samples
    assert rv_model.default_samples(Effects(pin_ring_m={"radial_2": 1e-6}), 1560) == 329
    assert rv_model.default_samples(Effects(pin_offset_m=off), 1560) == 1560


def test_pin_ring_sampling_and_orientation(small_khv):
    """On a 12-pin K-H-V drive on equal springs (its revolution 132 pitches): the ring's
    ovality (5 um) ripples at twice the lobe passing and its multiples (a K-H-V disc meets
    the oval twice per input turn); at its default sampling (105 pitches) it gives the
    whole period's amplitudes there within 1 %. The pattern turned round the ring (0.37
    rad, an oval's axis between pins) moves the first within 3 %: what the one-amplitude
    effect leaves out (on 12 pins; on RV-40E's 40 every fitted row within 1 %,
    docs/te_rig.md)."""
    m = RecordingModel(small_khv, positions=2, cache=False,
                       pin_spring_m_per_N=SPRING)
    oval = Effects(pin_ring_m={"radial_2": 5e-6}, friction_scale=0.0)   # elastic states
    fill, = m.te(oval, (None,))
    whole, = m.te(oval, (None,), samples=132)
    assert len(fill.sampled_pitches) == 105 and len(whole.sampled_pitches) == 132
    c = pin_centres(m.drive.geometry)
    theta = np.arctan2(c[1], c[0])
    turned = 5e-6 * c / np.linalg.norm(c, axis=0) * np.cos(2 * (theta - 0.37))
    turn, = m.te(Effects(pin_offset_m=turned, friction_scale=0.0), (None,))
    assert turn.period_pitches == 132
    assert whole.amplitude_arcsec(22) == pytest.approx(17.9, rel=0.01)
    for q in (22, 44):                   # 2 Za and 4 Za
        assert fill.amplitude_arcsec(q) == pytest.approx(whole.amplitude_arcsec(q),
                                                         rel=0.01), q
    assert turn.amplitude_arcsec(22) == pytest.approx(whole.amplitude_arcsec(22), rel=0.03)


def test_the_friction_settles_where_it_jumps(rv_model, monkeypatch):
    """The path friction's fixed point T_e = T - T_f(T_e): where T_f jumps across the root
    (a contact opening at the loop's knee) the secant steps fail and the bisection closes
    on the jump (the path sticks there); a smooth T_f gives its root. In the system: 10 um
    of crank-bearing play with a 3 um pitch error of the pin ring on springs, which
    refused ("did not settle") before the bisection."""
    from types import SimpleNamespace

    from toothfem.fem.system import datasheet as sd

    fake = SimpleNamespace(friction=SimpleNamespace(output_torque_Nm=1.0))

    def jump(te):
        tf = (2.0 if te < 10.0 else 4.0) + 0.05 * abs(te)
        return 13.0 - tf - te, tf
    assert sd.SystemTwist._bisected(fake, 13.0, jump, 2.5) == pytest.approx(10.0, abs=1e-2)

    def smooth(te):
        tf = 2.0 + 0.05 * abs(te)
        return 13.0 - tf - te, tf
    te = sd.SystemTwist._bisected(fake, 13.0, smooth, 2.5)
    assert abs(smooth(te)[0]) <= sd.FRICTION_RTOL * smooth(te)[1] * 1.01
    calls = []
    bisected = sd.SystemTwist._bisected
    monkeypatch.setattr(sd.SystemTwist, "_bisected",
                        lambda self, *a: calls.append(a[0]) or bisected(self, *a))
    loop = rv_model.hysteresis(Effects(crank_bearing_play_m=10e-6,
                                       pin_ring_m={"tangential_1": 3e-6}))
    assert calls
    assert all(math.isfinite(v) for v in loop.figures().values())
    assert np.all(np.isfinite(loop.twist_arcmin))
