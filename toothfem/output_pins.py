"""The output mechanism's pins in the members' holes (a K-H-V drive, the sine pair) as the
system model carries them: their forces and Hertz pressures over the positions, for the
contact summary (``toothfem contact``, ``toothfem run``), with the allowable pressure's
warning (:func:`toothfem.limits.contact_pressure`)."""
from __future__ import annotations

import numpy as np

from . import limits
from .fem.system.datasheet import SystemTwist
from .fem.system.output_pins import pin_pressures
from .units import MPA_PER_PA

#: What the output pins' figures are (summary.json's ``output_pins_definition``).
DEFINITION = ("the output flange's pins in the members' holes as the system model carries "
              "them (every member free on its supports, the split solved) over the run's "
              "positions of one meshing pitch (the pins' load pattern turns with the crank: "
              "a pitch samples part of it); P_h: Hertz's line contact (Johnson 1985, "
              "Eq. 4.45) of the pin, or its roller where it has one, in the hole over the "
              "member's face width; a roller's bore on its pin is a conformal journal (no "
              "Hertz pressure), its force the same")


def output_pin_summary(system, si, output_torque_Nm: float) -> tuple[dict, list]:
    """The output pins' largest force and Hertz pressure, pin by pin, and the warnings of
    that pressure against the material's limits.

    Parameters
    ----------
    system : toothfem.fem.contracts.ReducerModel
        The drive's system model over the positions.
    si : toothfem.si.CaseSI
        Its output mechanism and material.
    output_torque_Nm : float
        [N m].

    Returns
    -------
    summary : dict
        ``output_pin_force_max_N``, ``output_pin_ph_max_MPa``, where that pressure sits
        (``output_pin_ph_contact``), each pin's largest (``..._by_pin_...``), the fewest
        pins carrying on one member and the definition; empty for a drive without output
        pins (a 2K-V drive's cranks).
    warnings : list of toothfem.limits.Exceeded
    """
    om = si.output_mechanism
    states = SystemTwist(system).states(output_torque_Nm)
    if om is None or states[0].output_pin_force_N is None:
        return {}, []
    p = pin_pressures(states, om, si.material, system.drive.face_width_m,
                      system.mesh.eccentricity_m)
    force, ph = p["force_N"], p["ph_Pa"]                     # (positions, members, pins)
    at = np.unravel_index(int(np.argmax(ph)), ph.shape)
    roller = om.roller_radius_m is not None
    what = (f"{'roller' if roller else 'pin'} r {p['contact_radius_m'] * 1e3:.4g} mm in "
            f"hole r {p['hole_radius_m'] * 1e3:.4g} mm")
    summary = {
        "output_pin_force_max_N": float(force.max()),
        "output_pin_ph_max_MPa": float(ph.max()) * MPA_PER_PA,
        "output_pins_in_contact_min": int((force > 0).sum(axis=2).min()),
        "output_pin_ph_contact": {
            "member": int(at[1]) + 1, "pin": int(at[2]) + 1,
            "position_deg": float(np.degrees(states[at[0]].position_rad)),
            "force_N": float(force[at]), "ph_MPa": float(ph[at]) * MPA_PER_PA,
            "contact": what, "equivalent_radius_mm": p["equivalent_radius_m"] * 1e3,
            "half_width_um": float(p["half_width_m"][at]) * 1e6},
        "output_pin_force_max_by_pin_N": [float(v) for v in force.max(axis=(0, 1))],
        "output_pin_ph_max_by_pin_MPa": [float(v) * MPA_PER_PA for v in ph.max(axis=(0, 1))],
        "output_pins_definition": DEFINITION}
    found = limits.contact_pressure(f"the output pins on their holes ({what})",
                                    float(ph.max()) * MPA_PER_PA, si.material)
    return summary, found
