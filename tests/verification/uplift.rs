//! Uplift in the joint (docs/method.md §1.8): the pore pressure acts on the effective normal
//! stress, and the crack it fills at the heel is found by a fixed point.

use crate::common;
use damfem::contact::nitsche::NitscheParameters;
use damfem::contact::uplift::{CrackRule, Uplift};
use damfem::contact::JointLine;
use damfem::contact::{solve_by_continuation, ContactJoint, Continuation, JointLaw};
use damfem::elasticity::{BodyForce, Dirichlet, Material, Neumann, Problem, Traction};
use damfem::estimate::reference::{sharp_reference, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS};
use damfem::mesh::structured::{unit_square, BOTTOM, LEFT, RIGHT, TOP};
use damfem::scene::Scene;
use damfem::solve::NewtonOptions;
use std::sync::Arc;

/// Uniform uplift. Source: docs/method.md §1.8 with p_u constant. Goal: on a block pressed and
/// sheared by its top (u = (a y, −b y), closed and sticking base), a uniform pore pressure
/// lowers the contact pressure by exactly p_u, p_c = (λ + 2μ) b − p_u, and leaves u_h = u: the
/// total normal stress is fixed by the displacement. Checked to round-off for frictionless
/// and Coulomb joints, P1 and P2, θ = 1, 0, −1; the uplift force is p_u |Γ_C|.
/// Parameters: λ = μ = 1, a = b = 0.01, p_u = 0.005 (a sixth of (λ + 2μ) b), F = 0.5 (S = 0.0125
/// > μ a: it sticks), γ₀ = 100, 4 × 4 grid, δ = 0 reached from 10⁻².
#[test]
fn uniform_uplift_lowers_the_contact_pressure_by_exactly_p_u() {
    let (lambda, mu, a, b, p_u) = (1.0, 1.0, 0.01, 0.01, 0.005);
    let uplift = Uplift {
        line: JointLine { heel: [0.0, 0.0], along: [1.0, 0.0], length: 1.0 },
        upstream: p_u,
        downstream: p_u,
        drains: None,
        rule: CrackRule::Kept { prior: 0.0 },
        crack: 0.0,
    };
    for law in [JointLaw::Frictionless, JointLaw::Coulomb { friction: 0.5 }] {
        let shear = if law.has_friction() { mu * a } else { 0.0 };
        for order in [1, 2] {
            for theta in [1.0, 0.0, -1.0] {
                let mesh = unit_square(4, order);
                let (sxx, sxy) = (-lambda * b, shear);
                let top = if law.has_friction() { [a, -b] } else { [0.0, -b] };
                let problem = Problem {
                    materials: vec![Material::from_lame(lambda, mu); mesh.n_cells()],
                    dirichlet: vec![Dirichlet { tag: TOP, fix: [true; 2], value: Arc::new(move |_| top) }],
                    neumann: vec![
                        Neumann { tag: LEFT, traction: Traction::Constant([-sxx, -sxy]) },
                        Neumann { tag: RIGHT, traction: Traction::Constant([sxx, sxy]) },
                    ],
                    body_force: BodyForce::None,
                    mesh,
                };
                let disc = problem.discretise();
                let parameters = NitscheParameters { theta, ..crate::nitsche_parameters() };
                let joint =
                    ContactJoint::uniform(vec![BOTTOM], Vec::new(), law, parameters).with_uplift(uplift.clone());
                let settings =
                    Continuation { delta: 0.0, delta_start: 1e-2, newton: NewtonOptions::default(), path: None };
                let solution =
                    solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
                let u = problem.displacement(&disc, &solution.x);
                let error = common::max_nodal_error(&problem.mesh.points, &u, |x| [top[0] * x[1], top[1] * x[1]]);
                let expected = (lambda + 2.0 * mu) * b - p_u;
                let pressure = solution.faces.iter().map(|f| (f.pressure - expected).abs()).fold(0.0, f64::max);
                println!("{law:?} P{order} θ = {theta:2}: max nodal error {error:.1e}, max |p_c − ((λ+2μ)b − p_u)| {pressure:.1e}");
                assert!(error <= 1e-12 * a, "{law:?} P{order} θ = {theta}: error {error}");
                assert!(pressure <= 1e-12 * expected, "{law:?} P{order} θ = {theta}: pressure off by {pressure}");
                assert!((solution.uplift_force() - p_u).abs() <= 1e-14, "uplift force {}", solution.uplift_force());
            }
        }
    }
}

/// The dam with uplift. Source: geo/scene_a_uplift.toml (Scene A held by Coulomb friction,
/// reservoir at 45 m, drains 5 m from the heel, the crack filled with reservoir pressure).
/// Goal: global equilibrium with the uplift, N + U = W (the weight) and T = −the thrust
/// ρ_w g H_w²/2, to 10⁻⁸, so that FS_LE = F (W − U)/T; the crack–uplift fixed point settles with a crack at the heel; the
/// estimator with uplift is equilibrated to round-off and bounds the dual-norm reference
/// (the uplift enters both as the Γ_C traction −p_u ν). Parameters: P1 and P2, the file's mesh
/// sizes × 2; the sharp reference of `damfem solve --effectivity`.
#[test]
fn the_dam_with_uplift_balances_weight_thrust_and_uplift() {
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0;
    for order in [1, 2] {
        let common::SolvedScene { problem, disc, joint, solution } =
            common::solve_scene("geo/scene_a_uplift.toml", order, 2.0);
        let (n, t, u) = (solution.normal_force(), solution.tangential_force(), solution.uplift_force());
        let crack = solution.cracks[0].expect("the crack is iterated");
        let state = solution.linearisation(&problem, &disc);
        let e = damfem::estimate::estimate_iterate(&problem, &disc, &solution.x, Some(&state))
            .unwrap_or_else(|e| panic!("{e}"));
        let u_h = problem.displacement(&disc, &solution.x);
        // the residual of the problem that was solved: with the crack the fixed point found
        let solved = joint.as_solved(&solution);
        let reference = sharp_reference(&problem, &u_h, Some(&solved), REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)
            .unwrap_or_else(|e| panic!("{e}"))
            .norm();
        let (eta, worst) = (e.estimators.global().tot, e.equilibration.worst(order));
        println!(
            "P{order}: N {n:.6e} U {u:.6e} (N + U − W = {:.1e}), T {t:.6e}; crack {:.3} m after {} solves; eta_tot {eta:.4e}, reference {reference:.4e}, worst check {worst:.1e}",
            n + u - weight,
            crack.length,
            crack.iterations
        );
        assert!((n + u - weight).abs() <= 1e-8 * weight, "P{order}: N + U = {} against W = {weight}", n + u);
        assert!((t + thrust).abs() <= 1e-8 * thrust, "P{order}: T = {t} against the thrust {thrust}");
        // c = 0 on a horizontal joint: FS_LE = F N / T with N = W − U
        let fs = solution.sliding_safety_factor().expect("a frictional joint");
        let expected = 0.8391 * (weight - u) / thrust;
        assert!((fs - expected).abs() <= 1e-8 * expected, "P{order}: FS_LE {fs} against {expected}");
        assert!(crack.length > 0.0 && crack.change <= 1e-6 * 40.0, "P{order}: {crack:?}");
        assert!(worst < 1e-10, "P{order}: equilibration {worst:e}");
        assert!(eta >= reference, "P{order}: eta_tot {eta} below the reference {reference}");
    }
}

/// Strength reduction against the exact answer. Source: docs/method.md §1.7 (equilibrium of a
/// body held by a horizontal joint on a rigid foundation, c = 0): the joint holds the dam with
/// F/k exactly while k ≤ F N / T, N = W − U. Goal: FS_SR's bracket contains F (W − U)/T and is
/// within 0.5 % of it, with and without uplift, on two meshes and both degrees. Parameters:
/// geo/scene_a_uplift.toml with crack = "ignore" (U of the uncracked diagram), and without its
/// [uplift] table (U = 0), mesh sizes × 2 and × 4, P1 and P2, bisection to 0.2 %.
#[test]
fn strength_reduction_finds_the_exact_sliding_factor() {
    use damfem::safety::strength::strength_reduction;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a_uplift.toml");
    let mut with_uplift = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    with_uplift.uplift.as_mut().expect("[uplift]").crack = Some(damfem::scene::CrackKind::Ignore);
    let mut without_uplift = with_uplift.clone();
    without_uplift.uplift = None;
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0;
    for scene in [with_uplift, without_uplift] {
        for order in [1, 2] {
            for size_factor in [4.0, 2.0] {
                let mesh = common::mesh_scene(&scene, order, size_factor);
                let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
                let joint = joint.expect("a joint");
                let uplift = joint.uplift.first().map_or(0.0, |up| up.diagram.force(0.0));
                let disc = problem.discretise();
                let settings = scene.continuation(&problem, &disc.topology);
                let sr = strength_reduction(&problem, &disc, &joint, &settings, 2e-3).unwrap_or_else(|e| panic!("{e}"));
                let exact = 0.8391 * (weight - uplift) / thrust;
                println!(
                    "U = {uplift:.4e}, P{order} size {size_factor}: FS_SR in [{:.4}, {:.4}] after {} solves; F (W − U)/T = {exact:.4}",
                    sr.held, sr.failed, sr.solves
                );
                assert!(
                    sr.held <= exact * (1.0 + 1e-9) && sr.failed >= exact * (1.0 - 1e-9),
                    "P{order}: bracket {sr:?} misses {exact}"
                );
                assert!(sr.held >= 0.995 * exact, "P{order}: FS_SR {} more than 0.5 % below {exact}", sr.held);
            }
        }
    }
}

/// The classical cracked-base analysis of a gravity-dam section (USACE EM 1110-2-2200, Gravity
/// Dam Design, 1995, §4; CADAM's manual): the base pressure is linear on the uncracked ligament
/// l = B − c, zero at the crack tip, so the effective normal force N' = W − U(c) acts at l/3
/// from the toe; with the reservoir pressure H_u in the crack, U(c) = H_u c + H_u l/2, and
/// moment equilibrium about the toe gives c. Returns c and, for any c, the distance d(c) from
/// the toe at which statics put N'.
struct CrackedBase {
    weight: f64,
    thrust: f64,
    /// H_u = ρ_w g H_w at the heel (tailwater 0).
    heel_pressure: f64,
    base: f64,
    water: f64,
}

impl CrackedBase {
    fn uplift(&self, c: f64) -> f64 {
        self.heel_pressure * (c + (self.base - c) / 2.0)
    }

    /// d(c) = (W·2B/3 − P H_w/3 − M_U(c)) / (W − U(c)), all moments about the toe.
    fn resultant_from_toe(&self, c: f64) -> f64 {
        let (b, l) = (self.base, self.base - c);
        let uplift_moment = self.heel_pressure * (c * (b - c / 2.0) + l / 2.0 * (2.0 * l / 3.0));
        let moment = self.weight * 2.0 * b / 3.0 - self.thrust * self.water / 3.0 - uplift_moment;
        moment / (self.weight - self.uplift(c))
    }

    /// The crack of beam theory: d(c) = (B − c)/3, by bisection on [0, B/2] (d > l/3 at 0).
    fn beam_crack(&self) -> f64 {
        let f = |c: f64| self.resultant_from_toe(c) - (self.base - c) / 3.0;
        let (mut lo, mut hi) = (0.0, self.base / 2.0);
        assert!(f(lo) < 0.0 && f(hi) > 0.0, "the section cracks, and not beyond half its base");
        while hi - lo > 1e-12 * self.base {
            let mid = 0.5 * (lo + hi);
            *(if f(mid) < 0.0 { &mut lo } else { &mut hi }) = mid;
        }
        0.5 * (lo + hi)
    }
}

/// Cracked-base hand check. Source: the classical computation above, on a textbook section
/// (tests/data/cracked_base.toml: a triangle with a vertical upstream face, H = 50 m, B = 40 m,
/// reservoir at the crest, full uplift in the crack, no drains, a Coulomb joint with F = 2 on a
/// rigid foundation). Goal: the elastic crack lies within 10 % of beam theory's, on the short
/// side, and converges with the mesh; the difference is the one beam theory makes: plane
/// sections do not stay plane on a rigid foundation, whose restraint draws the base pressure
/// towards the toe, so that N' acts at α l from the toe with α < 1/3 (measured 0.327), and
/// d(c) − l/3 crosses zero at a shallow angle, so that 2 % in α moves the crack by 7 %
/// (15.07 m against 16.25 m). Exact statics hold throughout: N + U = W, T = the thrust, and U
/// is the diagram's integral with the computed crack. Parameters: P2, the fixture's mesh sizes
/// × 2 and × 1.
#[test]
fn the_crack_of_a_textbook_section_against_the_cracked_base_analysis() {
    let (h, b, water, g) = (50.0, 40.0, 50.0, 9.81);
    let section = CrackedBase {
        weight: 2400.0 * g * b * h / 2.0,
        thrust: 1000.0 * g * water * water / 2.0,
        heel_pressure: 1000.0 * g * water,
        base: b,
        water,
    };
    let beam = section.beam_crack();
    let mut cracks = Vec::new();
    for size_factor in [2.0, 1.0] {
        let solved = common::solve_scene("tests/data/cracked_base.toml", 2, size_factor);
        let s = &solved.solution;
        let (n, t, u) = (s.normal_force(), s.tangential_force(), s.uplift_force());
        let c = s.cracks[0].expect("the crack is iterated").length;
        let alpha = section.resultant_from_toe(c) / (b - c);
        println!(
            "size × {size_factor}: crack {c:.4} m (beam theory {beam:.4} m, {:+.1} %), N' at {alpha:.4} l from the toe, N {n:.6e} U {u:.6e} T {t:.6e}",
            100.0 * (c / beam - 1.0)
        );
        assert!((n + u - section.weight).abs() <= 1e-8 * section.weight, "N + U = {} against W", n + u);
        assert!((t + section.thrust).abs() <= 1e-8 * section.thrust, "T = {t}");
        assert!((u - section.uplift(c)).abs() <= 1e-8 * section.weight, "U = {u} against {}", section.uplift(c));
        assert!(c < beam && c > 0.9 * beam, "crack {c} against beam theory's {beam}");
        assert!((0.3..1.0 / 3.0).contains(&alpha), "N' at {alpha} l from the toe");
        cracks.push(c);
    }
    assert!((cracks[1] - cracks[0]).abs() <= 0.01 * cracks[1], "the crack moves with the mesh: {cracks:?}");
}

/// The uplift head [m] of the USACE diagrams (EM 1110-2-2100, Appendix C; EM 1110-2-2200,
/// §3-3), in their notation, at the distance x from the heel of a base of length L: H1 the
/// headwater and H2 the tailwater head above the base, drains at X with effectiveness E
/// (K = 1 − E), a crack of length T from the heel with the full head H1 inside. The drain line
/// carries H3 = H2 + K (H1 − H2)(L − X)/(L − T) while T < X; a crack that reaches the drains
/// leaves the line from H1 at T to H2 at L.
fn usace_head(x: f64, (h1, h2, l): (f64, f64, f64), drains: Option<(f64, f64)>, t: f64) -> f64 {
    let line = |x0: f64, h0: f64, x1: f64, h1: f64| h0 + (h1 - h0) * (x - x0) / (x1 - x0);
    if x <= t {
        return h1;
    }
    match drains.filter(|&(x_d, _)| t < x_d) {
        Some((x_d, e)) => {
            let h3 = h2 + (1.0 - e) * (h1 - h2) * (l - x_d) / (l - t);
            if x <= x_d {
                line(t, h1, x_d, h3)
            } else {
                line(x_d, h3, l, h2)
            }
        }
        None => line(t, h1, l, h2),
    }
}

/// The uplift diagrams value by value against the guideline. Source: USACE EM 1110-2-2100
/// (2005), Appendix C, and EM 1110-2-2200 (1995), §3-3, the diagrams CADAM implements
/// (`usace_head` above, written from them independently of src/contact/uplift.rs). Goal:
/// damfem's p_u of a scene equals ρ_w g × the guideline's head at the heel, the drain line, the
/// toe and two points between, to 10⁻¹² of ρ_w g H1, and its U the diagram's integral, for
/// drains (X, E) = (5 m, 2/3), (10 m, 1/2), (20 m, 1/4) and none, tailwater none and 8 m above
/// the base, cracks T = 0, 2.5 m (short of every drain line) and 12 m (past the first two).
/// Parameters: geo/scene_a_uplift.toml (base y = 0, L = 40 m, heel at x = 0, headwater 45 m)
/// with its [uplift] table replaced, P1, the file's mesh sizes × 4.
#[test]
fn the_uplift_diagrams_are_the_guidelines() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(repo.join("geo/scene_a_uplift.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo.join("geo/scene_a_friction.geo").display().to_string());
    let text = text.replace("geometry = \"scene_a_friction.geo\"", &geometry);
    let dir = std::env::temp_dir().join(format!("damfem-uplift-diagrams-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let gamma_w = 1000.0 * 9.81;
    let (h1, l) = (45.0, 40.0);
    for tailwater in [None, Some(8.0)] {
        for drains in [Some((5.0, 2.0 / 3.0)), Some((10.0, 0.5)), Some((20.0, 0.25)), None] {
            let mut table = String::from("[uplift]\nheadwater = 45.0\ncrack = \"full\"\n");
            if let Some(t) = tailwater {
                table += &format!("tailwater = {t:?}\n");
            }
            if let Some((x, e)) = drains {
                table += &format!("drains = {{ x = {x:?}, efficiency = {e:?} }}\n");
            }
            let start = text.find("[uplift]").unwrap();
            let end = text.find("[output]").unwrap();
            let path = dir.join("scene.toml");
            std::fs::write(&path, format!("{}{table}\n{}", &text[..start], &text[end..])).unwrap();
            let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
            let (_, joint) = scene.problem(common::mesh_scene(&scene, 1, 4.0)).unwrap();
            let uplift = joint.unwrap().uplift.remove(0).diagram;
            assert_eq!(uplift.line.heel, [0.0, 0.0]);
            let heads = (h1, tailwater.unwrap_or(0.0), l);
            for t in [0.0, 2.5, 12.0] {
                let x_d = drains.map_or(l / 2.0, |d| d.0);
                for x in [0.0, x_d, l, 0.5 * (t + x_d), 0.5 * (x_d + l)] {
                    let (damfem, guideline) = (uplift.pressure(x, t), gamma_w * usace_head(x, heads, drains, t));
                    assert!(
                        (damfem - guideline).abs() <= 1e-12 * gamma_w * h1,
                        "tailwater {tailwater:?}, drains {drains:?}, crack {t}: p_u({x}) = {damfem}, guideline {guideline}"
                    );
                }
                // U: the piecewise linear head integrated by the trapezoid rule on a fine grid
                // that holds the kinks T and X
                let n = 8000;
                let integral: f64 = (0..n)
                    .map(|i| {
                        let (a, b) = (l * i as f64 / n as f64, l * (i + 1) as f64 / n as f64);
                        0.5 * (b - a) * (usace_head(a, heads, drains, t) + usace_head(b, heads, drains, t))
                    })
                    .sum();
                let force = uplift.force(t);
                assert!(
                    (force - gamma_w * integral).abs() <= 1e-10 * force,
                    "tailwater {tailwater:?}, drains {drains:?}, crack {t}: U = {force}, guideline {}",
                    gamma_w * integral
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An uplift diagram per joint, each along its own line. Source: docs/method.md §1.8 and
/// §1.10; geo/dam_lifts_on_rock_uplift.toml, whose [joints.base.uplift] and
/// [joints.lift.uplift] give the dam–rock joint (y = 0) and the lift joint (y = 20 m) each a
/// diagram under the reservoir at 45 m. Goal: the scene's joint holds two diagrams, each on its
/// own curve only; each runs from its own heel, the end nearest the hydrostatic upstream face
/// (x = 0), along its own curve to its toe: the lift joint's from (0, 20) over 26 m, with
/// p_u = ρ_w g (45 − 20) at its heel and 0 at its toe, the base's from (0, 0) over 40 m, with
/// ρ_w g 45 at its heel and its drains 5 m downstream.
/// Parameters: P1, the file's mesh sizes × 4.
#[test]
fn each_joint_has_its_own_uplift_diagram() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::load(&repo.join("geo/dam_lifts_on_rock_uplift.toml")).unwrap_or_else(|e| panic!("{e}"));
    let (_, joint) = scene.problem(common::mesh_scene(&scene, 1, 4.0)).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.expect("a joint");
    let gamma_w = 1000.0 * 9.81;
    // the curves of the joint in the order of [joints]: base, lift
    assert_eq!(joint.uplift.len(), 2);
    for (curve, heel, length, head, drains) in
        [(0, [0.0, 0.0], 40.0, 45.0, Some(5.0)), (1, [0.0, 20.0], 26.0, 25.0, None)]
    {
        let up = &joint.uplift[curve];
        let p = &up.diagram;
        println!(
            "curve {curve}: heel {:?}, length {}, p_u {} … {} Pa",
            p.line.heel,
            p.line.length,
            p.pressure(0.0, 0.0),
            p.pressure(length, 0.0)
        );
        assert_eq!(up.curves, vec![curve]);
        assert!(p.line.heel.iter().zip(heel).all(|(a, b)| (a - b).abs() < 1e-12), "{:?}", p.line);
        assert!((p.line.length - length).abs() < 1e-9 && (p.line.along[0] - 1.0).abs() < 1e-12, "{:?}", p.line);
        assert!((p.pressure(0.0, 0.0) - gamma_w * head).abs() <= 1e-12 * gamma_w * head, "p_u at the heel");
        assert_eq!(p.pressure(length, 0.0), 0.0);
        assert_eq!(p.drains.map(|d| d.distance), drains);
    }
}
