"""damfem against GetFEM on the same gmsh mesh of a solid (make bench-peers-solid).

The monolith of geo/monolith.toml (the Scene A section extruded by 15 m on a rock block,
bonded, rollers u_y = 0 on both sides, the rock clamped at its base and on rollers u_x = 0 at
its ends, gravity), with the reservoir raised from 45 m to 60 m, above the crest, so that the
whole upstream face is wet and the two discrete problems are the same: damfem cuts a face
where the water plane crosses it and integrates the pressure's kink exactly (docs/method.md
§1.14), GetFEM would integrate it with its face rule (at 45 m the two then differ by
7·10⁻⁴ max |u|, at 60 m by round-off). In P2. For each size, `damfem mesh --order 1`
writes an order-1 .msh, which gmsh converts to its format 2 (GetFEM 5.4 takes the physical
tags as regions only from that format); GetFEM (Debian's python3-getfem, run with
/usr/bin/python3) solves it at P2 with its linear elasticity brick and MUMPS, the Dirichlet
dofs eliminated as damfem eliminates them, and damfem solves the same file (`--order 2`:
raised as gmsh raises it) with its direct solver (sparse Cholesky) and with its iterative one
(CG with PETSc's GAMG), each run in its own process, one after the other. Per size the table
gives the unknowns, the time of the linear solve (GetFEM's Model.solve, which assembles; damfem's
`assemble` and `solve` stages from summary.json), the whole process (wall and CPU time from
wait4), the ratio GetFEM / damfem of the solves (above 1: damfem is faster), the peak memory
of each process and the largest difference of the displacements over the nodes, relative to
max |u|.

usage: /usr/bin/python3 scripts/bench_peers_solid.py [--sizes 2e4 1e5 4e5] [--damfem PATH] [--out DIR]
       /usr/bin/python3 scripts/bench_peers_solid.py getfem MSH OUT.npz   (one GetFEM solve)
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_peers import measured, vtu_array, vtu_points  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
SCENE = REPO / "geo" / "monolith.toml"
# factors on the monolith's mesh sizes for about 2e4, 1e5 and 4e5 P2 unknowns
SIZES = {"2e4": 1.0, "1e5": 0.5, "4e5": 0.35}
# geo/monolith.toml: materials (E, nu, rho), gravity, water level, supports
MATERIALS = {"concrete": (3.0e10, 0.2, 2400.0), "rock": (2.0e10, 0.25, 2600.0)}
G, WATER, LEVEL = 9.81, 1000.0, 60.0
SUPPORTS = [("rock_base", (0, 1, 2)), ("rock_ends", (0,)), ("sides", (1,)), ("rock_sides", (1,))]
# largest accepted max|u_GetFEM - u_damfem| / max|u|: round-off, and the CG's tolerance 1e-10
AGREEMENT = {"direct": 1e-10, "iterative": 1e-8}


def physical_groups(msh):
    """{name: tag} of the $PhysicalNames of a .msh."""
    lines = Path(msh).read_text().splitlines()
    start = lines.index("$PhysicalNames")
    return {line.split(maxsplit=2)[2].strip('"'): int(line.split()[1])
            for line in lines[start + 2 : start + 2 + int(lines[start + 1])]}


def getfem_solve(msh, out):
    """Solves the monolith on the order-1 mesh `msh` (gmsh format 2) at P2; saves the nodes, the
    displacement, the unknowns and the solve time in `out`."""
    import getfem as gf

    gf.util_trace_level(0)
    gf.util_warning_level(0)
    names = physical_groups(msh)
    mesh = gf.Mesh("import", "gmsh", str(msh))
    mfu = gf.MeshFem(mesh, 3)
    mfu.set_fem(gf.Fem("FEM_PK(3,2)"))
    # the vector dofs of a node are consecutive: component d % 3
    fixed = set()
    for name, components in SUPPORTS:
        fixed |= {d for d in mfu.basic_dof_on_region(names[name]) if d % 3 in components}
    mfp = gf.MeshFem("partial", mfu, np.array([d for d in range(mfu.nbdof()) if d not in fixed]))
    mf0 = gf.MeshFem(mesh, 1)
    mf0.set_fem(gf.Fem("FEM_PK(3,0)"))
    lam, mu, rho = (np.zeros(mf0.nbdof()) for _ in range(3))
    for name, (e, nu, density) in MATERIALS.items():
        for cv in mesh.region(names[name])[0]:
            d = mf0.basic_dof_from_cv(cv)[0]
            lam[d], mu[d], rho[d] = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu)), density
    md = gf.Model("real")
    md.add_fem_variable("u", mfp)
    for name, values in [("lambda", lam), ("mu", mu), ("rho", rho)]:
        md.add_initialized_fem_data(name, mf0, values)
    # exact for the P2 stiffness (degree 2) and the weight; degree 3 for the water on a face
    md.add_isotropic_linearized_elasticity_brick(gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(2)")), "u", "lambda", "mu")
    md.add_source_term_generic_assembly_brick(gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(2)")), f"-rho*{G}*Test_u(3)")
    md.add_source_term_generic_assembly_brick(
        gf.MeshIm(mesh, gf.Integ("IM_TETRAHEDRON(3)")),
        f"(-{WATER * G}*pos_part({LEVEL}-X(3))*Normal).Test_u", names["upstream"])
    start = time.perf_counter()
    md.solve("lsolver", "mumps")
    seconds = time.perf_counter() - start
    u = np.asarray(mfp.extension_matrix().mult(md.variable("u"))).ravel()
    np.savez(out, nodes=mfu.basic_dof_nodes()[:, ::3].T, u=u.reshape(-1, 3), seconds=seconds,
             unknowns=mfp.nbdof())


def difference(getfem, damfem):
    """max over nodes of |u_GetFEM - u_damfem|, relative to max |u_damfem|, nodes matched by
    position (rounded to 1 nm)."""
    (xg, ug), (xd, ud) = getfem, damfem
    assert len(xg) == len(xd), f"{len(xg)} GetFEM nodes against {len(xd)} damfem nodes"
    order = lambda x: np.lexsort(np.round(x, 9).T[::-1])
    i, j = order(xg), order(xd)
    assert np.abs(xg[i] - xd[j]).max() < 1e-9, "the two codes' nodes differ"
    return np.abs(ug[i] - ud[j]).max() / np.abs(ud).max()


def bench(label, factor, args):
    """One size: mesh, solve with GetFEM and with damfem's two solvers, compare; one row per solver."""
    damfem, out = args.damfem, args.out / label
    out.mkdir(parents=True, exist_ok=True)
    measured([damfem, "mesh", "-q", "--order", "1", "--size-factor", str(factor), SCENE, "-o", out / "mesh"])
    msh = out / "monolith_v2.msh"
    subprocess.run(["gmsh", "-0", out / "mesh" / "monolith.msh", "-format", "msh2", "-o", msh],
                   check=True, stdout=subprocess.DEVNULL)
    scene = out / "monolith.toml"
    text = SCENE.read_text()
    assert "level = 45.0" in text, f"{SCENE} no longer holds the reservoir at 45 m"
    text = text.replace('"monolith.geo"', f'"{msh}"').replace("order = 1", "order = 2")
    scene.write_text(text.replace("level = 45.0", f"level = {LEVEL}"))
    getfem = measured([sys.executable, __file__, "getfem", msh, out / "getfem.npz"])
    g = np.load(out / "getfem.npz")
    rows = []
    for solver in ["direct", "iterative"]:
        run = measured([damfem, "solve", "-q", "--solver", solver, scene, "-o", out / solver])
        summary = json.loads((out / solver / "summary.json").read_text())
        assert int(g["unknowns"]) == summary["free_unknowns"], "GetFEM and damfem have different unknowns"
        text = (out / solver / "monolith.vtu").read_text()
        gap = difference((g["nodes"], g["u"]), (vtu_points(text), vtu_array(text, "displacement")))
        if gap > AGREEMENT[solver]:
            sys.exit(f"{msh}: the displacements of GetFEM and damfem ({solver}) differ by {gap:.1e} max|u|")
        seconds = summary["seconds"]["assemble"] + summary["seconds"]["solve"]
        rows.append((summary["free_unknowns"], solver, summary.get("iterations"), (float(g["seconds"]), *getfem),
                     (seconds, *run), gap))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", nargs="+", choices=list(SIZES), default=["2e4", "1e5"])
    parser.add_argument("--damfem", default=REPO / "target" / "release" / "damfem", type=Path)
    parser.add_argument("--out", default=REPO / "out" / "bench_peers_solid", type=Path)
    args = parser.parse_args()
    print("| unknowns (P2) | damfem's solver | CG iterations | solve GetFEM / damfem | ratio "
          "| whole process GetFEM / damfem | its CPU time GetFEM / damfem | peak memory GetFEM / damfem "
          "| max \\|Δu\\| / max \\|u\\| |")
    print("|---|---|---|---|---|---|---|---|---|")
    for label in args.sizes:
        for n, solver, its, (gt, gw, gc, gm), (dt, dw, dc, dm), gap in bench(label, SIZES[label], args):
            print(f"| {n} | {solver} | {its or '—'} | {gt:.2f} s / {dt:.2f} s | {gt / dt:.2f} | {gw:.2f} s / {dw:.2f} s "
                  f"| {gc:.2f} s / {dc:.2f} s | {gm:.0f} / {dm:.0f} MiB | {gap:.1e} |", flush=True)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "getfem":
        getfem_solve(Path(sys.argv[2]), Path(sys.argv[3]))
    else:
        main()
