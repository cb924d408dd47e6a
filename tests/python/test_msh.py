"""The .msh written by `damfem mesh` for Scene A."""

import meshio
import pytest


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
