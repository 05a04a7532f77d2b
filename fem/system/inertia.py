"""Masses and inertias of the system model's bodies from their geometry and the material's
density, and the mass matrix on the system model's coordinates (docs/dynamics.md).

Formulas (rho the density, t a plane body's thickness, each body about its own axis):

- a plane body (a member: the cycloid disc or the sine planet, its outline and holes as
  ``toothfem.cad.Region`` draws them), by Green's theorem over each closed polygon
  (x_i, y_i), c_i = x_i y_i+1 - x_i+1 y_i: area A = 1/2 sum c_i, polar second moment about
  the origin J_A = 1/12 sum c_i (x_i^2 + x_i x_i+1 + x_i+1^2 + y_i^2 + y_i y_i+1 +
  y_i+1^2); a circular hole of radius r at distance d: A = pi r^2, J_A = A (r^2/2 + d^2);
  m = rho t (A_outer - sum A_holes), J = rho t (J_outer - sum J_holes);
- a solid or hollow cylinder (shafts, journals, gears, pins, plates) of radii r_o, r_i
  and length L: m = rho pi (r_o^2 - r_i^2) L, J = m (r_o^2 + r_i^2) / 2; off its axis by
  d (an eccentric journal, the output pins about the reducer's axis): J + m d^2
  (Steiner);
- a gear as a solid disc of its pitch radius (its teeth's area above and below the pitch
  circle about alike).

The kinetic energy of small motions about the loaded configuration at rest,
T = 1/2 u'^T M u', is summed over the bodies' rigid motions in the model's coordinates
(fem/drives/assembly.py): a member's translation and rotation are coordinates of their
own; a shaft's journal at member j moves as its bearing's deformation says,
(1 - z_j) s1 + z_j s2 + w_j plus its frame's turn (the path's ``frame_terms``), its
rotation is the frame's turn plus psi_e; a path's own shaft coordinate (2K-V: the crank's
rotation at its gear, psi_g) carries the first stage's planet; the output flange (and the
load) turns with ``out``, a 2K-V carrier half with ``out`` and half with ``carrier``
where the pillars make them two. Neglected, and why: the centripetal and gyroscopic terms
of the turning cranks (m Omega^2 of a disc at 60 rad/s of crank is ~1e3 N/m against
1e8-1e9 N/m of its bearings), the rollers of the bearings (a few per cent of a member's
mass), the eccentric's own offset in the translation of a journal (e ~ 1 mm).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: ASSUMPTION: a 2K-V carrier is two plates (the output flange and the end plate) and a
#: K-H-V output flange one plate, each as wide as the member and one member's width thick
#: (the case draws neither: their inertia is of the member's order, 1e-3 of a robot
#: joint's load).
CARRIER_PLATES = 2
#: ASSUMPTION: the 2K-V input shaft fills the members' centre bore over the crankshafts'
#: span plus one span to the motor.
INPUT_SHAFT_SPANS = 2


@dataclass(frozen=True)
class Body:
    """One body's mass [kg] and its polar inertia about its own axis [kg m^2], with the
    formula it came from (docs/dynamics.md)."""
    name: str
    mass_kg: float
    inertia_kgm2: float
    formula: str


def polygon_moments(points) -> tuple[float, float]:
    """Area and polar second moment about the origin of a closed polygon (Green's theorem,
    the module docstring).

    Parameters
    ----------
    points : array_like, shape (2, N)
        The outline [m] (closed or not; either orientation).

    Returns
    -------
    (float, float)
        A [m^2], J_A [m^4].
    """
    x, y = np.asarray(points, float)
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    c = x * y1 - x1 * y
    area = 0.5 * float(np.sum(c))
    j = float(np.sum(c * (x * x + x * x1 + x1 * x1 + y * y + y * y1 + y1 * y1))) / 12.0
    return abs(area), abs(j)


def _shape_moments(shape) -> tuple[float, float]:
    """(A, J_A) of a polygon (2, N) or a circle (x, y, r) about the origin."""
    if len(shape) == 3 and np.ndim(shape[0]) == 0:
        x, y, r = (float(v) for v in shape)
        area = math.pi * r * r
        return area, area * (0.5 * r * r + x * x + y * y)
    return polygon_moments(shape)


def plane_body(name: str, outer, holes, thickness_m: float, density_kg_m3: float) -> Body:
    """A plane body of uniform thickness: its outline less its holes.

    Parameters
    ----------
    name : str
    outer : array_like
        The outline, (2, N) [m], or a circle (x, y, r) [m], about the body's axis.
    holes : sequence
        Each a (2, N) polygon or a circle (x, y, r) [m].
    thickness_m, density_kg_m3 : float
        t [m], rho [kg/m^3].

    Returns
    -------
    Body
        About the origin (the body's axis).
    """
    area, j = _shape_moments(outer)
    for h in holes:
        a, jh = _shape_moments(h)
        area, j = area - a, j - jh
    rt = density_kg_m3 * thickness_m
    return Body(name, rt * area, rt * j,
                "m = rho t (A - sum A_holes), J = rho t (J_A - sum J_holes) (Green)")


def cylinder(name: str, radius_m: float, length_m: float, density_kg_m3: float, *,
             inner_m: float = 0.0, offset_m: float = 0.0, count: int = 1) -> Body:
    """``count`` solid or hollow cylinders, each ``offset_m`` off the axis.

    Parameters
    ----------
    name : str
    radius_m, length_m : float
        r_o, L [m].
    density_kg_m3 : float
    inner_m : float
        r_i [m] (0: solid).
    offset_m : float
        d [m]: the axis the inertia is about (Steiner).
    count : int

    Returns
    -------
    Body
    """
    m = density_kg_m3 * math.pi * (radius_m ** 2 - inner_m ** 2) * length_m
    j = m * (0.5 * (radius_m ** 2 + inner_m ** 2) + offset_m ** 2)
    return Body(name, count * m, count * j,
                "m = rho pi (r_o^2 - r_i^2) L, J = m ((r_o^2 + r_i^2)/2 + d^2)")


def outer_radius_m(shape) -> float:
    """The largest radius of a polygon (2, N) or circle (x, y, r) about the origin [m].

    Parameters
    ----------
    shape : array_like

    Returns
    -------
    float
    """
    if len(shape) == 3 and np.ndim(shape[0]) == 0:
        return math.hypot(shape[0], shape[1]) + shape[2]
    return float(np.max(np.hypot(*np.asarray(shape, float))))


@dataclass(frozen=True)
class ReducerBodies:
    """The bodies of one reducer (each entry per one body; ``journal`` one member's
    eccentric on one shaft, ``gear`` the first stage's planet on each shaft, ``input`` the
    sun and input shaft turned by the motor: None where the layout has none)."""
    member: Body
    shaft: Body
    journal: Body
    gear: Body | None
    output: Body
    carrier: Body | None
    input: Body | None

    def rows(self) -> list:
        """The table of bodies.

        Returns
        -------
        list of dict
            name, mass_kg, inertia_kgm2, formula.
        """
        return [{"name": b.name, "mass_kg": b.mass_kg, "inertia_kgm2": b.inertia_kgm2,
                 "formula": b.formula}
                for b in (self.member, self.shaft, self.journal, self.gear, self.output,
                          self.carrier, self.input) if b is not None]


def reducer_bodies(system, member_region, density_kg_m3: float, *, output_pins=None,
                   first_stage=None) -> ReducerBodies:
    """The bodies of a system model from its member's drawing and the supports.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    member_region : toothfem.cad.Region
        The member (disc or planet) in its own frame: ``outer``, ``holes``,
        ``thickness_m``.
    density_kg_m3 : float
    output_pins : toothfem.si.OutputMechanismSI, optional
        A K-H-V output flange's pins (on the output, over the members' stack).
    first_stage : toothfem.si.SpurStageSI, optional
        A 2K-V first stage: its planet on each crank, its sun on the input.

    Returns
    -------
    ReducerBodies
    """
    rho, sup = density_kg_m3, system.supports
    t = float(member_region.thickness_m)
    member = plane_body(system.drive.member_name, member_region.outer, member_region.holes,
                        t, rho)
    span, d = sup.crankshaft_span_m, sup.crankshaft_diameter_m
    shaft = cylinder(system.path.SHAFT.format(k="").strip() + " body", 0.5 * d, span, rho)
    r_j = system.mesh.journal_radius_m(sup)
    journal = cylinder("eccentric journal", r_j, t, rho, offset_m=system.mesh.eccentricity_m)
    r_out = outer_radius_m(member_region.outer)
    stack = system.discs * t
    gear = inp = carrier = None
    if first_stage is not None:
        fs = first_stage
        gear = cylinder("first-stage planet", 0.5 * fs.module_m * fs.planet_teeth,
                        fs.face_width_m, rho)
        bore = min((float(h[2]) for h in member_region.holes
                    if len(h) == 3 and math.hypot(h[0], h[1]) < 1e-9), default=0.5 * d)
        sun = cylinder("sun", 0.5 * fs.module_m * fs.sun_teeth, fs.face_width_m, rho)
        shaft_in = cylinder("input shaft", bore, INPUT_SHAFT_SPANS * span, rho)
        inp = Body("sun and input shaft", sun.mass_kg + shaft_in.mass_kg,
                   sun.inertia_kgm2 + shaft_in.inertia_kgm2,
                   f"{sun.formula}: sun (pitch radius) + input shaft (centre bore x "
                   f"{INPUT_SHAFT_SPANS} spans)")
        carrier = cylinder("carrier (flange and end plate)", r_out, CARRIER_PLATES * t, rho)
        output = Body("output flange", 0.0, 0.0, "with the carrier")
    else:
        output = cylinder("output flange", r_out, t, rho)
        if output_pins is not None:
            om = output_pins
            pins = cylinder("output pins", om.contact_radius_m, stack, rho,
                            offset_m=om.pin_hole_circle_radius_m, count=om.pin_count)
            output = Body("output flange and pins", output.mass_kg + pins.mass_kg,
                          output.inertia_kgm2 + pins.inertia_kgm2,
                          f"{output.formula}; pins with Steiner's d")
    return ReducerBodies(member=member, shaft=shaft, journal=journal, gear=gear,
                         output=output, carrier=carrier, input=inp)


def mass_matrix(system, bodies: ReducerBodies, *, load_kgm2: float, motor_kgm2: float,
                input_index: int | None = None) -> np.ndarray:
    """The mass matrix on the system model's coordinates (the module docstring), the input
    coordinate appended where it is free.

    Parameters
    ----------
    system : toothfem.fem.drives.assembly.CycloidSystem
    bodies : ReducerBodies
    load_kgm2, motor_kgm2 : float
        The load's inertia on the output, the motor's on the input [kg m^2].
    input_index : int, optional
        The free input's coordinate (system.coords.n); None: the input held.

    Returns
    -------
    numpy.ndarray, shape (n, n) or (n + 1, n + 1)
        [kg, kg m, kg m^2].
    """
    c = system.coords
    n = c.n + (input_index is not None)
    m = np.zeros((n, n))

    def add(row, value):              # T += 1/2 value (row . u')^2 for each row
        row = np.atleast_2d(row)
        m[:] += value * row.T @ row

    def coords(terms):               # rows of the named coordinates' coefficients
        first = next(iter(terms.values()))
        r = np.zeros((np.shape(first)[0] if np.ndim(first) else 1, n))
        for name, coefficient in terms.items():
            r[:, c.index[name]] += coefficient
        return r

    out, carrier = c.index["out"], c.index["carrier"]
    add(coords({"out": 1.0}), load_kgm2 + bodies.output.inertia_kgm2)
    if bodies.carrier is not None:
        if carrier == out:
            add(coords({"out": 1.0}), bodies.carrier.inertia_kgm2)
        else:
            add(coords({"out": 1.0}), 0.5 * bodies.carrier.inertia_kgm2)
            add(coords({"carrier": 1.0}), 0.5 * bodies.carrier.inertia_kgm2)
    for j in range(system.discs):
        sl = c.index[f"disc{j}"]
        for axis in range(2):
            r = np.zeros(n)
            r[sl.start + axis] = 1.0
            add(r, bodies.member.mass_kg)
        r = np.zeros(n)
        r[sl.start + 2] = 1.0
        add(r, bodies.member.inertia_kgm2)
    frame = np.array([system.path.frame_rate(np.eye(c.n)[i], c) for i in range(c.n)])
    frame = np.concatenate([frame, np.zeros(n - c.n)])
    span = system.supports.crankshaft_span_m
    for k in range(system.cranks):
        a_k = system.r_c * np.array([math.cos(2 * math.pi * k / system.cranks),
                                     math.sin(2 * math.pi * k / system.cranks)])
        ends = 0.5 * bodies.shaft.mass_kg
        for name in ("s1", "s2"):          # the shaft's body at its supports
            v = coords({f"{name}_{k}": np.eye(2)})
            for term, cf in system.path.frame_terms(a_k, np.zeros(2)).items():
                v[:, c.index[term]] += cf[:, None]
            add(v, 0.5 * ends)
        for s in system.slots:             # the journals, each with half the body's rest
            z = s.axial_m / span
            v = coords({f"s1_{k}": (1 - z) * np.eye(2), f"s2_{k}": z * np.eye(2)})
            w = c.index[f"w{k}"]
            v[:, w.start + 2 * s.index: w.start + 2 * s.index + 2] += np.eye(2)
            for term, cf in system.path.frame_terms(a_k, np.zeros(2)).items():
                v[:, c.index[term]] += cf[:, None]
            add(v, bodies.journal.mass_kg + ends / system.discs)
        r = frame.copy()
        r[c.index[f"psi_e{k}"]] += 1.0
        add(r, bodies.shaft.inertia_kgm2 + system.discs * bodies.journal.inertia_kgm2)
        if bodies.gear is not None:
            for name in system.path.shaft_coordinates(k):
                r = frame.copy()
                r[c.index[name]] += 1.0
                add(r, bodies.gear.inertia_kgm2)
    if input_index is not None:
        r = np.zeros(n)
        r[input_index] = 1.0
        add(r, motor_kgm2 + (0.0 if bodies.input is None else bodies.input.inertia_kgm2))
    return m
