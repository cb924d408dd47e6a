//! A case beside its exact reference, and the table and summary of a battery.

use super::*;
use std::fmt::Write as _;

/// A case, its run and its exact reference.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub case: DamCase,
    pub run: Run,
    pub statics: Statics,
    /// N = R·ν − U and FS of the module's formulas, with damfem's U (crack filled) and L_c
    /// (cohesion) when it has a result.
    pub normal: f64,
    pub exact: f64,
}

impl Record {
    pub fn new(case: DamCase, run: Run) -> Record {
        let statics = case.statics();
        let uplift = match (case.crack, run.uplift) {
            (Crack::Full, Some(u)) => u,
            _ => statics.uplift,
        };
        let normal = statics.pressing - uplift;
        let closed = run.contact_length.unwrap_or(statics.length);
        let exact = (case.cohesion * closed + case.friction * normal) / statics.tangential.abs();
        Record { case, run, statics, normal, exact }
    }

    /// |FS_LE − FS| / FS.
    pub fn error(&self) -> Option<f64> {
        self.run.safety_factor.map(|fs| (fs - self.exact).abs() / self.exact)
    }

    /// |N_h − N| / N and |T_h − T| / |T| of damfem's joint forces.
    pub fn force_errors(&self) -> Option<(f64, f64)> {
        let (n, t) = (self.run.normal?, self.run.tangential?);
        Some((
            (n - self.normal).abs() / self.normal,
            (t - self.statics.tangential).abs() / self.statics.tangential.abs(),
        ))
    }

    /// How far FS lies outside FS_SR's bracket \[held, failed\], relative to FS (0 inside it);
    /// None without a bracket.
    pub fn strength_gap(&self) -> Option<f64> {
        let [held, failed] = self.run.strength?;
        let fs = self.exact;
        Some(if held <= fs && fs <= failed { 0.0 } else { (held - fs).abs().min((failed - fs).abs()) / fs })
    }

    /// Whether the case holds exactly.
    pub fn holds(&self) -> bool {
        self.exact >= 1.0
    }

    /// Whether the exact FS is within [`UNDECIDED`] of 1, where either answer is right.
    pub fn undecided(&self) -> bool {
        (self.exact - 1.0).abs() <= UNDECIDED
    }

    /// A result where the case holds, a verdict where it does not (either near FS = 1).
    pub fn agrees(&self) -> bool {
        match self.run.outcome {
            Outcome::Result => self.holds() || self.undecided(),
            Outcome::Verdict => !self.holds() || self.undecided(),
            Outcome::Failure | Outcome::Error => false,
        }
    }

    /// The crack s_c of the result's uplift diagram (0 with the crack ignored).
    fn diagram_crack(&self) -> Option<f64> {
        match self.case.crack {
            Crack::Ignore => self.run.safety_factor.map(|_| 0.0),
            Crack::Full => self.run.diagram_crack,
        }
    }

    /// |U_h − U(s_c)| / U(s_c) of a result, at its own crack s_c.
    pub fn uplift_error(&self) -> Option<f64> {
        let (u, _) = self.case.uplift(self.diagram_crack()?);
        Some((self.run.uplift? - u).abs() / u)
    }

    /// |s_R − s_N(s_c)| / L of a result, s_N(s_c) = −(M + M_u(s_c))/(R·ν − U(s_c)).
    pub fn position_error(&self) -> Option<f64> {
        let (u, mu) = self.case.uplift(self.diagram_crack()?);
        let s = -(self.statics.moment + mu) / (self.statics.pressing - u);
        Some((self.run.position? - s).abs() / self.statics.length)
    }

    /// Whether a result with the crack filled has its open length more than 10⁻³ L from the
    /// crack s_c of its diagram: the crack's fixed point did not settle. A crack that stopped at
    /// the drain line settled if s_c = s_d and the joint closes short of it there.
    pub fn unsettled(&self) -> bool {
        let (open, crack) = (self.run.crack_length, self.run.diagram_crack);
        let Some((open, crack)) = open.zip(crack).filter(|_| self.case.crack == Crack::Full) else { return false };
        if self.run.at_drains {
            return self.case.drains.is_none_or(|d| d.distance != crack || open > crack);
        }
        (open - crack).abs() > 1e-3 * self.statics.length
    }
}

/// The table's header: the seed, the foundation, the degree, H \[m\], m, β \[°\], E_rock/E_concrete,
/// φ \[°\], c \[MPa\], the crack rule, a \[g\], the outcome, the Newton steps (the most on one mesh /
/// summed over the levels), FS_LE, the exact FS, their relative difference and the wall time \[s\].
pub fn header() -> String {
    let names = [
        "seed", "kind", "p", "H", "m", "β°", "rock", "φ°", "c MPa", "crack", "a g", "outcome", "newton", "FS_LE", "FS",
        "error", "time s",
    ];
    let widths = [6, 5, 2, 6, 5, 5, 5, 5, 5, 6, 5, 8, 7, 7, 7, 8, 6];
    names.iter().zip(widths).map(|(n, w)| format!("{n:>w$}")).collect::<Vec<_>>().join(" ")
}

/// The row of a record under [`header`].
pub fn row(r: &Record) -> String {
    let c = &r.case;
    let opt = |v: Option<f64>, digits: usize| v.map_or("–".to_string(), |v| format!("{v:.digits$}"));
    format!(
        "{:>6} {:>5} {:>2} {:>6.1} {:>5.2} {:>5.1} {:>5} {:>5.1} {:>5.2} {:>6} {:>5.3} {:>8} {:>7} {:>7} {:>7.4} {:>8} {:>6.2}",
        c.seed,
        c.kind(),
        c.order,
        c.height,
        c.slope,
        c.base_angle.to_degrees(),
        opt(c.rock_ratio(), 2),
        c.friction.atan().to_degrees(),
        c.cohesion / 1e6,
        c.crack.name(),
        c.acceleration,
        r.run.outcome.name(),
        r.run.newton_steps_per_mesh.zip(r.run.newton_steps).map_or("–".to_string(), |(m, n)| format!("{m}/{n}")),
        opt(r.run.safety_factor, 4),
        r.exact,
        r.error().map_or("–".to_string(), |e| format!("{e:.1e}")),
        r.run.seconds
    )
}

/// The largest value of `f` over the records that have one.
fn largest(records: &[Record], f: impl Fn(&Record) -> Option<f64>) -> f64 {
    records.iter().filter_map(f).fold(0.0, f64::max)
}

/// FS_SR's bracket must hold the exact FS of a c = 0 case within this share of it.
pub const STRENGTH_GAP: f64 = 5e-3;

/// The seeds of the `records` that `pick`, comma-separated.
fn seeds(records: &[Record], pick: impl Fn(&Record) -> bool) -> String {
    records.iter().filter(|r| pick(r)).map(|r| r.case.seed.to_string()).collect::<Vec<_>>().join(", ")
}

/// The closing summary: the share of cases with a result or a correct verdict, the largest
/// FS error of the c = 0 results, the median and largest Newton steps (the most on one mesh,
/// and summed over the levels of nested iteration), the largest errors of N, T, U and s_R, the
/// seeds of the results whose crack did not settle, and each case that went wrong with its
/// exit code and message.
pub fn summary(records: &[Record]) -> String {
    let agreeing = records.iter().filter(|r| r.agrees()).count();
    let median_and_largest = |steps: fn(&Run) -> Option<u64>| {
        let mut steps: Vec<u64> = records.iter().filter_map(|r| steps(&r.run)).collect();
        steps.sort_unstable();
        let count = |n: Option<&u64>| n.map_or("–".to_string(), |n| n.to_string());
        format!("median {}, largest {}", count(steps.get(steps.len() / 2)), count(steps.last()))
    };
    let unsettled = seeds(records, Record::unsettled);
    let mut text = format!(
        "{agreeing} of {} cases ({:.1} %) with a result where they hold or a verdict where they do not\n\
         largest |FS_LE − FS|/FS of the c = 0 results: {:.2e}\n\
         Newton steps of the results on one mesh: {}; summed over the levels: {}\n\
         largest |N_h − N|/N, |T_h − T|/|T|, |U_h − U(s_c)|/U, |s_R − s_N(s_c)|/L of the results: \
         {:.2e}, {:.2e}, {:.2e}, {:.2e}\n\
         results whose crack did not settle (open length ≠ s_c by more than 10⁻³ L): seeds [{}]\n\
         results whose crack stopped at the drain line: seeds [{}]\n",
        records.len(),
        100.0 * agreeing as f64 / records.len().max(1) as f64,
        largest(records, |r| r.error().filter(|_| r.case.cohesion == 0.0)),
        median_and_largest(|r| r.newton_steps_per_mesh),
        median_and_largest(|r| r.newton_steps),
        largest(records, |r| r.force_errors().map(|e| e.0)),
        largest(records, |r| r.force_errors().map(|e| e.1)),
        largest(records, Record::uplift_error),
        largest(records, Record::position_error),
        unsettled,
        seeds(records, |r| r.run.at_drains),
    );
    if records.iter().any(|r| r.run.strength.is_some()) {
        let c0 = |r: &Record| r.case.cohesion == 0.0;
        writeln!(
            text,
            "largest distance of FS from FS_SR's bracket, relative to FS, of the c = 0 results: {:.2e}; over \
             {STRENGTH_GAP:.1e}: seeds [{}]",
            largest(records, |r| r.strength_gap().filter(|_| c0(r))),
            seeds(records, |r| c0(r) && r.strength_gap().is_some_and(|g| g > STRENGTH_GAP)),
        )
        .unwrap();
    }
    for r in records.iter().filter(|r| !r.agrees()) {
        writeln!(
            text,
            "seed {}: {} (exit {}) where FS = {:.4}: {}",
            r.case.seed,
            r.run.outcome.name(),
            r.run.code.map_or("by signal".to_string(), |c| c.to_string()),
            r.exact,
            r.run.message
        )
        .unwrap();
    }
    text
}
