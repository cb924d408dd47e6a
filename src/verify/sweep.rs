//! The stability sweep's machinery: one row per solver run (status, Newton steps, residual,
//! condition estimate, the answer at probe points), its comparison with a reference, and the
//! markdown and CSV tables. [`super::cases`] runs the combinations `examples/stability.rs` lists.

use crate::contact::nitsche::NitscheParameters;
use crate::contact::projection::Smoothing;
use crate::contact::{continuation, ContactJoint, ContactProblem, JointLaw};
use crate::elasticity::stress::cell_mean_stress;
use crate::elasticity::Problem;
use crate::fem::transfer::interpolate;
use crate::geometry::{distance, norm, Point, Vector};
use crate::io::atomic::write_output;
use crate::solve::condition::condition_1;
use crate::solve::{Cholesky, NewtonError, NewtonOptions, NonlinearSystem, SparseLu};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The error of a row's body.
pub type BoxError = Box<dyn std::error::Error + Send + Sync>;

/// How a combination ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Newton reached ‖F‖ ≤ rtol·‖b‖, or the Cholesky solve succeeded.
    Converged,
    /// Newton stopped because the increment reached round-off, above rtol.
    Stagnated,
    /// The solver returned an error (its text is the reason).
    Failed,
    /// The code panicked: a failure of the example.
    Panicked,
}

impl Status {
    pub fn name(&self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::Stagnated => "stagnated",
            Status::Failed => "failed",
            Status::Panicked => "PANIC",
        }
    }
}

/// What a reference comparison allows.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// On max(probe difference / max probe |u_ref|, |max|u| − max|u_ref|| / max|u_ref|).
    pub u: f64,
    /// On |L_c − L_c,ref| \[m\], when both have a contact zone.
    pub length: Option<f64>,
}

/// The computed displacement and the quantities compared, in the original units.
#[derive(Debug, Clone)]
pub struct Answer {
    /// Nodal displacements.
    pub u: Vec<Vector>,
    /// u at the probe points (of the cell nearest to a probe outside the mesh).
    pub probes: Vec<Vector>,
    pub max_u: f64,
    pub contact_length: Option<f64>,
    /// Length of the longest contact face.
    pub contact_face: Option<f64>,
    /// First NaN/inf found in u, the stresses or the contact states, if any.
    pub nonfinite: Option<String>,
}

/// One combination of the sweep.
#[derive(Debug, Clone)]
pub struct Row {
    pub group: String,
    pub case: String,
    pub order: usize,
    pub dofs: usize,
    pub iterations: Option<usize>,
    pub rel_residual: Option<f64>,
    /// Smallest relative residual of a Newton run that ran out of steps.
    pub min_rel_residual: Option<f64>,
    pub status: Status,
    /// The solver's message when it did not converge (full text).
    pub reason: String,
    /// A shortened reason for the markdown table.
    pub reason_short: String,
    /// Hager–Higham estimate of κ₁ of the final Jacobian (or stiffness matrix).
    pub cond: Option<f64>,
    pub solution: Option<Answer>,
    /// Differences to the reference: displacement (relative) and contact length \[m\].
    pub du: Option<f64>,
    pub dl: Option<f64>,
    pub tolerance: Option<Tolerance>,
    /// None: no comparison (reference row, or no answer).
    pub matches: Option<bool>,
    pub is_reference: bool,
    /// A retry of the combination in the row above.
    pub is_retry: bool,
    pub seconds: f64,
    pub note: String,
}

impl Row {
    pub fn new(group: &str, case: String, order: usize) -> Row {
        Row {
            group: group.into(),
            case,
            order,
            dofs: 0,
            iterations: None,
            rel_residual: None,
            min_rel_residual: None,
            status: Status::Failed,
            reason: String::new(),
            reason_short: String::new(),
            cond: None,
            solution: None,
            du: None,
            dl: None,
            tolerance: None,
            matches: None,
            is_reference: false,
            is_retry: false,
            seconds: 0.0,
            note: String::new(),
        }
    }

    /// Whether the answer is free of NaN/inf (None: there is no answer).
    pub fn finite(&self) -> Option<bool> {
        self.solution.as_ref().map(|s| s.nonfinite.is_none() && self.rel_residual.is_none_or(f64::is_finite))
    }

    /// Compares with `reference` under `tolerance`.
    pub fn compare(&mut self, reference: Option<&Answer>, tolerance: Tolerance) {
        self.tolerance = Some(tolerance);
        let (Some(s), Some(r)) = (&self.solution, reference) else { return };
        let scale = r.probes.iter().map(|&p| norm(p)).fold(0.0, f64::max);
        let probe = s.probes.iter().zip(&r.probes).map(|(&a, &b)| distance(a, b) / scale).fold(0.0, f64::max);
        let du = probe.max((s.max_u - r.max_u).abs() / r.max_u);
        self.du = Some(du);
        self.dl = match (s.contact_length, r.contact_length) {
            (Some(a), Some(b)) => Some((a - b).abs()),
            _ => None,
        };
        let length_ok = match (self.dl, tolerance.length) {
            (Some(d), Some(t)) => d <= t,
            _ => true,
        };
        self.matches = Some(du <= tolerance.u && length_ok);
    }
}

/// The first non-finite entry of u or of the cell stresses, if any.
fn nonfinite_fields(problem: &Problem, u: &[Vector]) -> Option<String> {
    if let Some(n) = u.iter().position(|v| !(v[0].is_finite() && v[1].is_finite())) {
        return Some(format!("u at node {n} = {:?}", u[n]));
    }
    let sigma = cell_mean_stress(problem, u);
    sigma.iter().position(|s| !s.iter().all(|v| v.is_finite())).map(|c| format!("stress in cell {c} = {:?}", sigma[c]))
}

/// The solution in the original units (displacements times `length`), with its checks.
fn answer_of(problem: &Problem, u: Vec<Vector>, length: f64, probes: &[Point]) -> Answer {
    let nonfinite = nonfinite_fields(problem, &u);
    let u: Vec<Vector> = u.into_iter().map(|v| [v[0] * length, v[1] * length]).collect();
    let points: Vec<Point> = probes.iter().map(|p| [p[0] / length, p[1] / length]).collect();
    Answer {
        probes: interpolate(&problem.mesh, &u, &points),
        max_u: u.iter().map(|&v| norm(v)).fold(0.0, f64::max),
        u,
        contact_length: None,
        contact_face: None,
        nonfinite,
    }
}

/// Nitsche and regularisation settings of one contact solve.
#[derive(Debug, Clone, Copy)]
pub struct Knobs {
    pub gamma0: f64,
    pub theta: f64,
    /// δ = delta · S (0: plain projection).
    pub delta: f64,
    /// First δ of the continuation path as a multiple of S (None: direct solve at δ).
    pub start: Option<f64>,
    /// Newton's relative residual tolerance and step limit.
    pub rtol: f64,
    pub max_iter: usize,
    /// The joint law of Γ_C.
    pub law: JointLaw,
}

impl Default for Knobs {
    /// The CLI's defaults: γ₀ = 10, θ = 0, δ = 10⁻⁴ S, no continuation, rtol 10⁻¹⁰,
    /// 50 Newton steps, frictionless.
    fn default() -> Self {
        Knobs {
            gamma0: NitscheParameters::GAMMA0,
            theta: 0.0,
            delta: 1e-4,
            start: None,
            rtol: 1e-10,
            max_iter: 50,
            law: JointLaw::Frictionless,
        }
    }
}

/// Steps, last and smallest relative residual and a short text of a Newton error.
fn describe_error(error: &NewtonError) -> (Option<usize>, Option<f64>, Option<f64>, String) {
    match error {
        NewtonError::NotConverged { history, scale } => {
            let rel: Vec<f64> = history.iter().map(|it| it.residual / scale).collect();
            let tail: Vec<String> = rel.iter().rev().take(3).rev().map(|r| format!("{r:.1e}")).collect();
            let min = rel.iter().copied().fold(f64::INFINITY, f64::min);
            let short = format!(
                "Newton did not converge in {} steps: last relative residuals {} (min {min:.1e})",
                history.len(),
                tail.join(", ")
            );
            (Some(history.len()), rel.last().copied(), Some(min), short)
        }
        NewtonError::NonFinite { step } => (Some(*step), None, None, error.to_string()),
        NewtonError::Solve { step, .. } => (Some(*step), None, None, error.to_string()),
    }
}

/// Solves the contact problem on the facets `tags` of `problem`; `length` scales the
/// displacement back to the original units.
pub fn contact_row(row: &mut Row, problem: &Problem, tags: &[i32], knobs: Knobs, length: f64, probes: &[Point]) {
    let disc = problem.discretise();
    row.dofs = disc.dofs.n_free;
    let scale = problem.stress_scale(&disc.topology);
    let delta = knobs.delta * scale;
    let start = knobs.start.map_or(delta, |s| (s * scale).max(delta));
    let parameters = NitscheParameters { gamma0: knobs.gamma0, theta: knobs.theta, ..Default::default() };
    let joint = ContactJoint::uniform(tags.to_vec(), Vec::new(), knobs.law, parameters);
    let mut contact = ContactProblem::new(problem, &disc, &joint, Smoothing { delta });
    let contact_face = contact.nitsche.faces.iter().map(|f| f.length).fold(0.0, f64::max) * length;
    let options = NewtonOptions { rtol: knobs.rtol, max_iter: knobs.max_iter, ..NewtonOptions::default() };
    match continuation(&mut contact, delta, start, vec![0.0; disc.dofs.n_free], &options) {
        Ok((x, stages)) => {
            let last = &stages.last().expect("at least one stage").report;
            let rel = last.residual / last.scale;
            row.iterations = Some(crate::contact::newton_steps(&stages));
            row.rel_residual = Some(rel);
            if rel <= options.rtol {
                row.status = Status::Converged;
            } else {
                row.status = Status::Stagnated;
                row.reason = format!(
                    "the Newton increment reached round-off (‖Δ‖ ≤ 1e-13‖x‖) at relative residual {rel:.2e} > rtol {:.0e}",
                    options.rtol
                );
                row.reason_short = row.reason.clone();
            }
            if stages.len() > 1 {
                let per: Vec<String> = stages.iter().map(|s| s.report.iterations.len().to_string()).collect();
                row.note = format!("{} stages, steps {}", stages.len(), per.join("+"));
            }
            // the Jacobian at the answer, with the projection of the last stage
            let mut residual = vec![0.0; disc.dofs.n_free];
            let mut jacobian = vec![0.0; disc.pattern.nnz()];
            contact.evaluate(&x, &mut residual, Some(&mut jacobian));
            row.cond = condition_1(&disc.pattern, &jacobian);
            let faces = contact.face_states(&x);
            let mut sol = answer_of(problem, problem.displacement(&disc, &x), length, probes);
            let bad_face = faces.iter().position(|f| {
                ![f.pressure, f.normal_displacement, f.contact_length, f.regularisation_error]
                    .iter()
                    .all(|v| v.is_finite())
            });
            if let (None, Some(k)) = (&sol.nonfinite, bad_face) {
                sol.nonfinite = Some(format!("contact face {k}: {:?}", faces[k]));
            }
            sol.contact_length = Some(faces.iter().map(|f| f.contact_length).sum::<f64>() * length);
            sol.contact_face = Some(contact_face);
            row.solution = Some(sol);
        }
        Err(error) => {
            let (steps, rel, min, short) = describe_error(&error);
            row.iterations = steps;
            row.rel_residual = rel;
            row.min_rel_residual = min;
            row.status = Status::Failed;
            row.reason = error.to_string();
            row.reason_short = short;
            if start > delta {
                row.note = "steps and residual of the failing continuation stage".into();
            }
        }
    }
}

/// Linear solve of `problem` by sparse Cholesky, checked by its residual and by an LU
/// solve of the same system; returns the LU answer as the reference.
pub fn linear_row(row: &mut Row, problem: &Problem, probes: &[Point]) -> Option<Answer> {
    let disc = problem.discretise();
    row.dofs = disc.dofs.n_free;
    let system = problem.assemble(&disc);
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    let residual = |x: &[f64]| {
        let mut r = vec![0.0; x.len()];
        disc.pattern.multiply(&system.values, x, &mut r);
        let r: Vec<f64> = r.iter().zip(&system.rhs).map(|(a, b)| a - b).collect();
        norm(&r) / norm(&system.rhs)
    };
    row.cond = condition_1(&disc.pattern, &system.values);
    let lu = SparseLu::analyse(&disc.pattern)
        .and_then(|lu| lu.factor(&disc.pattern, &system.values).map(|f| f.solve(&system.rhs)));
    let reference = match &lu {
        Ok(x) => {
            row.note = format!("LU residual {:.1e}", residual(x));
            Some(answer_of(problem, problem.displacement(&disc, x), 1.0, probes))
        }
        Err(e) => {
            row.note = format!("LU failed: {e}");
            None
        }
    };
    match Cholesky::analyse(&disc.pattern).and_then(|c| c.solve(&disc.pattern, &system.values, &system.rhs)) {
        Ok(x) => {
            row.status = Status::Converged;
            row.iterations = None;
            row.rel_residual = Some(residual(&x));
            row.solution = Some(answer_of(problem, problem.displacement(&disc, &x), 1.0, probes));
        }
        Err(e) => {
            row.status = Status::Failed;
            row.reason = format!("Cholesky: {e}");
            row.reason_short = row.reason.clone();
        }
    }
    reference
}

/// Runs `body` on a fresh row, timing it; a panic or an error becomes the row's reason.
pub fn run_row(group: &str, case: String, order: usize, body: impl FnOnce(&mut Row) -> Result<(), BoxError>) -> Row {
    let mut row = Row::new(group, case, order);
    let start = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut row)));
    row.seconds = start.elapsed().as_secs_f64();
    match outcome {
        Ok(Ok(())) => {}
        Ok(Err(e)) => {
            row.status = Status::Failed;
            row.reason = e.to_string();
            row.reason_short = row.reason.clone();
        }
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            row.status = Status::Panicked;
            row.reason = format!("panic: {message}");
            row.reason_short = row.reason.clone();
        }
    }
    eprintln!("  {:<10} {:<44} {:<9} {:>6.2} s", row.group, row.case, row.status.name(), row.seconds);
    row
}

/// The answer of a combination: the solution of its last row.
pub fn answer(rows: &[Row]) -> Option<Answer> {
    rows.last().and_then(|r| r.solution.clone())
}

fn sci(v: Option<f64>) -> String {
    v.map_or("n/a".into(), |v| format!("{v:.2e}"))
}

/// The columns of both tables, as text.
pub fn cells(row: &Row) -> Vec<String> {
    let s = row.solution.as_ref();
    let tol = row.tolerance.map_or("—".into(), |t| match t.length {
        Some(l) => format!("{:.0e}; {l:.1e} m", t.u),
        None => format!("{:.0e}", t.u),
    });
    let matches = if row.is_reference {
        "ref".to_string()
    } else {
        row.matches.map_or("n/a".into(), |m| if m { "yes".into() } else { "NO".into() })
    };
    let finite = row.finite().map_or("n/a".into(), |f| if f { "yes".into() } else { "NO".into() });
    vec![
        row.group.clone(),
        row.case.clone(),
        row.dofs.to_string(),
        row.iterations.map_or(if row.group == "contrast" { "direct".into() } else { "n/a".into() }, |n| n.to_string()),
        sci(row.rel_residual),
        row.status.name().into(),
        sci(row.cond),
        sci(s.map(|s| s.max_u)),
        s.and_then(|s| s.contact_length).map_or("—".into(), |l| format!("{l:.3}")),
        sci(row.du),
        row.dl.map_or("—".into(), |d| format!("{d:.2e}")),
        tol,
        matches,
        finite,
        format!("{:.2}", row.seconds),
    ]
}

pub const HEADER: [&str; 17] = [
    "group",
    "case",
    "free dofs",
    "Newton steps",
    "final rel. residual",
    "status",
    "cond₁ est.",
    "max |u| [m]",
    "contact length [m]",
    "Δu (rel.)",
    "ΔL_c [m]",
    "tol (u; L_c)",
    "matches ref",
    "finite",
    "time [s]",
    "reason",
    "note",
];

/// The CSV table (full reasons).
pub fn csv(rows: &[Row]) -> String {
    let quote = |s: &str| {
        if s.contains([',', '"', '\n']) {
            format!("\"{}\"", s.replace('"', "\"\""))
        } else {
            s.to_string()
        }
    };
    let mut out = HEADER.iter().map(|h| quote(h)).collect::<Vec<_>>().join(",") + "\n";
    for row in rows {
        let mut c = cells(row);
        c.push(row.reason.clone());
        c.push(row.note.clone());
        out.push_str(&(c.iter().map(|s| quote(s)).collect::<Vec<_>>().join(",") + "\n"));
    }
    out
}

/// "N combinations: …": the key number.
pub fn summary(rows: &[Row]) -> String {
    let count = |s: Status| rows.iter().filter(|r| r.status == s).count();
    let mismatched = rows.iter().filter(|r| r.matches == Some(false)).count();
    let nonfinite = rows.iter().filter(|r| r.finite() == Some(false)).count();
    let retries = rows.iter().filter(|r| r.is_retry).count();
    // the last row of each combination (the first row or its last retry)
    let last = (0..rows.len()).filter(|&i| rows.get(i + 1).is_none_or(|next| !next.is_retry));
    let unsolved = last.filter(|&i| !matches!(rows[i].status, Status::Converged | Status::Stagnated)).count();
    format!(
        "{} combinations ({} rows with {retries} retries): {} rows converged, {} stagnated at round-off, \
         {} stopped with a solver error, {} panicked; {unsolved} combinations without an answer after the \
         retries; {} rows outside their reference tolerance; {} rows with NaN/inf.",
        rows.len() - retries,
        rows.len(),
        count(Status::Converged),
        count(Status::Stagnated),
        count(Status::Failed),
        count(Status::Panicked),
        mismatched,
        nonfinite
    )
}

/// Whether the sweep itself failed: a panic, a NaN/inf, or a stop without a reason.
pub fn broken(rows: &[Row]) -> Vec<String> {
    rows.iter()
        .filter(|r| {
            r.status == Status::Panicked
                || r.finite() == Some(false)
                || (!matches!(r.status, Status::Converged) && r.reason.trim().is_empty())
        })
        .map(|r| format!("{} / {}: {} {}", r.group, r.case, r.status.name(), r.reason))
        .collect()
}

/// The rows of the markdown table: header, rule and one line per row.
pub fn markdown_rows(rows: &[Row]) -> String {
    let escape = |s: &str| s.replace('|', "\\|").replace('\n', " ");
    let mut out = format!("| {} |\n|{}\n", HEADER.join(" | "), "---|".repeat(HEADER.len()));
    for row in rows {
        let mut c = cells(row);
        c.push(escape(&row.reason_short));
        c.push(escape(&row.note));
        out.push_str(&format!("| {} |\n", c.join(" | ")));
    }
    out
}

/// Writes `markdown` to `path` and the CSV table of `rows` next to it (extension `.csv`),
/// each atomically; returns the CSV's path.
pub fn write_tables(markdown: &str, rows: &[Row], path: &Path) -> Result<PathBuf, BoxError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let csv_path = path.with_extension("csv");
    write_output(path, markdown.as_bytes())?;
    write_output(&csv_path, csv(rows).as_bytes())?;
    Ok(csv_path)
}
