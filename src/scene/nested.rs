//! The contact solve of `damfem solve` started by nested iteration on coarser meshes of the
//! scene's geometry (docs/method.md §1.5).

use super::Scene;
use crate::contact::{nested_start, solve_by_continuation, solve_from, ContactError, ContactJoint, ContactSolution};
use crate::contact::{Continuation, NestedStart};
use crate::elasticity::{Discretisation, Problem};
use crate::io::gmsh::{mesh_geo, MeshOptions};

/// The coarsest mesh of nested iteration has at least this many unknowns: below it a cold
/// Newton run costs less than meshing one more level.
const COARSEST_UNKNOWNS: usize = 5000;

/// The ratio of the mesh sizes of the finest coarse level to the mesh's; each level below is
/// twice as coarse as the next (about 4 times fewer unknowns). At 10⁵ unknowns the fine mesh
/// then needs at most 8 Newton steps for γ₀ ≤ 10³, 10 with a ratio of 2 (docs/results.md).
const RATIO: f64 = 1.5;

impl Scene {
    /// The contact solve on `problem` (meshed from this scene's geometry with its `[mesh]`
    /// options) along the δ path of `settings`. A mesh of N ≥ 1.5² × 5 000 unknowns meshed
    /// from a `.geo` starts Newton from nested iteration ([`nested_start`]) on the geometry
    /// meshed with the size factor × 1.5 × 2^k, k = K … 0 (about N / (1.5² 4^k) unknowns; K
    /// the largest with ≥ 5 000 left), and goes straight to δ; any other mesh, or a failure on
    /// the way, starts from u = 0 as [`solve_by_continuation`]. Both reach the same solution,
    /// to the Newton tolerance (docs/method.md §1.5).
    pub fn solve_contact(
        &self,
        problem: &Problem,
        disc: &Discretisation,
        joint: &ContactJoint,
        settings: &Continuation,
        allow_system_calls: bool,
    ) -> Result<ContactSolution, ContactError> {
        let coarse = self.coarse_problems(disc.dofs.n_free, allow_system_calls);
        if let Ok(Some(NestedStart { x0, solves })) = nested_start(problem, disc, &coarse, settings) {
            drop(coarse);
            let at_delta = Continuation { delta_start: settings.delta, ..*settings };
            if let Ok(solution) = solve_from(problem, disc, joint, &at_delta, x0) {
                return Ok(ContactSolution { coarse: solves, ..solution });
            }
        }
        solve_by_continuation(problem, disc, joint, settings)
    }

    /// The coarser problems of nested iteration for a mesh of `unknowns` unknowns, coarsest
    /// first, each with its joint; none for a `.msh` geometry, a small mesh, or when gmsh or
    /// the scene fails on one of them.
    fn coarse_problems(&self, unknowns: usize, allow_system_calls: bool) -> Vec<(Problem, ContactJoint)> {
        let coarse_unknowns = |k: i32| unknowns as f64 / (RATIO * RATIO * 4f64.powi(k));
        let levels = (0..).take_while(|&k| coarse_unknowns(k) >= COARSEST_UNKNOWNS as f64).count() as i32;
        if levels == 0 || self.geometry.extension().is_some_and(|e| e == "msh") {
            return Vec::new();
        }
        let options = self.mesh_options();
        let level = |k: i32| {
            let size_factor = options.size_factor * RATIO * 2f64.powi(k);
            let coarse = MeshOptions { size_factor, ..options.clone() };
            let mesh = mesh_geo(&self.geometry, &coarse, false, allow_system_calls).ok()?;
            match self.problem(mesh).ok()? {
                (problem, Some(joint)) => Some((problem, joint)),
                (_, None) => None,
            }
        };
        (0..levels).rev().map(level).collect::<Option<Vec<_>>>().unwrap_or_default()
    }
}
