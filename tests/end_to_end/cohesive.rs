//! End to end: a cohesive joint's keys, its checks and the crack–uplift coupling with a bond
//! (docs/method.md §1.13).

use super::support::{assert_ok, assert_solve_fails, check_summary, damfem, edited_scene, TempDir};
use std::path::{Path, PathBuf};

/// geo/scene_a_uplift.toml (its reservoir at 45 m, full uplift in the crack, Coulomb F = 0.84)
/// with `bond` added to its [contact] table.
fn bonded_scene(tmp: &TempDir, bond: &str) -> PathBuf {
    edited_scene(tmp, "scene_a_uplift", |text| text.replace("[contact]\n", &format!("[contact]\n{bond}\n")))
}

/// The summary's contact part of `scene` solved at size factor 2.
fn solved(tmp: &TempDir, name: &str, scene: &Path) -> serde_json::Value {
    let out = tmp.join(name);
    assert_ok(&damfem(&["solve", "-q", scene.to_str().unwrap(), "--size-factor", "2", "-o", out.to_str().unwrap()]));
    check_summary(&out)["contact"].clone()
}

// Source: docs/method.md §1.13 (the crack is the broken part of the bond) and §1.8 (full
// uplift in the crack). Goal: on the dam of geo/scene_a_uplift.toml, a bond of σ_t = 0.2 MPa
// and G_f = 100 N/m softens at the heel (a process zone of more than 0.3 m) but does not break:
// no crack, so less uplift than the crack of the joint without a bond lets in; with G_f = 1 N/m
// the bond breaks at the heel, the crack is that broken length, and its uplift lies between the
// two. Parameters: P2, size factor 2.
#[test]
fn the_reservoir_fills_the_broken_part_of_a_bond_only() {
    let tmp = TempDir::new("cohesive-uplift");
    let plain = solved(&tmp, "plain", &edited_scene(&tmp, "scene_a_uplift", |t| t.to_string()));
    let tough = solved(&tmp, "tough", &bonded_scene(&tmp, "tensile_strength = 2.0e5\nfracture_energy = 100.0"));
    let brittle = solved(&tmp, "brittle", &bonded_scene(&tmp, "tensile_strength = 2.0e5\nfracture_energy = 1.0"));
    let number = |c: &serde_json::Value, key: &str| c[key].as_f64().unwrap_or_else(|| panic!("{key} in {c}"));
    let lengths = |c: &serde_json::Value| {
        let l = &c["curves"][0]["bond_lengths"];
        ["bonded", "process_zone", "broken"].map(|k| l[k].as_f64().unwrap_or_else(|| panic!("{k} in {l}")))
    };
    let [_, zone, broken] = lengths(&tough);
    println!("tough: process zone {zone} m, broken {broken} m, crack {}", tough["crack_length"]);
    assert!(zone > 0.3 && broken == 0.0 && number(&tough, "crack_length") == 0.0, "{tough}");
    let [_, _, broken] = lengths(&brittle);
    let crack = number(&brittle, "crack_length");
    println!("brittle: broken {broken} m, crack {crack} m; plain crack {}", plain["crack_length"]);
    assert!(broken > 0.3 && (crack - broken).abs() < 1e-9, "the crack is the broken length: {brittle}");
    assert!((number(&brittle["crack"], "length") - crack).abs() < 1e-3, "the uplift's crack: {}", brittle["crack"]);
    let [u_tough, u_brittle, u_plain] = [&tough, &brittle, &plain].map(|c| number(c, "uplift_force"));
    assert!(u_tough < u_brittle && u_brittle < u_plain, "U: {u_tough}, {u_brittle}, {u_plain}");
}

// (bad input) The bond's keys: both or neither, positive, and a fracture energy the mesh can
// resolve (γ o_c > σ_t on every face), each refused in one sentence naming the key.
#[test]
fn bond_keys_are_checked() {
    let tmp = TempDir::new("cohesive-keys");
    let cases = [
        ("alone", "tensile_strength = 2.0e5", vec!["contact.tensile_strength is set without contact.fracture_energy"]),
        (
            "negative",
            "tensile_strength = -1.0\nfracture_energy = 100.0",
            vec!["contact.tensile_strength = -1", "positive"],
        ),
        ("zero", "tensile_strength = 2.0e5\nfracture_energy = 0.0", vec!["contact.fracture_energy = 0", "positive"]),
        (
            "unresolved",
            "tensile_strength = 2.0e6\nfracture_energy = 1.0e-3",
            vec!["contact.fracture_energy = 0.001 N/m is too small for the mesh of curve 'base'", "gamma0"],
        ),
    ];
    for (name, bond, keywords) in cases {
        let scene = bonded_scene(&tmp, bond);
        let message = assert_solve_fails(&format!("cohesive-{name}"), &scene, &keywords);
        assert_eq!(message.trim().lines().count(), 1, "{name}: {message}");
    }
}

// Source: docs/reference.md (outputs). Goal: a bonded joint's outputs: `damage` and
// `crack_state` on the boundary VTU, `bond_lengths` per curve in summary.json summing to the
// joint's length, and the bonded, process-zone and broken lengths in the safety report.
// Parameters: geo/scene_a_uplift.toml with σ_t = 0.2 MPa and G_f = 100 N/m, P2, size factor 2,
// one adaptive step.
#[test]
fn a_bonded_joint_reports_its_damage() {
    let tmp = TempDir::new("cohesive-outputs");
    let scene = bonded_scene(&tmp, "tensile_strength = 2.0e5\nfracture_energy = 100.0");
    let contact = solved(&tmp, "solve", &scene);
    let lengths = &contact["curves"][0]["bond_lengths"];
    let sum: f64 = ["bonded", "process_zone", "broken"].iter().map(|k| lengths[k].as_f64().unwrap()).sum();
    assert!((sum - 40.0).abs() < 1e-9, "the base is 40 m long: {lengths}");
    let boundary = std::fs::read_to_string(tmp.join("solve").join("scene_a_uplift_boundary.vtu")).unwrap();
    for field in ["damage", "crack_state"] {
        assert!(boundary.contains(&format!("Name=\"{field}\"")), "{field} on the boundary VTU");
    }
    let out = tmp.join("safety");
    let args = ["safety", "-q", scene.to_str().unwrap(), "--size-factor", "2", "--max-steps", "1", "-o"];
    assert_ok(&damfem(&[&args[..], &[out.to_str().unwrap()]].concat()));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    for row in ["bond: length bonded", "bond: length in the process zone (softening)", "bond: length broken"] {
        assert!(report.contains(row), "{row} in the report");
    }
}

// Source: docs/method.md §1.13 (a bond regularises the heel: its process zone has a length of
// its own, set by σ_t, G_f and the dam, not by the mesh). Goal: on the worked dam's usual
// combination with a bond of σ_t = 0.5 MPa and G_f = 100 N/m on its base, the process zone
// converges under refinement: its change from size factor 0.5 to 0.25 is less than half of
// that from 1 to 0.5, and the bond breaks on none of the meshes. Parameters: P2, gmsh's
// sizes of geo/dam_combinations.geo times 1, 0.5 and 0.25.
#[test]
fn the_process_zone_at_the_heel_converges_under_refinement() {
    let tmp = TempDir::new("cohesive-refinement");
    let scene = edited_scene(&tmp, "dam_combinations", |text| {
        text.replace("[joints.base]\n", "[joints.base]\ntensile_strength = 5.0e5\nfracture_energy = 100.0\n")
    });
    let zone = |factor: &str| {
        let out = tmp.join(&format!("f{factor}"));
        let args = ["solve", "-q", scene.to_str().unwrap(), "--combination", "usual", "--size-factor", factor, "-o"];
        assert_ok(&damfem(&[&args[..], &[out.to_str().unwrap()]].concat()));
        let lengths = check_summary(&out)["contact"]["curves"][0]["bond_lengths"].clone();
        assert_eq!(lengths["broken"].as_f64(), Some(0.0), "size factor {factor}: {lengths}");
        lengths["process_zone"].as_f64().unwrap_or_else(|| panic!("{lengths}"))
    };
    let zones = ["1", "0.5", "0.25"].map(zone);
    println!("process zone at size factors 1, 0.5, 0.25: {zones:?} m");
    assert!(zones.iter().all(|&z| z > 0.1), "{zones:?}");
    assert!((zones[2] - zones[1]).abs() < 0.5 * (zones[1] - zones[0]).abs(), "{zones:?}");
}

// (warnings) A bond given in the wrong unit, σ_t = 0.5 meant as MPa and G_f = 0.1 meant as
// kN/m, is warned of by `damfem check`, naming each key, and refused under --strict.
#[test]
fn a_bond_in_the_wrong_unit_is_warned_of() {
    let tmp = TempDir::new("cohesive-units");
    let scene = bonded_scene(&tmp, "tensile_strength = 0.5\nfracture_energy = 0.1");
    let out = damfem(&["check", scene.to_str().unwrap()]);
    assert_ok(&out);
    let warnings = super::support::stderr(&out);
    for key in ["contact.tensile_strength = 5e-1 Pa is outside", "contact.fracture_energy = 1e-1 N/m is outside"] {
        assert!(warnings.contains(key), "{key} in {warnings}");
    }
    let strict = damfem(&["check", "--strict", scene.to_str().unwrap()]);
    assert_eq!(strict.status.code(), Some(1), "{}", super::support::stderr(&strict));
}

// Source: docs/method.md §1.13 (a face resolves the bond only while h_F < γ₀ E o_c / σ_t).
// Goal: the adaptive loop holds the cells along a bonded joint below that size, so that no
// remesh coarsens the joint past it: a bond that the first mesh resolves by a factor of 1.5
// runs through every step (before, the second mesh coarsened a face of the base past it and
// the run stopped there). Parameters: geo/scene_a_uplift.toml with σ_t = 2 MPa and
// G_f = 0.74 N/m (o_c = 0.74 μm), P2, size factor 1, 4 adaptive steps.
#[test]
fn adaptive_remeshing_keeps_a_bond_resolved() {
    let tmp = TempDir::new("cohesive-adapt");
    let scene = bonded_scene(&tmp, "tensile_strength = 2.0e6\nfracture_energy = 0.74");
    let out = tmp.join("adapt");
    assert_ok(&damfem(&["adapt", "-q", scene.to_str().unwrap(), "--steps", "4", "-o", out.to_str().unwrap()]));
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 5, "a header and four steps:\n{history}");
}
