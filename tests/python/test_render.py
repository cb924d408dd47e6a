"""Off-screen rendering of Scene A's von Mises field with pyvista."""

import numpy as np
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
