"""The solution .vtu of `damfem solve` read back with meshio and pyvista, checked against summary.json."""

import meshio
import numpy as np
import pytest
import pyvista as pv

# (scene, --order): Scene A at P1 and P2, and the Hertz scene at its own order (P2)
CASES = [("scene_a", 1), ("scene_a", 2), ("hertz", None)]
STRESSES = ["sigma_xx", "sigma_yy", "sigma_xy", "sigma_zz", "von_mises", "sigma_1", "sigma_2"]
VTK_TRIANGLE, VTK_QUADRATIC_TRIANGLE = 5, 22


def check_fields(summary, displacement, cell_data):
    """Displacement and stresses agree with the summary and are sound."""
    assert displacement.shape == (summary["nodes"], 3)
    assert np.linalg.norm(displacement, axis=1).max() == pytest.approx(summary["max_displacement"], rel=1e-9)
    for name in STRESSES + ["material"]:
        assert name in cell_data, name
        assert len(cell_data[name]) == summary["cells"], name
        assert not np.isnan(cell_data[name]).any(), name
    assert not np.isnan(displacement).any()
    assert cell_data["von_mises"].max() == pytest.approx(summary["max_von_mises"], rel=1e-9)
    assert (cell_data["sigma_1"] >= cell_data["sigma_2"]).all()


@pytest.mark.parametrize("name,order", CASES)
def test_meshio_reads_solution(solved, name, order):
    # meshio sees the summary's nodes and cells, triangles of the right order and sound fields
    out, summary = solved(name, order)
    grid = meshio.read(out / f"{name}.vtu")
    assert len(grid.points) == summary["nodes"]
    assert [c.type for c in grid.cells] == ["triangle" if summary["order"] == 1 else "triangle6"]
    assert len(grid.cells[0].data) == summary["cells"]
    cell_data = {k: np.ravel(v[0]) for k, v in grid.cell_data.items()}
    check_fields(summary, grid.point_data["displacement"], cell_data)


@pytest.mark.parametrize("name,order", CASES)
def test_pyvista_reads_solution(solved, name, order):
    # pyvista (VTK) sees the same counts, VTK cell types 5 / 22 and the same fields
    out, summary = solved(name, order)
    grid = pv.read(out / f"{name}.vtu")
    assert grid.n_points == summary["nodes"]
    assert grid.n_cells == summary["cells"]
    expected = VTK_TRIANGLE if summary["order"] == 1 else VTK_QUADRATIC_TRIANGLE
    assert set(np.unique(grid.celltypes)) == {expected}
    cell_data = {k: np.asarray(grid.cell_data[k]) for k in grid.cell_data.keys()}
    check_fields(summary, np.asarray(grid.point_data["displacement"]), cell_data)


def test_scene_a_crest_moves_downstream(solved):
    # under the water load the crest (y > 45 m) moves downstream, i.e. towards +x
    out, _ = solved("scene_a", 2)
    grid = meshio.read(out / "scene_a.vtu")
    crest = grid.points[:, 1] > 45.0
    assert crest.sum() > 0
    assert grid.point_data["displacement"][crest, 0].mean() > 0.0
