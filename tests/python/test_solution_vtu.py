"""The solution .vtu of `damfem solve` read back with meshio and pyvista, checked against summary.json."""

import json
import subprocess

import meshio
import numpy as np
import pytest
import pyvista as pv

from conftest import scene

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


def test_estimate_fields(damfem, tmp_path):
    # --check-equilibration adds every estimator and sigma_h to the VTU, writes the
    # discontinuous _dg.vtu, and reports the global values and checks in the summary
    out = tmp_path / "estimate"
    subprocess.run([str(damfem), "solve", "-q", str(scene("scene_a")), "--order", "1", "-o", str(out),
                    "--check-equilibration"], check=True)
    summary = json.loads((out / "summary.json").read_text())
    grid = pv.read(out / "scene_a.vtu")
    names = ["eta_osc", "eta_flux", "eta_Neu", "eta_disc", "eta_reg", "eta_lin", "eta_tot"]
    for name in names:
        assert name in grid.cell_data
    tot = grid.cell_data["eta_tot"]
    parts = sum(grid.cell_data[n] for n in names[:-1])
    np.testing.assert_allclose(tot, parts, rtol=1e-12)
    assert np.sqrt((tot ** 2).sum()) == pytest.approx(summary["estimate"]["global"]["tot"], rel=1e-9)
    assert summary["estimate"]["global"]["osc"] == 0.0 and summary["estimate"]["global"]["neu"] == 0.0
    # weak symmetry is tested against P_{p-1} rotations: not applicable for p = 1
    checks = summary["estimate"]["equilibration"]
    assert checks["weak_symmetry"] == "not applicable (P1)"
    assert max(v for k, v in checks.items() if k != "weak_symmetry") < 1e-10
    dg = pv.read(out / "scene_a_dg.vtu")
    assert dg.n_cells == grid.n_cells and dg.n_points == 3 * grid.n_cells
    for c in ["sigma_h_xx", "sigma_h_xy", "sigma_h_yx", "sigma_h_yy"]:
        assert c in dg.point_data and c in grid.cell_data
        assert np.isfinite(dg.point_data[c]).all()


def units(field_data):
    """{array: unit} from the `<array> [<unit>]` field data arrays, checked against their bytes."""
    found = {}
    for key, value in field_data.items():
        if key.endswith("]") and " [" in key:
            name, unit = key[:-1].split(" [", 1)
            assert bytes(np.asarray(value, dtype=np.uint8).ravel()).decode() == unit, key
            found[name] = unit
    return found


@pytest.mark.parametrize("name", ["scene_a.vtu", "scene_a_boundary.vtu"])
def test_field_data_names_groups_and_states_units(solved, name):
    # meshio and VTK read the same field data: each physical group (tag, dim), as in
    # summary.json's tags, and a unit for every array of the file
    out, summary = solved("scene_a", 2)
    mesh, grid = meshio.read(out / name), pv.read(out / name)
    vtk_data = {k: np.asarray(grid.field_data[k]) for k in grid.field_data.keys()}
    assert set(vtk_data) == set(mesh.field_data)
    for key, value in mesh.field_data.items():
        np.testing.assert_array_equal(np.ravel(value), np.ravel(vtk_data[key]))
    groups = {(int(tag), dim): group for dim, key in [(2, "material"), (1, "physical_tag")]
              for tag, group in summary["tags"][key].items()}
    named = {k: v for k, v in mesh.field_data.items() if not k.endswith("]")}
    assert {(int(v[0]), int(v[1])): k for k, v in named.items()} == groups
    arrays = set(mesh.point_data) | set(mesh.cell_data)
    found = units(mesh.field_data)
    assert set(found) == arrays
    assert found["displacement"] == "m"
    assert found.get("von_mises", "Pa") == "Pa" and found.get("contact_pressure", "Pa") == "Pa"
