"""Render a damfem result to a PNG, off-screen, with pyvista.

Usage: .venv/bin/python scripts/render.py RESULT.vtu|RESULT.pvd OUT.png [--field von_mises] [--warp auto|FACTOR]
                                [--edges] [--log] [--box XMIN XMAX YMIN YMAX] [--range LOW HIGH]

For a .pvd collection (the steps of `damfem adapt`) the last step is drawn. The deformed mesh (displacement magnified so that the largest displacement is 5% of the
domain size, unless --warp gives the factor) is coloured by a cell field. If
RESULT_boundary.vtu exists beside it, the contact boundary is drawn on top: red where
the body is in contact (sticks, on a frictional joint), orange where it slips, blue where
it has separated, and black where the boundary is clamped (u = 0), with a legend. --edges draws the cell edges, --log
a logarithmic colour scale (for estimators); --box draws only the cells inside a box (a
close-up, e.g. of the refined zone).

The colour range is robust by default: the 1st to 99th percentile of the cell values
weighted by area, so
that the few cells at a singular point (a re-entrant corner, the end of the contact zone)
do not turn the rest into one colour; --range LOW HIGH sets it (in the unit of the colour
bar). Stresses are shown in MPa, displacements in mm; the axes are in metres.
"""

import argparse
import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

# Without an X display, VTK would try X first and warn "bad X server connection" before it
# falls back to EGL: ask for EGL at once.
if sys.platform.startswith("linux") and not os.environ.get("DISPLAY"):
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

import numpy as np  # noqa: E402
import pyvista as pv  # noqa: E402


def warp_factor(grid, requested):
    if requested != "auto":
        return float(requested)
    largest = np.linalg.norm(grid.point_data["displacement"], axis=1).max()
    size = np.linalg.norm(np.array(grid.bounds[1::2]) - np.array(grid.bounds[::2]))
    return 0.05 * size / largest if largest > 0 else 1.0


def contact_lines(boundary_path, factor):
    """The Γ_C facets of the boundary file, warped, split by contact status: (lines, colour, label)."""
    boundary = pv.read(boundary_path)
    if "contact_status" not in boundary.cell_data:
        return []
    warped = boundary.warp_by_vector("displacement", factor=factor)
    status = boundary.cell_data["contact_status"]
    closed = "stick" if "tangential_traction" in boundary.cell_data else "contact"
    zones = ((1, "red", closed), (2, "orange", "slip"), (0, "blue", "open"))
    lines = [(warped.extract_cells(np.where(status == s)[0]), colour, label) for s, colour, label in zones]
    return lines + [(warped.extract_cells(anchored(boundary)), "black", "anchored (u = 0)")]


def anchored(boundary):
    """The facets off the contact boundary whose every node stays in place: the clamped part."""
    still = np.linalg.norm(boundary.point_data["displacement"], axis=1) == 0.0
    cells = boundary.cell_connectivity.reshape(boundary.n_cells, -1) if boundary.n_cells else np.empty((0, 2), int)
    off_contact = boundary.cell_data["contact_status"] == -1
    return np.where(off_contact & still[cells].all(axis=1))[0]


PERCENTILES = (1.0, 99.0)

# Fields shown in another unit: (divisor, unit); the others are drawn as written.
UNITS = {name: (1e6, "MPa") for name in
         ["von_mises", "sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "sigma_1", "sigma_2"]}
UNITS["displacement"] = (1e-3, "mm")
ESTIMATOR_UNIT = "Pa m"


def field_label(field):
    """The colour-bar title of `field` with its unit."""
    if field in UNITS:
        return f"{field} [{UNITS[field][1]}]"
    if field.startswith("eta"):
        return f"{field} [{ESTIMATOR_UNIT}]"
    return field


def field_values(grid, field):
    """The cell values of `field` in the unit of its colour bar (a vector field by its norm)."""
    values = np.asarray(grid.cell_data[field] if field in grid.cell_data else grid.point_data[field], dtype=float)
    if values.ndim > 1:
        values = np.linalg.norm(values, axis=1)
    return values / UNITS.get(field, (1.0, ""))[0]


def colour_range(values, areas, log=False):
    """The 1st to 99th percentile of the finite (for log, positive) cell values, weighted by
    the cell areas: an adapted mesh puts many small cells at a singular point, which a count
    of cells would take for a large part of the domain."""
    keep = np.isfinite(values) & ((values > 0) if log else True)
    values, areas = values[keep], areas[keep]
    order = np.argsort(values)
    share = np.cumsum(areas[order]) / areas.sum()
    low, high = (values[order][np.searchsorted(share, p / 100.0)] for p in PERCENTILES)
    return (float(low), float(high)) if high > low else (float(values.min()), float(values.max()))


def inside(grid, box):
    """The cells of `grid` whose centres lie in box = (xmin, xmax, ymin, ymax)."""
    centres = grid.cell_centers().points
    keep = (centres[:, 0] >= box[0]) & (centres[:, 0] <= box[1]) & (centres[:, 1] >= box[2]) & (centres[:, 1] <= box[3])
    return grid.extract_cells(np.where(keep)[0])


def last_step(path):
    """The path itself, or the last data set of a .pvd collection."""
    if path.suffix != ".pvd":
        return path
    datasets = ET.parse(path).getroot().iter("DataSet")
    return path.parent / max(datasets, key=lambda d: float(d.get("timestep"))).get("file")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("result", type=Path)
    parser.add_argument("png", type=Path)
    parser.add_argument("--field", default="von_mises")
    parser.add_argument("--warp", default="auto")
    parser.add_argument("--edges", action="store_true")
    parser.add_argument("--log", action="store_true")
    parser.add_argument("--box", type=float, nargs=4, metavar=("XMIN", "XMAX", "YMIN", "YMAX"))
    parser.add_argument("--range", type=float, nargs=2, metavar=("LOW", "HIGH"),
                        help="colour range in the unit of the colour bar (default: 1st-99th percentile)")
    args = parser.parse_args()
    result = last_step(args.result)
    grid = pv.read(result)
    if args.box:
        grid = inside(grid, args.box)
    factor = warp_factor(grid, args.warp)
    plotter = pv.Plotter(off_screen=True, window_size=(900, 800))
    plotter.add_mesh(grid, style="wireframe", color="lightgrey", opacity=0.4)
    label = field_label(args.field)
    warped = grid.warp_by_vector("displacement", factor=factor)
    values = field_values(grid, args.field)
    if values.shape[0] == warped.n_cells:
        warped.cell_data[label] = values
    else:
        warped.point_data[label] = values
    areas = grid.compute_cell_sizes(length=False, volume=False).cell_data["Area"]
    clim = tuple(args.range) if args.range else colour_range(values, np.asarray(areas), args.log)
    title = label + (f"\n(displacement x{factor:.3g})" if factor else "")
    plotter.add_mesh(warped, scalars=label, cmap="viridis", clim=clim, show_edges=args.edges, log_scale=args.log,
                     scalar_bar_args={"title": title, "vertical": True,
                                      "position_x": 0.82, "position_y": 0.25, "height": 0.5})
    boundary_path = result.with_name(result.stem + "_boundary.vtu")
    if boundary_path.exists():
        legend = []
        for lines, colour, label in contact_lines(boundary_path, factor):
            lines = inside(lines, args.box) if args.box and lines.n_cells else lines
            if lines.n_cells:
                plotter.add_mesh(lines, color=colour, line_width=6)
                legend.append([label, colour])
        if legend:
            plotter.add_legend(legend, bcolor="white", face="line", size=(0.22, 0.045 * len(legend)), loc="upper left")
    plotter.show_bounds(grid=False, location="outer", xtitle="x [m]", ytitle="y [m]", ztitle=" ", show_zaxis=False)
    plotter.view_xy()
    plotter.camera.zoom(1.0)
    plotter.screenshot(args.png)
    print(args.png)


if __name__ == "__main__":
    main()
