//! A case's run through the `damfem` binary and what its `summary.json` gives.

use super::*;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// How a run of `damfem solve` ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Exit 0: a solution.
    Result,
    /// Exit 3, or exit 1 with "no equilibrium": the dam does not hold.
    Verdict,
    /// Exit 4: the solver failed.
    Failure,
    /// Any other exit.
    Error,
}

impl Outcome {
    pub fn name(&self) -> &'static str {
        match self {
            Outcome::Result => "result",
            Outcome::Verdict => "verdict",
            Outcome::Failure => "failure",
            Outcome::Error => "error",
        }
    }
}

/// What a run of `damfem solve` gave: its outcome, exit code, the message of a failed run,
/// and from `summary.json` the Newton steps (summed over the levels of nested iteration, and
/// the most on one mesh), FS_LE, N, T, U, the contact
/// length, the crack and the resultant's distance from the heel; the wall time \[s\].
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    pub outcome: Outcome,
    pub code: Option<i32>,
    pub message: String,
    pub newton_steps: Option<u64>,
    pub newton_steps_per_mesh: Option<u64>,
    pub safety_factor: Option<f64>,
    pub normal: Option<f64>,
    pub tangential: Option<f64>,
    pub uplift: Option<f64>,
    pub contact_length: Option<f64>,
    pub crack_length: Option<f64>,
    /// The crack s_c of the uplift diagram (`crack = "full"`), and whether it stopped at the
    /// drain line (`contact::Crack::at_drains`).
    pub diagram_crack: Option<f64>,
    pub at_drains: bool,
    pub position: Option<f64>,
    /// FS_SR's bracket \[held, failed\] (`--strength-reduction`).
    pub strength: Option<[f64; 2]>,
    pub seconds: f64,
}

/// `damfem solve <scene> -o <dir>/out --size-factor f` by the binary `damfem`, the case
/// written into `dir`.
pub fn run(damfem: &Path, case: &DamCase, dir: &Path) -> std::io::Result<Run> {
    run_with(damfem, case, dir, &[])
}

/// [`run`] with the flags `extra` too.
pub fn run_with(damfem: &Path, case: &DamCase, dir: &Path, extra: &[&str]) -> std::io::Result<Run> {
    let scene = case.write(dir)?;
    let out = dir.join("out");
    let start = Instant::now();
    let output = Command::new(damfem)
        .arg("solve")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .arg("--size-factor")
        .arg(case.size_factor().to_string())
        .args(extra)
        .output()?;
    let seconds = start.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&output.stderr);
    let code = output.status.code();
    let outcome = match code {
        Some(0) => Outcome::Result,
        Some(3) => Outcome::Verdict,
        Some(1) if stderr.contains("no equilibrium") => Outcome::Verdict,
        Some(4) => Outcome::Failure,
        _ => Outcome::Error,
    };
    let message = stderr
        .lines()
        .find(|l| l.starts_with("verdict:") || l.starts_with("error:"))
        .or_else(|| stderr.lines().last())
        .unwrap_or("")
        .to_string();
    let summary = match outcome {
        Outcome::Result => std::fs::read_to_string(out.join("summary.json")).ok(),
        _ => None,
    };
    let json: serde_json::Value = summary.and_then(|s| serde_json::from_str(&s).ok()).unwrap_or_default();
    let c = &json["contact"];
    let curve = &c["curves"][0];
    let either = |key: &str| c[key].as_f64().or_else(|| curve[key].as_f64());
    let coarse: Vec<u64> =
        c["coarse"].as_array().map_or(Vec::new(), |l| l.iter().filter_map(|s| s["newton_steps"].as_u64()).collect());
    let safety_factor = either("sliding_safety_factor");
    // a result without its safety factor, or whose Newton steps do not add up, is an error of
    // the run
    let (outcome, message) = match (outcome, safety_factor, steps_add_up(c)) {
        (Outcome::Result, None, _) => (Outcome::Error, "exit 0 without sliding_safety_factor in summary.json".into()),
        (Outcome::Result, _, Err(why)) => (Outcome::Error, why),
        _ => (outcome, message),
    };
    Ok(Run {
        outcome,
        code,
        message,
        newton_steps: c["newton_steps"].as_u64().map(|n| n + coarse.iter().sum::<u64>()),
        newton_steps_per_mesh: c["newton_steps"].as_u64().map(|n| coarse.iter().fold(n, |m, &k| m.max(k))),
        safety_factor,
        normal: either("normal_force"),
        tangential: either("tangential_force"),
        uplift: either("uplift_force"),
        contact_length: curve["contact_length"].as_f64(),
        crack_length: c["crack_length"].as_f64(),
        diagram_crack: curve["crack"]["length"].as_f64(),
        at_drains: curve["crack"]["at_drains"].as_bool() == Some(true),
        position: c["resultant"]["position"].as_f64(),
        strength: ["held", "failed"]
            .map(|k| json["strength_reduction"][k].as_f64())
            .into_iter()
            .collect::<Option<Vec<_>>>()
            .map(|v| [v[0], v[1]]),
        seconds,
    })
}

/// Whether the Newton steps of the `contact` section of a summary.json add up: `newton_steps`
/// = Σ `stages` + `discarded_newton_steps`, and, where the load path ran on this mesh,
/// = Σ of its states' steps.
fn steps_add_up(c: &serde_json::Value) -> Result<(), String> {
    let total = c["newton_steps"].as_u64().unwrap_or(0);
    let sum = |list: &serde_json::Value, of: &dyn Fn(&serde_json::Value) -> Option<u64>| {
        list.as_array().map_or(0, |l| l.iter().filter_map(of).sum::<u64>())
    };
    let stages = sum(&c["stages"], &|s| s[1].as_u64());
    let discarded = c["discarded_newton_steps"].as_u64().unwrap_or(0);
    let path = sum(&c["load_path"], &|p| p["newton_steps"].as_u64());
    if stages + discarded != total {
        return Err(format!("newton_steps {total} ≠ Σ stages {stages} + discarded {discarded} in summary.json"));
    }
    if path != 0 && path != total {
        return Err(format!("newton_steps {total} ≠ Σ load_path newton_steps {path} in summary.json"));
    }
    Ok(())
}
