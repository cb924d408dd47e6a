//! The terms that must vanish exactly: η_osc and η_Neu for polynomial data, the whole estimate
//! at exact solutions; hydrostatic loads with a kink inside a facet.

use super::support::*;

use damfem::elasticity::{BodyForce, Material, Neumann, Problem, Traction};
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::mesh::structured::{rectangle, unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::mesh::{Mesh, Topology};
use damfem::scene::Scene;
use damfem::verify::v1;
use std::sync::Arc;

/// |Ω| and the largest cell diameter.
fn area_and_size(mesh: &Mesh) -> (f64, f64) {
    let area = (0..mesh.n_cells()).map(|c| mesh.cell_area(c).abs()).sum();
    let h = (0..mesh.n_cells()).map(|c| mesh.cell_diameter(c)).fold(0.0, f64::max);
    (area, h)
}

/// √h_max · ‖g‖_{L²(Γ_N)} sampled at the facet midpoints: the scale of η_Neu.
fn neumann_scale(problem: &Problem) -> f64 {
    let (mesh, topology) = (&problem.mesh, Topology::new(&problem.mesh));
    let (_, h) = area_and_size(mesh);
    let mut sum = 0.0;
    for bc in &problem.neumann {
        for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
            let n = mesh.facet(f);
            let (a, b) = (mesh.points[n[0]], mesh.points[n[1]]);
            let g = bc.traction.at([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])], topology.outward_normal(mesh, f));
            sum += (g[0] * g[0] + g[1] * g[1]) * mesh.facet_length(f);
        }
    }
    h.sqrt() * sum.sqrt()
}

/// Source: docs/method.md §5 and src/estimate/estimators.rs: η_osc,T = (h_T/π)‖f − Π^{p−1}f‖_T
/// vanishes for piecewise constant f, η_Neu for tractions that are polynomials of degree ≤ p
/// on every face (hydrostatic pressure below the water level, constant tractions).
/// Goal: (a) η_osc = η_Neu = 0 exactly on Scene A (self-weight, flood level 70 m above the
/// 50 m crest, so every facet of the upstream face is below water), P1 and P2; (b) the same
/// data given as general fields (BodyForce::Field, Traction::Field), which the estimator does
/// integrate, give round-off only (relative to (h/π)‖f‖_Ω and h^{1/2}‖g_N‖_{Γ_N}); (c) a water
/// level inside the upstream face (30.3 m) gives η_Neu > 0 (the pressure has a kink in one
/// facet). Equilibration < 10⁻¹⁰ is asserted for (a) and (b); (c) is
/// [`kinked_hydrostatic_load_equilibrates`].
/// Parameters: geo/scene_a.toml, mesh sizes × 2, CLI contact settings.
#[test]
fn zero_oscillation_and_neumann_terms_on_scene_a() {
    for order in [1, 2] {
        let (problem, tags, run) = scene_with_contact("geo/scene_a.toml", order, 2.0);
        let e = evaluate(&problem, &run.u, run.state(), &tags, None);
        println!("scene A P{order} (gravity, hydrostatic level 70): {}", components(&e.est));
        assert_eq!(e.est.osc, 0.0, "P{order}: eta_osc with self-weight");
        assert_eq!(e.est.neu, 0.0, "P{order}: eta_Neu with the whole upstream face under water");
        assert!(e.eq.worst(order) < 1e-10, "P{order}: {:?}", e.eq);

        // the same data as general fields
        let BodyForce::Acceleration([_, minus_g]) = problem.body_force else { panic!("scene A has self-weight") };
        let g = -minus_g;
        let weight = problem.materials[0].density * g;
        assert!(problem.materials.iter().all(|m| m.density * g == weight), "one material");
        let mut fields = problem.clone();
        fields.body_force = BodyForce::Field(Arc::new(move |_| [0.0, -weight]));
        let mut levels = Vec::new();
        for bc in &mut fields.neumann {
            let Traction::Hydrostatic { density, gravity, level } = bc.traction else { continue };
            levels.push(level);
            // the upstream face is x = 0 with outward normal (−1, 0): g_N = −p n = (p, 0)
            bc.traction = Traction::Field(Arc::new(move |x| [density * gravity * (level - x[1]).max(0.0), 0.0]));
        }
        assert_eq!(levels, [70.0], "scene A: one hydrostatic curve");
        let f = evaluate(&fields, &run.u, run.state(), &tags, None);
        let (area, h) = area_and_size(&problem.mesh);
        let (osc_scale, neu_scale) = (h / std::f64::consts::PI * weight * area.sqrt(), neumann_scale(&fields));
        println!(
            "scene A P{order} as fields: eta_osc {:.3e} (relative {:.1e}), eta_Neu {:.3e} (relative {:.1e}), eta_tot {:.4e} vs {:.4e}",
            f.est.osc,
            f.est.osc / osc_scale,
            f.est.neu,
            f.est.neu / neu_scale,
            f.est.tot,
            e.est.tot
        );
        assert!(f.est.osc <= 1e-12 * osc_scale, "P{order}: eta_osc of a constant field {}", f.est.osc);
        assert!(f.est.neu <= 1e-12 * neu_scale, "P{order}: eta_Neu of a linear field {}", f.est.neu);
        assert!((f.est.tot - e.est.tot).abs() <= 1e-10 * e.est.tot, "P{order}: eta_tot changed");
        assert!(f.eq.worst(order) < 1e-10, "P{order} fields: {:?}", f.eq);

        // a water level inside the upstream face: a kink of g_N inside one face
        let (low, l) = scene_a_low_water(&problem, &tags);
        println!(
            "scene A P{order}, water level 30.3: {} (eta_Neu relative {:.2e}); worst check {:.1e}",
            components(&l.est),
            l.est.neu / neumann_scale(&low),
            l.eq.worst(order)
        );
        assert!(l.est.neu > 1e-6 * neumann_scale(&low), "P{order}: eta_Neu {} with a kink in a face", l.est.neu);
    }
}

/// Scene A with the water level lowered to 30.3 m (inside the upstream face), solved with the
/// CLI settings, and its evaluation.
fn scene_a_low_water(problem: &Problem, tags: &[i32]) -> (Problem, Evaluation) {
    let mut low = problem.clone();
    for bc in &mut low.neumann {
        if let Traction::Hydrostatic { level, .. } = &mut bc.traction {
            *level = LOW_WATER;
        }
    }
    let disc = low.discretise();
    let scene = Scene::load(&manifest("geo/scene_a.toml")).unwrap();
    let settings = scene.continuation(&low, &disc.topology);
    let (_, joint) = scene.problem(low.mesh.clone()).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.expect("Scene A has a contact curve");
    assert_eq!(joint.tags, tags, "the contact curves of Scene A");
    let run = solve_with_contact(&low, &disc, &joint, &settings);
    let e = evaluate(&low, &run.u, run.state(), tags, Some(1));
    (low, e)
}

const LOW_WATER: f64 = 30.3;

/// Source: geo/scene_a.toml with the flood level lowered to 30.3 m, so that the hydrostatic
/// pressure ρ_w g (H_w − y)₊ has its kink inside one facet of the upstream face.
/// Goal: equilibration below 10⁻¹⁰, in particular σ_h n = Π_F^p g_N on that facet.
/// Parameters: mesh sizes × 2, P1 and P2, CLI contact settings.
#[test]
fn kinked_hydrostatic_load_equilibrates() {
    let mut worst = Vec::new();
    for order in [1, 2] {
        let (problem, tags, _) = scene_with_contact("geo/scene_a.toml", order, 2.0);
        let (low, l) = scene_a_low_water(&problem, &tags);
        // the facet holding the water level: exact against (p + 4)-point moments ∫ g_x s^m
        let mesh = &low.mesh;
        for bc in &low.neumann {
            let Traction::Hydrostatic { .. } = bc.traction else { continue };
            for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
                let n = mesh.facet(f);
                let (a, b) = (mesh.points[n[0]], mesh.points[n[1]]);
                if (a[1] - LOW_WATER) * (b[1] - LOW_WATER) >= 0.0 {
                    continue;
                }
                let g = |s: f64| bc.traction.at([a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])], [-1.0, 0.0])[0];
                let moment = |rule: &[(f64, f64)], m: i32| rule.iter().map(|&(s, w)| g(s) * s.powi(m) * w).sum::<f64>();
                let gauss = |n: usize, lo: f64, hi: f64| -> Vec<(f64, f64)> {
                    let r = damfem::fem::quadrature::gauss_segment(n);
                    r.points.iter().zip(&r.weights).map(|(&s, &w)| (lo + s * (hi - lo), w * (hi - lo))).collect()
                };
                let cut = (LOW_WATER - a[1]) / (b[1] - a[1]);
                let exact: Vec<(f64, f64)> = gauss(6, 0.0, cut).into_iter().chain(gauss(6, cut, 1.0)).collect();
                for m in 0..=order as i32 {
                    let (e, q4, q2) = (
                        moment(&exact, m),
                        moment(&gauss(order + 4, 0.0, 1.0), m),
                        moment(&gauss(order + 2, 0.0, 1.0), m),
                    );
                    println!(
                        "P{order} facet y in [{:.2}, {:.2}], moment s^{m}: exact {e:.6e}, p+4 points {:+.2e} relative, p+2 points {:+.2e} relative",
                        a[1].min(b[1]),
                        a[1].max(b[1]),
                        (q4 - e) / e,
                        (q2 - e) / e
                    );
                }
            }
        }
        let dual = l.dual.unwrap();
        println!(
            "P{order} water level {LOW_WATER}: eta {:.4e} >= dual {dual:.4e}: {}; {:?}",
            l.est.tot,
            l.est.tot >= dual,
            l.eq
        );
        assert!(l.est.tot >= dual, "P{order}: bound violated, eta {} < dual {dual}", l.est.tot);
        worst.push((order, l.eq));
    }
    for (order, eq) in worst {
        assert!(eq.worst(order) < 1e-10, "P{order} level {LOW_WATER}: {eq:?}");
    }
}

/// A structured square (μ = λ = 1, ρ = 1) clamped on the left, self-weight g = 1, constant
/// tractions on the right and top sides, given as `Traction::Constant` or as fields.
fn constant_traction_problem(order: usize, as_fields: bool) -> Problem {
    let mesh = rectangle(0.0, 2.0, 0.0, 1.0, 8, 4, order);
    let mut material = Material::from_lame(1.0, 1.0);
    material.density = 1.0;
    let traction = |t: [f64; 2]| if as_fields { Traction::Field(Arc::new(move |_| t)) } else { Traction::Constant(t) };
    Problem {
        materials: vec![material; mesh.n_cells()],
        dirichlet: vec![damfem::elasticity::Dirichlet { tag: LEFT, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }],
        neumann: vec![
            Neumann { tag: RIGHT, traction: traction([0.3, -0.2]) },
            Neumann { tag: TOP, traction: traction([0.0, -1.0]) },
        ],
        body_force: if as_fields {
            BodyForce::Field(Arc::new(|_| [0.0, -1.0]))
        } else {
            BodyForce::Acceleration([0.0, -1.0])
        },
        mesh,
    }
}

/// Source: docs/method.md §5, src/estimate/estimators.rs (η_osc, η_Neu), §7 V1.
/// Goal: η_osc = η_Neu = 0 exactly for self-weight and constant tractions (P1, P2), round-off
/// when the same data are given as fields; η_osc > 0 for the smooth body force of V1, at the
/// rate h^{p+1} (‖f − Π^{p−1}f‖_T = O(h^p) times h_T/π).
/// Parameters: 2 × 1 rectangle, 8 × 4 cells, left clamped, tractions (0.3, −0.2) on the right
/// and (0, −1) on the top, g = 1; V1 on structured n = 4, 8.
#[test]
fn zero_oscillation_and_neumann_terms_on_constant_data() {
    for order in [1, 2] {
        let problem = constant_traction_problem(order, false);
        let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
        let fields = constant_traction_problem(order, true);
        let f = evaluate(&fields, &solve_linear(&fields), None, &[], None);
        let (area, h) = area_and_size(&problem.mesh);
        let (osc_scale, neu_scale) = (h / std::f64::consts::PI * area.sqrt(), neumann_scale(&problem));
        println!("constant data P{order}: {}; worst check {:.1e}", components(&e.est), e.eq.worst(order));
        println!(
            "    as fields: eta_osc {:.2e} (relative {:.1e}), eta_Neu {:.2e} (relative {:.1e}); worst check {:.1e}",
            f.est.osc,
            f.est.osc / osc_scale,
            f.est.neu,
            f.est.neu / neu_scale,
            f.eq.worst(order)
        );
        assert_eq!(e.est.osc, 0.0, "P{order}: eta_osc with self-weight");
        assert_eq!(e.est.neu, 0.0, "P{order}: eta_Neu with constant tractions");
        assert!(f.est.osc <= 1e-12 * osc_scale, "P{order}: eta_osc of a constant field {}", f.est.osc);
        assert!(f.est.neu <= 1e-12 * neu_scale, "P{order}: eta_Neu of a constant field {}", f.est.neu);
        assert!(e.eq.worst(order) < 1e-10 && f.eq.worst(order) < 1e-10, "P{order}: {:?} {:?}", e.eq, f.eq);

        let osc: Vec<f64> = [4, 8]
            .iter()
            .map(|&n| {
                let problem = v1::problem(unit_square(n, order), &[BOTTOM, RIGHT, TOP, LEFT]);
                let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
                println!("V1 P{order} n = {n}: {}", components(&e.est));
                e.est.osc
            })
            .collect();
        let rate = (osc[0] / osc[1]).log2();
        println!("V1 P{order}: eta_osc rate {rate:.3} (expected {})", order + 1);
        assert!(osc.iter().all(|&v| v > 0.0), "P{order}: eta_osc vanishes for a smooth f");
        assert!((rate - (order + 1) as f64).abs() < 0.3, "P{order}: eta_osc rate {rate}");
    }
}

/// The unit square with rollers on the left (u_x = 0) and bottom (u_y = 0) sides and constant
/// tractions (1, 0) on the right and (0, −0.5) on the top: σ = diag(1, −0.5), u affine.
fn roller_problem(mesh: Mesh, tags: [i32; 4]) -> Problem {
    let [bottom, right, top, left] = tags;
    let roller = |tag, fix| damfem::elasticity::Dirichlet { tag, fix, value: Arc::new(|_| [0.0; 2]) };
    Problem {
        materials: vec![Material::from_lame(1.0, 1.0); mesh.n_cells()],
        dirichlet: vec![roller(left, [true, false]), roller(bottom, [false, true])],
        neumann: vec![
            Neumann { tag: right, traction: Traction::Constant([1.0, 0.0]) },
            Neumann { tag: top, traction: Traction::Constant([0.0, -0.5]) },
        ],
        body_force: BodyForce::None,
        mesh,
    }
}

/// Source: docs/method.md §4.4 (free rigid motions of roller patches, the p = 1 rotation datum).
/// Goal: when u_h is the exact solution, η_tot is round-off, for P1 and P2, on a structured
/// and on a gmsh mesh. Roller patches leave one translation free and no rotation; a rotation
/// datum fitted to the round-off defect of that translation would make η large.
/// Parameters: unit square, rollers left and bottom, σ = diag(1, −0.5); structured 8 × 8,
/// gmsh geo/unit_square.geo (h = 1/8).
#[test]
fn exact_solution_with_rollers_has_zero_estimate() {
    for order in [1, 2] {
        let options = MeshOptions { order, size_factor: 1.0, ..Default::default() };
        let gmsh = mesh_geo(&manifest("geo/unit_square.geo"), &options, false, false).unwrap_or_else(|e| panic!("{e}"));
        let tags = ["bottom", "right", "top", "left"].map(|name| gmsh.group(1, name).unwrap().tag);
        for (label, problem) in [
            ("structured", roller_problem(unit_square(8, order), [BOTTOM, RIGHT, TOP, LEFT])),
            ("gmsh", roller_problem(gmsh.clone(), tags)),
        ] {
            let e = evaluate(&problem, &solve_linear(&problem), None, &[], None);
            println!("rollers {label} P{order}: {}; worst check {:.1e}", components(&e.est), e.eq.worst(order));
            let stress_norm = 1.25_f64.sqrt(); // ‖σ‖_Ω on the unit square
            assert!(e.est.tot < 1e-10 * stress_norm, "{label} P{order}: eta {} for an exact solution", e.est.tot);
            assert!(e.eq.worst(order) < 1e-10, "{label} P{order}: {:?}", e.eq);
        }
    }
}
