"""Pictures of contact results. Matplotlib for curves, pyvista (off-screen) for fields.
Functions take data and return a figure or write a PNG; nothing is shown on screen."""
from __future__ import annotations


import numpy as np

from . import pyplot




def load_per_contact(ls, title=""):
    """Force per pin or tooth and P_h versus meshing position (two panels)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    deg = np.degrees(ls.position_rad)
    for c in np.flatnonzero(np.any(ls.force > 0, axis=0)):
        a1.plot(deg, ls.force[:, c], lw=1, label=f"{int(ls.contact_id[0, c])}")
        a2.plot(deg, ls.ph[:, c] / 1e6, lw=1)
    a1.plot(deg, ls.force.max(axis=1), "k--", lw=1.5, label="max")
    a2.plot(deg, ls.ph.max(axis=1) / 1e6, "k--", lw=1.5)
    a1.set_ylabel("normal force [N]")
    a2.set_ylabel("P_h [MPa]")
    a2.set_xlabel("crank angle [deg]")
    a1.legend(ncol=8, fontsize=6, title="contact id", title_fontsize=7)
    a1.set_title(title or f"load sharing ({ls.method} mode), torque {ls.torque:.1f} N m")
    for a in (a1, a2):
        a.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def contacts_versus_torque(torques, counts, max_forces, labels, title=""):
    """Pins in contact (and maximum force) versus torque, one line per design."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.5))
    for n, f, lab in zip(counts, max_forces, labels):
        a1.plot(torques, n, "o-", label=lab)
        a2.plot(torques, f, "o-", label=lab)
    a1.set_xlabel("disc torque [N m]")
    a1.set_ylabel("pins in contact")
    a2.set_xlabel("disc torque [N m]")
    a2.set_ylabel("maximum pin force [N]")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend()
    fig.suptitle(title)
    fig.tight_layout()
    return fig


def field_png(vtu_path, png_path, scalar="von_mises", zoom_centre=None, zoom_radius=None,
              title=""):
    """Render a VTU field off-screen to PNG; with ``zoom_centre`` (x, y) a close-up."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    grid = pv.read(str(vtu_path))
    grid.point_data[scalar + "_MPa"] = grid.point_data[scalar] / 1e6
    plotter = pv.Plotter(off_screen=True, window_size=(1000, 900))
    plotter.add_mesh(grid, scalars=scalar + "_MPa", cmap="jet", show_edges=zoom_centre is not None,
                     edge_color="grey", line_width=0.3,
                     scalar_bar_args=dict(title=f"{scalar} [MPa]", vertical=True))
    plotter.view_xy()
    if zoom_centre is not None:
        x, y = zoom_centre
        r = zoom_radius
        plotter.camera.focal_point = (x, y, 0.0)
        plotter.camera.position = (x, y, 1.0)
        plotter.camera.parallel_projection = True
        plotter.camera.parallel_scale = r
    if title:
        plotter.add_text(title, font_size=10)
    plotter.screenshot(str(png_path))
    plotter.close()
    return png_path
