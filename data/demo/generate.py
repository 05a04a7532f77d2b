"""Write the demonstration rig data of data/demo/: for each shipped case, measured-like
efficiency data holding one effect its case does not declare, plus sensor noise.

Every file is synthetic and says so in its header: the effect and its true value, the
sensors and the noise (``# key: value`` lines, which the loader keeps as provenance), with the
sensors' table in the sidecar JSON. ``toothfem loop CASE data/demo/CASE_synthetic.csv --out
DIR`` then shows the loop finding the effect (or its alias group) and the error before and
after. Regenerate with ``python data/demo/generate.py`` (tests/test_loop_demo.py checks the
shipped files are what this script writes).
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
CASES = HERE.parent.parent / "cases"
#: Rows per file: enough for a 5-fold held-out error with room for two or three effects.
ROWS = 100
#: The shipped sets: case -> (effect, true values, generator keywords, what it stands for).
SETS = {
    "sine_prototype": ("windage", (26.7,), {"oil_temp_C": (30.0, 80.0)},
                       "a drag on the input growing with speed squared, 2.8 W at 1000 rpm"),
    "cycloid_pinhousing": ("warm_up", (20.0, 2.0), {"oil_temp_C": (40.0, 40.0),
                                                     "hours": 8.0},
                           "the oil warming 20 K over the run (time constant 2 h) while the "
                           "log reads 40 C throughout"),
    "cycloid_khv": ("drag_torque", (40.0,), {},
                    "a drag of 40 N mm on the input, a tight seal or preloaded input "
                    "bearings (to efficiency data the same number as the input meter's zero "
                    "offset: the report names the measurement that tells them apart)"),
    "rv40e": ("output_torque_offset", (5.0,), {},
              "the output torque meter's zero 5 N m off, 1 % of its 500 N m range (no "
              "operating point tells it from a drag on the input: the report says how to "
              "measure it)"),
    "rv_paper_example": ("viscosity_grade", (220.0,), {"oil_temp_C": (30.0, 80.0)},
                         "a VG 220 oil in the rig where the case says VG 68"),
}


def demo_data(name: str):
    """The demonstration data of one shipped case.

    Parameters
    ----------
    name : str
        A key of :data:`SETS` (the case file's stem).

    Returns
    -------
    tuple
        (CSV text with its provenance header, sidecar dict).
    """
    from toothfem import load_case
    from toothfem.efficiency.loop import synthetic as sy
    from toothfem.efficiency.loop.measured import to_csv

    effect, truth, kw, what = SETS[name]
    case = load_case(CASES / f"{name}.toml")
    data = sy.generate(case, {effect: truth}, n_points=ROWS, seed=23, **kw)
    rig = data.provenance["sensors"]
    header = [
        "source: synthetic demonstration data, not a measurement (data/demo/generate.py)",
        f"case: cases/{name}.toml",
        f"effect: {effect} = {', '.join(f'{v:g}' for v in truth)} ({what}); not declared "
        "in the case",
        "noise: Gaussian torque readings, one sigma = accuracy x range: input "
        f"{rig['input_torque']['accuracy']:g} x {rig['input_torque']['range_Nm']:g} N m, "
        f"output {rig['output_torque']['accuracy']:g} x {rig['output_torque']['range_Nm']:g} N m",
    ]
    text = "".join(f"# {line}\n" for line in header) + to_csv(data)
    return text, data.provenance


def main(argv=None) -> int:
    """Write every set of :data:`SETS` beside this script (``NAME_synthetic.csv`` and its
    sidecar ``.json``).

    Parameters
    ----------
    argv : list of str, optional
        Names to write (default all).

    Returns
    -------
    int
        0.
    """
    import json

    for name in (argv or list(SETS)):
        text, prov = demo_data(name)
        (HERE / f"{name}_synthetic.csv").write_text(text)
        (HERE / f"{name}_synthetic.json").write_text(json.dumps(prov, indent=2) + "\n")
        print(f"wrote data/demo/{name}_synthetic.csv")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
