"""Coulomb friction in the quasi-static path of the system model (docs/stiffness.md,
"Friction"): the friction torque the output meets as the twist grows at a solved state,
from each friction pair's force and its slip per unit output twist (the slips from the
state's tangent, :attr:`toothfem.fem.system.solve.Equilibrium.rate`)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import CaseError
from .parts import perp


@dataclass(frozen=True)
class PathFriction:
    """Coulomb friction in the quasi-static path (docs/stiffness.md, "Friction"): what
    resists the elastic micro-slips of a slow twist test. At creep speeds no film forms, so
    sliding contacts take their boundary coefficient.

    ``pin_disc``: the pin contacts' sliding; ``pin_groove``: conventional pins in their
    grooves (a pin that turns more easily in its groove than the disc slides on it rolls:
    the smaller coefficient acts); ``bearing``: the rolling bearings' friction moment
    mu F d / 2 (SKF's simplified model, d the bore); ``output_pin``: the output pins in
    their holes (with rollers: the roller's sleeve on its pin); ``output_torque_Nm``: a
    load-independent friction torque on the output (its seal)."""
    pin_disc: float
    pin_groove: float
    bearing: float
    output_pin: float
    output_torque_Nm: float = 0.0

    def __post_init__(self):
        for name in ("pin_disc", "pin_groove", "bearing", "output_pin", "output_torque_Nm"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise CaseError(f"friction {name} = {v!r}: >= 0 and finite")


def friction_torques(system, phi: float, pins, eq, fr: PathFriction) -> dict:
    """Friction torque [N m] on the output per source at a solved state: each friction
    pair's force (mu times its normal force, or its bearing's moment) times its slip per
    unit output twist. The members' contacts, the eccentric bearings (the shaft turns
    against the member), the shafts' supports (the shaft turns against its frame), the
    path's own contacts (:meth:`toothfem.fem.system.paths.OutputPath.friction`) and the
    output's seal, in that order.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    phi : float
        The crank angle [rad].
    pins : list of (ContactSet, MeshContacts)
        Each member's mesh as solved.
    eq : toothfem.fem.system.solve.Equilibrium
        The state, with its ``rate``.
    fr : PathFriction

    Returns
    -------
    dict of str to float
    """
    c, path = system.coords, system.path
    v = eq.rate / eq.rate[c.index["out"]][0]          # per unit output twist
    out = {}
    mu = system.mesh.sliding_coefficient(fr)
    total = 0.0
    for s, (cs, mc) in zip(system.slots, pins):
        dj = v[c.index[f"disc{s.index}"]]
        vel = dj[:2, None] + dj[2] * perp(mc.point)    # the member at each contact
        total += mu * float(eq.forces[cs.name] @ np.abs(np.sum(perp(mc.normal) * vel, 0)))
    out[f"{system.drive.contact_name} contacts"] = total
    journal = system.mesh.journal_radius_m(system.supports)
    bear = supp = 0.0
    for k in range(system.cranks):
        psi = v[c.index[f"psi_e{k}"]][0]
        for s in system.slots:        # the crank turns against the disc
            rel = psi - v[c.index[f"disc{s.index}"]][2] + path.frame_rate(v, c)
            force = eq.element_force[system.bearing_names[k][s.index]]
            bear += fr.bearing * np.hypot(*force) * journal * abs(rel)
        for end in "ab":            # the crank turns against its frame
            force = eq.element_force[system.support_names[k][end]]
            supp += fr.bearing * np.hypot(*force) * 0.5 \
                * system.supports.crankshaft_diameter_m * abs(psi)
    out[system.group("crank bearings")] = float(bear)
    out[system.group("support bearings")] = float(supp)
    out.update(path.friction(system, phi, v, eq, fr))
    out["output seal"] = fr.output_torque_Nm
    return out
