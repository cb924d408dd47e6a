"""The VTU files of `damfem solve` on two meshed bodies: both sides of the joint between the dam
and the rock of geo/dam_on_rock.toml (docs/method.md §1.10) carry the joint's fields, and the
estimators of geo/dam_lifts_on_rock_uplift.toml reach the cells of both sides (§5.6)."""

import json
import subprocess

import meshio
import numpy as np
import pytest
from conftest import scene


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


def test_estimators_of_both_sides_of_the_joints(damfem, tmp_path):
    # Source: geo/dam_lifts_on_rock_uplift.toml (two joints with their own uplift, three
    # bodies), docs/method.md §5.1 and §5.6. Goal: the η fields of the VTU combine as the summary
    # says for every component (η_tot,T the sum of the six, each global value (Σ_T η_T²)^{1/2}),
    # and η_disc reaches the cells of both sides of the base: the rock's, which own its master
    # facets, carry the same η_disc as the dam's on the matching sides (t^m = −t there).
    # Parameters: P1, gmsh's sizes × 3.
    out = tmp_path / "estimate"
    subprocess.run([str(damfem), "solve", "-q", str(scene("dam_lifts_on_rock_uplift")), "--order", "1",
                    "--size-factor", "3", "--estimate", "-o", str(out)], check=True)
    summary = json.loads((out / "summary.json").read_text())
    grid = meshio.read(out / "dam_lifts_on_rock_uplift.vtu")
    data = {name: np.ravel(values[0]) for name, values in grid.cell_data.items()}
    names = ["osc", "flux", "Neu", "disc", "reg", "lin"]
    parts = sum(data[f"eta_{n}"] for n in names)
    np.testing.assert_allclose(data["eta_tot"], parts, rtol=1e-12)
    for n in names + ["tot"]:
        globally = summary["estimate"]["global"][n.lower()]
        assert np.sqrt((data[f"eta_{n}"] ** 2).sum()) == pytest.approx(globally, rel=1e-12)
    material = {name: int(t) for t, name in summary["tags"]["material"].items()}
    disc = {name: np.sqrt((data["eta_disc"][data["material"] == t] ** 2).sum()) for name, t in material.items()}
    assert disc["rock"] > 1e-3 * summary["estimate"]["global"]["disc"], disc
    assert disc["rock"] == pytest.approx(disc["lower_block"], rel=1e-6), disc
