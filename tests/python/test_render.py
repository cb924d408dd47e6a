"""Off-screen rendering of Scene A's von Mises field with pyvista."""

import importlib.util
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv

pv.OFF_SCREEN = True

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "scripts" / "render.py"


def test_render_von_mises(solved, tmp_path):
    # a PNG of the warped von Mises field is written and is not a uniform image
    out, summary = solved("scene_a", 2)
    grid = pv.read(out / "scene_a.vtu")
    factor = 0.05 * grid.length / summary["max_displacement"]
    warped = grid.warp_by_vector("displacement", factor=factor)
    plotter = pv.Plotter(off_screen=True, window_size=(640, 480))
    plotter.add_mesh(warped, scalars="von_mises", preference="cell")
    plotter.view_xy()
    png = tmp_path / "scene_a_von_mises.png"
    image = plotter.screenshot(png, return_img=True)
    plotter.close()
    assert png.is_file() and png.stat().st_size > 0
    colours = np.unique(image.reshape(-1, image.shape[-1]), axis=0)
    assert len(colours) > 20


def load_render():
    spec = importlib.util.spec_from_file_location("render", Path(__file__).parents[2] / "scripts" / "render.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_render_script_default_range_excludes_singular_cells(damfem, solved, tmp_path):
    # scripts/render.py colours the von Mises field of Scene A over a range that leaves out
    # the singular cells (the maximum is many times the 99th percentile), labels the colour
    # bar in MPa, and draws a PNG with more than a flat colour
    out, summary = solved("scene_a", 2)
    render = load_render()
    grid = pv.read(out / "scene_a.vtu")
    values = render.field_values(grid, "von_mises")
    areas = np.asarray(grid.compute_cell_sizes(length=False, volume=False).cell_data["Area"])
    low, high = render.colour_range(values, areas)
    assert values.max() == pytest.approx(summary["max_von_mises"] / 1e6, rel=1e-9)
    assert low >= values.min() and high < values.max() / 2
    assert areas[values > high].sum() <= 0.011 * areas.sum()
    assert render.field_label("von_mises") == "von_mises [MPa]"
    assert render.field_label("eta_tot") == "eta_tot [Pa m]"
    png = tmp_path / "scene_a.png"
    subprocess.run([sys.executable, str(Path(render.__file__)), str(out / "scene_a.vtu"), str(png)], check=True,
                   capture_output=True)
    image = pv.read(png).point_data.active_scalars
    assert len(np.unique(image.reshape(len(image), -1), axis=0)) > 20


def test_render_script_marks_the_anchored_toe(solved):
    # the clamped facets of Scene A are its anchored toe, x from 32 to 40 m at y = 0
    out, _ = solved("scene_a", 2)
    render = load_render()
    boundary = pv.read(out / "scene_a_boundary.vtu")
    toe = boundary.extract_cells(render.anchored(boundary))
    assert toe.n_cells > 0
    assert np.allclose(toe.points[:, 1], 0.0)
    assert toe.points[:, 0].min() == pytest.approx(32.0) and toe.points[:, 0].max() == pytest.approx(40.0)
    assert toe.compute_cell_sizes().cell_data["Length"].sum() == pytest.approx(8.0)


def without_venv():
    """The environment with no Python environment on PATH: `python3` is the system's."""
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH", "PYTHONHOME")}
    venvs = {Path(sys.prefix).resolve(), (REPO / ".venv").resolve()}
    keep = [p for p in env.get("PATH", "").split(os.pathsep) if not any(v in Path(p).resolve().parents for v in venvs)]
    env["PATH"] = os.pathsep.join(keep or ["/usr/bin", "/bin"])
    return env


def readme_render_commands():
    """Every command line of the README that runs scripts/render.py on named files."""
    text = (REPO / "README.md").read_text()
    return [c for c in re.findall(r"`(scripts/render\.py [^`]+)`", text) if "|" not in c and "RESULT" not in c]


def colours(png):
    image = pv.read(png).point_data.active_scalars
    return len(np.unique(image.reshape(len(image), -1), axis=0))


def test_readme_render_command_runs_as_written(solved, tmp_path):
    # the README's command lines run as written from a directory holding scripts/ and the
    # result they name, under the system's python3 (the script's first line): the script
    # starts itself again under .venv and draws a picture titled with the scene
    assert os.access(SCRIPT, os.X_OK), "scripts/render.py has no execute bit"
    assert SCRIPT.read_text().startswith("#!/usr/bin/env python3\n")
    commands = readme_render_commands()
    assert commands, "the README has no scripts/render.py command on named files"
    out, _ = solved("scene_a", 2)
    (tmp_path / "scripts").symlink_to(REPO / "scripts")
    for command in commands:
        args = shlex.split(command)
        result = tmp_path / args[1]
        result.parent.mkdir(parents=True, exist_ok=True)
        if result.suffix == ".pvd":
            # a collection of one step, the solved result
            result.write_text('<VTKFile type="Collection"><Collection>'
                              f'<DataSet timestep="0" file="{result.stem}_00.vtu"/></Collection></VTKFile>')
            result = result.with_name(f"{result.stem}_00.vtu")
        shutil.copy(out / "scene_a.vtu", result)
        shutil.copy(out / "scene_a_boundary.vtu", result.with_name(result.stem + "_boundary.vtu"))
        shutil.copy(out / "summary.json", result.parent / "summary.json")
        done = subprocess.run(args, cwd=tmp_path, env=without_venv(), capture_output=True, text=True)
        assert done.returncode == 0, f"{command}: {done.stderr}"
        assert colours(tmp_path / args[2]) > 20, command


def test_without_the_venv_the_script_says_to_make_deps(tmp_path):
    # a copy of the script whose repository has no .venv, started by the system's python3
    # without numpy, stops with one line naming the environment and `make deps`
    env = without_venv()
    python = shutil.which("python3", path=env["PATH"])
    has_numpy = python and subprocess.run([python, "-c", "import numpy, pyvista, matplotlib"], env=env,
                                          capture_output=True).returncode == 0
    if not python or has_numpy:
        pytest.skip("the system's python3 has numpy, pyvista and matplotlib: nothing to re-execute")
    (tmp_path / "scripts").mkdir()
    copy = tmp_path / "scripts" / "render.py"
    shutil.copy(SCRIPT, copy)
    done = subprocess.run([str(copy), "a.vtu", "a.png"], env=env, capture_output=True, text=True)
    assert done.returncode != 0
    assert "make deps" in done.stderr and str(tmp_path / ".venv") in done.stderr, done.stderr


def test_title_names_scene_combination_and_step(tmp_path):
    # the title reads the scene and the combination from summary.json, the step (from 0, as
    # damfem numbers them) from the .pvd or the step file's name
    render = load_render()
    (tmp_path / "summary.json").write_text(json.dumps({"scene": "geo/dam.toml", "combination": "flood"}))
    pvd = tmp_path / "dam.pvd"
    pvd.write_text('<VTKFile type="Collection"><Collection><DataSet timestep="0" file="dam_00.vtu"/>'
                   '<DataSet timestep="1" file="dam_01.vtu"/></Collection></VTKFile>')
    result, step = render.last_step(pvd)
    assert result == tmp_path / "dam_01.vtu" and step == (1, 2)
    assert render.title(result, step) == "scene dam, combination flood, step 1, the last of 2"
    (tmp_path / "summary.json").unlink()
    assert render.title(tmp_path / "dam_01.vtu", render.last_step(tmp_path / "dam_01.vtu")[1]) == "scene dam, step 1"


def test_box_keeps_the_cells_across_its_edges_and_corners():
    # a cell with its centre outside the box but a corner inside is drawn
    render = load_render()
    points = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [5.0, 5.0], [6.0, 5.0], [5.0, 6.0]])
    triangles = np.array([[0, 1, 2], [3, 4, 5]])
    assert render.in_view(points, triangles, (1.5, 3.0, -1.0, 0.5)).tolist() == [True, False]


def test_auto_warp_leaves_several_bodies_undeformed(solved):
    # on a dam on a meshed rock block the automatic magnification is none; on Scene A, 5 %
    render = load_render()
    out, summary = solved("scene_a", 2)
    grid = pv.read(out / "scene_a.vtu")
    assert render.warp_factor(grid, "auto") == pytest.approx(0.05 * grid.length / summary["max_displacement"])
    out, _ = solved("dam_on_rock", None)
    assert render.warp_factor(pv.read(out / "dam_on_rock.vtu"), "auto") == 0.0
    assert render.warp_factor(grid, "3") == 3.0
