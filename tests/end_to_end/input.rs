//! Bad or unusual user input through the `damfem` binary: scene values that the physics
//! forbids, keys and flags that would be accepted without effect, two tables for one physical
//! group, output directories that hold an earlier run's files, combination names that are not
//! plain, uplift headwaters that do not fit the reservoir, combinations that only `safety`
//! used to build, and `.msh` tags with two names. Each is refused with one sentence naming the
//! key, flag, group or file, exit code 1 and no output file, or said in a warning.

use super::support::{
    assert_error, assert_ok, assert_refused, check_warnings, damfem, edited_scene, repo, stderr, TempDir,
};
use std::ffi::OsStr;
use std::path::Path;

/// A scene of geo/, a line of it, the line that replaces it, extra flags and the words of the
/// error.
type Case<'a> = (&'a str, &'a str, &'a str, &'a [&'a str], &'a [&'a str]);

// Source: the scenes of geo/, each edited by one key. Goal: a value that the physics or the
// method forbids, which damfem used to accept with exit code 0 (a weight pointing up, a water
// pressure pulling, a Newton tolerance that accepts u = 0, a displacement prescribed on a
// loaded curve or on a component left free, the third component of a heel, a material
// without density), or that it accepted and failed on later leaving history.json
// (max_iter = 0, an infinite γ₀ or δ on the command line), is refused before meshing, naming
// the key or the flag. Parameters: scene_a, unit_square and scene_a_uplift at P1.
#[test]
fn values_the_physics_forbids_are_refused() {
    let tmp = TempDir::new("forbidden-values");
    let hydrostatic = "hydrostatic = { density = 1000.0, level = 70.0 }";
    let cases: [Case; 14] = [
        (
            "scene_a",
            "[boundary.toe]\nrole = \"dirichlet\"",
            "[boundary.toe]\nrole = \"dirichlet\"\nfix = \"x\"\nvalue = [0.0, 0.01]",
            &[],
            &["'toe'", "value[1] = 0.01", "no effect"],
        ),
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

/// The names of the files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// `damfem <args> -q -o <dir>`, asserted to succeed.
fn run_into(dir: &Path, args: &[&str]) {
    let mut all: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    all.extend([OsStr::new("-q"), OsStr::new("-o"), dir.as_os_str()]);
    assert_ok(&damfem(&all));
}

// Source: geo/scene_a.toml run by `adapt`, `solve --estimate`, `solve` and `mesh` one after
// the other into one directory, beside a file of the user's. Goal: after each run the
// directory holds that run's files only (for `solve`, those summary.json lists, itself and
// history.json), where the step files, collections, history.csv and figures of `adapt`, or
// the `_dg.vtu` of an earlier estimate, used to stay beside a summary that does not list them;
// the user's file stays. Parameters: P1, sizes × 3, two adaptive steps.
#[test]
fn a_rerun_leaves_no_file_of_an_earlier_run() {
    let tmp = TempDir::new("rerun-outputs");
    let dir = tmp.join("out");
    let scene = repo("geo/scene_a.toml");
    let scene = scene.to_str().unwrap();
    let p1 = ["--order", "1", "--size-factor", "3"];
    run_into(&dir, &[&["adapt", scene, "--steps", "2"][..], &p1].concat());
    std::fs::write(dir.join("notes.txt"), "the user's").unwrap();
    for estimate in [&["--estimate"][..], &[]] {
        run_into(&dir, &[&["solve", scene][..], &p1, estimate].concat());
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        let files = summary["files"].as_array().unwrap().iter();
        let mut expected: Vec<String> =
            files.map(|f| Path::new(f.as_str().unwrap()).file_name().unwrap().to_string_lossy().into_owned()).collect();
        expected.extend(["history.json", "notes.txt", "summary.json"].map(String::from));
        expected.sort();
        assert_eq!(listing(&dir), expected, "solve {estimate:?}");
    }
    run_into(&dir, &[&["mesh", scene][..], &p1].concat());
    assert_eq!(listing(&dir), ["notes.txt", "scene_a.msh", "scene_a_boundary.vtu", "scene_a_mesh.vtu"]);
}

// Source: geo/scene_a.toml with a boundary table for a curve its geometry lacks, run by
// `adapt` into a directory that holds an earlier run. Goal: the scene is refused as `solve`
// refuses it, in one sentence without "adaptive step 0", and the directory is left as it was
// (no history.json of a run that never started, the earlier run's files kept), where adapt
// used to write history.json and history.csv and remove the earlier steps. Parameters: P1,
// sizes × 3.
#[test]
fn adapt_refuses_a_scene_that_does_not_fit_its_mesh_writing_nothing() {
    let tmp = TempDir::new("adapt-bad-scene");
    let dir = tmp.join("out");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let scene = repo("geo/scene_a.toml");
    run_into(&dir, &[&["adapt", scene.to_str().unwrap(), "--steps", "1"][..], &p1].concat());
    let before = listing(&dir);
    let bad = edited_scene(&tmp, "scene_a", |s| s + "[boundary.heel]\nrole = \"free\"\n");
    let args: Vec<&OsStr> = ["adapt", "-q"].iter().map(OsStr::new).chain([bad.as_os_str()]).collect();
    let out = damfem(&[&args[..], &["-o", dir.to_str().unwrap()].map(OsStr::new), &p1.map(OsStr::new)].concat());
    let message = assert_error(&out, &["scene_a.toml", "'heel'"]);
    assert!(!message.contains("step 0"), "{message}");
    assert_eq!(listing(&dir), before);
    let empty = tmp.join("empty");
    let out = damfem(&[&args[..], &["-o", empty.to_str().unwrap()].map(OsStr::new), &p1.map(OsStr::new)].concat());
    assert_error(&out, &["'heel'"]);
    assert!(!empty.exists(), "{} was left behind", empty.display());
}

// Source: geo/unit_square.toml (clamped, no contact curve, no joint) with a [contact] key or a
// contact flag of `solve`. Goal: a key or flag that has nothing to act on is refused, naming
// it, where damfem used to solve the bonded problem with exit code 0 as if it had been
// applied. Parameters: P1.
#[test]
fn contact_keys_without_contact_are_refused() {
    let tmp = TempDir::new("contact-unused");
    let square = repo("geo/unit_square.toml");
    for (flag, value) in [("--gamma0", "5"), ("--theta", "1"), ("--delta", "10"), ("--friction", "0.5")] {
        assert_refused(
            &format!("contact-unused{flag}"),
            "solve",
            &square,
            &["--order", "1", flag, value],
            &[&format!("{flag} = {value}"), "no curve has role contact", "command line"],
        );
    }
    for line in ["gap = 0.1", "max_iter = 20", "direction = [0.0, -1.0]"] {
        let scene = edited_scene(&tmp, "unit_square", |s| format!("{s}\n[contact]\n{line}\n"));
        let key = format!("contact.{}", line.split(" = ").next().unwrap());
        assert_refused("contact-unused-key", "check", &scene, &["--order", "1"], &[&key, "no curve has role contact"]);
    }
}

// Source: geo/scene_a_combinations.toml meshed by `damfem mesh --combination flood`. Goal: a
// flag the command accepts but cannot use (a load combination changes loads, never the mesh)
// is refused, naming it, where `mesh` used to write the same files as without it, with exit
// code 0. Parameters: P1.
#[test]
fn mesh_refuses_a_load_combination() {
    let scene = repo("geo/scene_a_combinations.toml");
    assert_refused(
        "mesh-combination",
        "mesh",
        &scene,
        &["--order", "1", "--combination", "flood"],
        &["--combination flood", "damfem mesh"],
    );
}

// Source: geo/scene_a_uplift.toml (its joint from (0, 0) to (40, 0)) with [uplift] heel at the
// joint's middle, then at its upstream end. Goal: a heel that is not an end of the joint is
// refused, naming the key and the joint's ends, where damfem used to take the nearer end (or
// either, at the middle) as the heel and lay the uplift diagram from it with exit code 0;
// the upstream end itself is accepted. Parameters: P1, sizes × 3.
#[test]
fn a_heel_off_the_joint_ends_is_refused() {
    let tmp = TempDir::new("heel-off");
    let at = |heel: &str| {
        edited_scene(&tmp, "scene_a_uplift", |s| {
            s.replace("crack = \"full\"", &format!("crack = \"full\"\nheel = {heel}"))
        })
    };
    let p1 = ["--order", "1", "--size-factor", "3"];
    assert_refused(
        "heel-off-middle",
        "check",
        &at("[20.0, 0.0]"),
        &p1,
        &["uplift.heel = [20.0, 0.0]", "(0, 0)", "(40, 0)"],
    );
    let upstream = at("[0.0, 0.0]");
    let args: Vec<&OsStr> = ["check", "-q"].iter().chain(&p1).map(OsStr::new).chain([upstream.as_os_str()]).collect();
    assert_ok(&damfem(&args));
}

// Source: geo/scene_a.toml with its geometry replaced by the degree-1 .msh that `damfem mesh
// --order 1` makes of it. Goal: the scene's `[mesh] order = 2` raises the mesh to degree 2
// as `--order 2` does, where it used to be ignored (a P1 solve with exit code 0), and a
// `[mesh]` key that only gmsh's meshing of a .geo reads (size_factor) is refused, naming it.
// Parameters: sizes × 3.
#[test]
fn a_msh_scene_reads_its_order_and_refuses_the_keys_of_gmsh() {
    let tmp = TempDir::new("msh-scene");
    let mesh_dir = tmp.join("mesh");
    run_into(&mesh_dir, &["mesh", repo("geo/scene_a.toml").to_str().unwrap(), "--order", "1", "--size-factor", "3"]);
    let msh = format!("geometry = {:?}", mesh_dir.join("scene_a.msh").display().to_string());
    let with_msh = |s: String| {
        let line = s.lines().find(|l| l.starts_with("geometry = ")).unwrap().to_string();
        s.replace(&line, &msh)
    };
    let p2 = edited_scene(&tmp, "scene_a", with_msh);
    let out_dir = tmp.join("out");
    run_into(&out_dir, &["solve", p2.to_str().unwrap()]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["order"], 2, "{summary}");
    let sized = edited_scene(&tmp, "scene_a", |s| with_msh(s).replace("order = 2", "order = 2\nsize_factor = 5.0"));
    assert_refused("msh-scene-size", "solve", &sized, &[], &["mesh.size_factor", "scene_a.msh"]);
}

// Source: geo/scene_a.toml with [output] boundary = false, meshed by `damfem mesh`. Goal: the
// key is honoured as by `solve` and `adapt` (no `<scene>_boundary.vtu`), where `mesh` used to
// write the file anyway. Parameters: P1, sizes × 3.
#[test]
fn mesh_honours_output_boundary() {
    let tmp = TempDir::new("mesh-boundary");
    let scene = edited_scene(&tmp, "scene_a", |s| s.replace("directory = \"out/scene_a\"", "boundary = false"));
    let dir = tmp.join("out");
    run_into(&dir, &["mesh", scene.to_str().unwrap(), "--order", "1", "--size-factor", "3"]);
    assert_eq!(listing(&dir), ["scene_a.msh", "scene_a_mesh.vtu"]);
}

// Source: an empty .geo file, solved and meshed. Goal: refused in one sentence naming the file,
// where the error was gmsh's "gmshModelGetBoundingBox failed: Empty bounding box", naming
// neither the file nor what is wrong with it.
#[test]
fn an_empty_geometry_is_named() {
    let tmp = TempDir::new("empty-geo");
    let geo = tmp.join("empty.geo");
    std::fs::write(&geo, "").unwrap();
    for command in ["solve", "mesh"] {
        assert_refused(&format!("empty-geo-{command}"), command, &geo, &[], &["empty.geo", "is empty"]);
    }
}

// Source: geo/dam_lifts_on_rock.toml with a [joints.nothing] table, a curve its geometry lacks
// (after the scene's own joints, base and lift, in the order of the tables). Goal: the error
// lists the physical curves of the geometry only, where it also listed 'base:rock' and
// 'lift:lower_block', the sides damfem makes of the joints it has split, which no scene can
// name. Parameters: P1, sizes × 3.
#[test]
fn an_unknown_joint_lists_the_curves_of_the_geometry() {
    let tmp = TempDir::new("unknown-joint");
    let scene = edited_scene(&tmp, "dam_lifts_on_rock", |s| s + "\n[joints.nothing]\nfriction = 0.5\n");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let message = assert_refused("unknown-joint-out", "check", &scene, &p1, &["'nothing'", "base, lift"]);
    assert!(!message.contains("base:rock") && !message.contains("lift:lower_block"), "{message}");
}

// Source: geo/scene_a_combinations.toml with its combinations replaced by one named "..",
// "../escaped", "a/b" or "" (each combination's results go to the directory of its name under
// -o). Goal: a name that is not plain is refused when the scene is read, naming the
// combination and what a name may hold, and no file is written in or outside the output
// directory, where `damfem safety` used to write its reports one directory above -o (and
// remove files there), in nested folders, or into -o itself over the combined report, with
// exit code 0. Parameters: P1, sizes × 3, one adaptive step.
#[test]
fn a_combination_name_that_is_not_plain_is_refused() {
    let tmp = TempDir::new("combination-names");
    for (k, name) in ["..", "../escaped", "a/b", ""].into_iter().enumerate() {
        let scene = edited_scene(&tmp, "scene_a_combinations", |s| {
            format!("{}[combinations.{name:?}]\n", &s[..s.find("[combinations.").unwrap()])
        });
        let run = tmp.join(&format!("run-{k}"));
        let out_dir = run.join("out");
        let p1 = ["--order", "1", "--size-factor", "3", "--max-steps", "1"];
        let args: Vec<&OsStr> = ["safety", "-q"].iter().map(OsStr::new).chain([scene.as_os_str()]).collect();
        let out = damfem(&[&args[..], &["-o".as_ref(), out_dir.as_os_str()], &p1.map(OsStr::new)].concat());
        assert_error(&out, &["scene_a_combinations.toml", &format!("[combinations.{name:?}]"), "letters, digits"]);
        assert!(!run.exists(), "{name:?}: {} was written", run.display());
        assert_eq!(listing(&tmp.0), ["scene_a_combinations.toml"], "{name:?}");
    }
}

// Source: geo/scene_a_uplift.toml (its joint from (0, 0) to (40, 0), the reservoir at 45 m on
// the upstream face) with [uplift] headwater = -10, geo/dam_lifts_on_rock_uplift.toml with
// [joints.lift.uplift] headwater = 15 (its lift joint at y = 20 m, under the same reservoir),
// and geo/scene_a_combinations.toml with [combinations.flood.uplift] headwater = -10. Goal: a
// headwater at or below the joint's heel while the reservoir at the heel stands above it is
// refused, naming both keys, where damfem used to lay no uplift along the joint with exit
// code 0, on the unsafe side. Parameters: P1, sizes × 3.
#[test]
fn a_headwater_below_the_heel_under_a_reservoir_above_it_is_refused() {
    let tmp = TempDir::new("headwater-below");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let reservoir = "boundary.upstream.hydrostatic.level = 45";
    let uplift = edited_scene(&tmp, "scene_a_uplift", |s| s.replace("headwater = 45.0", "headwater = -10.0"));
    for command in ["check", "solve"] {
        let keywords = ["uplift.headwater = -10", "y = 0", reservoir];
        assert_refused(&format!("headwater-below-{command}"), command, &uplift, &p1, &keywords);
    }
    let lift = edited_scene(&tmp, "dam_lifts_on_rock_uplift", |s| {
        s.replace("[joints.lift.uplift]\nheadwater = 45.0", "[joints.lift.uplift]\nheadwater = 15.0")
    });
    assert_refused(
        "headwater-below-lift",
        "check",
        &lift,
        &p1,
        &["joints.lift.uplift.headwater = 15", "y = 20", reservoir],
    );
    let flood = edited_scene(&tmp, "scene_a_combinations", |s| {
        s.replace("[combinations.flood.uplift]\nheadwater = 50.0", "[combinations.flood.uplift]\nheadwater = -10.0")
    });
    let keywords = ["uplift.headwater = -10", "boundary.upstream.hydrostatic.level = 50"];
    assert_refused("headwater-below-flood", "safety", &flood, &[&p1[..], &["--max-steps", "1"]].concat(), &keywords);
}

// Source: geo/scene_a_uplift.toml with [uplift] headwater = 40 (the reservoir at 45 m), and
// geo/scene_a_combinations.toml whose flood raises the reservoir to 50 m but leaves the
// uplift headwater at the scene's 45 m. Goal: an uplift headwater that differs from the level
// of the reservoir at the joint's heel is said, naming both keys, by `check` and `solve`, and
// by `safety` for that combination alone, naming it, where damfem used to take the two levels
// without a word; the scene's own combinations (the levels equal) are not. Parameters: P1,
// sizes × 3, one adaptive step.
#[test]
fn a_headwater_that_differs_from_the_reservoir_is_said() {
    let tmp = TempDir::new("headwater-differs");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let lower = edited_scene(&tmp, "scene_a_uplift", |s| s.replace("headwater = 45.0", "headwater = 40.0"));
    let warnings = check_warnings(&lower, &p1);
    let said = |w: &String, level: &str, reservoir: &str| {
        w.contains(&format!("uplift.headwater = {level}"))
            && w.contains(&format!("boundary.upstream.hydrostatic.level = {reservoir}"))
    };
    assert!(warnings.len() == 1 && said(&warnings[0], "40", "45"), "{warnings:?}");
    let dir = tmp.join("solve");
    let solve: Vec<&OsStr> = ["solve"].iter().chain(&p1).map(OsStr::new).chain([lower.as_os_str()]).collect();
    let out = damfem(&[&solve[..], &["-o".as_ref(), dir.as_os_str()]].concat());
    assert_ok(&out);
    assert!(stderr(&out).lines().any(|l| l.starts_with("warning: uplift.headwater = 40")), "{}", stderr(&out));
    assert!(check_warnings(&repo("geo/scene_a_combinations.toml"), &p1).is_empty());
    let flood =
        edited_scene(&tmp, "scene_a_combinations", |s| s.replace("[combinations.flood.uplift]\nheadwater = 50.0", ""));
    let warnings = check_warnings(&flood, &[&p1[..], &["--combination", "flood"]].concat());
    assert!(warnings.len() == 1 && said(&warnings[0], "45", "50"), "{warnings:?}");
    let dir = tmp.join("safety");
    let safety: Vec<&OsStr> =
        ["safety", "--max-steps", "1"].iter().chain(&p1).map(OsStr::new).chain([flood.as_os_str()]).collect();
    let out = damfem(&[&safety[..], &["-o".as_ref(), dir.as_os_str()]].concat());
    assert_ok(&out);
    let warnings: Vec<String> = stderr(&out)
        .lines()
        .filter(|l| l.starts_with("warning:") && l.contains("headwater"))
        .map(String::from)
        .collect();
    assert!(
        warnings.len() == 1 && warnings[0].starts_with("warning: combination flood: uplift.headwater = 45"),
        "{warnings:?}"
    );
}

// Source: geo/scene_a_combinations.toml with its flood combination edited: a load on a curve
// the geometry lacks, the base's role turned to free, or the flood's uplift headwater removed
// (the reservoir raised to 50 m, the headwater left at the scene's 45 m). Goal: `check`
// builds every combination's scene and problem as `safety` does, and refuses the first two
// as `safety` does, each message naming the combination, where `check` used to say ok and
// `safety` failed without naming it; the third's warning is said once, naming the
// combination. Parameters: P1, sizes × 3.
#[test]
fn check_checks_every_combination() {
    let tmp = TempDir::new("check-combinations");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let cases = [
        ("[combinations.flood.boundary.nothing]\nrole = \"neumann\"\n", ["combination flood: ", "'nothing'"]),
        ("[combinations.flood.boundary.base]\nrole = \"free\"\n", ["combination flood: ", "[uplift] needs a joint"]),
    ];
    for (k, (extra, keywords)) in cases.iter().enumerate() {
        let scene = edited_scene(&tmp, "scene_a_combinations", |s| format!("{s}\n{extra}"));
        for command in ["check", "safety"] {
            assert_refused(&format!("check-combination-{k}-{command}"), command, &scene, &p1, keywords);
        }
    }
    let raised =
        edited_scene(&tmp, "scene_a_combinations", |s| s.replace("[combinations.flood.uplift]\nheadwater = 50.0", ""));
    let warnings = check_warnings(&raised, &p1);
    let said =
        "warning: combination flood: uplift.headwater = 45 differs from boundary.upstream.hydrostatic.level = 50";
    assert!(warnings.len() == 1 && warnings[0].starts_with(said), "{warnings:?}");
}

// Source: tests/data/cli/square.msh (physical curve 1 "Gamma_D", surface 2 "block") with a
// second name, "bottom", for the physical curve 1 in its $PhysicalNames. Goal: the file is
// refused by every command that reads it, naming the file, the tag and both names, where
// gmsh kept one name and dropped the other without a word (a scene naming the dropped one
// failed on an unknown curve, the other ran with exit code 0).
#[test]
fn a_msh_tag_with_two_names_is_refused() {
    let tmp = TempDir::new("msh-two-names");
    let msh = tmp.join("two_names.msh");
    let body = std::fs::read_to_string(super::support::fixture("square.msh")).unwrap();
    let twice = body.replace("2\n1 1 \"Gamma_D\"\n", "3\n1 1 \"Gamma_D\"\n1 1 \"bottom\"\n");
    assert_ne!(twice, body);
    std::fs::write(&msh, twice).unwrap();
    for command in ["check", "solve"] {
        let keywords = ["two_names.msh", "physical tag 1", "\"Gamma_D\"", "\"bottom\""];
        assert_refused(&format!("msh-two-names-{command}"), command, &msh, &[], &keywords);
    }
}
