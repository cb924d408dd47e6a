//! End-to-end tests of joints between two meshed bodies (`[joints.<curve>]`,
//! docs/method.md §1.10) through the `damfem` binary: geo/dam_on_rock.toml against the bonded
//! geo/scene_b.toml, and the refusals.

use super::support::{assert_ok, assert_refused, check_summary, damfem, repo, TempDir};
use std::path::{Path, PathBuf};

/// Writes geo/dam_on_rock.toml with `edit` applied into `tmp` as `name`, the geometry by
/// absolute path.
fn dam_on_rock(tmp: &TempDir, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    edited(tmp, "dam_on_rock", name, edit)
}

/// Writes geo/`scene`.toml with `edit` applied into `tmp` as `name`, the geometry by absolute
/// path.
fn edited(tmp: &TempDir, scene: &str, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let text = std::fs::read_to_string(repo(&format!("geo/{scene}.toml"))).unwrap();
    let line = text.lines().find(|l| l.starts_with("geometry = ")).expect("the scene names its geometry");
    let file = line.trim_start_matches("geometry = ").trim_matches('"');
    let geometry = format!("geometry = {:?}", repo(&format!("geo/{file}")).display().to_string());
    let path = tmp.join(name);
    std::fs::write(&path, edit(text.replace(line, &geometry))).unwrap();
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
// ρ_w g 45²/2 to 10⁻⁶ (measured 5.8·10⁻¹⁴: Newton runs to its tolerance on the last mesh; at
// the iterate where the adaptive loop's rule stopped it, |T| was 1.6·10⁻³ off), FS_SR's bracket within 0.5 % around F W/thrust, the
// exact factor of a horizontal Coulomb joint (c = 0) that alone holds the dam, since the lift
// joint (FS_LE 7.2) holds far longer.
// Parameters: P1, gmsh's sizes × 2, one mesh.
#[test]
fn safety_analyses_the_joint_it_is_given() {
    let tmp = TempDir::new("sliding-plane");
    let scene = repo("geo/dam_lifts_on_rock.toml");
    let dir = tmp.join("safety");
    let report = quick_safety(&scene, &dir);
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    assert_plane(&report, &dir, 0.0, 40.0);
    let r = &report["resultant"];
    let (n, t) = (number(&r["normal_force"]), number(&r["tangential_force"]));
    let weight = 2400.0 * 9.81 * 0.5 * (40.0 + 5.0) * 50.0;
    let thrust = 0.5 * 1000.0 * 9.81 * 45.0 * 45.0;
    println!(
        "(N − W)/W = {:.2e}, (|T| − thrust)/thrust = {:.2e}, {}",
        (n - weight) / weight,
        (t.abs() - thrust) / thrust,
        report["strength_reduction"]
    );
    assert!((n - weight).abs() <= 1e-5 * weight, "N = {n}, the dam weighs {weight}");
    assert!((t.abs() - thrust).abs() <= 1e-6 * thrust, "|T| = {}, the thrust is {thrust}", t.abs());
    let exact = 0.8391 * weight / thrust;
    let sr = &report["strength_reduction"];
    let (held, failed) = (number(&sr["held"]), number(&sr["failed"]));
    assert!(held <= exact && failed >= exact && failed <= 1.005 * held, "{sr} against {exact}");
}

/// `damfem safety` on `scene` (P1, gmsh's sizes × 2, one mesh) into `dir`: its safety.json.
fn quick_safety(scene: &Path, dir: &Path) -> serde_json::Value {
    let args = ["--size-factor", "2", "--order", "1", "--max-steps", "1", "-q", "-o", dir.to_str().unwrap()];
    assert_ok(&damfem(&[&["safety", scene.to_str().unwrap()], &args[..]].concat()));
    serde_json::from_str(&std::fs::read_to_string(dir.join("safety.json")).unwrap()).unwrap()
}

/// The sliding plane of a safety report in `dir`: the horizontal joint line from (0, `y`) over
/// `length`, and joint.csv's faces all at height `y`.
fn assert_plane(report: &serde_json::Value, dir: &Path, y: f64, length: f64) {
    let line = &report["joint_line"];
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    assert_eq!((number(&line["heel"][0]), number(&line["heel"][1]), number(&line["length"])), (0.0, y, length));
    let csv = std::fs::read_to_string(dir.join("joint.csv")).unwrap();
    let heights: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(1).unwrap().parse().unwrap()).collect();
    assert!(!heights.is_empty() && heights.iter().all(|&h| h == y), "{csv}");
}

// Strength reduction on the sliding plane alone. Source: geo/dam_lifts_on_rock.toml with
// `[safety] joint = "lift"` and the lift joint's cohesion removed; docs/method.md §1.9. Goal:
// FS_SR divides the strength of the lift joint only, the base keeping its own: its bracket
// within 0.5 % around F W_u/T_u = 2.9966, the exact factor of the horizontal Coulomb lift
// joint (c = 0) that alone holds the upper block (W_u its weight, T_u = ρ_w g (45 − 20)²/2 the
// thrust on its face). Dividing the base's strength too would report the base's 2.2376 (what
// `damfem safety` did before). Parameters: P1, gmsh's sizes × 2, one mesh.
#[test]
fn safety_reduces_the_sliding_plane_alone() {
    let tmp = TempDir::new("sliding-plane-alone");
    let scene = edited(&tmp, "dam_lifts_on_rock", "lift_without_cohesion.toml", |text| {
        let edited = text.replace("cohesion = 5.0e5\n", "").replace("joint = \"base\"", "joint = \"lift\"");
        assert!(!edited.contains("5.0e5") && edited.contains("joint = \"lift\"") && edited != text);
        edited
    });
    let dir = tmp.join("safety");
    let report = quick_safety(&scene, &dir);
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    let weight = 2400.0 * 9.81 * 0.5 * (26.0 + 5.0) * 30.0;
    let thrust = 0.5 * 1000.0 * 9.81 * 25.0 * 25.0;
    let exact = 0.8391 * weight / thrust;
    let sr = &report["strength_reduction"];
    println!("FS_SR {sr} against F W_u/T_u = {exact:.5}");
    let (held, failed) = (number(&sr["held"]), number(&sr["failed"]));
    assert!(held <= exact && failed >= exact && failed <= 1.005 * held, "{sr} against {exact}");
}

// A frictionless sliding plane beside a frictional joint. Source: geo/dam_lifts_on_rock.toml
// with `[safety] joint = "lift"`, the lift joint frictionless (no friction, no cohesion) and
// the crest held along x so that the upper block stands; docs/method.md §1.9. Goal: the lift
// joint has no sliding resistance of its own, so `damfem safety` computes neither FS_LE nor
// FS_SR on it and says why, although the base has friction (before, the friction of any joint
// let FS_SR run on the lift joint, which held at every reduction: "> 1010" was reported).
// Parameters: P1, gmsh's sizes × 2, one mesh.
#[test]
fn safety_on_a_frictionless_plane_computes_no_factor() {
    let tmp = TempDir::new("frictionless-plane");
    let scene = edited(&tmp, "dam_lifts_on_rock", "frictionless_lift.toml", |text| {
        text.replace("friction = 0.8391\ncohesion = 5.0e5\n", "")
            .replace("joint = \"base\"", "joint = \"lift\"")
            .replace(
                "[boundary.upstream]",
                "[boundary.crest]\nrole = \"dirichlet\"\nfix = \"x\"\n\n[boundary.upstream]",
            )
    });
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(!text.contains("5.0e5") && text.contains("joint = \"lift\"") && text.contains("[boundary.crest]"));
    let dir = tmp.join("safety");
    let args = ["--size-factor", "2", "--order", "1", "--max-steps", "1", "-q", "-o", dir.to_str().unwrap()];
    assert_ok(&damfem(&[&["safety", scene.to_str().unwrap()], &args[..]].concat()));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("safety.json")).unwrap()).unwrap();
    println!(
        "FS_LE {}, FS_SR {}, note {}",
        report["sliding_safety_factor"], report["strength_reduction"], report["safety_factor_note"]
    );
    assert!(report["sliding_safety_factor"].is_null(), "{report}");
    assert!(report["strength_reduction"].is_null(), "{report}");
    let note = report["safety_factor_note"].as_str().unwrap_or_else(|| panic!("{report}"));
    assert!(note.contains("frictionless"), "{note}");
}

// A base in two parts with their own tables, one of them named. Source: geo/dam_lifts_on_rock.toml
// with its base cut at x = 20 m into "base" (the heel's half, `[safety] joint = "base"`) and
// "base_down" (its own Coulomb table); docs/method.md §1.9. Goal: the sliding plane is the line
// of the named curve with every joint curve on it, so `damfem safety` reports the whole base as
// on the uncut scene: L = 40 m, N = the dam's weight, e = s_R − 20 m within the middle third
// (before, L was the named half's 20 m while N, T and s_R were the whole base's: e = +9.14 m,
// outside the middle third, and the "toe" mean taken at mid-base). Parameters: P1, gmsh's
// sizes × 2, one mesh.
#[test]
fn safety_plane_spans_every_joint_curve_on_its_line() {
    let tmp = TempDir::new("split-base");
    let geo = std::fs::read_to_string(repo("geo/dam_lifts_on_rock.geo")).unwrap();
    let cuts = [
        ("Point(10) = {B + L, 0, 0, hr};", "Point(10) = {B + L, 0, 0, hr};\nPoint(11) = {B / 2, 0, 0, hb};"),
        ("Line(1) = {1, 2};", "Line(1) = {1, 11};\nLine(13) = {11, 2};"),
        ("Curve Loop(1) = {1, 2, -7, 6};", "Curve Loop(1) = {1, 13, 2, -7, 6};"),
        ("Curve Loop(3) = {8, 1, 12, 11, 10, 9};", "Curve Loop(3) = {8, 1, 13, 12, 11, 10, 9};"),
        ("Physical Curve(\"base\") = {1};", "Physical Curve(\"base\") = {1};\nPhysical Curve(\"base_down\") = {13};"),
    ];
    let geo = cuts.iter().fold(geo, |g, (from, to)| {
        assert!(g.contains(from), "{from}");
        g.replace(from, to)
    });
    let geometry = tmp.join("split_base.geo");
    std::fs::write(&geometry, geo).unwrap();
    let text = std::fs::read_to_string(repo("geo/dam_lifts_on_rock.toml")).unwrap();
    let down = "[joints.base_down]\ngamma0 = 100.0\ntheta = 0.0\nfriction = 0.8391\nslave = \"lower_block\"\n\n";
    let edited = text
        .replace("\"dam_lifts_on_rock.geo\"", &format!("{:?}", geometry.display().to_string()))
        .replace("\n[joints.lift]\n", &format!("\n{down}[joints.lift]\n"));
    assert!(edited.contains("[joints.base_down]") && edited.contains("joint = \"base\""));
    let scene = tmp.join("split_base.toml");
    std::fs::write(&scene, edited).unwrap();
    let dir = tmp.join("safety");
    let args = ["--size-factor", "2", "--order", "1", "--max-steps", "1", "-q", "-o", dir.to_str().unwrap()];
    assert_ok(&damfem(&[&["safety", scene.to_str().unwrap()], &args[..]].concat()));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("safety.json")).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    let line = &report["joint_line"];
    assert_eq!((number(&line["heel"][0]), number(&line["heel"][1]), number(&line["length"])), (0.0, 0.0, 40.0));
    let r = &report["resultant"];
    let (n, e) = (number(&r["normal_force"]), number(&r["eccentricity"]));
    let weight = 2400.0 * 9.81 * 0.5 * (40.0 + 5.0) * 50.0;
    println!("L = {}, (N − W)/W = {:.2e}, e = {e:.4} m", line["length"], (n - weight) / weight);
    assert!((n - weight).abs() <= 1e-5 * weight, "N = {n}, the dam weighs {weight}");
    assert!((number(&r["position"]) - 20.0 - e).abs() <= 1e-9 && e.abs() <= 40.0 / 6.0, "{r}");
    assert_eq!(r["middle_third"], true, "{r}");
    assert_eq!(number(&report["base_stresses"]["length"]), 4.0, "{report}");
}

// No safety factor of two planes at once. Source: geo/dam_lifts_on_rock.toml; docs/method.md
// §1.9. Goal: the base and the lift joint are on two lines, so `summary.json` gives no
// `sliding_safety_factor` of Γ_C as a whole (before: 2.97 on this scene, (F (N_b + N_l) +
// c L_l)/|T_b + T_l|, the factor of no plane), and each curve's own is the exact limit
// equilibrium of the horizontal joint that alone holds the blocks above it, (F W + c L)/thrust
// to 10⁻⁴ (base: W of the dam, c = 0, L = 40 m; lift: W of the upper block, c = 0.5 MPa,
// L = 26 m). Parameters: P1, gmsh's sizes × 2.
#[test]
fn summary_gives_each_plane_its_own_safety_factor() {
    let tmp = TempDir::new("planes");
    let dir = tmp.join("solve");
    let scene = repo("geo/dam_lifts_on_rock.toml");
    let args = ["--size-factor", "2", "--order", "1", "-q", "-o", dir.to_str().unwrap()];
    assert_ok(&damfem(&[&["solve", scene.to_str().unwrap()], &args[..]].concat()));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let contact = &summary["contact"];
    assert!(contact["sliding_safety_factor"].is_null(), "{contact}");
    let rho_g = 2400.0 * 9.81;
    let thrust = |h: f64| 0.5 * 1000.0 * 9.81 * h * h;
    let planes = [
        ("base", rho_g * 0.5 * (40.0 + 5.0) * 50.0, thrust(45.0), 0.0),
        ("lift", rho_g * 0.5 * (26.0 + 5.0) * 30.0, thrust(25.0), 5.0e5 * 26.0),
    ];
    for (name, weight, thrust, cohesion) in planes {
        let curves = contact["curves"].as_array().unwrap();
        let c = curves.iter().find(|c| c["curve"] == name).unwrap_or_else(|| panic!("{contact}"));
        let fs = c["sliding_safety_factor"].as_f64().unwrap_or_else(|| panic!("{c}"));
        let exact = (0.8391 * weight + cohesion) / thrust;
        println!("{name}: FS_LE {fs:.6} against (F W + c L)/thrust = {exact:.6}");
        assert!((fs - exact).abs() <= 1e-4 * exact, "{name}: FS_LE {fs}, exact {exact}");
    }
}

// A lift joint inside the dam. Source: geo/dam_lift_joint.toml (Scene A's dam cut at
// y = 20 m, a Mohr–Coulomb joint between the two blocks, reservoir at 65 m, base fixed).
// Goal: `damfem solve` and `damfem adapt` run on it; the joint carries the upper block alone,
// so N is its weight ρ g |A| (A the trapezoid 0 ≤ x ≤ 26 − 0.7 (y − 20), 20 ≤ y ≤ 50) and −T
// the water's thrust on its upstream face, ρ_w g ∫₂₀⁵⁰ (65 − y) dy, both to 10⁻⁶; the joint
// opens at its upstream end (the contact zone ends at the downstream end x = 26 m and starts
// inside the joint), and η_tot falls along the adaptive run; each step's
// `regularisation_balanced` says whether its η values meet (S_reg), η_reg ≤ γ_reg (η_osc +
// η_flux + η_Neu + η_disc + η_lin) with the default γ_reg = 0.1 (docs/method.md §5.3).
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
    for step in history["steps"].as_array().unwrap() {
        let g = |k: &str| step["eta"][k].as_f64().unwrap();
        let balanced = g("reg") <= 0.1 * (g("osc") + g("flux") + g("neu") + g("disc") + g("lin"));
        assert_eq!(step["regularisation_balanced"].as_bool(), Some(balanced), "{step}");
    }
}

/// ∫₀ᴸ p ds of the piecewise linear diagram through the points (s, p), s increasing.
fn integral(points: &[(f64, f64)]) -> f64 {
    points.windows(2).map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 + w[1].1)).sum()
}

// An uplift diagram per joint. Source: geo/dam_lifts_on_rock_uplift.toml, the two lifts of
// geo/dam_lifts_on_rock.toml with [joints.base.uplift] (drains 5 m from the heel, 2/3
// effective) and [joints.lift.uplift] (no drains), both cracks filled, and its combination
// `flood` (the reservoir at 50 m on the dam, the rock and in both joints); docs/method.md §1.8,
// §1.10. Goal: `damfem solve` gives each curve of `summary.json` its own U and crack; each
// block is held by its joint alone and the upstream face is vertical, so on each joint
// N + U = the weight of the blocks above it to 10⁻⁵ W and −T = the water's thrust on them to
// 10⁻⁶; each U is its own diagram's integral with its crack (USACE, docs/method.md §1.8): the
// lift joint's runs from ρ_w g (H_w − 20 m) at its heel (x = 0) to 0 at its toe, 26 m
// downstream, the base's from ρ_w g H_w with its drains; each crack settles (|open − s_c| ≤
// 10⁻⁶ L). Under the flood the base cracks at the heel and the lift joint stays closed.
// `damfem check` lists each joint with its heel and the uplift there.
// Parameters: P2, gmsh's sizes × 2.
#[test]
fn each_joint_has_its_own_uplift() {
    let tmp = TempDir::new("joint-uplift");
    let scene = repo("geo/dam_lifts_on_rock_uplift.toml");
    let check = damfem(&["check", scene.to_str().unwrap()]);
    assert_ok(&check);
    let table = String::from_utf8_lossy(&check.stdout);
    for (name, depth, heel) in [("base", 45.0, "[0.0, 0.0]"), ("lift", 25.0, "[0.0, 20.0]")] {
        let heel = format!("uplift {:.4e} Pa at the heel {heel}", 1000.0 * 9.81 * depth);
        let line =
            table.lines().find(|l| l.starts_with(&format!("joint    {name} "))).unwrap_or_else(|| panic!("{table}"));
        assert!(line.ends_with(&heel), "{line} against {heel}");
    }
    let rho_g = 2400.0 * 9.81;
    let gamma_w = 1000.0 * 9.81;
    for (combination, level) in [(None, 45.0), (Some("flood"), 50.0)] {
        let dir = tmp.join(combination.unwrap_or("usual"));
        let mut args = vec!["solve", scene.to_str().unwrap(), "--size-factor", "2", "-q", "-o", dir.to_str().unwrap()];
        args.extend(combination.map(|c| ["--combination", c]).into_iter().flatten());
        assert_ok(&damfem(&args));
        let summary = check_summary(&dir);
        let curves = summary["contact"]["curves"].as_array().unwrap().clone();
        let curve =
            |name: &str| curves.iter().find(|c| c["curve"] == name).unwrap_or_else(|| panic!("{curves:?}")).clone();
        let thrust = |depth: f64| 0.5 * gamma_w * depth * depth;
        // the base: H_u = ρ_w g H_w, drains at 5 m keep (1 − E)(L − X)/(L − s_c) of it while s_c < 5 m
        let base = |s_c: f64| {
            let h_u = gamma_w * level;
            let h_3 = (1.0 - 0.6667) * h_u * (40.0 - 5.0) / (40.0 - s_c);
            assert!(s_c < 5.0, "the base's crack {s_c} m reaches its drains");
            integral(&[(0.0, h_u), (s_c, h_u), (5.0, h_3), (40.0, 0.0)])
        };
        let lift =
            |s_c: f64| integral(&[(0.0, gamma_w * (level - 20.0)), (s_c, gamma_w * (level - 20.0)), (26.0, 0.0)]);
        let joints = [
            ("base", 40.0, rho_g * 0.5 * (40.0 + 5.0) * 50.0, thrust(level)),
            ("lift", 26.0, rho_g * 0.5 * (26.0 + 5.0) * 30.0, thrust(level - 20.0)),
        ];
        for (name, length, weight, thrust) in joints {
            let c = curve(name);
            let number = |key: &str| c[key].as_f64().unwrap_or_else(|| panic!("{key}: {c}"));
            let (n, t, u) = (number("normal_force"), number("tangential_force"), number("uplift_force"));
            let crack = &c["crack"];
            let (s_c, change) = (crack["length"].as_f64().unwrap(), crack["change"].as_f64().unwrap());
            println!(
                "{combination:?} {name}: N {n:.6e} U {u:.6e} (N + U − W = {:.1e} W), T {t:.6e}, crack {s_c:.4} m, FS_LE {}",
                (n + u - weight) / weight,
                c["sliding_safety_factor"]
            );
            assert!(
                (n + u - weight).abs() <= 1e-5 * weight,
                "{name}: N + U = {}, the blocks above weigh {weight}",
                n + u
            );
            assert!((t + thrust).abs() <= 1e-6 * thrust, "{name}: T = {t}, the thrust is {thrust}");
            assert!(change <= 1e-6 * length, "{name}: {crack}");
            let expected = if name == "base" { base(s_c) } else { lift(s_c) };
            assert!((u - expected).abs() <= 1e-9 * expected, "{name}: U = {u}, its diagram gives {expected}");
        }
        let cracks = ["base", "lift"].map(|name| curve(name)["crack"]["length"].as_f64().unwrap());
        match combination {
            None => assert_eq!(cracks, [0.0, 0.0]),
            Some(_) => assert!(cracks[0] > 1.0 && cracks[1] == 0.0, "cracks {cracks:?}"),
        }
    }
}

// The crack fixed point on a lift joint. Source: geo/dam_lift_joint.toml (the lower block
// fixed, the Mohr–Coulomb lift joint alone holding the upper block) with the reservoir at
// 55 m and [joints.lift.uplift] headwater = 55 m, the crack filled; docs/method.md §1.8.
// Goal: the reservoir opens the lift joint at its upstream end and the crack settles there:
// |open − s_c| ≤ 10⁻⁶ L, the open length from the heel that summary.json measures is s_c to
// that tolerance, U = ρ_w g 35 (s_c + (26 − s_c)/2) (the full head in the crack, then linear
// to 0 at the toe), N + U = the upper block's weight to 10⁻⁵ and −T the thrust
// ρ_w g ∫₂₀⁵⁰ (55 − y) dy to 10⁻⁶.
// Parameters: P2, gmsh's sizes × 2, δ = 2·10⁴ Pa (the figures of docs/results.md, "Joints
// between two meshed bodies"; at the default δ of `damfem solve` Newton on this Mohr–Coulomb
// joint settles the crack only with the frozen steps of docs/solver.md §3).
#[test]
fn a_lift_joint_cracks_under_its_own_uplift() {
    let tmp = TempDir::new("lift-crack");
    let scene = edited(&tmp, "dam_lift_joint", "lift-uplift.toml", |t| {
        t.replace("level = 65.0", "level = 55.0")
            .replace("slave = \"upper_block\"\n", "slave = \"upper_block\"\n\n[joints.lift.uplift]\nheadwater = 55.0\n")
    });
    let dir = tmp.join("solve");
    let args =
        ["solve", scene.to_str().unwrap(), "--size-factor", "2", "--delta", "2e4", "-q", "-o", dir.to_str().unwrap()];
    assert_ok(&damfem(&args));
    let summary = check_summary(&dir);
    let contact = &summary["contact"];
    let lift = &contact["curves"][0];
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{contact}"));
    let (n, t, u) = (number(&lift["normal_force"]), number(&lift["tangential_force"]), number(&lift["uplift_force"]));
    let (s_c, change, open) =
        (number(&lift["crack"]["length"]), number(&lift["crack"]["change"]), number(&contact["crack_length"]));
    let gamma_w = 1000.0 * 9.81;
    let weight = 2400.0 * 9.81 * 0.5 * (26.0 + 5.0) * 30.0;
    let thrust = gamma_w * (55.0 * 30.0 - 0.5 * (50.0f64.powi(2) - 20.0f64.powi(2)));
    let expected = gamma_w * 35.0 * (s_c + 0.5 * (26.0 - s_c));
    println!(
        "crack {s_c:.4} m (open {open:.4} m) after {} solves; N {n:.6e} U {u:.6e} (diagram {expected:.6e}), T {t:.6e}",
        lift["crack"]["iterations"]
    );
    assert!(s_c > 1.0 && change <= 1e-6 * 26.0, "{}", lift["crack"]);
    assert!((open - s_c).abs() <= 1e-6 * 26.0, "open {open} against the crack {s_c}");
    assert!((u - expected).abs() <= 1e-9 * expected, "U = {u}, the diagram gives {expected}");
    assert!((n + u - weight).abs() <= 1e-5 * weight, "N + U = {}, the upper block weighs {weight}", n + u);
    assert!((t + thrust).abs() <= 1e-6 * thrust, "T = {t}, the thrust is {thrust}");
}

// Bad uplift tables on joints, each one error line, exit 1 and no output (docs/method.md §1.8,
// §1.10): uplift on a curve that is no joint (the crest; the base of role contact of
// geo/scene_a_uplift.toml, a rigid foundation), [uplift] beside a joint's own diagram,
// [uplift] along two joints that are not on one line, a joint curve that is not straight (the
// lift joint bent at x = 13 m), drains outside the joint, and combinations that change a
// joint's law or name a curve that is no joint.
// Parameters: geo/dam_lifts_on_rock_uplift.toml and geo/scene_a_uplift.toml edited; `damfem
// check` (the bent curve: `damfem solve`).
#[test]
fn joint_uplift_refuses_bad_input() {
    let tmp = TempDir::new("joint-uplift-bad");
    let text = std::fs::read_to_string(repo("geo/dam_lifts_on_rock_uplift.toml")).unwrap();
    let geometry = repo("geo/dam_lifts_on_rock.geo").display().to_string();
    let text = text.replace("\"dam_lifts_on_rock.geo\"", &format!("{geometry:?}"));
    let count = std::cell::Cell::new(0);
    let scene = |edit: &dyn Fn(String) -> String| {
        count.set(count.get() + 1);
        let path = tmp.join(&format!("scene-{}.toml", count.get()));
        std::fs::write(&path, edit(text.clone())).unwrap();
        path
    };
    let bent = tmp.join("bent.geo");
    let geo = std::fs::read_to_string(repo("geo/dam_lifts_on_rock.geo")).unwrap();
    let geo = geo
        .replace("Line(7) = {6, 3};", "Point(11) = {13, 21, 0, hb};\nLine(7) = {6, 11};\nLine(13) = {11, 3};")
        .replace("Curve Loop(1) = {1, 2, -7, 6};", "Curve Loop(1) = {1, 2, -13, -7, 6};")
        .replace("Curve Loop(2) = {7, 3, 4, 5};", "Curve Loop(2) = {7, 13, 3, 4, 5};")
        .replace("Physical Curve(\"lift\") = {7};", "Physical Curve(\"lift\") = {7, 13};");
    std::fs::write(&bent, geo).unwrap();
    let top = "\n[uplift]\nheadwater = 45.0\n";
    let cases: Vec<(PathBuf, &str, Vec<&str>)> = vec![
        (
            scene(&|t| t.replace("[joints.lift.uplift]", "[joints.crest.uplift]")),
            "check",
            vec!["curve 'crest' is not shared by two surfaces"],
        ),
        (
            scene(&|t| format!("{t}{top}")),
            "check",
            vec!["curve 'base' has two uplift diagrams", "[joints.<curve>.uplift]"],
        ),
        (
            scene(&|t| {
                // without the joints' own tables and the combination that changes them
                let t = &t[..t.find("\n# the reservoir at the crest").unwrap()];
                let t = t.replace(
                    "\n[joints.base.uplift]\nheadwater = 45.0\ndrains = { x = 5.0, efficiency = 0.6667 }\n",
                    "",
                );
                t.replace("\n[joints.lift.uplift]\nheadwater = 45.0\n", "").replace("crack = \"full\"\n", "") + top
            }),
            "check",
            vec![
                "[uplift] lays one diagram along all the joint curves",
                "not on one straight line",
                "[joints.<curve>.uplift]",
            ],
        ),
        (
            scene(&|t| t.replace(&geometry, bent.to_str().unwrap())),
            "solve",
            vec!["joints.lift.uplift needs a straight joint", "curve 'lift' is not on one straight line"],
        ),
        (
            scene(&|t| t.replace("drains = { x = 5.0,", "drains = { x = 45.0,")),
            "check",
            vec!["joints.base.uplift.drains.x = 45 lies outside the joint"],
        ),
        (
            scene(&|t| format!("{t}\n[combinations.weak.joints.lift]\nfriction = 0.3\n")),
            "check",
            vec!["combinations.weak", "'joints.lift.friction' cannot be combined"],
        ),
        (
            scene(&|t| format!("{t}\n[combinations.odd.joints.crest.uplift]\nheadwater = 45.0\n")),
            "check",
            vec!["combinations.odd", "joints.crest is not a joint of the scene", "base, lift"],
        ),
    ];
    // a joint's own table on a rigid foundation's curve
    let rigid = tmp.join("rigid.toml");
    let text = std::fs::read_to_string(repo("geo/scene_a_uplift.toml")).unwrap();
    let geometry = format!("{:?}", repo("geo/scene_a_friction.geo").display().to_string());
    let text = text.replace("\"scene_a_friction.geo\"", &geometry).replace("\n[uplift]\n", "\n[joints.base.uplift]\n");
    std::fs::write(&rigid, text).unwrap();
    let cases = cases.into_iter().chain([(
        rigid,
        "check",
        vec!["[joints.base.uplift] is for a joint between two meshed bodies", "role contact", "[uplift]"],
    )]);
    for (input, command, keywords) in cases {
        assert_refused("joint-uplift-input", command, &input, &[], &keywords);
    }
}

// The sliding plane's own uplift. Source: geo/dam_lifts_on_rock_uplift.toml without its
// combinations and with `[safety] joint = "lift"`; docs/method.md §1.9, §1.10. Goal: `damfem
// safety` analyses the lift joint with its own diagram: its joint line from the heel (0, 20) over
// 26 m, joint.csv with faces at y = 20 only, U = ρ_w g (45 − 20) · 26/2 (the joint stays
// closed, crack 0) to 10⁻⁹, where the base's diagram would give more than its 40 m, and
// N + U = the upper block's weight to 10⁻⁶ (measured 2.1·10⁻¹⁴: Newton runs to its tolerance
// on the last mesh; at the iterate where the adaptive loop's rule stopped it, N + U − W was
// 0.49 % of W).
// Parameters: P1, gmsh's sizes × 2, one mesh.
#[test]
fn safety_takes_the_sliding_planes_own_uplift() {
    let tmp = TempDir::new("lift-safety");
    let scene = edited(&tmp, "dam_lifts_on_rock_uplift", "lift.toml", |text| {
        text[..text.find("\n[combinations.usual]").unwrap()].replace("joint = \"base\"", "joint = \"lift\"")
    });
    let dir = tmp.join("safety");
    let report = quick_safety(&scene, &dir);
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    assert_plane(&report, &dir, 20.0, 26.0);
    let r = &report["resultant"];
    let (n, u) = (number(&r["normal_force"]), number(&r["uplift_force"]));
    let weight = 2400.0 * 9.81 * 0.5 * (26.0 + 5.0) * 30.0;
    let expected = 1000.0 * 9.81 * 25.0 * 26.0 / 2.0;
    println!(
        "lift: N = {n:.6e}, U = {u:.6e} (diagram {expected:.6e}), N + U − W = {:.2e} W",
        (n + u - weight) / weight
    );
    assert_eq!(number(&report["crack_length"]), 0.0);
    assert!((u - expected).abs() <= 1e-9 * expected, "U = {u}, the lift joint's diagram gives {expected}");
    assert!((n + u - weight).abs() <= 1e-6 * weight, "N + U = {}, the upper block weighs {weight}", n + u);
}

/// geo/dam_lifts_on_rock_uplift.toml without its combinations, edited so that both joints crack
/// at once: the reservoir at 55 m (on the dam, the rock and in both joints), a lower block of
/// 3200 kg/m³, the base's drains 10 m from its heel and its friction 2; written into `tmp`.
fn two_cracks_scene(tmp: &TempDir) -> PathBuf {
    edited(tmp, "dam_lifts_on_rock_uplift", "two-cracks.toml", |text| {
        text[..text.find("\n[combinations.usual]").unwrap()]
            .replace("level = 45.0", "level = 55.0")
            .replace("headwater = 45.0", "headwater = 55.0")
            .replace(
                "[materials.lower_block]\nE = 3.0e10\nnu = 0.2\nrho = 2400.0",
                "[materials.lower_block]\nE = 3.0e10\nnu = 0.2\nrho = 3200.0",
            )
            .replace("drains = { x = 5.0,", "drains = { x = 10.0,")
            .replace("friction = 0.8391\nslave = \"lower_block\"", "friction = 2.0\nslave = \"lower_block\"")
            // every load at once: along the load path (docs/method.md §1.11) the lift joint
            // also opens 0.17 m past its crack tip, a state this test does not describe
            .replace("[contact]\nmax_iter = 100", "[contact]\nmax_iter = 100\nload_path = false")
    })
}

/// The weights above each joint of the scene of [`two_cracks_scene`] \[N/m\]: (base, lift).
fn two_cracks_weights() -> (f64, f64) {
    let (lower, upper) = (0.5 * (40.0 + 26.0) * 20.0, 0.5 * (26.0 + 5.0) * 30.0);
    (9.81 * (3200.0 * lower + 2400.0 * upper), 9.81 * 2400.0 * upper)
}

// Two cracks opening at once. Source: geo/dam_lifts_on_rock_uplift.toml with the reservoir at
// 55 m, a lower block of 3200 kg/m³, the base's drains at 10 m and its friction 2
// ([`two_cracks_scene`]); docs/method.md §1.8, §1.10. Goal: `damfem solve` opens both joints
// at their heels, and both cracks settle in one fixed point (|open − s_c| ≤ 10⁻⁶ L each);
// each block is held by its joint alone and the upstream face is vertical, so on each joint
// N + U = the weight above it to 10⁻⁵ W and −T = the water's thrust on the face above it
// (ρ_w g ∫_y^50 (55 − y') dy', the reservoir above the crest) to 10⁻⁶; each U
// is its own diagram with its own crack to 10⁻⁹ (USACE, docs/method.md §1.8: ρ_w g 55 on the
// base's crack, then its drains, the crack short of them; ρ_w g 35 on the lift's crack, then
// linear to 0 at its toe); each joint is closed from its crack tip to its toe (its contact
// length is L − s_c to within |open − s_c|: the normal traction changes sign at the tip, and
// only there). `damfem adapt` finds two cracks on its second mesh, each settled, within a face
// at the joint's end (0.75 m × 2) of those of `solve`, with the same statics; there the sides
// no longer match, and up to 0.2 m past each tip may open again (0.043 m measured on the
// base and 0.021 m on the lift joint with Newton's monotone line search, 0.127 m on the lift
// joint since its natural monotonicity test, docs/solver.md §2: another solution of the
// frictional problem, whose solution need not be unique).
// Parameters: P2, gmsh's sizes × 2; `adapt` two steps.
#[test]
fn two_cracks_open_at_once() {
    let tmp = TempDir::new("two-cracks");
    let scene = two_cracks_scene(&tmp);
    let gamma_w = 1000.0 * 9.81;
    let (base_weight, lift_weight) = two_cracks_weights();
    let base = |s_c: f64| {
        let h_u = gamma_w * 55.0;
        assert!(s_c < 10.0, "the base's crack {s_c} m reaches its drains");
        integral(&[(0.0, h_u), (s_c, h_u), (10.0, (1.0 - 0.6667) * h_u * 30.0 / (40.0 - s_c)), (40.0, 0.0)])
    };
    let lift = |s_c: f64| integral(&[(0.0, gamma_w * 35.0), (s_c, gamma_w * 35.0), (26.0, 0.0)]);
    // the water on the upstream face from y to the crest: ρ_w g ∫_y^50 (55 − y') dy'
    let thrust = |y: f64| gamma_w * (55.0 * (50.0 - y) - 0.5 * (50.0f64.powi(2) - y * y));
    let joints = [
        ("base", 40.0, base_weight, thrust(0.0), &base as &dyn Fn(f64) -> f64),
        ("lift", 26.0, lift_weight, thrust(20.0), &lift),
    ];
    // `open_beyond`: how much of the joint past its crack tip may be open
    let cracks = |dir: &Path, open_beyond: f64| -> Vec<f64> {
        let summary = check_summary(dir);
        let curves = summary["contact"]["curves"].as_array().unwrap().clone();
        let mut cracks = Vec::new();
        for (name, length, weight, thrust, diagram) in &joints {
            let c = curves.iter().find(|c| c["curve"] == *name).unwrap_or_else(|| panic!("{curves:?}"));
            let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{c}"));
            let (n, t, u) = (number(&c["normal_force"]), number(&c["tangential_force"]), number(&c["uplift_force"]));
            let (s_c, change, contact) =
                (number(&c["crack"]["length"]), number(&c["crack"]["change"]), number(&c["contact_length"]));
            let expected = diagram(s_c);
            println!(
                "{}: {name}: crack {s_c:.4} m (|open − s_c| {change:.1e} m, {} solves), contact {contact:.4} m; \
                 N {n:.6e} U {u:.6e} (diagram {expected:.6e}), N + U − W = {:.1e} W, T {t:.6e}",
                dir.display(),
                c["crack"]["iterations"],
                (n + u - weight) / weight
            );
            assert!(s_c > 1.0 && change <= 1e-6 * length, "{name}: {}", c["crack"]);
            assert!((u - expected).abs() <= 1e-9 * expected, "{name}: U = {u}, its diagram gives {expected}");
            assert!((n + u - weight).abs() <= 1e-5 * weight, "{name}: N + U = {}, W = {weight}", n + u);
            assert!((t + thrust).abs() <= 1e-6 * thrust, "{name}: T = {t}, the thrust is {thrust}");
            // with the whole joint past the tip closed, contact = L − open = L − s_c + change: the
            // bound holds with equality, to the rounding of the lengths
            let (closed_beyond, rounding) = (length - s_c, 1e-12 * length);
            assert!(
                contact <= closed_beyond + change + rounding && contact >= closed_beyond - change - open_beyond,
                "{name}: contact {contact} m, {closed_beyond} m past the tip"
            );
            cracks.push(s_c);
        }
        cracks
    };
    let solve_dir = tmp.join("solve");
    assert_ok(&damfem(&[
        "solve",
        scene.to_str().unwrap(),
        "--size-factor",
        "2",
        "-q",
        "-o",
        solve_dir.to_str().unwrap(),
    ]));
    let solved = cracks(&solve_dir, 1e-9 * 40.0);
    let adapt_dir = tmp.join("adapt");
    let args = ["--size-factor", "2", "--steps", "2", "-q", "-o", adapt_dir.to_str().unwrap()];
    assert_ok(&damfem(&[&["adapt", scene.to_str().unwrap()], &args[..]].concat()));
    let adapted = cracks(&adapt_dir, 0.2);
    for (s, a) in solved.iter().zip(&adapted) {
        assert!((s - a).abs() <= 1.5, "solve's cracks {solved:?}, adapt's {adapted:?}");
    }
}

// The two cracks in either order. Source: the scene of [`two_cracks_open_at_once`]
// ([`two_cracks_scene`]); docs/solver.md §3, docs/method.md §1.8. Goal: the fixed point does not depend on
// the order in which the cracks settle: settled together from s_c = 0 (as `damfem solve`
// does), from the lift joint's crack given at that fixed point and the base's at 0, and from
// the base's given and the lift joint's at 0, each crack agrees to 10⁻⁵ L (the search stops
// at |open − s_c| ≤ 10⁻⁶ L, or a bracket that narrow, on each; before a moving crack cleared
// the others' brackets, the lift joint's closed on a bracket of zero width, its two signs of
// g seen with two cracks of the base, at |open − s_c| = 5.2·10⁻⁵ L). With the base's crack
// given, the first update of the cracks (to 7.03 m and 6.57 m) moved the lift joint's tip
// over 6.6 m of cohesive joint, and Newton stalled there (line search cuts to t ≈ 2⁻¹¹, the
// residual still 1.7·10⁻² after 100 steps) before its stalled steps took the frozen
// Jacobian. On each joint of the first, the normal traction changes sign at the crack tip:
// every face before the tip is open (no contact length), every face past it closed over its
// whole length with a positive pressure.
// Parameters: P2, gmsh's sizes × 2, the δ of `damfem solve`.
#[test]
fn two_cracks_settle_in_either_order() {
    use damfem::contact::{solve_by_continuation, ContactSolution};
    use damfem::io::gmsh::{mesh_geo, MeshOptions};
    let tmp = TempDir::new("two-cracks-order");
    let scene = damfem::scene::Scene::load(&two_cracks_scene(&tmp)).unwrap_or_else(|e| panic!("{e}"));
    let m = &scene.mesh;
    let options =
        MeshOptions { order: 2, size_factor: 2.0, size_min: m.size_min, size_max: m.size_max, algorithm: m.algorithm };
    let mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap_or_else(|e| panic!("{e}"));
    let (problem, joint) = scene.problem(mesh).unwrap_or_else(|e| panic!("{e}"));
    let joint = joint.expect("two joints");
    let disc = problem.discretise();
    let settings = scene.continuation(&problem, &disc.topology);
    let together = solve_by_continuation(&problem, &disc, &joint, &settings).unwrap_or_else(|e| panic!("{e}"));
    let lengths = |s: &ContactSolution| s.nitsche.uplift.iter().map(|u| u.diagram.crack).collect::<Vec<f64>>();
    // Newton steps of each solve, and those of the frozen Jacobian among them
    let steps = |s: &ContactSolution| {
        let its = s.stages.iter().flat_map(|stage| &stage.report.iterations);
        (its.clone().count(), its.filter(|it| it.frozen).count())
    };
    let reference = lengths(&together);
    println!(
        "together: cracks {reference:?}, {:?}; Newton steps (all, frozen) {:?}",
        together.cracks,
        steps(&together)
    );
    for (d, up) in together.nitsche.uplift.iter().enumerate() {
        let (line, s_c) = (&up.diagram.line, reference[d]);
        let change = together.cracks[d].expect("a filled crack").change;
        for k in (0..together.faces.len()).filter(|&k| together.on_line(k, line)) {
            let [a, b] = [0.0, 1.0].map(|s| line.distance(together.nitsche.position(k, s)));
            let (a, b, f) = (a.min(b), a.max(b), &together.faces[k]);
            if b <= s_c - change {
                assert_eq!(f.contact_length, 0.0, "diagram {d}: face [{a}, {b}] before the tip {s_c}: {f:?}");
            } else if a >= s_c + change {
                let closed = (f.contact_length - f.length).abs() <= 1e-12 * f.length && f.pressure > 0.0;
                assert!(closed, "diagram {d}: face [{a}, {b}] past the tip {s_c}: {f:?}");
            }
        }
    }
    // one joint's crack given at the fixed point, the other's from 0: the other settles on it
    let lift = joint.uplift.iter().position(|up| up.diagram.line.heel[1] == 20.0).expect("the lift joint's diagram");
    for (given, name) in [(lift, "the lift joint's"), (1 - lift, "the base's")] {
        let mut preset = joint.clone();
        preset.uplift[given].diagram.crack = reference[given];
        let solution = solve_by_continuation(&problem, &disc, &preset, &settings)
            .unwrap_or_else(|e| panic!("{name} crack given: {e}"));
        let settled = lengths(&solution);
        println!("{name} crack given: cracks {settled:?}, {:?}; Newton steps {:?}", solution.cracks, steps(&solution));
        for (d, up) in solution.nitsche.uplift.iter().enumerate() {
            let length = up.diagram.line.length;
            assert!(
                (settled[d] - reference[d]).abs() <= 1e-5 * length,
                "diagram {d}: from {name} crack given, {settled:?}; from none, {reference:?}"
            );
        }
    }
}
