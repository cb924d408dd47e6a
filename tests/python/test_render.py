"""Off-screen rendering of Scene A's von Mises field with pyvista."""

import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv

pv.OFF_SCREEN = True


def test_render_von_mises(solved, tmp_path):
    # a PNG of the warped von Mises field is written and is not a uniform image
    out, summary = solved("scene_a", 2)
    grid = pv.read(out / "scene_a.vtu")
    factor = 0.05 * grid.length / summary["max_displacement"]
    warped = grid.warp_by_vector("displacement", factor=factor)
    plotter = pv.Plotter(off_screen=True, window_size=(640, 480))
    plotter.add_mesh(warped, scalars="von_mises", preference="cell")
    plotter.view_xy()
    png = tmp_path / "scene_a_von_mises.png"
    image = plotter.screenshot(png, return_img=True)
    plotter.close()
    assert png.is_file() and png.stat().st_size > 0
    colours = np.unique(image.reshape(-1, image.shape[-1]), axis=0)
    assert len(colours) > 20


def load_render():
    spec = importlib.util.spec_from_file_location("render", Path(__file__).parents[2] / "scripts" / "render.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_render_script_default_range_excludes_singular_cells(damfem, solved, tmp_path):
    # scripts/render.py colours the von Mises field of Scene A over a range that leaves out
    # the singular cells (the maximum is many times the 99th percentile), labels the colour
    # bar in MPa, and draws a PNG with more than a flat colour
    out, summary = solved("scene_a", 2)
    render = load_render()
    grid = pv.read(out / "scene_a.vtu")
    values = render.field_values(grid, "von_mises")
    areas = np.asarray(grid.compute_cell_sizes(length=False, volume=False).cell_data["Area"])
    low, high = render.colour_range(values, areas)
    assert values.max() == pytest.approx(summary["max_von_mises"] / 1e6, rel=1e-9)
    assert low >= values.min() and high < values.max() / 2
    assert areas[values > high].sum() <= 0.011 * areas.sum()
    assert render.field_label("von_mises") == "von_mises [MPa]"
    assert render.field_label("eta_tot") == "eta_tot [Pa m]"
    png = tmp_path / "scene_a.png"
    subprocess.run([sys.executable, str(Path(render.__file__)), str(out / "scene_a.vtu"), str(png)], check=True,
                   capture_output=True)
    image = pv.read(png).point_data.active_scalars
    assert len(np.unique(image.reshape(len(image), -1), axis=0)) > 20


def test_render_script_marks_the_anchored_toe(solved):
    # the clamped facets of Scene A are its anchored toe, x from 32 to 40 m at y = 0
    out, _ = solved("scene_a", 2)
    render = load_render()
    boundary = pv.read(out / "scene_a_boundary.vtu")
    toe = boundary.extract_cells(render.anchored(boundary))
    assert toe.n_cells > 0
    assert np.allclose(toe.points[:, 1], 0.0)
    assert toe.points[:, 0].min() == pytest.approx(32.0) and toe.points[:, 0].max() == pytest.approx(40.0)
    assert toe.compute_cell_sizes().cell_data["Length"].sum() == pytest.approx(8.0)
