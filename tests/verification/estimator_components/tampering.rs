//! The checks can fail: a tampered reconstruction violates them.

use super::support::*;

use damfem::contact::projection::Smoothing;
use damfem::contact::{ContactJoint, Continuation, Linearisation};
use damfem::elasticity::Displacement;
use damfem::estimate::afw::COMPONENTS;
use damfem::estimate::checks::{check, Equilibration};
use damfem::estimate::reconstruction::{reconstruct, Reconstruction};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::{Mesh, Topology};
use damfem::solve::NewtonOptions;
use damfem::verify::rng::Rng;
use damfem::verify::{v1, v3};

/// Adds `scale` × a pseudo-random vector to the coefficients of component `i` on `cells`.
fn perturb(rec: &mut Reconstruction, i: usize, cells: &[usize], scale: f64, random: &mut Rng) {
    let n = COMPONENTS * rec.n_basis;
    for &c in cells {
        for v in &mut rec.sigma[i][c * n..(c + 1) * n] {
            *v += scale * random.symmetric();
        }
    }
}

/// The index in `topology.vertices` of the vertex nearest to x.
fn vertex_near(mesh: &Mesh, topology: &Topology, x: [f64; 2]) -> usize {
    let d = |k: &usize| damfem::geometry::distance(mesh.points[topology.vertices[*k]], x);
    (0..topology.vertices.len()).min_by(|a, b| d(a).total_cmp(&d(b))).unwrap()
}

fn print_checks(label: &str, eq: &Equilibration) {
    println!(
        "{label:46} divergence {:.2e}  continuity {:.2e}  Neumann {:.2e}  contact {:.2e}  symmetry {:.2e}",
        eq.divergence, eq.normal_continuity, eq.neumann, eq.contact, eq.weak_symmetry
    );
}

/// Source: src/estimate/checks.rs (E1)–(E3).
/// Goal: the checks detect a broken reconstruction. A valid one is below 10⁻¹⁰; perturbing the
/// coefficients of one patch by 10⁻⁶ × a random vector raises normal continuity and divergence
/// far above it; a perturbation of one boundary patch raises the Neumann check; moving a
/// random field from σ_h2 to σ_h3 on one contact cell (σ_h unchanged) is seen by the contact
/// check alone.
/// Parameters: V1, structured n = 4, P2, the patch of the interior vertex (0.5, 0.5); V3 (n = 4,
/// P2, δ = 10⁻³, converged), the patch of the vertex (1, 0.5) on the Neumann side and the
/// cell of the contact face nearest to (0.25, 0); the seeded generator.
#[test]
fn tampered_reconstruction_fails_the_checks() {
    let mut random = Rng::new(0x9e37_79b9_7f4a_7c15);
    // V1: interior patch
    let problem = v1::problem(unit_square(4, 2), &[BOTTOM, RIGHT, TOP, LEFT]);
    let u = Displacement::from(solve_linear(&problem));
    let topology = Topology::new(&problem.mesh);
    let mut rec = reconstruct(&problem, &topology, &u, None).unwrap();
    let valid = check(&problem, &topology, &u, &rec, None);
    print_checks("V1 P2 n = 4, valid", &valid);
    assert!(valid.worst(2) < 1e-10, "{valid:?}");
    let k = vertex_near(&problem.mesh, &topology, [0.5, 0.5]);
    let cells = topology.patch(k).to_vec();
    perturb(&mut rec, 0, &cells, 1e-6, &mut random);
    let broken = check(&problem, &topology, &u, &rec, None);
    print_checks(&format!("V1, sigma_h1 + 1e-6 random on {} cells", cells.len()), &broken);
    assert!(broken.normal_continuity > 1e-8, "{broken:?}");
    assert!(broken.divergence > 1e-8, "{broken:?}");
    assert!(broken.worst(2) > 1e3 * valid.worst(2).max(1e-14), "{broken:?}");

    // V3: a patch on the Neumann side and the σ_h2/σ_h3 split on Γ_C
    let problem = v3::problem(unit_square(4, 2));
    let disc = problem.discretise();
    let joint = ContactJoint::frictionless(vec![BOTTOM], crate::nitsche_parameters());
    let settings = Continuation { delta: 1e-3, delta_start: 0.1, newton: NewtonOptions::default(), path: None };
    let run = solve_with_contact(&problem, &disc, &joint, &settings);
    let state =
        Linearisation { nitsche: &run.nitsche, smoothing: Smoothing { delta: run.delta }, u_prev: run.u_prev.clone() };
    let topology = Topology::new(&problem.mesh);
    let u = Displacement::from(run.u.clone());
    let valid_rec = reconstruct(&problem, &topology, &u, Some(&state)).unwrap();
    let valid = check(&problem, &topology, &u, &valid_rec, Some(&state));
    print_checks("V3 P2 n = 4, valid", &valid);
    assert!(valid.worst(2) < 1e-10, "{valid:?}");

    let mut rec = reconstruct(&problem, &topology, &u, Some(&state)).unwrap();
    let k = vertex_near(&problem.mesh, &topology, [1.0, 0.5]);
    let cells = topology.patch(k).to_vec();
    perturb(&mut rec, 0, &cells, 1e-6, &mut random);
    let broken = check(&problem, &topology, &u, &rec, Some(&state));
    print_checks(&format!("V3, Neumann patch + 1e-6 random on {} cells", cells.len()), &broken);
    assert!(broken.neumann > 1e-8, "{broken:?}");

    let mut rec = reconstruct(&problem, &topology, &u, Some(&state)).unwrap();
    let face = run
        .nitsche
        .faces
        .iter()
        .min_by(|a, b| {
            let d = |f: &damfem::contact::nitsche::ContactFace| {
                let m = f.map.to_physical([0.5 * (f.ends[0][0] + f.ends[1][0]), 0.5 * (f.ends[0][1] + f.ends[1][1])]);
                damfem::geometry::distance(m, [0.25, 0.0])
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let n = COMPONENTS * rec.n_basis;
    let shift: Vec<f64> = (0..n).map(|_| 1e-6 * random.symmetric()).collect();
    for (j, v) in shift.iter().enumerate() {
        rec.sigma[1][face.cell * n + j] += v;
        rec.sigma[2][face.cell * n + j] -= v;
    }
    let broken = check(&problem, &topology, &u, &rec, Some(&state));
    print_checks("V3, 1e-6 random moved sigma_h3 -> sigma_h2", &broken);
    assert!(broken.contact > 1e-8, "{broken:?}");
    for (name, v) in
        [("divergence", broken.divergence), ("continuity", broken.normal_continuity), ("Neumann", broken.neumann)]
    {
        assert!(v < 1e-10, "{name} changed although sigma_h is unchanged: {broken:?}");
    }
}
