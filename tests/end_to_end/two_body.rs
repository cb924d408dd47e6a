//! End-to-end tests of joints between two meshed bodies (`[joints.<curve>]`,
//! docs/method.md §1.10) through the `damfem` binary: geo/dam_on_rock.toml against the bonded
//! geo/scene_b.toml, and the refusals.

use super::cli::{assert_ok, assert_refused, check_summary, damfem, repo, TempDir};
use std::path::PathBuf;

/// Writes geo/dam_on_rock.toml with `edit` applied into `tmp` as `name`, the geometry by
/// absolute path.
fn dam_on_rock(tmp: &TempDir, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    edited(tmp, "dam_on_rock", name, edit)
}

/// Writes geo/`scene`.toml with `edit` applied into `tmp` as `name`, the geometry by absolute
/// path.
fn edited(tmp: &TempDir, scene: &str, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(repo(&format!("geo/{scene}.toml"))).unwrap();
    let geometry = format!("geometry = {:?}", repo(&format!("geo/{scene}.geo")).display().to_string());
    let path = tmp.join(name);
    std::fs::write(&path, edit(text.replace(&format!("geometry = \"{scene}.geo\""), &geometry))).unwrap();
    path
}

// The dam on its rock block with a frictionless joint. Source: geo/dam_on_rock.toml.
// Goal: `damfem solve` runs; the joint carries no shear (T = 0, frictionless) and presses
// (N > 0); the boundary VTU holds the joint's pressure; the dam slides on the rock, so its
// crest moves downstream more than on the bonded interface of geo/scene_b.toml.
// Parameters: P2, gmsh's sizes × 2.
#[test]
fn dam_on_rock_solves_with_its_joint() {
    let tmp = TempDir::new("two-body-dam");
    let run = |scene: &str, dir: &str| {
        let out_dir = tmp.join(dir);
        let out = damfem(&[
            "solve",
            "-q",
            repo(scene).to_str().unwrap(),
            "--size-factor",
            "2",
            "-o",
            out_dir.to_str().unwrap(),
        ]);
        assert_ok(&out);
        (check_summary(&out_dir), String::from_utf8_lossy(&out.stdout).into_owned())
    };
    let (joint, _) = run("geo/dam_on_rock.toml", "joint");
    let (bonded, _) = run("geo/scene_b.toml", "bonded");
    let contact = &joint["contact"];
    let (n, t) = (contact["normal_force"].as_f64().unwrap(), contact["tangential_force"].as_f64().unwrap());
    println!("joint: N = {n:.4e} N/m, T = {t:.4e} N/m");
    assert!(n > 0.0 && t == 0.0, "N = {n}, T = {t}");
    let boundary = std::fs::read_to_string(tmp.join("joint/dam_on_rock_boundary.vtu")).unwrap();
    assert!(boundary.contains("contact_pressure"));
    let (u_joint, u_bonded) =
        (joint["max_displacement"].as_f64().unwrap(), bonded["max_displacement"].as_f64().unwrap());
    println!("max |u|: joint {u_joint:.4e} m, bonded {u_bonded:.4e} m");
    assert!(u_joint > u_bonded, "the joint lets the dam move more: {u_joint} vs {u_bonded}");
}

// Bad input on joints, each one error line, exit 1 and no output: a joint on the outer
// boundary, a curve both a joint and a boundary curve, a joint law key out of range (on the
// dam on its rock, and on the second of the two joints of geo/dam_lifts_on_rock.toml, whose
// error names that joint), a sliding plane ([safety] joint) that is no joint, a
// [contact] law key beside joints, a law on a bonded interface, a slave that is not a side, an
// unknown joint curve, contact on the interface without a joint, a body that its frictionless
// joints leave free to slide (the dam on its rock; the upper block of geo/dam_lift_joint.toml,
// a body of its own once its joint is split), a [contact] flag on a joint, and `damfem safety` on a joint whose
// heel it cannot tell.
#[test]
fn joints_refuse_bad_input() {
    let tmp = TempDir::new("two-body-bad");
    let count = std::cell::Cell::new(0);
    let scene = |edit: &dyn Fn(String) -> String| {
        count.set(count.get() + 1);
        dam_on_rock(&tmp, &format!("scene-{}.toml", count.get()), edit)
    };
    let cases: Vec<(PathBuf, &str, Vec<&str>, Vec<&str>)> = vec![
        (
            scene(&|t| t.replace("\n[joints.joint]\n", "\n[joints.rock_bottom]\n")),
            "solve",
            vec![],
            vec!["rock_bottom", "both a joint", "[boundary.rock_bottom]"],
        ),
        (
            scene(&|t| t.replace("\n[joints.joint]\n", "\n[joints.ground]\n")),
            "solve",
            vec![],
            vec!["curve 'ground' is not shared by two surfaces", "bounds 'rock' only"],
        ),
        (
            scene(&|t| t.replace("theta = 0.0\nslave", "friction = -1.0\nslave")),
            "solve",
            vec![],
            vec!["joints.joint.friction = -1", "non-negative"],
        ),
        (
            edited(&tmp, "dam_lifts_on_rock", "bad-sliding-plane.toml", |t| {
                t.replace("joint = \"base\"", "joint = \"crest\"")
            }),
            "safety",
            vec![],
            vec!["safety.joint = 'crest' is not a joint", "base, lift"],
        ),
        (
            edited(&tmp, "dam_lifts_on_rock", "bad-lift.toml", |t| t.replace("cohesion = 5.0e5", "cohesion = -1.0")),
            "solve",
            vec![],
            vec!["joints.lift.cohesion = -1", "non-negative"],
        ),
        (
            scene(&|t| format!("{t}\n[contact]\nfriction = 0.6\n")),
            "solve",
            vec![],
            vec!["contact.friction", "[joints.joint]"],
        ),
        (
            repo("geo/scene_b.toml"),
            "solve",
            vec!["--friction", "0.6"],
            vec!["no curve has role contact", "bonded", "[joints.<curve>]"],
        ),
        (
            scene(&|t| t.replace("slave = \"concrete\"", "slave = \"water\"")),
            "solve",
            vec![],
            vec!["slave 'water'", "rock"],
        ),
        (
            scene(&|t| t.replace("\n[joints.joint]\n", "\n[joints.gallery]\n")),
            "solve",
            vec![],
            vec!["joint 'gallery'", "physical curve"],
        ),
        (
            scene(&|t| {
                t.replace("\n[joints.joint]\n", "\n[boundary.joint]\nrole = \"contact\"\n\n[contact]\n")
                    .replace("slave = \"concrete\"", "")
            }),
            "solve",
            vec![],
            vec!["role contact (a rigid foundation)", "[joints.joint] table"],
        ),
        (
            scene(&|t| format!("{t}\n[joints.bonded]\nslave = \"concrete\"\n")),
            "solve",
            vec![],
            vec!["nothing holds the body of 'concrete'", "translation along x"],
        ),
        (
            edited(&tmp, "dam_lift_joint", "frictionless-lift.toml", |t| {
                t.replace("friction = 0.8391\ncohesion = 5.0e5\n", "")
            }),
            "solve",
            vec![],
            vec!["nothing holds the body of 'upper_block'", "translation along x"],
        ),
        (repo("geo/dam_on_rock.toml"), "solve", vec!["--gamma0", "10"], vec!["--gamma0", "[joints.joint]"]),
        (
            scene(&|t| t.replace("hydrostatic = { density = 1000.0, level = 50.0 }", "traction = [1.0e5, 0.0]")),
            "safety",
            vec![],
            vec!["straight joint whose heel is known"],
        ),
    ];
    for (input, command, extra, keywords) in cases {
        assert_refused("two-body-input", command, &input, &extra, &keywords);
    }
}

// The error estimate across the joint through the CLI. Source: geo/dam_on_rock.toml,
// docs/method.md §5.6. Goal: `damfem solve --estimate --effectivity` and `damfem adapt` run on
// two meshed bodies; every estimate is equilibrated (the run would refuse it otherwise), η_tot
// bounds the sharp reference (I_eff ≥ 1) on every step, also once the sides no longer match,
// and falls along the adaptive run; `summary.json` counts the joint's facets (`faces`) and its
// pieces, one per facet on the matching sides of `solve`, more on the last adaptive mesh.
// Parameters: P2, gmsh's sizes × 2, three adaptive steps.
#[test]
fn dam_on_rock_is_estimated_across_its_joint() {
    let tmp = TempDir::new("two-body-estimate");
    let scene = repo("geo/dam_on_rock.toml");
    let solve_dir = tmp.join("solve");
    let args = ["--size-factor", "2", "--estimate", "--effectivity", "-q", "-o", solve_dir.to_str().unwrap()];
    let out = damfem(&[&["solve", scene.to_str().unwrap()], &args[..]].concat());
    assert_ok(&out);
    let summary = check_summary(&solve_dir);
    let count = |summary: &serde_json::Value, key: &str| summary["contact"][key].as_u64().unwrap();
    assert_eq!(count(&summary, "pieces"), count(&summary, "faces"), "matching sides: one piece per facet");
    let i_eff = summary["effectivity"]["i_eff"].as_f64().unwrap();
    println!("solve: I_eff = {i_eff:.3}, equilibration {}", summary["estimate"]["equilibration"]);
    assert!(i_eff >= 1.0, "I_eff = {i_eff}");
    let adapt_dir = tmp.join("adapt");
    let args = ["--size-factor", "2", "--steps", "3", "--effectivity", "-q", "-o", adapt_dir.to_str().unwrap()];
    let out = damfem(&[&["adapt", scene.to_str().unwrap()], &args[..]].concat());
    assert_ok(&out);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(adapt_dir.join("history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap();
    let eta: Vec<f64> = steps.iter().map(|s| s["eta"]["tot"].as_f64().unwrap()).collect();
    let i_eff: Vec<f64> = steps.iter().map(|s| s["i_eff"].as_f64().unwrap()).collect();
    println!("adapt: η_tot {eta:?}, I_eff {i_eff:?}");
    assert_eq!(steps.len(), 3);
    assert!(i_eff.iter().all(|&i| i >= 1.0), "I_eff {i_eff:?}");
    assert!(eta.windows(2).all(|w| w[1] < w[0]), "η_tot {eta:?}");
    // the last step's sides, remeshed each with its own sizes, do not match: a slave facet
    // facing two master facets is two pieces
    let last = check_summary(&adapt_dir);
    let (faces, pieces) = (count(&last, "faces"), count(&last, "pieces"));
    println!("adapt, last step: {faces} slave facets, {pieces} pieces");
    assert!(pieces > faces, "{pieces} pieces on {faces} facets");
}

// One law per joint. Source: geo/dam_lifts_on_rock.toml, the dam of Scene A in two lifts on
// the rock block of Scene B: [joints.base] a Coulomb joint without cohesion, [joints.lift] a
// Mohr–Coulomb joint (c = 0.5 MPa) with γ₀ = 50; docs/method.md §1.10. Goal: `damfem solve
// --estimate --effectivity` solves it; `summary.json` gives each curve its own law, γ₀ and
// forces, and each block is held by its joint alone, so the lift joint carries the upper
// block's weight ρ g |A_upper| and the water's thrust on its upstream face ρ_w g (45 − 20)²/2,
// and the base the whole dam's weight and thrust ρ_w g 45²/2, each to 10⁻⁶; FS_LE ≥ 1 on each
// (the solved traction satisfies its own law); the estimate is equilibrated to 10⁻¹² on every
// check and η_tot bounds the sharp reference (I_eff ≥ 1).
// Parameters: P2, gmsh's sizes × 2.
#[test]
fn each_joint_has_its_own_law() {
    let tmp = TempDir::new("two-laws");
    let dir = tmp.join("solve");
    let scene = repo("geo/dam_lifts_on_rock.toml");
    let args = ["--size-factor", "2", "--estimate", "--effectivity", "-q", "-o", dir.to_str().unwrap()];
    let out = damfem(&[&["solve", scene.to_str().unwrap()], &args[..]].concat());
    assert_ok(&out);
    let summary = check_summary(&dir);
    let curves = summary["contact"]["curves"].as_array().unwrap().clone();
    let curve = |name: &str| curves.iter().find(|c| c["curve"] == name).unwrap_or_else(|| panic!("{curves:?}")).clone();
    let (base, lift) = (curve("base"), curve("lift"));
    println!("base {base}\nlift {lift}");
    assert_eq!((base["law"].as_str(), base["gamma0"].as_f64()), (Some("coulomb"), Some(100.0)), "{base}");
    assert!(base["cohesion"].is_null(), "{base}");
    assert_eq!((lift["law"].as_str(), lift["gamma0"].as_f64()), (Some("mohr_coulomb"), Some(50.0)), "{lift}");
    assert_eq!(lift["cohesion"].as_f64(), Some(5.0e5), "{lift}");
    let rho_g = 2400.0 * 9.81;
    let thrust = |depth: f64| 0.5 * 1000.0 * 9.81 * depth * depth;
    let expected = [
        (&base, rho_g * 0.5 * (40.0 + 5.0) * 50.0, thrust(45.0)),
        (&lift, rho_g * 0.5 * (26.0 + 5.0) * 30.0, thrust(25.0)),
    ];
    for (c, weight, thrust) in expected {
        let number = |key: &str| c[key].as_f64().unwrap_or_else(|| panic!("{key}: {c}"));
        let (n, t, fs) = (number("normal_force"), number("tangential_force"), number("sliding_safety_factor"));
        assert!((n - weight).abs() <= 1e-6 * weight, "{}: N = {n}, the blocks above weigh {weight}", c["curve"]);
        assert!((t + thrust).abs() <= 1e-6 * thrust, "{}: T = {t}, the thrust is {thrust}", c["curve"]);
        assert!(fs >= 1.0, "{}: FS_LE = {fs}", c["curve"]);
    }
    let checks = summary["estimate"]["equilibration"].as_object().unwrap();
    assert!(checks.values().all(|v| v.as_f64().unwrap() <= 1e-12), "{checks:?}");
    let i_eff = summary["effectivity"]["i_eff"].as_f64().unwrap();
    println!("I_eff = {i_eff:.3}, equilibration {checks:?}");
    assert!(i_eff >= 1.0, "I_eff = {i_eff}");
}

// The sliding plane among several joints. Source: geo/dam_lifts_on_rock.toml, whose
// `[safety] joint = "base"` names the dam–rock joint below the lift joint; docs/method.md §1.9.
// Goal: `damfem safety` reports the base alone: its joint line from the heel (0, 0) to the toe
// (40, 0), joint.csv with faces at y = 0 only, N the whole dam's weight (the base carries both
// lifts; with the lift joint's faces it would be 1.41 times that) to 10⁻⁵, |T| the thrust
// ρ_w g 45²/2 to 10⁻² (the adaptive loop's Newton stops once its linearisation error is below
// the discretisation error: 1.6·10⁻³ here), FS_SR's bracket within 0.5 % around F W/thrust, the
// exact factor of a horizontal Coulomb joint (c = 0) that alone holds the dam, since the lift
// joint (FS_LE 7.2) holds far longer.
// Parameters: P1, gmsh's sizes × 2, one mesh.
#[test]
fn safety_analyses_the_joint_it_is_given() {
    let tmp = TempDir::new("sliding-plane");
    let scene = repo("geo/dam_lifts_on_rock.toml");
    let dir = tmp.join("safety");
    let args = ["--size-factor", "2", "--order", "1", "--max-steps", "1", "-q", "-o", dir.to_str().unwrap()];
    let out = damfem(&[&["safety", scene.to_str().unwrap()], &args[..]].concat());
    assert_ok(&out);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("safety.json")).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    let line = &report["joint_line"];
    assert_eq!((number(&line["heel"][0]), number(&line["heel"][1]), number(&line["length"])), (0.0, 0.0, 40.0));
    let csv = std::fs::read_to_string(dir.join("joint.csv")).unwrap();
    let y: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    assert!(!y.is_empty() && y.iter().all(|&y| y == 0.0), "{csv}");
    let r = &report["resultant"];
    let (n, t) = (number(&r["normal_force"]), number(&r["tangential_force"]));
    let weight = 2400.0 * 9.81 * 0.5 * (40.0 + 5.0) * 50.0;
    let thrust = 0.5 * 1000.0 * 9.81 * 45.0 * 45.0;
    println!("N = {n:.6e} (W {weight:.6e}), T = {t:.6e} (thrust {thrust:.6e}), {}", report["strength_reduction"]);
    assert!((n - weight).abs() <= 1e-5 * weight, "N = {n}, the dam weighs {weight}");
    assert!((t.abs() - thrust).abs() <= 1e-2 * thrust, "|T| = {}, the thrust is {thrust}", t.abs());
    let exact = 0.8391 * weight / thrust;
    let sr = &report["strength_reduction"];
    let (held, failed) = (number(&sr["held"]), number(&sr["failed"]));
    assert!(held <= exact && failed >= exact && failed <= 1.005 * held, "{sr} against {exact}");
}

// A lift joint inside the dam. Source: geo/dam_lift_joint.toml (Scene A's dam cut at
// y = 20 m, a Mohr–Coulomb joint between the two blocks, reservoir at 65 m, base fixed).
// Goal: `damfem solve` and `damfem adapt` run on it; the joint carries the upper block alone,
// so N is its weight ρ g |A| (A the trapezoid 0 ≤ x ≤ 26 − 0.7 (y − 20), 20 ≤ y ≤ 50) and −T
// the water's thrust on its upstream face, ρ_w g ∫₂₀⁵⁰ (65 − y) dy, both to 10⁻⁶; the joint
// opens at its upstream end (the contact zone ends at the downstream end x = 26 m and starts
// inside the joint), and η_tot falls along the adaptive run.
// Parameters: P2, gmsh's sizes × 2; `adapt` three steps.
#[test]
fn lift_joint_opens_at_its_upstream_end() {
    let tmp = TempDir::new("lift-joint");
    let scene = repo("geo/dam_lift_joint.toml");
    let solve_dir = tmp.join("solve");
    let out =
        damfem(&["solve", "-q", scene.to_str().unwrap(), "--size-factor", "2", "-o", solve_dir.to_str().unwrap()]);
    assert_ok(&out);
    let contact = check_summary(&solve_dir)["contact"].clone();
    let (n, t) = (contact["normal_force"].as_f64().unwrap(), contact["tangential_force"].as_f64().unwrap());
    let weight = 2400.0 * 9.81 * 0.5 * (26.0 + 5.0) * 30.0;
    let thrust = 1000.0 * 9.81 * (65.0 * 30.0 - 0.5 * (50.0f64.powi(2) - 20.0f64.powi(2)));
    let extent: Vec<f64> =
        contact["contact_extent"].as_array().unwrap().iter().map(|p| p[0].as_f64().unwrap()).collect();
    let length = contact["contact_length"].as_f64().unwrap();
    println!("N = {n:.6e} (weight {weight:.6e}), T = {t:.6e} (thrust {thrust:.6e}); contact {extent:?}, length {length:.4} m");
    assert!((n - weight).abs() <= 1e-6 * weight, "N = {n}, the upper block weighs {weight}");
    assert!((t + thrust).abs() <= 1e-6 * thrust, "T = {t}, the thrust is {thrust}");
    assert!(extent[0] > 1.0 && (extent[1] - 26.0).abs() < 1e-9, "contact from {} to {}", extent[0], extent[1]);
    assert!(length < 26.0 - 1.0, "contact length {length}");
    let adapt_dir = tmp.join("adapt");
    let args = ["--size-factor", "2", "--steps", "3", "-q", "-o", adapt_dir.to_str().unwrap()];
    let out = damfem(&[&["adapt", scene.to_str().unwrap()], &args[..]].concat());
    assert_ok(&out);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(adapt_dir.join("history.json")).unwrap()).unwrap();
    let eta: Vec<f64> =
        history["steps"].as_array().unwrap().iter().map(|s| s["eta"]["tot"].as_f64().unwrap()).collect();
    println!("adapt: η_tot {eta:?}");
    assert_eq!(eta.len(), 3);
    assert!(eta.windows(2).all(|w| w[1] < w[0]), "η_tot {eta:?}");
}

// Newton on the lift joint along the default adaptive run. Source: geo/dam_lift_joint.toml at
// its default sizes (docs/method.md §1.7, the C¹ closed indicator of the cohesion; §5.3, the
// displacement moved to the next mesh side by side). Goal: every mesh converges, without a
// restart at a smoother δ: each mesh after the first within 40 Newton steps (the steep,
// kinked cohesion switch took 28, 151 and 192 steps on meshes 2 to 4, the next meshes
// stalled), and η_tot falls. Parameters: P2, `adapt` four steps.
#[test]
fn lift_joint_adapts_in_few_newton_steps() {
    let tmp = TempDir::new("lift-joint-newton");
    let scene = repo("geo/dam_lift_joint.toml");
    let dir = tmp.join("adapt");
    let out = damfem(&["adapt", scene.to_str().unwrap(), "--steps", "4", "-q", "-o", dir.to_str().unwrap()]);
    assert_ok(&out);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap();
    let column = |f: &dyn Fn(&serde_json::Value) -> f64| -> Vec<f64> { steps.iter().map(f).collect() };
    let n_lin = column(&|s| s["n_lin"].as_f64().unwrap());
    let eta = column(&|s| s["eta"]["tot"].as_f64().unwrap());
    println!("N_lin {n_lin:?}, η_tot {eta:?}, δ {:?}", column(&|s| s["delta"].as_f64().unwrap()));
    assert_eq!(steps.len(), 4);
    // a restart at a smoother δ discards a run of max_iter = 100 steps
    assert!(n_lin[1..].iter().all(|&n| n <= 40.0), "Newton steps per mesh {n_lin:?}");
    assert!(eta.windows(2).all(|w| w[1] < w[0]), "η_tot {eta:?}");
}
