//! Equilibration and the bound on gmsh meshes: the scenes with contact, Scene B, and V1 on
//! unstructured meshes.

use super::support::*;

use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::verify::v1;

/// Source: geo/scene_a.toml, geo/hertz.toml (docs/method.md §6), solved as the CLI does
/// (src/cli/solve.rs: δ = 10⁻⁴ S with S = problem.stress_scale, γ₀ = 100, θ = 0, one stage).
/// Goal: every equilibration check below 10⁻¹⁰ (relative) on unstructured gmsh meshes with
/// contact, hydrostatic loads and self-weight; the estimator components are reported, and
/// η_tot ≥ dual norm (mesh refined once) is asserted as well.
/// Parameters: Scene A at P1 and P2, Hertz at P2, mesh sizes × 2 (size_factor 2) for speed.
#[test]
fn scenes_with_contact_equilibrate() {
    for (file, order) in [("geo/scene_a.toml", 1), ("geo/scene_a.toml", 2), ("geo/hertz.toml", 2)] {
        let clock = std::time::Instant::now();
        let (problem, tags, run) = scene_with_contact(file, order, 2.0);
        let e = evaluate(&problem, &run.u, run.state(), &tags, Some(1));
        let dual = e.dual.unwrap();
        println!(
            "{file} P{order}: {} cells, delta = {:.3e}, {} Newton steps, contact length {:.4}; {}; dual {dual:.4e}, I_eff {:.3}; worst check {:.1e} ({:.2} s)",
            problem.mesh.n_cells(),
            run.delta,
            run.newton_steps,
            run.contact_length,
            components(&e.est),
            e.est.tot / dual,
            e.eq.worst(order),
            clock.elapsed().as_secs_f64()
        );
        println!("    {:?}", e.eq);
        assert!(e.eq.worst(order) < 1e-10, "{file} P{order}: {:?}", e.eq);
        assert!(e.est.tot >= dual, "{file} P{order}: bound violated, eta {} < dual {dual}", e.est.tot);
    }
}

/// Source: geo/scene_b.toml (docs/method.md §6): the dam bonded to a rock block, two
/// materials, the rock clamped at the bottom and on rollers (u_x = 0) on its sides, hydrostatic
/// water on the upstream face and the reservoir floor, self-weight; no contact (a linear solve).
/// Goal: every equilibration check below 10⁻¹⁰ with rollers and a material interface.
/// Parameters: P1 and P2, mesh sizes × 2.
#[test]
fn scene_b_equilibrates() {
    for order in [1, 2] {
        let clock = std::time::Instant::now();
        let (scene, mesh) = scene_mesh("geo/scene_b.toml", order, 2.0);
        let (problem, _) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
        assert!(problem.dirichlet.iter().any(|bc| bc.fix == [true, false]), "scene B has rollers");
        let u = solve_linear(&problem);
        let e = evaluate(&problem, &u, None, &[], None);
        println!(
            "scene B P{order}: {} cells; {}; worst check {:.1e} ({:.2} s)",
            problem.mesh.n_cells(),
            components(&e.est),
            e.eq.worst(order),
            clock.elapsed().as_secs_f64()
        );
        println!("    {:?}", e.eq);
        assert!(e.eq.worst(order) < 1e-10, "scene B P{order}: {:?}", e.eq);
    }
}

/// Source: docs/method.md §7 V1 (src/verify/v1.rs) on geo/unit_square.geo meshed by gmsh
/// (Frontal-Delaunay, unstructured), Dirichlet data on the curves bottom, right, top, left.
/// Goal: equilibration below 10⁻¹⁰ and η_tot ≥ dual norm on unstructured meshes.
/// Parameters: p = 1, 2; size_factor 1 (h = 1/8) and 0.5 (h = 1/16); dual norm on the mesh
/// refined once.
#[test]
fn v1_on_gmsh_meshes() {
    let geo = manifest("geo/unit_square.geo");
    for order in [1, 2] {
        for size_factor in [1.0, 0.5] {
            let options = MeshOptions { order, size_factor, ..Default::default() };
            let mesh = mesh_geo(&geo, &options, false, false).unwrap_or_else(|e| panic!("{e}"));
            let tags: Vec<i32> = ["bottom", "right", "top", "left"]
                .iter()
                .map(|name| mesh.group(1, name).unwrap_or_else(|| panic!("physical curve {name}")).tag)
                .collect();
            let problem = v1::problem(mesh, &tags);
            let u = solve_linear(&problem);
            let e = evaluate(&problem, &u, None, &[], Some(1));
            let dual = e.dual.unwrap();
            println!(
                "V1 gmsh P{order} size factor {size_factor}: {} cells; eta {:.4e} (osc {:.2e}, flux {:.3e}), dual {dual:.4e}, I_eff {:.3}; worst check {:.1e}",
                problem.mesh.n_cells(),
                e.est.tot,
                e.est.osc,
                e.est.flux,
                e.est.tot / dual,
                e.eq.worst(order)
            );
            assert!(e.eq.worst(order) < 1e-10, "P{order} size factor {size_factor}: {:?}", e.eq);
            assert!(
                e.est.tot >= dual,
                "P{order} size factor {size_factor}: bound violated, eta {} < {dual}",
                e.est.tot
            );
        }
    }
}
