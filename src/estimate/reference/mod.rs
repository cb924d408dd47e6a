//! The dual norm of the residual of a discrete displacement, computed on a finer space.
//!
//! **A verification tool**: it gives an independent measure of the error of u_h, against
//! which the guaranteed upper bound of the estimator is tested. It is far more expensive than
//! a solve on the coarse mesh and is not meant for production runs.
//!
//! For a discrete displacement u_h of the problem (docs/method.md §2),
//!
//!   ⟨R(u_h), v⟩ = (f, v) + (g_N, v)_{Γ_N} + ([P_γ(u_h)]_{R⁻}, v^n)_{Γ_C} − (σ(u_h), ε(v)),
//!
//! with the exact projection \[x\]_{R⁻} = min(x, 0), P_γ(u_h) = σ^n(u_h) − γ(u_h^n − g) and
//! γ|_F = γ₀ E / h_F on each coarse contact face F. The test functions v vanish on Γ_D (only
//! the fixed components of a roller). The norm on the test space is
//!
//!   ‖v‖²_{C,h} = ‖∇v‖²_Ω + Σ_{F ⊂ Γ_C} h_F⁻¹ ‖v‖²_F      (h_F the coarse face length),
//!
//! and ‖R(u_h)‖ = sup ⟨R(u_h), v⟩ / ‖v‖_{C,h}. Its Riesz representative is approximated in a
//! conforming space V_fine ⊂ H¹_D: vector P2 Lagrange on the coarse mesh refined uniformly
//! `levels` times (it contains the coarse P1 and P2 spaces). r ∈ V_fine solves
//!
//!   (∇r, ∇v) + Σ_F h_F⁻¹ (r, v)_F = ⟨R(u_h), v⟩   for all v ∈ V_fine,
//!
//! and ‖r‖_{C,h} = sup over V_fine ≤ ‖R(u_h)‖: a lower bound that grows with `levels`
//! (the spaces are nested) and converges to ‖R(u_h)‖ from below.
//!
//! Integration. u_h is a polynomial of degree p on each coarse cell: at a fine quadrature
//! point, u_h and ∇u_h are evaluated in the parent coarse cell (inverse affine map), σ(u_h)
//! with that cell's material. Volume terms use a rule of degree 8 on each fine cell. On a fine
//! contact face, P_γ(u_h) comes from the coarse cell owning the coarse face; it is a
//! polynomial of degree p along the face, so the face is split at the roots of P_γ(u_h) = 0
//! and each piece is integrated exactly by 4 Gauss points. Neumann faces use 6 Gauss points
//! per piece, hydrostatic loads being split at the water level.
//!
//! Linear algebra. The Gram matrix is block diagonal in the components, so each component is
//! a scalar problem (Laplacian plus the Γ_C face mass) with its own Dirichlet nodes, solved
//! by sparse Cholesky; when both components have the same Dirichlet nodes, one factorisation
//! serves both. ‖r‖²_{C,h} = Σ_a r_aᵀ A_a r_a.

pub mod refine;

use crate::contact::nitsche::Nitsche;
use crate::contact::projection::Smoothing;
use crate::contact::ContactJoint;
use crate::elasticity::{kernels, Problem};
use crate::fem::dofs::{DofMap, FIXED};
use crate::fem::lagrange;
use crate::fem::quadrature::{gauss_segment, split_rule, Rule1d};
use crate::fem::sparse::{vector_dofs, LinearSystem, Local, SparsePattern};
use crate::fem::tabulate::Tabulation;
use crate::geometry::{ddot, dot, sub, AffineMap, Point, Vector, D};
use crate::mesh::midpoints::elevate_to_p2;
use crate::mesh::midpoints::vertex_mesh;
use crate::mesh::{Mesh, Topology};
use crate::solve::{Cholesky, SolveError};
use faer::Mat;
use rayon::prelude::*;
use refine::{bisect, refine_levels, Refinement};
use serde::Serialize;

/// Refinement levels used when the caller has no reason to choose.
pub const DEFAULT_LEVELS: usize = 2;

/// Degree of the volume quadrature on fine cells (2·2 + 4).
const VOLUME_DEGREE: usize = 8;

/// The Riesz representative r of R(u_h) in V_fine and its norm.
#[derive(Debug, Clone)]
pub struct RieszRepresentative {
    /// ‖r‖_{C,h}, the lower bound of ‖R(u_h)‖.
    pub norm: f64,
    /// Per coarse cell: ‖∇r‖²_T plus h_F⁻¹‖r‖²_F for the contact faces F of T.
    /// Sums to `norm²`.
    pub cell_contributions: Vec<f64>,
    /// The fine P2 mesh and its parents in the coarse mesh.
    pub fine: Refinement,
    /// Nodal values of r on the fine mesh.
    pub r: Vec<Vector>,
    /// Number of scalar unknowns of the Riesz problem (both components).
    pub n_unknowns: usize,
}

/// A reference of ‖R(u_h)‖ sharp near singularities: ‖r‖_{C,h} on a sequence of reference
/// meshes, each refined where the last representative concentrates.
#[derive(Debug, Clone)]
pub struct SharpReference {
    /// ‖r‖_{C,h} on each reference mesh: lower bounds of ‖R(u_h)‖, increasing.
    pub norms: Vec<f64>,
    /// Unknowns of each Riesz problem.
    pub unknowns: Vec<usize>,
    /// Whether the last two norms agree within the asked relative difference.
    pub converged: bool,
}

impl SharpReference {
    /// The last (largest) lower bound.
    pub fn norm(&self) -> f64 {
        *self.norms.last().expect("at least one reference")
    }
}

/// Share of ‖r‖²_{C,h} carried by the cells refined at each step of [`sharp_reference`].
pub const MARKED_SHARE: f64 = 0.8;

/// The lower bound ‖r‖_{C,h} ≤ ‖R(u_h)‖ enriched until two successive values agree within
/// `agreement` (relative), or until a Riesz problem would exceed `max_unknowns`. The first
/// space is vector P2 on the coarse mesh refined [`sharp_start`] times (as
/// [`residual_dual_norm`] with that many levels); each next one halves the cells that carry
/// [`MARKED_SHARE`] of ‖∇r‖² (the smallest such set, by two newest-vertex bisections), so it
/// contains the last and the bounds increase.
pub fn sharp_reference(
    problem: &Problem,
    u_h: &[Vector],
    contact: Option<&ContactJoint>,
    agreement: f64,
    max_unknowns: usize,
) -> Result<SharpReference, SolveError> {
    let mut skeleton = refine_levels(&vertex_mesh(&problem.mesh), sharp_start(problem.mesh.order));
    let mut reference = SharpReference { norms: Vec::new(), unknowns: Vec::new(), converged: false };
    loop {
        let fine = Refinement { mesh: elevate_to_p2(&skeleton.mesh), ..skeleton.clone() };
        let riesz = riesz_on(problem, u_h, contact, fine)?;
        reference.norms.push(riesz.norm);
        reference.unknowns.push(riesz.n_unknowns);
        if let [.., previous, last] = reference.norms[..] {
            reference.converged = last - previous <= agreement * last;
        }
        let marked = largest_share(&gradient_energy(&riesz.fine.mesh, &riesz.r), MARKED_SHARE);
        let grown = 3 * marked.iter().filter(|&&m| m).count() * riesz.n_unknowns / marked.len();
        if reference.converged || riesz.n_unknowns + grown > max_unknowns {
            return Ok(reference);
        }
        skeleton = bisect_twice(&skeleton, &marked);
    }
}

/// Uniform refinements of the first space of [`sharp_reference`] for u_h of degree p: none for
/// p = 1 (P2 on the coarse mesh already contains V_h), one for p = 2 (P2 on the coarse mesh is
/// V_h itself, where the residual nearly vanishes by Galerkin orthogonality).
pub fn sharp_start(degree: usize) -> usize {
    if degree == 1 {
        0
    } else {
        1
    }
}

/// Relative agreement of two successive references that ends the enrichment of [`effectivity`].
pub const REFERENCE_AGREEMENT: f64 = 0.02;

/// Largest Riesz problem of [`effectivity`] (scalar unknowns, both components).
pub const REFERENCE_MAX_UNKNOWNS: usize = 4_000_000;

/// An estimate η_tot against the sharp reference of ‖R(u_h)‖.
#[derive(Debug, Clone, Serialize)]
pub struct Effectivity {
    pub eta_tot: f64,
    /// The last (largest) lower bound of ‖R(u_h)‖.
    pub reference: f64,
    /// η_tot / reference ≥ the true effectivity index η_tot / ‖R(u_h)‖.
    pub i_eff: f64,
    /// The lower bounds on the successively enriched reference spaces, and their unknowns.
    pub references: Vec<f64>,
    pub unknowns: Vec<usize>,
    /// Whether the last two agree within [`REFERENCE_AGREEMENT`].
    pub converged: bool,
}

/// `eta_tot`, an estimate of ‖R(u_h)‖, against [`sharp_reference`] with
/// [`REFERENCE_AGREEMENT`] and [`REFERENCE_MAX_UNKNOWNS`].
pub fn effectivity(
    problem: &Problem,
    u_h: &[Vector],
    contact: Option<&ContactJoint>,
    eta_tot: f64,
) -> Result<Effectivity, SolveError> {
    let r = sharp_reference(problem, u_h, contact, REFERENCE_AGREEMENT, REFERENCE_MAX_UNKNOWNS)?;
    Ok(Effectivity {
        eta_tot,
        reference: r.norm(),
        i_eff: eta_tot / r.norm(),
        converged: r.converged,
        references: r.norms,
        unknowns: r.unknowns,
    })
}

/// The smallest set of cells whose `values` sum to at least `share` of the total.
fn largest_share(values: &[f64], share: f64) -> Vec<bool> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    let total: f64 = values.iter().sum();
    let mut marked = vec![false; values.len()];
    let mut sum = 0.0;
    for c in order {
        if sum >= share * total {
            break;
        }
        marked[c] = true;
        sum += values[c];
    }
    marked
}

/// `refined` with its `marked` cells bisected twice (each into four), parents kept.
fn bisect_twice(refined: &Refinement, marked: &[bool]) -> Refinement {
    let local = Refinement {
        mesh: refined.mesh.clone(),
        cell_parents: (0..refined.mesh.n_cells()).collect(),
        facet_parents: (0..refined.mesh.n_facets()).collect(),
    };
    let once = bisect(&local, marked);
    let children: Vec<bool> = once.cell_parents.iter().map(|&c| marked[c]).collect();
    let twice = bisect(&once, &children);
    Refinement {
        cell_parents: twice.cell_parents.iter().map(|&c| refined.cell_parents[c]).collect(),
        facet_parents: twice.facet_parents.iter().map(|&f| refined.facet_parents[f]).collect(),
        mesh: twice.mesh,
    }
}

/// ‖r‖_{C,h} ≤ ‖R(u_h)‖ on the coarse mesh refined `levels` times (see the module doc).
/// `u_h` holds the nodal values on `problem.mesh`; `contact` is `None` without Γ_C.
pub fn residual_dual_norm(
    problem: &Problem,
    u_h: &[Vector],
    contact: Option<&ContactJoint>,
    levels: usize,
) -> Result<f64, SolveError> {
    residual_riesz(problem, u_h, contact, levels).map(|r| r.norm)
}

/// The Riesz representative of R(u_h) in V_fine (see the module doc). Fails if the Gram
/// matrix is singular: a component that is fixed nowhere while Γ_C is empty.
pub fn residual_riesz(
    problem: &Problem,
    u_h: &[Vector],
    contact: Option<&ContactJoint>,
    levels: usize,
) -> Result<RieszRepresentative, SolveError> {
    riesz_on(problem, u_h, contact, refine_levels(&elevate_to_p2(&problem.mesh), levels))
}

/// The Riesz representative of R(u_h) in the vector P2 space of the degree-2 mesh `fine`,
/// nested in `problem.mesh`.
fn riesz_on(
    problem: &Problem,
    u_h: &[Vector],
    contact: Option<&ContactJoint>,
    fine: Refinement,
) -> Result<RieszRepresentative, SolveError> {
    let coarse = &problem.mesh;
    assert_eq!(u_h.len(), coarse.n_points(), "u_h must hold one value per node of the coarse mesh");
    assert_eq!(problem.materials.len(), coarse.n_cells(), "one material per coarse cell");
    let topology = Topology::new(coarse);
    let faces = contact.map(|c| ContactFaces::new(problem, &topology, c, &fine));

    let mut load = volume_residual(problem, u_h, &fine);
    neumann_residual(problem, &topology, &fine, &mut load);
    if let Some(faces) = &faces {
        faces.add_residual(&fine, u_h, &mut load);
    }

    // Dirichlet nodes of each component on the fine mesh
    let mesh = &fine.mesh;
    let mut fixed = [vec![false; mesh.n_points()], vec![false; mesh.n_points()]];
    for bc in &problem.dirichlet {
        for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
            for &n in mesh.facet(f) {
                for a in (0..D).filter(|&a| bc.fix[a]) {
                    fixed[a][n] = true;
                }
            }
        }
    }
    let mut r = vec![[0.0; 2]; mesh.n_points()];
    let mut norm2 = 0.0;
    let mut n_unknowns = 0;
    // the same Dirichlet nodes: one matrix, one factorisation, two right-hand sides
    let groups: &[&[usize]] = if fixed[0] == fixed[1] { &[&[0, 1]] } else { &[&[0], &[1]] };
    for &components in groups {
        let system = ScalarSystem::new(mesh, &fixed[components[0]], faces.as_ref(), &fine);
        let free: Vec<usize> = (0..mesh.n_points()).filter(|&n| system.dofs.free[2 * n] != FIXED).collect();
        if free.is_empty() {
            continue;
        }
        let mut x = Mat::from_fn(free.len(), components.len(), |i, j| load[free[i]][components[j]]);
        system.solve_in_place(&mut x)?;
        for (j, &a) in components.iter().enumerate() {
            let column: Vec<f64> = (0..free.len()).map(|i| x[(i, j)]).collect();
            let mut product = vec![0.0; free.len()];
            system.pattern.multiply(&system.values, &column, &mut product);
            norm2 += column.iter().zip(&product).map(|(u, v)| u * v).sum::<f64>();
            n_unknowns += free.len();
            for (&n, &value) in free.iter().zip(&column) {
                r[n][a] = value;
            }
        }
    }
    let cell_contributions = cell_contributions(coarse, &fine, &r, faces.as_ref());
    Ok(RieszRepresentative { norm: norm2.max(0.0).sqrt(), cell_contributions, fine, r, n_unknowns })
}

/// ξ = J⁻¹ (x − v0): reference coordinates of the physical point x in the cell of `map`.
fn to_reference(map: &AffineMap, x: Point) -> Point {
    let d = sub(x, map.origin);
    let m = &map.inv_t; // J⁻ᵀ, so (J⁻¹)_{cr} = m[r][c]
    [m[0][0] * d[0] + m[1][0] * d[1], m[0][1] * d[0] + m[1][1] * d[1]]
}

/// (f, φ_i e_a) − (σ(u_h), ∇(φ_i e_a)) for every fine node i, component a.
fn volume_residual(problem: &Problem, u_h: &[Vector], fine: &Refinement) -> Vec<Vector> {
    let coarse = &problem.mesh;
    let p = coarse.order;
    let mesh = &fine.mesh;
    let tab = Tabulation::new(2, VOLUME_DEGREE);
    let locals: Vec<[Vector; 6]> = (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| {
            let parent = fine.cell_parents[c];
            let map = AffineMap::new(mesh.cell_vertices(c));
            let parent_map = AffineMap::new(coarse.cell_vertices(parent));
            let u: Vec<Vector> = coarse.cell(parent).iter().map(|&n| u_h[n]).collect();
            let material = &problem.materials[parent];
            let (lambda, mu) = material.lame();
            let mut scratch = [[0.0; 2]; 6];
            let mut local = [[0.0; 2]; 6];
            for q in 0..tab.n_points() {
                let w = tab.weights[q] * map.det.abs();
                let x = map.to_physical(tab.points[q]);
                let grad = kernels::displacement_gradient(
                    &parent_map,
                    p,
                    to_reference(&parent_map, x),
                    &u,
                    &mut scratch[..u.len()],
                );
                let [sxx, syy, sxy, _] = kernels::stress(grad, lambda, mu);
                let sigma = [[sxx, sxy], [sxy, syy]];
                let f = problem.body_force_at(parent, x);
                for (i, (phi, gr)) in tab.phi(q).iter().zip(tab.grad(q)).enumerate() {
                    let g = map.physical_gradient(*gr);
                    for a in 0..D {
                        local[i][a] += w * (f[a] * phi - sigma[a][0] * g[0] - sigma[a][1] * g[1]);
                    }
                }
            }
            local
        })
        .collect();
    let mut load = vec![[0.0; 2]; mesh.n_points()];
    for (c, local) in locals.iter().enumerate() {
        for (&n, l) in mesh.cell(c).iter().zip(local) {
            load[n][0] += l[0];
            load[n][1] += l[1];
        }
    }
    load
}

/// Adds (g_N, φ_i e_a)_{Γ_N} on the fine Neumann facets.
fn neumann_residual(problem: &Problem, topology: &Topology, fine: &Refinement, load: &mut [Vector]) {
    let mesh = &fine.mesh;
    let rule = gauss_segment(6);
    let mut phi = [0.0; 3];
    for bc in &problem.neumann {
        for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == bc.tag) {
            let normal = topology.outward_normal(&problem.mesh, fine.facet_parents[f]);
            let nodes = mesh.facet(f);
            let (a, b) = (mesh.points[nodes[0]], mesh.points[nodes[1]]);
            let length = crate::geometry::distance(a, b);
            let cuts = bc.traction.kinks([a, b]);
            for (t, w) in split_rule(&rule, cuts) {
                let x = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
                let g = bc.traction.at(x, normal);
                lagrange::segment_values(2, t, &mut phi);
                for (&n, &ph) in nodes.iter().zip(&phi) {
                    load[n][0] += w * length * g[0] * ph;
                    load[n][1] += w * length * g[1] * ph;
                }
            }
        }
    }
}

/// The coarse contact faces with their Nitsche data, and the coarse facets of Γ_C (on a joint
/// between two bodies, the slave facets and the master facets).
struct ContactFaces {
    nitsche: Nitsche,
    /// (h_F, the cell that owns it) of each coarse boundary facet on Γ_C (None elsewhere).
    facet_of_gamma: Vec<Option<(f64, usize)>>,
    /// The fine facets of each coarse boundary facet.
    children: Vec<Vec<usize>>,
    /// Per face: its coarse dofs (its cell's, then the master cell's on a joint) and its sides.
    face_dofs: Vec<Vec<usize>>,
    sides: Vec<Vec<Side>>,
    rule: Rule1d,
}

/// A side of a contact face: the coarse facet it lies on, the physical points of the face's
/// ends s = 0, 1 on it, and the sign of that side in the jump: + for the slave, − the master.
struct Side {
    facet: usize,
    ends: [Point; 2],
    sign: f64,
}

/// A fine facet of a side with the face parameters s of its two end nodes.
struct FineFacet {
    facet: usize,
    s: [f64; 2],
}

impl ContactFaces {
    fn new(problem: &Problem, topology: &Topology, data: &ContactJoint, fine: &Refinement) -> Self {
        let coarse = &problem.mesh;
        let nitsche = Nitsche::new(coarse, topology, &problem.materials, data);
        let mut facet_of_gamma = vec![None; coarse.n_facets()];
        let (mut face_dofs, mut sides) = (Vec::new(), Vec::new());
        for (k, face) in nitsche.faces.iter().enumerate() {
            let mut face_sides =
                vec![Side { facet: face.facet, ends: face.ends.map(|xi| face.map.to_physical(xi)), sign: 1.0 }];
            if let Some(opposite) = &face.opposite {
                let ends = opposite.ends.map(|xi| opposite.map.to_physical(xi));
                face_sides.push(Side { facet: opposite.facet, ends, sign: -1.0 });
            }
            for side in &face_sides {
                facet_of_gamma[side.facet] = Some((coarse.facet_length(side.facet), topology.tagged_cell(side.facet)));
            }
            let mut dofs = Vec::new();
            nitsche.face_dofs(coarse, k, &mut dofs);
            face_dofs.push(dofs);
            sides.push(face_sides);
        }
        let mut children = vec![Vec::new(); coarse.n_facets()];
        for (f, &parent) in fine.facet_parents.iter().enumerate() {
            children[parent].push(f);
        }
        ContactFaces { nitsche, facet_of_gamma, children, face_dofs, sides, rule: gauss_segment(4) }
    }

    /// The fine facets of `side` that meet the face, with the face parameters of their ends.
    fn fine_facets(&self, fine: &Refinement, side: &Side) -> Vec<FineFacet> {
        let [a, b] = side.ends;
        let d = sub(b, a);
        let s = |n: usize| dot(sub(fine.mesh.points[n], a), d) / dot(d, d);
        (self.children[side.facet].iter())
            .map(|&f| FineFacet { facet: f, s: [s(fine.mesh.facet(f)[0]), s(fine.mesh.facet(f)[1])] })
            .filter(|f| f.s[0].max(f.s[1]) > 0.0 && f.s[0].min(f.s[1]) < 1.0)
            .collect()
    }

    /// Adds ⟨t(u_h), [φ_i e_a]⟩ = ∫ t(u_h)·(φ_i e_a)(x) − t(u_h)·(φ_i e_a)(y(x)) dx over every
    /// contact face (the second term on a joint between two bodies only, y(x) the master point
    /// facing x), t(u_h) = [P_γ(u_h)]_{R⁻} ν + Π_S(P^t_γ(u_h)) τ the exact traction: each face
    /// is cut at the ends of the fine facets of both sides and at the kinks of t(u_h), and each
    /// piece integrated by 4 Gauss points.
    fn add_residual(&self, fine: &Refinement, u_h: &[Vector], load: &mut [Vector]) {
        let mut phi = [0.0; 3];
        for (k, sides) in self.sides.iter().enumerate() {
            let u: Vec<f64> = self.face_dofs[k].iter().map(|&g| u_h[g / 2][g % 2]).collect();
            let u = self.nitsche.local(k, &u, None);
            let length = self.nitsche.faces[k].length;
            let facets: Vec<Vec<FineFacet>> = sides.iter().map(|side| self.fine_facets(fine, side)).collect();
            let mut cuts: Vec<f64> = self.nitsche.kinks(k, &u, Smoothing::NONE);
            cuts.extend(facets.iter().flatten().flat_map(|f| f.s));
            cuts.retain(|s| *s > 0.0 && *s < 1.0);
            for (s, w) in split_rule(&self.rule, cuts) {
                let value = self.nitsche.traction(k, &self.nitsche.point(k, s), &u, Smoothing::NONE);
                for (side, facets) in sides.iter().zip(&facets) {
                    let inside = |f: &&FineFacet| f.s[0].min(f.s[1]) <= s && s <= f.s[0].max(f.s[1]);
                    let Some(f) = facets.iter().find(inside) else { continue };
                    lagrange::segment_values(2, (s - f.s[0]) / (f.s[1] - f.s[0]), &mut phi);
                    for (&n, &ph) in fine.mesh.facet(f.facet).iter().zip(&phi) {
                        for (l, v) in load[n].iter_mut().zip(value) {
                            *l += side.sign * w * length * v * ph;
                        }
                    }
                }
            }
        }
    }

    /// h_F⁻¹ ∫ φ_i φ_j on fine facet f (3 × 3, row-major), if it lies on Γ_C.
    fn face_mass(&self, fine: &Refinement, f: usize) -> Option<[f64; 9]> {
        let (h, _) = self.facet_of_gamma[fine.facet_parents[f]]?;
        let scale = fine.mesh.facet_length(f) / h;
        let mut m = [0.0; 9];
        let mut phi = [0.0; 3];
        for (&t, &w) in self.rule.points.iter().zip(&self.rule.weights) {
            lagrange::segment_values(2, t, &mut phi);
            for i in 0..3 {
                for j in 0..3 {
                    m[3 * i + j] += w * scale * phi[i] * phi[j];
                }
            }
        }
        Some(m)
    }
}

/// The Gram matrix of one component: ∫ ∇φ_i · ∇φ_j + Σ_F h_F⁻¹ ∫_F φ_i φ_j over the scalar
/// unknowns. Node n is stored in slot 2n of a vector [`DofMap`] whose slots 2n + 1 are all
/// fixed, so that the vector pattern and assembly serve a scalar field.
struct ScalarSystem {
    dofs: DofMap,
    pattern: SparsePattern,
    values: Vec<f64>,
}

impl ScalarSystem {
    fn new(mesh: &Mesh, fixed: &[bool], faces: Option<&ContactFaces>, fine: &Refinement) -> Self {
        let constraints: Vec<(usize, f64)> = (0..mesh.n_points())
            .flat_map(|n| [(2 * n + 1, true), (2 * n, fixed[n])])
            .filter(|&(_, fix)| fix)
            .map(|(dof, _)| (dof, 0.0))
            .collect();
        let dofs = DofMap::new(mesh.n_points(), 2, &constraints);
        let pattern = SparsePattern::new(mesh, &dofs);
        let mut system = LinearSystem::zeros(&pattern);
        let tab = Tabulation::new(2, 2);
        let kernel = |c: usize, local: &mut Local| {
            let map = AffineMap::new(mesh.cell_vertices(c));
            let n = 12;
            local.matrix.fill(0.0);
            local.load.fill(0.0);
            for q in 0..tab.n_points() {
                let w = tab.weights[q] * map.det.abs();
                let mut g = [[0.0; 2]; 6];
                for (gi, gr) in g.iter_mut().zip(tab.grad(q)) {
                    *gi = map.physical_gradient(*gr);
                }
                for i in 0..6 {
                    for j in 0..6 {
                        local.matrix[2 * i * n + 2 * j] += w * dot(g[i], g[j]);
                    }
                }
            }
        };
        let dofs_of = |c: usize, out: &mut Vec<usize>| vector_dofs(mesh.cell(c), out);
        system.assemble(&pattern, &dofs, mesh.n_cells(), 12, dofs_of, kernel);
        if let Some(faces) = faces {
            for f in 0..mesh.n_facets() {
                let Some(m) = faces.face_mass(fine, f) else { continue };
                let nodes = mesh.facet(f);
                for (i, &ni) in nodes.iter().enumerate() {
                    for (j, &nj) in nodes.iter().enumerate() {
                        let (row, col) = (dofs.free[2 * ni], dofs.free[2 * nj]);
                        if row != FIXED && col != FIXED {
                            system.values[pattern.position(row, col)] += m[3 * i + j];
                        }
                    }
                }
            }
        }
        ScalarSystem { dofs, pattern, values: system.values }
    }

    /// Overwrites the columns of `b` by A⁻¹ b: one sparse Cholesky factorisation for all columns.
    fn solve_in_place(&self, b: &mut Mat<f64>) -> Result<(), SolveError> {
        Cholesky::analyse(&self.pattern)?.factor(&self.pattern, &self.values)?.solve_in_place(b)
    }
}

/// ‖∇r‖²_T + Σ_{F ⊂ ∂T ∩ Γ_C} h_F⁻¹‖r‖²_F for every coarse cell T.
fn cell_contributions(coarse: &Mesh, fine: &Refinement, r: &[Vector], faces: Option<&ContactFaces>) -> Vec<f64> {
    let mesh = &fine.mesh;
    let mut out = vec![0.0; coarse.n_cells()];
    for (c, v) in gradient_energy(mesh, r).into_iter().enumerate() {
        out[fine.cell_parents[c]] += v;
    }
    if let Some(faces) = faces {
        for f in 0..mesh.n_facets() {
            let Some(m) = faces.face_mass(fine, f) else { continue };
            let (_, cell) = faces.facet_of_gamma[fine.facet_parents[f]].expect("face mass only on Γ_C");
            let nodes = mesh.facet(f);
            let mut sum = 0.0;
            for (i, &ni) in nodes.iter().enumerate() {
                for (j, &nj) in nodes.iter().enumerate() {
                    sum += m[3 * i + j] * dot(r[ni], r[nj]);
                }
            }
            out[cell] += sum;
        }
    }
    out
}

/// ‖∇r‖²_T for every cell T of the degree-2 `mesh`.
fn gradient_energy(mesh: &Mesh, r: &[Vector]) -> Vec<f64> {
    let tab = Tabulation::new(2, 2);
    (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| {
            let map = AffineMap::new(mesh.cell_vertices(c));
            let nodes = mesh.cell(c);
            let mut sum = 0.0;
            for q in 0..tab.n_points() {
                let mut g = [[0.0f64; D]; D];
                for (&n, gr) in nodes.iter().zip(tab.grad(q)) {
                    let d = map.physical_gradient(*gr);
                    for a in 0..D {
                        for b in 0..D {
                            g[a][b] += r[n][a] * d[b];
                        }
                    }
                }
                sum += tab.weights[q] * map.det.abs() * ddot(g, g);
            }
            sum
        })
        .collect()
}
