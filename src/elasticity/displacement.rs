//! Nodal displacements as an unevaluated sum u_h = hi + lo (docs/method.md §5.2).
//!
//! A double u_h resolves the difference of two nodal values only to ε |u_h|, so on a cell of
//! size h its strain is known only to ε |u_h| / h. The linear solve therefore refines a
//! correction `lo` below the rounding of `hi` ([`crate::elasticity::Problem::solve_refined`]),
//! and whatever reads the strain takes the nodal differences of the pair,
//! (hi_k − hi_0) + (lo_k − lo_0), exact to ε |u_k − u_0|.

use crate::geometry::{norm, sub, Vector};

/// Nodal displacements u_h = hi + lo: `hi` the double values, `lo` a correction below their
/// rounding, or None for a plain double u_h.
#[derive(Debug, Clone)]
pub struct Displacement {
    pub hi: Vec<Vector>,
    pub lo: Option<Vec<Vector>>,
}

impl From<Vec<Vector>> for Displacement {
    /// A plain double u_h.
    fn from(hi: Vec<Vector>) -> Self {
        Displacement { hi, lo: None }
    }
}

impl Displacement {
    /// The value at node n, rounded to double.
    pub fn value(&self, n: usize) -> Vector {
        let lo = self.lo.as_ref().map_or([0.0; 2], |lo| lo[n]);
        [self.hi[n][0] + lo[0], self.hi[n][1] + lo[1]]
    }

    /// u_k − u_0 for the nodes k of `nodes` (0 at the first), into `out`: the differences of
    /// `hi` (exact between nearby values) plus those of `lo`.
    pub fn relative(&self, nodes: &[usize], out: &mut Vec<Vector>) {
        let (hi, n0) = (&self.hi, nodes[0]);
        out.clear();
        out.extend(nodes.iter().map(|&n| {
            let lo = self.lo.as_ref().map_or([0.0; 2], |lo| sub(lo[n], lo[n0]));
            [(hi[n][0] - hi[n0][0]) + lo[0], (hi[n][1] - hi[n0][1]) + lo[1]]
        }));
    }

    /// The largest nodal |u_h| of `nodes`.
    pub fn size(&self, nodes: &[usize]) -> f64 {
        nodes.iter().map(|&n| norm(self.hi[n])).fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_of_the_pair_keep_what_hi_alone_rounds_away() {
        // u_1 − u_0 = 3·2⁻⁶⁰ is below the rounding of |u| = 1: hi alone sees 0
        let lo = 3.0 * 2f64.powi(-60);
        let u = Displacement { hi: vec![[1.0, -1.0], [1.0, -1.0]], lo: Some(vec![[0.0, 0.0], [lo, -lo]]) };
        let mut d = Vec::new();
        u.relative(&[0, 1], &mut d);
        assert_eq!(d, vec![[0.0, 0.0], [lo, -lo]]);
        Displacement::from(u.hi.clone()).relative(&[0, 1], &mut d);
        assert_eq!(d, vec![[0.0, 0.0], [0.0, 0.0]]);
    }
}
