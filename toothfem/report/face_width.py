"""The face width's files of `toothfem contact` with ``face_slices`` > 1 (issue 43):
face_width.csv (load and P_h of every slice of every loaded contact at every position) and
face_width.png (the peak P_h over the width and the meshing position; the pressure along
the width of each contact at the worst position). Records from
:mod:`toothfem.fem.cycloid_fe.slices`; nothing computed here.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ..units import MM_PER_M, PA_PER_MPA
from . import pyplot, save, wrap

#: face_width.csv's columns.
FACE_COLUMNS = ("position_deg", "contact_id", "z_mm", "slice_force_N", "line_load_N_per_mm",
                "ph_MPa")
#: Most contacts drawn one by one along the width (the most loaded ones).
MAX_PROFILES = 8


def write_face(sliced, folder: Path, title: str) -> list:
    """face_width.csv and face_width.png into an existing ``folder``.

    Parameters
    ----------
    sliced : toothfem.fem.cycloid_fe.slices.SlicedSharing
    folder : pathlib.Path
    title : str
        The picture's first line (the case and the torque).

    Returns
    -------
    list of str
        The files' names.
    """
    folder = Path(folder)
    with open(folder / "face_width.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(FACE_COLUMNS)
        for row in sliced.rows():
            w.writerow([f"{v:.9g}" if isinstance(v, float) else v for v in row])
    save(face_picture(sliced, title), folder / "face_width.png")
    return ["face_width.csv", "face_width.png"]


def face_picture(sliced, title: str):
    """Left: the largest P_h over the contacts at each slice and position (a map, the width
    against the crank angle); right: P_h along the width of the most loaded contacts at the
    position of the peak.

    Parameters
    ----------
    sliced : toothfem.fem.cycloid_fe.slices.SlicedSharing
    title : str

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = pyplot()
    ls, face = sliced.load_sharing, sliced.face
    ph = sliced.ph / PA_PER_MPA                      # (S, P, C)
    z = sliced.z * MM_PER_M
    deg = np.degrees(ls.position_rad)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.6), gridspec_kw={"width_ratios": [1.3, 1],
                                                                  "wspace": 0.35})
    half = 0.5 * sliced.slice_width * MM_PER_M
    step = deg[1] - deg[0] if deg.size > 1 else 1.0
    im = a.imshow(ph.max(axis=2), aspect="auto", origin="lower", cmap="viridis",
                  extent=(deg[0] - step / 2, deg[-1] + step / 2, z[0] - half, z[-1] + half))
    fig.colorbar(im, ax=a, label="largest P_h over the contacts [MPa]")
    a.set_xlabel("crank angle [deg]")
    a.set_ylabel("position along the face width z [mm]")
    s_pk, p_pk, c_pk = np.unravel_index(int(np.argmax(ph)), ph.shape)
    a.plot(deg[p_pk], z[s_pk], "r+", ms=12, mew=2, label="peak")
    a.legend(loc="upper left", bbox_to_anchor=(0.0, -0.14), ncol=1, frameon=False)
    loaded = np.argsort(ls.force[p_pk])[::-1][:MAX_PROFILES]
    for c in loaded[ls.force[p_pk, loaded] > 0]:
        b.plot(z, ph[:, p_pk, c], "o-", ms=3,
               label=f"pin {int(ls.contact_id[p_pk, c])}: {ls.force[p_pk, c]:.0f} N")
    b.set_xlabel("z [mm]")
    b.set_ylabel("P_h [MPa]")
    b.set_ylim(bottom=0)
    b.set_xlim(z[0] - half, z[-1] + half)
    b.grid(alpha=0.3)
    b.set_title(f"along the width at crank angle {deg[p_pk]:.2f} deg", fontsize=10)
    b.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), frameon=False, fontsize=8)
    crown = (f"crown {face.crown_m * 1e6:g} um ({face.form})" if face.crown_m
             else "no crown")
    fig.suptitle(wrap(f"{title}\n{face.slices} slices, tilt "
                      f"{math.degrees(face.tilt_rad) * 60:g} arcmin, {crown}; peak P_h "
                      f"{ph.max():.1f} MPa at z = {z[s_pk]:+.2f} mm", 124), fontsize=10, y=1.03)
    return fig
