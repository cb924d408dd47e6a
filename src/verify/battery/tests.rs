//! The statics against hand calculations, and the draw's admissibility.

use super::statics::{area_centroid, gamma_w, water};
use super::*;

// A rectangle 10 m wide and 20 m high, its heel at the origin, the water at 20 m on its
// upstream side x = 0: the thrust γ_w 20²/2 at a third of the height.
#[test]
fn water_on_a_vertical_face_is_the_hydrostatic_triangle() {
    let (f, m) = water([0.0, 20.0], [0.0, 0.0], 20.0);
    let thrust = gamma_w() * 200.0;
    assert!((f[0] - thrust).abs() < 1e-9 * thrust && f[1].abs() < 1e-9 * thrust, "{f:?}");
    assert!((m + thrust * 20.0 / 3.0).abs() < 1e-9 * thrust * 20.0, "{m}");
}

// Scene A under its usual load (geo/scene_a_uplift.toml, docs/results.md "Dam safety"): H = 50 m,
// B = 40 m, C = 5 m, reservoir at 45 m, drains 5 m from the heel, 2/3 effective. The
// weight is W = 2.6487·10⁷ N/m, the thrust γ_w 45²/2 = 9.9326·10⁶ N/m, the uplift without
// crack 3.6785·10⁶ N/m; with the crack past the drains, the triangle-and-strip
// γ_w 45 (s_c + (L − s_c)/2).
#[test]
fn scene_a_has_the_forces_of_the_readme() {
    let case = DamCase {
        seed: 0,
        height: 50.0,
        crest: 5.0,
        slope: 0.7,
        batter: None,
        gallery: None,
        base_angle: 0.0,
        foundation: Foundation::Rigid,
        friction: 0.8391,
        cohesion: 0.0,
        bond: None,
        reservoir: 45.0,
        tailwater: None,
        drains: Some(Drains { distance: 5.0, efficiency: 0.6667 }),
        crack: Crack::Full,
        acceleration: 0.0,
        order: 2,
    };
    let s = case.statics();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-4 * b.abs();
    assert!(close(s.length, 40.0) && close(s.pressing, 2.6487e7), "{s:?}");
    assert!(close(s.tangential, -9.9326e6) && close(s.uplift, 3.6785e6), "{s:?}");
    let (u, _) = case.uplift(6.0);
    assert!(close(u, gamma_w() * 45.0 * (6.0 + 17.0)), "{u}");
}

// The section drawn is closed and counter-clockwise, the base from the heel to the toe at
// angle β, and the drawn case is as asked: N > 0, and FS ≥ 1.1 or ≤ 0.9.
#[test]
fn drawn_sections_are_admissible() {
    for case in cases(1, 200) {
        let (area, _) = area_centroid(&case.outline());
        assert!(area > 0.0, "{case:?}");
        let toe = case.toe();
        assert!((toe[1].atan2(toe[0]) - case.base_angle).abs() < 1e-12);
        let s = case.statics();
        let fs = (case.cohesion * s.length + case.friction * s.normal) / s.tangential.abs();
        let friction_alone = case.friction * s.normal / s.tangential.abs();
        assert!(s.normal > 0.0 && (friction_alone >= 1.1 - 1e-9 || fs <= 0.9 + 1e-9), "{case:?}");
    }
}
