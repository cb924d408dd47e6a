//! Bad or unusual user input through the `damfem` binary: scene values that the physics
//! forbids, keys and flags that would be accepted without effect, two tables for one physical
//! group, and output directories that hold an earlier run's files. Each is refused with one
//! sentence naming the key, flag or group, exit code 1 and no output file.

use super::cli::{assert_refused, check_warnings, edited_scene, TempDir};

// Source: the scenes of geo/, each edited by one key. Goal: a value that the physics or the
// method forbids, which damfem used to accept with exit code 0 (a weight pointing up, a
// water pressure pulling, a Newton tolerance that accepts u = 0, a
// displacement prescribed on a loaded curve, the third component of a heel), or that it
// accepted and failed on later leaving history.json (max_iter = 0, an infinite γ₀ or δ on the
// command line), is refused before meshing, naming the key or the flag. Parameters: scene_a,
// unit_square and scene_a_uplift at P1.
#[test]
fn values_the_physics_forbids_are_refused() {
    let tmp = TempDir::new("forbidden-values");
    let hydrostatic = "hydrostatic = { density = 1000.0, level = 70.0 }";
    let cases: [(&str, &str, &str, &[&str], &[&str]); 13] = [
        ("unit_square", "gravity = 1.0", "gravity = -1.0", &[], &["loads.gravity = -1", "non-negative"]),
        ("scene_a", "gravity = 9.81", "gravity = 0.0", &[], &["boundary.upstream.hydrostatic", "loads.gravity"]),
        (
            "scene_a",
            hydrostatic,
            "hydrostatic = { density = -1000.0, level = 70.0 }",
            &[],
            &["boundary.upstream.hydrostatic.density = -1000", "positive"],
        ),
        (
            "scene_a",
            "role = \"contact\"",
            "role = \"contact\"\nvalue = [0.1, 0.0]",
            &[],
            &["'base'", "value", "dirichlet"],
        ),
        ("scene_a", hydrostatic, &format!("{hydrostatic}\nfix = \"x\""), &[], &["'upstream'", "fix", "dirichlet"]),
        ("scene_a", "theta = 0.0", "theta = 0.0\nrtol = 1.0", &[], &["contact.rtol = 1", "[0, 1)"]),
        ("scene_a", "theta = 0.0", "theta = 0.0\nmax_iter = 0", &[], &["contact.max_iter = 0", "at least 1"]),
        (
            "scene_a",
            "theta = 0.0",
            "theta = 0.0\ndelta_start = -1.0",
            &[],
            &["contact.delta_start = -1", "non-negative"],
        ),
        (
            "scene_a",
            "theta = 0.0",
            "theta = 0.0\ndelta = 10.0",
            &["--semismooth"],
            &["contact.delta = 10", "semismooth"],
        ),
        ("scene_a", "theta = 0.0", "theta = 0.0", &["--gamma0", "inf"], &["--gamma0 = inf", "command line"]),
        ("scene_a", "theta = 0.0", "theta = 0.0", &["--delta", "inf"], &["--delta = inf", "command line"]),
        ("scene_a", "rho = 2400.0\n", "", &[], &["materials.concrete", "rho"]),
        (
            "scene_a_uplift",
            "crack = \"full\"",
            "crack = \"full\"\nheel = [0.0, 0.0, 0.0]",
            &[],
            &["uplift.heel", "3 components"],
        ),
    ];
    for (k, (name, from, to, extra, keywords)) in cases.into_iter().enumerate() {
        let scene = edited_scene(&tmp, name, |s| {
            assert!(s.contains(from), "{name}: {from}");
            s.replacen(from, to, 1)
        });
        let args: Vec<&str> = ["--order", "1"].iter().chain(extra).copied().collect();
        assert_refused(&format!("forbidden-{k}"), "solve", &scene, &args, keywords);
    }
}

// Source: geo/scene_a.toml with [contact] rtol = 0.01. Goal: a Newton tolerance that the
// method allows but that leaves an error of about 1 % in the results is said by `check`,
// naming the key (the scene's own tolerance, 10⁻¹⁰, is not: cli.rs,
// check_warns_about_defaults_and_strict_refuses). Parameters: P1.
#[test]
fn a_loose_newton_tolerance_is_said() {
    let tmp = TempDir::new("loose-rtol");
    let loose = edited_scene(&tmp, "scene_a", |s| s.replace("theta = 0.0", "theta = 0.0\nrtol = 0.01"));
    let warnings = check_warnings(&loose, &["--order", "1"]);
    assert!(warnings.len() == 1 && warnings[0].contains("contact.rtol = 0.01"), "{warnings:?}");
}

// Source: geo/scene_a.toml and geo/dam_lifts_on_rock.toml with a second table for one
// physical group, its name spelt with another case (names are matched ignoring case). Goal:
// the two tables are refused, naming both and the group, where damfem used to apply both
// water loads to the upstream face (twice the thrust) or keep one material or one role of the
// two with exit code 0. Parameters: P1.
#[test]
fn two_tables_for_one_physical_group_are_refused() {
    let tmp = TempDir::new("two-tables");
    let water = "[boundary.Upstream]\nrole = \"neumann\"\nhydrostatic = { level = 70.0 }\n";
    let twice = edited_scene(&tmp, "scene_a", |s| s + water);
    assert_refused(
        "two-tables-water",
        "solve",
        &twice,
        &["--order", "1"],
        &["[boundary.Upstream]", "[boundary.upstream]", "'upstream'"],
    );
    let roles = edited_scene(&tmp, "scene_a", |s| s + "[boundary.Crest]\nrole = \"dirichlet\"\n");
    assert_refused("two-tables-roles", "check", &roles, &["--order", "1"], &["[boundary.Crest]", "[boundary.crest]"]);
    let material = "[materials.Upper_block]\nE = 1.0e9\nnu = 0.2\nrho = 2400.0\n";
    let materials = edited_scene(&tmp, "dam_lifts_on_rock", |s| s + material);
    assert_refused(
        "two-tables-materials",
        "check",
        &materials,
        &["--order", "1", "--size-factor", "3"],
        &["[materials.Upper_block]", "[materials.upper_block]", "'upper_block'"],
    );
}
