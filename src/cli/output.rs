//! ParaView files and summaries of one solution, shared by `solve` and `adapt`.

use crate::contact::{
    Bond, BondLengths, CoarseSolve, ContactSolution, Crack, CrackRule, FaceState, JointForces, JointLaw, JointLine,
    PathPoint,
};
use crate::elasticity::kernels::{principal, von_mises};
use crate::elasticity::{Discretisation, Problem};
use crate::estimate::estimators::{GlobalEstimators, NAMES};
use crate::estimate::Estimate;
use crate::geometry::{norm, Point, Vector};
use crate::io::atomic::Provisional;
use crate::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
use crate::mesh::Mesh;
use crate::safety::resultant::{resultant, Resultant};
use crate::scene::{OutputSection, Scene};
use anyhow::Result;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Names of the reconstructed stress components.
const SIGMA_H: [&str; 4] = ["sigma_h_xx", "sigma_h_xy", "sigma_h_yx", "sigma_h_yy"];

/// One solution as the output files need it.
pub struct Results<'a> {
    pub problem: &'a Problem,
    /// Nodal displacements.
    pub u: &'a [Vector],
    /// Cell means of σ(u_h) [xx, yy, xy, zz].
    pub sigma: &'a [[f64; 4]],
    pub contact: Option<&'a ContactSolution>,
    pub estimate: Option<&'a Estimate>,
}

/// What `summary.json` records of an estimate.
#[derive(Serialize)]
pub struct EstimateSummary {
    pub global: GlobalEstimators,
    pub equilibration: serde_json::Value,
}

impl EstimateSummary {
    /// The global estimators and checks of `e` on a mesh of degree `order`; the weak symmetry
    /// is tested against P_{p−1} rotations, so for P1 it is "not applicable".
    pub fn new(e: &Estimate, order: usize) -> Self {
        let mut equilibration = serde_json::json!(e.equilibration);
        if order < 2 {
            equilibration["weak_symmetry"] = NOT_APPLICABLE.into();
        }
        EstimateSummary { global: e.estimators.global(), equilibration }
    }
}

/// The units of the numbers in the JSON files: SI, per metre of dam (plane strain).
#[derive(Serialize, Clone, Copy)]
pub struct Units {
    length: &'static str,
    stress: &'static str,
    force: &'static str,
    residual: &'static str,
    estimator: &'static str,
    time: &'static str,
}

/// The units every JSON file states.
pub const UNITS: Units = Units {
    length: "m (coordinates, lengths, displacements, mesh sizes)",
    stress: "Pa (stresses, pressures, delta, stress_scale)",
    force: "N/m (forces per metre of dam)",
    residual: "N/m (Newton residuals; relative residuals have no unit)",
    estimator: "Pa m (eta_* and stress norms: L2 norms of stresses over the section)",
    time: "s",
};

/// The units of the JSON files of a solid: SI, forces in newtons.
pub const SOLID_UNITS: Units = Units {
    length: "m (coordinates, lengths, displacements, mesh sizes)",
    stress: "Pa (stresses, pressures)",
    force: "N",
    residual: "N",
    estimator: "Pa m^(3/2) (L2 norms of stresses over the solid)",
    time: "s",
};

/// The physical names of the numeric tags of the VTU files: `material` (cells) and
/// `physical_tag` (boundary facets).
#[derive(Serialize)]
pub struct TagNames {
    material: BTreeMap<i32, String>,
    physical_tag: BTreeMap<i32, String>,
}

impl TagNames {
    pub fn new<const D: usize>(mesh: &Mesh<D>) -> Self {
        let names = |dim| mesh.groups.iter().filter(|g| g.dim == dim).map(|g| (g.tag, g.name.clone())).collect();
        TagNames { material: names(D as u8), physical_tag: names(D as u8 - 1) }
    }
}

/// What `summary.json` says of the weak-symmetry check on P1 meshes.
const NOT_APPLICABLE: &str = "not applicable (P1)";

/// Writes `<name>.vtu`, and as the scene asks `<name>_boundary.vtu` and `<name>_dg.vtu`, each
/// added to `written` once written; returns their paths, `<name>.vtu` first.
pub fn write_results(
    dir: &Path,
    name: &str,
    scene: &Scene,
    results: &Results,
    written: &mut Provisional,
) -> Result<Vec<PathBuf>> {
    let Results { problem, u, sigma, contact, estimate } = *results;
    let mut files = vec![dir.join(format!("{name}.vtu"))];
    let mut cells = stress_fields(sigma);
    if let Some(e) = estimate {
        cells.extend(estimate_fields(e, &scene.output));
        if scene.output.reconstruction {
            let dg = dir.join(format!("{name}_dg.vtu"));
            let fields: Vec<Field> =
                SIGMA_H.iter().zip(e.reconstruction.vertex_values()).map(|(n, v)| Field::scalar(*n, "Pa", v)).collect();
            write_mesh_vtu(&dg, &problem.mesh.discontinuous(), &fields, &[])?;
            written.add(&dg);
            files.push(dg);
        }
    }
    write_mesh_vtu(&files[0], &problem.mesh, &[Field::vector("displacement", "m", u.to_vec())], &cells)?;
    written.add(&files[0]);
    if scene.output.boundary {
        let boundary = dir.join(format!("{name}_boundary.vtu"));
        let facet_fields = contact.map(|c| contact_fields(problem.mesh.n_facets(), c)).unwrap_or_default();
        write_boundary_vtu(&boundary, &problem.mesh, &[Field::vector("displacement", "m", u.to_vec())], &facet_fields)?;
        written.add(&boundary);
        files.push(boundary);
    }
    Ok(files)
}

/// Cell fields: σ components, von Mises and principal stresses.
fn stress_fields(sigma: &[[f64; 4]]) -> Vec<Field> {
    let component = |k: usize| sigma.iter().map(|s| s[k]).collect();
    let principal: Vec<[f64; 2]> = sigma.iter().map(|&s| principal(s)).collect();
    vec![
        Field::scalar("sigma_xx", "Pa", component(0)),
        Field::scalar("sigma_yy", "Pa", component(1)),
        Field::scalar("sigma_xy", "Pa", component(2)),
        Field::scalar("sigma_zz", "Pa", component(3)),
        Field::scalar("von_mises", "Pa", sigma.iter().map(|&s| von_mises(s)).collect()),
        Field::scalar("sigma_1", "Pa", principal.iter().map(|p| p[0]).collect()),
        Field::scalar("sigma_2", "Pa", principal.iter().map(|p| p[1]).collect()),
    ]
}

/// Cell fields the output section asks for: every η component and the cell means of σ_h.
fn estimate_fields(e: &Estimate, output: &OutputSection) -> Vec<Field> {
    let mut fields = Vec::new();
    if output.estimators {
        fields.extend(NAMES.iter().zip(e.estimators.components()).map(|(n, v)| Field::scalar(*n, "Pa m", v.clone())));
    }
    if output.reconstruction {
        fields.extend(SIGMA_H.iter().zip(e.reconstruction.cell_means()).map(|(n, v)| Field::scalar(*n, "Pa", v)));
    }
    fields
}

/// Facet fields of Γ_C, on both sides of a joint between two bodies (the normal displacement
/// and the slip are there the jumps [u]·ν and [u]·τ): mean pressure, mean normal displacement,
/// status (−1 not a contact facet, 0 open, 1 closed: stick with friction, 2 slip), the
/// regularisation error; with friction the mean tangential traction and slip; with a bond the
/// mean damage and the crack state (bonded, softening, broken); with uplift the mean pore
/// pressure and the mean effective normal stress σ'^n = −p_c.
fn contact_fields(n_facets: usize, contact: &ContactSolution) -> Vec<Field> {
    type Column = (&'static str, &'static str, fn(&FaceState) -> f64);
    let mut columns: Vec<Column> = vec![
        ("contact_pressure", "Pa", |f| f.pressure),
        ("normal_displacement", "m", |f| f.normal_displacement),
        ("contact_status", STATUS_UNIT, FaceState::status),
        ("regularisation_error", "Pa", |f| f.regularisation_error),
    ];
    if contact.nitsche.has_friction() {
        columns.extend([
            ("tangential_traction", "Pa", (|f| f.tangential_traction) as fn(&FaceState) -> f64),
            ("slip", "m", |f| f.slip),
        ]);
    }
    if contact.nitsche.has_bond() {
        columns.extend([
            ("damage", "1: opening / critical opening", (|f| f.damage) as fn(&FaceState) -> f64),
            ("crack_state", CRACK_STATE_UNIT, FaceState::bond_state),
        ]);
    }
    if !contact.nitsche.uplift.is_empty() {
        columns.extend([
            ("uplift_pressure", "Pa", (|f| f.uplift) as fn(&FaceState) -> f64),
            ("effective_normal_stress", "Pa", |f| -f.pressure),
        ]);
    }
    let states = contact.facet_states();
    columns
        .into_iter()
        .map(|(name, unit, value)| {
            let code = name == "contact_status" || name == "crack_state";
            let mut field = vec![if code { -1.0 } else { 0.0 }; n_facets];
            for (facet, state) in &states {
                field[*facet] = value(state);
            }
            Field::scalar(name, unit, field)
        })
        .collect()
}

/// The "unit" of `contact_status`: the meaning of its codes.
const STATUS_UNIT: &str = "code: -1 not on the joint, 0 open, 1 closed (stick), 2 slip";

/// The "unit" of `crack_state`: the meaning of its codes (the state of most of the facet).
const CRACK_STATE_UNIT: &str = "code: -1 not on the joint, 0 bonded, 1 softening, 2 broken";

/// What `summary.json` records of a solution (`solve`, and the last step of `adapt`), with
/// the command's own part `command` (flattened into it).
#[derive(Serialize)]
pub struct Summary<T> {
    units: Units,
    scene: PathBuf,
    /// The load combination solved, if not the scene's own loads.
    #[serde(skip_serializing_if = "Option::is_none")]
    combination: Option<String>,
    #[serde(flatten)]
    size: ProblemSize,
    max_displacement: f64,
    max_von_mises: f64,
    /// The centroid of the cell of `max_von_mises`, and what that value is worth.
    max_von_mises_at: Point,
    max_von_mises_note: &'static str,
    min_principal_stress: f64,
    max_principal_stress: f64,
    pub contact: Option<ContactSummary>,
    pub estimate: Option<EstimateSummary>,
    #[serde(flatten)]
    command: T,
    files: Vec<PathBuf>,
    /// The physical names of the tags in the VTU files.
    tags: TagNames,
}

/// The size of a discrete problem, as `summary.json` records it.
#[derive(Serialize)]
pub struct ProblemSize {
    pub order: usize,
    pub nodes: usize,
    pub cells: usize,
    /// Every dof, the constrained ones included.
    pub unknowns: usize,
    pub free_unknowns: usize,
    pub matrix_nonzeros: usize,
}

/// Contact part of the summary.
#[derive(Serialize)]
pub struct ContactSummary {
    /// The contact curves' facets (on a joint between two bodies, the slave side's).
    faces: usize,
    /// On a joint between two bodies, the pieces of those facets that face one master facet
    /// each (docs/method.md §1.10).
    #[serde(skip_serializing_if = "Option::is_none")]
    pieces: Option<usize>,
    /// δ of the last Newton step.
    delta: f64,
    stress_scale: f64,
    /// Length of the zone where P_γ(u_h) < 0 (with a bond: where it is not broken), and its
    /// bounding box [[x, y], [x, y]].
    pub contact_length: f64,
    contact_extent: Option<[Point; 2]>,
    /// Newton steps in all on this mesh: those of `stages` and the discarded ones.
    newton_steps: usize,
    /// Newton steps of the attempts that failed and were discarded (load steps of the path
    /// that were halved).
    discarded_newton_steps: usize,
    /// Newton steps at each δ of the continuation path.
    stages: Vec<(f64, usize)>,
    /// Nested iteration: the unknowns and Newton steps of each coarser mesh whose solution
    /// started Newton, coarsest first (empty: from u = 0).
    coarse: Vec<CoarseSolve>,
    /// The converged states of the load path from rest (docs/method.md §1.11): λ, the crack,
    /// N, T, the contact length, FS_LE and the Newton steps of each (empty: every load at once).
    load_path: Vec<PathPoint>,
    max_pressure: f64,
    max_regularisation_error: f64,
    /// Each curve of Γ_C: its law, Nitsche parameters and forces.
    curves: Vec<CurveSummary>,
    /// With friction, the lengths of the closed part that sticks and that slips \[m\].
    stick_length: f64,
    slip_length: f64,
    /// ∫_{Γ_C} p_c ds and ∫_{Γ_C} t^t ds along τ = (−ν_y, ν_x) \[N/m\].
    pub normal_force: f64,
    pub tangential_force: f64,
    /// With friction, FS_LE = ∫ (c b(P_γ) + F p_c) / |∫ t^t| (docs/method.md §1.7, §1.9, §1.13), on
    /// a Γ_C on one line (joints on several lines have each their own in `curves`).
    sliding_safety_factor: Option<f64>,
    /// With uplift: U = ∫_{Γ_C} p_u ds \[N/m\], and, with one diagram, the crack at the heel
    /// that it fills (each curve's in `curves`).
    pub uplift_force: Option<f64>,
    crack: Option<Crack>,
    /// With one diagram, what the water does in its crack ("filled"; "kept" or "drained" with
    /// the crack before the earthquake, `prior` \[m\]).
    crack_rule: Option<CrackRule>,
    /// On a straight joint whose heel is known (docs/method.md §1.9): the joint from its heel,
    /// the length open at the heel \[m\], and the resultant of the joint traction.
    joint_line: Option<JointLine>,
    pub crack_length: Option<f64>,
    pub resultant: Option<Resultant>,
}

/// One curve of Γ_C in `summary.json`: its physical name (on a joint between two bodies, the
/// slave side's), law, Nitsche parameters and forces; with uplift on it, U = ∫ p_u ds over
/// it \[N/m\] and the crack of its diagram.
#[derive(Serialize)]
struct CurveSummary {
    curve: String,
    #[serde(flatten)]
    law: JointLaw,
    gamma0: f64,
    theta: f64,
    #[serde(flatten)]
    forces: JointForces,
    #[serde(skip_serializing_if = "Option::is_none")]
    uplift_force: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    crack: Option<Crack>,
    #[serde(skip_serializing_if = "Option::is_none")]
    crack_rule: Option<CrackRule>,
    /// A cohesive joint's σ_t and G_f, and the lengths of it that are bonded, softening (the
    /// process zone) and broken \[m\].
    #[serde(flatten)]
    bond: Option<Bond>,
    #[serde(skip_serializing_if = "Option::is_none")]
    bond_lengths: Option<BondLengths>,
}

impl CurveSummary {
    /// Every curve of `c` that has faces.
    fn of_each(mesh: &Mesh, c: &ContactSolution) -> Vec<CurveSummary> {
        let faces = &c.nitsche.faces;
        (c.nitsche.laws.iter().enumerate())
            .filter_map(|(curve, l)| {
                let tag = mesh.facet_tags[faces.iter().find(|f| f.curve == curve)?.facet];
                let name = mesh.groups.iter().find(|g| g.dim == 1 && g.tag == tag).map_or("?", |g| &g.name);
                let diagram = c.nitsche.uplift.iter().position(|up| up.curves.contains(&curve));
                Some(CurveSummary {
                    curve: name.to_string(),
                    law: l.law,
                    gamma0: l.parameters.gamma0,
                    theta: l.parameters.theta,
                    forces: c.forces(|k| faces[k].curve == curve),
                    uplift_force: diagram.map(|_| c.uplift_force_of(|k| faces[k].curve == curve)),
                    crack: diagram.and_then(|d| c.cracks.get(d).copied().flatten()),
                    crack_rule: diagram.map(|d| c.nitsche.uplift[d].diagram.rule),
                    bond: l.bond,
                    bond_lengths: l.bond.map(|_| {
                        BondLengths::of(
                            c.faces.iter().zip(faces).filter(|(_, face)| face.curve == curve).map(|(f, _)| f),
                        )
                    }),
                })
            })
            .collect()
    }
}

/// What is said of a crack of `curve` that stopped at the drain line ([`Crack::at_drains`]).
pub fn drain_note(curve: &str, c: &Crack) -> Option<String> {
    c.at_drains.then(|| {
        format!(
            "the crack of {curve} stops at the drain line, {:.4} m from the heel: with the drains counted the joint \
             opens past them, without them it closes {:.4} m from the heel, so the drains are taken as reached (the \
             larger uplift)",
            c.length,
            c.length - c.change
        )
    })
}

/// A fall of a face's mean damage along the load path above which the run says that the bond
/// healed.
const HEALING: f64 = 1e-3;

/// What `summary.json` says of `max_von_mises`.
pub const SINGULAR_MAXIMUM: &str =
    "mesh-dependent where it sits at a singular point (a re-entrant corner, the end of a \
     contact zone or of a support): a cell mean that grows with every refinement there";

impl<T> Summary<T> {
    /// The summary of `results` on the joint `line` (if known), with the files written and
    /// the command's part.
    pub fn new(
        scene: &Scene,
        disc: &Discretisation,
        results: &Results,
        line: Option<JointLine>,
        files: Vec<PathBuf>,
        command: T,
    ) -> Self {
        let Results { problem, u, sigma, contact, estimate } = *results;
        let principal_stresses: Vec<[f64; 2]> = sigma.iter().map(|&s| principal(s)).collect();
        let peak = (0..sigma.len()).max_by(|&a, &b| von_mises(sigma[a]).total_cmp(&von_mises(sigma[b]))).unwrap_or(0);
        Summary {
            units: UNITS,
            scene: scene.source.clone(),
            combination: scene.combination_name.clone(),
            size: ProblemSize {
                order: problem.mesh.order,
                nodes: problem.mesh.n_points(),
                cells: problem.mesh.n_cells(),
                unknowns: problem.n_dofs(),
                free_unknowns: disc.dofs.n_free,
                matrix_nonzeros: disc.pattern.nnz(),
            },
            max_displacement: u.iter().map(|&v| norm(v)).fold(0.0, f64::max),
            max_von_mises: von_mises(sigma[peak]),
            max_von_mises_at: problem.mesh.cell_centroid(peak),
            max_von_mises_note: SINGULAR_MAXIMUM,
            min_principal_stress: principal_stresses.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            max_principal_stress: principal_stresses.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
            contact: contact.map(|c| ContactSummary::new(problem, disc, c, line)),
            estimate: estimate.map(|e| EstimateSummary::new(e, problem.mesh.order)),
            command,
            files,
            tags: TagNames::new(&problem.mesh),
        }
    }

    /// The closing lines: the numbers that converge under refinement, the largest
    /// displacement and, with contact, the contact length, the joint forces, the crack at the
    /// heel and the resultant. The largest stress sits at a singular point (a re-entrant
    /// corner, the end of the contact zone) and grows with refinement, so it is left to
    /// `summary.json`.
    pub fn headline(&self) -> Vec<String> {
        let mut lines = vec![format!("max |u| = {:.4e} m", self.max_displacement)];
        if let Some(c) = &self.contact {
            lines.push(c.forces_line());
            lines.extend(c.resultant_line());
            lines.extend(c.drain_lines());
            lines.extend(c.bond_lines());
        }
        lines
    }
}

impl ContactSummary {
    fn new(problem: &Problem, disc: &Discretisation, c: &ContactSolution, line: Option<JointLine>) -> Self {
        let mesh = &problem.mesh;
        let in_contact = c.nitsche.faces.iter().zip(&c.faces).filter(|(_, state)| state.contact_length > 0.0);
        let extent = in_contact.flat_map(|(face, _)| mesh.facet(face.facet)[..2].iter().map(|&n| mesh.points[n])).fold(
            None,
            |b: Option<[Point; 2]>, p| {
                let [lo, hi] = b.unwrap_or([p, p]);
                Some([[lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])]])
            },
        );
        ContactSummary {
            faces: c.nitsche.faces.iter().map(|f| f.facet).collect::<std::collections::BTreeSet<_>>().len(),
            pieces: c.nitsche.faces.first().and_then(|f| f.opposite.as_ref()).map(|_| c.nitsche.faces.len()),
            delta: c.smoothing.delta,
            stress_scale: problem.stress_scale(&disc.topology),
            contact_length: c.contact_length(),
            contact_extent: extent,
            newton_steps: c.newton_steps(),
            discarded_newton_steps: c.discarded_steps,
            stages: c.stages.iter().map(|st| (st.delta, st.report.iterations.len())).collect(),
            coarse: c.coarse.clone(),
            load_path: c.path.clone(),
            max_pressure: c.faces.iter().map(|f| f.pressure).fold(0.0, f64::max),
            max_regularisation_error: c.faces.iter().map(|f| f.regularisation_error).fold(0.0, f64::max),
            curves: CurveSummary::of_each(mesh, c),
            stick_length: c.stick_length(),
            slip_length: c.slip_length(),
            normal_force: c.normal_force(),
            tangential_force: c.tangential_force(),
            sliding_safety_factor: c.sliding_safety_factor().filter(|_| c.on_one_line()),
            uplift_force: (!c.nitsche.uplift.is_empty()).then(|| c.uplift_force()),
            crack: if let [crack] = c.cracks[..] { crack } else { None },
            crack_rule: if let [up] = &c.nitsche.uplift[..] { Some(up.diagram.rule) } else { None },
            joint_line: line,
            crack_length: line.map(|l| c.crack_from_heel(&l)),
            resultant: line.and_then(|l| resultant(c, &l)),
        }
    }

    /// "contact length …, N = …, T = …[, U = …]".
    fn forces_line(&self) -> String {
        let uplift = self.uplift_force.map_or(String::new(), |u| format!(", U = {u:.4e} N/m"));
        format!(
            "contact length {:.4} m, joint forces N = {:.4e} N/m, T = {:.4e} N/m{uplift}",
            self.contact_length, self.normal_force, self.tangential_force
        )
    }

    /// One note per curve whose crack stopped at the drain line ([`drain_note`]).
    fn drain_lines(&self) -> Vec<String> {
        (self.curves.iter())
            .filter_map(|curve| curve.crack.and_then(|c| drain_note(&curve.curve, &c)))
            .map(|note| format!("note: {note}"))
            .collect()
    }

    /// "bond of <curve> (σ_t = …, G_f = …): bonded …, process zone …, broken … m", per curve with
    /// a bond.
    fn bond_lines(&self) -> Vec<String> {
        let healed = self.load_path.windows(2).max_by(|a, b| a[1].healing.total_cmp(&b[1].healing));
        let warning = healed.filter(|w| w[1].healing > HEALING).map(|w| {
            format!(
                "warning: the bond healed on the load path: a face's mean damage fell by {:.3} from λ = {:.4} to \
                 λ = {:.4}, which the holonomic law of docs/method.md §1.13 allows and an irreversible bond would not; \
                 the result may differ from it there",
                w[1].healing, w[0].load_factor, w[1].load_factor
            )
        });
        (self.curves.iter())
            .filter_map(|curve| {
                let (bond, l) = (curve.bond?, curve.bond_lengths.as_ref()?);
                Some(format!(
                    "bond of {} (tensile strength {:.4e} Pa, fracture energy {:.4e} N/m): bonded {:.4} m, process zone \
                     {:.4} m, broken {:.4} m",
                    curve.curve, bond.tensile_strength, bond.fracture_energy, l.bonded, l.process_zone, l.broken
                ))
            })
            .chain(warning)
            .collect()
    }

    /// "crack … m from the heel, resultant at … m from the heel (e = … m, …)", on a straight
    /// joint with a heel.
    fn resultant_line(&self) -> Option<String> {
        let crack = self.crack_length?;
        let resultant = self.resultant.map_or(", nothing presses on the joint".into(), |r| {
            let third = if r.middle_third { "inside" } else { "outside" };
            format!(
                ", resultant at {:.4} m from the heel (e = {:.4} m, {third} the middle third)",
                r.position, r.eccentricity
            )
        });
        let open = if self.curves.iter().any(|c| c.bond.is_some()) { "broken" } else { "open" };
        Some(format!("crack {crack:.4} m {open} from the heel{resultant}"))
    }
}
