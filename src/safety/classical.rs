//! The classical gravity method (US Army Corps of Engineers, EM 1110-2-2100, Stability Analysis
//! of Concrete Structures, 2005, chapter 3; EM 1110-2-2200, Gravity Dam Design, 1995, chapter 4;
//! CADAM's "gravity method"): the section above the sliding plane as a rigid body on a plane
//! base, a linear base pressure, and the uplift diagram of the joint with the guideline's crack.
//!
//! # Frame
//!
//! The base runs from the heel to the toe, length L, τ the unit vector from the heel to the
//! toe and ν the unit normal from the section into the foundation. A force F acting at x, with
//! r = x − x_toe, has
//!
//!   V = F·ν (pressing on the base), H = F·τ (pushing towards the toe),
//!   d = −r·τ (upstream of the toe), h = −r·ν (above the base),
//!
//! and the moment about the toe M = V d − H h: positive where it holds the heel down
//! (resisting), negative where it lifts it (overturning). A distributed load is summed point
//! by point; its arms are d_V = ∫ V d / V and h_H = ∫ H h / H.
//!
//! # The loads
//!
//! From the finite-element problem itself ([`section_loads`]): the weight ρ g A (0, −1) and the
//! inertia ρ g A (a_x, a_y) of every cell of the section, at its centroid; the tractions of its
//! Neumann faces with the problem's own quadrature (exact for the piecewise-linear water
//! pressure), each face's water called reservoir (n·τ < 0, the upstream face), tailwater
//! (n·τ > 0) or crest water (a face parallel to the base, facing up); the uplift of the joint's
//! diagram ([`Uplift`]), U = ∫ p_u ds at s_U = ∫ p_u s ds / U from the heel.
//!
//! # The answer ([`Classical::solve`])
//!
//! With P = Σ V (every load but the uplift), N = P − U, T = Σ H and M = Σ M (the uplift's
//! −U (L − s_U) included), the resultant of the base pressure acts at d_R = M / N from the toe,
//! s_R = L − d_R from the heel, e = s_R − L/2. Beam theory gives the effective normal stress,
//! tension positive,
//!
//!   σ_heel = −N/L (1 − 6e/L),   σ_toe = −N/L (1 + 6e/L).
//!
//! When σ_heel > 0 the base cracks from the heel (EM 1110-2-2100 §3-3 and Appendix C): the
//! crack T leaves L_c = L − T in compression with a triangular pressure, zero at the crack tip
//! and −2N/L_c at the toe, so d_R(T) = L_c / 3; under the joint's crack rule (`crack = "full"`)
//! the reservoir pressure fills the crack and U, s_U follow T (`none`: the crack is dry and U
//! falls with T; `unchanged`, `ignore`: the diagram before the earthquake, whatever T). T is the smallest root of
//! g(T) = L − T − 3 d_R(T) on [0, L], bracketed by a scan and refined by bisection.
//!
//! - sliding (Mohr–Coulomb on the plane, limit equilibrium): FS = (c L_c + tan φ N) / |T|,
//!   N and T normal and tangential to the plane (for an inclined plane, the loads resolved
//!   on it; no separate (1 − tan φ tan β) term), c L_c the cohesion on the compressed length
//!   (a Tresca threshold s gives s L_c);
//! - overturning: FS_OT = Σ M⁺ / Σ |M⁻| about the toe, each load's V d_V and −H h_H counted
//!   apart (the uplift overturns);
//! - flotation: FS_F = P / U, the loads pressing on the base over the uplift.

use crate::contact::{ContactJoint, CrackRule, JointLaw, JointLine, Uplift};
use crate::elasticity::problem::traction_rule;
use crate::elasticity::{BodyForce, Problem, Traction};
use crate::geometry::{distance, dot, sub, Point, Segment, Vector};
use crate::mesh::Topology;
use serde::Serialize;

/// Cells of the scan of g(T) over [0, L] that brackets the crack.
const SCAN: usize = 1000;
/// Bisection steps on the bracket: its width falls below 2⁻⁶⁰ L / SCAN.
const BISECTION: usize = 60;

/// What a load is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoadKind {
    Weight,
    /// The pseudo-static inertia ρ g A a.
    Inertia,
    /// Water on the upstream face (n·τ < 0).
    Reservoir,
    /// Water on the downstream face (n·τ > 0).
    Tailwater,
    /// Water on a face parallel to the base, facing up (over the crest).
    CrestWater,
    /// Westergaard's added pressure on the reservoir's faces.
    Hydrodynamic,
    /// Silt's horizontal earth pressure.
    Silt,
    /// The ice sheet's thrust.
    Ice,
    /// Any other traction of a Neumann curve.
    Traction,
    Uplift,
}

impl LoadKind {
    /// The load's name in a report.
    pub fn label(&self) -> &'static str {
        match self {
            LoadKind::Weight => "weight",
            LoadKind::Inertia => "inertia (pseudo-static)",
            LoadKind::Reservoir => "reservoir (upstream face)",
            LoadKind::Tailwater => "tailwater (downstream face)",
            LoadKind::CrestWater => "water on the crest",
            LoadKind::Hydrodynamic => "hydrodynamic (Westergaard)",
            LoadKind::Silt => "silt",
            LoadKind::Ice => "ice",
            LoadKind::Traction => "other tractions",
            LoadKind::Uplift => "uplift",
        }
    }
}

/// One load on the section in the base's frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Load {
    pub kind: LoadKind,
    /// V = Σ F·ν \[N/m\], pressing on the base.
    pub normal: f64,
    /// d_V \[m\]: where V acts, upstream of the toe (0 when V = 0).
    pub normal_arm: f64,
    /// H = Σ F·τ \[N/m\], towards the toe.
    pub shear: f64,
    /// h_H \[m\]: where H acts, above the base (0 when H = 0).
    pub shear_arm: f64,
    /// M = V d_V − H h_H \[N m/m\] about the toe, resisting positive.
    pub moment: f64,
}

/// Sums V, ∫ V d, H, ∫ H h of a load.
#[derive(Debug, Clone, Copy, Default)]
struct Sums {
    normal: f64,
    normal_moment: f64,
    shear: f64,
    shear_moment: f64,
}

impl Sums {
    fn load(&self, kind: LoadKind) -> Load {
        let arm = |moment: f64, force: f64| if force != 0.0 { moment / force } else { 0.0 };
        Load {
            kind,
            normal: self.normal,
            normal_arm: arm(self.normal_moment, self.normal),
            shear: self.shear,
            shear_arm: arm(self.shear_moment, self.shear),
            moment: self.normal_moment - self.shear_moment,
        }
    }
}

/// The plane base: the joint from the heel to the toe and ν, from the section into the
/// foundation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Base {
    pub line: JointLine,
    pub normal: Vector,
}

impl Base {
    /// The toe.
    pub fn toe(&self) -> Point {
        self.line.point(self.line.length)
    }

    /// Adds the force `f` at `x` to `sums`: V, V d, H, H h.
    fn add(&self, sums: &mut Sums, f: Vector, x: Point) {
        let (tau, nu, toe) = (self.line.along, self.normal, self.toe());
        let r = sub(x, toe);
        let (v, h) = (dot(f, nu), dot(f, tau));
        sums.normal += v;
        sums.normal_moment += v * -dot(r, tau);
        sums.shear += h;
        sums.shear_moment += h * -dot(r, nu);
    }
}

/// The section above the sliding plane on `problem`'s mesh: the bodies whose cells touch the
/// faces of the joint's curves (either side of a joint between two bodies) on `line` from
/// above (y up), ν the unit normal of the line pointing down into the foundation; per cell
/// whether it is the section's, and per curve of the joint whether it has a face on the plane.
/// Err: why there is none.
pub fn section(problem: &Problem, joint: &ContactJoint, line: &JointLine) -> Result<Section, String> {
    let mesh = &problem.mesh;
    let topology = Topology::new(mesh);
    let on_line = |f: usize| mesh.facet(f)[..2].iter().all(|&n| line.holds(mesh.points[n]));
    let [tx, ty] = line.along;
    if tx.abs() <= 1e-9 {
        return Err("the sliding plane is vertical: no side of it lies above the other".into());
    }
    // ν ⟂ τ with ν_y < 0
    let normal = if tx > 0.0 { [ty, -tx] } else { [-ty, tx] };
    let sides: Vec<i32> = joint.tags.iter().chain(&joint.masters).copied().collect();
    let faces: Vec<usize> = mesh.facets_tagged(&sides).filter(|&f| on_line(f)).collect();
    let above = |c: usize| dot(sub(mesh.cell_centroid(c), line.heel), normal) < 0.0;
    let bodies = bodies_apart(problem, &topology, line);
    let resting: Vec<usize> =
        faces.iter().map(|&f| topology.tagged_cell(f)).filter(|&c| above(c)).map(|c| bodies[c]).collect();
    if resting.is_empty() {
        return Err("no face of the joint on the sliding plane has a body above it".into());
    }
    let cells = bodies.iter().map(|b| resting.contains(b)).collect();
    let plane = joint.tags.iter().map(|t| faces.iter().any(|&f| mesh.facet_tags[f] == *t)).collect();
    Ok(Section { base: Base { line: *line, normal }, cells, plane })
}

/// The body of each cell: the cells joined through their edges, but not across an edge on
/// `line` (the nodes of a joint between two bodies need not be split).
fn bodies_apart(problem: &Problem, topology: &Topology, line: &JointLine) -> Vec<usize> {
    let mesh = &problem.mesh;
    let mut parent: Vec<usize> = (0..mesh.n_cells()).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    for (edge, cells) in topology.facets.iter().zip(&topology.facet_cells) {
        let on_line = edge.iter().all(|&n| line.holds(mesh.points[n]));
        if cells[1] != crate::mesh::topology::NONE && !on_line {
            let (a, b) = (root(&mut parent, cells[0]), root(&mut parent, cells[1]));
            parent[a] = b;
        }
    }
    (0..mesh.n_cells()).map(|c| root(&mut parent, c)).collect()
}

/// The section of [`section`].
pub struct Section {
    pub base: Base,
    /// Per cell: whether it is the section's.
    pub cells: Vec<bool>,
    /// Per curve of the joint: whether it has a face on the sliding plane.
    pub plane: Vec<bool>,
}

/// The loads on the cells of the section (`cells`) other than the uplift, in the frame of
/// `base`: the weight and the inertia of the acceleration `acceleration` (in g, g =
/// `gravity`), which must be the problem's body force, then the tractions of its faces.
pub fn section_loads(
    problem: &Problem,
    base: &Base,
    cells: &[bool],
    gravity: f64,
    acceleration: Vector,
) -> Result<Vec<Load>, String> {
    let [a_x, a_y] = acceleration;
    match problem.body_force {
        BodyForce::None if gravity == 0.0 => {}
        BodyForce::Acceleration(f) if f == [gravity * a_x, gravity * (a_y - 1.0)] => {}
        _ => return Err("the body force is not the weight with a uniform acceleration".into()),
    }
    let mesh = &problem.mesh;
    let (mut weight, mut inertia) = (Sums::default(), Sums::default());
    for c in (0..mesh.n_cells()).filter(|&c| cells[c]) {
        let [p, q, r] = mesh.cell_vertices(c);
        let area = 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])).abs();
        let mass_g = problem.materials[c].density * gravity * area;
        let centroid = mesh.cell_centroid(c);
        base.add(&mut weight, [0.0, -mass_g], centroid);
        base.add(&mut inertia, [mass_g * a_x, mass_g * a_y], centroid);
    }
    let mut loads = vec![weight.load(LoadKind::Weight)];
    if acceleration != [0.0; 2] && gravity != 0.0 {
        loads.push(inertia.load(LoadKind::Inertia));
    }
    loads.extend(traction_loads(problem, base, cells));
    Ok(loads)
}

/// The kind of the traction `t` on a face of outward normal n.
fn kind_of(t: &Traction, n: Vector, base: &Base) -> LoadKind {
    let along = dot(n, base.line.along);
    let down = dot(n, base.normal);
    match t {
        Traction::Silt { .. } => LoadKind::Silt,
        Traction::Ice { .. } => LoadKind::Ice,
        Traction::Hydrostatic { .. } | Traction::Westergaard { .. } if along < -1e-9 => LoadKind::Reservoir,
        Traction::Hydrostatic { .. } | Traction::Westergaard { .. } if along > 1e-9 => LoadKind::Tailwater,
        Traction::Hydrostatic { .. } | Traction::Westergaard { .. } if down < 0.0 => LoadKind::CrestWater,
        _ => LoadKind::Traction,
    }
}

/// The tractions of the Neumann faces of the section's cells, one load per kind that acts.
fn traction_loads(problem: &Problem, base: &Base, cells: &[bool]) -> Vec<Load> {
    let mesh = &problem.mesh;
    let topology = Topology::new(mesh);
    let kinds = [
        LoadKind::Reservoir,
        LoadKind::Tailwater,
        LoadKind::CrestWater,
        LoadKind::Traction,
        LoadKind::Hydrodynamic,
        LoadKind::Silt,
        LoadKind::Ice,
    ];
    let mut sums = [Sums::default(); 7];
    let hydrodynamic = kinds.iter().position(|&k| k == LoadKind::Hydrodynamic).expect("a kind");
    for bc in &problem.neumann {
        let faces = mesh.facets_tagged(std::slice::from_ref(&bc.tag));
        for f in faces.filter(|&f| cells[topology.tagged_cell(f)]) {
            let n = topology.outward_normal(mesh, f);
            let ends = [mesh.points[mesh.facet(f)[0]], mesh.points[mesh.facet(f)[1]]];
            let segment = Segment::new(ends[0], ends[1]);
            let rule = traction_rule(&bc.traction, ends, mesh.order);
            for part in bc.traction.parts() {
                let k = kinds.iter().position(|&k| k == kind_of(part, n, base)).expect("a kind");
                for &(s, w) in &rule {
                    let x = segment.point(s);
                    // the added pressure apart from the water's own
                    let (g, added) = (part.at(x, n), part.hydrodynamic(x, n));
                    let scale = w * segment.length();
                    base.add(&mut sums[k], [(g[0] - added[0]) * scale, (g[1] - added[1]) * scale], x);
                    base.add(&mut sums[hydrodynamic], [added[0] * scale, added[1] * scale], x);
                }
            }
        }
    }
    let acts = |s: &Sums| s.normal != 0.0 || s.shear != 0.0;
    kinds.iter().zip(&sums).filter(|(_, s)| acts(s)).map(|(&k, s)| s.load(k)).collect()
}

/// The uplift diagram and the joint law of the sliding plane of `joint` on `line`, whose
/// curves are those with `plane`: the one diagram on them (none: no uplift), along the same
/// line, and their one law.
pub fn plane_of<'j>(
    joint: &'j ContactJoint,
    line: &JointLine,
    plane: &[bool],
) -> Result<(Option<&'j Uplift>, JointLaw), String> {
    let on_plane = |u: &&crate::contact::CurveUplift| u.curves.iter().any(|&k| plane[k]);
    let diagrams: Vec<&Uplift> = joint.uplift.iter().filter(on_plane).map(|u| &u.diagram).collect();
    if diagrams.iter().any(|d| !same_line(&d.line, line)) {
        return Err("the uplift diagram of the sliding plane runs along another line".into());
    }
    if diagrams.len() > 1 {
        return Err("the sliding plane has several uplift diagrams; the classical method takes one".into());
    }
    let mut laws = joint.laws.iter().zip(plane).filter(|(_, &on)| on).map(|(c, _)| c.law);
    let law = laws.next().ok_or("the joint has no curve")?;
    if laws.any(|l| l != law) {
        return Err("the curves of the sliding plane have different laws; the classical method takes one".into());
    }
    Ok((diagrams.first().copied(), law))
}

/// Whether two joint lines share their heel and length (to 10⁻⁹ of the length).
fn same_line(a: &JointLine, b: &JointLine) -> bool {
    let tol = 1e-9 * b.length;
    distance(a.heel, b.heel) <= tol && (a.length - b.length).abs() <= tol
}

/// The gravity method's answer on one section (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Classical {
    /// The loads, the uplift last (at the crack below).
    pub loads: Vec<Load>,
    /// L \[m\].
    pub length: f64,
    /// P = Σ V of the loads but the uplift, U, N = P − U and T = Σ H \[N/m\].
    pub pressing_force: f64,
    pub uplift_force: f64,
    pub normal_force: f64,
    pub shear_force: f64,
    /// Σ M⁺ and Σ |M⁻| about the toe \[N m/m\].
    pub resisting_moment: f64,
    pub overturning_moment: f64,
    /// FS = (c L_c + tan φ N) / |T| (None without a tangential strength or without shear).
    pub sliding_factor: Option<f64>,
    /// Σ M⁺ / Σ |M⁻| (None: nothing overturns).
    pub overturning_factor: Option<f64>,
    /// P / U (None without uplift).
    pub flotation_factor: Option<f64>,
    /// s_R from the heel, d_R = L − s_R from the toe, e = s_R − L/2 \[m\].
    pub resultant_position: f64,
    pub resultant_from_toe: f64,
    pub eccentricity: f64,
    /// The crack T from the heel and the compressed length L_c = L − T \[m\].
    pub crack: f64,
    pub compressed_length: f64,
    /// σ'^n at the heel (0 in a crack) and at the toe by beam theory \[Pa\], tension positive.
    pub heel_stress: f64,
    pub toe_stress: f64,
    /// What the water does in the crack (None without uplift).
    pub crack_rule: Option<CrackRule>,
    /// The toe in tension: the method cracks the heel only, so the stresses are uncracked.
    pub toe_in_tension: bool,
}

/// N, M and d_R of the section with the crack T.
struct State {
    uplift: Load,
    normal: f64,
    moment: f64,
}

impl State {
    fn resultant_arm(&self) -> f64 {
        self.moment / self.normal
    }
}

impl Classical {
    /// The answer for the `loads` (no uplift among them) on a base of length L = `length`, with
    /// the uplift diagram `uplift` (None: none) and the joint law `law` of the plane.
    pub fn solve(loads: Vec<Load>, length: f64, uplift: Option<&Uplift>, law: JointLaw) -> Result<Self, String> {
        let pressing: f64 = loads.iter().map(|l| l.normal).sum();
        let moment: f64 = loads.iter().map(|l| l.moment).sum();
        let state = |crack: f64| {
            let uplift = uplift_load(uplift, length, crack);
            State { normal: pressing + uplift.normal, moment: moment + uplift.moment, uplift }
        };
        let uncracked = state(0.0);
        if uncracked.normal <= 0.0 {
            return Err(format!(
                "the section floats: the loads press on the base with {pressing:.4e} N/m against an uplift of {:.4e} N/m",
                -uncracked.uplift.normal
            ));
        }
        let d = uncracked.resultant_arm();
        let crack = if d < length / 3.0 { crack_length(&state, length)? } else { 0.0 };
        let at = state(crack);
        let (n, lc) = (at.normal, length - crack);
        let (s_r, e) = (length - at.resultant_arm(), length / 2.0 - at.resultant_arm());
        let toe_in_tension = crack == 0.0 && e < -length / 6.0;
        let (heel_stress, toe_stress) = match crack > 0.0 {
            true => (0.0, -2.0 * n / lc),
            false => (-n / length * (1.0 - 6.0 * e / length), -n / length * (1.0 + 6.0 * e / length)),
        };
        let mut all = loads;
        all.push(at.uplift);
        let shear: f64 = all.iter().map(|l| l.shear).sum();
        let parts = all.iter().flat_map(|l| [l.normal * l.normal_arm, -l.shear * l.shear_arm]);
        let (resisting, overturning) =
            parts.fold((0.0, 0.0), |(r, o), m| if m > 0.0 { (r + m, o) } else { (r, o - m) });
        let strength = law.capacity(n, lc);
        Ok(Classical {
            length,
            pressing_force: pressing,
            uplift_force: -at.uplift.normal,
            normal_force: n,
            shear_force: shear,
            resisting_moment: resisting,
            overturning_moment: overturning,
            sliding_factor: (law.has_friction() && shear != 0.0).then(|| strength / shear.abs()),
            overturning_factor: (overturning > 0.0).then(|| resisting / overturning),
            flotation_factor: (at.uplift.normal < 0.0).then(|| pressing / -at.uplift.normal),
            resultant_position: s_r,
            resultant_from_toe: at.resultant_arm(),
            eccentricity: e,
            crack,
            compressed_length: lc,
            heel_stress,
            toe_stress,
            crack_rule: uplift.map(|u| u.rule),
            toe_in_tension,
            loads: all,
        })
    }

    /// The share of the base in compression, L_c / L.
    pub fn compressed_fraction(&self) -> f64 {
        self.compressed_length / self.length
    }
}

/// The uplift with the crack T as a load: V = −U at d = L − s_U (no uplift: a zero load).
fn uplift_load(uplift: Option<&Uplift>, length: f64, crack: f64) -> Load {
    let mut sums = Sums::default();
    if let Some(u) = uplift {
        // ∫ p_u (L − s) ds = U L − M_u, pushing away from the foundation
        let (force, first) = (u.force(crack), u.moment(crack));
        sums.normal = -force;
        sums.normal_moment = -(force * length - first);
    }
    sums.load(LoadKind::Uplift)
}

/// The crack T: the smallest root of g(T) = L − T − 3 d_R(T) on [0, L] (g(0) > 0), or why there
/// is none (the resultant leaves the base, or N ≤ 0 first).
fn crack_length(state: &impl Fn(f64) -> State, length: f64) -> Result<f64, String> {
    let g = |t: f64| -> Result<f64, String> {
        let s = state(t);
        if s.normal <= 0.0 {
            return Err(format!(
                "with a crack of {t:.3} m from the heel the uplift lifts the section (N = {:.4e} N/m): it overturns",
                s.normal
            ));
        }
        Ok(length - t - 3.0 * s.resultant_arm())
    };
    let mut lo = 0.0;
    for k in 1..=SCAN {
        let hi = length * k as f64 / SCAN as f64;
        if g(hi)? <= 0.0 {
            let mut bracket = (lo, hi);
            for _ in 0..BISECTION {
                let mid = 0.5 * (bracket.0 + bracket.1);
                bracket = if g(mid)? > 0.0 { (mid, bracket.1) } else { (bracket.0, mid) };
            }
            return Ok(0.5 * (bracket.0 + bracket.1));
        }
        lo = hi;
    }
    Err("no crack keeps the resultant within the base: the section overturns about its toe".into())
}

/// The gravity method on the section of `problem` above the sliding plane `line` of `joint`,
/// with the scene's `gravity` and `acceleration` (in g).
pub fn classical(
    problem: &Problem,
    joint: &ContactJoint,
    line: &JointLine,
    gravity: f64,
    acceleration: Vector,
) -> Result<Classical, String> {
    let Section { base, cells, plane } = section(problem, joint, line)?;
    let loads = section_loads(problem, &base, &cells, gravity, acceleration)?;
    let (uplift, law) = plane_of(joint, line, &plane)?;
    Classical::solve(loads, line.length, uplift, law)
}

#[cfg(test)]
mod tests;
