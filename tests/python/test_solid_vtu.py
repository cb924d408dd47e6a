"""The .vtu of `damfem solve` on a solid read back with meshio and pyvista.

Source: geo/block3d.toml (uniaxial compression, u linear: exact in P2) and geo/monolith.toml
(the Scene A section extruded by 15 m with rollers u_y = 0 on its sides: plane strain).
Goal: VTK_QUADRATIC_TETRA cells with every edge node at the midpoint of its edge in VTK's
order, boundary triangles, the exact displacement of the block, and the monolith held at
u_y = 0 on its sides, with u_y inside below 1 % of max |u| (the unstructured mesh's error).
"""

import json
import subprocess

import meshio
import numpy as np
import pyvista as pv

from conftest import scene

VTK_QUADRATIC_TETRA, VTK_QUADRATIC_TRIANGLE = 24, 22
# VTK's order of the edges of a 10-node tetrahedron: nodes 4..9
VTK_EDGES = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]


def solve(damfem, name, out):
    subprocess.run([damfem, "solve", "-q", scene(name), "-o", out], check=True)
    return json.loads((out / "summary.json").read_text())


def test_p2_tetrahedra_read_back_with_their_edge_nodes_at_the_midpoints(damfem, tmp_path):
    summary = solve(damfem, "block3d", tmp_path)
    mesh = meshio.read(tmp_path / "block3d.vtu")
    (block,) = mesh.cells
    assert block.type == "tetra10" and len(block.data) == summary["cells"]
    p, c = mesh.points, block.data
    for k, (i, j) in enumerate(VTK_EDGES):
        assert np.abs(p[c[:, 4 + k]] - 0.5 * (p[c[:, i]] + p[c[:, j]])).max() < 1e-12, f"edge node {4 + k}"
    strain = 1e6 / 3e10
    exact = np.stack([0.2 * strain * p[:, 0], 0.2 * strain * p[:, 1], -strain * p[:, 2]], axis=1)
    assert np.abs(mesh.point_data["displacement"] - exact).max() < 1e-12 * strain
    grid = pv.read(tmp_path / "block3d.vtu")
    assert set(grid.celltypes) == {VTK_QUADRATIC_TETRA}
    assert abs(grid.volume - 2.0) < 1e-9
    boundary = pv.read(tmp_path / "block3d_boundary.vtu")
    assert set(boundary.celltypes) == {VTK_QUADRATIC_TRIANGLE}
    assert abs(boundary.area - 10.0) < 1e-9


def test_the_extruded_monolith_is_in_plane_strain(damfem, tmp_path):
    summary = solve(damfem, "monolith", tmp_path)
    mesh = meshio.read(tmp_path / "monolith.vtu")
    u = mesh.point_data["displacement"]
    assert np.linalg.norm(u, axis=1).max() == summary["max_displacement"]
    sides = np.isclose(mesh.points[:, 1], 0.0) | np.isclose(mesh.points[:, 1], 15.0)
    assert sides.sum() > 100 and (u[sides, 1] == 0.0).all()
    # inside, the unstructured P1 mesh is not a plane-strain space: u_y is its error, 0.17 %
    assert np.abs(u[:, 1]).max() < 1e-2 * summary["max_displacement"]
    sigma_3 = mesh.cell_data["sigma_3"][0]
    assert (mesh.cell_data["sigma_1"][0] >= sigma_3).all()
