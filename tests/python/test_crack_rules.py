"""Source: EM 1110-2-2100 §3-3 and CADAM3D's seismic crack rules (docs/method.md §1.8).

Goal: under crack = "none" the joint the earthquake opens beyond the crack s0 before it,
[s0, s_c], carries no pressure, and the rest keeps the diagram of the state before the
earthquake: on the boundary VTU, every base face on [0, s0] has p_u = h1, every face on
[s0, s_c] none, and every face beyond s_c the mean of h1 (L - s) / (L - s0) over it, its
midpoint value (under `full` it would be that of s_c).
Parameters: scene_a_friction with the reservoir and the uplift at 45 m, no drains, no
tailwater, 0.1 g, P2; s0 and s_c read from summary.json.
"""

import meshio
import numpy as np
import pytest

from conftest import REPO, scene

H1 = 1000.0 * 9.81 * 45.0
L = 40.0


def drained_scene(tmp_path):
    text = scene("scene_a_friction").read_text()
    text = text.replace('geometry = "scene_a_friction.geo"', f'geometry = "{REPO / "geo" / "scene_a_friction.geo"}"')
    text = text.replace("level = 70.0", "level = 45.0").replace("gravity = 9.81", "gravity = 9.81\nacceleration = [0.1, 0.0]")
    path = tmp_path / "drained.toml"
    path.write_text(text + '\n[uplift]\nheadwater = 45.0\ncrack = "none"\n')
    return path


def test_a_drained_crack_carries_no_pressure_and_the_rest_the_static_diagram(solve, tmp_path):
    out, summary = solve(drained_scene(tmp_path), tmp_path / "out")
    contact = summary["contact"]
    s0, s_c = contact["crack_rule"]["drained"]["prior"], contact["crack"]["length"]
    assert 0.0 < s0 < s_c < L, (s0, s_c)
    grid = meshio.read(out / "drained_boundary.vtu")
    tags = np.ravel(grid.cell_data["physical_tag"][0])
    base_tag = grid.field_data["base"][0]
    cells = grid.cells[0].data[tags == base_tag]
    uplift = np.ravel(grid.cell_data["uplift_pressure"][0])[tags == base_tag]
    ends = np.sort(grid.points[cells[:, :2], 0], axis=1)
    filled, drained, beyond = ends[:, 1] <= s0, (ends[:, 0] >= s0) & (ends[:, 1] <= s_c), ends[:, 0] >= s_c
    assert filled.sum() >= 2 and beyond.sum() >= 10
    assert uplift[filled] == pytest.approx(H1, rel=1e-12)
    assert np.all(uplift[drained] == 0.0)
    middle = ends[beyond].mean(axis=1)
    assert uplift[beyond] == pytest.approx(H1 * (L - middle) / (L - s0), rel=1e-9)
