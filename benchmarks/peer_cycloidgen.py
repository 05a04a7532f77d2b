"""toothfem's datasheet beside cycloidgen's (PyPI, rigid bodies and Hertz line contacts) on
the pin-housing drive, unmodified and with a 10 um equidistant modification: the mesh's
rigidity, its backlash (play), the pins engaged at the rated torque, the mesh's TE over
one pin pitch (issue 11, item 7; docs/stiffness.md explains each difference).

The peer is never a dependency of toothfem: it lives in its own environment,

    python3 -m venv benchmarks/.venv-peer && benchmarks/.venv-peer/bin/pip install cycloidgen

and this script runs its half there (``--peer-python``). Run from the project's venv:

    .venv/bin/python benchmarks/peer_cycloidgen.py [--positions 12] [--out FILE.json]
"""
import argparse
import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PEER_PYTHON = ROOT / "benchmarks" / ".venv-peer" / "bin" / "python"
#: The modifications compared (equidistant, mm), and the torque (the case's, N m).
MODIFICATIONS_MM = (0.0, 0.010)

#: The peer's half, run by its own interpreter: its GearSpec of the pin-housing drive
#: (40 pins on R 100 mm, rz 2 mm, e 1 mm, 39 lobes, two 10 mm discs, integral pin housing,
#: ground steel, an equidistant clearance, no position tolerance) and its stiffness and
#: TE results. Only its ring stage (the disc-pin mesh) has a counterpart here.
PEER_CODE = r"""
import json, sys
from cycloidgen.core.spec import GearSpec, OffsetMode, Process
from cycloidgen.analysis.stiffness import analyse_stiffness, analyse_transmission_error
out = {}
for clearance in json.loads(sys.argv[1]):
    spec = GearSpec(pin_circle_radius=100.0, pin_radius=2.0, eccentricity=1.0, lobes=39,
                    disc_thickness=10.0, disc_count=2, process=Process.EDM,
                    offset_mode=OffsetMode.EQUIDISTANT, profile_clearance=clearance,
                    position_tolerance=0.0, disc_material="Steel 4140 (hardened)",
                    pin_material="Steel 4140 (hardened)", ring_pins_integral=True,
                    output_torque_Nm=float(sys.argv[2]))
    s = analyse_stiffness(spec)
    te = analyse_transmission_error(spec)
    out[str(clearance)] = {
        "mesh_rigidity_Nm_per_arcmin": s.ring_stage_Nm_per_arcmin,
        "mesh_backlash_arcmin": s.lost_motion_ring_arcmin,
        "pins_engaged": s.pins_engaged,
        "pins_engaged_ideal": s.pins_engaged_ideal,
        "mesh_te_peak_to_peak_arcsec": 60 * te.ring_arcmin,
        "drive_rigidity_Nm_per_arcmin": s.stiffness_Nm_per_arcmin,
    }
import cycloidgen
out["version"] = cycloidgen.__version__
print(json.dumps(out))
"""


def peer(torque, python):
    res = subprocess.run([str(python), "-c", PEER_CODE,
                          json.dumps(list(MODIFICATIONS_MM)), str(torque)],
                         check=True, capture_output=True, text=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def ours(case, positions):
    sys.path.insert(0, str(ROOT))
    import numpy as np

    from toothfem.fem.datasheet.sheet import datasheet
    from toothfem.fem.datasheet.twist import ARCSEC
    from toothfem.efficiency import rated_output_torque
    from toothfem.fem.drives import drive_for
    from toothfem.fem.system.datasheet import SystemTwist

    base = drive_for(case)
    supports = base.supports(case.to_si().supports)
    rated, _ = rated_output_torque(case)
    out = {}
    for mod in MODIFICATIONS_MM:
        g = replace(base.geometry, equidistant_m=mod * 1e-3)
        drive = replace(base, stage=replace(base.stage, geometry=g))
        model = SystemTwist(drive.system_model(supports, positions))
        sheet = datasheet(model, rated)
        at = model.at(rated)
        out[str(mod)] = {
            "mesh_rigidity_Nm_per_arcmin": 1 / sheet.compliance_arcmin_per_Nm["mesh"],
            "mesh_backlash_arcmin": sheet.backlash_arcmin,
            "pins_engaged": float(np.mean(at.contacts)),
            "mesh_te_peak_to_peak_arcsec": float(np.ptp(at.paths["mesh"]) / ARCSEC),
            "drive_rigidity_Nm_per_arcmin": sheet.rigidity_Nm_per_arcmin,
            "lost_motion_arcmin": sheet.lost_motion_arcmin,
        }
    return out


def pinhousing_case(peer_python):
    """The pin-housing case and its rated output torque [N m], once the peer's environment
    is known to exist (the peer scripts' common start)."""
    if not Path(peer_python).exists():
        sys.exit(f"no peer environment at {peer_python}: create it as the module "
                 "docstring says")
    sys.path.insert(0, str(ROOT))
    from toothfem import load_case
    from toothfem.efficiency import rated_output_torque

    case = load_case(ROOT / "cases" / "cycloid_pinhousing.toml")
    return case, rated_output_torque(case)[0]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--positions", type=int, default=12,
                    help="toothfem's positions over one pin pitch (default 12)")
    ap.add_argument("--peer-python", default=str(PEER_PYTHON))
    ap.add_argument("--out", default=None, help="write both results as JSON")
    args = ap.parse_args(argv)
    case, torque = pinhousing_case(args.peer_python)
    theirs = peer(torque, args.peer_python)
    mine = ours(case, args.positions)
    print(f"pin-housing drive at {torque:g} N m; cycloidgen {theirs['version']}")
    keys = ("mesh_rigidity_Nm_per_arcmin", "mesh_backlash_arcmin", "pins_engaged",
            "mesh_te_peak_to_peak_arcsec", "drive_rigidity_Nm_per_arcmin")
    for mod in MODIFICATIONS_MM:
        print(f"\nequidistant modification {1e3 * mod:g} um")
        print(f"  {'quantity':32s} {'toothfem':>12s} {'cycloidgen':>12s}")
        for k in keys:
            print(f"  {k:32s} {mine[str(mod)][k]:12.4g} {theirs[str(mod)][k]:12.4g}")
    if args.out:
        Path(args.out).write_text(json.dumps({"toothfem": mine, "cycloidgen": theirs,
                                              "torque_Nm": torque}, indent=2))


if __name__ == "__main__":
    main()
