//! The history of an adaptive run as CSV, and its figures.

use super::StepRecord;
use crate::io::atomic::OutputError;
use crate::io::plot::{write_figure, Figure, Panel, Series};
use std::path::{Path, PathBuf};

/// Columns of [`to_csv`].
const HEADER: &str = "step,cells,unknowns,eta_osc,eta_flux,eta_Neu,eta_disc,eta_reg,eta_lin,eta_tot,stress_norm,\
delta,n_reg,n_lin,n_est,n_finish,equilibration,i_eff,crack_length,normal_force,tangential_force,resultant_position,eccentricity,\
t_mesh,t_transfer,t_assemble,t_solve,t_estimate,t_remesh,elapsed";

/// One line per step; δ is empty without contact, n_finish (the Newton steps that finished
/// the last mesh's run after (S_lin) stopped it, 0 where it ran to the residual tolerance from
/// the start) on the other steps, I_eff when it was not computed, the joint's numbers
/// without a straight joint with a heel (docs/method.md §1.9).
pub fn to_csv(history: &[StepRecord]) -> String {
    let mut csv = format!("{HEADER}\n");
    for r in history {
        let (e, t) = (&r.eta, &r.seconds);
        let number = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
        let delta = number(r.delta);
        let n_finish = r.finish.map_or(String::new(), |f| f.n_lin.to_string());
        let i_eff = r.i_eff.map_or(String::new(), |i| format!("{i:.4}"));
        let joint = [
            r.crack_length,
            r.resultant.map(|f| f.normal_force),
            r.resultant.map(|f| f.tangential_force),
            r.resultant.map(|f| f.position),
            r.resultant.map(|f| f.eccentricity),
        ]
        .map(number)
        .join(",");
        csv += &format!(
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{delta},{},{},{},{n_finish},{:.1e},{i_eff},{joint},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}\n",
            r.step,
            r.cells,
            r.unknowns,
            e.osc,
            e.flux,
            e.neu,
            e.disc,
            e.reg,
            e.lin,
            e.tot,
            r.stress_norm,
            r.n_reg,
            r.n_lin,
            r.n_est,
            r.equilibration,
            t.mesh,
            t.transfer,
            t.assemble,
            t.solve,
            t.estimate,
            t.remesh,
            r.elapsed
        );
    }
    csv
}

/// η_tot and its discretisation components against the number of unknowns, and below, on
/// their own axis, η_reg and η_lin, which the solver drives down by orders of magnitude more;
/// a component that is zero throughout has no curve and no legend entry, but keeps its
/// colour slot.
pub fn components_figure(title: &str, history: &[StepRecord]) -> Figure {
    let component = |name: &str, value: fn(&StepRecord) -> f64| Series {
        label: name.into(),
        points: history.iter().map(|r| (r.unknowns as f64, value(r))).collect(),
        dashed: name != "η_tot",
    };
    let discretisation = [
        component("η_tot", |r| r.eta.tot),
        component("η_osc", |r| r.eta.osc),
        component("η_flux", |r| r.eta.flux),
        component("η_Neu", |r| r.eta.neu),
        component("η_disc", |r| r.eta.disc),
    ];
    let solver = [component("η_reg", |r| r.eta.reg), component("η_lin", |r| r.eta.lin)];
    Figure {
        title: title.into(),
        x_label: "unknowns".into(),
        y_label: format!("estimator [{ESTIMATOR_UNIT}]"),
        series: discretisation.into(),
        lower: Some(Panel { y_label: format!("η_reg, η_lin [{ESTIMATOR_UNIT}]"), series: solver.into() }),
        ..Default::default()
    }
}

/// The unit of the estimators: L² norms of stresses over the section.
const ESTIMATOR_UNIT: &str = "Pa m";

/// η_tot of several runs against `x` (unknowns or wall time).
pub fn comparison_figure(
    title: &str,
    x_label: &str,
    runs: &[(&str, &[StepRecord])],
    x: fn(&StepRecord) -> f64,
) -> Figure {
    Figure {
        title: title.into(),
        x_label: x_label.into(),
        y_label: format!("η_tot [{ESTIMATOR_UNIT}]"),
        series: runs
            .iter()
            .map(|(label, h)| Series {
                label: label.to_string(),
                points: h.iter().map(|r| (x(r), r.eta.tot)).collect(),
                dashed: false,
            })
            .collect(),
        ..Default::default()
    }
}

/// Writes `<name>_eta.{svg,png}` (components against unknowns) and `<name>_time.{svg,png}`
/// (η_tot against wall time), both titled `title`; returns the files.
pub fn write_plots(dir: &Path, name: &str, title: &str, history: &[StepRecord]) -> Result<Vec<PathBuf>, OutputError> {
    let mut files = write_figure(&dir.join(format!("{name}_eta")), &components_figure(title, history))?;
    let time = comparison_figure(title, "wall time [s]", &[("η_tot", history)], |r| r.elapsed);
    files.extend(write_figure(&dir.join(format!("{name}_time")), &time)?);
    Ok(files)
}

/// η_tot against the unknowns of an adaptive and a uniform run, each labelled with its fitted
/// slope ([`eta_rate`]) when it has one.
pub fn adaptive_uniform_figure(title: &str, adaptive: &[StepRecord], uniform: &[StepRecord]) -> Figure {
    let label = |name: &str, history: &[StepRecord]| match eta_rate(history) {
        slope if slope.is_finite() => format!("{name}, slope {slope:.2}"),
        _ => name.to_string(),
    };
    let (a, u) = (label("adaptive", adaptive), label("uniform", uniform));
    comparison_figure(title, "unknowns", &[(&a, adaptive), (&u, uniform)], |r| r.unknowns as f64)
}

/// Writes `<name>_adaptive_uniform.{svg,png}` ([`adaptive_uniform_figure`]); returns the files.
pub fn write_adaptive_uniform(
    dir: &Path,
    name: &str,
    adaptive: &[StepRecord],
    uniform: &[StepRecord],
) -> Result<Vec<PathBuf>, OutputError> {
    let figure = adaptive_uniform_figure(&format!("{name}: adaptive against uniform"), adaptive, uniform);
    write_figure(&dir.join(format!("{name}_adaptive_uniform")), &figure)
}

/// Steps over which [`eta_rate`] fits.
pub const RATE_STEPS: usize = 4;

/// The rate of η_tot ~ N^rate against the unknowns N, fitted over the last [`RATE_STEPS`]
/// steps (−p/2 is optimal in 2D); NaN with fewer than two distinct N.
pub fn eta_rate(history: &[StepRecord]) -> f64 {
    let tail = &history[history.len().saturating_sub(RATE_STEPS)..];
    loglog_slope(&tail.iter().map(|r| (r.unknowns as f64, r.eta.tot)).collect::<Vec<_>>())
}

/// Least-squares slope of log y against log x: the rate of y ~ x^slope.
pub fn loglog_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = logs.iter().fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let sxy: f64 = logs.iter().map(|&(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = logs.iter().map(|&(x, _)| (x - mx).powi(2)).sum();
    sxy / sxx
}
