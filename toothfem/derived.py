"""Derived quantities of a case: what `toothfem check` prints (units in the key names)."""
from __future__ import annotations

import math

import numpy as np

from .case import Case
from .efficiency import evaluate, operating_point
from .errors import CaseError, ToothfemError
from .geometry import cycloid as cy, cycloid_mesh as cym, sine, train
from .fem.drives.registry import provide, record_of
from .units import ARCMIN, M_PER_UM, MM_PER_M, rpm_to_rad_s


#: The sign convention of every ratio `check` prints (toothfem.geometry.train), said once.
RATIO_CONVENTION = ("ratios are i = n_input / n_output, signed: i > 0 when the output turns "
                    "with the input, i < 0 against it (case files state |i|)")


def derived(case: Case) -> dict:
    """A flat mapping of the quantities an engineer checks first, per drive.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    dict
        Units in the key names: the signed ratio (:data:`RATIO_CONVENTION`), output speed,
        the operating point's torques, powers and efficiency (analytic loads), each drive's
        geometry and train figures, and ``warnings`` (an operating point above a declared
        rating; a quantity that could not be derived).
    """
    out: dict = {"name": case.name, "drive": case.drive,
                 "ratio_sign_convention": RATIO_CONVENTION, "ratio": _r(case.ratio())}
    op = case.operating
    out["output_speed_rpm"] = _r(op.input_speed_rpm / case.ratio())
    warnings: list[str] = []
    out.update(_operating(case, warnings))
    out.update(record_of(case).part("derived_rows")(case))
    if out.get("interference_before_load_um", 0) > 0:
        warnings.append(f"the disc interferes with its pins by {out['interference_before_load_um']:.4g}"
                        f" um before load (pins {out['interference_pins']}, '+': the flank "
                        "of a positive disc torque) wherever it is turned: both flanks are "
                        "preloaded on assembly")
    out["warnings"] = warnings
    return out


def _operating(case: Case, warnings: list) -> dict:
    """Torques [N m], powers [W] and efficiency at the operating point (analytic loads,
    the case's efficiency model), and the rating check."""
    op = case.operating
    try:
        e = evaluate(case, *operating_point(case))
    except ToothfemError as exc:
        warnings.append(f"operating point not derived: {exc}")
        return {}
    speed, torque = float(e.speed_rpm[0]), float(e.torque_Nm[0])
    p_in, p_out = float(e.input_power_W[0]), float(e.output_power_W[0])
    d = {"operating_input_speed_rpm": _r(speed),
         "operating_output_torque_Nm": _r(torque),
         "operating_input_torque_Nm": _r(p_in / rpm_to_rad_s(speed)),
         "operating_input_power_W": _r(p_in),
         "operating_output_power_W": _r(p_out),
         "operating_efficiency_analytic": _r(float(e.efficiency[0]), 6)}
    rated = op.rated_torque_Nm
    if rated is not None:
        d["rated_torque_Nm"] = rated
        if torque > rated:
            warnings.append(f"the operating point's output torque {torque:.4g} N m is "
                            f"{torque / rated:.2f} x the rated {rated:g} N m "
                            "(operating.rated_torque_Nm)")
    return d


def _r(x, digits=10):
    return float(f"{x:.{digits}g}")


def _cycloid(case: Case) -> dict:

    st = case.cycloid
    if st is None:
        raise CaseError(f"[cycloid] section is required for drive = {case.drive!r}")
    g = st.geometry()
    rho = cy.min_convex_curvature_radius(g.generating())
    d = {
        "stage_ratio_KHV": _r(train.khv_ratio(st.lobe_count, st.pin_count)),
        "K1": _r(g.k1),
        "disc_pitch_radius_mm": _r(g.disc_pitch_radius_m * MM_PER_M),
        "pin_pitch_radius_mm": _r(g.pin_pitch_radius_m * MM_PER_M),
        "disc_root_radius_mm": _r(g.root_radius_m * MM_PER_M),
        "disc_tip_radius_mm": _r(g.tip_radius_m * MM_PER_M),
        "min_convex_curvature_radius_mm": _r(rho * MM_PER_M),
        "undercut_margin_mm": _r((rho - g.generating_pin_radius) * MM_PER_M),
    }
    d.update(_before_load(g, _reducer_per_disc_turn(case)))
    if case.first_stage is not None:
        fs = case.first_stage
        d["first_stage_centre_distance_mm"] = _r(fs.module_mm * (fs.sun_teeth + fs.planet_teeth)
                                                 / 2)
    if case.operating.output_torque_Nm is not None:
        m_a = st.disc_load_factor * case.operating.output_torque_Nm / st.disc_count
        d["disc_torque_Nm"] = _r(m_a)
        # seed Eq. 13: P_max = 4 M_a / (r_a Zb) (rigid pins, all pins on one side loaded)
        d["seed_max_pin_force_N"] = _r(4 * m_a / (g.disc_pitch_radius_m * st.pin_count))
    m = cym.meshing(g, 0.0)
    d["pins_with_load_carrying_normal"] = int(np.sum(m.moment_arm[0] < 0))
    d["min_pressure_angle_loaded_deg"] = _r(math.degrees(
        float(np.min(m.pressure_angle[0][m.moment_arm[0] < 0]))))
    return d


def _reducer_per_disc_turn(case: Case) -> float:
    """The output's turn per turn of the disc about its centre that closes the same pin
    clearance, input held (docs/stiffness.md): the pins' normals pass through the pitch
    point, e Za from the disc's centre; a K-H-V disc turns with its output about its held
    eccentric (1), a 2K-V drive's disc also moves with its cranks, which turn
    (1 + z_s/z_p) times the output angle: Za / (Za + 1 + z_s/z_p)."""
    fs = case.first_stage
    if case.cycloid is None:
        raise CaseError(f"[cycloid] section is required for drive = {case.drive!r}")
    za = case.cycloid.lobe_count
    return 1.0 if fs is None else za / (za + 1 + fs.sun_teeth / fs.planet_teeth)


def _before_load(g, per_disc_turn: float = 1.0) -> dict:
    """The disc on its pins before load over one meshing period (exact gaps of both flanks,
    :func:`toothfem.geometry.cycloid_mesh.before_load`), with the first-order backlash of
    the closed form beside (docs/derivations.md C6: twice the closing rotation beta0). The
    backlash is the reducer's, input held (the disc's own closing rotation about its centre
    times ``per_disc_turn``, :func:`_reducer_per_disc_turn`), the disc's own beside."""
    phis = np.linspace(0.0, 2 * math.pi / g.pin_count, BEFORE_LOAD_POSITIONS, endpoint=False)
    b = cym.before_load(g, phis)
    lo, hi = b["backlash_min_arcmin"], b["backlash_max_arcmin"]
    d = {"backlash_arcmin": None if lo is None else _r(lo * per_disc_turn),
         "backlash_max_arcmin": None if hi is None else _r(hi * per_disc_turn),
         "disc_backlash_arcmin": None if lo is None else _r(lo),
         "backlash_first_order_arcmin": _r(2 * cym.closing_rotation(g) / ARCMIN
                                           * per_disc_turn),
         "clearance_before_load_um": _r(b["clearance_before_load_um"], 6),
         "interference_before_load_um": _r(b["interference_before_load_um"], 6)}
    if b["interference_pins"]:
        d["interference_position_deg"] = _r(b["interference_position_deg"])
        d["interference_pins"] = ", ".join(f"{j} ({f})" for j, f in
                                           zip(b["interference_pins"], b["interference_flanks"]))
    return d


#: Crank angles over one meshing period at which `check` places the disc on its pins.
BEFORE_LOAD_POSITIONS = 36


def _sine(case: Case) -> dict:

    st = case.sine
    if st is None:
        raise CaseError(f"[sine] section is required for drive = {case.drive!r}")
    pair = st.geometry()
    d = {
        "planet_pitch_radius_mm": _r(pair.planet_pitch_radius_m * MM_PER_M),
        "ring_pitch_radius_mm": _r(pair.ring_pitch_radius_m * MM_PER_M),
        "centre_distance_mm": _r(pair.centre_distance_m * MM_PER_M),
        "tooth_height_bound_mm": _r(sine.max_tooth_height_m(pair) * MM_PER_M),
    }
    pitch = 2 * math.pi / st.ring_teeth
    chi = np.linspace(0.0, pitch, 13)
    m = sine.meshing(pair, chi)
    conj = m.gap <= 1e-9                   # the conjugate contact of each position
    d["conjugate_pressure_angle_min_deg"] = _r(math.degrees(float(np.min(
        m.pressure_angle[conj]))))
    d["conjugate_equivalent_radius_min_mm"] = _r(float(np.min(m.equivalent_radius[conj])) * MM_PER_M)
    for gap_um in (1.0, 5.0, 10.0):
        n = sine.contact_count(pair, chi, gap_um * M_PER_UM)
        d[f"tooth_pairs_within_{gap_um:g}um_min"] = int(np.min(n))
        d[f"tooth_pairs_within_{gap_um:g}um_max"] = int(np.max(n))
    return d


def _rv(case: Case) -> dict:
    rv = case.rv
    if rv is None:
        raise CaseError(f"[rv] section is required for drive = {case.drive!r}")
    w = train.rv_speeds(rv.sun_teeth, rv.planet_teeth, rv.disc_teeth, rv.pin_count)
    d = {f"speed_{k}_per_input": _r(v) for k, v in w.items()}
    d["crank_to_output_ratio"] = _r(w["planet"] / w["carrier"])
    return d


@provide("derived_rows", "rv")
def _rv_rows(case: Case) -> dict:
    """An RV (2K-V) case: its train from [rv], its disc from [cycloid], each if declared."""
    return {**(_cycloid(case) if case.cycloid is not None else {}),
            **(_rv(case) if case.rv is not None else {})}


provide("derived_rows", "cycloid")(_cycloid)
provide("derived_rows", "sine")(_sine)
