//! The contact solve of `damfem solve` started by nested iteration on coarser meshes of the
//! scene's geometry, or on the degree-1 problem on the triangles of a degree-2 `.msh`
//! (docs/solver.md §4).

use super::Scene;
use crate::contact::projection::Smoothing;
use crate::contact::{nested_start, solve_by_continuation, solve_system_along, solve_system_from, CoarseLevel};
use crate::contact::{ContactError, ContactJoint};
use crate::contact::{ContactProblem, ContactSolution, Continuation, NestedStart};
use crate::elasticity::{Discretisation, Problem};
use crate::io::gmsh::{mesh_geo, MeshOptions};
use crate::mesh::midpoints::vertex_mesh;
use crate::solve::{NewtonOptions, NonlinearSystem};
use std::sync::mpsc::sync_channel;
use std::time::Instant;

/// The coarsest mesh of nested iteration has at least this many unknowns. From a coarse level
/// of 1 000 unknowns on, the battery's meshes of 3 500–8 000 unknowns take fewer Newton steps
/// per mesh and no more time than cold runs (docs/results.md, "The Nitsche parameter").
const COARSEST_UNKNOWNS: usize = 1000;

/// The ratio of the mesh sizes of the finest coarse level to the mesh's. At 10⁵ unknowns the
/// fine mesh then needs at most 8 Newton steps for γ₀ ≤ 10³, 10 with a ratio of 2
/// (docs/results.md).
const RATIO: f64 = 1.5;

/// The ratio of the mesh sizes of each coarse level to the next finer one (16 times fewer
/// unknowns), the coarsest possibly only 2: every level costs gmsh's mesh and the
/// factorisation of its stiffness, whatever its Newton steps (docs/results.md).
const LEVEL_RATIO: f64 = 4.0;

/// Newton on a coarse level stops at ‖F‖ ≤ 10⁻³ ‖b‖: its solution only starts the next
/// level, which receives it with the error of the interpolation between the meshes. The given
/// mesh keeps the scene's tolerance and, at 10⁵ unknowns, the same steps as after coarse
/// levels solved to 10⁻¹⁰ ‖b‖ (docs/results.md).
const COARSE_RTOL: f64 = 1e-3;

/// Coarse levels solve at this many times the scene's δ (10⁻² S at the default δ = 10⁻⁴ S):
/// a smoother law, whose solution only starts the next level at δ. Under cohesion the closed
/// indicator at δ is nearly a step, and Newton on a coarse level stalled after each move of
/// the crack (battery case 51: 73 Newton steps on its coarse level, 14 at 100 δ;
/// docs/results.md, "Newton steps counted in full").
const COARSE_DELTA: f64 = 100.0;

impl Scene {
    /// The contact solve on `problem` (meshed from this scene's geometry with its `[mesh]`
    /// options) along the δ path of `settings`, started by nested iteration ([`nested_start`];
    /// docs/solver.md §4) on coarser levels solved at 100 δ to ‖F‖ ≤ 10⁻³ ‖b‖, then straight
    /// to δ:
    /// - a mesh of N ≥ 1.5² × 1 000 unknowns meshed from a `.geo`: the geometry meshed
    ///   1.5 × 4^k times coarser, k = 0, 1, … (about N / (1.5² 16^k) unknowns, while ≥ 1 000,
    ///   the coarsest possibly only twice as coarse as the next); gmsh meshes each level on a
    ///   thread of its own while Newton solves the level below;
    /// - a degree-2 mesh read from a `.msh` (no geometry to mesh coarser): the degree-1
    ///   problem on the same triangles (about N / 4 unknowns), whose solution is a degree-2
    ///   field of the mesh.
    ///
    /// Any other mesh, or a failure on the way, starts from u = 0 as [`solve_by_continuation`].
    /// Both reach the same solution, to the Newton tolerance. A thread factorises the
    /// stiffness of `problem` while the levels are solved.
    pub fn solve_contact(
        &self,
        problem: &Problem,
        disc: &Discretisation,
        joint: &ContactJoint,
        settings: &Continuation,
        allow_system_calls: bool,
    ) -> Result<ContactSolution, ContactError> {
        let size_factors = self.coarse_size_factors(disc.dofs.n_free);
        let degree_one = self.degree_one_level(problem, joint);
        let contact = ContactProblem::new(problem, disc, joint, Smoothing { delta: settings.delta });
        if size_factors.is_empty() && degree_one.is_none() {
            return solve_system_from(contact, joint, settings, vec![0.0; disc.dofs.n_free]);
        }
        let rtol = COARSE_RTOL.max(settings.newton.rtol);
        let delta = COARSE_DELTA * settings.delta;
        let newton = NewtonOptions { rtol, ..settings.newton };
        let coarse = Continuation { delta, delta_start: settings.delta_start.max(delta), newton, ..*settings };
        let nested = std::thread::scope(|scope| {
            // the given mesh's stiffness factorised meanwhile (assembled before: the assembly's
            // threads would hold up those of the coarse levels)
            scope.spawn(|| {
                contact.schur();
            });
            if let Some(level) = degree_one {
                return nested_start(problem, disc, [Some(level)], &coarse);
            }
            // a level is meshed while the one below is solved, and waits for it to finish
            let (send, levels) = sync_channel(0);
            scope.spawn(move || {
                for size_factor in size_factors {
                    let level = self.coarse_level(size_factor, allow_system_calls);
                    let made = level.is_some();
                    if send.send(level).is_err() || !made {
                        break;
                    }
                }
            });
            nested_start(problem, disc, levels, &coarse)
        });
        if let Ok(Some(NestedStart { x0, slip_origin, solves, cracks })) = nested {
            let at_delta = Continuation { delta_start: settings.delta, ..*settings };
            let mut contact = contact;
            contact.set_cracks(&cracks);
            contact.set_slip_origin(slip_origin.as_deref());
            let failed = match solve_system_from(contact, joint, &at_delta, x0) {
                Ok(solution) => return Ok(ContactSolution { coarse: solves, ..solution }),
                Err(failed) => failed.newton_steps(),
            };
            let solution = solve_by_continuation(problem, disc, joint, settings)?;
            return Ok(ContactSolution { discarded_steps: solution.discarded_steps + failed, ..solution });
        }
        // a coarse level's path that ended at λ* gives this mesh the load factors it reached
        let schedule: Vec<f64> = match &nested {
            Err(ContactError::NoEquilibrium(limit)) => limit.path.iter().map(|p| p.load_factor).collect(),
            _ => Vec::new(),
        };
        solve_system_along(contact, joint, settings, vec![0.0; disc.dofs.n_free], &schedule)
    }

    /// The degree-1 problem on the vertices of the degree-2 mesh of `problem` read from a
    /// `.msh` (its cells, materials, conditions and joint), the coarse level of nested
    /// iteration there; None for a `.geo` or a degree-1 mesh. Its continuous piecewise-linear
    /// solution is a degree-2 field of the same triangles, interpolated exactly at the
    /// midpoint nodes of straight edges.
    fn degree_one_level(&self, problem: &Problem, joint: &ContactJoint) -> Option<CoarseLevel> {
        if !self.is_msh() || problem.mesh.order != 2 {
            return None;
        }
        let clock = Instant::now();
        let level = Problem {
            mesh: vertex_mesh(&problem.mesh),
            materials: problem.materials.clone(),
            dirichlet: problem.dirichlet.clone(),
            neumann: problem.neumann.clone(),
            body_force: problem.body_force.clone(),
        };
        Some(CoarseLevel { problem: level, joint: joint.clone(), seconds: clock.elapsed().as_secs_f64() })
    }

    /// The size factors of the coarser meshes of nested iteration for a mesh of `unknowns`
    /// unknowns, coarsest first: the size factor × 1.5, then × 4 for each level below (× 2 for
    /// the last if × 4 leaves too few), each kept while it has ≥ 1 000 unknowns (about N / r²
    /// for a mesh r times coarser); none for a `.msh` geometry or a small mesh.
    fn coarse_size_factors(&self, unknowns: usize) -> Vec<f64> {
        if self.is_msh() {
            return Vec::new();
        }
        let kept = |r: f64| unknowns as f64 / (r * r) >= COARSEST_UNKNOWNS as f64;
        let mut ratios = Vec::new();
        let mut next = Some(RATIO).filter(|&r| kept(r));
        while let Some(r) = next {
            ratios.push(r);
            next = [LEVEL_RATIO * r, 2.0 * r].into_iter().find(|&coarser| kept(coarser));
        }
        ratios.iter().rev().map(|r| self.mesh.size_factor * r).collect()
    }

    /// The coarser problem of nested iteration meshed with `size_factor`, with its joint; None
    /// when gmsh or the scene fails on it.
    fn coarse_level(&self, size_factor: f64, allow_system_calls: bool) -> Option<CoarseLevel> {
        let clock = Instant::now();
        let options = MeshOptions { size_factor, ..self.mesh_options() };
        let mesh = mesh_geo(&self.geometry, &options, false, allow_system_calls).ok()?;
        match self.problem(mesh).ok()? {
            (problem, Some(joint)) => Some(CoarseLevel { problem, joint, seconds: clock.elapsed().as_secs_f64() }),
            (_, None) => None,
        }
    }

    /// Whether the geometry is a mesh file.
    pub(super) fn is_msh(&self) -> bool {
        self.geometry.extension().is_some_and(|e| e == "msh")
    }
}
