"""`damfem adapt` output read back by VTK (pyvista) and meshio, and rendered off-screen."""

import csv
import subprocess
import sys

import meshio
import numpy as np
import pytest
import pyvista as pv

from conftest import REPO, scene

pv.OFF_SCREEN = True
STEPS = 3


@pytest.fixture(scope="module")
def adapted(damfem, tmp_path_factory):
    out = tmp_path_factory.mktemp("adapt")
    done = subprocess.run([damfem, "adapt", "-q", scene("scene_a"), "--order", "1", "--steps", str(STEPS), "-o", out],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return out


def test_pvd_collection_lists_every_step(adapted):
    reader = pv.get_reader(adapted / "scene_a.pvd")
    assert len(reader.time_values) == STEPS
    cells = []
    for step, time in enumerate(reader.time_values):
        reader.set_active_time_value(time)
        grid = reader.read()[0]
        assert {"eta_tot", "eta_flux", "sigma_h_xx", "von_mises"} <= set(grid.cell_data.keys())
        assert np.all(np.isfinite(grid.cell_data["eta_tot"]))
        cells.append(grid.n_cells)
    # every step is a new mesh; equidistribution may coarsen the smooth parts at first
    assert len(set(cells)) == STEPS and cells[0] < cells[-1]


def test_history_matches_the_files(adapted):
    rows = list(csv.DictReader(open(adapted / "history.csv")))
    assert len(rows) == STEPS
    for row in rows:
        mesh = meshio.read(adapted / f"scene_a_{int(row['step']):02d}.vtu")
        assert sum(len(block.data) for block in mesh.cells) == int(row["cells"])
        eta = np.sqrt(np.sum(mesh.cell_data["eta_tot"][0] ** 2))
        assert eta == pytest.approx(float(row["eta_tot"]), rel=1e-12)


def test_render_last_step(adapted, tmp_path):
    png = tmp_path / "mesh.png"
    done = subprocess.run([sys.executable, REPO / "scripts" / "render.py", adapted / "scene_a.pvd", png, "--field", "eta_tot",
                           "--log", "--edges", "--warp", "0", "--box", "24", "40", "0", "8"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert png.stat().st_size > 10_000
    # VTK's log lines (an X server warning off-screen, an empty axis title) stay out of stderr
    assert "WARN|" not in done.stderr and "ERR|" not in done.stderr, done.stderr
