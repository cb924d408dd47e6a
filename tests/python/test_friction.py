"""The frictional dam (geo/scene_a_friction): held by Coulomb friction alone, open at the heel.

Source: global equilibrium of the dam and Coulomb's law on the joint. Goal: the joint forces in
summary.json balance the weight and the water thrust, computed here from the geometry; the boundary
VTU shows the zones (0 open at the heel, 1 stick, 2 slip, -1 off the joint) and its mean tractions
obey |t^t| <= F p_c. Parameters: the scene file (P2, F = 0.8391, flood level 70 m).
"""

import meshio
import numpy as np
import pytest

H, B, C = 50.0, 40.0, 5.0  # height, base, crest of scene_a_friction.geo [m]
RHO_G, WATER_G, LEVEL, F = 2400.0 * 9.81, 1000.0 * 9.81, 70.0, 0.8391


def test_the_joint_forces_balance_weight_and_thrust(solved):
    _, summary = solved("scene_a_friction")
    contact = summary["contact"]
    weight = RHO_G * (B + C) / 2 * H
    thrust = WATER_G * (LEVEL * H - H**2 / 2)
    [base] = contact["curves"]
    assert {k: base[k] for k in ("curve", "law", "friction", "gamma0", "theta")} == {
        "curve": "base", "law": "coulomb", "friction": F, "gamma0": 100.0, "theta": 0.0}
    assert base["normal_force"] == contact["normal_force"] and base["tangential_force"] == contact["tangential_force"]
    assert contact["normal_force"] == pytest.approx(weight, rel=1e-8)
    # τ = (−ν_y, ν_x) = (1, 0) on the base: the joint pushes upstream, against the thrust
    assert contact["tangential_force"] == pytest.approx(-thrust, rel=1e-8)
    assert contact["stick_length"] + contact["slip_length"] == pytest.approx(contact["contact_length"], rel=1e-9)


def test_the_boundary_shows_open_stick_and_slip_zones(solved):
    out, summary = solved("scene_a_friction")
    grid = meshio.read(out / "scene_a_friction_boundary.vtu")
    data = {name: np.ravel(values[0]) for name, values in grid.cell_data.items()}
    cells = grid.cells[0].data.astype(np.int64)
    mid_x = grid.points[cells[:, :2], 0].mean(axis=1)
    on_base = np.abs(grid.points[cells[:, :2], 1]).max(axis=1) < 1e-9
    status = data["contact_status"]
    assert set(np.unique(status[~on_base])) == {-1.0}
    assert set(np.unique(status[on_base])) <= {0.0, 1.0, 2.0}
    # the heel lifts off, the toe is closed
    assert np.all(status[on_base & (mid_x < 5.0)] == 0.0)
    assert np.all(status[on_base & (mid_x > 35.0)] > 0.0)
    assert summary["contact"]["contact_extent"][0][0] > 5.0
    # Coulomb on face means, |∫ t^t| <= ∫ |t^t| <= F ∫ p_c: p_c is the solved traction
    # −[P^n]_reg, whose threshold −F [P^n]_reg is the one the smoothed clamp respects
    closed = on_base & (status > 0)
    assert np.all(np.abs(data["tangential_traction"][closed]) <= F * data["contact_pressure"][closed] * (1 + 1e-12))
    # where P^n >= 0 (open), the smoothing leaves at most δ/4 of pressure
    open_faces = on_base & (status == 0)
    assert np.all(data["contact_pressure"][open_faces] <= summary["contact"]["delta"] / 4)
