#!/usr/bin/env python3
"""Render a damfem result to a PNG.

Usage: scripts/render.py RESULT.vtu|RESULT.pvd OUT.png [--field von_mises] [--warp auto|FACTOR]
                         [--edges] [--log] [--box XMIN XMAX YMIN YMAX] [--range LOW HIGH]

The script runs under the project's Python environment .venv (made by `make deps`): started by
another Python without numpy, it starts itself again under .venv/bin/python.

For a .pvd collection (the steps of `damfem adapt`) the last step is drawn. The title names the
scene, the load combination and the step (from summary.json beside the file, and the .pvd).
The cells are coloured by a cell field on the deformed shape: with --warp auto (the default)
the displacement is magnified so that the largest is 5% of the domain size for a single body,
and not at all where several bodies meet (a magnified rock block would sink under the dam);
--warp gives the factor. If RESULT_boundary.vtu exists beside it, the contact boundary or the
joint is drawn on top: red where it is closed (sticks, on a frictional joint), orange where it
slips, blue where it is open, and black where the boundary is clamped (u = 0). --edges draws
the cell edges, --log a logarithmic colour scale (for estimators); --box draws a close-up.

The colour range is robust by default: the 1st to 99th percentile of the cell values in view,
weighted by area, so that the few cells at a singular point (a re-entrant corner, the end of
the contact zone) do not turn the rest into one colour (the colour bar's arrows show values
beyond it); --range LOW HIGH sets it (in the unit of the colour bar). Stresses are shown in
MPa, displacements in mm; the axes are in metres.
"""

import json
import os
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

VENV = Path(__file__).resolve().parents[1] / ".venv"


def missing_environment(error):
    """Start this script again under the project's .venv, or say how to make it."""
    python = VENV / "bin" / "python"
    if python.exists() and Path(sys.prefix).resolve() != VENV.resolve():
        os.execv(python, [str(python), str(Path(__file__).resolve()), *sys.argv[1:]])
    state = "lacks it" if python.exists() else "does not exist"
    sys.exit(f"{Path(__file__).name}: cannot import {error.name}, and the project's Python environment {VENV} "
             f"{state}: run `make deps` in {VENV.parent}")


try:
    import matplotlib
    import numpy as np
    import pyvista as pv
except ImportError as error:
    if __name__ != "__main__":
        raise
    missing_environment(error)

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.colors import LogNorm, Normalize  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402
from matplotlib.tri import Triangulation  # noqa: E402
from mpl_toolkits.axes_grid1 import make_axes_locatable  # noqa: E402


def several_bodies(grid):
    """Whether the grid has more than one region (a dam on a meshed rock block, lifts)."""
    return "material" in grid.cell_data and len(np.unique(grid.cell_data["material"])) > 1


def warp_factor(grid, requested):
    """The displacement magnification: `requested`, or for "auto" 5% of the domain's size over
    the largest displacement on a single body and none (0) on several."""
    if requested != "auto":
        return float(requested)
    if several_bodies(grid):
        return 0.0
    largest = np.linalg.norm(grid.point_data["displacement"], axis=1).max()
    size = np.linalg.norm(np.array(grid.bounds[1::2]) - np.array(grid.bounds[::2]))
    return 0.05 * size / largest if largest > 0 else 0.0


def warped_points(grid, factor):
    """The (x, y) of the points of `grid` displaced by `factor` times the displacement."""
    return grid.points[:, :2] + factor * np.asarray(grid.point_data["displacement"])[:, :2]


def segments(boundary, cells, points):
    """The facets `cells` of `boundary` as polylines through `points`: end, midpoint, end."""
    nodes = boundary.cell_connectivity.reshape(boundary.n_cells, -1)[cells]
    order = [0, 2, 1] if nodes.shape[1] == 3 else [0, 1]
    return points[nodes[:, order]]


def contact_lines(boundary, factor):
    """The Γ_C facets of the boundary file, warped, by contact status: (polylines, colour, label)."""
    if "contact_status" not in boundary.cell_data:
        return []
    points = warped_points(boundary, factor)
    status = boundary.cell_data["contact_status"]
    closed = "stick" if "tangential_traction" in boundary.cell_data else "closed (contact)"
    zones = [(np.where(status == s)[0], colour, label)
             for s, colour, label in ((1, "red", closed), (2, "orange", "slip"), (0, "blue", "open"))]
    zones.append((anchored(boundary), "black", "anchored (u = 0)"))
    return [(segments(boundary, cells, points), colour, label) for cells, colour, label in zones if len(cells)]


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
    """The cell values of `field` in the unit of its colour bar (a vector field by its norm, a
    point field by its mean over the corners of each cell)."""
    if field in grid.cell_data:
        values = np.asarray(grid.cell_data[field], dtype=float)
    elif field in grid.point_data:
        values = np.asarray(grid.point_data[field], dtype=float)
    else:
        known = ", ".join(sorted(set(grid.cell_data.keys()) | set(grid.point_data.keys())))
        sys.exit(f"render.py: no field {field!r} in the file; it has: {known}")
    if values.ndim > 1:
        values = np.linalg.norm(values, axis=1)
    if field not in grid.cell_data:
        # a point field: the mean over each cell's corners
        values = values[grid.cell_connectivity.reshape(grid.n_cells, -1)[:, :3]].mean(axis=1)
    return values / UNITS.get(field, (1.0, ""))[0]


def colour_range(values, areas, log=False):
    """The 1st to 99th percentile of the finite (for log, positive) cell values, weighted by
    the cell areas: an adapted mesh puts many small cells at a singular point, which a count
    of cells would take for a large part of the domain."""
    keep = np.isfinite(values) & ((values > 0) if log else True)
    values, areas = values[keep], areas[keep]
    order = np.argsort(values)
    share = np.cumsum(areas[order]) / areas.sum()
    low, high = (values[order][min(np.searchsorted(share, p / 100.0), len(order) - 1)] for p in PERCENTILES)
    return (float(low), float(high)) if high > low else (float(values.min()), float(values.max()))


def in_view(points, triangles, box):
    """Which triangles have a point in box = (xmin, xmax, ymin, ymax) or overlap it: every cell
    that shows in a close-up, those that cross its edges and corners included."""
    x, y = points[triangles, 0], points[triangles, 1]
    return (x.max(axis=1) >= box[0]) & (x.min(axis=1) <= box[1]) & (y.max(axis=1) >= box[2]) & (y.min(axis=1) <= box[3])


def round_log_ticks(bar, clim):
    """Ticks of a logarithmic colour bar at 1, 2 and 5 times powers of ten over less than two
    decades (else at the powers), written as plain numbers or powers of ten."""
    decades = np.log10(clim[1] / clim[0]) if clim[0] > 0 else np.inf
    subs = (1.0, 2.0, 5.0) if decades < 2 else (1.0,)
    bar.ax.yaxis.set_major_locator(LogLocator(subs=subs))
    bar.ax.yaxis.set_minor_formatter(NullFormatter())
    bar.ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}" if 1e-3 <= v < 1e5 else f"{v:.0e}"))


def last_step(path):
    """The path itself, or the last data set of a .pvd collection, and (step, steps) or None:
    the step numbered from 0 as damfem numbers them, and how many the collection has."""
    if path.suffix != ".pvd":
        match = re.search(r"_(\d+)$", path.stem)
        return path, ((int(match.group(1)), None) if match else None)
    datasets = sorted(ET.parse(path).getroot().iter("DataSet"), key=lambda d: float(d.get("timestep")))
    return path.parent / datasets[-1].get("file"), (len(datasets) - 1, len(datasets))


def title(result, step):
    """Scene, combination and step of the result, from summary.json beside it where there is one."""
    summary_path = result.parent / "summary.json"
    summary = json.loads(summary_path.read_text()) if summary_path.exists() else {}
    scene = Path(summary["scene"]).stem if "scene" in summary else re.sub(r"_\d+$", "", result.stem)
    parts = [f"scene {scene}"]
    if summary.get("combination"):
        parts.append(f"combination {summary['combination']}")
    if step:
        parts.append(f"step {step[0]}" + (f", the last of {step[1]}" if step[1] else ""))
    return ", ".join(parts)


def draw_boundary(ax, boundary_path, factor, box):
    """The contact boundary or joint coloured by its status, and the undeformed outline when
    warped; returns the legend's handles, of the zones in view of `box`."""
    boundary = pv.read(boundary_path)
    if factor:
        outline = segments(boundary, np.arange(boundary.n_cells), boundary.points[:, :2])
        ax.add_collection(LineCollection(outline, colors="grey", linewidths=0.8, linestyles="dashed", zorder=2))
    handles = []
    for lines, colour, label in contact_lines(boundary, factor):
        x, y = lines[..., 0], lines[..., 1]
        if not ((x >= box[0]) & (x <= box[1]) & (y >= box[2]) & (y <= box[3])).any():
            continue
        ax.add_collection(LineCollection(lines, colors=colour, linewidths=3.5, capstyle="butt", zorder=3))
        handles.append(Line2D([], [], color=colour, linewidth=3.5, label=label))
    if factor:
        handles.append(Line2D([], [], color="grey", linewidth=0.8, linestyle="dashed", label="undeformed outline"))
    return handles


def parse():
    import argparse
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
    return parser.parse_args()


def main():
    args = parse()
    result, step = last_step(args.result)
    grid = pv.read(result)
    factor = warp_factor(grid, args.warp)
    points = warped_points(grid, factor)
    triangles = grid.cell_connectivity.reshape(grid.n_cells, -1)[:, :3]
    values = field_values(grid, args.field)
    areas = np.asarray(grid.compute_cell_sizes(length=False, volume=False).cell_data["Area"])
    box = args.box or (points[:, 0].min(), points[:, 0].max(), points[:, 1].min(), points[:, 1].max())
    shown = in_view(points, triangles, box)
    clim = tuple(args.range) if args.range else colour_range(values[shown], areas[shown], args.log)
    norm = LogNorm(*clim, clip=False) if args.log else Normalize(*clim)
    cmap = plt.get_cmap("viridis").with_extremes(bad="lightgrey")

    fig, ax = plt.subplots(figsize=(10, 7.5), dpi=100)
    edges = {"edgecolors": "white", "linewidth": 0.15} if args.edges else {"edgecolors": "face", "linewidth": 0.05}
    mesh = ax.tripcolor(Triangulation(points[:, 0], points[:, 1], triangles), facecolors=values, cmap=cmap,
                        norm=norm, zorder=1, **edges)
    low, high = np.nanmin(values[shown]), np.nanmax(values[shown])
    extend = {(True, True): "both", (True, False): "min", (False, True): "max"}.get((low < clim[0], high > clim[1]))
    bar = fig.colorbar(mesh, cax=make_axes_locatable(ax).append_axes("right", size="3%", pad=0.15),
                       label=field_label(args.field), extend=extend or "neither")
    if args.log:
        round_log_ticks(bar, clim)
    boundary_path = result.with_name(result.stem + "_boundary.vtu")
    handles = draw_boundary(ax, boundary_path, factor, box) if boundary_path.exists() else []
    if handles:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=len(handles), frameon=False)
    ax.set_aspect("equal")
    pad = 0.02 * max(box[1] - box[0], box[3] - box[2])
    ax.set_xlim(box[0] - pad, box[1] + pad)
    ax.set_ylim(box[2] - pad, box[3] + pad)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    shape = f"displacement × {float(f'{factor:.3g}'):g}" if factor else "undeformed shape"
    ax.set_title(f"{title(result, step)}\n{field_label(args.field)}, {shape}")
    fig.savefig(args.png, bbox_inches="tight", pad_inches=0.2)
    plt.close(fig)
    print(args.png)


if __name__ == "__main__":
    main()
