//! The acceptance criteria of a load combination by its category (the scene's `[criteria]`).
//!
//! Defaults, by category usual / unusual / extreme:
//!
//! - required sliding factor 2.0 / 1.7 / 1.3, resultant within the middle third / the middle
//!   half / the base, allowable compression 0.3 / 0.5 / 0.9 f'c: US Army Corps of Engineers,
//!   EM 1110-2-2200, Gravity Dam Design (1995), Table 4-1 (the sliding factors are also those
//!   of EM 1110-2-2100 (2005), Table 3-2, for critical structures with ordinary site
//!   information; its resultant requirements read 100 %, 75 % of the base in compression and
//!   the resultant within the base);
//! - required flotation factor 1.3 / 1.2 / 1.1: EM 1110-2-2100, Table 3-4;
//! - no required overturning factor: the Corps checks overturning by the resultant's location;
//!   a scene may require one.
//!
//! The allowable compression needs the concrete's strength f'c (`compressive_strength`);
//! without it the stresses are reported and not checked.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The category of a load combination.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Category {
    #[default]
    Usual,
    Unusual,
    Extreme,
}

/// Where the resultant of the base pressure must lie.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ResultantRule {
    /// |e| ≤ L/6: the whole base in compression.
    MiddleThird,
    /// |e| ≤ L/4: 75 % of the base in compression.
    MiddleHalf,
    /// 0 ≤ s_R ≤ L.
    WithinBase,
}

impl ResultantRule {
    /// Whether the resultant at s_R from the heel of a base of length L meets the rule.
    pub fn holds(&self, position: f64, length: f64) -> bool {
        let e = (position - 0.5 * length).abs();
        match self {
            ResultantRule::MiddleThird => e <= length / 6.0 * (1.0 + 1e-12),
            ResultantRule::MiddleHalf => e <= length / 4.0 * (1.0 + 1e-12),
            ResultantRule::WithinBase => (0.0..=length).contains(&position),
        }
    }

    pub fn label(&self) -> &'static str {
        match self {
            ResultantRule::MiddleThird => "middle third",
            ResultantRule::MiddleHalf => "middle half",
            ResultantRule::WithinBase => "within the base",
        }
    }
}

/// `[criteria.<category>]`: what a scene changes of a category's defaults.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RequirementsSection {
    pub sliding: Option<f64>,
    pub overturning: Option<f64>,
    pub flotation: Option<f64>,
    pub resultant: Option<ResultantRule>,
    /// The allowable compression as a fraction of f'c.
    pub compression: Option<f64>,
}

/// The requirements of one category.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Requirements {
    pub category: Category,
    pub sliding: f64,
    pub overturning: Option<f64>,
    pub flotation: f64,
    pub resultant: ResultantRule,
    /// The allowable compressive stress \[Pa\] (a magnitude), None without f'c.
    pub allowable_compression: Option<f64>,
}

/// `[criteria]`.
#[derive(Debug, Clone, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CriteriaSection {
    /// The category of a combination not named in `categories` (and of a scene without).
    #[serde(default)]
    pub category: Category,
    /// The category of each combination by name.
    #[serde(default)]
    pub categories: BTreeMap<String, Category>,
    /// f'c \[Pa\].
    pub compressive_strength: Option<f64>,
    #[serde(default)]
    pub usual: RequirementsSection,
    #[serde(default)]
    pub unusual: RequirementsSection,
    #[serde(default)]
    pub extreme: RequirementsSection,
}

impl CriteriaSection {
    /// The category of the combination `name` (None: the scene without combinations).
    pub fn category_of(&self, name: Option<&str>) -> Category {
        name.and_then(|n| self.categories.get(n).copied()).unwrap_or(self.category)
    }

    /// The requirements of `category`: the defaults of the module docs, with the scene's keys.
    pub fn requirements(&self, category: Category) -> Requirements {
        let (given, sliding, flotation, resultant, compression) = match category {
            Category::Usual => (&self.usual, 2.0, 1.3, ResultantRule::MiddleThird, 0.3),
            Category::Unusual => (&self.unusual, 1.7, 1.2, ResultantRule::MiddleHalf, 0.5),
            Category::Extreme => (&self.extreme, 1.3, 1.1, ResultantRule::WithinBase, 0.9),
        };
        let fraction = given.compression.unwrap_or(compression);
        Requirements {
            category,
            sliding: given.sliding.unwrap_or(sliding),
            overturning: given.overturning,
            flotation: given.flotation.unwrap_or(flotation),
            resultant: given.resultant.unwrap_or(resultant),
            allowable_compression: self.compressive_strength.map(|f| fraction * f),
        }
    }

    /// The first key out of range, as "criteria.key = value must …", against the scene's
    /// `combinations` names.
    pub fn check(&self, combinations: &[&str]) -> Result<(), String> {
        if let Some(name) = self.categories.keys().find(|n| !combinations.contains(&n.as_str())) {
            let names = if combinations.is_empty() { "none".to_string() } else { combinations.join(", ") };
            return Err(format!(
                "criteria.categories.{name} names no combination of the scene; its combinations are: {names}"
            ));
        }
        if let Some(f) = self.compressive_strength.filter(|f| !(*f > 0.0 && f.is_finite())) {
            return Err(format!("criteria.compressive_strength = {f} must be a positive stress in Pa"));
        }
        let tables = [("usual", &self.usual), ("unusual", &self.unusual), ("extreme", &self.extreme)];
        for (table, r) in tables {
            let factors = [("sliding", r.sliding), ("overturning", r.overturning), ("flotation", r.flotation)];
            if let Some((key, v)) =
                factors.iter().find_map(|(k, v)| v.filter(|x| !(*x > 0.0 && x.is_finite())).map(|x| (k, x)))
            {
                return Err(format!("criteria.{table}.{key} = {v} must be a positive factor"));
            }
            if let Some(c) = r.compression.filter(|c| !(*c > 0.0 && *c <= 1.0)) {
                return Err(format!("criteria.{table}.compression = {c} must be a fraction of f'c in (0, 1]"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Source: EM 1110-2-2200 Table 4-1, EM 1110-2-2100 Table 3-4 (module docs). Goal: the
    // defaults by category, a scene's key replacing one, the resultant rules at their limits,
    // and a bad value named by its key. Parameters: f'c = 30 MPa.
    #[test]
    fn the_categories_have_the_guideline_defaults() {
        let mut c = CriteriaSection { compressive_strength: Some(3e7), ..Default::default() };
        c.unusual.sliding = Some(1.5);
        let usual = c.requirements(Category::Usual);
        assert_eq!((usual.sliding, usual.flotation, usual.resultant), (2.0, 1.3, ResultantRule::MiddleThird));
        assert!((usual.allowable_compression.unwrap() - 9e6).abs() < 1e-6);
        assert_eq!(c.requirements(Category::Unusual).sliding, 1.5);
        let extreme = c.requirements(Category::Extreme);
        assert_eq!((extreme.sliding, extreme.flotation, extreme.overturning), (1.3, 1.1, None));
        assert!(ResultantRule::MiddleThird.holds(60.0 / 3.0, 60.0) && !ResultantRule::MiddleThird.holds(19.9, 60.0));
        assert!(ResultantRule::MiddleHalf.holds(15.0, 60.0) && !ResultantRule::MiddleHalf.holds(14.9, 60.0));
        assert!(ResultantRule::WithinBase.holds(0.1, 60.0) && !ResultantRule::WithinBase.holds(-0.1, 60.0));
        c.extreme.flotation = Some(-1.0);
        assert_eq!(c.check(&[]).unwrap_err(), "criteria.extreme.flotation = -1 must be a positive factor");
        c.extreme.flotation = None;
        c.categories.insert("flod".into(), Category::Unusual);
        let e = c.check(&["flood"]).unwrap_err();
        assert!(e.starts_with("criteria.categories.flod names no combination"), "{e}");
    }
}
