"""The _boundary.vtu of `damfem solve` on geo/dam_on_rock.toml: both sides of the joint between
the dam and the rock (docs/method.md §1.10) carry the joint's fields."""

import meshio
import numpy as np
import pytest


@pytest.mark.parametrize("order", [1, 2])
def test_both_sides_of_the_joint_carry_its_fields(solved, order):
    # every facet of the dam's side ('joint') and of the rock's side ('joint:rock') is a
    # contact facet; on the matching sides the two carry the same pressure and jump, and the
    # pressure integrates to the summary's normal force N on each side
    out, summary = solved("dam_on_rock", order)
    grid = meshio.read(out / "dam_on_rock_boundary.vtu")
    data = {name: np.ravel(values[0]) for name, values in grid.cell_data.items()}
    tag = {name: int(t) for t, name in summary["tags"]["physical_tag"].items()}
    ends = grid.cells[0].data[:, :2]
    lengths = np.linalg.norm(grid.points[ends[:, 1]] - grid.points[ends[:, 0]], axis=1)
    sides = [data["physical_tag"] == tag[name] for name in ["joint", "joint:rock"]]
    normal_force = summary["contact"]["normal_force"]
    for side in sides:
        assert np.all(data["contact_status"][side] >= 0)
        assert lengths[side].sum() == pytest.approx(32.0, rel=1e-12)
        assert (data["contact_pressure"][side] * lengths[side]).sum() == pytest.approx(normal_force, rel=1e-12)
    for field in ["contact_pressure", "normal_displacement"]:
        dam, rock = (np.sort(data[field][side]) for side in sides)
        assert dam == pytest.approx(rock, rel=1e-12, abs=1e-12 * np.abs(dam).max())
    assert np.all(data["contact_status"][~(sides[0] | sides[1])] == -1)
