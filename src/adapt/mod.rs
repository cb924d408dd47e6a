//! The adaptive algorithm (docs/method.md §5.3–§5.4).
//!
//! Step ℓ meshes the geometry (from the target sizes of step ℓ − 1), moves the previous
//! displacement onto the new mesh as Newton's initial guess, and solves with the
//! estimator-driven stopping rules of [`level`]: Newton stops once
//! η_lin ≤ γ_lin (η_osc + η_flux + η_Neu + η_disc), and δ is divided by ρ_δ until
//! η_reg ≤ γ_reg (η_osc + η_flux + η_Neu + η_disc + η_lin). The run stops when η_tot meets the
//! tolerance or after the last step, and the last step reports the iterate of the equations
//! solved: on a mesh known to be the last before its solve (the last by count, or one with
//! `max_unknowns`), Newton runs to the residual tolerance at every δ, without (S_lin); on a
//! mesh that meets the tolerance, Newton is finished to the residual tolerance from where
//! (S_lin) stopped it and estimated again ([`level::Level::finish`]), and the tolerance must
//! hold for the finished estimate too, or the loop goes on from the finished iterate;
//! otherwise η_tot,T gives every cell a target size
//! ([`marking`]: equidistribution, or marking), and these sizes define the next mesh. δ is
//! kept from one mesh to the next. On the first mesh, one Newton step from u = 0 at
//! δ = `delta0` × S (S the stress scale of the loads) gives u_h¹, and δ₀ = `delta0` × max over
//! the Γ_C quadrature points of |P_γ(u_h¹)| (`delta0` × S if that is 0); Newton continues
//! from u_h¹ at δ₀. δ is a stress, never a multiple of E.
//!
//! Target sizes never go below the smallest size: 10⁻⁸ of the domain's extent
//! ([`marking::smallest_size`]), or the mesher's own minimum if larger (gmsh's `size_min`).
//! Once the cells held at that size carry θ² of η_tot² (θ = `bulk`), no later mesh can
//! bring η_tot below θ η_tot, the aim of a step, and the run stops with a [`Stall`].

pub mod geo;
pub mod history;
pub mod level;
pub mod marking;

use crate::contact::{CarriedState, ContactError, ContactJoint, ContactSolution, JointLine, LoadPath};
use crate::elasticity::{nodal, Discretisation, Problem};
use crate::estimate::estimators::{stress_norm, GlobalEstimators};
use crate::estimate::Estimate;
use crate::estimate::EstimateError;
use crate::geometry::Point;
use crate::mesh::Mesh;
use crate::safety::resultant::{resultant, Resultant};
use crate::solve::{NewtonError, NewtonOptions, SolveError};
use level::{Level, StartDelta, Stopping};
use marking::Marking;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// How the next mesh is made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Refinement {
    /// Target sizes from the local estimators ([`Marking`]).
    Adaptive,
    /// Halve every size (for comparison).
    Uniform,
}

/// Parameters of the adaptive loop (the scene's `[adapt]` table).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AdaptSettings {
    /// Maximum number of meshes.
    pub steps: usize,
    /// Stop when η_tot ≤ tol [Pa·m].
    pub tol: Option<f64>,
    /// Stop when η_tot ≤ tol_relative ‖σ_h‖.
    pub tol_relative: Option<f64>,
    /// Stop after the first mesh with at least this many unknowns.
    pub max_unknowns: Option<usize>,
    pub refinement: Refinement,
    pub marking: Marking,
    /// The fraction θ of the marking strategy.
    pub bulk: f64,
    /// γ_lin of (S_lin).
    pub gamma_lin: f64,
    /// γ_reg of (S_reg).
    pub gamma_reg: f64,
    /// δ ← δ / ρ_δ while (S_reg) fails.
    pub rho_delta: f64,
    /// δ₀ = delta0 × max_{Γ_C} |P_γ(u_h¹)|, u_h¹ the first Newton iterate (or delta0 × the
    /// stress scale of the loads when that maximum is 0).
    pub delta0: f64,
    /// Most δ reductions on one mesh.
    pub max_delta_reductions: usize,
    /// `damfem adapt` only: after the run, refine uniformly from the same first mesh and draw
    /// both runs on one figure.
    pub compare_uniform: bool,
}

impl Default for AdaptSettings {
    fn default() -> Self {
        AdaptSettings {
            steps: 8,
            tol: None,
            tol_relative: None,
            max_unknowns: None,
            refinement: Refinement::Adaptive,
            marking: Marking::Equidistribution,
            bulk: 0.5,
            gamma_lin: 0.1,
            gamma_reg: 0.1,
            rho_delta: 2.0,
            delta0: 0.1,
            max_delta_reductions: 60,
            compare_uniform: false,
        }
    }
}

impl AdaptSettings {
    /// The first value out of range, as "key = value must …".
    pub fn validate(&self) -> Result<(), String> {
        let positive = [
            ("gamma_lin", self.gamma_lin),
            ("gamma_reg", self.gamma_reg),
            ("delta0", self.delta0),
            ("tol", self.tol.unwrap_or(1.0)),
            ("tol_relative", self.tol_relative.unwrap_or(1.0)),
        ];
        if let Some((key, value)) = positive.iter().find(|(_, v)| !(v.is_finite() && *v > 0.0)) {
            return Err(format!("adapt.{key} = {value} must be positive"));
        }
        if !(self.bulk > 0.0 && self.bulk <= 1.0) {
            return Err(format!("adapt.bulk = {} must be in (0, 1]", self.bulk));
        }
        if !(self.rho_delta > 1.0 && self.rho_delta.is_finite()) {
            return Err(format!("adapt.rho_delta = {} must be greater than 1", self.rho_delta));
        }
        if self.steps == 0 {
            return Err("adapt.steps = 0 must be at least 1".into());
        }
        if self.compare_uniform && self.refinement == Refinement::Uniform {
            return Err("adapt.compare_uniform = true compares adaptive with uniform refinement, \
                        so adapt.refinement must be \"adaptive\" (no --uniform)"
                .into());
        }
        Ok(())
    }

    /// The absolute tolerance on η_tot, the larger of `tol` and `tol_relative` ‖σ_h‖
    /// (‖σ_h‖ = `stress`), if either is set.
    fn tolerance(&self, stress: f64) -> Option<f64> {
        let relative = self.tol_relative.map(|tol| tol * stress);
        self.tol.into_iter().chain(relative).reduce(f64::max)
    }

    /// Whether η_tot meets the tolerance, given the global estimators and ‖σ_h‖.
    fn met(&self, (eta, stress): (GlobalEstimators, f64)) -> bool {
        self.tolerance(stress).is_some_and(|tol| eta.tot <= tol)
    }
}

/// Why the adaptive loop stopped without finishing.
#[derive(Debug, thiserror::Error)]
pub enum AdaptError {
    #[error("meshing failed: {0}")]
    Mesh(Box<dyn std::error::Error + Send + Sync>),
    #[error("{0}")]
    Problem(Box<dyn std::error::Error + Send + Sync>),
    #[error("at delta = {delta:.3e}: {source}")]
    Newton { delta: f64, source: NewtonError },
    #[error("linear solve: {0}")]
    Solve(#[from] SolveError),
    #[error("error estimation: {0}")]
    Estimate(#[from] EstimateError),
    #[error(
        "eta_reg = {eta_reg:.3e} is still too large after {reductions} reductions of delta (now {delta:.3e}); \
         raise adapt.max_delta_reductions or adapt.gamma_reg"
    )]
    Regularisation { delta: f64, reductions: usize, eta_reg: f64 },
    #[error(transparent)]
    Contact(#[from] ContactError),
    #[error("on the last mesh, Newton did not reach the residual tolerance contact.rtol: {0}")]
    Finish(Box<AdaptError>),
    #[error("writing step {step}: {error}")]
    Output { step: usize, error: Box<dyn std::error::Error + Send + Sync> },
}

/// Where the meshes come from.
pub trait Mesher {
    /// The mesh of step `step`: the initial mesh, or for step ≥ 1 one with the target cell
    /// sizes `sizes` on the previous mesh `previous` (uniform refinement ignores them).
    fn mesh(&mut self, step: usize, previous: Option<(&Mesh, &[f64])>) -> Result<Mesh, AdaptError>;

    /// The smallest cell size it makes \[m\], if it has one.
    fn size_min(&self) -> Option<f64> {
        None
    }

    /// The next mesh's estimated cell count and the limit, if the count from `previous` and
    /// its target sizes `sizes` (empty for uniform refinement) exceeds the limit.
    fn over_cell_limit(&self, _previous: &Mesh, _sizes: &[f64]) -> Option<CellLimit> {
        None
    }
}

/// The problem on a mesh and its contact boundary.
pub trait Model {
    /// The problem on `mesh` and its contact joint (None: no Γ_C).
    fn problem(&self, mesh: Mesh) -> Result<(Problem, Option<ContactJoint>), AdaptError>;
    /// Newton options of the contact solve.
    fn newton(&self) -> NewtonOptions;
    /// The straight joint from its heel, if the problem has one (for the crack length and the
    /// resultant of every step).
    fn joint_line(&self, _problem: &Problem) -> Option<JointLine> {
        None
    }
    /// The load path that the first mesh follows from rest (None: every load at once).
    fn load_path(&self) -> Option<LoadPath> {
        None
    }
}

/// Wall time of each phase of a step \[s\]. `mesh` is gmsh's (the initial mesh at step 0, a
/// remesh afterwards), `transfer` moves the previous displacement to the new mesh, `remesh`
/// marks cells and computes the target sizes for the next mesh.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct PhaseTimes {
    pub mesh: f64,
    pub transfer: f64,
    pub assemble: f64,
    pub solve: f64,
    pub estimate: f64,
    pub remesh: f64,
}

impl PhaseTimes {
    pub fn total(&self) -> f64 {
        self.mesh + self.transfer + self.assemble + self.solve + self.estimate + self.remesh
    }
}

/// One row of the history: a mesh and what it took.
#[derive(Debug, Clone, Serialize)]
pub struct StepRecord {
    pub step: usize,
    pub cells: usize,
    /// Free displacement unknowns.
    pub unknowns: usize,
    pub eta: GlobalEstimators,
    /// ‖σ_h‖, the scale of relative errors.
    pub stress_norm: f64,
    /// δ of the final iterate (None without contact).
    pub delta: Option<f64>,
    pub n_reg: usize,
    pub n_lin: usize,
    /// With contact, on the last mesh (or on a mesh whose finished estimate missed the
    /// tolerance that its unfinished one met): how Newton was run to the residual tolerance,
    /// from the start or after (S_lin) stopped it; the step's iterate, forces and estimate
    /// are the finished ones.
    pub finish: Option<level::Finish>,
    /// On a mesh whose Newton run was to reach the residual tolerance (the last, or one
    /// finished): true when it stalled before, and the step reports the iterate where (S_lin)
    /// stopped Newton at that δ instead (its η_tot bounds the error, η_lin included;
    /// docs/method.md §5.3).
    pub newton_stalled: bool,
    /// With contact, whether the final estimate meets (S_reg): false when Newton stalled at
    /// the smaller δ and the level ended at a larger δ solved on it (docs/method.md §5.3).
    pub regularisation_balanced: Option<bool>,
    /// Estimates computed on this mesh (at least the final one).
    pub n_est: usize,
    /// The largest relative violation of an equilibration condition by the final estimate.
    pub equilibration: f64,
    /// η_tot / a sharp lower bound of ‖R(u_h)‖, if the caller computed one.
    pub i_eff: Option<f64>,
    /// Whether the last two references of I_eff agree within 2 %: if not (the reference's
    /// size limit), I_eff is only an upper bound of the true η_tot / ‖R(u_h)‖.
    pub i_eff_reference_converged: Option<bool>,
    /// On a straight joint with a heel: the length open at the heel \[m\] and the resultant
    /// of the joint traction (docs/method.md §1.9).
    pub crack_length: Option<f64>,
    pub resultant: Option<Resultant>,
    /// Set on the last step if the run stopped because of the smallest size.
    pub stall: Option<Stall>,
    /// Set on the last step if the run stopped because the next mesh would exceed the cell limit.
    pub cell_limit: Option<CellLimit>,
    pub seconds: PhaseTimes,
    /// Wall time since the start of the run, at the end of this step.
    pub elapsed: f64,
}

/// Cells whose target is the smallest size while they carry at least θ² of η_tot².
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Stall {
    /// The smallest size \[m\].
    pub size: f64,
    /// Cells held at it, and their share of η_tot².
    pub cells: usize,
    pub share: f64,
    /// Centre of the one with the largest η_T.
    pub at: Point,
}

impl std::fmt::Display for Stall {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "{} cells near ({:.3}, {:.3}) ask for sizes below the smallest size {:.2e} m \
             and hold {:.0} % of eta_tot^2, so no mesh can bring eta_tot below adapt.bulk times its value, \
             the aim of a step",
            self.cells,
            self.at[0],
            self.at[1],
            self.size,
            100.0 * self.share
        )
    }
}

/// A next mesh estimated to have more cells than the mesher's limit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CellLimit {
    /// The estimated cell count.
    pub cells: f64,
    pub limit: usize,
}

impl std::fmt::Display for CellLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "the next mesh would have about {:.1e} triangles, above the limit of {} cells (raise it with --max-cells)",
            self.cells, self.limit
        )
    }
}

/// The [`Stall`] of the target sizes `sizes` on `mesh`, if any: the cells at the smallest
/// size hold at least θ² of Σ_T η_T².
fn stalled(theta: f64, size: f64, mesh: &Mesh, eta: &[f64], sizes: &[f64]) -> Option<Stall> {
    let held: Vec<usize> = (0..sizes.len()).filter(|&c| sizes[c] <= size).collect();
    let total: f64 = eta.iter().map(|e| e * e).sum();
    let share = held.iter().map(|&c| eta[c] * eta[c]).sum::<f64>() / total;
    let worst = held.iter().copied().max_by(|&a, &b| eta[a].total_cmp(&eta[b]))?;
    let at = mesh.cell_centroid(worst);
    (share >= theta * theta).then_some(Stall { size, cells: held.len(), share, at })
}

/// Everything known at the end of a step, for output.
pub struct Step<'a> {
    pub record: &'a StepRecord,
    pub problem: &'a Problem,
    pub disc: &'a Discretisation,
    pub x: &'a [f64],
    pub estimate: &'a Estimate,
    /// The joint of the step's problem and its solution.
    pub joint: Option<&'a ContactJoint>,
    pub contact: Option<&'a ContactSolution>,
}

/// Runs the adaptive loop; `on_step` sees every step as soon as it is solved (and may write
/// it out). Returns the history.
pub fn run(
    settings: &AdaptSettings,
    mesher: &mut dyn Mesher,
    model: &dyn Model,
    mut on_step: impl FnMut(&Step) -> Result<(), AdaptError>,
) -> Result<Vec<StepRecord>, AdaptError> {
    let start = Instant::now();
    let mut history = Vec::new();
    // the previous mesh's state and its target sizes
    let mut previous: Option<(CarriedState, Vec<f64>)> = None;
    let mut kept = None;
    let mut cracks: crate::contact::Cracks = Vec::new();
    for step in 0..settings.steps {
        let mut seconds = PhaseTimes::default();
        let clock = Instant::now();
        let mesh = mesher.mesh(step, previous.as_ref().map(|(state, sizes)| (&state.mesh, &sizes[..])))?;
        seconds.mesh = clock.elapsed().as_secs_f64();
        let (problem, mut joint) = model.problem(mesh)?;
        // the cracks filled by the reservoir start where the previous mesh left them
        for (up, crack) in joint.iter_mut().flat_map(|j| j.uplift.iter_mut()).zip(&cracks) {
            up.diagram.crack = crack.map_or(up.diagram.crack, |c| c.length);
        }
        let clock = Instant::now();
        let disc = problem.discretise();
        seconds.assemble = clock.elapsed().as_secs_f64();
        // the last mesh by count or size, known before its solve: Newton runs to the
        // residual tolerance at once
        let last = step + 1 == settings.steps || settings.max_unknowns.is_some_and(|n| disc.dofs.n_free >= n);
        let clock = Instant::now();
        let (x0, slip_origin) = match &previous {
            Some((state, _)) => state.onto(&problem, &disc),
            None => (vec![0.0; disc.dofs.n_free], None),
        };
        seconds.transfer = clock.elapsed().as_secs_f64();
        let mut level = match &joint {
            None => level::linear_level(&problem, &disc)?,
            Some(joint) => contact_level(settings, model, (&problem, &disc, joint), (x0, slip_origin), kept, last)?,
        };
        // a mesh that turns out to be the last reports the iterate of Newton finished to its
        // residual tolerance, and the tolerance counts as met only on that iterate's estimate
        if !last && settings.met(measures(&problem, &level)) {
            level = level.finish(&model.newton(), settings)?;
        }
        let (mut eta, mut stress) = measures(&problem, &level);
        let mut done = last || settings.met((eta, stress));
        let clock = Instant::now();
        let eta_cells = &level.estimate.estimators.tot;
        let floor = marking::smallest_size(&problem.mesh).max(mesher.size_min().unwrap_or(0.0));
        let tol = settings.tolerance(stress);
        let mut sizes = if done { Vec::new() } else { next_sizes(settings, &problem.mesh, eta_cells, tol, floor) };
        if let Some(c) = level.solution.contact().filter(|_| !sizes.is_empty()) {
            resolve_bonds(&mut sizes, c);
        }
        let stall =
            (!sizes.is_empty()).then(|| stalled(settings.bulk, floor, &problem.mesh, eta_cells, &sizes)).flatten();
        seconds.remesh = clock.elapsed().as_secs_f64();
        let cell_limit = (!done && stall.is_none()).then(|| mesher.over_cell_limit(&problem.mesh, &sizes)).flatten();
        if stall.is_some() || cell_limit.is_some() {
            (done, level) = (true, level.finish(&model.newton(), settings)?);
            (eta, stress) = measures(&problem, &level);
        }
        let contact = level.solution.contact();
        if let Some(c) = contact {
            crate::contact::lifts_off(&problem, &c.nitsche, &c.faces, 1.0)?;
        }
        kept = contact.map(|c| (c.smoothing.delta, level.trend));
        cracks = contact.map_or_else(Vec::new, |c| c.cracks.clone());
        (seconds.solve, seconds.estimate) = (level.solve_seconds, level.estimate_seconds);
        let record = StepRecord {
            stall,
            cell_limit,
            seconds,
            elapsed: start.elapsed().as_secs_f64(),
            ..StepRecord::of_level(step, (&problem, &disc), &level, (eta, stress), settings, model.joint_line(&problem))
        };
        on_step(&Step {
            record: &record,
            problem: &problem,
            disc: &disc,
            x: level.solution.x(),
            estimate: &level.estimate,
            joint: joint.as_ref(),
            contact,
        })?;
        history.push(record);
        if done {
            break;
        }
        let u = problem.displacement(&disc, level.solution.x());
        let slip_origin = level.solution.contact().and_then(|c| c.nitsche.slip_origin()).map(nodal);
        drop(level);
        previous = Some((CarriedState { mesh: problem.mesh, u, slip_origin }, sizes));
    }
    Ok(history)
}

/// The contact level of a step on `problem` with its `joint`, from `start` (the previous
/// mesh's solution carried over, and the slip origin) at the δ and trend `kept` from it (the
/// first mesh starts from the scene's load path); Newton to the residual tolerance at once on
/// the `last` mesh.
fn contact_level<'a>(
    settings: &AdaptSettings,
    model: &dyn Model,
    (problem, disc, joint): (&'a Problem, &'a Discretisation, &ContactJoint),
    start: (Vec<f64>, Option<Vec<f64>>),
    kept: Option<(f64, Option<level::Trend>)>,
    last: bool,
) -> Result<Level<'a>, AdaptError> {
    let delta = kept.map_or_else(
        || StartDelta::FirstIterate { load_scale: problem.stress_scale(&disc.topology), path: model.load_path() },
        |(delta, trend)| StartDelta::Kept(delta, trend),
    );
    let stopping = if last { Stopping::Residual } else { Stopping::Linearisation };
    level::contact_level(problem, disc, joint, &model.newton(), settings, (start, delta), stopping).map_err(|e| {
        if last {
            unfinished(e)
        } else {
            e
        }
    })
}

impl StepRecord {
    /// The record of mesh `step` from its solved `level` and its global estimators and ‖σ_h‖
    /// (`measures`), the joint's crack and resultant read on `line`; no stall, cell limit or
    /// times.
    fn of_level(
        step: usize,
        (problem, disc): (&Problem, &Discretisation),
        level: &Level,
        (eta, stress): (GlobalEstimators, f64),
        settings: &AdaptSettings,
        line: Option<JointLine>,
    ) -> StepRecord {
        let contact = level.solution.contact();
        StepRecord {
            step,
            cells: problem.mesh.n_cells(),
            unknowns: disc.dofs.n_free,
            eta,
            stress_norm: stress,
            delta: contact.map(|c| c.smoothing.delta),
            n_reg: level.n_reg,
            n_lin: level.n_lin,
            finish: level.finish,
            newton_stalled: level.stalled_before_tolerance,
            regularisation_balanced: contact.map(|_| level::regularisation_small(&eta, settings.gamma_reg)),
            n_est: level.n_est,
            equilibration: level.estimate.equilibration.worst(problem.mesh.order),
            i_eff: None,
            i_eff_reference_converged: None,
            crack_length: contact.zip(line).map(|(c, line)| c.crack_from_heel(&line)),
            resultant: contact.zip(line).and_then(|(c, line)| resultant(c, &line)),
            stall: None,
            cell_limit: None,
            seconds: PhaseTimes::default(),
            elapsed: 0.0,
        }
    }
}

/// A Newton failure on the last mesh, where Newton runs to the residual tolerance, as
/// [`AdaptError::Finish`]; other errors as they are.
fn unfinished(e: AdaptError) -> AdaptError {
    match e {
        AdaptError::Newton { .. } => AdaptError::Finish(Box::new(e)),
        e => e,
    }
}

/// A bonded joint's face resolves its softening only while h_F < γ₀ E o_c / σ_t (docs/method.md
/// §1.13; γ = γ₀ E / h_F): the target size of each cell owning such a face is held at half that,
/// so that a remesh does not coarsen the joint past it.
fn resolve_bonds(sizes: &mut [f64], contact: &ContactSolution) {
    for face in &contact.nitsche.faces {
        let Some(bond) = contact.nitsche.laws[face.curve].bond else { continue };
        let largest = face.length * face.gamma * bond.critical_opening() / bond.tensile_strength;
        sizes[face.cell] = sizes[face.cell].min(0.5 * largest);
    }
}

/// The global estimators of a level and ‖σ_h‖ of its reconstruction.
fn measures(problem: &Problem, level: &Level) -> (GlobalEstimators, f64) {
    (level.estimate.estimators.global(), stress_norm(problem, &level.estimate.reconstruction))
}

/// Target cell sizes for the next mesh (empty for uniform refinement, which needs none).
fn next_sizes(settings: &AdaptSettings, mesh: &Mesh, eta: &[f64], tol: Option<f64>, floor: f64) -> Vec<f64> {
    match settings.refinement {
        Refinement::Adaptive => settings.marking.target_sizes(settings.bulk, eta, mesh, tol, floor),
        Refinement::Uniform => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stall_needs_theta_squared_of_the_estimate_at_the_smallest_size() {
        let mesh = crate::mesh::structured::unit_square(2, 1);
        let floor = marking::smallest_size(&mesh);
        let n = mesh.n_cells();
        let mut eta = vec![1.0; n];
        eta[0] = 2.0;
        let mut sizes = vec![0.1; n];
        sizes[0] = floor;
        // cell 0 holds 4 / (4 + n − 1) = 4/11 of η² on the 8 cells
        let share = 4.0 / (n as f64 + 3.0);
        assert_eq!(n, 8);
        assert!(stalled(0.5, floor, &mesh, &eta, &sizes).is_some(), "4/11 ≥ 0.5²");
        assert!(stalled(0.7, floor, &mesh, &eta, &sizes).is_none(), "4/11 < 0.7²");
        let stall = stalled(share.sqrt(), floor, &mesh, &eta, &sizes).expect("θ² = the share");
        assert_eq!((stall.cells, stall.size), (1, floor));
        assert!((stall.share - share).abs() < 1e-15);
        assert!(stalled(share.sqrt() * 1.01, floor, &mesh, &eta, &sizes).is_none());
        assert!(stalled(0.1, floor, &mesh, &eta, &vec![0.1; n]).is_none(), "no cell at the smallest size");
    }
}
