//! Limits and leftovers through the `damfem` binary: the cell limit of an adaptive run, the
//! files of a failed or concurrent run, inputs that are not regular files, and values beyond
//! any dam. Each ends with exit code 1 and one sentence naming the flag, key or file and no
//! file left behind, or with a result and a sentence saying where it stopped.

use super::support::{assert_error, assert_ok, damfem, repo, spawned_until, stderr, TempDir};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Output;

/// The JSON file `path`.
fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

// Source: geo/scene_a.toml adapted with a cell limit of 8000, far below what 20 steps reach
// (about 10⁶ cells). Goal: the run stops after the step whose next mesh would exceed the
// limit, saying so in one sentence naming --max-cells, with every step written and no mesh
// beyond about the limit, where remeshes from a size field skipped the estimate and grew
// without bound. Parameters: P1, equidistribution.
#[test]
fn adapt_stops_at_the_cell_limit() {
    let tmp = TempDir::new("adapt-cell-limit");
    let (scene, dir) = (repo("geo/scene_a.toml"), tmp.join("out"));
    let mut args: Vec<&OsStr> =
        ["adapt", "--order", "1", "--steps", "20", "--max-cells", "8000"].iter().map(OsStr::new).collect();
    args.extend([scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]);
    let out = damfem(&args);
    assert_ok(&out);
    let progress = stderr(&out);
    let said: Vec<&str> = progress.lines().filter(|l| l.contains("--max-cells")).collect();
    assert_eq!(said.len(), 1, "{progress}");
    assert!(said[0].contains("stopped after step") && said[0].contains("limit of 8000 cells"), "{progress}");
    let history = json(&dir.join("history.json"));
    let steps = history["steps"].as_array().unwrap();
    assert!(steps.len() < 20, "{} steps", steps.len());
    assert!(steps.iter().all(|s| s["cells"].as_u64().unwrap() < 8800), "{steps:?}");
    let (last, before) = steps.split_last().unwrap();
    assert!(last["cell_limit"]["cells"].as_f64().unwrap() > 8000.0, "{last}");
    assert!(before.iter().all(|s| s["cell_limit"].is_null()));
    let pvd = std::fs::read_to_string(dir.join("scene_a.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), steps.len());
}

/// `damfem <command> -q <input> [-o <dir>] <extra>` (`check` writes nothing and has no -o).
fn run(command: &str, input: &Path, dir: &Path, extra: &[&str]) -> Output {
    let mut args = vec![OsStr::new(command), OsStr::new("-q"), input.as_os_str()];
    if command != "check" {
        args.extend([OsStr::new("-o"), dir.as_os_str()]);
    }
    args.extend(extra.iter().map(OsStr::new));
    damfem(&args)
}

/// [`run`] of `check` or `solve` (no flags), killed and failed if it takes longer than 20 s.
fn run_briefly(command: &str, input: &Path, dir: &Path) -> Output {
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_damfem"))
        .args([OsStr::new(command), OsStr::new("-q"), input.as_os_str()])
        .args(if command == "check" { vec![] } else { vec![OsStr::new("-o"), dir.as_os_str()] })
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed().as_secs() > 20 {
            child.kill().unwrap();
            panic!("{command} {} still runs after 20 s", input.display());
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    child.wait_with_output().unwrap()
}

/// The names in `dir`, sorted (hidden files too); empty if it does not exist.
fn listing(dir: &Path) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(dir) else { return Vec::new() };
    let mut names: Vec<String> = entries.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    names
}

/// The step files `<scene>_NN*.vtu` in `dir` that no `.pvd` of `dir` lists.
fn unlisted_step_files(dir: &Path) -> Vec<String> {
    let pvd: String = listing(dir)
        .iter()
        .filter(|f| f.ends_with(".pvd"))
        .map(|f| std::fs::read_to_string(dir.join(f)).unwrap())
        .collect();
    listing(dir).into_iter().filter(|f| f.ends_with(".vtu") && !pvd.contains(&format!("\"{f}\""))).collect()
}

// Source: geo/scene_a.toml, each command into a directory where one of its files is a
// directory, so that writing it fails after others were written (as on a full disk). Goal: the
// command fails naming that file and leaves none of its files, where `mesh` left a complete
// .msh and its `_mesh.vtu`, `solve --estimate` its `_dg.vtu`, and a failed adaptive step its
// `_NN_dg.vtu` (on step 0, also a history of no step); a step before the failed one stays,
// listed by the collections. Parameters: P1, sizes × 3.
#[test]
fn a_failed_write_leaves_none_of_the_commands_files() {
    let tmp = TempDir::new("failed-write");
    let scene = repo("geo/scene_a.toml");
    let p1 = ["--order", "1", "--size-factor", "3"];
    let cases: [(&str, &[&str], &str, &[&str]); 4] = [
        ("mesh", &[], "scene_a_boundary.vtu", &[]),
        ("solve", &["--estimate"], "scene_a.vtu", &[]),
        ("adapt", &["--steps", "2"], "scene_a_00.vtu", &[]),
        ("adapt", &["--steps", "3"], "scene_a_01.vtu", &["scene_a_00.vtu", "scene_a_00_boundary.vtu"]),
    ];
    for (command, extra, blocked, kept) in cases {
        let dir = tmp.join("out");
        std::fs::create_dir_all(dir.join(blocked)).unwrap();
        let out = run(command, &scene, &dir, &[extra, &p1[..]].concat());
        let message = assert_error(&out, &[blocked]);
        assert_eq!(out.status.code(), Some(1), "{message}");
        let files = listing(&dir);
        assert!(files.contains(&blocked.to_string()), "{files:?}");
        if kept.is_empty() {
            assert_eq!(files, [blocked], "{command} {extra:?}");
        } else {
            assert!(kept.iter().all(|k| files.contains(&k.to_string())), "{files:?}");
            assert!(!files.iter().any(|f| f.starts_with("scene_a_01") && f != blocked), "{files:?}");
            assert_eq!(unlisted_step_files(&dir), [blocked], "{files:?}");
            assert_eq!(json(&dir.join("history.json"))["steps"].as_array().unwrap().len(), 1);
        }
        assert_eq!(listing(&tmp.0), ["out"], "outside the output directory");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

// Source: geo/scene_a.toml adapted into a directory whose lock another command holds (here
// the test itself), and solved there while a `solve` runs. Goal: the second command is refused
// with one sentence naming the directory, writing nothing, where an `adapt` started during a
// `solve` removed that solve's results with both exiting 0; a command that ends removes its
// lock file. Parameters: P1, sizes × 3.
#[test]
fn an_output_directory_in_use_is_refused() {
    let tmp = TempDir::new("dir-in-use");
    let (scene, dir) = (repo("geo/scene_a.toml"), tmp.join("out"));
    let p1 = ["--order", "1", "--size-factor", "3"];
    std::fs::create_dir_all(&dir).unwrap();
    let lock = std::fs::File::create(dir.join(".damfem.lock")).unwrap();
    lock.try_lock().unwrap();
    let out = run("adapt", &scene, &dir, &p1);
    assert_error(&out, &[&format!("output directory {} is in use", dir.display()), "-o"]);
    assert_eq!(listing(&dir), [".damfem.lock"]);
    lock.unlock().unwrap();
    std::fs::remove_file(dir.join(".damfem.lock")).unwrap();
    // a real solve, and an adapt once the solve holds the directory
    let args = ["solve", "-q", "--order", "2", "--size-factor", "0.5", "--estimate", "-o"].map(OsStr::new);
    let args = [&args[..], &[dir.as_os_str(), scene.as_os_str()]].concat();
    let solve = spawned_until(&args, &dir.join(".damfem.lock"), std::time::Duration::from_millis(5));
    let out = run("adapt", &scene, &dir, &p1);
    assert_error(&out, &["is in use"]);
    let solved = solve.wait_with_output().unwrap();
    assert_ok(&solved);
    let files = listing(&dir);
    assert!(files.contains(&"scene_a_dg.vtu".to_string()) && !files.contains(&"history.csv".to_string()), "{files:?}");
    assert!(!files.contains(&".damfem.lock".to_string()), "{files:?}");
}

// Source: a FIFO, /dev/zero, a loop of symbolic links, a link to nothing and a directory
// given as the scene, and a FIFO as a scene's geometry and as a file its .geo includes. Goal:
// each is refused before it is opened, in one sentence naming the file and saying what it
// is (a FIFO does not block the run), where a FIFO blocked forever and a loop or /dev/zero
// were "file not found"; no output directory is made.
#[test]
fn an_input_that_is_not_a_regular_file_is_refused() {
    let tmp = TempDir::new("not-a-file");
    let fifo = |name: &str| {
        let path = tmp.join(name);
        let made = std::process::Command::new("mkfifo").arg(&path).status().unwrap();
        assert!(made.success());
        path
    };
    let (loop_a, loop_b) = (tmp.join("a.toml"), tmp.join("b.toml"));
    std::os::unix::fs::symlink(&loop_b, &loop_a).unwrap();
    std::os::unix::fs::symlink(&loop_a, &loop_b).unwrap();
    let dangling = tmp.join("dangling.toml");
    std::os::unix::fs::symlink(tmp.join("nothing.toml"), &dangling).unwrap();
    std::fs::create_dir(tmp.join("dir.toml")).unwrap();
    fifo("pipe.geo");
    let pipe_geometry = tmp.join("pipe_geometry.toml");
    std::fs::write(&pipe_geometry, "geometry = \"pipe.geo\"\n").unwrap();
    let body = std::fs::read_to_string(super::support::fixture("bare.geo")).unwrap();
    let includes = tmp.join("includes.geo");
    std::fs::write(&includes, format!("Include \"pipe.geo\";\n{body}")).unwrap();
    let cases: [(PathBuf, &str, &str); 8] = [
        (fifo("pipe.toml"), "pipe.toml", "named pipe (FIFO)"),
        ("/dev/zero".into(), "/dev/zero", "character device"),
        (loop_a, "a.toml", "loop of symbolic links"),
        (dangling, "dangling.toml", "symbolic link to a file that does not exist"),
        (tmp.join("dir.toml"), "dir.toml", "directory"),
        (pipe_geometry, "pipe.geo", "named pipe (FIFO)"),
        (includes, "pipe.geo", "named pipe (FIFO)"),
        (tmp.join("missing.toml"), "missing.toml", "file not found"),
    ];
    for (input, file, what) in cases {
        for command in ["check", "solve"] {
            let dir = tmp.join("out");
            let out = run_briefly(command, &input, &dir);
            let message = assert_error(&out, &[file, what]);
            assert_eq!(out.status.code(), Some(1), "{message}");
            assert!(!message.contains("not found") || what == "file not found", "{message}");
            assert!(!dir.exists(), "{command} {}", input.display());
        }
    }
}

// Source: geo/scene_a.toml with one value beyond any dam: E = 10³⁰⁸ Pa, rho = 10⁹ kg/m³, a
// water density of 10⁹ kg/m³, --friction 10³⁰⁸, and --cohesion 10¹² Pa. Goal: each is
// refused before meshing, in one sentence naming the key or flag and the bound, where Newton
// failed after 17–51 s blaming contact.max_iter. Parameters: P1.
#[test]
fn values_beyond_any_dam_are_refused() {
    let tmp = TempDir::new("beyond-any-dam");
    let hydrostatic = "hydrostatic = { density = 1000.0, level = 70.0 }";
    let cases: [(&str, &str, &[&str], &[&str]); 5] = [
        ("E = 3.0e10", "E = 1e308", &[], &["material 'concrete'", "E = 1e308 Pa exceeds 1e13 Pa"]),
        ("rho = 2400.0", "rho = 1e9", &[], &["material 'concrete'", "rho = 1e9", "exceeds 1e5"]),
        (hydrostatic, "hydrostatic = { density = 1e9, level = 70.0 }", &[], &["hydrostatic.density = 1e9", "1e5"]),
        ("E = 3.0e10", "E = 3.0e10", &["--friction", "1e308"], &["--friction", "exceeds 100"]),
        ("E = 3.0e10", "E = 3.0e10", &["--friction", "0.5", "--cohesion", "1e12"], &["--cohesion", "1e10 Pa"]),
    ];
    for (k, (from, to, flags, keywords)) in cases.into_iter().enumerate() {
        let scene = super::support::edited_scene(&tmp, "scene_a", |s| {
            assert!(s.contains(from), "{from}");
            s.replacen(from, to, 1)
        });
        let start = std::time::Instant::now();
        let args: Vec<&str> = ["--order", "1"].iter().chain(flags).copied().collect();
        super::support::assert_refused(&format!("beyond-{k}"), "solve", &scene, &args, keywords);
        assert!(start.elapsed().as_secs() < 5, "{to} {flags:?} took {:?}", start.elapsed());
    }
}

// Source: tests/data/cli/bare.geo with 10 000 more physical curve groups on one of its curves,
// none with a role. Goal: `check` ends in seconds (the groups were read and checked in a time
// that grew as the square of their count, 14 s on 10 000) and prints its first 20 warnings and
// how many more there are, where it printed 800 KB of them.
#[test]
fn ten_thousand_physical_groups_are_read_in_seconds_with_few_warnings() {
    let tmp = TempDir::new("many-groups");
    let body = std::fs::read_to_string(super::support::fixture("bare.geo")).unwrap();
    let groups: String = (0..10_000).map(|i| format!("Physical Curve(\"c{i}\", {}) = {{2}};\n", 100 + i)).collect();
    let geo = tmp.join("many.geo");
    std::fs::write(&geo, body + &groups).unwrap();
    let start = std::time::Instant::now();
    let out = damfem(&[OsStr::new("check"), geo.as_os_str()]);
    assert!(start.elapsed().as_secs() < 8, "took {:?}", start.elapsed());
    let text = stderr(&out);
    assert_ok(&out);
    let warnings: Vec<&str> = text.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 21, "{}", &text[..text.len().min(2000)]);
    assert_eq!(warnings[20], "warning: 9981 more warnings not shown");
}

// Source: geo/scene_a.toml with a combination "bad" whose boundary table names a curve the
// geometry lacks, run by `solve --combination bad` and `adapt --combination bad`. Goal: the
// error of building its problem names the combination, where it named the curve only.
// Parameters: P1.
#[test]
fn a_combination_whose_problem_fails_is_named() {
    let tmp = TempDir::new("combination-problem");
    let scene = super::support::edited_scene(&tmp, "scene_a", |s| {
        s + "\n[combinations.bad.boundary.nowhere]\nrole = \"free\"\n"
    });
    for command in ["solve", "adapt"] {
        let args = ["--order", "1", "--combination", "bad"];
        super::support::assert_refused(command, command, &scene, &args, &["--combination bad", "'nowhere'"]);
    }
}

// Source: geo/scene_a.toml adapted, sent SIGINT as soon as the first file of step 1 (its
// `_01_dg.vtu`) exists. Goal: the run ends with 130 and leaves no step file that the `.pvd`
// collections do not list and no hidden temporary, where an interrupt left a `_NN_dg.vtu`
// that no collection listed. Parameters: P2, sizes × 0.5.
#[test]
fn an_interrupted_adaptive_step_leaves_no_unlisted_file() {
    let tmp = TempDir::new("adapt-sigint-step");
    let (scene, dir) = (repo("geo/scene_a.toml"), tmp.join("out"));
    let args = ["adapt", "-q", "--size-factor", "0.5", "--steps", "40", "-o"].map(OsStr::new);
    let args = [&args[..], &[dir.as_os_str(), scene.as_os_str()]].concat();
    let mut child = spawned_until(&args, &dir.join("scene_a_01_dg.vtu"), std::time::Duration::from_micros(200));
    // SAFETY: kill sends a signal to the child process started above
    assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
    assert_eq!(child.wait().unwrap().code(), Some(130));
    assert_eq!(unlisted_step_files(&dir), Vec::<String>::new(), "{:?}", listing(&dir));
    assert!(!listing(&dir).iter().any(|f| f.starts_with('.')), "{:?}", listing(&dir));
}
