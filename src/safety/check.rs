//! The code check of one load combination: each quantity by the finite elements and by the
//! classical method beside the requirement of the combination's category, pass or fail.
//!
//! Factors pass at or above their requirement; the resultant passes within its rule
//! ([`ResultantRule`]); a normal stress passes unless it is a compression larger than the
//! allowable one. The base in compression and the crack are reported, not checked (the
//! resultant's rule checks them).

use super::classical::Classical;
use super::criteria::{Requirements, ResultantRule};
use serde::Serialize;

/// What the finite elements give of the checked quantities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FiniteElements {
    /// L \[m\].
    pub length: f64,
    pub sliding: Option<f64>,
    /// FS_SR: the largest reduction at which the joint held.
    pub strength_reduction: Option<f64>,
    /// (N + U) / U.
    pub flotation: Option<f64>,
    /// s_R \[m\].
    pub resultant: Option<f64>,
    /// The contact length and the crack from the heel \[m\].
    pub contact: f64,
    pub crack: f64,
    /// σ'^n \[Pa\] at the heel, beyond the crack and at the toe (tension positive): means over a
    /// stated length from each end and from the crack tip.
    pub heel: f64,
    pub heel_closed: f64,
    pub toe: f64,
}

/// One line of the code check.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    pub quantity: String,
    pub unit: &'static str,
    pub finite_elements: Option<f64>,
    pub classical: Option<f64>,
    /// The requirement in words ("≥ 2.000"), None: reported only.
    pub requirement: Option<String>,
    pub finite_elements_pass: Option<bool>,
    pub classical_pass: Option<bool>,
}

/// The verdict of a combination by each method: None where the method checked nothing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    pub finite_elements: Option<bool>,
    pub classical: Option<bool>,
    /// The quantities that fail, with the method ("sliding FS (classical)").
    pub failed: Vec<String>,
}

/// A line with the test `pass` of its values.
fn line(
    quantity: &str,
    unit: &'static str,
    values: [Option<f64>; 2],
    requirement: Option<String>,
    pass: impl Fn(f64) -> Option<bool>,
) -> Check {
    let judged = |v: Option<f64>| requirement.as_ref().and(v).and_then(&pass);
    Check {
        quantity: quantity.into(),
        unit,
        finite_elements: values[0],
        classical: values[1],
        finite_elements_pass: judged(values[0]),
        classical_pass: judged(values[1]),
        requirement,
    }
}

/// The lines of the check of `fe` and `classical` against `req`.
pub fn checks(fe: &FiniteElements, classical: Option<&Classical>, req: &Requirements) -> Vec<Check> {
    let c = |f: fn(&Classical) -> Option<f64>| classical.and_then(f);
    let at_least = |r: f64| move |v: f64| Some(v >= r);
    let none = |_: f64| None;
    let l = fe.length;
    let rule: ResultantRule = req.resultant;
    let allowed = req.allowable_compression;
    let stress = move |v: f64| allowed.map(|a| v >= -a);
    let allowable = allowed.map(|a| format!("≥ −{:.3} MPa", a / 1e6));
    vec![
        line(
            "sliding FS_LE",
            "",
            [fe.sliding, c(|c| c.sliding_factor)],
            Some(format!("≥ {:.3}", req.sliding)),
            at_least(req.sliding),
        ),
        line(
            "sliding FS_SR (held)",
            "",
            [fe.strength_reduction, None],
            Some(format!("≥ {:.3}", req.sliding)),
            at_least(req.sliding),
        ),
        line(
            "overturning FS_OT",
            "",
            [None, c(|c| c.overturning_factor)],
            req.overturning.map(|r| format!("≥ {r:.3}")),
            move |v| req.overturning.map(|r| v >= r),
        ),
        line(
            "flotation FS_F",
            "",
            [fe.flotation, c(|c| c.flotation_factor)],
            Some(format!("≥ {:.3}", req.flotation)),
            at_least(req.flotation),
        ),
        line(
            "resultant s_R from the heel",
            "m",
            [fe.resultant, c(|c| Some(c.resultant_position))],
            Some(rule.label().into()),
            move |s| Some(rule.holds(s, l)),
        ),
        line(
            "base in compression",
            "%",
            [Some(100.0 * fe.contact / l), c(|c| Some(100.0 * c.compressed_fraction()))],
            None,
            none,
        ),
        line("crack from the heel", "m", [Some(fe.crack), c(|c| Some(c.crack))], None, none),
        line(
            "crack from the heel",
            "% of L",
            [Some(100.0 * fe.crack / l), c(|c| Some(100.0 * c.crack / c.length))],
            None,
            none,
        ),
        line("heel normal stress", "Pa", [Some(fe.heel), c(|c| Some(c.heel_stress))], allowable.clone(), stress),
        line("normal stress from the crack tip", "Pa", [Some(fe.heel_closed), None], allowable.clone(), stress),
        line("toe normal stress", "Pa", [Some(fe.toe), c(|c| Some(c.toe_stress))], allowable, stress),
    ]
}

/// The verdict of the `checks`.
pub fn verdict(checks: &[Check]) -> Verdict {
    let of = |pass: fn(&Check) -> Option<bool>| {
        let judged: Vec<bool> = checks.iter().filter_map(pass).collect();
        (!judged.is_empty()).then(|| judged.iter().all(|&p| p))
    };
    let mut failed = Vec::new();
    for c in checks {
        let unit = if c.unit.is_empty() { String::new() } else { format!(" [{}]", c.unit) };
        if c.finite_elements_pass == Some(false) {
            failed.push(format!("{}{unit} (finite elements)", c.quantity));
        }
        if c.classical_pass == Some(false) {
            failed.push(format!("{}{unit} (classical)", c.quantity));
        }
    }
    Verdict { finite_elements: of(|c| c.finite_elements_pass), classical: of(|c| c.classical_pass), failed }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::safety::criteria::{Category, CriteriaSection};

    // Goal: each line passes or fails against its requirement, lines without a requirement are
    // not judged, and the verdict names what fails by which method. Parameters: an unusual
    // combination (FS ≥ 1.7, middle half, f'c = 20 MPa: 10 MPa allowed) whose finite-element
    // FS_LE is 1.6 and toe stress −11 MPa, its resultant at 15.5 m of 60 m (|e| = 14.5 ≤ 15).
    #[test]
    fn each_line_is_judged_against_its_category() {
        let criteria = CriteriaSection { compressive_strength: Some(2e7), ..Default::default() };
        let req = criteria.requirements(Category::Unusual);
        let fe = FiniteElements {
            length: 60.0,
            sliding: Some(1.6),
            strength_reduction: Some(1.75),
            flotation: Some(3.0),
            resultant: Some(15.5),
            contact: 50.0,
            crack: 10.0,
            heel: 0.0,
            heel_closed: -1e6,
            toe: -1.1e7,
        };
        let lines = checks(&fe, None, &req);
        let pass = |q: &str| lines.iter().find(|c| c.quantity == q).unwrap().finite_elements_pass;
        assert_eq!(pass("sliding FS_LE"), Some(false));
        assert_eq!(pass("sliding FS_SR (held)"), Some(true));
        assert_eq!(pass("resultant s_R from the heel"), Some(true));
        assert_eq!(pass("base in compression"), None);
        assert_eq!((pass("heel normal stress"), pass("toe normal stress")), (Some(true), Some(false)));
        let v = verdict(&lines);
        assert_eq!((v.finite_elements, v.classical), (Some(false), None));
        assert_eq!(v.failed, ["sliding FS_LE (finite elements)", "toe normal stress [Pa] (finite elements)"]);
    }
}
