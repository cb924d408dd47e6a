//! The guaranteed bound of `damfem solve --estimate` across the inputs the CLI accepts.

use super::support::{assert_ok, check_summary, damfem, repo, TempDir};
use std::path::Path;

/// `damfem solve -q <scene> --effectivity -o <dir> [extra]`; its summary.json.
fn effectivity_run(dir: &Path, scene: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["solve", "-q", scene.to_str().unwrap(), "--effectivity"];
    args.extend(["-o", dir.to_str().unwrap()]);
    args.extend(extra);
    assert_ok(&damfem(&args));
    check_summary(dir)
}

// The bound on every kind of joint and load. Source: docs/method.md §2 (the error measure),
// §5.2 (the bound with friction and uplift), §5.6 (two bodies). Goal: on each kind of input the
// estimate is equilibrated to 10⁻¹² on every check and η_tot bounds the sharp reference of
// `--effectivity` (I_eff ≥ 1, the last two references within 2 %); the global values combine
// the per-cell sums, max_i η_i ≤ η_tot ≤ Σ_i η_i. Kinds: frictionless, Tresca, Coulomb and
// Mohr–Coulomb on the rigid foundation; uplift with the crack filled (one diagram, and one per
// joint of two bodies with a Mohr–Coulomb lift joint); a lift joint; a load combination with a
// pseudo-static acceleration; a degree-1 `.msh` raised by `--order 2`; the plain projection
// (δ = 0) and a large δ; γ₀ = 1 and 10⁴; the estimate beside `--strength-reduction`.
// Measured I_eff 1.08 (dam_lifts_on_rock_uplift, P1) to 4.76 (δ = 10⁸ Pa, P2).
// Parameters: gmsh's sizes × 3, P1 and P2.
#[test]
fn the_bound_holds_on_every_kind_of_input() {
    let tmp = TempDir::new("bound-kinds");
    let mesh = tmp.join("mesh");
    assert_ok(&damfem(&[
        "mesh",
        "-q",
        repo("geo/scene_a_uplift.toml").to_str().unwrap(),
        "--order",
        "1",
        "--size-factor",
        "3",
        "-o",
        mesh.to_str().unwrap(),
    ]));
    let text = std::fs::read_to_string(repo("geo/scene_a_uplift.toml")).unwrap();
    let msh_scene = mesh.join("scene_a_uplift.toml");
    let geometry = format!("geometry = {:?}", mesh.join("scene_a_uplift.msh").display().to_string());
    std::fs::write(&msh_scene, text.replace("geometry = \"scene_a_friction.geo\"", &geometry)).unwrap();
    let cases: [(&str, &Path, &[&str]); 16] = [
        ("frictionless", &repo("geo/scene_a.toml"), &["--order", "2"]),
        ("tresca", &repo("geo/scene_a.toml"), &["--order", "2", "--threshold", "2e5"]),
        ("coulomb", &repo("geo/scene_a_friction.toml"), &["--order", "2"]),
        ("mohr-coulomb", &repo("geo/scene_a.toml"), &["--order", "1", "--friction", "0.8", "--cohesion", "2e5"]),
        ("uplift", &repo("geo/scene_a_uplift.toml"), &["--order", "2"]),
        ("joint-uplift", &repo("geo/dam_lifts_on_rock_uplift.toml"), &["--order", "1"]),
        ("two-bodies", &repo("geo/dam_on_rock.toml"), &["--order", "1"]),
        ("lift-joint", &repo("geo/dam_lift_joint.toml"), &["--order", "2"]),
        ("earthquake", &repo("geo/scene_a_combinations.toml"), &["--order", "1", "--combination", "earthquake"]),
        ("raised-msh", &msh_scene, &["--order", "2"]),
        ("semismooth", &repo("geo/scene_a.toml"), &["--order", "1", "--semismooth"]),
        ("large-delta", &repo("geo/scene_a.toml"), &["--order", "2", "--delta", "1e8"]),
        ("small-gamma0", &repo("geo/scene_a_uplift.toml"), &["--order", "2", "--gamma0", "1"]),
        ("large-gamma0", &repo("geo/scene_a_uplift.toml"), &["--order", "2", "--gamma0", "1e4"]),
        ("strength", &repo("geo/scene_a_uplift.toml"), &["--order", "1", "--strength-reduction"]),
        ("mohr-coulomb-p2", &repo("geo/scene_a.toml"), &["--order", "2", "--friction", "0.8", "--cohesion", "2e5"]),
    ];
    for (name, scene, extra) in cases {
        // the .msh has the sizes of the .geo × 3 already
        let coarse: &[&str] = if name == "raised-msh" { &[] } else { &["--size-factor", "3"] };
        let s = effectivity_run(&tmp.join(name), scene, &[extra, coarse].concat());
        let estimate = &s["estimate"];
        for (check, value) in estimate["equilibration"].as_object().unwrap() {
            if let Some(v) = value.as_f64() {
                assert!(v <= 1e-12, "{name}: {check} violated by {v:e}");
            }
        }
        let global = &estimate["global"];
        let eta = |key: &str| global[key].as_f64().unwrap_or_else(|| panic!("{name}: {key} in {global}"));
        let parts = ["osc", "flux", "neu", "disc", "reg", "lin"].map(eta);
        let largest = parts.iter().copied().fold(0.0, f64::max);
        let sum: f64 = parts.iter().sum();
        assert!(largest <= eta("tot") && eta("tot") <= sum * (1.0 + 1e-14), "{name}: {global}");
        let e = &s["effectivity"];
        assert_eq!(e["converged"], true, "{name}: {e}");
        assert!(e["i_eff"].as_f64().unwrap() >= 1.0, "{name}: eta_tot below the reference: {e}");
    }
}
