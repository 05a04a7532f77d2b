"""The output flange's pins (or rollers) in holes through the members, as the system model
takes them (docs/stiffness.md, "The system model"; the K-H-V path,
:class:`toothfem.fem.system.paths.PinsInHoles`).

Output pin k (centre P_k, radius r) in member j's hole (centre P_k + E_j, radius
r + e + clearance) touches along n = -E_j / e; its gap changes by
-n . (out x P_k - d_j - theta_j x P_k). Flexibility: Palmgren's line contact at the hole
(and at the roller's bore) per contact, the pins' bending between the output flange and
their support ring coupling the members on one pin.
"""
from __future__ import annotations

import math

import numpy as np

from ..datasheet import supports as sp
from .parts import perp, softened
from .solve import ContactSet

#: The output pins' secant flexibility is taken at no less than this fraction of a typical
#: pin load (Palmgren's approach ~ Q^0.9 has an infinite secant compliance at zero load).
OUTPUT_LOAD_FLOOR = 1e-3


def pin_bending(system, om) -> np.ndarray:
    """The pins' bending between their flange and support ring, simply supported on the
    shafts' span: pin deflection at member i's plane per unit force at member j's.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
        Its members placed (``slots``) and its supports.
    om : toothfem.si.OutputMechanismSI

    Returns
    -------
    numpy.ndarray, shape (members, members)
        [m/N].
    """
    axial = np.array([s.axial_m for s in system.slots])
    m = system.drive.material_si
    return sp.simply_supported_influence(
        axial[:, None], axial[None, :], system.supports.crankshaft_span_m,
        2 * om.pin_radius_m, m.youngs_modulus_Pa, m.poisson_ratio)


def pin_contacts(system, om, phi: float, torque: float) -> ContactSet:
    """The output pins in every member's holes at crank angle phi: one contact per pin and
    member, gap the holes' clearance, the pins' bending from ``system.output_pin_bending``.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    om : toothfem.si.OutputMechanismSI
    phi : float
        [rad].
    torque : float
        The output torque [N m]: a typical pin load, the floor of Palmgren's secant.

    Returns
    -------
    toothfem.fem.system.solve.ContactSet
        "output pins", member by member, pin by pin.
    """
    c = system.coords
    n_o, r_w = om.pin_count, om.pin_hole_circle_radius_m
    e = system.mesh.eccentricity_m
    centres = _centres(system, om, phi)
    rows, g0, normals = [], [], []
    hole = om.hole_radius_m if om.hole_radius_m is not None else om.contact_radius_m + e
    clearance = hole - om.contact_radius_m - e
    clearance = 0.0 if abs(clearance) < 1e-12 else clearance      # mm -> m round-off
    for s in system.slots:
        n = _normal(system, phi, s)
        dj = c.index[f"disc{s.index}"]
        for k in range(n_o):
            r = np.zeros(c.n)
            r[c.index["out"]] = -n @ perp(centres[:, k])
            r[dj.start:dj.start + 2] = n
            r[dj.start + 2] = n @ perp(centres[:, k])
            rows.append(r)
            normals.append(n)
            g0.append(clearance)
    nrm = np.array(normals)                                              # (M n_o, 2)
    disc = np.repeat(np.arange(system.discs), n_o)
    pin = np.tile(np.arange(n_o), system.discs)
    same_pin = pin[:, None] == pin[None, :]
    bending = np.where(same_pin, system.output_pin_bending[np.ix_(disc, disc)], 0.0) \
        * (nrm @ nrm.T)
    width = system.drive.face_width_m
    contacts = 1 if om.roller_radius_m is None else 2
    mean = abs(torque) / (0.5 * n_o * r_w * system.discs)               # a typical load

    def local(lam):             # Palmgren's secant, per contact
        q = np.maximum(np.abs(np.asarray(lam, float)), OUTPUT_LOAD_FLOOR * mean)
        return contacts * sp.roller_approach(q, width) / q
    bending, local = softened(bending, local, system.stiffness_scale.get("output pins", 1.0))
    return ContactSet("output pins", "output pins", np.array(g0), np.array(rows),
                      bending, local)


def pin_friction(system, om, phi: float, v, eq, friction) -> float:
    """The friction torque [N m] of the pins (rollers) sliding against their holes,
    tangentially (with rollers: the roller's sleeve on its pin, the slip times
    r_pin / r_roller).

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    om : toothfem.si.OutputMechanismSI
    phi : float
        [rad].
    v : numpy.ndarray
        The coordinates' rate per unit output twist.
    eq : toothfem.fem.system.solve.Equilibrium
    friction : toothfem.fem.system.friction.PathFriction

    Returns
    -------
    float
    """
    c = system.coords
    centres = _centres(system, om, phi)
    slip = []
    for s in system.slots:
        t = perp(_normal(system, phi, s))
        dj = v[c.index[f"disc{s.index}"]]
        rel = v[c.index["out"]][0] * perp(centres) - dj[:2, None] - dj[2] * perp(centres)
        slip.append(np.abs(t @ rel))
    lever = 1.0 if om.roller_radius_m is None else om.pin_radius_m / om.roller_radius_m
    return friction.output_pin * lever * float(eq.forces["output pins"] @ np.concatenate(slip))


def _centres(system, om, phi: float) -> np.ndarray:
    """(2, n_o) the output pins' centres [m] at crank angle phi."""
    angle = 2 * math.pi * np.arange(om.pin_count) / om.pin_count + system.mesh.turn_ratio * phi
    return om.pin_hole_circle_radius_m * np.stack([np.cos(angle), np.sin(angle)])


def _normal(system, phi: float, s) -> np.ndarray:
    """(2,) the output pins' contact normal in member ``s``'s holes, -E_j/e."""
    return -system.eccentric(phi, s) / system.mesh.eccentricity_m


def pin_pressures(states, om, material, width_m: float, eccentricity_m: float) -> dict:
    """The output pins' forces on the members' holes as the system model carries them, and
    Hertz's pressure where each pin (its roller, where it has one) touches its hole
    (Johnson 1985, Eq. 4.45: a convex cylinder in a concave one, 1/R = 1/r - 1/R_hole,
    over the member's face width). A roller's bore on its pin is a sleeve on a pin of its
    radius, a conformal journal: Hertz's b << R does not hold there and no pressure is
    given for it; the force is the same.

    Parameters
    ----------
    states : sequence of toothfem.fem.system.parts.SystemState
        One per position, each with ``output_pin_force_N`` (members, pins).
    om : toothfem.si.OutputMechanismSI
    material : toothfem.si.MaterialSI
        The pins' and the members' (one material).
    width_m : float
        The member's face width [m], the line contact's length.
    eccentricity_m : float
        [m]: the holes' radius where ``om`` gives none (the contact radius plus it, as
        :func:`pin_contacts` takes them).

    Returns
    -------
    dict
        ``force_N`` (positions, members, pins) [N], ``ph_Pa`` the same shape [Pa] (0 where
        a pin carries nothing), ``equivalent_radius_m``, ``hole_radius_m``,
        ``contact_radius_m`` and ``half_width_m`` (positions, members, pins) [m].
    """
    from ..hertz import hertz_line, reduced_modulus

    force = np.array([s.output_pin_force_N for s in states], float)
    r = om.contact_radius_m
    hole = om.hole_radius_m if om.hole_radius_m is not None else r + eccentricity_m
    r_eq = 1.0 / (1.0 / r - 1.0 / hole)
    e_star = reduced_modulus(material.youngs_modulus_Pa, material.poisson_ratio,
                             material.youngs_modulus_Pa, material.poisson_ratio)
    carried = force > 0
    ph = np.zeros_like(force)
    b = np.zeros_like(force)
    if carried.any():
        p0, half = hertz_line(force[carried] / width_m, r_eq, e_star)
        ph[carried], b[carried] = p0, half
    return {"force_N": force, "ph_Pa": ph, "equivalent_radius_m": r_eq,
            "hole_radius_m": hole, "contact_radius_m": r, "half_width_m": b}
