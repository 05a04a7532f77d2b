#!/usr/bin/env python3
"""CalculiX (ccx) peer for the cycloid disc - pin contact of a K-H-V / RV stage.

One cycloid disc at the kinematically exact pose of each crank angle, frictionless contact
with the Zb pins, torque on the disc through a rigid coupling of its crank-hole edges to a
reference node at the disc centre (fixed in x, y; free to turn). Plane strain, modelled as
a thin slab of 8-node bricks (C3D8 by default; one element through the thickness, u_z = 0
everywhere), forces scaled to the case's face width. See README.md beside this file for what is modelled.

Usage (from the repository root, with the project's venv):

    .venv/bin/python benchmarks/calculix/run_peer.py \
        --case cases/cycloid_pinhousing.toml --positions 0,1/4,1/2,3/4 \
        --mesh-size-mm 0.008,0.004,0.002 --out benchmarks/calculix/results

``--positions``: crank angles as fractions of the meshing period 2*pi/Zb (the load pattern
repeats when the crank turns by one pin pitch; see README). ``--mesh-size-mm``: element
size at the contact points (default 0.002 mm); a comma list runs a refinement study in
which the profile and body sizes scale with it.

Large files (.inp, .dat, .frd, meshes) go to ``--work`` (default /tmp/toothfem_ccx).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
if str(REPO) not in sys.path:          # run from a checkout without installing
    sys.path.insert(0, str(REPO))

# ---------------------------------------------------------------------------------------
# ccx installation


def ensure_ccx() -> str:
    """Path of the ccx executable; installs Debian's calculix-ccx when it is missing."""
    exe = shutil.which("ccx")
    if exe:
        return exe
    if shutil.which("apt-get") is None:
        sys.exit("ccx is not on PATH and apt-get is not available: install CalculiX ccx "
                 "(Debian/Ubuntu package calculix-ccx) and rerun")
    print("ccx not found: running apt-get install -y calculix-ccx", flush=True)
    sudo = [] if os.geteuid() == 0 else ["sudo"]
    env = dict(os.environ, DEBIAN_FRONTEND="noninteractive")
    subprocess.run(sudo + ["apt-get", "update"], check=True, env=env)
    subprocess.run(sudo + ["apt-get", "install", "-y", "calculix-ccx"], check=True, env=env)
    exe = shutil.which("ccx")
    if not exe:
        sys.exit("calculix-ccx installed but ccx is still not on PATH")
    return exe


def ccx_version(exe: str) -> str:
    try:
        out = subprocess.run([exe, "-v"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.TimeoutExpired):
        return "unknown"
    m = re.search(r"[Vv]ersion\s+([0-9][0-9.]*)", out)
    return m.group(1) if m else out.strip()[:60]


# ---------------------------------------------------------------------------------------
# Problem definition


@dataclass
class Problem:
    """Everything the deck needs, in mm, N, MPa (consistent units for ccx)."""
    name: str
    zb: int
    za: int
    rz_circle: float        # Rz, mm
    ecc: float              # A, mm
    r_pin: float            # rz, mm
    face_width: float       # b, mm
    E: float                # MPa
    nu: float
    torque_Nmm: float       # M_a on one disc, N mm
    geom: object            # CycloidGeometry (SI)
    holes: object           # DiscHolesSI (SI)
    crank_holes: list       # [(x, y, r)] disc frame, mm


def problem_from_case(path) -> Problem:
    from toothfem import load_case
    case = load_case(path)
    if case.drive != "cycloid" or case.cycloid is None:
        sys.exit(f"{path}: the ccx peer models cycloid drives only (drive = {case.drive!r})")
    cy = case.cycloid
    geom = cy.geometry()
    if geom.modified:
        # the contact pattern would still be found by ccx, but the pose/refinement points
        # below are those of the conjugate profile; keep the peer to what it was checked on
        print("warning: profile modifications are present; refinement is placed at the "
              "conjugate contact points", file=sys.stderr)
    holes = cy.holes_si()
    if case.operating.output_torque_Nm is None:
        sys.exit(f"{path}: operating.output_torque_Nm is required (torque on the disc)")
    torque = cy.disc_load_factor * case.operating.output_torque_Nm / cy.disc_count
    crank = [(x * 1e3, y * 1e3, r * 1e3) for x, y, r, lab in holes.circles()
             if lab.startswith("crank")]
    if not crank:
        sys.exit(f"{path}: the disc has no crank holes to hold it by "
                 "(cycloid.disc_holes.crank_hole_count = 0)")
    return Problem(name=case.name, zb=cy.pin_count, za=cy.lobe_count,
                   rz_circle=cy.pin_circle_radius_mm, ecc=cy.eccentricity_mm,
                   r_pin=cy.pin_radius_mm, face_width=cy.face_width_mm,
                   E=case.material.youngs_modulus_GPa * 1e3, nu=case.material.poisson_ratio,
                   torque_Nmm=torque * 1e3, geom=geom, holes=holes, crank_holes=crank)


@dataclass
class Options:
    mesh_size: float = 0.002          # h_c: element size at the contact points, mm
    far_size: float = 1.0             # interior size, mm (default 500 h_c)
    edge_size: float = 0.125          # size along the working profile away from contacts
                                      # (default 62.5 h_c)
    refine_radius: float = 0.03       # radius of the uniform h_c zone, mm (>= 1.5 x the
                                      # Hertz half-width, about 0.016 mm at 240 N)
    grading: float = 0.2              # size growth per unit distance outside that zone
    unloaded_size: float = 0.02       # size at the contact points of pins on the unloaded
                                      # side (moment arm > 0; they separate under load)
    slab: float = 0.1                 # slab thickness, mm (results scaled to face width)
    stiffness_factor: float = 100.0   # contact slope K = factor * E / h_c
    points_per_lobe: int = 160        # spline points per lobe of the outer profile
    threads: int = 2
    preturn: float = 2e-6             # rad, disc rotation prescribed in step 1
    support: str = "crank"            # holes whose edges form the rigid coupling:
                                      # "crank" (hardware) or "centre_bore" (a check)
    element: str = "C3D8"             # disc brick: C3D8 or C3D8I (incompatible modes;
                                      # same pin forces within 0.2 %, twice the time)
    timeout: float = 1800.0
    keep: bool = True


# ---------------------------------------------------------------------------------------
# Mesh (gmsh, 2D quads) -> slab of C3D8I


@dataclass
class Mesh2D:
    xy: np.ndarray                    # (N, 2) mm, housing frame
    disc_quads: np.ndarray            # (Q, 4) 0-based, counter-clockwise
    disc_tris: np.ndarray             # (T, 3)
    pin_quads: list                   # per pin (Qj, 4)
    pin_tris: list                    # per pin (Tj, 3)
    profile_edges: np.ndarray         # (Ep, 2) node pairs on the working profile
    pin_edges: list                   # per pin (Ej, 2)
    crank_nodes: np.ndarray           # nodes on the crank-hole edges
    profile_nodes: np.ndarray
    pin_nodes: list                   # per pin: all nodes of the pin
    stats: dict = field(default_factory=dict)


def _rot(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


def _ccw(conn, xy):
    """Reorder elements to counter-clockwise (positive signed area)."""
    if conn.size == 0:
        return conn
    p = xy[conn]                                  # (E, k, 2)
    x, y = p[..., 0], p[..., 1]
    area = 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)
    out = conn.copy()
    out[area < 0] = out[area < 0][:, ::-1]
    return out


def build_mesh(pb: Problem, phi: float, opt: Options, msh_path: Path | None = None) -> Mesh2D:
    import gmsh
    from toothfem.geometry import cycloid, cycloid_distance, cycloid_mesh

    geom = pb.geom
    g = geom.generating()
    centre_m, theta = cycloid_mesh.disc_pose(geom, phi)
    oc = centre_m[:, 0] * 1e3                       # disc centre, mm
    rot = _rot(float(theta[0]))
    def to_h(pts):
        return (rot @ pts).T + oc           # disc frame (2, n) mm -> (n, 2) housing

    state = cycloid_mesh.meshing(geom, phi)
    kpts = state.point[0] * 1e3                      # (Zb, 2) contact points, housing, mm
    pins = cycloid_mesh.pin_centres(geom).T * 1e3         # (Zb, 2)

    hc = opt.mesh_size
    r_in = max(opt.refine_radius, 3 * hc)
    # pins whose conjugate normal gives a torque against the applied one (moment arm < 0,
    # 0 < theta_b < pi) are the candidates to carry load; the pins on the line of centres
    # (arm ~ 0) are refined too. The others are meshed coarser: contact may still occur
    # there (it is not excluded), it is only less resolved.
    arm = state.moment_arm[0] * 1e3
    fine = arm <= 0.05 * pb.r_pin
    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.model.add("disc")
        occ = gmsh.model.occ
        # outer working profile: one interpolating spline per lobe, junctions at the roots
        za, m = pb.za, opt.points_per_lobe
        psi_root = 0.0                               # w(0) is a tooth root (radius Rz-A-rz)
        lobe_curves, first_pt, prev_pt = [], None, None
        for k in range(za):
            psi = psi_root + 2 * math.pi * (k + np.linspace(0.0, 1.0, m + 1)) / za
            pts = to_h(cycloid.working_profile(g, psi) * 1e3)
            tags = []
            for i, (x, y) in enumerate(pts):
                if i == 0 and prev_pt is not None:
                    tags.append(prev_pt)
                elif k == za - 1 and i == m:
                    tags.append(first_pt)
                else:
                    tags.append(occ.addPoint(x, y, 0.0))
            first_pt = first_pt or tags[0]
            prev_pt = tags[-1]
            lobe_curves.append(occ.addSpline(tags))
        outer_loop = occ.addCurveLoop(lobe_curves)
        hole_loops, crank_curves = [], []
        for x, y, r, lab in pb.holes.circles():
            cx, cy_ = to_h(np.array([[x], [y]]) * 1e3)[0]
            c = occ.addCircle(cx, cy_, 0.0, r * 1e3)
            hole_loops.append(occ.addCurveLoop([c]))
            if lab.startswith(opt.support):
                crank_curves.append(c)
        disc = occ.addPlaneSurface([outer_loop] + hole_loops)
        pin_surfs, pin_curves = [], []
        for cx, cy_ in pins:
            c = occ.addCircle(cx, cy_, 0.0, pb.r_pin)
            pin_curves.append(c)
            pin_surfs.append(occ.addPlaneSurface([occ.addCurveLoop([c])]))
        kp_tags = [occ.addPoint(x, y, 0.0) for x, y in kpts]
        occ.synchronize()

        fld = gmsh.model.mesh.field
        spots = []
        for sel, h0 in ((fine, hc), (~fine, max(opt.unloaded_size, hc))):
            if not np.any(sel):
                continue
            f_d = fld.add("Distance")
            fld.setNumbers(f_d, "PointsList", [t for t, s_ in zip(kp_tags, sel) if s_])
            f_t = fld.add("Threshold")
            fld.setNumber(f_t, "InField", f_d)
            fld.setNumber(f_t, "SizeMin", h0)
            fld.setNumber(f_t, "SizeMax", opt.far_size)
            fld.setNumber(f_t, "DistMin", r_in if sel is fine else 0.0)
            fld.setNumber(f_t, "DistMax", (r_in if sel is fine else 0.0)
                          + (opt.far_size - h0) / opt.grading)
            spots.append(f_t)
        f_e = fld.add("Distance")
        fld.setNumbers(f_e, "CurvesList", lobe_curves)
        fld.setNumber(f_e, "Sampling", 4 * m)
        f_et = fld.add("Threshold")
        fld.setNumber(f_et, "InField", f_e)
        fld.setNumber(f_et, "SizeMin", opt.edge_size)
        fld.setNumber(f_et, "SizeMax", opt.far_size)
        fld.setNumber(f_et, "DistMin", 0.0)
        fld.setNumber(f_et, "DistMax", 4 * opt.far_size)
        f_min = fld.add("Min")
        fld.setNumbers(f_min, "FieldsList", spots + [f_et])
        fld.setAsBackgroundMesh(f_min)
        for k, v in {"Mesh.MeshSizeFromPoints": 0, "Mesh.MeshSizeFromCurvature": 0,
                     "Mesh.MeshSizeExtendFromBoundary": 0, "Mesh.Algorithm": 8,
                     "Mesh.RecombineAll": 1, "Mesh.RecombinationAlgorithm": 1,
                     "Mesh.ElementOrder": 1, "Mesh.Smoothing": 2}.items():
            gmsh.option.setNumber(k, v)
        t0 = time.perf_counter()
        gmsh.model.mesh.generate(2)
        t_mesh = time.perf_counter() - t0
        if msh_path is not None:
            gmsh.write(str(msh_path))

        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
        index[tags.astype(np.int64)] = np.arange(tags.size)
        xy = coords.reshape(-1, 3)[:, :2].copy()

        def surf_elems(s):
            types, _, nodes = gmsh.model.mesh.getElements(2, s)
            quads = np.zeros((0, 4), np.int64)
            tris = np.zeros((0, 3), np.int64)
            for t, nn in zip(types, nodes):
                nn = index[np.asarray(nn, np.int64)]
                if t == 3:
                    quads = nn.reshape(-1, 4)
                elif t == 2:
                    tris = nn.reshape(-1, 3)
                else:
                    raise RuntimeError(f"unexpected gmsh element type {t}")
            return _ccw(quads, xy), _ccw(tris, xy)

        def curve_edges(curves):
            out = []
            for c in curves:
                types, _, nodes = gmsh.model.mesh.getElements(1, c)
                for _t, nn in zip(types, nodes):
                    out.append(index[np.asarray(nn, np.int64)].reshape(-1, 2))
            return np.concatenate(out) if out else np.zeros((0, 2), np.int64)

        dq, dt = surf_elems(disc)
        pq, pt = zip(*[surf_elems(s) for s in pin_surfs])
        prof_edges = curve_edges(lobe_curves)
        pin_edges = [curve_edges([c]) for c in pin_curves]
        crank_nodes = np.unique(curve_edges(crank_curves))
    finally:
        gmsh.finalize()

    used = np.unique(np.concatenate([dq.ravel(), dt.ravel()]
                                    + [q.ravel() for q in pq] + [t.ravel() for t in pt]))
    # drop gmsh nodes that belong to no element (the refinement marker points)
    keep = np.full(xy.shape[0], -1, np.int64)
    keep[used] = np.arange(used.size)
    xy = xy[used]
    def rn(a):
        return keep[a]
    dq, dt = rn(dq), rn(dt)
    pq = [rn(q) for q in pq]
    pt = [rn(t) for t in pt]
    prof_edges = rn(prof_edges)
    pin_edges = [rn(e) for e in pin_edges]
    crank_nodes = rn(crank_nodes)

    # Put the boundary nodes exactly on the analytical curves (the splines are within
    # ~1e-7 mm already; this removes even that from the initial contact gaps).
    prof_nodes = np.unique(prof_edges)
    local = rot.T @ (xy[prof_nodes] - oc).T * 1e-3             # disc frame, m
    psi0 = np.mod(np.arctan2(local[1], local[0]), 2 * math.pi)
    # polish the polar-angle guess on a dense sample before Newton
    dense = np.linspace(0, 2 * math.pi, 200 * za, endpoint=False)
    wd = cycloid.working_profile(g, dense)
    j = np.searchsorted(dense, psi0)
    cand = (j[:, None] + np.arange(-60, 61)[None, :]) % dense.size
    d2 = (wd[0][cand] - local[0][:, None]) ** 2 + (wd[1][cand] - local[1][:, None]) ** 2
    psi0 = dense[cand[np.arange(cand.shape[0]), np.argmin(d2, axis=1)]]
    psi, dist = cycloid_distance.foot_point(g, local, psi0)
    move_prof = float(np.max(np.abs(dist))) * 1e3
    xy[prof_nodes] = to_h(cycloid.working_profile(g, psi) * 1e3)
    move_pin = 0.0
    pin_nodes_all = []
    for jpin, e in enumerate(pin_edges):
        nodes = np.unique(e)
        d = xy[nodes] - pins[jpin]
        r = np.hypot(d[:, 0], d[:, 1])
        move_pin = max(move_pin, float(np.max(np.abs(r - pb.r_pin))))
        xy[nodes] = pins[jpin] + d * (pb.r_pin / r)[:, None]
        pin_nodes_all.append(np.unique(np.concatenate([pq[jpin].ravel(), pt[jpin].ravel()])))

    # edge length along the profile at each contact point (the achieved h_c)
    mid = 0.5 * (xy[prof_edges[:, 0]] + xy[prof_edges[:, 1]])
    lens = np.hypot(*(xy[prof_edges[:, 0]] - xy[prof_edges[:, 1]]).T)
    dk = np.hypot(mid[:, 0][:, None] - kpts[:, 0][None], mid[:, 1][:, None] - kpts[:, 1][None])
    near = np.argmin(dk, axis=0)
    stats = dict(nodes_2d=int(xy.shape[0]), disc_quads=int(dq.shape[0]),
                 disc_tris=int(dt.shape[0]),
                 pin_quads=int(sum(q.shape[0] for q in pq)),
                 pin_tris=int(sum(t.shape[0] for t in pt)),
                 profile_edges=int(prof_edges.shape[0]),
                 contact_edge_mm_min=float(lens[near].min()),
                 contact_edge_mm_max=float(lens[near].max()),
                 profile_projection_mm=move_prof, pin_projection_mm=move_pin,
                 gmsh_seconds=t_mesh)
    return Mesh2D(xy=xy, disc_quads=dq, disc_tris=dt, pin_quads=list(pq), pin_tris=list(pt),
                  profile_edges=prof_edges, pin_edges=pin_edges, crank_nodes=crank_nodes,
                  profile_nodes=prof_nodes, pin_nodes=pin_nodes_all, stats=stats)


# ---------------------------------------------------------------------------------------
# Input deck


_HEX_FACE = {(0, 1): "S3", (1, 2): "S4", (2, 3): "S5", (3, 0): "S6"}
_WEDGE_FACE = {(0, 1): "S3", (1, 2): "S4", (2, 0): "S5"}


def _lines(ids, per=8):
    ids = [i if isinstance(i, str) else str(int(i)) for i in ids]
    return "\n".join(", ".join(ids[i:i + per]) for i in range(0, len(ids), per))


@dataclass
class Deck:
    text: str
    ref_node: int
    rot_node: int
    node_xy: np.ndarray               # 2D coordinates by 2D node index
    n2d: int
    scale: float                      # slab -> face width force factor
    contact_k: float
    n_elements: int
    zb: int


def write_deck(pb: Problem, mesh: Mesh2D, phi: float, opt: Options) -> Deck:
    from toothfem.geometry import cycloid_mesh
    xy = mesh.xy
    n = xy.shape[0]
    t = opt.slab
    def nid(i, top=False):
        return i + 1 + (n if top else 0)       # 1-based 3D node ids
    out = ["*HEADING", f"toothfem ccx peer: {pb.name}, crank angle {math.degrees(phi):.6f} deg",
           "** units: mm, N, MPa. Plane strain slab of thickness "
           f"{t} mm; forces scale by {pb.face_width / t:g} to the face width.",
           "*NODE"]
    for i, (x, y) in enumerate(xy):
        out.append(f"{nid(i)}, {x:.12g}, {y:.12g}, 0")
    for i, (x, y) in enumerate(xy):
        out.append(f"{nid(i, True)}, {x:.12g}, {y:.12g}, {t:.12g}")
    centre_m, _ = cycloid_mesh.disc_pose(pb.geom, phi)
    oc = centre_m[:, 0] * 1e3
    ref, rotn = 2 * n + 1, 2 * n + 2
    out += [f"{ref}, {oc[0]:.12g}, {oc[1]:.12g}, {t / 2:.12g}", f"{rotn}, 0, 0, 0"]

    eid = 0
    face_of = {}                                   # sorted 2D edge -> (eid, face label)

    def add_elems(conn, etype, elset, faces):
        nonlocal eid
        if conn.shape[0] == 0:
            return
        out.append(f"*ELEMENT, TYPE={etype}, ELSET={elset}")
        k = conn.shape[1]
        for row in conn:
            eid += 1
            ids = [nid(a) for a in row] + [nid(a, True) for a in row]
            out.append(f"{eid}, " + ", ".join(map(str, ids)))
            for a in range(k):
                b = (a + 1) % k
                face_of[(min(row[a], row[b]), max(row[a], row[b]))] = (
                    eid, faces[(a, b)])

    add_elems(mesh.disc_quads, opt.element, "DISC", _HEX_FACE)
    add_elems(mesh.disc_tris, "C3D6", "DISC", _WEDGE_FACE)
    for j in range(pb.zb):
        add_elems(mesh.pin_quads[j], "C3D8", f"PIN{j}", _HEX_FACE)
        add_elems(mesh.pin_tris[j], "C3D6", f"PIN{j}", _WEDGE_FACE)
    out.append("*ELSET, ELSET=PINS")
    out.append(_lines([f"PIN{j}" for j in range(pb.zb)]))

    def surface(name, edges):
        out.append(f"*SURFACE, NAME={name}, TYPE=ELEMENT")
        for a, b in edges:
            e, f = face_of[(min(a, b), max(a, b))]
            out.append(f"{e}, {f}")

    surface("SDISC", mesh.profile_edges)
    surface("SPINS", np.concatenate(mesh.pin_edges))

    crank = np.concatenate([[nid(i) for i in mesh.crank_nodes],
                            [nid(i, True) for i in mesh.crank_nodes]])
    out += ["*NSET, NSET=CRANK", _lines(crank)]
    disc_nodes = np.unique(np.concatenate([mesh.disc_quads.ravel(), mesh.disc_tris.ravel()]))
    free_z = np.setdiff1d(disc_nodes, mesh.crank_nodes)
    out += ["*NSET, NSET=DISCZ", _lines([nid(i) for i in free_z] + [nid(i, True) for i in free_z])]
    for j in range(pb.zb):
        pn = mesh.pin_nodes[j]
        out += [f"*NSET, NSET=NPIN{j}", _lines([nid(i) for i in pn] + [nid(i, True) for i in pn])]
    out += [f"*NSET, NSET=NREF\n{ref}", f"*NSET, NSET=NROT\n{rotn}"]

    out += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{pb.E:.9g}, {pb.nu:.9g}",
            "*SOLID SECTION, ELSET=DISC, MATERIAL=STEEL",
            "*SOLID SECTION, ELSET=PINS, MATERIAL=STEEL",
            f"*RIGID BODY, NSET=CRANK, REF NODE={ref}, ROT NODE={rotn}"]
    k_contact = opt.stiffness_factor * pb.E / opt.mesh_size      # MPa/mm
    out += ["*SURFACE INTERACTION, NAME=FRICTIONLESS",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            f"{k_contact:.6g}, 0.01",
            "*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=NODE TO SURFACE",
            "SDISC, SPINS",
            "*BOUNDARY"]
    fixed = [f"NPIN{j}, 1, 3" for j in range(pb.zb)] + ["DISCZ, 3, 3", "NREF, 1, 3",
                                                         "NROT, 1, 2"]
    # Step 1 turns the disc by a small prescribed angle so that contact is established on
    # the loaded side (with the exact conjugate pose every pin touches at zero clearance,
    # and a torque applied to a disc without active contact springs has no stiffness
    # against rotation). Step 2 frees the rotation and applies the torque.
    out += fixed + ["NROT, 3, 3, 0"]
    m_slab = pb.torque_Nmm * t / pb.face_width
    out += ["*STEP, INC=100", "*STATIC", "1.0, 1.0, 1e-6, 1.0",
            "*BOUNDARY", f"NROT, 3, 3, {opt.preturn:.6g}", "*END STEP",
            "*STEP, INC=200", "*STATIC", "0.5, 1.0, 1e-6, 1.0",
            "*BOUNDARY, OP=NEW"] + fixed + [
            "*CLOAD", f"NROT, 3, {m_slab:.9g}"]
    for j in range(pb.zb):
        out += [f"*NODE PRINT, NSET=NPIN{j}, TOTALS=ONLY", "RF"]
    out += ["*NODE PRINT, NSET=NREF", "U, RF", "*NODE PRINT, NSET=NROT", "U",
            "*CONTACT PRINT", "CSTR, CDIS",
            "*END STEP"]
    return Deck(text="\n".join(out) + "\n", ref_node=ref, rot_node=rotn, node_xy=xy, n2d=n,
                scale=pb.face_width / t, contact_k=k_contact, n_elements=eid, zb=pb.zb)


# ---------------------------------------------------------------------------------------
# Run and read back


_FLOAT = r"[-+]?\d*\.?\d+(?:[EeDd][-+]?\d+)?"


def _f(s):
    return float(s.replace("D", "E").replace("d", "e"))


def parse_dat(text: str, zb: int) -> dict:
    """Last-increment totals per pin set, reference-node results and contact stresses."""
    blocks = re.split(r"\n(?=\s*(?:forces|displacements|contact|relative|total))", text)
    totals, ref_u, rot_u, cstr = {}, None, None, {}
    for blk in blocks:
        head = blk.strip().split("\n", 1)[0].lower()
        m = re.match(r"forces \(fx,fy,fz\) for set (\S+) and time", head)
        if m:
            name = m.group(1).upper()
            tm = re.search(r"total force \(fx,fy,fz\) for set \S+ and time\s*" + _FLOAT
                           + r"\s*\n\s*(" + _FLOAT + r")\s+(" + _FLOAT + r")\s+(" + _FLOAT + ")",
                           blk, re.I)
            if tm:
                totals[name] = np.array([_f(tm.group(i)) for i in (1, 2, 3)])
            continue
        m = re.match(r"total force \(fx,fy,fz\) for set (\S+) and time", head)
        if m:
            name = m.group(1).upper()
            nums = re.findall(_FLOAT, blk.split("\n", 1)[1] if "\n" in blk else "")
            if len(nums) >= 3:
                totals[name] = np.array([_f(v) for v in nums[:3]])
            continue
        m = re.match(r"displacements \(vx,vy,vz\) for set (\S+) and time", head)
        if m:
            rows = re.findall(r"^\s*(\d+)\s+(" + _FLOAT + r")\s+(" + _FLOAT + r")\s+("
                              + _FLOAT + r")\s*$", blk, re.M)
            if rows:
                v = np.array([_f(x) for x in rows[-1][1:]])
                if m.group(1).upper() == "NREF":
                    ref_u = v
                elif m.group(1).upper() == "NROT":
                    rot_u = v
            continue
        if head.startswith("contact stress"):
            cstr = {}
            for row in re.findall(r"^\s*(\d+)\s+(" + _FLOAT + r")\s+(" + _FLOAT + r")\s+("
                                  + _FLOAT + r")\s*$", blk, re.M):
                cstr[int(row[0])] = _f(row[1])
    forces = np.array([totals.get(f"NPIN{j}", np.full(3, np.nan)) for j in range(zb)])
    return dict(pin_rf=forces, ref_u=ref_u, rot_u=rot_u, cstr=cstr)


def run_ccx(exe: str, deck: Deck, work: Path, job: str, opt: Options) -> tuple[dict, float, str]:
    work.mkdir(parents=True, exist_ok=True)
    (work / f"{job}.inp").write_text(deck.text)
    env = dict(os.environ, OMP_NUM_THREADS=str(opt.threads),
               CCX_NPROC_STIFFNESS=str(opt.threads), CCX_NPROC_EQUATION_SOLVER=str(opt.threads),
               CCX_NPROC_RESULTS=str(opt.threads))
    t0 = time.perf_counter()
    with open(work / f"{job}.log", "w") as log:
        proc = subprocess.run([exe, "-i", job], cwd=work, stdout=log, stderr=subprocess.STDOUT,
                              env=env, timeout=opt.timeout)
    wall = time.perf_counter() - t0
    logtext = (work / f"{job}.log").read_text(errors="replace")
    dat = work / f"{job}.dat"
    if proc.returncode != 0 or not dat.exists() or "*ERROR" in logtext:
        tail = "\n".join(logtext.strip().splitlines()[-25:])
        raise RuntimeError(f"ccx failed (exit {proc.returncode}) on {work / job}.inp:\n{tail}")
    return parse_dat(dat.read_text(errors="replace"), deck.zb), wall, logtext


# ---------------------------------------------------------------------------------------
# One position


def seed_distribution(pb: Problem, phi: float):
    """Seed's rigid-body sharing: P_i = P_max l_i / r_a on the pins with 0 < theta_b < pi,
    P_max = 4 M_a / (r_a Zb). Returns (P (Zb,), theta_b (Zb,), loaded mask)."""
    from toothfem.geometry import cycloid_mesh
    geom = pb.geom
    theta_b = np.mod(2 * math.pi * np.arange(pb.zb) / pb.zb - phi, 2 * math.pi)
    loaded = np.sin(theta_b) > 1e-12
    r_a = geom.disc_pitch_radius_m
    l = np.abs(cycloid_mesh.seed_moment_arm(geom, theta_b))
    p_max = 4 * pb.torque_Nmm * 1e-3 / (r_a * pb.zb)
    return np.where(loaded, p_max * l / r_a, 0.0), theta_b, loaded, p_max


def run_position(pb: Problem, frac: Fraction, opt: Options, exe: str, work: Path) -> dict:
    from toothfem.geometry import cycloid_mesh
    phi = float(frac) * 2 * math.pi / pb.zb
    tag = f"phi{float(frac):.4f}_h{opt.mesh_size:g}".replace(".", "p")
    wdir = work / tag
    wdir.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    mesh = build_mesh(pb, phi, opt, wdir / "mesh.msh" if opt.keep else None)
    deck = write_deck(pb, mesh, phi, opt)
    t_prep = time.perf_counter() - t0
    res, wall, log = run_ccx(exe, deck, wdir, "disc", opt)

    if np.isnan(res["pin_rf"]).any() or not res["cstr"]:
        raise RuntimeError(f"could not read pin forces / contact stresses from {wdir}/disc.dat")
    state = cycloid_mesh.meshing(pb.geom, phi)
    normal = state.normal[0]                          # (Zb, 2) pin -> disc
    kpts = state.point[0] * 1e3
    rf = res["pin_rf"][:, :2] * deck.scale            # reaction on the fixed pin nodes
    force_on_disc = rf                                # support reaction = force disc <- pin
    fmag = np.hypot(rf[:, 0], rf[:, 1])
    fn = np.sum(force_on_disc * normal, axis=1)       # along the conjugate normal
    # contact pressures: slave nodes (both slab faces) -> nearest pin
    cs = res["cstr"]
    pmax_pin = np.zeros(pb.zb)
    nact = np.zeros(pb.zb, int)
    if cs:
        ids = np.array(list(cs.keys())) - 1
        press = np.array(list(cs.values()))
        nodes2d = ids % deck.n2d
        pts = deck.node_xy[nodes2d]
        d = np.hypot(pts[:, 0][:, None] - kpts[:, 0][None], pts[:, 1][:, None] - kpts[:, 1][None])
        owner = np.argmin(d, axis=1)
        for j in range(pb.zb):
            sel = (owner == j) & (press > 0)
            if np.any(sel):
                pmax_pin[j] = press[sel].max()
                nact[j] = int(np.unique(nodes2d[sel]).size)
    fmax = float(np.nanmax(fmag))
    in_contact = (nact > 0) & (fmag > 1e-3 * fmax)
    # Hertz line contact with the FE force (rigid pin: E* = E/(1-nu^2); disc curvature
    # radius from the conjugate geometry)
    r_eq = np.abs(state.equivalent_radius[0]) * 1e3
    e_star = pb.E / (1 - pb.nu**2)
    p_hertz = np.sqrt(np.maximum(fn, 0) / pb.face_width * e_star / (math.pi * r_eq))
    seed, theta_b, loaded, seed_pmax = seed_distribution(pb, phi)
    # moment balance check: sum of pin moments about the disc centre vs applied torque
    oc = state.centre[0] * 1e3
    rel = kpts - oc
    m_pins = float(np.sum(rel[:, 0] * force_on_disc[:, 1] - rel[:, 1] * force_on_disc[:, 0]))
    if abs(-m_pins * 1e-3 - pb.torque_Nmm * 1e-3) > 0.01 * pb.torque_Nmm * 1e-3:
        print(f"warning: the pin forces' moment {-m_pins * 1e-3:.4g} N m differs from the "
              f"applied torque {pb.torque_Nmm * 1e-3:.4g} N m by more than 1 %",
              file=sys.stderr)
    rot_z = float(res["rot_u"][2]) if res["rot_u"] is not None else float("nan")
    iters = len(re.findall(r"iteration\s+\d+", log))
    neq = re.search(r"number of equations\s*\n\s*(\d+)", log)
    incs = len(re.findall(r"increment\s+\d+\s+attempt", log))
    pins = []
    for j in range(pb.zb):
        pins.append(dict(pin=j, theta_b_deg=math.degrees(theta_b[j]),
                         moment_arm_mm=float(state.moment_arm[0, j] * 1e3),
                         force_N=float(fmag[j]), fx_N=float(force_on_disc[j, 0]),
                         fy_N=float(force_on_disc[j, 1]), normal_force_N=float(fn[j]),
                         active_slave_nodes=int(nact[j]), in_contact=bool(in_contact[j]),
                         max_pressure_MPa=float(pmax_pin[j]),
                         hertz_p0_MPa=float(p_hertz[j]), seed_force_N=float(seed[j])))
    return dict(
        position_fraction_of_pitch=str(frac), crank_angle_deg=math.degrees(phi),
        disc_rotation_deg=math.degrees(-phi / pb.za),
        pins_in_contact=int(in_contact.sum()),
        max_pin_force_N=fmax, max_force_pin=int(np.nanargmax(fmag)),
        max_pressure_MPa=float(pmax_pin.max()), max_pressure_pin=int(np.argmax(pmax_pin)),
        max_hertz_p0_MPa=float(p_hertz.max()),
        seed_pins_loaded=int(loaded.sum()), seed_max_pin_force_N=float(seed.max()),
        seed_P_max_N=float(seed_pmax),
        pin_moment_Nm=-m_pins * 1e-3, applied_torque_Nm=pb.torque_Nmm * 1e-3,
        disc_rotation_under_load_urad=rot_z * 1e6,
        ccx_wall_s=wall, prep_s=t_prep, ccx_iterations=iters, ccx_increments=incs,
        ccx_equations=int(neq.group(1)) if neq else None,
        mesh_size_mm=opt.mesh_size, contact_stiffness_MPa_per_mm=deck.contact_k,
        elements_3d=deck.n_elements, nodes_3d=2 * deck.n2d + 2, mesh=mesh.stats,
        work_dir=str(wdir), pins=pins)


# ---------------------------------------------------------------------------------------
# CLI


def parse_positions(s: str) -> list[Fraction]:
    out = []
    for tok in s.split(","):
        tok = tok.strip()
        if tok:
            out.append(Fraction(tok).limit_denominator(10000))
    if not out:
        raise argparse.ArgumentTypeError("no positions given")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default=str(REPO / "cases" / "cycloid_pinhousing.toml"))
    ap.add_argument("--positions", type=parse_positions, default=parse_positions("0,1/4,1/2,3/4"),
                    help="crank angles as fractions of the meshing period 2*pi/Zb "
                         "(comma list, e.g. 0,1/3,2/3 or 0.5)")
    ap.add_argument("--mesh-size-mm", default="0.002",
                    help="element size at the contact points in mm; a comma list runs a "
                         "refinement study (coarse to fine)")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"))
    ap.add_argument("--work", default="/tmp/toothfem_ccx",
                    help="folder for decks, meshes and ccx output (large files)")
    ap.add_argument("--stiffness-factor", type=float, default=Options.stiffness_factor,
                    help="contact slope K = factor * E / h_c (default %(default)s)")
    ap.add_argument("--slab-mm", type=float, default=Options.slab,
                    help="thickness of the plane-strain slab (results are scaled to the "
                         "case's face width)")
    ap.add_argument("--edge-size-mm", type=float, default=None,
                    help="element size along the working profile away from the contacts "
                         "(default 62.5 x the contact size)")
    ap.add_argument("--far-size-mm", type=float, default=None,
                    help="element size in the disc body (default 500 x the contact size)")
    ap.add_argument("--element", choices=("C3D8I", "C3D8"), default=Options.element,
                    help="disc brick type (C3D8I: incompatible modes, no shear locking, "
                         "about 3x the equations; default %(default)s)")
    ap.add_argument("--support", choices=("crank", "centre_bore"), default=Options.support,
                    help="holes whose edges are tied to the reference node at the disc "
                         "centre (default %(default)s: the crank-bearing holes)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args(argv)

    pb = problem_from_case(args.case)
    exe = ensure_ccx()
    version = ccx_version(exe)
    sizes = [float(s) for s in args.mesh_size_mm.split(",") if s.strip()]
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    work = Path(args.work)
    runs = []
    for h in sizes:
        opt = Options(mesh_size=h, slab=args.slab_mm, stiffness_factor=args.stiffness_factor,
                      edge_size=args.edge_size_mm or 62.5 * h,
                      far_size=args.far_size_mm or 500 * h,
                      threads=args.threads, element=args.element, support=args.support)
        for frac in args.positions:
            print(f"position {frac} of the pin pitch, h_c = {h} mm ...", flush=True)
            r = run_position(pb, frac, opt, exe, work)
            print(f"  pins in contact {r['pins_in_contact']}, max pin force "
                  f"{r['max_pin_force_N']:.2f} N (pin {r['max_force_pin']}), max pressure "
                  f"{r['max_pressure_MPa']:.1f} MPa (Hertz {r['max_hertz_p0_MPa']:.1f}), "
                  f"torque check {r['pin_moment_Nm']:.3f}/{r['applied_torque_Nm']:.3f} N m, "
                  f"ccx {r['ccx_wall_s']:.1f} s, {r['elements_3d']} elements", flush=True)
            runs.append(r)
    write_results(out, pb, args, version, runs)


def write_results(out: Path, pb: Problem, args, version: str, runs: list[dict]):
    meta = dict(case=str(args.case), case_name=pb.name, ccx_version=version,
                torque_on_disc_Nm=pb.torque_Nmm * 1e-3, face_width_mm=pb.face_width,
                slab_mm=args.slab_mm, stiffness_factor=args.stiffness_factor,
                element=args.element, support=args.support,
                E_MPa=pb.E, nu=pb.nu, pins=pb.zb, lobes=pb.za,
                position_unit="fraction of the meshing period 2*pi/Zb of crank angle",
                command=" ".join([Path(sys.argv[0]).name] + sys.argv[1:]))
    (out / "summary.json").write_text(json.dumps(dict(meta=meta, runs=runs), indent=1))
    cols = ["mesh_size_mm", "position_fraction_of_pitch", "crank_angle_deg", "pins_in_contact",
            "max_pin_force_N", "max_force_pin", "max_pressure_MPa", "max_hertz_p0_MPa",
            "seed_pins_loaded", "seed_max_pin_force_N", "pin_moment_Nm", "ccx_wall_s",
            "ccx_iterations", "ccx_equations", "elements_3d", "nodes_3d"]
    with open(out / "positions.csv", "w") as fh:
        fh.write(",".join(cols) + "\n")
        for r in runs:
            fh.write(",".join(_fmt(r[c]) for c in cols) + "\n")
    pcols = ["pin", "theta_b_deg", "moment_arm_mm", "force_N", "normal_force_N", "fx_N", "fy_N",
             "in_contact", "active_slave_nodes", "max_pressure_MPa", "hertz_p0_MPa",
             "seed_force_N"]
    with open(out / "pins.csv", "w") as fh:
        fh.write("mesh_size_mm,position_fraction_of_pitch," + ",".join(pcols) + "\n")
        for r in runs:
            for p in r["pins"]:
                fh.write(f"{r['mesh_size_mm']:g},{r['position_fraction_of_pitch']},"
                         + ",".join(_fmt(p[c]) for c in pcols) + "\n")
    # refinement table: per position, each mesh against the next finer one
    sizes = sorted({r["mesh_size_mm"] for r in runs}, reverse=True)
    with open(out / "refinement.csv", "w") as fh:
        fh.write("position_fraction_of_pitch,mesh_size_mm,elements_3d,max_pin_force_N,"
                 "change_to_next_finer_pct,max_pressure_MPa,max_hertz_p0_MPa,ccx_wall_s\n")
        for pos in dict.fromkeys(r["position_fraction_of_pitch"] for r in runs):
            rs = {r["mesh_size_mm"]: r for r in runs if r["position_fraction_of_pitch"] == pos}
            hs = [h for h in sizes if h in rs]
            for i, h in enumerate(hs):
                r = rs[h]
                ch = ""
                if i + 1 < len(hs):
                    f1 = rs[hs[i + 1]]["max_pin_force_N"]
                    ch = f"{100 * (r['max_pin_force_N'] - f1) / f1:.3f}"
                fh.write(f"{pos},{h:g},{r['elements_3d']},{r['max_pin_force_N']:.6g},{ch},"
                         f"{r['max_pressure_MPa']:.6g},{r['max_hertz_p0_MPa']:.6g},"
                         f"{r['ccx_wall_s']:.1f}\n")
    print(f"wrote {out / 'summary.json'}, positions.csv, pins.csv, refinement.csv")


def _fmt(v):
    if isinstance(v, bool):
        return str(int(v))
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


if __name__ == "__main__":
    main()
