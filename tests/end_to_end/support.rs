//! What the end-to-end tests share: temporary directories, running the binary, the scenes of
//! geo/ edited in a copy, and the assertions on a run's outcome.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh directory under the system temp dir, removed when dropped.
pub(crate) struct TempDir(pub(crate) PathBuf);

impl TempDir {
    pub(crate) fn new(name: &str) -> TempDir {
        let dir = std::env::temp_dir().join(format!("damfem-cli-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        TempDir(dir)
    }

    pub(crate) fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs the binary with `args`.
pub(crate) fn damfem<S: AsRef<OsStr>>(args: &[S]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_damfem")).args(args).output().expect("cannot run damfem")
}

/// A file of the repository.
pub(crate) fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// A fixture of tests/data/cli.
pub(crate) fn fixture(name: &str) -> PathBuf {
    repo("tests/data/cli").join(name)
}

pub(crate) fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts a successful run, showing stderr otherwise.
pub(crate) fn assert_ok(out: &Output) {
    assert!(out.status.success(), "{:?}: {}", out.status, stderr(out));
}

/// Asserts a failed run whose stderr is one "error:" line, continued only by indented lines
/// (a TOML error's excerpt), containing every keyword; returns it.
pub(crate) fn assert_error(out: &Output, keywords: &[&str]) -> String {
    let text = stderr(out);
    assert!(!out.status.success(), "expected a failure, stderr: {text}");
    assert!(!text.contains("panicked"), "panic: {text}");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("error:"), "{text}");
    assert!(lines[1..].iter().all(|l| l.starts_with("  ")), "expected one error on stderr, got: {text}");
    for k in keywords {
        assert!(text.contains(k), "{k:?} not in: {text}");
    }
    text
}

/// Asserts that `dir` holds no file at all (results, temporaries), if it exists.
pub(crate) fn assert_nothing_written(dir: &Path) {
    if let Ok(entries) = std::fs::read_dir(dir) {
        let names: Vec<_> = entries.map(|e| e.unwrap().file_name()).collect();
        assert!(names.is_empty(), "{} holds {names:?}", dir.display());
    }
}

/// Files of `dir` whose names start with '.' (hidden temporaries).
pub(crate) fn hidden_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// Runs `damfem solve -q <scene> -o <tmp>/out` and asserts it fails with `keywords`, writing nothing.
pub(crate) fn assert_solve_fails(name: &str, scene: &Path, keywords: &[&str]) -> String {
    let tmp = TempDir::new(name);
    let out_dir = tmp.join("out");
    let out = damfem(&["solve".as_ref(), "-q".as_ref(), scene.as_os_str(), "-o".as_ref(), out_dir.as_os_str()]);
    let message = assert_error(&out, keywords);
    assert_nothing_written(&out_dir);
    message
}

/// Reads summary.json of `dir` and checks that it describes a non-empty, finite solution.
pub(crate) fn check_summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    for key in ["nodes", "cells", "unknowns", "free_unknowns"] {
        assert!(s[key].as_u64().unwrap() > 0, "{key} in {text}");
    }
    for key in ["max_displacement", "max_von_mises", "min_principal_stress", "max_principal_stress"] {
        assert!(s[key].as_f64().unwrap().is_finite(), "{key} in {text}");
    }
    for file in s["files"].as_array().unwrap() {
        assert!(Path::new(file.as_str().unwrap()).is_file(), "{file}");
    }
    assert!(s["units"]["stress"].as_str().unwrap().starts_with("Pa "), "units in {text}");
    assert!(s["units"]["length"].as_str().unwrap().starts_with("m "), "units in {text}");
    assert!(!s["tags"]["material"].as_object().unwrap().is_empty(), "tag names in {text}");
    s
}

/// Runs `damfem <command> -q <input> -o <tmp>/out [extra]` (no `-o` for `check`) and asserts
/// that it fails with one error line holding `keywords`, and leaves no output directory;
/// returns the line.
pub(crate) fn assert_refused(name: &str, command: &str, input: &Path, extra: &[&str], keywords: &[&str]) -> String {
    let tmp = TempDir::new(name);
    let out_dir = tmp.join("out");
    let mut args = vec![OsStr::new(command), OsStr::new("-q"), input.as_os_str()];
    if command != "check" {
        args.extend([OsStr::new("-o"), out_dir.as_os_str()]);
    }
    args.extend(extra.iter().map(OsStr::new));
    let message = assert_error(&damfem(&args), keywords);
    assert!(!out_dir.exists(), "{} was left behind", out_dir.display());
    message
}

/// `damfem check <scene> [extra]`: asserts success and returns the "warning:" lines of stderr.
pub(crate) fn check_warnings(scene: &Path, extra: &[&str]) -> Vec<String> {
    let mut args = vec![OsStr::new("check"), scene.as_os_str()];
    args.extend(extra.iter().map(OsStr::new));
    let out = damfem(&args);
    assert_ok(&out);
    stderr(&out).lines().filter(|l| l.starts_with("warning:")).map(str::to_owned).collect()
}

/// A copy of geo/<name>.toml in `tmp` with its geometry path made absolute and `edit` applied.
pub(crate) fn edited_scene(tmp: &TempDir, name: &str, edit: impl Fn(String) -> String) -> PathBuf {
    let body = std::fs::read_to_string(repo(&format!("geo/{name}.toml"))).unwrap();
    let line = body.lines().find(|l| l.starts_with("geometry = ")).expect("a geometry line");
    let file = line.trim_start_matches("geometry = ").trim_matches('"');
    let geometry = format!("geometry = {:?}", repo(&format!("geo/{file}")).display().to_string());
    let path = tmp.join(&format!("{name}.toml"));
    std::fs::write(&path, edit(body.replace(line, &geometry))).unwrap();
    path
}

/// `damfem args` started, its stderr piped, once `file` exists (looked for every `poll`, for at
/// most five minutes).
pub(crate) fn spawned_until(args: &[&OsStr], file: &Path, poll: std::time::Duration) -> std::process::Child {
    let child =
        Command::new(env!("CARGO_BIN_EXE_damfem")).args(args).stderr(std::process::Stdio::piped()).spawn().unwrap();
    let start = std::time::Instant::now();
    while !file.exists() {
        assert!(start.elapsed().as_secs() < 300, "no {} after five minutes", file.display());
        std::thread::sleep(poll);
    }
    child
}
