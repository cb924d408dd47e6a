//! End-to-end tests of the dam–rock joint through the `damfem` binary: friction and uplift
//! keys, load combinations, the joint's resultant in `solve` and `adapt`, and `damfem safety`.

use super::support::{
    assert_error, assert_nothing_written, assert_ok, assert_refused, assert_solve_fails, check_summary, damfem,
    edited_scene, repo, stderr, TempDir,
};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

/// geo/scene_a_friction.toml with `edit` applied, in `tmp`.
fn frictional_scene(tmp: &TempDir, edit: impl Fn(String) -> String) -> PathBuf {
    edited_scene(tmp, "scene_a_friction", edit)
}

/// geo/scene_b_joint.toml without its cohesion (a Coulomb joint, c = 0), in `tmp`.
fn coulomb_rock_scene(tmp: &TempDir) -> PathBuf {
    edited_scene(tmp, "scene_b_joint", |text| text.replace("cohesion = 1.0e5\n", ""))
}

// Friction keys out of range are refused, naming the key; a flag gets the same check.
#[test]
fn friction_keys_out_of_range() {
    let tmp = TempDir::new("friction-keys");
    for (line, expected) in [
        ("friction = -0.5", vec!["contact.friction = -0.5", "non-negative"]),
        ("friction = nan", vec!["contact.friction = NaN", "finite number"]),
        ("cohesion = -1e5", vec!["contact.cohesion = -100000", "non-negative"]),
        ("threshold = 1e5", vec!["contact.threshold", "exclusive"]),
    ] {
        let scene = frictional_scene(&tmp, |t| t.replace("friction = 0.8391", line));
        let scene = if line.starts_with("threshold") {
            frictional_scene(&tmp, |t| t.replace("[contact]", &format!("[contact]\n{line}")))
        } else {
            scene
        };
        assert_solve_fails("friction-key", &scene, &expected);
    }
    let scene = frictional_scene(&tmp, |t| t);
    let out_dir = tmp.join("out");
    let out =
        damfem(&["solve".as_ref(), scene.as_os_str(), "--friction=-1".as_ref(), "-o".as_ref(), out_dir.as_os_str()]);
    assert_error(&out, &["friction = -1", "non-negative"]);
    assert_nothing_written(&out_dir);
}

/// Asserts a run whose stderr is one "verdict:" line with every keyword and whose exit code
/// is 3: the dam does not hold.
fn assert_verdict(out: &Output, keywords: &[&str]) {
    let text = stderr(out);
    assert_eq!(out.status.code(), Some(3), "{text}");
    let verdict: Vec<&str> = text.lines().filter(|l| l.starts_with("verdict:")).collect();
    assert_eq!(verdict.len(), 1, "{text}");
    for k in keywords {
        assert!(text.contains(k), "{k:?} not in: {text}");
    }
}

// A joint that cannot hold the loads is judged before Newton, with the forces that say why:
// a verdict (exit 3), not bad input, and nothing written.
#[test]
fn a_joint_too_weak_for_the_loads_has_no_equilibrium() {
    let tmp = TempDir::new("friction-weak");
    let scene = frictional_scene(&tmp, |t| t.replace("friction = 0.8391", "friction = 0.5"));
    let out_dir = tmp.join("out");
    let out = damfem(&["solve".as_ref(), "-q".as_ref(), scene.as_os_str(), "-o".as_ref(), out_dir.as_os_str()]);
    assert_verdict(&out, &["no equilibrium", "N/m", "contact.friction"]);
    assert_nothing_written(&out_dir);
}

// The load path against every load at once. Source: docs/method.md §1.11 (without friction the
// solution does not depend on the path). Goal: Scene A (frictionless base, anchored toe) with
// an uplift diagram, which the load path follows by default, gives the forces and the largest
// displacement of `contact.load_path = false` to 10⁻⁶, and its summary lists the path's states
// from λ = 0 to 1 (the direct solve none). Parameters: P1, mesh sizes × 2, reservoir at 70 m,
// crack = "ignore".
#[test]
fn the_load_path_and_the_direct_solve_agree_on_a_frictionless_joint() {
    let tmp = TempDir::new("load-path-frictionless");
    let uplift = "\n[uplift]\nheadwater = 70.0\ncrack = \"ignore\"\n";
    let summary = |load_path: bool| {
        let scene = edited_scene(&tmp, "scene_a", |t| {
            let t = t + uplift;
            if load_path {
                t
            } else {
                t.replace("[contact]", "[contact]\nload_path = false")
            }
        });
        let dir = tmp.join(&format!("out-{load_path}"));
        let args = ["solve", "-q", "--order", "1", "--size-factor", "2", "-o"].map(OsStr::new);
        assert_ok(&damfem(&[&args[..], &[dir.as_os_str(), scene.as_os_str()]].concat()));
        check_summary(&dir)
    };
    let (path, direct) = (summary(true), summary(false));
    for key in ["normal_force", "tangential_force", "uplift_force"] {
        let (a, b) = (path["contact"][key].as_f64().unwrap(), direct["contact"][key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-6 * b.abs().max(1.0), "{key}: {a} against {b}");
    }
    let (a, b) = (path["max_displacement"].as_f64().unwrap(), direct["max_displacement"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-6 * b, "max |u| {a} against {b}");
    let states = path["contact"]["load_path"].as_array().unwrap();
    assert_eq!(states.first().unwrap()["load_factor"], 0.0, "{states:?}");
    assert_eq!(states.last().unwrap()["load_factor"], 1.0, "{states:?}");
    assert!(direct["contact"]["load_path"].as_array().unwrap().is_empty());
}

// The estimator covers friction: `--estimate` on the frictional dam writes the η values and
// checks the equilibration of the reconstruction, tangential traces included.
#[test]
fn the_estimator_covers_a_frictional_joint() {
    let tmp = TempDir::new("friction-estimate");
    let scene = frictional_scene(&tmp, |t| t);
    let out_dir = tmp.join("out");
    let args = [
        "solve",
        "-q",
        scene.to_str().unwrap(),
        "--estimate",
        "--check-equilibration",
        "-o",
        out_dir.to_str().unwrap(),
    ];
    assert_ok(&damfem(&args));
    let summary = check_summary(&out_dir);
    let estimate = &summary["estimate"];
    assert!(estimate["global"]["tot"].as_f64().unwrap() > 0.0, "{estimate}");
    let worst = estimate["equilibration"]["contact"].as_f64().unwrap();
    assert!(worst < 1e-10, "contact traces equilibrated to {worst}");
}

// The flood combination is estimated. Source: geo/scene_a_combinations.toml, flood (the
// reservoir at the crest, 50 m, on the face and in the joint); docs/method.md §1.6 (Coulomb's
// face integrals exact where both projections are smoothed, so that the estimator integrates
// what Newton did) and §1.8. Goal: `damfem adapt` estimates its first mesh (its first full
// Newton step at the first δ used to be refused at the toe); the crack settles past the drains
// at 5 m, which then no longer count, so U = ρ_w g 50 m (s_c + (L − s_c)/2) to 10⁻⁹; every
// equilibration check holds to 10⁻¹⁰. Parameters: P2, the file's mesh sizes, one mesh.
#[test]
fn adapt_estimates_the_flood_combination() {
    let tmp = TempDir::new("adapt-flood");
    let scene = repo("geo/scene_a_combinations.toml");
    let args = ["adapt", "-q", "--combination", "flood", "--steps", "1", "-o"];
    let mut args: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    args.extend([tmp.0.as_os_str(), scene.as_os_str()]);
    assert_ok(&damfem(&args));
    let summary = check_summary(&tmp.0);
    let c = &summary["contact"];
    let crack = c["crack"]["length"].as_f64().unwrap();
    assert!(crack > 5.0 && crack < 10.0, "{}", c["crack"]);
    let expected = 1000.0 * 9.81 * 50.0 * (crack + 0.5 * (40.0 - crack));
    let uplift = c["uplift_force"].as_f64().unwrap();
    assert!((uplift - expected).abs() <= 1e-9 * expected, "U = {uplift} against {expected}");
    let worst = summary["estimate"]["equilibration"].as_object().unwrap();
    for (check, value) in worst {
        assert!(value.as_f64().unwrap() < 1e-10, "{check}: {value}");
    }
}

// `damfem solve` converges on the drains-blocked combination. Source:
// geo/scene_a_combinations.toml, drains_blocked; docs/solver.md §6 (with Coulomb's face
// integrals inexact where both projections were smoothed, the residual depended on where the
// cuts fell, and Newton stalled in the first stage, 100 steps at a relative residual of 1.18).
// Goal: the solve succeeds and settles the crack at the heel. Parameters: P2, the file's mesh
// sizes × 2, the scene's 100 Newton steps per stage.
#[test]
fn solve_converges_with_the_drains_blocked() {
    let tmp = TempDir::new("solve-drains-blocked");
    let scene = repo("geo/scene_a_combinations.toml");
    let args = ["solve", "-q", "--combination", "drains_blocked", "--size-factor", "2", "-o"];
    let mut args: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    args.extend([tmp.0.as_os_str(), scene.as_os_str()]);
    assert_ok(&damfem(&args));
    let crack = &check_summary(&tmp.0)["contact"]["crack"];
    let length = crack["length"].as_f64().unwrap();
    assert!(length > 0.0 && length < 5.0 && crack["change"].as_f64().unwrap() <= 1e-6 * 40.0, "{crack}");
}

// Bad [uplift] values are refused, naming the key: a non-finite level, a tailwater above the
// headwater, drains outside the joint.
#[test]
fn uplift_keys_out_of_range() {
    let tmp = TempDir::new("uplift-keys");
    for (section, expected) in [
        ("headwater = nan", vec!["uplift.headwater = NaN", "finite"]),
        ("headwater = 40.0\ntailwater = 45.0", vec!["uplift.tailwater = 45", "above uplift.headwater = 40"]),
        (
            "headwater = 45.0\ndrains = { x = 55.0, efficiency = 0.5 }",
            vec!["uplift.drains.x = 55", "outside the joint"],
        ),
        ("headwater = 45.0\ndrains = { x = 5.0, efficiency = 1.5 }", vec!["uplift.drains", "efficiency within [0, 1]"]),
    ] {
        let scene = frictional_scene(&tmp, |t| format!("{t}\n[uplift]\n{section}\n"));
        assert_solve_fails("uplift-key", &scene, &expected);
    }
    let scene = frictional_scene(&tmp, |t| {
        format!("{}\n[uplift]\nheadwater = 45.0\n", t.replace("role = \"contact\"", "role = \"dirichlet\""))
    });
    assert_solve_fails("uplift-no-joint", &scene, &["[uplift] needs a joint", "contact"]);
}

// A load combination overrides the water levels and the pseudo-static acceleration of the
// scene: the joint forces follow statics exactly, N + U = W and T = −(the thrust + a_x W + the
// hydrodynamic thrust), with the thrust ρ_w g H_w²/2 of the combination's reservoir level and,
// under the earthquake, Westergaard's (7/12) a_x ρ_w g H_w² on the vertical upstream face.
#[test]
fn combinations_override_water_levels_and_acceleration() {
    let tmp = TempDir::new("combinations");
    let scene = frictional_scene(&tmp, |t| {
        format!(
            "{t}\n[uplift]\nheadwater = 45.0\ndrains = {{ x = 5.0, efficiency = 0.6667 }}\ncrack = \"ignore\"\n\n\
             [combinations.usual]\nboundary.upstream.hydrostatic.level = 45.0\n\n\
             [combinations.flood]\nboundary.upstream.hydrostatic.level = 50.0\nuplift.headwater = 50.0\n\n\
             [combinations.earthquake]\nboundary.upstream.hydrostatic.level = 45.0\nloads.acceleration = [0.1, 0.0]\n"
        )
    });
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    for (name, level, a_x) in [("usual", 45.0_f64, 0.0), ("flood", 50.0, 0.0), ("earthquake", 45.0, 0.1)] {
        let out = tmp.join(name);
        let args = ["solve", "-q", scene.to_str().unwrap(), "--combination", name, "--size-factor", "2", "-o"];
        assert_ok(&damfem(&[&args[..], &[out.to_str().unwrap()]].concat()));
        let c = &check_summary(&out)["contact"];
        let force = |key: &str| c[key].as_f64().unwrap_or_else(|| panic!("{key} in {c}"));
        let thrust = 1000.0 * 9.81 * level * level / 2.0;
        let (n, t, u) = (force("normal_force"), force("tangential_force"), force("uplift_force"));
        assert!((n + u - weight).abs() <= 1e-8 * weight, "{name}: N + U = {} against W = {weight}", n + u);
        let hydrodynamic = 7.0 / 12.0 * a_x * 1000.0 * 9.81 * level * level;
        let expected = -(thrust + a_x * weight + hydrodynamic);
        assert!((t - expected).abs() <= 1e-8 * expected.abs(), "{name}: T = {t} against {expected}");
    }
}

// Source: EM 1110-2-2100 §3-3 and CADAM3D's seismic crack rules (docs/method.md §1.8). Goal:
// a combination with an acceleration and no crack key takes `unchanged`, which keeps the uplift
// of the state before the earthquake (the same reservoir without acceleration, its crack
// filled): the crack s₀ it keeps is the static combination's, and U equals its U to round-off,
// whatever the earthquake opens, in `solve` and in `safety`'s adaptive run and report. (`none`:
// tests/python/test_crack_rules.py.) Parameters: scene_a_friction at 45 m, 0.1 g, P2, size
// factor 2.
#[test]
fn an_earthquake_keeps_the_uplift_before_it() {
    let tmp = TempDir::new("crack-rules");
    let scene = frictional_scene(&tmp, |t| {
        format!(
            "{}\n[uplift]\nheadwater = 45.0\n\n[combinations.static]\n\n\
             [combinations.earthquake]\nloads.acceleration = [0.1, 0.0]\n",
            t.replace("level = 70.0", "level = 45.0")
        )
    });
    let solve = |name: &str| {
        let out = tmp.join(name);
        let args = ["solve", "-q", scene.to_str().unwrap(), "--combination", name, "--size-factor", "2", "-o"];
        assert_ok(&damfem(&[&args[..], &[out.to_str().unwrap()]].concat()));
        check_summary(&out)["contact"].clone()
    };
    let (before, quake) = (solve("static"), solve("earthquake"));
    let number = |c: &serde_json::Value, path: &[&str]| {
        path.iter().fold(c, |v, key| &v[*key]).as_f64().unwrap_or_else(|| panic!("{path:?} in {c}"))
    };
    let s0 = number(&before, &["crack", "length"]);
    assert!(s0 > 0.0 && before["crack_rule"] == "filled", "{}", before["crack"]);
    assert_eq!(number(&quake, &["crack_rule", "kept", "prior"]), s0);
    let (u0, u1) = (number(&before, &["uplift_force"]), number(&quake, &["uplift_force"]));
    assert!((u1 - u0).abs() <= 1e-12 * u0, "U under the earthquake {u1} against {u0} before it");
    assert!(number(&quake, &["crack_length"]) > s0 + 0.5, "the earthquake opens more than it keeps: {quake}");
    // safety's adaptive run keeps the same crack, and its report says so
    let out = tmp.join("safety");
    let args = ["safety", "-q", scene.to_str().unwrap(), "--combination", "earthquake", "--size-factor", "2"];
    assert_ok(&damfem(&[&args[..], &["--max-steps", "1", "-o", out.to_str().unwrap()]].concat()));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("safety.json")).unwrap()).unwrap();
    assert_eq!(number(&report, &["crack_rule", "kept", "prior"]), s0);
    let markdown = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        markdown.contains(&format!("kept: the diagram of the {s0:.4} m crack before the earthquake")),
        "{markdown}"
    );
}

// Source: statics of a rigid section. Goal: silt and ice on the upstream face beside the
// reservoir add their thrusts to the joint's shear exactly, T = −(ρ_w g H²/2 + K ρ' g h²/2 + F),
// N = W; a silt density ≤ 0 or an ice sheet without thickness is refused, naming the key.
// Parameters: scene_a_friction at 45 m, silt 12 m deep (ρ' = 1100 kg/m³, K = 0.5), ice
// F = 150 kN/m over 0.6 m at 45 m, P2, size factor 2.
#[test]
fn silt_and_ice_add_their_thrusts() {
    let tmp = TempDir::new("silt-ice");
    let loads = "silt = { level = 12.0, density = 1100.0, coefficient = 0.5 }\n\
                 ice = { force = 1.5e5, level = 45.0, thickness = 0.6 }\n";
    let scene = |extra: &str| {
        let extra = extra.to_string();
        frictional_scene(&tmp, move |t| {
            t.replace("level = 70.0 }", &format!("level = 45.0 }}\n{extra}"))
                .replace("friction = 0.8391", "friction = 1.5")
        })
    };
    let out = tmp.join("out");
    let run = scene(loads);
    assert_ok(&damfem(&["solve", "-q", run.to_str().unwrap(), "--size-factor", "2", "-o", out.to_str().unwrap()]));
    let c = &check_summary(&out)["contact"];
    let (n, t) = (c["normal_force"].as_f64().unwrap(), c["tangential_force"].as_f64().unwrap());
    let weight = 2400.0 * 9.81 * (40.0 + 5.0) / 2.0 * 50.0;
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0 + 0.5 * 1100.0 * 9.81 * 12.0 * 12.0 / 2.0 + 1.5e5;
    assert!((n - weight).abs() <= 1e-8 * weight, "N = {n} against W = {weight}");
    assert!((t + thrust).abs() <= 1e-8 * thrust, "T = {t} against -{thrust}");
    for (bad, expected) in [
        ("silt = { level = 12.0, density = -5.0 }", "boundary.upstream.silt.density = -5"),
        ("ice = { force = 1.5e5, level = 45.0, thickness = 0.0 }", "boundary.upstream.ice.thickness = 0"),
    ] {
        assert_solve_fails("silt-ice-key", &scene(bad), &[expected]);
    }
}

// A combination is checked like the scene: an unknown key, a NaN level, a tailwater above the
// headwater, or a table it may not override is refused when the scene is read, naming the
// combination; an unknown --combination lists the scene's.
#[test]
fn bad_combinations_are_refused() {
    let tmp = TempDir::new("bad-combinations");
    let uplift = "\n[uplift]\nheadwater = 45.0\ncrack = \"ignore\"\n";
    for (combination, expected) in [
        ("uplift.headwatr = 50.0", vec!["combinations.bad", "headwatr"]),
        ("boundary.upstream.hydrostatic.level = nan", vec!["combinations.bad", "level = NaN", "finite"]),
        ("uplift.tailwater = 60.0", vec!["combinations.bad", "tailwater = 60", "above uplift.headwater = 45"]),
        ("mesh.size_factor = 0.5", vec!["combinations.bad", "'mesh' cannot be combined"]),
    ] {
        let scene = frictional_scene(&tmp, |t| format!("{t}{uplift}\n[combinations.bad]\n{combination}\n"));
        assert_solve_fails("bad-combination", &scene, &expected);
    }
    let scene = frictional_scene(&tmp, |t| format!("{t}{uplift}\n[combinations.usual]\n[combinations.flood]\n"));
    assert_refused(
        "unknown-combination",
        "solve",
        &scene,
        &["--combination", "storm"],
        &["--combination storm", "combinations.storm: no such combination", "flood, usual"],
    );
}

// --strength-reduction needs a frictional joint, and says so before writing anything.
#[test]
fn strength_reduction_needs_friction() {
    let tmp = TempDir::new("strength-frictionless");
    let out = tmp.join("out");
    let scene = repo("geo/scene_a.toml");
    let args =
        [OsStr::new("solve"), scene.as_os_str(), OsStr::new("--strength-reduction"), OsStr::new("-o"), out.as_os_str()];
    let result = damfem(&args);
    assert_error(&result, &["--strength-reduction", "frictional joint"]);
    assert!(!out.exists(), "no output directory");
}

/// ∫ s p(s) ds and ∫ p(s) ds of the piecewise linear p through the points (s, p).
fn linear_moments(points: &[(f64, f64)]) -> (f64, f64) {
    points.windows(2).fold((0.0, 0.0), |(m, f), w| {
        let ((a, pa), (b, pb)) = (w[0], w[1]);
        (m + (b - a) / 6.0 * (a * (2.0 * pa + pb) + b * (pa + 2.0 * pb)), f + 0.5 * (b - a) * (pa + pb))
    })
}

/// Scene A's section (vertical upstream face, base 40 m, crest 5 m, height 50 m, ρ = 2400):
/// the weight W [N/m] and its lever arm x̄ from the heel [m].
fn scene_a_weight() -> (f64, f64) {
    let (rectangle, triangle) = (5.0 * 50.0, 35.0 * 50.0 / 2.0);
    let x_bar = (rectangle * 2.5 + triangle * (5.0 + 35.0 / 3.0)) / (rectangle + triangle);
    (2400.0 * 9.81 * (rectangle + triangle), x_bar)
}

// The joint's headline numbers of `solve` against statics. Source: the equilibrium of the dam
// held by its joint alone (geo/scene_a_friction.toml, flood level 70 m; geo/scene_a_uplift.toml,
// reservoir at 45 m with uplift, drains 5 m from the heel, 2/3 effective, the crack filled):
// with no Dirichlet condition the rigid rotations are test functions, so the moments about the
// heel balance, N s_R = W x̄ + M_water − ∫ s p_u ds, and N = W − U. Goal: `summary.json`
// reports the crack from the heel, N, T, U and the resultant (position, eccentricity, middle
// third), and these satisfy the balance to 10⁻⁶; the stderr lines show them. Parameters: the
// scenes' P2 meshes; p_u by hand from the diagram of docs/method.md §1.8 with the reported crack.
#[test]
fn solve_reports_the_joint_resultant_in_equilibrium() {
    let (weight, x_bar) = scene_a_weight();
    let water = 1000.0 * 9.81;
    for (name, level) in [("scene_a_friction", 70.0_f64), ("scene_a_uplift", 45.0)] {
        let tmp = TempDir::new(&format!("resultant-{name}"));
        let scene = repo(&format!("geo/{name}.toml"));
        let out = damfem(&[OsStr::new("solve"), scene.as_os_str(), OsStr::new("-o"), tmp.0.as_os_str()]);
        assert_ok(&out);
        let summary = check_summary(&tmp.0);
        let c = &summary["contact"];
        let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{c}"));
        let r = &c["resultant"];
        let (n, s_r, crack) = (number(&r["normal_force"]), number(&r["position"]), number(&c["crack_length"]));
        // the upstream face from y = 0 to 50 under ρ_w g (level − y)₊
        let wet = level.min(50.0);
        let (m_water, _) = linear_moments(&[(0.0, water * level), (wet, water * (level - wet))]);
        let (m_uplift, uplift) = if name == "scene_a_uplift" {
            let (h_u, l, s_d, e) = (water * level, 40.0, 5.0, 0.6667);
            let fixed_point = number(&c["crack"]["length"]);
            assert!((crack - fixed_point).abs() <= 2e-6 * l, "crack {crack} against its fixed point {fixed_point}");
            let at_drains = (1.0 - e) * h_u * (l - s_d) / (l - fixed_point);
            linear_moments(&[(0.0, h_u), (fixed_point, h_u), (s_d, at_drains), (l, 0.0)])
        } else {
            assert!(c["uplift_force"].is_null() && crack > 0.0, "{c}");
            (0.0, 0.0)
        };
        let expected = (weight * x_bar + m_water - m_uplift) / (weight - uplift);
        println!(
            "{name}: crack {crack:.4} m, N = {n:.6e}, U = {uplift:.6e}, s_R = {s_r:.6} m (statics {expected:.6} m)"
        );
        assert!((n - (weight - uplift)).abs() <= 1e-6 * weight, "{name}: N = {n} against W − U = {}", weight - uplift);
        assert!((s_r - expected).abs() <= 1e-6 * 40.0, "{name}: s_R = {s_r} against {expected}");
        assert_eq!(number(&r["uplift_force"]), c["uplift_force"].as_f64().unwrap_or(0.0));
        let e = number(&r["eccentricity"]);
        assert!((e - (s_r - 20.0)).abs() <= 1e-12 && r["middle_third"] == (e.abs() <= 40.0 / 6.0), "{r}");
        assert_eq!(c["joint_line"]["heel"], serde_json::json!([0.0, 0.0]), "{c}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(&format!("crack {crack:.4} m open from the heel, resultant at {s_r:.4} m")), "{text}");
    }
}

// `adapt` iterates the crack–uplift fixed point on every mesh and writes `summary.json` of the
// last step; its history has the crack and the resultant of every step. Source:
// geo/scene_a_uplift.toml (crack = "full"). Goal: every step's crack settled to 10⁻⁶ L (on the
// last mesh, the only one whose Newton runs go to its tolerance, from converged iterates,
// docs/method.md §5.3), the history's crack and resultant per step (JSON and
// CSV) and summary.json's equal to the last step's, and the last step's closing lines.
// Parameters: P1, mesh sizes × 2, three meshes.
#[test]
fn adapt_settles_the_crack_and_records_the_joint_per_step() {
    let tmp = TempDir::new("adapt-uplift");
    let scene = repo("geo/scene_a_uplift.toml");
    let args = ["adapt", "--order", "1", "--size-factor", "2", "--steps", "3", "-o"];
    let mut args: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    args.extend([tmp.0.as_os_str(), scene.as_os_str()]);
    let out = damfem(&args);
    assert_ok(&out);
    let summary = check_summary(&tmp.0);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    for step in steps {
        let (crack, position) =
            (step["crack_length"].as_f64().unwrap(), step["resultant"]["position"].as_f64().unwrap());
        assert!(crack > 0.0 && crack < 10.0 && (position - 20.8).abs() < 0.1, "{step}");
    }
    let c = &summary["contact"];
    let settled = &c["crack"];
    assert!(settled["change"].as_f64().unwrap() <= 1e-6 * 40.0, "{settled}");
    assert!(settled["iterations"].as_u64().unwrap() >= 1, "{settled}");
    let finished: Vec<bool> = steps.iter().map(|s| s["finish"].is_object()).collect();
    assert_eq!(finished, [false, false, true], "{}", steps[2]["finish"]);
    assert_eq!(summary["step"], 2);
    assert_eq!(c["crack_length"], steps[2]["crack_length"]);
    assert_eq!(c["resultant"], steps[2]["resultant"]);
    let csv = std::fs::read_to_string(tmp.join("history.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let last: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    let column = |name: &str| last[header.iter().position(|h| *h == name).unwrap()].parse::<f64>().unwrap();
    assert_eq!(column("crack_length"), steps[2]["crack_length"].as_f64().unwrap());
    assert_eq!(column("resultant_position"), steps[2]["resultant"]["position"].as_f64().unwrap());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("last step: crack ") && text.contains("U = "), "{text}");
}

/// Runs `damfem safety <scene> -o <dir>` on meshes twice as coarse as the file's, with `extra`
/// flags.
fn safety_coarse(scene: &Path, dir: &Path, extra: &[&str]) -> Output {
    let mut args: Vec<&OsStr> = ["safety", "--size-factor", "2"].iter().map(OsStr::new).collect();
    args.extend(extra.iter().map(OsStr::new));
    args.extend([scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]);
    damfem(&args)
}

// The estimate of the dam on its rock with a Coulomb joint without cohesion, its sides remeshed
// apart. Source: geo/scene_b_joint.toml without its cohesion (c = 0, P2); docs/method.md §1.6
// (the face split at every kink of the traction) and §1.10, docs/solver.md §6. Goal: `damfem adapt` reaches its
// second mesh, the first whose sides no longer match, with a guaranteed bound: the
// equilibration checks of both meshes below EQUILIBRATION_TOLERANCE = 10⁻¹⁰ (a pair of close
// crossings of a Coulomb margin, missed by Newton's split and the reconstruction's alike, made
// it 2.8·10⁻⁸ there). Parameters: the scene's meshes, --tol-relative 0.001, two meshes.
#[test]
fn adapt_estimates_the_coulomb_joint_remeshed_apart() {
    let tmp = TempDir::new("coulomb-remeshed-apart");
    let scene = coulomb_rock_scene(&tmp);
    let dir = tmp.join("out");
    let args = ["adapt", "--tol-relative", "0.001", "--steps", "2", "-q"].map(OsStr::new);
    let out = damfem(&[&args[..], &[scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]].concat());
    assert_ok(&out);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap_or_else(|| panic!("{history}"));
    assert_eq!(steps.len(), 2, "{history}");
    for step in steps {
        let equilibration = step["equilibration"].as_f64().unwrap_or_else(|| panic!("{step}"));
        assert!(equilibration <= 1e-10, "equilibration {equilibration:.2e} on {step}");
    }
}

// `damfem safety` on the frictional dam with uplift. Source: geo/scene_a_uplift.toml (c = 0,
// horizontal joint: FS_LE = F N/|T| and FS_SR = F N/|T| with the crack of k = 1, N = W − U);
// docs/method.md §1.9. Goal: the adaptive run meets its tolerance; safety.json states its
// units and gives N = W − U (to 10⁻⁸: Newton's tolerance), FS_LE = F N/|T|, FS_SR's bracket around it within 0.5 %, the
// crack and resultant of summary.json, compressive heel and toe means over L/10; joint.csv
// runs from the heel to the toe, open (status 0) under full reservoir pressure ρ_w g 45 m up to
// the crack; report.md (saying that its numbers carry no error bar) and the figure, marking the drain line and the crack tip, exist; the table goes to stdout, progress to stderr, and
// -q prints nothing. Parameters: P1, mesh sizes × 2, --tol-relative 0.005.
#[test]
fn safety_reports_the_dam_with_uplift() {
    let tmp = TempDir::new("safety-uplift");
    let scene = repo("geo/scene_a_uplift.toml");
    let out = safety_coarse(&scene, &tmp.0, &["--tol-relative", "0.005"]);
    assert_ok(&out);
    let json = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(tmp.join(name)).unwrap()).unwrap()
    };
    let (report, summary) = (json("safety.json"), json("summary.json"));
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    assert!(report["units"]["force"].as_str().unwrap().starts_with("N/m"), "{report}");
    assert_eq!(report["tolerance_met"], true);
    assert!(number(&report["eta_relative"]) <= 0.005);
    let r = &report["resultant"];
    let (n, t, u) = (number(&r["normal_force"]), number(&r["tangential_force"]), number(&r["uplift_force"]));
    let (weight, _) = scene_a_weight();
    // p_c is the solved traction, and the crack settles with Newton converged at the adaptive δ
    // (relative residual 10⁻¹⁰): measured 4·10⁻¹⁶ W
    assert!((n + u - weight).abs() <= 1e-8 * weight, "N + U = {} against W = {weight}", n + u);
    let fs_le = number(&report["sliding_safety_factor"]);
    assert!((fs_le - 0.8391 * n / t.abs()).abs() <= 1e-6 * fs_le, "FS_LE {fs_le}");
    let sr = &report["strength_reduction"];
    let (held, failed) = (number(&sr["held"]), number(&sr["failed"]));
    assert!(held <= fs_le * (1.0 + 1e-6) && failed >= fs_le * (1.0 - 1e-6) && held >= 0.995 * fs_le, "{sr}");
    assert_eq!(report["crack_length"], summary["contact"]["crack_length"]);
    assert_eq!(report["resultant"], summary["contact"]["resultant"]);
    let base = &report["base_stresses"];
    assert_eq!(number(&base["length"]), 4.0);
    assert!(number(&base["heel"]) < 0.0 && number(&base["toe"]) < 0.0, "{base}");
    let crack = number(&report["crack_length"]);
    let csv = std::fs::read_to_string(tmp.join("joint.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert!(rows.windows(2).all(|w| w[0][2] < w[1][2]) && rows[0][2] > 0.0 && rows.last().unwrap()[2] < 40.0);
    for row in rows.iter().take_while(|row| row[2] < crack - 1.0) {
        let full = 1000.0 * 9.81 * 45.0;
        assert!(row[7] == 0.0 && (row[6] - full).abs() <= 1e-12 * full, "open under full pressure: {row:?}");
    }
    let md = std::fs::read_to_string(tmp.join("report.md")).unwrap();
    assert!(md.contains("| FS_SR |") && md.contains("base_stresses.png") && md.contains("no error bar"), "{md}");
    assert!(tmp.join("base_stresses.png").is_file() && tmp.join("base_stresses.svg").is_file());
    let svg = std::fs::read_to_string(tmp.join("base_stresses.svg")).unwrap();
    for mark in ["drains, s = 5.00 m".to_string(), format!("crack tip, s = {crack:.2} m")] {
        assert!(svg.contains(&mark), "the figure does not mark {mark}");
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("FS_SR") && stdout.contains("crack length from the heel"), "{stdout}");
    assert!(stderr(&out).contains("strength ") && !stderr(&out).contains("FS_LE"), "{}", stderr(&out));
}

// `damfem safety` on a frictionless joint reports the rest and says why FS is missing.
// Source: geo/scene_a.toml (frictionless base, anchored toe). Goal: exit 0, FS_LE and FS_SR
// null with the reason in safety.json, a warning on stderr, the resultant reported; with -q
// nothing on stdout or stderr. Parameters: P1, mesh sizes × 2, two meshes at most.
#[test]
fn safety_without_friction_reports_no_safety_factor() {
    let tmp = TempDir::new("safety-frictionless");
    let scene = repo("geo/scene_a.toml");
    let out = safety_coarse(&scene, &tmp.0, &["--order", "1", "--max-steps", "2"]);
    assert_ok(&out);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("safety.json")).unwrap()).unwrap();
    assert!(report["sliding_safety_factor"].is_null() && report["strength_reduction"].is_null(), "{report}");
    assert!(report["safety_factor_note"].as_str().unwrap().contains("frictionless"), "{report}");
    assert!(report["resultant"]["normal_force"].as_f64().unwrap() > 0.0, "{report}");
    assert!(stderr(&out).contains("warning: the joint is frictionless"), "{}", stderr(&out));
    let quiet = safety_coarse(&scene, &tmp.join("quiet"), &["--order", "1", "--max-steps", "2", "-q"]);
    assert_ok(&quiet);
    assert!(quiet.stdout.is_empty() && quiet.stderr.is_empty(), "{}", stderr(&quiet));
}

// Bad input to `damfem safety`: an unknown key, a NaN level, a tailwater above the headwater,
// drains outside the joint, the same in a load combination, a key a combination cannot change,
// a three-component acceleration, a misspelt or out-of-range [criteria] key, a category for a
// combination the scene does not have, Westergaard's pressure without an acceleration, a scene
// without a joint, and out-of-range flags each give one error line, exit 1 and no output
// directory.
#[test]
fn safety_refuses_bad_input() {
    let tmp = TempDir::new("safety-bad");
    let count = std::cell::Cell::new(0);
    let uplift = |section: &str| {
        let scene = frictional_scene(&tmp, |t| format!("{t}\n[uplift]\n{section}\n"));
        count.set(count.get() + 1);
        let kept = tmp.join(&format!("scene-{}.toml", count.get()));
        std::fs::rename(&scene, &kept).unwrap();
        kept
    };
    for (scene, extra, keywords) in [
        (uplift("headwater = 45.0\nlevel = 3.0"), vec![], vec!["unknown field", "level"]),
        (uplift("headwater = nan"), vec![], vec!["uplift.headwater = NaN", "finite"]),
        (uplift("headwater = 40.0\ntailwater = 45.0"), vec![], vec!["uplift.tailwater = 45", "above"]),
        (uplift("headwater = 45.0\ndrains = { x = 55.0, efficiency = 0.5 }"), vec![], vec!["drains.x = 55", "outside"]),
        (
            uplift("headwater = 45.0\n[combinations.flood]\nfoo = 1"),
            vec![],
            vec!["combinations.flood", "'foo' cannot be combined"],
        ),
        (
            uplift("headwater = 45.0\n[combinations.flood.uplift]\nlevel = 3.0"),
            vec![],
            vec!["combinations.flood", "level"],
        ),
        (
            uplift("headwater = 45.0\n[combinations.flood.uplift]\nheadwater = nan"),
            vec![],
            vec!["combinations.flood.uplift.headwater = NaN", "finite"],
        ),
        (
            uplift("headwater = 45.0\n[combinations.flood.uplift]\ntailwater = 50.0"),
            vec![],
            vec!["combinations.flood: uplift.tailwater = 50", "above"],
        ),
        (
            uplift("headwater = 45.0\n[combinations.quake.loads]\nacceleration = [0.1, 0.0, 0.0]"),
            vec![],
            vec!["combinations.quake.loads.acceleration has 3 components"],
        ),
        (uplift("headwater = 45.0\n[criteria.usual]\nslidng = 2.0"), vec![], vec!["unknown field `slidng`", "sliding"]),
        (
            uplift("headwater = 45.0\n[criteria.unusual]\nflotation = 0.0"),
            vec![],
            vec!["criteria.unusual.flotation = 0", "positive"],
        ),
        (
            uplift("headwater = 45.0\n[criteria]\ncategories = { flood = \"extreme\" }"),
            vec![],
            vec!["criteria.categories.flood names no combination"],
        ),
        (
            uplift("headwater = 45.0\n[combinations.quake.loads]\nwestergaard = true"),
            vec![],
            vec!["combinations.quake: loads.westergaard = true needs a horizontal loads.acceleration"],
        ),
        (repo("geo/unit_square.toml"), vec![], vec!["needs a joint", "contact"]),
        (
            repo("geo/scene_a_uplift.toml"),
            vec!["--average-length", "30"],
            vec!["--average-length 30", "half the joint"],
        ),
        (repo("geo/scene_a_uplift.toml"), vec!["--tol-relative", "0"], vec!["--tol-relative", "positive"]),
        (repo("geo/scene_a_uplift.toml"), vec!["--max-steps", "0"], vec!["--max-steps", "at least 1"]),
    ] {
        assert_refused("safety-input", "safety", &scene, &extra, &keywords);
    }
}

// Load combinations. Source: geo/scene_a_uplift.toml with [combinations.usual] (no change),
// [combinations.drains_blocked] (drain efficiency 0) and [combinations.earthquake] (a
// pseudo-static acceleration of 0.05 g downstream). Goal: one row per combination on stdout and
// in safety.json, each combination's files in its own directory; horizontal equilibrium of the
// earthquake, T = −(the thrust + 0.05 W), to 10⁻⁶; the blocked drains raise U and lower FS_LE.
// Parameters: P1, mesh sizes × 2, one mesh per combination.
#[test]
fn safety_runs_every_load_combination() {
    let tmp = TempDir::new("safety-combinations");
    let text = std::fs::read_to_string(repo("geo/scene_a_uplift.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/scene_a_friction.geo").display().to_string());
    let scene = tmp.join("dam.toml");
    let combinations = "\n[combinations.usual]\n\
        [combinations.drains_blocked.uplift]\ndrains = { x = 5.0, efficiency = 0.0 }\n\
        [combinations.earthquake.loads]\nacceleration = [0.05, 0.0]\n\
        [criteria]\ncategories = { earthquake = \"extreme\" }\n";
    std::fs::write(&scene, text.replace("geometry = \"scene_a_friction.geo\"", &geometry) + combinations).unwrap();
    let out = safety_coarse(&scene, &tmp.join("out"), &["--order", "1", "--max-steps", "1"]);
    assert_ok(&out);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 4, "{stdout}");
    for (line, name) in lines[1..].iter().zip(["drains_blocked", "earthquake", "usual"]) {
        assert!(line.starts_with(name), "{stdout}");
        assert!(tmp.join("out").join(name).join("report.md").is_file(), "{name}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("out/safety.json")).unwrap()).unwrap();
    let case =
        |name: &str| report["combinations"].as_array().unwrap().iter().find(|c| c["name"] == name).unwrap().clone();
    let number = |c: &serde_json::Value, key: &str| c["resultant"][key].as_f64().unwrap_or_else(|| panic!("{c}"));
    let (weight, _) = scene_a_weight();
    let thrust = 1000.0 * 9.81 * 45.0 * 45.0 / 2.0;
    // Westergaard's added pressure on the vertical upstream face: (7/12) a_x ρ_w g H² at 0.4 H
    let hydrodynamic = 7.0 / 12.0 * 0.05 * 1000.0 * 9.81 * 45.0 * 45.0;
    let t = number(&case("earthquake"), "tangential_force");
    let pushed = thrust + 0.05 * weight + hydrodynamic;
    assert!((t + pushed).abs() <= 1e-6 * thrust, "T = {t} against {}", -pushed);
    let (usual, blocked) = (case("usual"), case("drains_blocked"));
    assert!(number(&blocked, "uplift_force") > number(&usual, "uplift_force"), "{blocked}");
    let fs = |c: &serde_json::Value| c["sliding_safety_factor"].as_f64().unwrap();
    assert!(fs(&blocked) < fs(&usual), "FS_LE {} against {}", fs(&blocked), fs(&usual));
    let md = std::fs::read_to_string(tmp.join("out/report.md")).unwrap();
    assert!(md.contains("[earthquake](earthquake/report.md)") && md.contains("## Code check of all combinations"));
    // the classical method on the same loads: T and P = N + U by the section's equilibrium,
    // the earthquake judged as extreme (FS ≥ 1.3), the others as usual
    let quake = &case("earthquake");
    let classical = |key: &str| quake["classical"][key].as_f64().unwrap_or_else(|| panic!("{quake}"));
    assert!((classical("shear_force") - pushed).abs() <= 1e-6 * thrust, "{quake}");
    let loads = quake["classical"]["loads"].as_array().unwrap();
    let added = loads.iter().find(|l| l["kind"] == "hydrodynamic").unwrap_or_else(|| panic!("{quake}"));
    let (h, arm) = (added["shear"].as_f64().unwrap(), added["shear_arm"].as_f64().unwrap());
    assert!((h - hydrodynamic).abs() <= 1e-6 * hydrodynamic && (arm - 18.0).abs() <= 1e-6 * 18.0, "{added}");
    assert!((classical("pressing_force") - weight).abs() <= 1e-9 * weight, "{quake}");
    assert_eq!(
        (&quake["requirements"]["category"], &quake["requirements"]["sliding"]),
        (&"extreme".into(), &1.3.into())
    );
    assert_eq!(usual["requirements"]["category"], "usual");
    assert!(usual["verdict"]["classical"].is_boolean() && usual["checks"].as_array().unwrap().len() == 11, "{usual}");
    let sub = std::fs::read_to_string(tmp.join("out/earthquake/report.md")).unwrap();
    assert!(
        sub.contains("## Code check (extreme combination)") && sub.contains("| inertia (pseudo-static) |"),
        "{sub}"
    );
}

// A combination under which the dam does not hold is a row of the report, and the others go
// on. Source: geo/scene_a_uplift.toml with [combinations.usual] (no change) and
// [combinations.overtopped] (the reservoir at 150 m on the face and in the joint: its thrust
// exceeds what F N can carry, judged before meshing). Goal: exit 3 with one "verdict:" line;
// report.md links the usual combination's report and says that the dam does not hold under
// the other, whose safety.json entry has outcome does_not_hold; the usual one is solved.
// Parameters: P1, mesh sizes × 2, one mesh per combination.
#[test]
fn safety_reports_a_combination_that_does_not_hold() {
    let tmp = TempDir::new("safety-does-not-hold");
    let combinations = "\n[combinations.usual]\n\
        [combinations.overtopped.boundary.upstream]\nhydrostatic = { level = 150.0 }\n\
        [combinations.overtopped.uplift]\nheadwater = 150.0\n";
    let text = std::fs::read_to_string(repo("geo/scene_a_uplift.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/scene_a_friction.geo").display().to_string());
    let scene = tmp.join("dam.toml");
    std::fs::write(&scene, text.replace("geometry = \"scene_a_friction.geo\"", &geometry) + combinations).unwrap();
    let dir = tmp.join("out");
    let out = safety_coarse(&scene, &dir, &["--order", "1", "--max-steps", "1"]);
    assert_verdict(&out, &["overtopped", "no equilibrium"]);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("[usual](usual/report.md)") && md.contains("overtopped: the dam does not hold"), "{md}");
    assert!(dir.join("usual/report.md").is_file());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("safety.json")).unwrap()).unwrap();
    let outcome = |name: &str| {
        let cases = report["combinations"].as_array().unwrap();
        cases.iter().find(|c| c["name"] == name).unwrap()["outcome"].clone()
    };
    assert_eq!((outcome("usual"), outcome("overtopped")), ("solved".into(), "does_not_hold".into()), "{report}");
}

// `damfem safety` on the dam standing on its rock block with a frictional joint and uplift
// (Scene B as the real case). Source: geo/scene_b_joint.toml without its cohesion (c = 0,
// horizontal joint between
// the two meshed bodies, the dam held by the joint alone: its rigid motions are test functions,
// so N = W − U and T = the reservoir's thrust on the dam ρ_w g 45²/2; FS_SR = F N/|T| exactly,
// the crack being closed); docs/method.md §1.9–§1.10. Goal: safety.json gives the joint line
// from the heel (0, 0) to the toe (40, 0), N + U = W to 10⁻⁵ on every mesh (N from the solved,
// smoothed traction; the second mesh's sides remeshed apart), |T| = the thrust to 10⁻⁶ on the
// last mesh (the adaptive loop's Newton, stopped on the first mesh once its linearisation error
// is below the discretisation error, runs there to its tolerance), U from the drained diagram, FS_SR's bracket around F (W − U)/thrust
// within 0.5 %, FS_LE = F N/|T|, compressive heel and toe means; joint.csv runs from the heel
// to the toe. Parameters: P1, mesh sizes × 2, two meshes.
#[test]
fn safety_reports_the_dam_on_its_rock_with_a_frictional_joint() {
    let tmp = TempDir::new("safety-two-body");
    // the scene without its cohesion, for the exact FS_SR
    let scene = coulomb_rock_scene(&tmp);
    let out = safety_coarse(&scene, &tmp.join("out"), &["--order", "1", "--max-steps", "2"]);
    assert_ok(&out);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("out/safety.json")).unwrap()).unwrap();
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{report}"));
    let line = &report["joint_line"];
    assert_eq!((number(&line["heel"][0]), number(&line["heel"][1])), (0.0, 0.0), "{line}");
    assert_eq!((number(&line["along"][0]), number(&line["length"])), (1.0, 40.0), "{line}");
    let r = &report["resultant"];
    let (n, t, u) = (number(&r["normal_force"]), number(&r["tangential_force"]), number(&r["uplift_force"]));
    let (weight, _) = scene_a_weight();
    let thrust = 0.5 * 1000.0 * 9.81 * 45.0 * 45.0;
    // N is the normal force of the traction the solved equations carry, at their δ: the dam's
    // vertical translation, a test function, balances it against W − U up to the residual of the
    // last Newton iterate, on every mesh, matching (the first) or remeshed apart (the second):
    // measured 2.0·10⁻¹⁰ of W at the iterate of (S_lin) on the first mesh and 2.4·10⁻¹⁴ on the
    // second, solved to Newton's tolerance (2.6·10⁻⁶ at the iterate where (S_lin) stopped Newton
    // there when the last mesh was finished from it), where the plain projection
    // of the iterate gave 0.66 %
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("out/history.json")).unwrap()).unwrap();
    for step in history["steps"].as_array().unwrap() {
        let r = &step["resultant"];
        let balance = number(&r["normal_force"]) + number(&r["uplift_force"]) - weight;
        println!("step {}: (N + U − W)/W = {:.2e}", step["step"], balance / weight);
        assert!(balance.abs() <= 1e-5 * weight, "step {}: N + U − W = {balance}", step["step"]);
    }
    assert!((n + u - weight).abs() <= 1e-5 * weight, "N + U = {} against W = {weight}", n + u);
    // T balances the thrust up to the residual of the last mesh's iterate, which Newton takes
    // to its tolerance: |T| − thrust measured 5.5·10⁻¹¹ of the thrust (2.0·10⁻³ when the
    // iterate of (S_lin), at a relative residual of 1.7·10⁻³, was reported)
    println!("(|T| − thrust)/thrust = {:.2e}", (t.abs() - thrust) / thrust);
    assert!((t.abs() - thrust).abs() <= 1e-6 * thrust, "|T| = {} against the thrust {thrust}", t.abs());
    // the drained diagram without a crack: H_u = ρ_w g 45 to the drains at 5 m, then to 0 at the toe
    let h_u = 1000.0 * 9.81 * 45.0;
    let at_drains = (1.0 - 0.6667) * h_u * 35.0 / 40.0;
    let (_, uplift) = linear_moments(&[(0.0, h_u), (5.0, at_drains), (40.0, 0.0)]);
    assert_eq!(number(&report["crack_length"]), 0.0, "{report}");
    assert!((u - uplift).abs() <= 1e-9 * uplift, "U = {u} against {uplift}");
    // the classical method takes the dam alone above the joint (the rock below it, joined at
    // the joint's nodes, is not its section): its weight W, the thrust and the same uplift
    let c = &report["classical"];
    let load = |kind: &str| c["loads"].as_array().unwrap().iter().find(|l| l["kind"] == kind).unwrap().clone();
    assert!((number(&load("weight")["normal"]) - weight).abs() <= 1e-9 * weight, "{c}");
    assert!((number(&load("reservoir")["shear"]) - thrust).abs() <= 1e-9 * thrust, "{c}");
    assert!((number(&c["uplift_force"]) - uplift).abs() <= 1e-9 * uplift, "{c}");
    assert_eq!(c["loads"].as_array().unwrap().len(), 3, "{c}");
    let exact = 0.8391 * (weight - uplift) / thrust;
    let sr = &report["strength_reduction"];
    let (held, failed) = (number(&sr["held"]), number(&sr["failed"]));
    assert!(held <= exact && failed >= exact && failed <= 1.005 * held, "{sr} against {exact}");
    let fs_le = number(&report["sliding_safety_factor"]);
    assert!((fs_le - 0.8391 * n / t.abs()).abs() <= 1e-6 * fs_le, "FS_LE {fs_le}");
    let base = &report["base_stresses"];
    assert!(number(&base["heel"]) < 0.0 && number(&base["toe"]) < 0.0, "{base}");
    let csv = std::fs::read_to_string(tmp.join("out/joint.csv")).unwrap();
    let s: Vec<f64> = csv.lines().skip(1).map(|l| l.split(',').nth(2).unwrap().parse().unwrap()).collect();
    assert!(s.windows(2).all(|w| w[0] <= w[1]) && s[0] >= 0.0 && *s.last().unwrap() <= 40.0, "{csv}");
}

// `damfem solve` from rest on a Coulomb joint that alone holds the dam. Source:
// geo/scene_b_joint.toml without its cohesion (c = 0, P2, mesh sizes × 2: 3 862 unknowns, no
// nested levels, so Newton starts from u = 0); docs/solver.md §4. From u = 0 Newton slid the
// dam far into slip and stalled at a relative residual of about 0.3 after 100 steps; the path
// now starts again from the closed, sticking state. Goal: the solve converges, with
// N + U = W (the rigid motions of the dam held by the joint alone are test functions) and
// |T| = the thrust ρ_w g 45²/2 to 10⁻⁶. Parameters: the scene's δ path (0.1 S to 10⁻⁴ S),
// at most 100 steps per δ.
#[test]
fn solve_holds_the_dam_on_a_coulomb_joint_from_rest() {
    let tmp = TempDir::new("coulomb-from-rest");
    let scene = coulomb_rock_scene(&tmp);
    let dir = tmp.join("out");
    let args = ["solve", "--size-factor", "2", "-q"].map(OsStr::new);
    let out = damfem(&[&args[..], &[scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]].concat());
    assert_ok(&out);
    let c = check_summary(&dir)["contact"].clone();
    let number = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{c}"));
    let (n, t, u) = (number(&c["normal_force"]), number(&c["tangential_force"]), number(&c["uplift_force"]));
    let (weight, _) = scene_a_weight();
    let thrust = 0.5 * 1000.0 * 9.81 * 45.0 * 45.0;
    println!("N + U = {:.6e} (W = {weight:.6e}), T = {t:.6e} (thrust {thrust:.6e})", n + u);
    assert!((n + u - weight).abs() <= 1e-6 * weight, "N + U = {} against W = {weight}", n + u);
    assert!((t.abs() - thrust).abs() <= 1e-6 * thrust, "|T| = {} against the thrust {thrust}", t.abs());
}
