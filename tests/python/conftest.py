"""Fixtures of the Python tests: the damfem binary and cached runs of its solve and mesh commands."""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def scene(name):
    """The scene file geo/<name>.toml."""
    return REPO / "geo" / f"{name}.toml"


def physical_names(msh):
    """{name: (dim, tag)} from the $PhysicalNames section of a gmsh .msh file."""
    lines = Path(msh).read_text().splitlines()
    start = lines.index("$PhysicalNames")
    groups = {}
    for line in lines[start + 2 : start + 2 + int(lines[start + 1])]:
        dim, tag, name = line.split(maxsplit=2)
        groups[name.strip('"')] = (int(dim), int(tag))
    return groups


@pytest.fixture(scope="session")
def damfem():
    """Path of the binary: $DAMFEM, else <repo>/target/release/damfem."""
    path = Path(os.environ.get("DAMFEM", REPO / "target" / "release" / "damfem"))
    if not path.is_file():
        pytest.fail(f"{path} not found: run `cargo build --release` or set DAMFEM")
    return path


def _run(args):
    done = subprocess.run(args, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(map(str, args))} failed:\n{done.stderr}"
    return done


@pytest.fixture(scope="session")
def solve(damfem):
    """solve(scene, out_dir, order=None) runs `damfem solve -q`; returns (out_dir, summary)."""

    def run(scene_path, out_dir, order=None):
        args = [damfem, "solve", "-q", scene_path, "-o", out_dir]
        if order is not None:
            args += ["--order", str(order)]
        _run(args)
        return Path(out_dir), json.loads((Path(out_dir) / "summary.json").read_text())

    return run


@pytest.fixture(scope="session")
def mesh(damfem):
    """mesh(scene, out_dir, order=None) runs `damfem mesh -q`; returns the path of the .msh."""

    def run(scene_path, out_dir, order=None):
        args = [damfem, "mesh", "-q", scene_path, "-o", out_dir]
        if order is not None:
            args += ["--order", str(order)]
        _run(args)
        return Path(out_dir) / f"{Path(scene_path).stem}.msh"

    return run


@pytest.fixture(scope="session")
def solved(solve, tmp_path_factory):
    """solved(name, order) solves geo/<name>.toml once per session; returns (out_dir, summary)."""
    cache = {}

    def get(name, order=None):
        if (name, order) not in cache:
            out = tmp_path_factory.mktemp(f"{name}-P{order or 'scene'}")
            cache[name, order] = solve(scene(name), out, order)
        return cache[name, order]

    return get


@pytest.fixture(scope="session")
def scene_a_msh(mesh, tmp_path_factory):
    """The .msh of Scene A at P2, written by `damfem mesh`."""
    return mesh(scene("scene_a"), tmp_path_factory.mktemp("scene_a-mesh"), order=2)


@pytest.fixture(scope="session")
def scene_a_groups(scene_a_msh):
    """Scene A's physical groups, {name: (dim, tag)}, read from its .msh."""
    return physical_names(scene_a_msh)
