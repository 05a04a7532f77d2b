"""What the K-H-V and RV layouts share: a cycloid disc on its pins. The rows ``toothfem
check`` prints of the disc, the drawing of the disc among its pins and its CAD parts, and
the drive of the stage on the output path each layout builds."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import CaseError
from ..fem.drives import CycloidDrive
from ..geometry import cycloid as cy, cycloid_backlash as cyb, cycloid_mesh as cym, train
from ..report import plots
from ..units import ARCMIN, DEG, M_PER_MM, MM_PER_M
from .common import rounded

if TYPE_CHECKING:
    from ..case import Case


#: The disc's profile modifications ``toothfem design`` varies: case key -> (the SI
#: geometry field it sets, the factor from the key's unit to SI).
CYCLOID_DESIGN = {"equidistant_modification_mm": ("equidistant_m", M_PER_MM),
                  "move_distance_modification_mm": ("move_distance_m", M_PER_MM),
                  "rotation_modification_deg": ("rotation_rad", DEG)}
#: A cycloid stage's ``[tolerances]`` keys.
CYCLOID_TOLERANCES = ("pin_position_mm", "pin_diameter_lower_mm", "pin_diameter_upper_mm",
                      "pin_circle_radius_mm", "disc_profile_mm", "crank_hole_position_mm")


def cycloid_drive(si, layout, path):
    """The cycloid disc stage of a case on the layout's output path
    (:meth:`toothfem.fem.drives.CycloidDrive.from_case`).

    Parameters
    ----------
    si : toothfem.si.CaseSI
    layout : toothfem.layout.Layout
        The layout the drive belongs to.
    path : toothfem.fem.system.paths.OutputPath
        Its output path (:mod:`toothfem.fem.system.paths`).

    Returns
    -------
    toothfem.fem.drives.CycloidDrive
    """
    return CycloidDrive.from_case(si, layout, path)


def pair_drawing(drive, case_name: str):
    """The disc among its pins with its dimensions, at crank angle 0.

    Parameters
    ----------
    drive : toothfem.fem.drives.Drive
    case_name : str
        Named in the title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    return plots.cycloid_drawing(drive.geometry, drive.stage.holes, case_name=case_name)


def cycloid_rows(case: Case) -> dict:
    """The cycloid disc's rows ``toothfem check`` prints: K1, its radii, the undercut
    margin, the disc on its pins before load (backlash, clearance or interference), the
    first stage's centre distance, the seed's disc torque and largest pin force.

    Parameters
    ----------
    case : toothfem.case.Case

    Returns
    -------
    dict
        Units in the key names.
    """
    st = case.cycloid
    if st is None:
        raise CaseError(f"[cycloid] section is required for drive = {case.drive!r}")
    g = st.geometry()
    rho = cy.min_convex_curvature_radius(g.generating())
    d = {
        "stage_ratio_KHV": rounded(train.khv_ratio(st.lobe_count, st.pin_count)),
        "K1": rounded(g.k1),
        "disc_pitch_radius_mm": rounded(g.disc_pitch_radius_m * MM_PER_M),
        "pin_pitch_radius_mm": rounded(g.pin_pitch_radius_m * MM_PER_M),
        "disc_root_radius_mm": rounded(g.root_radius_m * MM_PER_M),
        "disc_tip_radius_mm": rounded(g.tip_radius_m * MM_PER_M),
        "min_convex_curvature_radius_mm": rounded(rho * MM_PER_M),
        "undercut_margin_mm": rounded((rho - g.generating_pin_radius) * MM_PER_M),
    }
    d.update(_before_load(g, reducer_per_disc_turn(case)))
    if case.first_stage is not None:
        fs = case.first_stage
        d["first_stage_centre_distance_mm"] = rounded(fs.module_mm * (fs.sun_teeth + fs.planet_teeth)
                                                      / 2)
    if case.operating.output_torque_Nm is not None:
        # the drive's one torque rule (Drive.member_torque), as contact and run take it:
        # a 2K-V drive's discs carry T (1 - 1/i) Za/Zb, a K-H-V drive's T
        m_a = case.layout.make_drive(case.to_si()).member_torque(
            case.operating.output_torque_Nm)
        d["disc_torque_Nm"] = rounded(m_a)
        # seed Eq. 13: P_max = 4 M_a / (r_a Zb) (rigid pins, all pins on one side loaded)
        d["seed_max_pin_force_N"] = rounded(4 * m_a / (g.disc_pitch_radius_m * st.pin_count))
    m = cym.meshing(g, 0.0)
    d["pins_with_load_carrying_normal"] = int(np.sum(m.moment_arm[0] < 0))
    d["min_pressure_angle_loaded_deg"] = rounded(math.degrees(
        float(np.min(m.pressure_angle[0][m.moment_arm[0] < 0]))))
    return d


def reducer_per_disc_turn(case: Case) -> float:
    """The output's turn per turn of the disc about its centre that closes the same pin
    clearance, input held (docs/stiffness.md): the pins' normals pass through the pitch
    point, e Za from the disc's centre; a K-H-V disc turns with its output about its held
    eccentric (1), a 2K-V drive's disc also moves with its cranks, which turn
    (1 + z_s/z_p) times the output angle: Za / (Za + 1 + z_s/z_p).

    Parameters
    ----------
    case : Case
        A cycloid or 2K-V case.

    Returns
    -------
    float
        The output's turn per turn of the disc [-].
    """
    fs = case.first_stage
    if case.cycloid is None:
        raise CaseError(f"[cycloid] section is required for drive = {case.drive!r}")
    za = case.cycloid.lobe_count
    return 1.0 if fs is None else za / (za + 1 + fs.sun_teeth / fs.planet_teeth)


def reducer_backlash(case: Case, described: dict) -> dict:
    """The FE model's description with its disc's backlash before load (its own free turn,
    the cranks held) turned into the reducer's, input held, as `check` gives it
    (:func:`toothfem.layouts.cycloid.reducer_per_disc_turn`); the disc's own kept beside as
    ``disc_backlash_min_arcmin`` / ``disc_backlash_max_arcmin``.

    Parameters
    ----------
    case : Case
    described : dict
        The FE model's ``describe()``.

    Returns
    -------
    dict
    """
    if described.get("backlash_min_arcmin") is None or case.cycloid is None:
        return described
    turn = reducer_per_disc_turn(case)
    out = dict(described)
    for key in ("backlash_min_arcmin", "backlash_max_arcmin"):
        if described.get(key) is not None:
            out[f"disc_{key}"] = described[key]
            out[key] = described[key] * turn
    return out


def _before_load(g, per_disc_turn: float = 1.0) -> dict:
    """The disc on its pins before load over one meshing period (exact gaps of both flanks,
    :func:`toothfem.geometry.cycloid_backlash.before_load`), with the first-order backlash of
    the closed form beside (docs/derivations.md C6: twice the closing rotation beta0). The
    backlash is the reducer's, input held (the disc's own closing rotation about its centre
    times ``per_disc_turn``, :func:`reducer_per_disc_turn`), the disc's own beside: the least
    over the period (``backlash_min_arcmin``: the datasheet's ``backlash_arcmin`` is the
    system model's mean over its positions, toothfem stiffness) and the most."""
    phis = np.linspace(0.0, 2 * math.pi / g.pin_count, BEFORE_LOAD_POSITIONS, endpoint=False)
    b = cyb.before_load(g, phis)
    lo, hi = b["backlash_min_arcmin"], b["backlash_max_arcmin"]
    d: dict = {"backlash_min_arcmin": None if lo is None else rounded(lo * per_disc_turn),
               "backlash_max_arcmin": None if hi is None else rounded(hi * per_disc_turn),
               "disc_backlash_min_arcmin": None if lo is None else rounded(lo),
               "backlash_first_order_arcmin": rounded(2 * cyb.closing_rotation(g) / ARCMIN
                                                      * per_disc_turn),
               "clearance_before_load_um": rounded(b["clearance_before_load_um"], 6),
               "interference_before_load_um": rounded(b["interference_before_load_um"], 6)}
    if b["interference_pins"]:
        d["interference_position_deg"] = rounded(b["interference_position_deg"])
        d["interference_pins"] = ", ".join(f"{j} ({f})" for j, f in
                                           zip(b["interference_pins"], b["interference_flanks"]))
    return d


#: Crank angles over one meshing period at which `check` places the disc on its pins.
BEFORE_LOAD_POSITIONS = 36
