"""Write the demonstration TE and hysteresis recordings of data/demo/te/: rig-like files of
the RV-40E case's system model with one effect its case does not declare, plus encoder
noise and a zero offset per file (each file's header says it is synthetic, the effect and
its true value, the noise).

- ``rv40e_crank_play/``: crank-bearing play 10 um; shape A (one file per torque, forward
  and backward columns) and the hysteresis staircase;
- ``rv40e_running/``: crank-bearing play 10 um, as a production running rig writes it
  (shape W: one file per torque at 11 torques from 0 to 110 % of the rating, each re-zeroed,
  8 windows of 1 degree a direction scattered over three quarters of a turn, the rig's
  once-per-turn of 20 arcsec); the model's running losses in the widths;
- ``rv40e_eccentric/``: the eccentric under crank 1, disc 1, 5 um off its place: 4 um
  radially (its eccentricity) and 3 um across (its phase, 8 arcmin at e = 1.3 mm); shape B
  (one long table with a direction column, re-zeroed from its second torque on) and the
  staircase.

``toothfem te-loop cases/rv40e.toml --te data/demo/te/rv40e_crank_play/ --hysteresis
data/demo/te/rv40e_crank_play/hysteresis.csv --out DIR`` then finds the play and reports the
error before and after. Regenerate with ``python data/demo/te/generate.py``
(tests/test_te_loop.py checks the shipped files are what this script writes).
"""
from __future__ import annotations

import math
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
CASES = HERE.parent.parent.parent / "cases"
#: Output revolutions of each TE sweep and readings per revolution: one revolution resolves
#: the orders 39 and 40 apart (rectangular window), 3600 readings (0.1 deg) sample the
#: orders the loop fits many times over and keep each file near 200 kB.
REVOLUTIONS = 1
SAMPLES_PER_REVOLUTION = 3600
#: The TE's torque levels, fractions of the rated torque.
TORQUE_FRACTIONS = (0.5, 1.0)
#: The sets: folder -> (effects keywords, file shapes, noise keywords).
SETS = {
    "rv40e_crank_play": ({"crank_bearing_play_m": 10e-6}, ("A", "hysteresis"), {"seed": 1}),
    "rv40e_eccentric": ({"crank_eccentricity_m": ((5e-6, 0.0), (0.0, 0.0)),
                         "crank_phase_rad": ((math.atan2(3.0, 4.0), 0.0), (0.0, 0.0))},
                        ("B", "hysteresis"),
                        {"seed": 2, "rezero_at": 1, "rezero_offset_arcsec": 120.0}),
    "rv40e_running": ({"crank_bearing_play_m": 10e-6}, ("W",), {"seed": 3}),
}
#: The torque levels of a set other than TORQUE_FRACTIONS': the running rig's 11 torques
#: from 0 to 110 % of the rated torque, the brake opposing the motion both ways.
SET_TORQUE_FRACTIONS = {"rv40e_running": tuple(0.11 * k for k in range(11))}


def write(folder: Path, name: str) -> Path:
    """Write one set into ``folder/name`` (through a temporary folder, then renamed).

    Parameters
    ----------
    folder : pathlib.Path
    name : str
        A key of SETS.

    Returns
    -------
    pathlib.Path
        The set's folder.
    """
    from toothfem import load_case
    from toothfem.efficiency.loop.te.model import Effects, RecordingModel
    from toothfem.efficiency.loop.te.synthetic_model import Noise, write_synthetic_recordings

    effects, shapes, noise = SETS[name]
    case = load_case(CASES / "rv40e.toml")
    model = RecordingModel(case)
    torques = [round(f * model.rated_torque_Nm, 1)
               for f in SET_TORQUE_FRACTIONS.get(name, TORQUE_FRACTIONS)]
    target = folder / name
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}-", dir=folder))
    try:
        write_synthetic_recordings(tmp, case, Effects(**effects), torques, model=model,
                                   noise=Noise(**noise), shapes=shapes,
                                   revolutions=REVOLUTIONS,
                                   samples_per_revolution=SAMPLES_PER_REVOLUTION)
        if target.exists():
            shutil.rmtree(target)
        tmp.rename(target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return target


def main(argv=None) -> int:
    """Write every set (or those named) into this folder.

    Parameters
    ----------
    argv : list of str, optional
        Set names (default all).

    Returns
    -------
    int
        0.
    """
    sys.path.insert(0, str(HERE.parent.parent.parent))
    for name in (argv or list(SETS)):
        print(write(HERE, name))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
