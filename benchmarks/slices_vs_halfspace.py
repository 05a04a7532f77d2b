"""The face-width slicing (issue 43) against Hertz's elliptic contact and the 3-D elastic
half-space: a crowned roller on a flat under a tilt (fem/slice_check.py). Prints, per
case, the 3-D half-space's peak pressure and where it sits, the independent slices' (9
and 60) and, where the crowned contact stays on the roller, Hertz's ellipse.

Run: .venv/bin/python benchmarks/slices_vs_halfspace.py
"""
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from toothfem.fem.datasheet.hertz_point import hertz_point_contact  # noqa: E402
from toothfem.fem.slice_check import halfspace_roller, sliced_roller  # noqa: E402

ARCMIN = math.pi / 180 / 60
#: The pin-housing case's pin: radius 2 mm, 10 mm face, 24 N/mm, steel (E* 113.9 GPa).
R, L, E_STAR, LOAD = 2e-3, 10e-3, 113.9e9, 240.0


def main():
    print("| tilt [arcmin] | crown [um] | Hertz ellipse p_max [MPa] | 3-D half-space 24 x 60: "
          "peak [MPa] at y [mm] | 9 slices | 60 slices |")
    print("|---|---|---|---|---|---|")
    for tilt, crown in ((0, 0), (1, 0), (3, 0), (0, 8), (3, 8), (3, 20)):
        th, c = tilt * ARCMIN, crown * 1e-6
        hz = "-"
        if c:
            h = hertz_point_contact(LOAD, R, L ** 2 / (8 * c), E_STAR)
            if h.semi_major_m + th * L ** 2 / (8 * c) < L / 2:
                hz = f"{h.p_max_Pa / 1e6:.1f} at {-th * L ** 2 / (8 * c) * 1e3:+.2f}"
        _, y, p = halfspace_roller(R, L, E_STAR, LOAD, th, c, nx=24, ny=60)
        at = y[np.unravel_index(int(np.argmax(p)), p.shape)[1]]
        cells = []
        for s in (9, 60):
            ys, _, ph = sliced_roller(R, L, E_STAR, LOAD, th, c, s)
            cells.append(f"{ph.max() / 1e6:.1f} at {ys[np.argmax(ph)] * 1e3:+.2f} "
                         f"({ph.max() / p.max() - 1:+.1%})")
        print(f"| {tilt} | {crown} | {hz} | {p.max() / 1e6:.1f} at {at * 1e3:+.2f} | "
              f"{cells[0]} | {cells[1]} |")


if __name__ == "__main__":
    main()
