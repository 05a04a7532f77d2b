"""cycloidgen's half of a side-by-side benchmark on the K-H-V drive with output pins
(cases/cycloid_khv.toml): the drive's torsional rigidity, the ring stage's and the output
stage's apart, its lost motion and backlash, the pins engaged, the ring pins' and the
output pins' peak forces, at the case's 40 N m, with an unmodified profile and with a
10 um equidistant modification. toothfem's half (``ours``) is left to the system model's
K-H-V layout.

The peer is never a dependency of toothfem: it lives in its own environment,

    python3 -m venv benchmarks/.venv-peer && benchmarks/.venv-peer/bin/pip install cycloidgen

and this script runs its half there by subprocess (``--peer-python``), as
benchmarks/peer_cycloidgen.py does. Run it from the project's venv (it needs only the
standard library on this side):

    .venv/bin/python benchmarks/peer_cycloidgen_khv.py [--out FILE.json]

It prints the peer's table and writes benchmarks/results/peer_cycloidgen_khv_peer.json.

What cycloidgen 8.0 models (read from its source, site-packages/cycloidgen)
----------------------------------------------------------------------------
Layout. One crank, ``disc_count`` discs phased 360/n deg apart, ``lobes + 1`` ring pins
(one-tooth difference only: the pin count is derived, never an input), output taken off
the carrier of the output pins with the ring fixed (``output_member = CARRIER``,
ratio = lobes = 29). The output mechanism is ``output_pin_count`` pins of diameter
``output_pin_diameter`` on ``output_bolt_circle_radius`` in holes of diameter
``output_pin_diameter + 2 E + hole_clearance``. ``output_pins_are_rollers`` only switches
the friction (rolling mu in efficiency/thermal) and the roller-bearing selection, and
with it on, ``output_pin_diameter`` *is* the roller's OD, the working surface
(analysis/bearings.py: "the roller's OD *is* the working pin"). There is no separate pin
core diameter: everything (contact, hole, pin bending) uses that one diameter.
``ring_pins_integral`` and ``ring_pins_are_rollers`` change only mass and friction, not
any stiffness or force.

Load sharing, F_max (analysis/mechanics.py ``analyse_contacts``, core/kinematics.py).
Rigid disc, every contact a linear spring ("Kudryavtsev/Lehmann"): the force at a contact
is proportional to its moment arm about the disc centre, only the half of the pins whose
arm pushes against the torque carry, sum F_i h_i = T_disc. Clearance-blind (theoretical
profile). The torque is split exactly 50/50: ``T_disc = T / disc_count`` (hard-coded in
analyse_contacts and analyse_stiffness; only the TE solve lets the stack share unequally).
Ring F_max = the largest share over 144 crank angles spanning one ring-stage period;
output-pin F_max likewise over one output-stage period. Output pins: relative to the
carrier the disc makes a pure circular translation of radius E, so every pin's force is
parallel to the eccentricity direction, F_j = T_disc |h_j| / sum h^2 over the pins with
h_j < 0 (half the pins, rigid disc and rigid carrier).

Stiffness (analysis/stiffness.py ``analyse_stiffness``). Input held, output twisted; the
disc turns rigidly by theta with its centre fixed on a rigid crank (the eccentric bearing
is not in the model, nor the main bearings). Each contact is a Hertz line contact whose
approach is Johnson eq. 4.45 (logarithmic; body radii capped at the pin-circle radius as
the reference length), fitted as delta = c F^0.9 at its rigid-share load; length = disc
thickness. Ring contacts: pin radius against the local profile radius (concave,
negative). Output contacts: pin (roller) radius against the hole radius r + E
(conforming). Each contact closes its gap first, delta_i = max(0, theta h_i - g_i); the
ring gaps are *measured* from each pin to a 2000-point polyline of the manufactured
profile, the output gaps are hole_clearance/2 for every pin. theta is bisected so that
sum F_i h_i = T_disc, and the stage stiffness is dT/dtheta there (a tangent, not a
secant), averaged over 8 crank angles in one ring-stage period (the output stage is read
at the same 8 angles); the two discs act in parallel (x disc_count). Ring stage and output
stage in series = "contact only". In series with that, "structure"
(analysis/compliance.py), all closed forms and linear: ring-pin seats (the pin bedding
into its pocket, a conforming line contact pin in a bore Rr + hole_clearance/2 of the
housing's material; the pins themselves are taken as not bending, supported along their
length), the housing barrel in torsion (G J / (stack/2)), the disc body as an annulus in
in-plane torsion from the output-pin circle to the root radius, the output pins as
Timoshenko cantilevers off the carrier loaded at stack_height/2 (one set of pins for the
whole stack, so not multiplied by the disc count; k = k_pin sum h^2 over the loaded pins),
the carrier plate as an annulus from R_w to R_w + d_pin (rim-driven), the input shaft in
torsion referred to the output (x ratio^2). Friction is nowhere in it: no hysteresis.

Lost motion (cycloidgen's name) = the zero-torque play only, both directions:
2 x max over crank angles of min_i(g_i / h_i) for the ring, plus 2 x (hole_clearance/2) /
R_w for the output holes. That is toothfem's *backlash* (theta(0 from +) - theta(0 from
-)), so it is reported here as ``backlash_arcmin`` (as peer_cycloidgen.py reported its
ring part as the mesh backlash). ``lost_motion_arcmin`` here is toothfem's definition,
theta(+3 %) - theta(-3 %), built from the peer's own numbers: its play plus twice its
wind-up at 3 % of the torque. cycloidgen's "backlash_total" (play + wind-up at the rated
torque) is kept under its own name.

Mapping of the case onto GearSpec (``peer_spec``)
--------------------------------------------------
========================================  =================================================
case                                      GearSpec
========================================  =================================================
pin_count 30, lobe_count 29               lobes = 29 (pin_count derived = 30; checked)
pin_circle_radius_mm 50, pin_radius 3     pin_circle_radius = 50, pin_radius = 3
eccentricity_mm 1.2                       eccentricity = 1.2
face_width_mm 8, disc_count 2             disc_thickness = 8, disc_count = 2
equidistant modification 0 / 10 um        offset_mode = EQUIDISTANT, profile_clearance =
                                          0 / 0.010 (equidistant = grow the generating
                                          roller radius, the same modification)
pin_structure conventional                ring_pins_integral = False, ring_pins_are_rollers
                                          = False (pins in housing grooves; no effect on
                                          the quantities here)
centre_bore_radius_mm 14                  center_bore_diameter = 28
eccentric_bearing_inner_radius_mm 10      eccentric_cam_diameter = 20
output pins 8 on 30 mm                    output_pin_count = 8, output_bolt_circle_radius
                                          = 30, output_member = CARRIER (ratio 29)
roller_radius_mm 5.5 on pin_radius 4      output_pins_are_rollers = True,
                                          output_pin_diameter = 11 (the roller OD, the
                                          surface touching the hole)
hole_radius_mm 6.7 (= 5.5 + 1.2)          hole_clearance = 2 (6.7 - 5.5 - 1.2) = 0, so the
                                          hole is 13.4 mm exactly
steel E 208 GPa, nu 0.3                   every material "Bearing steel 100Cr6" (E 210 GPa,
                                          nu 0.30; the peer takes only named materials:
                                          E is 1 % high, the contacts ~1 % stiff)
output_torque_Nm 40, input 1500 rpm       output_torque_Nm = 40, input_rpm = 1500
position tolerance (none)                 position_tolerance = 0 (one perfect ring)
========================================  =================================================

Values the peer needs that the case does not give (ASSUMPTIONS, peer defaults unless
said): disc_gap = 0 (the case stacks two 8 mm discs and states no gap; the peer's default
is 1 mm, which would lengthen the pin cantilever from 8.0 to 8.5 mm), process = EDM/ground
(roughness only; the clearances are set explicitly), input_shaft_diameter = 10 mm
(default; its torsion, x 29^2, is in the structure), housing_wall = 6 mm,
output_flange_thickness (carrier plate) = 6 mm, end plates, bolts, bearings: defaults
(none of them is in the quantities reported), lubricant "Grease NLGI 2
(lithium/mineral)" (the nearest to grease of VG 100 base oil; friction only).

What the case has that the peer cannot take: the pin core (4 mm radius) under the roller
-- the peer bends an 11 mm pin, the roller OD, as the output-pin cantilever (the extra
``core_pin`` figures re-bend the 8 mm core with the peer's own cantilever formula and
re-sum its series); the eccentric bearing ([supports], 14 rollers 4 x 8 mm): not in the
peer's stiffness at all; the pin-groove contact of a conventional pin is the peer's
"ring seat", which with hole_clearance = 0 becomes a conforming contact of equal radii and
is effectively rigid (~4e11 N m/arcmin) -- the same hole_clearance sets the output holes'
zero clearance, so the two cannot be set apart.

A peer artifact, reported and not corrected in the main figures: the ring gaps come from
a 2000-vertex polyline of the profile, whose chord error on this profile (K1 = 0.72, 29
lobes) is about -19 um -- a polyline pin "interference" larger than the 10 um
modification. So the peer's own validate() reports PROFILE_INTERFERENCE, its 10 um ring
play comes out 0 and its gapped load sharing, pins engaged and ring rigidity are spoilt
by that numerical error (at 0 um too). The ``resampled`` figures rerun the identical
solve with the gaps measured on a 50 000-vertex polyline (error ~0.03 um), nothing else
changed; they are what the peer's model gives for this drive, the main figures are what
the peer as shipped prints.
"""
import argparse
import json
import math
import subprocess
import sys
import time

import numpy as np
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10: the project's own fallback
    import tomli as tomllib

ROOT = Path(__file__).resolve().parent.parent
PEER_PYTHON = ROOT / "benchmarks" / ".venv-peer" / "bin" / "python"
CASE_PATH = ROOT / "cases" / "cycloid_khv.toml"
OUT_PATH = ROOT / "benchmarks" / "results" / "peer_cycloidgen_khv_peer.json"
#: The equidistant modifications compared (mm).
CLEARANCES_MM = (0.0, 0.010)
#: The vertices of the diagnostic re-measurement of the ring gaps (the peer's: 2000).
RESAMPLED_VERTICES = 50_000
#: The peer's material for every part: the nearest of its named steels to the case's.
PEER_STEEL = "Bearing steel 100Cr6"
PEER_STEEL_E_GPA, PEER_STEEL_NU = 210.0, 0.30


def peer_spec(case_path=CASE_PATH):
    """The case as cycloidgen's GearSpec keyword arguments (JSON-able; the enums by
    value), the profile clearance left out, and the pin core diameter [mm] the peer has
    no field for. Every value is stated in the module docstring's mapping table."""
    case = tomllib.loads(Path(case_path).read_text())
    cy, om = case["cycloid"], case["output_mechanism"]
    mat, op = case["material"], case["operating"]
    if cy["pin_count"] != cy["lobe_count"] + 1:
        raise ValueError("cycloidgen takes one-tooth-difference drives only")
    if cy.get("pin_structure", "conventional") != "conventional":
        raise ValueError("mapping written for conventional pins")
    for key in ("move_distance_modification_mm", "rotation_modification_deg"):
        if cy.get(key, 0.0) != 0.0:
            raise ValueError(f"the peer takes no {key}")
    e = cy["eccentricity_mm"]
    contact_r = om.get("roller_radius_mm") or om["pin_radius_mm"]
    hole_r = om.get("hole_radius_mm") or contact_r + e
    hole_clearance = round(2.0 * (hole_r - contact_r - e), 9)
    if hole_clearance < 0:
        raise ValueError("the case's output holes are smaller than roller + e")
    if (abs(mat["youngs_modulus_GPa"] - PEER_STEEL_E_GPA) > 0.02 * PEER_STEEL_E_GPA
            or abs(mat["poisson_ratio"] - PEER_STEEL_NU) > 0.01):
        raise ValueError(f"the case's material is not near the peer's {PEER_STEEL}")
    spec = dict(
        pin_circle_radius=cy["pin_circle_radius_mm"], pin_radius=cy["pin_radius_mm"],
        eccentricity=e, lobes=cy["lobe_count"],
        disc_thickness=cy["face_width_mm"], disc_count=cy["disc_count"], disc_gap=0.0,
        center_bore_diameter=2.0 * case["cycloid"]["disc_holes"]["centre_bore_radius_mm"],
        eccentric_cam_diameter=2.0 * om["eccentric_bearing_inner_radius_mm"],
        output_member="output pin carrier",
        output_pin_count=om["pin_count"],
        output_pin_diameter=2.0 * contact_r,
        output_bolt_circle_radius=om["pin_hole_circle_radius_mm"],
        output_pins_are_rollers=om.get("roller_radius_mm") is not None,
        process="Wire EDM / ground", offset_mode="equidistant",
        hole_clearance=hole_clearance, position_tolerance=0.0,
        disc_material=PEER_STEEL, pin_material=PEER_STEEL,
        housing_material=PEER_STEEL, shaft_material=PEER_STEEL,
        ring_pins_integral=False, ring_pins_are_rollers=False,
        lubricant="Grease NLGI 2 (lithium/mineral)",
        friction_coefficient=case.get("friction", {}).get("pin_groove_coefficient", 0.05),
        input_rpm=op["input_speed_rpm"], output_torque_Nm=op["output_torque_Nm"],
    )
    return spec, 2.0 * om["pin_radius_mm"]


#: The peer's half, run by its own interpreter. argv[1]: {"spec", "clearances",
#: "core_pin_diameter", "resample"}. Prints one JSON line.
PEER_CODE = r"""
import json, math, sys
import numpy as np
import cycloidgen
from cycloidgen.core.spec import GearSpec
from cycloidgen.core import kinematics as kin
from cycloidgen.core.validate import validate
from cycloidgen.analysis import stiffness as st
from cycloidgen.analysis.mechanics import analyse_contacts
from cycloidgen.analysis.compliance import cantilever_stiffness, series_stiffness

cfg = json.loads(sys.argv[1])
STOCK_MESH_GAPS = st.mesh_gaps


def gapped_ring_fmax(spec):
    # The peer's own gapped ring solve (analyse_stiffness's crank angles and solver),
    # its largest pin force: what the load concentration multiplies.
    tpd = spec.output_torque_Nm * 1000.0 / spec.disc_count
    states = kin.sweep(spec, kin.SWEEP_STEPS)
    fmax = 0.0
    for cs in states[:: max(1, len(states) // 8)]:
        c = st._ring_contacts(spec, cs, tpd)
        if c is None:
            continue
        _theta, f = st._solve_rotation(c.c, c.arms, c.gaps, tpd)
        fmax = max(fmax, float(f.max()))
    return fmax


def output_pin_forces(spec):
    # One disc's rigid-share output-pin forces at the crank angle of the largest
    # (analyse_contacts's own sweep over one output-stage period).
    tpd = spec.output_torque_Nm * 1000.0 / spec.disc_count
    best = None
    for phi in kin.output_sweep_angles(spec.lobes, spec.output_pin_count, kin.SWEEP_STEPS):
        ol = kin.output_loads(spec, float(phi), tpd)
        if best is None or ol.forces.max() > best.forces.max():
            best = ol
    return [float(f) for f in best.forces], math.degrees(best.phi)


def figures(spec):
    torque = spec.output_torque_Nm
    s = st.analyse_stiffness(spec)
    s50 = st.analyse_stiffness(spec.model_copy(update={"output_torque_Nm": 0.5 * torque}))
    s3 = st.analyse_stiffness(spec.model_copy(update={"output_torque_Nm": 0.03 * torque}))
    ct = analyse_contacts(spec)
    forces, phi_deg = output_pin_forces(spec)
    # the output pins bent as the case's pin core instead of the roller OD: the peer's
    # cantilever formula and series composition, nothing else changed
    length = max(spec.stack_height / 2.0, 1e-9)
    E, nu = spec.pin_mat.E_GPa * 1000.0, spec.pin_mat.nu
    scale = (cantilever_stiffness(E, nu, cfg["core_pin_diameter"], length)
             / cantilever_stiffness(E, nu, spec.output_pin_diameter, length))
    pins = s.structure.output_pin_Nm_per_arcmin
    structure_core = 1.0 / (1.0 / s.structure_Nm_per_arcmin - 1.0 / pins
                            + 1.0 / (scale * pins))
    return {
        "drive_rigidity_Nm_per_arcmin": s.stiffness_Nm_per_arcmin,
        "ring_rigidity_Nm_per_arcmin": s.ring_stage_Nm_per_arcmin,
        "output_rigidity_Nm_per_arcmin": s.output_stage_Nm_per_arcmin,
        "lost_motion_arcmin": s3.lost_motion_arcmin + 2.0 * s3.windup_arcmin,
        "backlash_arcmin": s.lost_motion_arcmin,
        "pins_engaged": s.pins_engaged,
        "f_max_N": ct.max_pin_force_N,
        "output_pin_forces_N": forces,
        # ---- the rest of what the peer gives --------------------------------
        "hysteresis_arcmin": None,
        "output_f_max_N": ct.max_output_force_N,
        "output_pin_forces_crank_deg": phi_deg,
        "pins_engaged_ideal": s.pins_engaged_ideal,
        "pins_in_contact_max_rigid": ct.pins_in_contact,
        "f_max_gapped_N": gapped_ring_fmax(spec),
        "load_concentration": s.load_concentration,
        "drive_rigidity_secant_50_100_Nm_per_arcmin":
            0.5 * torque / (s.windup_arcmin - s50.windup_arcmin),
        "contact_only_Nm_per_arcmin": s.contact_only_Nm_per_arcmin,
        "structure_Nm_per_arcmin": s.structure_Nm_per_arcmin,
        "structure_parts_Nm_per_arcmin": {
            "ring_pin_seats": s.structure.ring_seat_Nm_per_arcmin,
            "housing": s.structure.housing_Nm_per_arcmin,
            "disc_bodies": s.structure.disc_body_Nm_per_arcmin,
            "output_pins_bending": pins,
            "carrier_plate": s.structure.carrier_plate_Nm_per_arcmin,
            "input_shaft": s.structure.input_shaft_Nm_per_arcmin},
        "core_pin": {
            "output_pins_bending_Nm_per_arcmin": scale * pins,
            "structure_Nm_per_arcmin": structure_core,
            "drive_rigidity_Nm_per_arcmin":
                series_stiffness(s.contact_only_Nm_per_arcmin, structure_core)},
        "windup_arcmin": s.windup_arcmin,
        "peer_lost_motion_arcmin": s.lost_motion_arcmin,
        "peer_lost_motion_ring_arcmin": s.lost_motion_ring_arcmin,
        "peer_lost_motion_output_arcmin": s.lost_motion_output_arcmin,
        "peer_backlash_total_arcmin": s.backlash_total_arcmin,
        "ring_gap_spread_um": 1e3 * s.max_gap_spread_mm,
        "ring_interference_um": 1e3 * s.position_interference_mm,
        "eccentric_bearing_load_N": ct.eccentric_bearing_load_N,
    }


out = {"version": cycloidgen.__version__}
for clearance in cfg["clearances"]:
    spec = GearSpec(**cfg["spec"], profile_clearance=clearance)
    st.mesh_gaps = STOCK_MESH_GAPS
    row = figures(spec)
    row["peer_checks"] = [f"{f.severity.name} {f.code} [{f.value} vs {f.limit}]"
                          for f in validate(spec).findings
                          if f.severity.name in ("ERROR", "WARNING")]
    n = cfg["resample"]
    st.mesh_gaps = lambda spec, phi, n=n: kin.mesh_gaps(spec, phi, n)
    row["resampled"] = figures(spec)
    row["resampled"]["vertices"] = n
    st.mesh_gaps = STOCK_MESH_GAPS
    out[str(clearance)] = row
print(json.dumps(out))
"""


def peer(python=PEER_PYTHON, case_path=CASE_PATH) -> dict:
    """cycloidgen's figures for the case, per profile clearance (keys str(mm)), and its
    version; ``gearspec`` records the mapping used."""
    spec, core_d = peer_spec(case_path)
    cfg = {"spec": spec, "clearances": list(CLEARANCES_MM), "core_pin_diameter": core_d,
           "resample": RESAMPLED_VERTICES}
    res = subprocess.run([str(python), "-c", PEER_CODE, json.dumps(cfg)],
                         check=True, capture_output=True, text=True)
    out = json.loads(res.stdout.strip().splitlines()[-1])
    out["gearspec"] = spec
    out["pin_core_diameter_mm"] = core_d
    return out


# ---------------------------------------------------------------------------------------
# toothfem's half: the system model's K-H-V layout (fem/drives/assembly.py)
# ---------------------------------------------------------------------------------------
#: Positions per pin pitch (the datasheet's default, `toothfem stiffness`).
POSITIONS = 36
#: Pin pitches swept for the largest ring-pin and output-pin forces: a pin pitch is
#: 360/30 = 12 deg of crank angle, the output pins' pattern repeats every 360/8 = 45 deg,
#: so four pitches (48 deg) hold every output-pin configuration.
FORCE_PITCHES = 4
#: The outputs' names (the work balance's paths) of the parts of a K-H-V drive.
OUTPUT_PINS, MESH = "output pins", "mesh"


def _rigid_all():
    """Every element group of the system model (fem.drives.assembly.GROUPS): made rigid,
    only the contacts (ring pins through the FE tables, output pins) keep a compliance."""
    from toothfem.fem.drives.assembly import GROUPS
    return tuple(GROUPS)


def _sheet(system, rated):
    """The datasheet (fem/datasheet/sheet.py) of a system model, and its twist model."""
    from toothfem.fem.datasheet.sheet import datasheet
    from toothfem.fem.system.datasheet import SystemTwist
    twist = SystemTwist(system)
    return twist, datasheet(twist, rated)


def _unbend_output_pins(system):
    """The output pins' bending taken out of a built model (the benchmark's own limit case,
    no option exists for it): the pins' influence matrix, read at each solve by
    ``fem.system.output_pins.pin_contacts``, set to zero; what is left of the output stage is its
    line contacts (Palmgren at the hole and at the roller's bore)."""
    if not hasattr(system, "output_pin_bending"):
        raise RuntimeError("CycloidSystem has no output_pin_bending any more: adapt "
                           "_unbend_output_pins to the model's API")
    system.output_pin_bending = np.zeros_like(system.output_pin_bending)
    return system


def _per_Nm(sheet, path):
    """A path's secant compliance 50-100 % [arcmin/(N m)], 0 if the path is absent."""
    return float(sheet.compliance_arcmin_per_Nm.get(path, 0.0))


def _forces(drive, supports, rated, positions, pitches):
    """The largest ring-pin, output-pin and eccentric-bearing forces at the rated torque over
    ``pitches`` pin pitches of ``positions`` each (both discs), and the worst position's
    output-pin forces (the disc that carries the largest)."""
    ring = out = bearing = shift = -1.0
    worst = None
    for m in range(pitches):
        system = drive.system_model(supports, positions, pitch=m)
        last = None
        for p in range(positions):
            st = system.solve(rated, p, start=last)
            last = st
            ring = max(ring, float(st.pin_force_N.max()))
            shift = max(shift, _disc_translation(system, st))
            bearing = max([bearing] + [float(np.hypot(*f)) for name, f in
                                       st.bearing_force_N.items() if "eccentric" in name])
            f = st.output_pin_force_N
            j = int(np.argmax(f.max(axis=1)))
            if float(f[j].max()) > out:
                out = float(f[j].max())
                worst = {"disc": j + 1, "crank_deg": math.degrees(float(st.position_rad)),
                         "forces_N": [float(x) for x in f[j]],
                         "other_disc_forces_N": [float(x) for x in f[1 - j]]
                         if f.shape[0] == 2 else None}
    return ring, out, worst, bearing, shift


def _disc_translation(system, state) -> float:
    """The largest translation of a disc's centre [m] in a solved state (the model's
    coordinates ``disc{j}``: x, y, theta); NaN if the model's internals changed."""
    try:
        u = state.equilibrium.u
        return max(float(np.hypot(*u[system.coords.index[f"disc{j}"]][:2]))
                   for j in range(system.discs))
    except (AttributeError, KeyError):
        return float("nan")


def _eccentric_load(states) -> float:
    """The largest eccentric-bearing force [N] over solved states."""
    return max(float(np.hypot(*f)) for st in states
               for name, f in st.bearing_force_N.items() if "eccentric" in name)


def ours(case_path, positions=POSITIONS, force_pitches=FORCE_PITCHES, progress=print):
    """toothfem's figures for the same case and the same keys as ``peer`` (per profile
    clearance in CLEARANCES_MM), from the system model (input held, torque on the output
    flange, both flanks, FE ring-pin tables at each disc's true configuration).

    Three models per clearance, all the same system model:

    - ``full``: the reducer as the datasheet computes it (eccentric bearings, input
      bearings, input shaft bending and torsion, the FE disc-pin mesh, the output pins'
      Palmgren line contacts and their bending between the output flange and the support
      ring); the datasheet's figures and compliance shares;
    - ``contacts``: every element group rigid (``rigid=GROUPS``): the discs turn on a rigid
      eccentric about fixed centres, as the peer's discs do; its twist is the FE mesh in
      series with the output pins (contacts and bending);
    - ``contacts, unbent pins``: the same with the output pins' bending set to zero
      (:func:`_unbend_output_pins`): the counterpart of the peer's "contact only", its
      work-balance paths the counterparts of the peer's ring stage (``mesh``) and output
      stage (``output pins``). The output pins' bending alone is the difference of the
      ``output pins`` path between the two.

    Every rigidity is the datasheet's secant 50-100 % of the rated torque (the peer's
    stage figures are tangents at the rated torque; its drive figure is given both ways).
    """
    import sys as _sys
    _sys.path.insert(0, str(ROOT))
    from dataclasses import replace

    from toothfem.case import load_case
    from toothfem.efficiency import rated_output_torque
    from toothfem.fem.drives import drive_for

    base = load_case(case_path)
    out = {"positions": int(positions), "force_pitches": int(force_pitches)}
    for clearance in CLEARANCES_MM:
        t0 = time.perf_counter()
        case = replace(base, cycloid=replace(base.cycloid,
                                             equidistant_modification_mm=clearance))
        drive = drive_for(case)
        si = case.to_si()
        supports = drive.supports(si.supports)
        rated, rated_assumed = rated_output_torque(si)
        full_twist, full = _sheet(drive.system_model(supports, positions), rated)
        rigid = _rigid_all()
        _, bent = _sheet(drive.system_model(supports, positions, rigid=rigid), rated)
        unbent_twist, unbent = _sheet(_unbend_output_pins(
            drive.system_model(supports, positions, rigid=rigid)), rated)
        ring_f, out_f, worst, bearing_f, shift = _forces(drive, supports, rated, positions, force_pitches)
        at = full_twist.at(rated, 1)
        c_full = sum(full.compliance_arcmin_per_Nm.values())
        c_contact = sum(unbent.compliance_arcmin_per_Nm.values())
        c_bend = _per_Nm(bent, OUTPUT_PINS) - _per_Nm(unbent, OUTPUT_PINS)
        summary = full.summary()
        row = {
            "rated_torque_Nm": rated, "rated_torque_assumed": rated_assumed,
            "drive_rigidity_Nm_per_arcmin": full.rigidity_Nm_per_arcmin,
            "drive_rigidity_by_direction_Nm_per_arcmin": list(full.rigidity_by_direction),
            "drive_rigidity_secant_50_100_Nm_per_arcmin": full.rigidity_Nm_per_arcmin,
            "three_segments_Nm_per_arcmin": list(full.segment_stiffness_Nm_per_arcmin),
            "lost_motion_arcmin": full.lost_motion_arcmin,
            "backlash_arcmin": full.backlash_arcmin,
            "pins_engaged": float(np.mean(at.contacts)),
            "pins_engaged_range": [int(np.min(at.contacts)), int(np.max(at.contacts))],
            "f_max_N": ring_f,
            "output_f_max_N": out_f,
            "output_pin_forces_N": worst["forces_N"],
            "output_pin_forces_crank_deg": worst["crank_deg"],
            "output_pin_forces_disc": worst["disc"],
            "output_pin_forces_other_disc_N": worst["other_disc_forces_N"],
            "twist_at_rated_arcmin": float(np.mean(at.total)) / ARCMIN_,
            "disc_torques_at_rated_Nm": list(at.member_torques_Nm),
            "compliance_arcmin_per_Nm": dict(full.compliance_arcmin_per_Nm),
            "compliance_shares": dict(full.compliance_shares),
            "supports": summary["supports"],
            # the full model's mesh path (the disc free on its eccentric bearing)
            "mesh_in_drive_Nm_per_arcmin": 1.0 / _per_Nm(full, MESH),
            "output_pins_in_drive_Nm_per_arcmin": 1.0 / _per_Nm(full, OUTPUT_PINS),
            # the partial models
            "ring_rigidity_Nm_per_arcmin": 1.0 / _per_Nm(unbent, MESH),
            "output_rigidity_Nm_per_arcmin": 1.0 / _per_Nm(unbent, OUTPUT_PINS),
            "output_pins_bending_Nm_per_arcmin": 1.0 / c_bend if c_bend > 0 else math.inf,
            "output_pins_with_bending_Nm_per_arcmin": 1.0 / _per_Nm(bent, OUTPUT_PINS),
            "contact_only_Nm_per_arcmin": unbent.rigidity_Nm_per_arcmin,
            "contacts_and_pin_bending_Nm_per_arcmin": bent.rigidity_Nm_per_arcmin,
            "contact_only_paths_arcmin_per_Nm": dict(unbent.compliance_arcmin_per_Nm),
            "contacts_and_pin_bending_paths_arcmin_per_Nm":
                dict(bent.compliance_arcmin_per_Nm),
            # the rest of the drive (bearings, input shaft, pin bending): total less contacts
            "structure_Nm_per_arcmin": 1.0 / (c_full - c_contact),
            "contact_only_backlash_arcmin": unbent.backlash_arcmin,
            "contact_only_pins_engaged": float(np.mean(unbent_twist.at(rated, 1).contacts)),
            "eccentric_bearing_load_max_N": bearing_f,
            "disc_translation_max_m": shift,
            "contact_only_f_max_N": max(float(st.pin_force_N.max())
                                        for st in unbent_twist.states(rated, 1)),
            "contact_only_eccentric_bearing_load_max_N":
                _eccentric_load(unbent_twist.states(rated, 1)),
            "contact_only_lost_motion_arcmin": unbent.lost_motion_arcmin,
            "seconds": None,
        }
        row["seconds"] = time.perf_counter() - t0
        progress(f"toothfem, {1e3 * clearance:g} um: {row['seconds']:.1f} s")
        out[str(clearance)] = row
    return out


ARCMIN_ = math.pi / (180 * 60)

#: The held ring of the K-H-V disc's FE (its centre bore) moved outward for a diagnostic of
#: the ring stage: the case's 14 mm, then 18 and 22 mm (the output holes begin at 23.3 mm).
BORE_DIAGNOSTIC_MM = (14.0, 18.0, 22.0)


def bore_diagnostic(case_path, positions=12):
    """The ring stage's rigidity (every group rigid, output pins unbent, 0 um) with the
    disc's FE held at a larger centre bore: how much of the FE ring stage is the disc's
    in-plane torsion between its bore and its output holes (the FE holds the disc at its
    bore, while the torque leaves through the output holes at R_w). A diagnostic of the
    model, not a figure of the drive. Beside it, the closed form of a plain annulus (two
    discs in parallel) twisted between the bore and R_w:
    theta/T = (1/r_b^2 - 1/R_w^2) / (4 pi G t) / discs."""
    from dataclasses import replace

    from toothfem.case import load_case
    from toothfem.efficiency import rated_output_torque
    from toothfem.fem.drives import drive_for

    base = load_case(case_path)
    out = {}
    for bore in BORE_DIAGNOSTIC_MM:
        holes = replace(base.cycloid.disc_holes, centre_bore_radius_mm=bore)
        case = replace(base, cycloid=replace(base.cycloid, disc_holes=holes,
                                             equidistant_modification_mm=0.0))
        drive = drive_for(case)
        si = case.to_si()
        rated, _ = rated_output_torque(si)
        system = _unbend_output_pins(drive.system_model(
            drive.supports(si.supports), positions, rigid=_rigid_all()))
        _, sheet = _sheet(system, rated)
        out[str(bore)] = 1.0 / _per_Nm(sheet, MESH)
    g = 208e9 / (2 * 1.3)          # the case's steel: E 208 GPa, nu 0.3
    t, discs = 8e-3, 2
    r_w = 30e-3
    ann = {str(b): (1 / (b * 1e-3) ** 2 - 1 / r_w ** 2) / (4 * math.pi * g * t) / discs
           / ARCMIN_ for b in BORE_DIAGNOSTIC_MM}
    return {"ring_rigidity_Nm_per_arcmin": out,
            "annulus_bore_to_Rw_arcmin_per_Nm": ann}


def hand_check(theirs) -> dict:
    """The classical rigid formulas beside the peer's F_max, with the torque split 50/50:
    output pins 4 T_disc / (n_o R_w), ring pins 4 T_disc / (e Zb Za)."""
    s = theirs["gearspec"]
    t_disc = s["output_torque_Nm"] * 1e3 / s["disc_count"]                # N mm
    out_rigid = 4 * t_disc / (s["output_pin_count"] * s["output_bolt_circle_radius"])
    za = s["lobes"]
    ring_rigid = 4 * t_disc / (s["eccentricity"] * (za + 1) * za)
    row = theirs[str(CLEARANCES_MM[0])]
    return {"T_disc_Nm": t_disc / 1e3,
            "output_f_max_classical_N": out_rigid,
            "output_f_max_peer_N": row["output_f_max_N"],
            "output_ratio": row["output_f_max_N"] / out_rigid,
            "ring_f_max_classical_N": ring_rigid,
            "ring_f_max_peer_N": row["f_max_N"],
            "ring_ratio": row["f_max_N"] / ring_rigid}


BOTH_PATH = ROOT / "benchmarks" / "results" / "peer_cycloidgen_khv.json"


def _series(*k):
    return 1.0 / sum(1.0 / x for x in k)


def shares(mine, theirs):
    """Each part's share of the compliance, ours (secant 50-100 %, the datasheet's paths; the
    output pins split into contacts and bending by the partial models) and the peer's
    (tangents at the rated torque, its stages and structure parts in series). None: the
    model has no such part (or holds it inside another row, said in the label)."""
    rows = {}
    for key, r in mine.items():
        if not isinstance(r, dict):
            continue
        c = dict(r["compliance_arcmin_per_Nm"])
        total = sum(c.values())
        out_pins = c.pop(OUTPUT_PINS, 0.0)
        contact = r["contact_only_paths_arcmin_per_Nm"][OUTPUT_PINS]
        bent = r["contacts_and_pin_bending_paths_arcmin_per_Nm"][OUTPUT_PINS]
        rows[f"ours {key}"] = {
            "ring mesh": c.get(MESH, 0.0) / total,
            "output pin contacts": out_pins * contact / bent / total,
            "output pin bending": out_pins * (1 - contact / bent) / total,
            "eccentric bearing": c.get("eccentric bearings", 0.0) / total,
            "input bearings": c.get("input bearings", 0.0) / total,
            "input shaft bending": c.get("input shaft bending", 0.0) / total,
            "input shaft torsion": c.get("input shaft torsion", 0.0) / total,
            "disc bodies": None, "carrier plate": None, "housing + pin seats": None}
    for c in CLEARANCES_MM:
        for tag, r in ((f"{c}", theirs[str(c)]), (f"{c} resampled", theirs[str(c)]["resampled"])):
            parts = r["structure_parts_Nm_per_arcmin"]
            comp = {"ring mesh": 1 / r["ring_rigidity_Nm_per_arcmin"],
                    "output pin contacts": 1 / r["output_rigidity_Nm_per_arcmin"],
                    "output pin bending": 1 / parts["output_pins_bending"],
                    "input shaft torsion": 1 / parts["input_shaft"],
                    "disc bodies": 1 / parts["disc_bodies"],
                    "carrier plate": 1 / parts["carrier_plate"],
                    "housing + pin seats": 1 / parts["housing"] + 1 / parts["ring_pin_seats"]}
            total = sum(comp.values())
            rows[f"peer {tag}"] = {
                **{k: v / total for k, v in comp.items()},
                "eccentric bearing": None, "input bearings": None,
                "input shaft bending": None}
    return rows


def table(mine, theirs) -> str:
    """The side-by-side Markdown table: ours, the peer as shipped and resampled, per
    clearance."""
    cols = []
    for c in CLEARANCES_MM:
        um = f"{1e3 * c:g} um"
        cols += [(f"{um} toothfem", mine[str(c)], "ours"),
                 (f"{um} cycloidgen", theirs[str(c)], "peer"),
                 (f"{um} cg resampled", theirs[str(c)]["resampled"], "peer")]

    def peer_output_total(r):
        return _series(r["output_rigidity_Nm_per_arcmin"],
                       r["structure_parts_Nm_per_arcmin"]["output_pins_bending"])

    rows = [
        ("drive rigidity 50-100 % secant [N m/arcmin]",
         lambda r: r["drive_rigidity_secant_50_100_Nm_per_arcmin"],
         lambda r: r["drive_rigidity_secant_50_100_Nm_per_arcmin"]),
        ("drive rigidity, peer's tangent at rated", None,
         lambda r: r["drive_rigidity_Nm_per_arcmin"]),
        ("ring stage only (rigid eccentric, unbent output pins)",
         lambda r: r["ring_rigidity_Nm_per_arcmin"],
         lambda r: r["ring_rigidity_Nm_per_arcmin"]),
        ("  mesh path in the whole drive (disc free)",
         lambda r: r["mesh_in_drive_Nm_per_arcmin"], None),
        ("output pins only: contacts",
         lambda r: r["output_rigidity_Nm_per_arcmin"],
         lambda r: r["output_rigidity_Nm_per_arcmin"]),
        ("output pins only: bending",
         lambda r: r["output_pins_bending_Nm_per_arcmin"],
         lambda r: r["structure_parts_Nm_per_arcmin"]["output_pins_bending"]),
        ("output pins only: contacts + bending",
         lambda r: r["output_pins_with_bending_Nm_per_arcmin"], peer_output_total),
        ("contact only (ring + output contacts)",
         lambda r: r["contact_only_Nm_per_arcmin"],
         lambda r: r["contact_only_Nm_per_arcmin"]),
        ("rest: ours bearings+shaft+pin bending, peer structure",
         lambda r: r["structure_Nm_per_arcmin"], lambda r: r["structure_Nm_per_arcmin"]),
        ("lost motion +-3 % [arcmin]", lambda r: r["lost_motion_arcmin"],
         lambda r: r["lost_motion_arcmin"]),
        ("backlash [arcmin]", lambda r: r["backlash_arcmin"],
         lambda r: r["backlash_arcmin"]),
        ("pins in contact at rated (mean, one disc)", lambda r: r["pins_engaged"],
         lambda r: r["pins_engaged"]),
        ("  same, rigid eccentric (contact only)", lambda r: r["contact_only_pins_engaged"],
         None),
        ("ring-pin F_max [N] (peer: its gapped solve)", lambda r: r["f_max_N"],
         lambda r: r["f_max_gapped_N"]),
        ("  peer: rigid share, clearance-blind", None, lambda r: r["f_max_N"]),
        ("output-pin F_max [N]", lambda r: r["output_f_max_N"],
         lambda r: r["output_f_max_N"]),
        ("eccentric bearing load max [N]", lambda r: r["eccentric_bearing_load_max_N"],
         lambda r: r["eccentric_bearing_load_N"]),
    ]
    lines = ["| quantity | " + " | ".join(h for h, _, _ in cols) + " |",
             "|---|" + "---:|" * len(cols)]
    for label, fo, fp in rows:
        cells = []
        for _, r, who in cols:
            f = fo if who == "ours" else fp
            cells.append("—" if f is None else f"{f(r):.4g}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    sh = shares(mine, theirs)
    keys = [f"ours {c}" if False else None for c in ()]
    order = []
    for c in CLEARANCES_MM:
        order += [(f"{1e3 * c:g} um toothfem", sh[f"ours {c}"]),
                  (f"{1e3 * c:g} um cycloidgen", sh[f"peer {c}"]),
                  (f"{1e3 * c:g} um cg resampled", sh[f"peer {c} resampled"])]
    lines += ["", "| compliance share | " + " | ".join(h for h, _ in order) + " |",
              "|---|" + "---:|" * len(order)]
    for part in order[0][1]:
        cells = ["—" if row[part] is None else f"{100 * row[part]:.1f} %" for _, row in order]
        lines.append(f"| {part} | " + " | ".join(cells) + " |")
    del keys
    return "\n".join(lines)


def explanation(mine, theirs, bores) -> str:
    """Each difference of the table, explained by what each model includes (numbers from
    this run)."""
    m0, m1 = mine[str(CLEARANCES_MM[0])], mine[str(CLEARANCES_MM[1])]
    p0, p1 = theirs[str(CLEARANCES_MM[0])], theirs[str(CLEARANCES_MM[1])]
    r0, r1 = p0["resampled"], p1["resampled"]
    parts = r0["structure_parts_Nm_per_arcmin"]
    sh = shares(mine, theirs)
    s0 = sh[f"ours {CLEARANCES_MM[0]}"]
    rb = bores["ring_rigidity_Nm_per_arcmin"]
    ann = bores["annulus_bore_to_Rw_arcmin_per_Nm"]["14.0"]
    pc = p0["core_pin"]["output_pins_bending_Nm_per_arcmin"]
    c_ours = 1 / m0["drive_rigidity_Nm_per_arcmin"]
    c_peer = 1 / r0["drive_rigidity_secant_50_100_Nm_per_arcmin"]
    d_bend = 1 / m0["output_pins_bending_Nm_per_arcmin"] - 1 / parts["output_pins_bending"]
    d_cont = 1 / m0["output_rigidity_Nm_per_arcmin"] - 1 / r0["output_rigidity_Nm_per_arcmin"]
    d_ring = 1 / m0["mesh_in_drive_Nm_per_arcmin"] - 1 / r0["ring_rigidity_Nm_per_arcmin"]
    d_ecc = m0["compliance_arcmin_per_Nm"].get("eccentric bearings", 0.0)
    d_shaft = (m0["compliance_arcmin_per_Nm"].get("input shaft torsion", 0.0)
               - 1 / parts["input_shaft"])
    torsion = 1 / max(m0['compliance_arcmin_per_Nm'].get('input shaft torsion', 1e-30), 1e-30)
    peer_torsion = 100 * sh[f"peer {CLEARANCES_MM[0]} resampled"]['input shaft torsion']
    backlash_gap = 100 * (m1['backlash_arcmin'] / r1['backlash_arcmin'] - 1)
    out = f"""
Differences, each explained (numbers of this run; compliances in arcmin per N m, 0 um
unless said, the peer resampled where its polyline spoils the figure):

1. Drive rigidity: ours {m0['drive_rigidity_Nm_per_arcmin']:.1f} against the peer's
   {r0['drive_rigidity_secant_50_100_Nm_per_arcmin']:.1f} (secant 50-100 %, 0 um). The
   compliance differs by {c_ours - c_peer:+.5f}; the parts of that difference below add up to
   it: output-pin bending {d_bend:+.5f}, output-pin contacts {d_cont:+.5f}, ring mesh
   {d_ring:+.5f}, eccentric bearing {d_ecc:+.5f} (not in the peer), input shaft torsion
   {d_shaft:+.5f}, the rest (our input bearings and shaft bending; the peer's disc bodies,
   carrier plate, housing) {c_ours - c_peer - d_bend - d_cont - d_ring - d_ecc - d_shaft:+.5f}.
2. Output-pin bending, ours {m0['output_pins_bending_Nm_per_arcmin']:.1f} against
   {parts['output_pins_bending']:.1f}: the peer bends the roller's OD (11 mm) as a cantilever
   off the carrier loaded at half the stack (8 mm), one pin set for the whole stack; ours
   bends the pin core (8 mm; the roller sleeve carries no bending) as a beam simply supported
   between the output flange and a support ring, on the input shaft's assumed span (32 mm),
   loaded by each disc at its own plane (12 and 20 mm). With the peer's own cantilever of
   the 8 mm core it would read {pc:.1f}. Span (32 mm simply supported against 8 mm
   clamped), diameter ((11/8)^4 = 3.6) and the load count (ours: each disc loads its own
   half of the pins, so the two halves work in parallel; the peer puts the whole torque on
   one half) set the ratio. Neither is measured; this is the largest single part of our
   compliance ({100 * s0['output pin bending']:.0f} %).
3. Output-pin contacts, ours {m0['output_rigidity_Nm_per_arcmin']:.1f} against
   {r0['output_rigidity_Nm_per_arcmin']:.1f}: ours has two line contacts in series per pin
   (roller on the hole, roller's bore on the pin), each Palmgren's empirical bearing law
   delta = 3.84e-5 Q^0.9 / l^0.8 (no radii); the peer has one (roller OD in the hole),
   Johnson's logarithmic Hertz approach with the conforming radii 5.5 / 6.7 mm (the roller's
   bore is not in its model). Per contact ours is
   {2 * m0['output_rigidity_Nm_per_arcmin'] / r0['output_rigidity_Nm_per_arcmin']:.2f} times
   the peer's stiffness (Palmgren against Johnson at these radii); the second contact halves
   ours again.
4. Ring stage, ours {m0['ring_rigidity_Nm_per_arcmin']:.0f} (every group rigid) and
   {m0['mesh_in_drive_Nm_per_arcmin']:.0f} (in the whole drive) against the peer's
   {r0['ring_rigidity_Nm_per_arcmin']:.0f} (resampled; {p0['ring_rigidity_Nm_per_arcmin']:.0f}
   as shipped): the peer's ring stage is the Hertz approach of each pin on the disc alone
   (rigid disc, rigid pins, seats booked apart and near rigid); ours is the FE of the disc
   and of the pins in their grooves, i.e. also the disc body, the pins' flattening and the
   grooves. A part of ours is a model artifact: the K-H-V disc's FE is held at its centre
   bore (14 mm), so its in-plane torsion from the bore out to the output holes (30 mm) is
   counted although the torque leaves at the holes. Holding the FE at 18 and 22 mm instead
   raises the ring stage to {rb['18.0']:.0f} and {rb['22.0']:.0f} (from {rb['14.0']:.0f});
   the closed-form annulus 14 -> 30 mm (two discs in parallel) is {ann:.5f} of our
   {1 / m0['ring_rigidity_Nm_per_arcmin']:.5f}. Free disc translation (the disc floats on its
   elastic eccentric bearing, the peer's centre is fixed) softens our mesh path further to
   {m0['mesh_in_drive_Nm_per_arcmin']:.0f} and moves the loaded zone (point 8). With 10 um
   both drop (ours {m1['ring_rigidity_Nm_per_arcmin']:.0f}, the peer
   {r1['ring_rigidity_Nm_per_arcmin']:.0f} resampled, {p1['ring_rigidity_Nm_per_arcmin']:.0f}
   as shipped, where its 2000-vertex polyline leaves ~1.6 pins: its docstring's artifact).
5. Eccentric bearing ({100 * s0['eccentric bearing']:.0f} % of ours): 14 rollers 4 x 8 mm,
   roller by roller (Palmgren on both raceways, zero play); the peer has no eccentric
   bearing in its stiffness at all (its disc centre is fixed on a rigid crank). Input
   bearings and input shaft bending (ours {100 * s0['input bearings']:.1f} % and
   {100 * s0['input shaft bending']:.1f} %): assumed tapered rollers and an assumed 17.6 mm
   shaft on a 32 mm span; not in the peer.
6. Input shaft torsion: ours {torsion:.0f}
   against the peer's {parts['input_shaft']:.0f} N m/arcmin, both referred to the output by
   29^2: ours twists the assumed 17.6 mm journal shaft over half its span (16 mm, eccentrics
   to the held end); the peer its default 10 mm input shaft over the stack plus two
   overhangs (stack_height + 2 shaft_overhang). The diameter alone is (17.6/10)^4 = 9.6x;
   in the peer this is {peer_torsion:.0f} % of the compliance, in ours
   {100 * s0['input shaft torsion']:.1f} %. Neither shaft is the case's (it gives none).
7. Backlash, 10 um: ours {m1['backlash_arcmin']:.4f} against {r1['backlash_arcmin']:.4f}
   resampled: both the rigid rotation that closes the first pin's clearance, input held;
   ours from the exact gaps at the FE's pins over the pitch (36 positions), the peer's the
   max over its 144 angles of its resampled gaps ({backlash_gap:+.2f} %).
   As shipped the peer gives 0: its polyline's ~10-20 um chord error swallows the 10 um.
   Lost motion +-3 %: the backlash plus the wind-up at 1.2 N m each way; ours
   ({m0['lost_motion_arcmin']:.3f} at 0 um) winds up more than the peer
   ({r0['lost_motion_arcmin']:.3f}) by its softer drive and its stiffening laws (Palmgren
   Q^0.9 contacts and bearings, the roller bearing's load zone): the 0-25 % segment is
   {m0['three_segments_Nm_per_arcmin'][0]:.1f} against {m0['three_segments_Nm_per_arcmin'][2]:.1f}
   at 50-100 %.
8. Pins in contact at rated torque, 0 um: ours {m0['pins_engaged']:.1f} (range
   {m0['pins_engaged_range'][0]}-{m0['pins_engaged_range'][1]}) against the peer's
   {r0['pins_engaged']:.1f} resampled ({p0['pins_engaged']:.1f} as shipped, its polyline).
   The peer's rigid disc on a fixed centre loads exactly the half of the pins whose arm
   resists (15 of 30). Ours with the eccentric rigid gives {m0['contact_only_pins_engaged']:.1f}
   (the FE disc and pins deform, the unmodified profile touches every pin at no load); the
   free disc translates on its eccentric bearing (up to
   {1e6 * m0['disc_translation_max_m']:.2f} um at the rated torque) and turns the loaded zone by a few
   pins, so 17-18 carry. At 10 um: ours {m1['pins_engaged']:.2f}, the peer
   {r1['pins_engaged']:.2f} resampled.
9. Ring-pin F_max: ours {m0['f_max_N']:.1f} N against the peer's gapped solve
   {r0['f_max_gapped_N']:.1f} (resampled) and its rigid share {p0['f_max_N']:.1f}
   (= 4 T_disc/(e Zb Za), the classical value). Ours is higher although more pins carry,
   and as high with the eccentric rigid ({m0['contact_only_f_max_N']:.1f} N on
   {m0['contact_only_pins_engaged']:.1f} pins, pitch 0): it is the FE's distribution, not the
   free disc: the FE's contact compliance differs from pin to pin (curvature, the disc's
   and the groove's local stiffness; which one dominates is not separated here), while the
   peer's equal linear springs give F ~ arm exactly. At 10 um:
   ours {m1['f_max_N']:.0f} N on ~5 pins, the peer {r1['f_max_gapped_N']:.0f} N on 4
   (resampled; {p1['f_max_gapped_N']:.0f} N on 1-2 as shipped, the polyline).
10. Output-pin forces: ours {m0['output_f_max_N']:.1f} N (0 um) and {m1['output_f_max_N']:.1f} N
   (10 um) against the peer's {r0['output_f_max_N']:.1f} N, the rigid share
   F_j = T_disc |h_j| / sum h^2 (= 4 T_disc / (n R_w) here) at the same worst angle (a pin on
   the eccentric's line). The same three pins carry
   ({', '.join(f'{x:.0f}' for x in sorted(m0['output_pin_forces_N'], reverse=True) if x > 0)}
   against {', '.join(f'{x:.0f}' for x in sorted(r0['output_pin_forces_N'], reverse=True) if x > 1e-6)}); ours
   adds the disc's translation along the eccentric's line (it moves every pin's gap alike,
   so the forces are no longer proportional to the arm), more with 10 um where the ring
   resultant and so the translation grow.
11. Eccentric bearing load: ours at most {m0['eccentric_bearing_load_max_N']:.0f} N (0 um),
   {m1['eccentric_bearing_load_max_N']:.0f} N (10 um); the peer's {r0['eccentric_bearing_load_N']:.0f} N
   from its rigid shares. With the eccentric rigid ours carries up to
   {m0['contact_only_eccentric_bearing_load_max_N']:.0f} N (0 um) and
   {m1['contact_only_eccentric_bearing_load_max_N']:.0f} N (10 um): the free disc moves to
   where ring pins, output pins and bearing balance elastically, which relieves the bearing.
"""
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--peer-python", default=str(PEER_PYTHON))
    ap.add_argument("--case", default=str(CASE_PATH))
    ap.add_argument("--out", default=str(OUT_PATH), help="the peer's results as JSON")
    ap.add_argument("--out-both", default=str(BOTH_PATH),
                    help="both results side by side as JSON")
    ap.add_argument("--positions", type=int, default=POSITIONS,
                    help=f"toothfem's positions per pin pitch (default {POSITIONS})")
    args = ap.parse_args(argv)
    if not Path(args.peer_python).exists():
        sys.exit(f"no peer environment at {args.peer_python}: create it as the module "
                 "docstring says")
    t0 = time.perf_counter()
    theirs = peer(args.peer_python, args.case)
    t_peer = time.perf_counter() - t0
    theirs["hand_check"] = check = hand_check(theirs)
    s = theirs["gearspec"]
    print(f"K-H-V drive ({Path(args.case).name}) at {s['output_torque_Nm']:g} N m; "
          f"cycloidgen {theirs['version']}")
    cols = [(f"{1e3 * c:g} um", theirs[str(c)]) for c in CLEARANCES_MM]
    cols += [(f"{1e3 * c:g} um resampled", theirs[str(c)]["resampled"])
             for c in CLEARANCES_MM]
    rows = [("drive rigidity [N m/arcmin]", "drive_rigidity_Nm_per_arcmin"),
            ("  secant 50-100 %", "drive_rigidity_secant_50_100_Nm_per_arcmin"),
            ("ring stage rigidity", "ring_rigidity_Nm_per_arcmin"),
            ("output stage rigidity (contacts)", "output_rigidity_Nm_per_arcmin"),
            ("structure rigidity", "structure_Nm_per_arcmin"),
            ("lost motion +-3 % [arcmin]", "lost_motion_arcmin"),
            ("backlash (peer's lost motion)", "backlash_arcmin"),
            ("pins engaged (mean, one disc)", "pins_engaged"),
            ("ring F_max rigid [N]", "f_max_N"),
            ("ring F_max gapped solve [N]", "f_max_gapped_N"),
            ("output-pin F_max [N]", "output_f_max_N")]
    print(f"  {'quantity':34s}" + "".join(f"{h:>18s}" for h, _ in cols))
    for label, key in rows:
        print(f"  {label:34s}" + "".join(f"{r[key]:18.4g}" for _, r in cols))
    print(f"  {'drive rigidity, 8 mm pin core':34s}" + "".join(
        f"{r['core_pin']['drive_rigidity_Nm_per_arcmin']:18.4g}" for _, r in cols))
    row = theirs[str(CLEARANCES_MM[0])]
    print("\nstructure parts [N m/arcmin]: " + ", ".join(
        f"{k} {v:.4g}" for k, v in row["structure_parts_Nm_per_arcmin"].items()))
    print(f"output-pin forces, one disc, crank {row['output_pin_forces_crank_deg']:.2f} "
          "deg [N]: " + ", ".join(f"{f:.1f}" for f in row["output_pin_forces_N"]))
    print(f"hand check (T_disc = {check['T_disc_Nm']:g} N m, 50/50): output pins "
          f"4T/(n R_w) = {check['output_f_max_classical_N']:.2f} N, peer "
          f"{check['output_f_max_peer_N']:.2f} N; ring 4T/(e Zb Za) = "
          f"{check['ring_f_max_classical_N']:.2f} N, peer {check['ring_f_max_peer_N']:.2f} N")
    for c in CLEARANCES_MM:
        print(f"peer checks at {1e3 * c:g} um: " + "; ".join(theirs[str(c)]["peer_checks"]))
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(theirs, indent=2))
    print(f"\nwritten {args.out} (peer: {t_peer:.1f} s)\n")

    t1 = time.perf_counter()
    mine = ours(args.case, args.positions)
    bores = bore_diagnostic(args.case)
    t_ours = time.perf_counter() - t1
    print(f"\ntoothfem (system model, {args.positions} positions per pitch, forces over "
          f"{FORCE_PITCHES} pitches): {t_ours:.1f} s\n")
    print(table(mine, theirs))
    print("\nour worst output-pin position: " + "; ".join(
        f"{1e3 * c:g} um: crank {mine[str(c)]['output_pin_forces_crank_deg']:.2f} deg, disc "
        f"{mine[str(c)]['output_pin_forces_disc']}: "
        + ", ".join(f"{f:.1f}" for f in mine[str(c)]["output_pin_forces_N"])
        for c in CLEARANCES_MM))
    print("ring stage vs the FE's held bore radius (diagnostic, 0 um): " + ", ".join(
        f"{b} mm: {v:.0f}" for b, v in bores["ring_rigidity_Nm_per_arcmin"].items())
        + " N m/arcmin")
    print(explanation(mine, theirs, bores))
    Path(args.out_both).write_text(json.dumps(
        {"case": str(Path(args.case).name), "toothfem": mine, "cycloidgen": theirs,
         "shares": shares(mine, theirs), "bore_diagnostic": bores,
         "seconds": {"peer": t_peer, "toothfem": t_ours}},
        indent=2, default=float))
    print(f"written {args.out_both}")


if __name__ == "__main__":
    main()
