"""damfem against GetFEM's Nitsche contact brick on the same gmsh meshes (make bench-peers).

Scene A with its 70 m flood (geo/scene_a.toml): P2, theta = 0, gamma0 = 100, frictionless
contact without regularisation (damfem --semismooth, delta = 0). For each size, `damfem mesh
--order 1` writes an order-1 .msh; GetFEM 5.4 (Debian's python3-getfem, run with
/usr/bin/python3) solves it at P2 from u = 0, and damfem solves the same mesh twice, each in
its own process: from the .msh (`damfem solve --order 2 --semismooth`: Newton starts from the
solution of the P1 problem on the same triangles) and from the .geo at the same size factor
(`damfem solve --size-factor F --semismooth`: gmsh meshes the same mesh, which the
node-by-node comparison checks, and damfem starts Newton by nested iteration on coarser
meshes of the .geo). The three runs of a size follow one another. Per size and damfem input
the table gives the unknowns, the Newton steps of each code (for damfem: on the coarse
levels, coarsest first, + on the given mesh), the time of the contact solve (GetFEM's
Model.solve, which assembles its linear bricks on the first step; damfem's `assemble` and
`solve` stages from summary.json, the latter holding the coarse levels' solves and, from the
.geo, gmsh's meshing of the coarse meshes), the whole process (wall and CPU time,
the latter from wait4 and less sensitive to other loads of the machine; from the .geo it
includes gmsh's meshing of the given mesh, which GetFEM reads from the .msh), the ratios
GetFEM / damfem of the contact solves and of the CPU times (above 1: damfem is faster), the
peak memory of each process (ru_maxrss from wait4), and the largest difference of the two
displacements over the nodes (vertices and midpoints), relative to max |u|. With --repeat N
each code solves each mesh N times and the run with the fastest contact solve is kept.

The two discrete problems coincide: GetFEM's brick takes r = gamma0 / element_size in
P = sigma^n(u) + r (g_obs - u.n) (getfem_contact_and_friction_integral.cc), so its gamma0
is given as the expression gamma0 E element_size / h_F, with h_F the length of each cell's
contact face held in a P0 field; r is then gamma0 E / h_F, damfem's gamma (docs/method.md
§1.3). They differ in quadrature only: damfem splits a contact face where P changes sign
and integrates each piece exactly (docs/method.md §1.6); GetFEM integrates that face with
its plain 4-point Gauss rule. The displacements therefore agree to 1e-5 to 1e-6 max|u|
(the error of one face's rule, falling with h), not to round-off; with the whole base in
contact (no kink) they agree to 1e-11. The benchmark stops if they differ by more than
1e-4 max|u|. Newton tolerances: damfem ||F|| <= 1e-10 ||b||; GetFEM min(|F|_1 / |b|_1,
|du|_1 / |u|_1) <= 1e-10 (its max_res), with line search 'simplest' and MUMPS.

usage: /usr/bin/python3 scripts/bench_peers.py [--large] [--sizes 1e4 1e5 5e5] [--repeat N]
           [--flood H] [--contact-rule RULE] [--damfem PATH] [--out DIR]
       /usr/bin/python3 scripts/bench_peers.py getfem MSH OUT.npz H RULE   (one GetFEM solve)
"""

import argparse
import base64
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
SCENE = REPO / "geo" / "scene_a.toml"
# factors on Scene A's mesh sizes for about 1e4, 1e5 and 5e5 P2 unknowns
SIZES = {"1e4": 0.89, "1e5": 0.275, "5e5": 0.123}

# Scene A (geo/scene_a.toml): material, loads, contact
E, NU, RHO, G = 3.0e10, 0.2, 2400.0, 9.81
WATER, FLOOD = 1000.0, 70.0
GAMMA0 = 100.0
RTOL = 1e-10
# largest accepted max|u_GetFEM - u_damfem| / max|u| (quadrature on the kink, see above)
AGREEMENT = 1e-4
# GetFEM's rule on the contact faces: 4 Gauss points per face, as damfem on each piece
CONTACT_RULE = "IM_TRIANGLE(6)"


def physical_curves(msh):
    """{name: tag} of the physical curves in the $PhysicalNames section of a .msh."""
    lines = Path(msh).read_text().splitlines()
    start = lines.index("$PhysicalNames")
    names = {}
    for line in lines[start + 2 : start + 2 + int(lines[start + 1])]:
        dim, tag, name = line.split(maxsplit=2)
        if dim == "1":
            names[name.strip('"')] = int(tag)
    return names


def getfem_solve(msh, out, flood, rule):
    """Solves Scene A with the water at `flood` [m] on the order-1 mesh `msh` at P2 with
    GetFEM's Nitsche brick, integrating the contact term by `rule`; saves the node
    coordinates, the displacement, the Newton steps and the solve time in `out`."""
    import getfem as gf

    gf.util_trace_level(0)
    gf.util_warning_level(0)
    curves = physical_curves(msh)
    mesh = gf.Mesh("import", "gmsh", str(msh))
    base, toe, upstream = curves["base"], curves["toe"], curves["upstream"]
    for tag in (base, toe, upstream):
        faces = mesh.region(tag)
        assert faces.shape[1] > 0 and faces[1].max() < 3, f"region {tag} of {msh} holds no faces"

    mfu = gf.MeshFem(mesh, 2)
    mfu.set_fem(gf.Fem("FEM_PK(2,2)"))
    # Dirichlet (toe, u = 0): its dofs eliminated by a partial MeshFem
    fixed = set(mfu.basic_dof_on_region(toe))
    kept = np.array([d for d in range(mfu.nbdof()) if d not in fixed])
    mfp = gf.MeshFem("partial", mfu, kept)
    mf1 = gf.MeshFem(mesh, 1)
    mf1.set_fem(gf.Fem("FEM_PK(2,1)"))
    mf0 = gf.MeshFem(mesh, 1)
    mf0.set_fem(gf.Fem("FEM_PK(2,0)"))
    # the bulk rule is exact for the P2 stiffness and the hydrostatic load (degree 3 on a face)
    mim = gf.MeshIm(mesh, gf.Integ("IM_TRIANGLE(4)"))
    mim_contact = gf.MeshIm(mesh, gf.Integ(rule))

    md = gf.Model("real")
    md.add_fem_variable("u", mfp)
    md.add_initialized_data("lambda", [E * NU / ((1 + NU) * (1 - 2 * NU))])
    md.add_initialized_data("mu", [E / (2 * (1 + NU))])
    md.add_isotropic_linearized_elasticity_brick(mim, "u", "lambda", "mu")
    md.add_initialized_data("f", [0.0, -RHO * G])
    md.add_source_term_brick(mim, "u", "f")
    # water pressure p = rho_w g (H_w - y)+ along -n
    md.add_source_term_generic_assembly_brick(
        mim, f"(-{WATER * G}*pos_part({flood}-X(2))*Normal).Test_u", upstream
    )
    # obstacle: the signed distance y to the rock, so the contact normal is (0, -1) and the gap u_y
    md.add_initialized_fem_data("obs", mf1, mf1.basic_dof_nodes()[1])
    md.add_initialized_fem_data("h_F", mf0, contact_face_lengths(mesh, mf0, base))
    md.add_initialized_data("gamma0E", [GAMMA0 * E])
    neumann = md.Neumann_term("u", base)
    md.add_Nitsche_contact_with_rigid_obstacle_brick(
        mim_contact, "u", neumann, "obs", "(gamma0E*element_size/h_F)", base, 0.0
    )

    start = time.perf_counter()
    steps, converged = md.solve(
        "max_res", RTOL, "max_iter", 50, "lsolver", "mumps", "lsearch", "simplest"
    )
    seconds = time.perf_counter() - start
    if not converged:
        sys.exit(f"GetFEM did not converge on {msh} in {steps} steps")
    u = extend(mfp, md.variable("u"))
    np.savez(out, nodes=mfu.basic_dof_nodes()[:, ::2].T, u=u.reshape(-1, 2), steps=steps,
             seconds=seconds, unknowns=mfp.nbdof())


def extend(mfp, u):
    """The displacement at every basic dof of the partial MeshFem (0 at the eliminated ones)."""
    ext = mfp.extension_matrix()
    return np.asarray(ext.mult(u)).ravel()


def contact_face_lengths(mesh, mf0, region):
    """A P0 field holding, on each cell with a face in `region`, the length h_F of that face (1
    elsewhere, where the contact term is not integrated)."""
    h = np.ones(mf0.nbdof())
    faces = mesh.region(region)
    points = mesh.pts()
    for cv, f in faces.T:
        a, b = mesh.pid_in_faces(np.array([[cv], [f]]))
        h[mf0.basic_dof_from_cv(cv)[0]] = np.hypot(*(points[:, a] - points[:, b]))
    return h


def measured(args):
    """Runs `args` in a child and waits with wait4; returns (wall seconds, CPU seconds (user +
    system, all threads), peak resident memory in MiB)."""
    with tempfile.TemporaryFile() as stderr:
        start = time.perf_counter()
        process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=stderr)
        _, status, usage = os.wait4(process.pid, 0)
        seconds = time.perf_counter() - start
        if os.waitstatus_to_exitcode(status) != 0:
            stderr.seek(0)
            sys.exit(f"{' '.join(map(str, args))} failed:\n{stderr.read().decode()}")
    return seconds, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def vtu_array(text, name):
    """A Float64 DataArray of a damfem .vtu (raw binary, base64, UInt64 header), as rows of 3."""
    match = re.search(rf'<DataArray type="Float64" Name="{name}"[^>]*>([^<]*)<', text)
    raw = base64.b64decode(match.group(1))
    return np.frombuffer(raw[8:], dtype="<f8").reshape(-1, 3)


def vtu_points(text):
    """The points of a damfem .vtu (raw binary, base64, UInt64 header), as rows of 3."""
    points = re.search(r'<Points><DataArray type="Float64"[^>]*>([^<]*)<', text)
    return np.frombuffer(base64.b64decode(points.group(1))[8:], dtype="<f8").reshape(-1, 3)


def damfem_displacement(vtu):
    """(nodes, displacement) of a damfem solution file."""
    text = Path(vtu).read_text()
    return vtu_points(text)[:, :2], vtu_array(text, "displacement")[:, :2]


def by_position(nodes):
    """Node order sorted by (x, y) rounded to 1 nm (a midpoint may differ by an ulp)."""
    p = np.round(nodes, 9)
    return np.lexsort((p[:, 1], p[:, 0]))


def difference(getfem, damfem):
    """max over nodes of |u_GetFEM - u_damfem|, relative to max |u_damfem|."""
    (xg, ug), (xd, ud) = getfem, damfem
    assert len(xg) == len(xd), f"{len(xg)} GetFEM nodes against {len(xd)} damfem nodes"
    i, j = by_position(xg), by_position(xd)
    assert np.abs(xg[i] - xd[j]).max() < 1e-9, "the two codes' nodes differ"
    return np.abs(ug[i] - ud[j]).max() / np.abs(ud).max()


def fastest(runs):
    """Of repeated runs [(contact solve, wall, CPU, memory)], the one with the fastest contact solve."""
    return min(runs, key=lambda run: run[0])


def scene_file(path, geometry, flood):
    """Writes Scene A with `geometry` and the water at `flood` [m] to `path`; returns `path`."""
    text = SCENE.read_text()
    assert f"level = {FLOOD}" in text, f"{SCENE} no longer holds the flood of {FLOOD} m"
    path.write_text(text.replace('"scene_a.geo"', f'"{geometry}"').replace(f"level = {FLOOD}", f"level = {flood}"))
    return path


def damfem_solve(damfem, scene, options, out):
    """One `damfem solve --semismooth` of `scene` with `options` into `out`: (contact solve,
    wall, CPU, memory) and its summary.json."""
    run = measured([damfem, "solve", "-q", *options, "--semismooth", scene, "-o", out])
    summary = json.loads((out / "summary.json").read_text())
    return (summary["seconds"]["assemble"] + summary["seconds"]["solve"], *run), summary


def bench(label, factor, args):
    """One size: mesh, solve `args.repeat` times with GetFEM and with damfem from the .msh and
    from the .geo (keeping the fastest of each), compare; returns a row per damfem input."""
    damfem, out, repeat = args.damfem, args.out / label, args.repeat
    out.mkdir(parents=True, exist_ok=True)
    measured([damfem, "mesh", "-q", "--order", "1", "--size-factor", str(factor), SCENE, "-o", out / "mesh"])
    msh = out / "mesh" / "scene_a.msh"
    inputs = {
        ".msh": (scene_file(out / "scene_a_msh.toml", msh, args.flood), ["--order", "2"]),
        ".geo": (scene_file(out / "scene_a_geo.toml", SCENE.parent / "scene_a.geo", args.flood),
                 ["--size-factor", str(factor)]),
    }
    runs = {name: [] for name in ["GetFEM", *inputs]}
    summaries = {}
    for _ in range(repeat):
        getfem = [sys.executable, __file__, "getfem", msh, out / "getfem.npz", str(args.flood), args.contact_rule]
        run = measured(getfem)
        g = np.load(out / "getfem.npz")
        runs["GetFEM"].append((float(g["seconds"]), *run))
        for name, (scene, options) in inputs.items():
            run, summaries[name] = damfem_solve(damfem, scene, options, out / scene.stem)
            runs[name].append(run)
    rows = []
    for name, (scene, _) in inputs.items():
        summary, contact = summaries[name], summaries[name]["contact"]
        assert int(g["unknowns"]) == summary["free_unknowns"], f"GetFEM and damfem ({name}) have different unknowns"
        # the same nodes at the same places: from the .geo, gmsh has meshed the .msh's mesh
        gap = difference((g["nodes"], g["u"]), damfem_displacement(out / scene.stem / f"{scene.stem}.vtu"))
        if gap > AGREEMENT:
            sys.exit(f"{msh}: the displacements of GetFEM and damfem ({name}) differ by {gap:.1e} max|u|")
        rows.append({
            "unknowns": summary["free_unknowns"],
            "input": name,
            "steps": (int(g["steps"]), " + ".join(str(s["newton_steps"]) for s in [*contact["coarse"], contact])),
            "getfem": fastest(runs["GetFEM"]),
            "damfem": fastest(runs[name]),
            "difference": gap,
        })
    return rows


def table(rows):
    """The results as a Markdown table."""
    lines = [
        "| unknowns (P2) | damfem from | Newton steps GetFEM / damfem | contact solve GetFEM / damfem | ratio "
        "| whole process GetFEM / damfem | its CPU time GetFEM / damfem | ratio "
        "| peak memory GetFEM / damfem | max \\|Δu\\| / max \\|u\\| |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        (gs, ds), (gt, gw, gc, gm), (dt, dw, dc, dm) = r["steps"], r["getfem"], r["damfem"]
        lines.append(
            f"| {r['unknowns']} | {r['input']} | {gs} / {ds} | {gt:.2f} s / {dt:.2f} s | {gt / dt:.2f} "
            f"| {gw:.2f} s / {dw:.2f} s | {gc:.2f} s / {dc:.2f} s | {gc / dc:.2f} | {gm:.0f} / {dm:.0f} MiB "
            f"| {r['difference']:.1e} |"
        )
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--large", action="store_true", help="also the 5e5-unknown mesh")
    parser.add_argument("--sizes", nargs="+", choices=list(SIZES), help="these sizes only")
    parser.add_argument("--flood", type=float, default=FLOOD, help="water level [m] (default 70)")
    parser.add_argument("--contact-rule", default=CONTACT_RULE, help="GetFEM's rule on the contact faces")
    parser.add_argument("--repeat", type=int, default=1, help="solves per code and size; the fastest is kept")
    parser.add_argument("--damfem", default=REPO / "target" / "release" / "damfem", type=Path)
    parser.add_argument("--out", default=REPO / "out" / "bench_peers", type=Path)
    args = parser.parse_args()
    sizes = args.sizes or [s for s in SIZES if args.large or s != "5e5"]
    rows, load = [], os.getloadavg()
    for label in sizes:
        for r in bench(label, SIZES[label], args):
            rows.append(r)
            print(f"{r['unknowns']} unknowns: GetFEM {r['getfem'][0]:.2f} s, damfem from the {r['input']} "
                  f"{r['damfem'][0]:.2f} s", file=sys.stderr)
    print(table(rows))
    averages = lambda loads: " ".join(f"{x:.1f}" for x in loads)
    print(f"load average over the last 1, 5 and 15 minutes: {averages(load)} at the start, "
          f"{averages(os.getloadavg())} at the end")


if __name__ == "__main__":
    if len(sys.argv) == 6 and sys.argv[1] == "getfem":
        getfem_solve(Path(sys.argv[2]), Path(sys.argv[3]), float(sys.argv[4]), sys.argv[5])
    else:
        main()
