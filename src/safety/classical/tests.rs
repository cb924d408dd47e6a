//! The gravity method on a triangular section whose answer is written here by hand.

use super::*;
use crate::contact::nitsche::NitscheParameters;
use crate::elasticity::{Material, Neumann};
use crate::mesh::{Mesh, PhysicalGroup};

const G: f64 = 9.81;
const RHO_W: f64 = 1000.0;
const RHO_C: f64 = 2400.0;
/// Base B, height H, reservoir and tailwater levels above the base \[m\].
const B: f64 = 40.0;
const H: f64 = 50.0;
const HW: f64 = 45.0;
const TW: f64 = 5.0;
/// tan φ and c \[Pa\] of the joint.
const FRICTION: f64 = 0.7;
const COHESION: f64 = 1.0e5;

/// The triangle heel (0, 0), toe (B, 0), crest (0, H) as one P1 cell: the base (tag 1), the
/// sloping downstream face (2) under the tailwater, the vertical upstream face (3) under the
/// reservoir, loaded by the weight with the acceleration `a` (in g).
fn triangle(a: Vector) -> Problem {
    let group = |tag, name: &str| PhysicalGroup { dim: 1, tag, name: name.into() };
    let mesh = Mesh {
        points: vec![[0.0, 0.0], [B, 0.0], [0.0, H]],
        order: 1,
        cell_nodes: vec![0, 1, 2],
        cell_tags: vec![1],
        facet_nodes: vec![0, 1, 1, 2, 2, 0],
        facet_tags: vec![1, 2, 3],
        groups: vec![group(1, "base"), group(2, "downstream"), group(3, "upstream")],
    };
    let water = |tag, level| Neumann { tag, traction: Traction::Hydrostatic { density: RHO_W, gravity: G, level } };
    Problem {
        mesh,
        materials: vec![Material { young: 3e10, poisson: 0.2, density: RHO_C }],
        dirichlet: vec![],
        neumann: vec![water(2, TW), water(3, HW)],
        body_force: BodyForce::Acceleration([G * a[0], G * (a[1] - 1.0)]),
    }
}

/// The base with a linear uplift from γ_w H_w at the heel to γ_w T_w at the toe, no drains.
fn joint(rule: CrackRule) -> (ContactJoint, JointLine) {
    let line = JointLine::new([0.0, 0.0], [B, 0.0]);
    let law = JointLaw::MohrCoulomb { friction: FRICTION, cohesion: COHESION };
    let uplift = Uplift { line, upstream: RHO_W * G * HW, downstream: RHO_W * G * TW, drains: None, rule, crack: 0.0 };
    (ContactJoint::uniform(vec![1], vec![], law, NitscheParameters::default()).with_uplift(uplift), line)
}

fn close(what: &str, got: f64, want: f64) {
    assert!((got - want).abs() <= 1e-6 * want.abs().max(1.0), "{what}: {got} against {want}");
}

/// The loads of the triangle by hand: (kind, V, d_V, H, h_H).
fn hand_loads(a: Vector) -> Vec<(LoadKind, f64, f64, f64, f64)> {
    let gw = RHO_W * G;
    let w = RHO_C * G * B * H / 2.0;
    // the water above the sloping face: a wedge of width b_t = B T_w / H, its centroid b_t/3
    // upstream of the toe
    let wedge = B * TW / H;
    vec![
        (LoadKind::Weight, w, 2.0 * B / 3.0, 0.0, 0.0),
        (LoadKind::Inertia, -a[1] * w, 2.0 * B / 3.0, a[0] * w, H / 3.0),
        (LoadKind::Reservoir, 0.0, 0.0, gw * HW * HW / 2.0, HW / 3.0),
        (LoadKind::Tailwater, gw * wedge * TW / 2.0, wedge / 3.0, -gw * TW * TW / 2.0, TW / 3.0),
    ]
}

// Source: EM 1110-2-2100 §3-3 (forces and moments about the toe, the resultant, the linear
// base pressure N/B (1 ± 6e/B)), worked by hand for a triangle. Goal: the loads taken from
// the finite-element problem, their arms about the toe, FS, overturning, flotation, the
// resultant and the heel and toe stresses, to 1e-6. Parameters: B = 40 m, H = 50 m,
// H_w = 45 m, T_w = 5 m, a = (0.1, −0.05) g: the heel stays in compression.
#[test]
fn a_triangle_has_its_hand_computed_answer() {
    let a = [0.1, -0.05];
    let (joint, line) = joint(CrackRule::Filled);
    let c = classical(&triangle(a), &joint, &line, G, a).unwrap();
    let hand = hand_loads(a);
    for (load, &(kind, v, d, h, arm)) in c.loads.iter().zip(&hand) {
        assert_eq!(load.kind, kind);
        close("V", load.normal, v);
        close("d_V", load.normal_arm, d);
        close("H", load.shear, h);
        close("h_H", load.shear_arm, arm);
        close("M", load.moment, v * d - h * arm);
    }
    let gw = RHO_W * G;
    // linear uplift: U = γ_w B (H_w + T_w)/2, its centroid B (H_w + 2 T_w)/(3 (H_w + T_w)) from the heel
    let u = gw * B * (HW + TW) / 2.0;
    let s_u = B * (HW + 2.0 * TW) / (3.0 * (HW + TW));
    let uplift = c.loads.last().unwrap();
    assert_eq!((uplift.kind, c.loads.len()), (LoadKind::Uplift, hand.len() + 1));
    close("U", uplift.normal, -u);
    close("d_U", uplift.normal_arm, B - s_u);
    let p: f64 = hand.iter().map(|l| l.1).sum();
    let t: f64 = hand.iter().map(|l| l.3).sum();
    let parts = hand.iter().flat_map(|l| [l.1 * l.2, -l.3 * l.4]).chain([-u * (B - s_u)]);
    let resisting: f64 = parts.clone().filter(|&m| m > 0.0).sum();
    let overturning: f64 = -parts.clone().filter(|&m| m < 0.0).sum::<f64>();
    let (n, m) = (p - u, parts.sum::<f64>());
    let e = B / 2.0 - m / n;
    assert!(e < B / 6.0, "the case is meant uncracked");
    close("P", c.pressing_force, p);
    close("N", c.normal_force, n);
    close("T", c.shear_force, t);
    close("resisting", c.resisting_moment, resisting);
    close("overturning", c.overturning_moment, overturning);
    close("FS_OT", c.overturning_factor.unwrap(), resisting / overturning);
    close("FS_F", c.flotation_factor.unwrap(), p / u);
    close("FS", c.sliding_factor.unwrap(), (COHESION * B + FRICTION * n) / t);
    close("d_R", c.resultant_from_toe, m / n);
    close("s_R", c.resultant_position, B - m / n);
    close("e", c.eccentricity, e);
    close("heel", c.heel_stress, -n / B * (1.0 - 6.0 * e / B));
    close("toe", c.toe_stress, -n / B * (1.0 + 6.0 * e / B));
    assert_eq!((c.crack, c.compressed_fraction()), (0.0, 1.0));
}

// Source: EM 1110-2-2100 §3-3 (the base cracks from the heel until the pressure is zero at
// the crack tip, full reservoir pressure in the crack). Worked by hand: with the pressure
// γ_w H_w on the crack and linear to γ_w T_w at the toe, U = γ_w T_w B + γ_w (H_w − T_w)(2B − L_c)/2
// and its moment about the toe γ_w T_w B²/2 + γ_w (H_w − T_w)(B²/2 − L_c²/6); the condition
// 3 (M₀ − M_U) = L_c (P − U) loses its L_c² terms and gives L_c = (3 M₀ − 3/2 γ_w H_w B²) /
// (P − γ_w H_w B), M₀ and P those of the loads but the uplift. Without water in the crack,
// L_c = 3 d_R of the uncracked base. Goal: the crack, N, the toe stress −2N/L_c and FS to
// 1e-6, both ways. Parameters: the triangle above with a = (0.2, 0) g.
#[test]
fn a_cracked_triangle_has_its_hand_computed_crack() {
    let a = [0.2, 0.0];
    let hand = hand_loads(a);
    let gw = RHO_W * G;
    let p: f64 = hand.iter().map(|l| l.1).sum();
    let t: f64 = hand.iter().map(|l| l.3).sum();
    let m0: f64 = hand.iter().map(|l| l.1 * l.2 - l.3 * l.4).sum();
    let lc = (3.0 * m0 - 1.5 * gw * HW * B * B) / (p - gw * HW * B);
    let u = gw * TW * B + gw * (HW - TW) * (2.0 * B - lc) / 2.0;
    let (joint_full, line) = joint(CrackRule::Filled);
    let c = classical(&triangle(a), &joint_full, &line, G, a).unwrap();
    assert!(lc > 0.0 && lc < B);
    close("crack", c.crack, B - lc);
    close("L_c", c.compressed_length, lc);
    close("U", c.uplift_force, u);
    close("N", c.normal_force, p - u);
    close("d_R", c.resultant_from_toe, lc / 3.0);
    close("toe", c.toe_stress, -2.0 * (p - u) / lc);
    assert_eq!(c.heel_stress, 0.0);
    close("FS", c.sliding_factor.unwrap(), (COHESION * lc + FRICTION * (p - u)) / t);
    // the crack ignored: the uplift stays linear, L_c = 3 d_R(0)
    let u0 = gw * B * (HW + TW) / 2.0;
    let m = m0 - u0 * (B - B * (HW + 2.0 * TW) / (3.0 * (HW + TW)));
    let (joint_ignored, _) = joint(CrackRule::Kept { prior: 0.0 });
    let dry = classical(&triangle(a), &joint_ignored, &line, G, a).unwrap();
    close("L_c dry", dry.compressed_length, 3.0 * m / (p - u0));
    close("U dry", dry.uplift_force, u0);
}

// Goal: a section that the loads lift off its base is said to float, not given numbers.
#[test]
fn a_section_lifted_by_its_uplift_floats() {
    let (mut joint, line) = joint(CrackRule::Filled);
    joint.uplift[0].diagram.upstream *= 20.0;
    let e = classical(&triangle([0.0; 2]), &joint, &line, G, [0.0; 2]).unwrap_err();
    assert!(e.contains("floats"), "{e}");
}

// Source: Westergaard (1933), p(z) = (7/8) a_h ρ_w g √(H z) on a vertical face, whose resultant
// is ∫₀^H p dz = (7/12) a_h ρ_w g H² at ∫₀^H p (H − z) dz / ∫ p dz = 0.4 H above the base. Goal:
// the added pressure of the problem's traction, integrated by its own rule, has them to 1e-6,
// and the reservoir's own thrust is unchanged. Parameters: the triangle with a_h = 0.15 g,
// the reservoir at H_w = 45 m on the 50 m face.
#[test]
fn westergaards_pressure_has_its_resultant_on_a_vertical_face() {
    let a = [0.15, 0.0];
    let mut problem = triangle(a);
    problem.neumann[1].traction =
        Traction::Westergaard { density: RHO_W, gravity: G, level: HW, depth: HW, acceleration: a[0] };
    let (joint, line) = joint(CrackRule::Filled);
    let c = classical(&problem, &joint, &line, G, a).unwrap();
    let load = |k: LoadKind| *c.loads.iter().find(|l| l.kind == k).unwrap();
    let added = load(LoadKind::Hydrodynamic);
    close("H", added.shear, 7.0 / 12.0 * a[0] * RHO_W * G * HW * HW);
    close("h_H", added.shear_arm, 0.4 * HW);
    close("V", added.normal, 0.0);
    close("reservoir", load(LoadKind::Reservoir).shear, RHO_W * G * HW * HW / 2.0);
}

// Source: CADAM3D's cos² correction of Westergaard's pressure on an inclined face: along the
// normal, (7/8) a cos²θ ρ_w g √(H z), whose horizontal force per unit height is the same, so
// the resultant is cos²θ (7/12) a ρ_w g H² at 0.4 H, and the vertical one tan θ times it.
// Goal: the problem's traction on the triangle's sloping face has them to 1e-6. Parameters:
// water at 20 m on the downstream face (tan θ = B/H = 0.8), a_h = −0.15 g (towards it).
#[test]
fn westergaards_pressure_on_an_inclined_face_is_corrected_by_cos_squared() {
    let (a, level) = ([-0.15, 0.0], 20.0);
    let mut problem = triangle(a);
    problem.neumann[0].traction =
        Traction::Westergaard { density: RHO_W, gravity: G, level, depth: level, acceleration: a[0] };
    let (joint, line) = joint(CrackRule::Filled);
    let c = classical(&problem, &joint, &line, G, a).unwrap();
    let added = *c.loads.iter().find(|l| l.kind == LoadKind::Hydrodynamic).unwrap();
    let cos2 = H * H / (H * H + B * B);
    let horizontal = cos2 * 7.0 / 12.0 * a[0].abs() * RHO_W * G * level * level;
    close("H", added.shear, -horizontal);
    close("h_H", added.shear_arm, 0.4 * level);
    close("V", added.normal, horizontal * B / H);
}

// Source: a silt layer h deep of submerged density ρ' and coefficient K thrusts K ρ' g h²/2 at
// h/3 above its foot; an ice sheet's thrust F spread over its thickness t acts at t/2 below the
// surface. Goal: beside the reservoir on the vertical upstream face, the classical method has
// both loads to 1e-6 and the reservoir's own thrust unchanged. Parameters: silt 12 m deep,
// ρ' = 1100 kg/m³, K = 0.5; ice F = 150 kN/m, t = 0.6 m at the 45 m reservoir surface.
#[test]
fn silt_and_ice_thrust_with_their_resultants() {
    let (depth, density, k, force, thickness) = (12.0, 1100.0, 0.5, 1.5e5, 0.6);
    let mut problem = triangle([0.0; 2]);
    problem.neumann[1].traction = Traction::Sum(vec![
        Traction::Hydrostatic { density: RHO_W, gravity: G, level: HW },
        Traction::Silt { gradient: k * density * G, level: depth },
        Traction::Ice { pressure: force / thickness, bottom: HW - thickness, top: HW },
    ]);
    let (joint, line) = joint(CrackRule::Filled);
    let c = classical(&problem, &joint, &line, G, [0.0; 2]).unwrap();
    let load = |kind: LoadKind| *c.loads.iter().find(|l| l.kind == kind).unwrap();
    let (silt, ice) = (load(LoadKind::Silt), load(LoadKind::Ice));
    close("silt H", silt.shear, k * density * G * depth * depth / 2.0);
    close("silt h_H", silt.shear_arm, depth / 3.0);
    close("ice H", ice.shear, force);
    close("ice h_H", ice.shear_arm, HW - thickness / 2.0);
    close("V", silt.normal + ice.normal, 0.0);
    close("reservoir", load(LoadKind::Reservoir).shear, RHO_W * G * HW * HW / 2.0);
}
