"""What ``toothfem check`` says of a case's parts against each other, against its
catalogue envelope and its tolerances, without solving anything (docs/sizing.md,
"Consistency"): each a warning line naming the keys, the values and the rule."""
from __future__ import annotations

import math

import numpy as np

from .case import Case
from .sizing_rules import INTERFERING_MAX

#: Built reducers of the interference estimate, and its seed (the same answer each time).
ESTIMATE_RINGS, ESTIMATE_SEED = 4000, 0
#: Share of built reducers that may interfere before ``check`` warns: the sizing's rule.
INTERFERING_WARN = INTERFERING_MAX
#: The sigma a zone's limit stands for (a capable process: 3 sigma at the limit).
SIGMAS_AT_LIMIT = 3.0


def consistency(case: Case, rows: dict) -> list:
    """Every consistency warning of a case.

    Parameters
    ----------
    case : Case
    rows : dict
        Its derived quantities (:func:`toothfem.derived.derived`'s, before the warnings).

    Returns
    -------
    list of str
    """
    out = []
    out += _crank_circle(case)
    out += _ratings(case)
    out += _envelope(case)
    est = interference_estimate(case, rows)
    if est is not None and est["share"] > INTERFERING_WARN:
        out.append(
            f"as built within [tolerances], about {100 * est['share']:.0f} % of reducers "
            f"interfere (both flanks preloaded on assembly): the nominal clearance "
            f"{est['clearance_um']:.3g} um per flank against a closure of "
            f"{est['closure_p50_um']:.3g} um at the tightest of {est['pins']} pins (median; "
            f"an estimate by a normal model of the zones, above {100 * INTERFERING_WARN:g} %; "
            "toothfem run and toothfem tolerance solve the built reducers; an "
            "equidistant modification opens clearance: toothfem size chooses one)")
    return out


def _crank_circle(case: Case) -> list:
    fs, cyc = case.first_stage, case.cycloid
    if fs is None or cyc is None or not cyc.disc_holes.crank_hole_count:   # a 2K-V's cranks
        return []
    a = fs.module_mm * (fs.sun_teeth + fs.planet_teeth) / 2
    r_c = cyc.disc_holes.crank_hole_circle_radius_mm
    if math.isclose(a, r_c, rel_tol=1e-6):
        return []
    return [f"cycloid.disc_holes.crank_hole_circle_radius_mm = {r_c:g} differs from the first "
            f"stage's centre distance {a:.4g} mm (first_stage.module_mm = {fs.module_mm:g} x "
            f"(sun_teeth + planet_teeth) / 2): each planet sits on its crank, so they must "
            "agree"]


def _ratings(case: Case) -> list:
    """The rated torque the same in [operating] and the maker's [published] (the order of
    the maker's torques, rated <= start-stop <= momentary, the loader refuses)."""
    rated, pub = case.operating.rated_torque_Nm, case.published
    if rated is not None and "rated_torque_Nm" in pub and \
            not math.isclose(rated, float(pub["rated_torque_Nm"]), rel_tol=1e-9):
        return [f"operating.rated_torque_Nm = {rated:g} differs from the maker's "
                f"published.rated_torque_Nm = {pub['rated_torque_Nm']:g}"]
    return []


def _envelope(case: Case) -> list:
    env, cyc = case.envelope, case.cycloid
    if env is None or cyc is None:
        return []
    out = []
    d = 2 * float(cyc.housing_outer_radius_mm or 0.0)
    if d > env.outer_diameter_mm:
        out.append(f"the pin housing's outer diameter {d:.4g} mm (cycloid.housing_outer_radius_"
                   f"mm) exceeds envelope.outer_diameter_mm = {env.outer_diameter_mm:g}")
    bore = 2 * cyc.disc_holes.centre_bore_radius_mm
    if env.centre_bore_diameter_mm > bore:
        out.append(f"envelope.centre_bore_diameter_mm = {env.centre_bore_diameter_mm:g} does "
                   f"not pass the discs' centre bore of {bore:g} mm "
                   "(cycloid.disc_holes.centre_bore_radius_mm)")
    stack = cyc.disc_count * cyc.face_width_mm
    if stack > env.length_mm:
        out.append(f"the discs side by side ({stack:g} mm: cycloid.disc_count x face_width_mm)"
                   f" exceed envelope.length_mm = {env.length_mm:g}")
    return out


def interference_estimate(case: Case, rows: dict) -> dict | None:
    """The share of reducers built within ``[tolerances]`` whose discs interfere with their
    pins, by a normal model of the zones (no solve: what ``check`` can say).

    Each flank's nominal clearance c is half the first-order backlash on the disc's pitch
    radius; a built ring closes each pin's gap by its own deviations (the pin's position
    along the normal, zone d at 3 sigma: sigma d/6; its radius between the ISO 286
    deviations' halves; the flank's profile, a/3) and by those common to the ring (the pin
    circle's radius and the eccentricity, by their radial part at the tightest pin;
    the crank hole's position closes one flank as it opens the other). The disc turns to
    share its play between the flanks, so it interferes where (c - the tightest pin's
    closure) summed over both flanks is negative. The
    tightest pin is the largest of ``pins_with_load_carrying_normal`` per flank.

    Parameters
    ----------
    case : Case
    rows : dict
        Its derived quantities (``backlash_first_order_arcmin``, ``disc_pitch_radius_mm``,
        ``pins_with_load_carrying_normal``).

    Returns
    -------
    dict or None
        ``share``, ``clearance_um``, ``closure_p50_um``, ``pins`` and
        ``clearance_needed_um`` (per flank, for at most :data:`INTERFERING_WARN`); None
        without cycloid tolerances or the rows it reads.
    """
    tol = case.tolerances
    need = ("backlash_first_order_arcmin", "disc_pitch_radius_mm",
            "pins_with_load_carrying_normal")
    if case.cycloid is None or any(rows.get(k) is None for k in need):
        return None
    own = [tol.pin_position_mm, tol.pin_diameter_lower_mm, tol.pin_diameter_upper_mm,
           tol.disc_profile_mm]
    common = [tol.pin_circle_radius_mm, tol.eccentricity_mm, tol.crank_hole_position_mm]
    if not any(own + common):
        return None
    um = 1000.0
    clearance = (rows["backlash_first_order_arcmin"] / 2 * math.pi / 180 / 60
                 * rows["disc_pitch_radius_mm"] * um)
    n = max(int(rows["pins_with_load_carrying_normal"]), 1)
    rng = np.random.default_rng(ESTIMATE_SEED)
    k = SIGMAS_AT_LIMIT
    lo, hi = tol.pin_diameter_lower_mm / 2 * um, tol.pin_diameter_upper_mm / 2 * um
    shape = (ESTIMATE_RINGS, 2, n)
    closure = (rng.normal(0.0, tol.pin_position_mm / 2 / k * um, shape)
               + rng.normal((lo + hi) / 2, (hi - lo) / 2 / k, shape)
               + rng.normal(0.0, tol.disc_profile_mm / k * um, shape))
    # the ring's own: the pin circle's radius and the eccentricity move every pin along
    # its normal by their radial part, sqrt(1 - K1^2) at the tightest pin (cos theta = K1,
    # docs/derivations.md C4); the crank hole's position shifts the disc, closing one
    # flank as it opens the other (nothing to first order in the sum over both)
    radial = math.sqrt(max(1.0 - float(rows.get("K1", 0.0)) ** 2, 0.0))
    ring = radial * (rng.normal(0.0, tol.pin_circle_radius_mm / k * um, ESTIMATE_RINGS)
                     + rng.normal(0.0, tol.eccentricity_mm / k * um, ESTIMATE_RINGS))
    tight = closure.max(axis=2) + ring[:, None]
    play = (clearance - tight).sum(axis=1)
    return {"share": float(np.mean(play < 0)), "clearance_um": float(clearance),
            "closure_p50_um": float(np.median(tight)), "pins": n,
            # the clearance per flank at which INTERFERING_WARN of the rings interfere
            "clearance_needed_um": float(np.percentile(tight.sum(axis=1) / 2,
                                                       100 * (1 - INTERFERING_WARN)))}
