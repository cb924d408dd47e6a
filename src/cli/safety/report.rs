//! `safety.json`, `report.md`, `joint.csv` and the figure of the joint's stresses of one
//! combination, and the table of all combinations: what `damfem safety` writes of the analyses
//! of `super`.

use super::{Combination, Outcome, STALLED};
use crate::cli::adapt::BestStep;
use crate::cli::output::Units;
use crate::contact::{BondLengths, ContactSolution, CrackRule, JointLine};
use crate::geometry::Point;
use crate::io::atomic::write_output;
use crate::io::plot::{Figure, Mark, Series};
use crate::safety::base::BaseStresses;
use crate::safety::check::{Check, Verdict};
use crate::safety::classical::Classical;
use crate::safety::criteria::Requirements;
use crate::safety::resultant::Resultant;
use crate::safety::strength::StrengthReduction;
use anyhow::Result;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One step of the adaptive run as the report shows it.
#[derive(Serialize, Clone, Copy)]
pub(super) struct StepRow {
    pub(super) step: usize,
    pub(super) unknowns: usize,
    /// η_tot / ‖σ_h‖.
    pub(super) eta_relative: f64,
    pub(super) crack_length: f64,
    pub(super) resultant_position: Option<f64>,
    pub(super) sliding_safety_factor: Option<f64>,
}

/// What `safety.json` records.
#[derive(Serialize)]
pub(super) struct Report {
    pub(super) units: Units,
    pub(super) scene: PathBuf,
    pub(super) order: usize,
    /// The adaptive run: its tolerance on η_tot / ‖σ_h‖, whether the last mesh met it, and
    /// every step.
    pub(super) tol_relative: f64,
    pub(super) tolerance_met: bool,
    pub(super) steps: Vec<StepRow>,
    pub(super) unknowns: usize,
    /// η_tot of the last mesh \[Pa m\] and η_tot / ‖σ_h‖.
    pub(super) eta_tot: f64,
    pub(super) eta_relative: f64,
    /// The earlier step of smallest η_tot, when the last mesh's η_tot is larger (null
    /// otherwise); the numbers below are the last mesh's.
    pub(super) best_step: Option<BestStep>,
    /// Whether the last mesh's Newton run stalled before the residual tolerance: its numbers
    /// are then those of the iterate where (S_lin) stopped Newton (docs/method.md §5.3).
    pub(super) newton_stalled: bool,
    pub(super) joint_line: JointLine,
    pub(super) contact_length: f64,
    pub(super) crack_length: f64,
    /// What the water does in the crack of the sliding plane (None without uplift there).
    pub(super) crack_rule: Option<CrackRule>,
    /// On a bonded sliding plane, its bonded, process-zone and broken lengths.
    pub(super) bond_lengths: Option<BondLengths>,
    /// N, T, U, the resultant's point, position, eccentricity and the middle-third check; None
    /// when nothing presses on the joint.
    pub(super) resultant: Option<Resultant>,
    pub(super) base_stresses: BaseStresses,
    /// FS_LE and FS_SR's bracket \[held, failed\], or why they are not computed.
    pub(super) sliding_safety_factor: Option<f64>,
    pub(super) strength_reduction: Option<StrengthReduction>,
    pub(super) safety_factor_note: Option<String>,
    /// Where the crack of the sliding plane stopped at the drain line, what of it.
    pub(super) crack_note: Option<String>,
    /// The combination's category and what it requires.
    pub(super) requirements: Requirements,
    /// The classical gravity method on the same loads, or why it has no answer.
    pub(super) classical: Option<Classical>,
    pub(super) classical_note: Option<String>,
    /// The code check, line by line, and its verdict by each method.
    pub(super) checks: Vec<Check>,
    pub(super) verdict: Verdict,
}

/// The results as (quantity, value, unit) rows.
pub(super) fn table(r: &Report) -> Vec<[String; 3]> {
    let row = |name: &str, value: String, unit: &str| [name.to_string(), value, unit.to_string()];
    let force = |v: f64| format!("{v:.4e}");
    let mut rows = vec![
        row("mesh: unknowns, eta_tot / ||sigma_h||", format!("{}, {:.2e}", r.unknowns, r.eta_relative), ""),
        row("eta_tot of the last mesh", format!("{:.4e}", r.eta_tot), "Pa m"),
        row("joint length L", format!("{:.4}", r.joint_line.length), "m"),
        row("contact length", format!("{:.4}", r.contact_length), "m"),
        row("crack length from the heel", format!("{:.4}", r.crack_length), "m"),
    ];
    rows.extend(r.crack_rule.map(|rule| row("uplift in the crack", rule_words(rule), "")));
    rows.extend(r.bond_lengths.iter().flat_map(|l| {
        [("bonded", l.bonded), ("in the process zone (softening)", l.process_zone), ("broken", l.broken)]
            .map(|(state, length)| row(&format!("bond: length {state}"), format!("{length:.4}"), "m"))
    }));
    match &r.resultant {
        Some(f) => rows.extend([
            row("normal force N", force(f.normal_force), "N/m"),
            row("tangential force T", force(f.tangential_force), "N/m"),
            row("uplift force U", force(f.uplift_force), "N/m"),
            row("resultant from the heel s_R", format!("{:.4}", f.position), "m"),
            row("eccentricity e = s_R - L/2", format!("{:.4}", f.eccentricity), "m"),
            row("middle third |e| <= L/6", (if f.middle_third { "yes" } else { "no" }).into(), ""),
        ]),
        None => rows.push(row("resultant", "nothing presses on the joint".into(), "")),
    }
    let b = &r.base_stresses;
    let mpa = |v: f64| format!("{:.4}", v / 1e6);
    rows.push(row(&format!("heel normal stress (mean over {:.3} m)", b.length), mpa(b.heel), "MPa"));
    rows.push(row(&format!("toe normal stress (mean over {:.3} m)", b.length), mpa(b.toe), "MPa"));
    let none = || "not computed".to_string();
    rows.push(row("FS_LE", r.sliding_safety_factor.map_or_else(none, |f| format!("{f:.4}")), ""));
    rows.push(row("FS_SR", r.strength_reduction.as_ref().map_or_else(none, bracket), ""));
    rows
}

/// The crack rule in words.
pub(super) fn rule_words(rule: CrackRule) -> String {
    match rule {
        CrackRule::Filled => "full: the reservoir's pressure fills it".into(),
        CrackRule::Kept { prior } => format!("kept: the diagram of the {prior:.4} m crack before the earthquake"),
        CrackRule::Drained { prior } => format!("none: dry beyond the {prior:.4} m crack before the earthquake"),
    }
}

/// FS_SR's bracket \[held, failed\], or "> held" if the joint never failed.
pub(super) fn bracket(s: &StrengthReduction) -> String {
    match s.failed.is_finite() {
        true => format!("[{:.4}, {:.4}]", s.held, s.failed),
        false => format!("> {:.0}", s.held),
    }
}

/// The rows as aligned columns.
pub(super) fn text_table(rows: &[[String; 3]]) -> String {
    let width = |k: usize| rows.iter().map(|r| r[k].chars().count()).max().unwrap_or(0);
    let (w0, w1) = (width(0), width(1));
    rows.iter()
        .map(|[a, b, c]| format!("{a:<w0$}  {b:>w1$}  {c}").trim_end().to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

/// `safety.json` and `report.md` of one analysis in `dir`.
pub(super) fn write_files(dir: &Path, report: &Report, table: &[[String; 3]]) -> Result<()> {
    write_output(&dir.join("safety.json"), serde_json::to_string_pretty(report)?.as_bytes())?;
    write_output(&dir.join("report.md"), markdown(report, table).as_bytes())?;
    Ok(())
}

/// The header and one row per combination: the headline numbers of each report.
pub(super) fn combination_rows(reports: &[Combination]) -> Vec<Vec<String>> {
    let header = [
        "combination",
        "outcome",
        "crack [m]",
        "N [N/m]",
        "T [N/m]",
        "U [N/m]",
        "s_R [m]",
        "e [m]",
        "middle third",
        "heel [MPa]",
        "toe [MPa]",
        "FS_LE",
        "FS_SR",
        "eta_tot/||sigma_h||",
    ];
    let mut rows = vec![header.map(String::from).to_vec()];
    let optional = |v: Option<f64>, format: fn(f64) -> String| v.map_or("-".to_string(), format);
    for Combination { name, outcome } in reports {
        let Some(r) = outcome.report() else {
            let mut row = vec![name.clone(), outcome.label()];
            row.resize(header.len(), "-".to_string());
            rows.push(row);
            continue;
        };
        let f = r.resultant;
        rows.push(vec![
            name.clone(),
            outcome.label(),
            format!("{:.4}", r.crack_length),
            optional(f.map(|f| f.normal_force), |v| format!("{v:.4e}")),
            optional(f.map(|f| f.tangential_force), |v| format!("{v:.4e}")),
            optional(f.map(|f| f.uplift_force), |v| format!("{v:.4e}")),
            optional(f.map(|f| f.position), |v| format!("{v:.4}")),
            optional(f.map(|f| f.eccentricity), |v| format!("{v:.4}")),
            f.map_or("-", |f| if f.middle_third { "yes" } else { "no" }).to_string(),
            format!("{:.4}", r.base_stresses.heel / 1e6),
            format!("{:.4}", r.base_stresses.toe / 1e6),
            optional(r.sliding_safety_factor, |v| format!("{v:.4}")),
            r.strength_reduction.as_ref().map_or("-".to_string(), bracket),
            format!("{:.2e}", r.eta_relative),
        ]);
    }
    rows
}

/// The rows as columns aligned on the right (the first on the left).
pub(super) fn text_columns(rows: &[Vec<String>]) -> String {
    let widths: Vec<usize> =
        (0..rows[0].len()).map(|k| rows.iter().map(|r| r[k].chars().count()).max().unwrap_or(0)).collect();
    let line = |row: &Vec<String>| {
        let cells = row.iter().zip(&widths).enumerate().map(|(k, (cell, &w))| match k {
            0 => format!("{cell:<w$}"),
            _ => format!("{cell:>w$}"),
        });
        cells.collect::<Vec<_>>().join("  ")
    };
    rows.iter().map(line).collect::<Vec<_>>().join("\n")
}

/// `report.md` of a scene with combinations: one row per combination, linked to its report,
/// and a line for each combination whose last mesh has not the smallest η_tot of its run.
pub(super) fn combinations_markdown(scene: &Path, rows: &[Vec<String>], reports: &[Combination]) -> String {
    let mut md = format!("# Dam safety: {}, load combinations\n\n", scene.display());
    md += "Stresses are positive in tension. Each combination's report, joint stresses and figure are in \
           its own directory.\n\n";
    let cells = |row: &[String]| row.iter().map(|c| c.replace('|', "\\|")).collect::<Vec<_>>().join(" | ");
    md += &format!("| {} |\n|{}\n", cells(&rows[0]), "---|".repeat(rows[0].len()));
    for (row, c) in rows[1..].iter().zip(reports) {
        let name = match c.outcome {
            Outcome::Solved(_) => format!("[{}]({}/report.md)", row[0], row[0]),
            _ => row[0].clone(),
        };
        md += &format!("| {name} | {} |\n", cells(&row[1..]));
    }
    md += &code_check_summary(reports);
    for Combination { name, outcome } in reports {
        match outcome {
            Outcome::DoesNotHold { verdict, .. } => md += &format!("\n{name}: the dam does not hold. {verdict}.\n"),
            Outcome::SolverFailed { error } => md += &format!("\n{name}: no result, the solver failed. {error}.\n"),
            Outcome::Solved(_) => {}
        }
        if let Some((b, r)) = outcome.report().and_then(|r| r.best_step.as_ref().map(|b| (b, r))) {
            md += &format!(
                "\n{name}: step {} has a smaller η_tot than the last mesh, {:.3e} against {:.3e} Pa m (its report).\n",
                b.step, b.eta_tot, r.eta_tot
            );
        }
    }
    md
}

/// The sentence of `report.md` on the step `b` whose η_tot is below the last mesh's.
pub(super) fn best_sentence(b: &BestStep, r: &Report) -> String {
    let file = b.file.file_name().map_or(b.file.display().to_string(), |f| f.to_string_lossy().into_owned());
    format!(
        "\nStep {} has the smallest η_tot of the run, {:.3e} Pa m with {} unknowns, against {:.3e} Pa m with {} \
         unknowns on the last mesh, whose numbers this report gives; its crack, s_R and FS_LE are in its row \
         above, and its fields in `{file}`.\n",
        b.step, b.eta_tot, b.unknowns, r.eta_tot, r.unknowns
    )
}

/// One contact face along the joint: its midpoint x, its distance s from the heel, and the
/// face means of σ'^n = −p_c, σ^n = σ'^n − p_u, σ^t and p_u \[Pa\], and its status.
pub(super) struct JointRow {
    pub(super) x: Point,
    pub(super) s: f64,
    pub(super) effective: f64,
    pub(super) total: f64,
    pub(super) tangential: f64,
    pub(super) uplift: f64,
    pub(super) status: f64,
}

/// The faces of the joint sorted from the heel.
pub(super) fn joint_rows(c: &ContactSolution, line: &JointLine) -> Vec<JointRow> {
    let mut rows: Vec<JointRow> = c
        .faces
        .iter()
        .enumerate()
        .filter(|&(k, _)| c.on_line(k, line))
        .map(|(k, f)| {
            let x = c.nitsche.position(k, 0.5);
            JointRow {
                x,
                s: line.distance(x),
                // + 0.0: no −0 where the joint is open
                effective: -f.pressure + 0.0,
                total: -f.pressure - f.uplift,
                tangential: f.tangential_traction,
                uplift: f.uplift,
                status: f.status(),
            }
        })
        .collect();
    rows.sort_by(|a, b| a.s.total_cmp(&b.s));
    rows
}

pub(super) fn joint_csv(rows: &[JointRow]) -> String {
    let mut csv =
        String::from("x,y,s,effective_normal_stress,normal_stress,tangential_stress,uplift_pressure,status\n");
    for r in rows {
        csv += &format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}\n",
            r.x[0], r.x[1], r.s, r.effective, r.total, r.tangential, r.uplift, r.status
        );
    }
    csv
}

/// The distance from the heel of the drain line of a diagram on the `plane`'s curves.
pub(super) fn plane_drains(solution: &ContactSolution, plane: &[bool]) -> Option<f64> {
    let uplift = solution.nitsche.uplift.iter().find(|up| up.curves.iter().any(|&c| plane[c]))?;
    uplift.diagram.drains.map(|d| d.distance)
}

/// σ'^n, σ^n, σ^t and −p_u \[MPa\] against the distance from the heel \[m\], with the
/// drain line at `drains` and the crack tip marked. Further lines (beam theory) are series,
/// allowable stresses horizontal marks.
pub(super) fn base_figure(rows: &[JointRow], report: &Report, drains: Option<f64>) -> Figure {
    let series = |label: &str, value: fn(&JointRow) -> f64, dashed: bool| Series {
        label: label.into(),
        points: rows.iter().map(|r| (r.s, value(r) / 1e6)).collect(),
        dashed,
    };
    let mut all = vec![series("effective normal stress σ'ⁿ = −p_c", |r| r.effective, false)];
    if report.resultant.is_some_and(|f| f.uplift_force > 0.0) {
        all.push(series("total normal stress σⁿ = σ'ⁿ − p_u", |r| r.total, false));
        all.push(series("uplift −p_u", |r| -r.uplift, true));
    }
    if report.sliding_safety_factor.is_some() {
        all.push(series("tangential stress σᵗ", |r| r.tangential, false));
    }
    if let Some(c) = &report.classical {
        all.push(beam_theory(c));
    }
    let mut marks: Vec<Mark> = drains.map(|s| Mark::vertical(format!("drains, s = {s:.2} m"), s)).into_iter().collect();
    if report.crack_length > 0.0 {
        marks.push(Mark::vertical(format!("crack tip, s = {:.2} m", report.crack_length), report.crack_length));
    }
    if let Some(allowable) = report.requirements.allowable_compression {
        marks.push(Mark::horizontal(format!("allowable compression {:.1} MPa", allowable / 1e6), -allowable / 1e6));
    }
    Figure {
        title: "stresses along the joint (tension positive)".into(),
        x_label: "distance from the heel s [m]".into(),
        y_label: "stress [MPa]".into(),
        series: all,
        marks,
        lower: None,
    }
}

/// σ'ⁿ of the classical method along the joint: 0 over its crack T, then linear from the
/// crack tip (the heel without a crack) to the toe, from its heel to its toe stress [MPa].
pub(super) fn beam_theory(c: &Classical) -> Series {
    let mut points = vec![(0.0, 0.0), (c.crack, c.heel_stress / 1e6), (c.length, c.toe_stress / 1e6)];
    if c.crack == 0.0 {
        points.remove(0);
    }
    Series { label: "σ'ⁿ by beam theory (classical method)".into(), points, dashed: true }
}

/// `report.md`: the results table, the convergence of the adaptive run, the figure.
pub(super) fn markdown(r: &Report, table: &[[String; 3]]) -> String {
    let mut md = format!("# Dam safety: {}\n\n", r.scene.display());
    md += &format!(
        "P{} elements, refined adaptively until η_tot ≤ {} ‖σ_h‖ (adaptive steps: {}{}). Stresses are \
         positive in tension; the heel and toe stresses are means of σ'ⁿ = −p_c over {:.3} m of the joint. \
         η_tot bounds the error of the last mesh in the dual norm of the residual (docs/method.md §2), not \
         the error of the numbers below, which carry no error bar (their changes along the adaptive run \
         are in its table); FS_SR's bracket is that of its search on the last mesh.\n\n",
        r.order,
        r.tol_relative,
        r.steps.len(),
        if r.tolerance_met { "" } else { "; the tolerance was NOT met" },
        r.base_stresses.length
    );
    md += "| quantity | value | unit |\n|---|---|---|\n";
    let cell = |text: &str| text.replace('|', "\\|");
    for [a, b, c] in table {
        md += &format!("| {} | {} | {} |\n", cell(a), cell(b), c);
    }
    if let Some(note) = &r.safety_factor_note {
        md += &format!("\n{note}.\n");
    }
    if r.newton_stalled {
        md += &format!("\nO{}.\n", &STALLED[1..]);
    }
    if let Some(note) = &r.crack_note {
        md += &format!("\nT{}.\n", &note[1..]);
    }
    md += "\n## Adaptive run\n\n| step | unknowns | η_tot / ‖σ_h‖ | crack [m] | s_R [m] | FS_LE |\n|---|---|---|---|---|---|\n";
    let optional = |v: Option<f64>| v.map_or("–".to_string(), |v| format!("{v:.4}"));
    for s in &r.steps {
        md += &format!(
            "| {} | {} | {:.2e} | {:.4} | {} | {} |\n",
            s.step,
            s.unknowns,
            s.eta_relative,
            s.crack_length,
            optional(s.resultant_position),
            optional(s.sliding_safety_factor)
        );
    }
    md += &r.best_step.as_ref().map_or(String::new(), |b| best_sentence(b, r));
    md += &code_check_markdown(r);
    md += "\n## Stresses along the joint\n\n![stresses along the joint](base_stresses.png)\n\n\
           The values per contact face are in `joint.csv`.\n";
    md
}

/// Why the two answers differ, in one sentence.
pub(super) const DIFFER: &str =
    "The classical method takes the section rigid on a plane base, so its base pressure is \
     linear and its crack is where that line would be tensile; the finite elements take the dam and its foundation \
     elastic, so the pressure gathers at the heel and the toe, and their crack is the open part of the elastic \
     joint (docs/method.md §1.8).";

/// A category in a word.
pub(super) fn category_name(r: &Requirements) -> String {
    format!("{:?}", r.category).to_lowercase()
}

/// A value of a check in its report unit (MPa for a stress).
pub(super) fn check_value(v: Option<f64>, unit: &str) -> String {
    match (v, unit) {
        (None, _) => "–".into(),
        (Some(v), "Pa") => format!("{:.4}", v / 1e6),
        (Some(v), _) => format!("{v:.4}"),
    }
}

pub(super) fn pass_word(p: Option<bool>) -> &'static str {
    match p {
        Some(true) => "pass",
        Some(false) => "FAIL",
        None => "–",
    }
}

/// A method's verdict in words.
pub(super) fn verdict_word(v: Option<bool>) -> &'static str {
    match v {
        Some(true) => "meets the criteria",
        Some(false) => "fails",
        None => "no answer",
    }
}

/// The classical method's loads table.
pub(super) fn loads_markdown(c: &Classical) -> String {
    let mut md = String::from(
        "V presses on the base, H pushes towards the toe; d_V is the arm of V upstream of the toe, h_H that of H \
         above the base, and M = V d_V − H h_H the moment about the toe, resisting positive.\n\n\
         | load | V [N/m] | d_V [m] | H [N/m] | h_H [m] | M [N m/m] |\n|---|---|---|---|---|---|\n",
    );
    for l in &c.loads {
        md += &format!(
            "| {} | {:.4e} | {:.4} | {:.4e} | {:.4} | {:.4e} |\n",
            l.kind.label(),
            l.normal,
            l.normal_arm,
            l.shear,
            l.shear_arm,
            l.moment
        );
    }
    let total = |f: fn(&crate::safety::classical::Load) -> f64| c.loads.iter().map(f).sum::<f64>();
    md += &format!(
        "| total | {:.4e} | | {:.4e} | | {:.4e} |\n",
        total(|l| l.normal),
        total(|l| l.shear),
        total(|l| l.moment)
    );
    md
}

/// The code check of `report.md`: the requirements, the classical loads, each line with both
/// methods, the verdict.
pub(super) fn code_check_markdown(r: &Report) -> String {
    let req = &r.requirements;
    let mut md = format!(
        "\n## Code check ({} combination)\n\nThe requirements are those of the scene's [criteria] for its category \
         (defaults: US Army Corps of Engineers, EM 1110-2-2200 Table 4-1 and EM 1110-2-2100 Table 3-4; \
         docs/method.md §1.12). Stresses in MPa, tension positive; the finite-element ones are means of σ'ⁿ over \
         {:.3} m at the heel, from the end of its closed part (the crack tip) and at the toe, the classical ones beam theory on the same loads (0 in a crack).\n\n",
        category_name(req),
        r.base_stresses.length
    );
    if let Some(c) = &r.classical {
        md += &format!(
            "### Loads on the section (classical method{})\n\n",
            if c.crack > 0.0 { ", the uplift with the classical crack" } else { "" }
        );
        md += &loads_markdown(c);
        if c.toe_in_tension {
            md += "\nThe toe is in tension by beam theory: the classical method cracks the heel only, so its \
                   stresses are those of the uncracked base.\n";
        }
        md += "\n";
    }
    if let Some(note) = &r.classical_note {
        md += &format!("T{}.\n\n", &note[1..]);
    }
    md += "| quantity | unit | finite elements | classical | required | finite elements | classical |\n\
           |---|---|---|---|---|---|---|\n";
    for c in &r.checks {
        let unit = if c.unit == "Pa" { "MPa" } else { c.unit };
        md += &format!(
            "| {} | {unit} | {} | {} | {} | {} | {} |\n",
            c.quantity,
            check_value(c.finite_elements, c.unit),
            check_value(c.classical, c.unit),
            c.requirement.as_deref().unwrap_or("–"),
            pass_word(c.finite_elements_pass),
            pass_word(c.classical_pass)
        );
    }
    let v = &r.verdict;
    md += &format!(
        "\nVerdict: by the finite elements the combination {}, by the classical method it {}{}.\n\n{DIFFER}\n",
        verdict_word(v.finite_elements),
        verdict_word(v.classical),
        if v.failed.is_empty() { String::new() } else { format!(" (failing: {})", v.failed.join(", ")) }
    );
    md
}

/// The summary table of the code check of every combination.
pub(super) fn code_check_summary(reports: &[Combination]) -> String {
    let mut md = String::from(
        "\n## Code check of all combinations\n\n| combination | category | FS_LE | FS classical | required FS | \
         FS_OT classical | FS_F classical | s_R [m] | s_R classical [m] | resultant | crack classical [% of L] | \
         finite elements | classical |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let value = |v: Option<f64>| check_value(v, "");
    for Combination { name, outcome } in reports {
        let Some(r) = outcome.report() else {
            md += &format!("| {name} | | | | | | | | | | | {} | |\n", outcome.label());
            continue;
        };
        let c = r.classical.as_ref();
        md += &format!(
            "| {name} | {} | {} | {} | {:.3} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            category_name(&r.requirements),
            value(r.sliding_safety_factor),
            value(c.and_then(|c| c.sliding_factor)),
            r.requirements.sliding,
            value(c.and_then(|c| c.overturning_factor)),
            value(c.and_then(|c| c.flotation_factor)),
            value(r.resultant.map(|f| f.position)),
            value(c.map(|c| c.resultant_position)),
            r.requirements.resultant.label(),
            value(c.map(|c| 100.0 * c.crack / c.length)),
            verdict_word(r.verdict.finite_elements),
            verdict_word(r.verdict.classical)
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::super::{outside_note, Combination, Outcome};
    use super::{
        combination_rows, combinations_markdown, markdown, table, BaseStresses, BestStep, Report, StepRow,
        StrengthReduction,
    };
    use crate::cli::output::UNITS;
    use crate::contact::JointLine;
    use crate::safety::criteria::{Category, CriteriaSection};
    use std::path::Path;

    /// The report of a frictionless joint after two steps, the last with η_tot = 2 Pa m and 100
    /// unknowns, and `best_step`.
    fn report(best_step: Option<BestStep>) -> Report {
        let row = |step| StepRow {
            step,
            unknowns: 100,
            eta_relative: 0.1,
            crack_length: 1.0,
            resultant_position: None,
            sliding_safety_factor: None,
        };
        Report {
            units: UNITS,
            scene: "dam.toml".into(),
            order: 1,
            tol_relative: 0.01,
            tolerance_met: false,
            steps: vec![row(0), row(1)],
            unknowns: 100,
            eta_tot: 2.0,
            eta_relative: 0.1,
            best_step,
            newton_stalled: false,
            joint_line: JointLine::new([0.0, 0.0], [10.0, 0.0]),
            contact_length: 9.0,
            crack_length: 1.0,
            crack_rule: None,
            bond_lengths: None,
            resultant: None,
            base_stresses: BaseStresses { length: 1.0, heel: 0.0, toe: -1.0, heel_closed: -0.5 },
            sliding_safety_factor: None,
            strength_reduction: None,
            safety_factor_note: None,
            crack_note: None,
            requirements: CriteriaSection::default().requirements(Category::Usual),
            classical: None,
            classical_note: None,
            checks: Vec::new(),
            verdict: crate::safety::check::verdict(&[]),
        }
    }

    // Source: an adaptive run of geo/dam_lift_joint.toml (docs/results.md), whose last mesh
    // had an η_tot 19 times that of the sixth. Goal: report.md names the step of smallest η_tot
    // under the adaptive run, with its η_tot and unknowns against the last mesh's and its VTU
    // file, and the report of load combinations names each combination that has one; neither
    // says anything without one. Parameters: hand-built reports of two steps, the first with
    // η_tot = 1 Pa m and 200 unknowns.
    #[test]
    fn the_report_names_a_step_tighter_than_the_last_mesh() {
        let best = BestStep {
            step: 0,
            eta_tot: 1.0,
            unknowns: 200,
            crack_length: Some(1.0),
            resultant: None,
            file: "out/dam_00.vtu".into(),
        };
        let with = report(Some(best));
        let md = markdown(&with, &table(&with));
        let sentence =
            "Step 0 has the smallest η_tot of the run, 1.000e0 Pa m with 200 unknowns, against 2.000e0 Pa m \
                        with 100 unknowns on the last mesh";
        let adaptive = md.split("## Adaptive run").nth(1).unwrap();
        assert!(adaptive.contains(sentence) && adaptive.contains("`dam_00.vtu`"), "{md}");
        let without = report(None);
        assert!(!markdown(&without, &table(&without)).contains("smallest η_tot"));
        let reports = [
            Combination { name: "flood".into(), outcome: Outcome::Solved(Box::new(with)) },
            Combination { name: "usual".into(), outcome: Outcome::Solved(Box::new(without)) },
        ];
        let md = combinations_markdown(Path::new("dam.toml"), &combination_rows(&reports), &reports);
        assert!(
            md.contains("\nflood: step 0 has a smaller η_tot than the last mesh, 1.000e0 against 2.000e0 Pa m"),
            "{md}"
        );
        assert!(!md.contains("usual: step"), "{md}");
    }

    // Source: the usual and earthquake combinations of a 60 m dam on rock with a Mohr–Coulomb
    // joint (c = 0.2 MPa), FS_LE 2.1446 above FS_SR in [2.1393, 2.1423] and 1.0972 below
    // [1.1074, 1.1094]. Goal: FS_LE outside the bracket is said, on either side, with both
    // numbers, and with a bond also why a bond lifts FS_SR; inside it nothing is. Parameters:
    // those brackets.
    #[test]
    fn a_safety_factor_outside_the_strength_bracket_is_explained() {
        let sr = |held, failed| StrengthReduction { held, failed, solves: 9, retried: 0 };
        let above = outside_note(2.1446, &sr(2.1393, 2.1423), false).unwrap();
        assert!(above.contains("2.1446 lies above FS_SR's bracket [2.1393, 2.1423]"), "{above}");
        let below = outside_note(1.0972, &sr(1.1074, 1.1094), false).unwrap();
        assert!(below.contains("lies below") && !below.contains("bond's tension"), "{below}");
        let bonded = outside_note(1.0972, &sr(1.1074, 1.1094), true).unwrap();
        assert!(bonded.contains("the bond's tension included"), "{bonded}");
        assert_eq!(outside_note(2.14, &sr(2.1393, 2.1423), false), None);
    }

    // Source: docs/method.md §5.3 (a last mesh whose Newton run stalls before the residual
    // tolerance ends where (S_lin) stopped it). Goal: report.md says that the numbers are those
    // of that iterate, and says nothing of it otherwise. Parameters: the hand-built report
    // above, with and without the flag.
    #[test]
    fn the_report_says_when_the_last_mesh_stopped_short_of_the_residual_tolerance() {
        let stalled = Report { newton_stalled: true, ..report(None) };
        let md = markdown(&stalled, &table(&stalled));
        assert!(
            md.contains("\nOn the last mesh Newton stalled before the residual tolerance: its numbers are those"),
            "{md}"
        );
        let converged = report(None);
        assert!(!markdown(&converged, &table(&converged)).contains("Newton stalled"));
    }
}
