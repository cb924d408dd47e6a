"""The .msh written by `damfem mesh` for Scene A."""

import subprocess

import meshio
import numpy as np
import pytest
from conftest import scene


def test_msh_physical_groups(scene_a_groups):
    # the five curves and the surface of scene_a.geo are physical groups of the .msh
    assert {n: d for n, (d, _) in scene_a_groups.items()} == {
        "base": 1, "toe": 1, "downstream": 1, "crest": 1, "upstream": 1, "concrete": 2
    }


def test_meshio_reads_msh(scene_a_msh, solved):
    # meshio reads the .msh with the node count of the solve and the physical names
    _, summary = solved("scene_a", 2)
    grid = meshio.read(scene_a_msh)
    assert len(grid.points) == summary["nodes"]
    assert "base" in grid.field_data


def by_position(grid):
    """Indices of the nodes of `grid` sorted by (x, y), rounded to 1 nm so that a midpoint
    computed in another order (an ulp away) sorts in the same place."""
    p = np.round(grid.points[:, :2], 9)
    return np.lexsort((p[:, 1], p[:, 0]))


def test_order_1_msh_raised_to_p2_solves_as_the_geo_at_p2(mesh, solve, solved, tmp_path):
    """Source: docs/method.md §6 (Scene A) and the raising of a mesh's order by gmsh
    (Mesh.SecondOrderLinear: a node at the middle of every straight edge).
    Goal: `solve --order 2` on an order-1 .msh gives, vertex by vertex, the displacement of the
    .geo meshed at order 2 (the same triangles), to round-off: the two systems differ only in
    the numbering of the nodes. Parameters: geo/scene_a.toml (P2, contact, flood); tolerance
    10^-10 max|u|, the Newton tolerance."""
    msh = mesh(scene("scene_a"), tmp_path / "mesh", order=1)
    assert meshio.read(msh).cells_dict.keys() == {"line", "triangle"}
    toml = tmp_path / "scene_a_msh.toml"
    toml.write_text(scene("scene_a").read_text().replace('"scene_a.geo"', f'"{msh}"'))
    out, summary = solve(toml, tmp_path / "out", order=2)
    geo_out, geo_summary = solved("scene_a", 2)
    assert summary["order"] == 2 and summary["unknowns"] == geo_summary["unknowns"]
    raised = meshio.read(out / "scene_a_msh.vtu")
    meshed = meshio.read(geo_out / "scene_a.vtu")
    assert raised.cells_dict.keys() == {"triangle6"}
    i, j = by_position(raised), by_position(meshed)
    assert np.abs(raised.points[i] - meshed.points[j]).max() < 1e-12
    u, v = raised.point_data["displacement"][i], meshed.point_data["displacement"][j]
    assert np.abs(u - v).max() <= 1e-10 * np.abs(v).max()


def test_msh_order_cannot_be_lowered(damfem, scene_a_msh, tmp_path):
    """Source: the `--order` option. Goal: `--order 1` on a degree-2 .msh, which would drop its
    midpoint nodes, stops with one sentence naming the flag and the file, and writes nothing.
    Parameters: Scene A's P2 .msh."""
    done = subprocess.run([damfem, "solve", "--order", "1", scene_a_msh, "-o", tmp_path / "out"],
                          capture_output=True, text=True)
    assert done.returncode == 1
    assert "--order 1" in done.stderr and scene_a_msh.name in done.stderr and "lowered" in done.stderr
    assert not (tmp_path / "out").exists()
