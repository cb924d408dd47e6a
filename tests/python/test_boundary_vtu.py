"""The _boundary.vtu of `damfem solve`: line cells tagged with the physical curves of Scene A."""

import meshio
import numpy as np
import pytest
import pyvista as pv

VTK_CELL_TYPES = {1: ("line", 3), 2: ("line3", 21)}


def read_boundary(out):
    grid = meshio.read(out / "scene_a_boundary.vtu")
    assert len(grid.cells) == 1
    return grid, grid.cells[0], np.ravel(grid.cell_data["physical_tag"][0])


@pytest.mark.parametrize("order", [1, 2])
def test_boundary_cells_carry_physical_curve_tags(solved, scene_a_groups, order):
    # the cells are lines of the mesh's order and their tags are exactly the physical curves
    out, _ = solved("scene_a", order)
    _, cells, tags = read_boundary(out)
    assert cells.type == VTK_CELL_TYPES[order][0]
    curves = {tag for dim, tag in scene_a_groups.values() if dim == 1}
    assert set(np.unique(tags)) == curves


@pytest.mark.parametrize("order", [1, 2])
def test_boundary_vtk_cell_types(solved, order):
    # VTK sees VTK_LINE (3) at P1 and VTK_QUADRATIC_EDGE (21) at P2
    out, _ = solved("scene_a", order)
    grid = pv.read(out / "scene_a_boundary.vtu")
    assert set(np.unique(grid.celltypes)) == {VTK_CELL_TYPES[order][1]}


@pytest.mark.parametrize("order", [1, 2])
def test_base_is_32_m_long(solved, scene_a_groups, order):
    # the cells of the physical curve 'base' add up to the 32 m contact zone (end points only)
    out, _ = solved("scene_a", order)
    grid, cells, tags = read_boundary(out)
    base = cells.data[tags == scene_a_groups["base"][1]]
    lengths = np.linalg.norm(grid.points[base[:, 1]] - grid.points[base[:, 0]], axis=1)
    assert lengths.sum() == pytest.approx(32.0, rel=1e-9)


def test_meshio_node_indices_are_integers(solved):
    # meshio returns the connectivity as integers, usable to index the points
    out, _ = solved("scene_a", 2)
    for name in ["scene_a.vtu", "scene_a_boundary.vtu"]:
        assert np.issubdtype(meshio.read(out / name).cells[0].data.dtype, np.integer), name
