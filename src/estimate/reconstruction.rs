//! Equilibrated stress reconstruction σ_h = σ_h1 + σ_h2 + σ_h3 (docs/method.md §4).
//!
//! For every vertex a, the patch problem of [`super::patch`] is solved with the target
//! τ* = ψ_a σ(u_h), the divergence datum g_a = −ψ_a f + σ(u_h)∇ψ_a and the traces ψ_a g_N on
//! Γ_N and ψ_a t n on Γ_C, where the Γ_C traction of the Newton iterate u_h = u^k is
//!
//!   t₁ = [P_γ(u_h)]_{R⁻},  t₂ = [P_γ(u_h)]_{reg,δ} − t₁,
//!   t₃ = [P_γ(u^{k−1})]_{reg,δ} + χ^{k−1} (P_γ(u_h) − P_γ(u^{k−1})) − [P_γ(u_h)]_{reg,δ},
//!
//! so that t₁ + t₂ + t₃ is the traction of the Newton equation that u_h solves. The same
//! patch matrix gives σ_h2^a (target 0, traces ψ_a t₂ n) and σ_h3^a (traces ψ_a t₃ n);
//! σ_h1^a is the total minus both. Both vanish on the patches that do not touch Γ_C, which
//! solve for the total alone. Summing over the vertices gives an H(div) stress with
//! ∇·σ_h = −Π^{p−1} f. Patches are solved in parallel.

use super::afw::{self, cell_integrals, edge_moments, CellIntegrals, COMPONENTS};
use super::facets::{sampled_facets, SampledFacet};
use super::patch::{self, FaceKind, PatchFace, PatchInput};
use super::{volume_degree, EstimateError};
use crate::contact::Linearisation;
use crate::elasticity::kernels::{displacement_gradient, stress};
use crate::elasticity::problem::traction_rule;
use crate::elasticity::rigid;
use crate::elasticity::{Displacement, Problem, Traction};
use crate::fem::lagrange;
use crate::fem::quadrature::triangle_cached;
use crate::geometry::{distance, AffineMap, Point, Segment, Vector, D};
use crate::mesh::topology::NONE;
use crate::mesh::{Mesh, Topology};
use rayon::prelude::*;

/// The reconstructed stresses as cell coefficients (layout of [`afw`]) per cell:
/// `sigma[i][cell · 4 n_basis + c · n_basis + k]` for σ_h1, σ_h2, σ_h3.
pub struct Reconstruction {
    pub order: usize,
    pub n_basis: usize,
    pub sigma: [Vec<f64>; 3],
    /// Largest residual of the compatibility condition on patches with free rigid motions
    /// (after the p = 1 rotation correction), relative to the largest of its terms.
    pub compatibility: f64,
    /// The vertex of the patch where that residual is largest.
    pub compatibility_at: Point,
}

impl Reconstruction {
    /// Coefficients of component i (0: σ_h1, 1: σ_h2, 2: σ_h3) on cell c.
    pub fn cell(&self, i: usize, c: usize) -> &[f64] {
        let n = COMPONENTS * self.n_basis;
        &self.sigma[i][c * n..(c + 1) * n]
    }

    /// Coefficients of σ_h = σ_h1 + σ_h2 + σ_h3 on cell c.
    pub fn total(&self, c: usize) -> Vec<f64> {
        (0..COMPONENTS * self.n_basis).map(|k| (0..3).map(|i| self.cell(i, c)[k]).sum()).collect()
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.sigma[0].len() / (COMPONENTS * self.n_basis)
    }

    /// Cell means (1/|T|) ∫_T σ_h of the components [xx, xy, yx, yy]: ∫_T φ_k / |T| is 1/3 for
    /// each P1 basis function, and 0 at the vertices and 1/3 at the midpoints for P2.
    pub fn cell_means(&self) -> [Vec<f64>; COMPONENTS] {
        let nb = self.n_basis;
        let mean = |k: usize| if self.order == 2 && k < 3 { 0.0 } else { 1.0 / 3.0 };
        let mut means: [Vec<f64>; COMPONENTS] = std::array::from_fn(|_| Vec::with_capacity(self.n_cells()));
        for t in 0..self.n_cells() {
            let sigma = self.total(t);
            for (c, column) in means.iter_mut().enumerate() {
                column.push((0..nb).map(|k| sigma[c * nb + k] * mean(k)).sum());
            }
        }
        means
    }

    /// σ_h at the three vertices of every cell, in the order of [`Mesh::discontinuous`]
    /// (cell c, vertex v at 3c + v), components [xx, xy, yx, yy].
    pub fn vertex_values(&self) -> [Vec<f64>; COMPONENTS] {
        let mut values: [Vec<f64>; COMPONENTS] = std::array::from_fn(|_| Vec::with_capacity(3 * self.n_cells()));
        for c in 0..self.n_cells() {
            let sigma = self.total(c);
            for &xi in lagrange::reference_nodes(1) {
                let tau = afw::evaluate(self.order, &sigma, xi);
                for (column, value) in values.iter_mut().zip(tau) {
                    column.push(value);
                }
            }
        }
        values
    }
}

/// Role of a boundary facet in the patch problems.
#[derive(Clone, Copy)]
enum Role {
    Dirichlet([bool; 2]),
    Neumann(usize),
    Contact(usize),
    Free,
}

/// Mesh-wide data shared by the patch problems.
struct Context<'a> {
    problem: &'a Problem,
    topology: &'a Topology,
    u: &'a Displacement,
    /// The facets of Γ_C on every side with their samples ([`sampled_facets`]).
    facets: &'a [SampledFacet],
    maps: Vec<AffineMap>,
    integrals: Vec<CellIntegrals>,
    /// The volume data of every cell for each of its vertices, from [`volume_data`].
    volume: Vec<Vec<f64>>,
    /// Role of every facet (Free for interior facets).
    facet_role: Vec<Role>,
    /// Right-hand sides of the patches that touch Γ_C: 3 with Γ_C, else 1.
    cases: usize,
}

/// Builds σ_h1, σ_h2, σ_h3 for the iterate `u` (nodal values).
pub fn reconstruct(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    contact: Option<&Linearisation>,
) -> Result<Reconstruction, EstimateError> {
    covered(contact)?;
    let facets = contact.map_or_else(Vec::new, |c| sampled_facets(&problem.mesh, topology, c, u));
    reconstruct_sampled(problem, topology, u, contact.is_some(), &facets)
}

/// Fails unless the estimator covers the Nitsche variant of `contact` (θ = 0 only).
pub(crate) fn covered(contact: Option<&Linearisation>) -> Result<(), EstimateError> {
    let theta = contact.and_then(|c| c.nitsche.laws.iter().map(|l| l.parameters.theta).find(|&t| t != 0.0));
    theta.map_or(Ok(()), |theta| Err(EstimateError::Theta(theta)))
}

/// [`reconstruct`] of a [`covered`] iterate, with (if `contact`) the facets of Γ_C sampled at
/// `u` ([`sampled_facets`]).
pub(crate) fn reconstruct_sampled(
    problem: &Problem,
    topology: &Topology,
    u: &Displacement,
    contact: bool,
    facets: &[SampledFacet],
) -> Result<Reconstruction, EstimateError> {
    let mesh = &problem.mesh;
    let order = mesh.order;
    let maps: Vec<AffineMap> = (0..mesh.n_cells()).map(|c| AffineMap::new(mesh.cell_vertices(c))).collect();
    let integrals = maps.par_iter().map(|m| cell_integrals(order, m)).collect();
    let facet_role = facet_roles(problem, topology, facets);
    let cases = if contact { 3 } else { 1 };
    let mut ctx = Context { problem, topology, u, facets, maps, integrals, volume: Vec::new(), facet_role, cases };
    let volume = (0..mesh.n_cells()).into_par_iter().map(|c| volume_data(&ctx, c)).collect();
    ctx.volume = volume;
    let results: Vec<_> = (0..topology.vertices.len())
        .into_par_iter()
        .map_init(patch::Workspace::default, |work, k| {
            let input = patch_input(&ctx, k);
            patch::solve(&input, work).map_err(|why| {
                let [x, y] = mesh.points[topology.vertices[k]];
                EstimateError::Patch { x, y, why }
            })
        })
        .collect::<Result<_, _>>()?;
    let nb = lagrange::n_basis(order);
    let n = COMPONENTS * nb;
    let mut sigma = [vec![0.0; mesh.n_cells() * n], vec![0.0; mesh.n_cells() * n], vec![0.0; mesh.n_cells() * n]];
    let (mut defect, mut scale, mut compatibility_at): (f64, f64, Point) = (0.0, 0.0, [0.0; 2]);
    for (k, solution) in results.into_iter().enumerate() {
        if solution.compatibility.0 > defect {
            (defect, compatibility_at) = (solution.compatibility.0, mesh.points[topology.vertices[k]]);
        }
        scale = scale.max(solution.compatibility.1);
        for (t, &cell) in topology.patch(k).iter().enumerate() {
            // the total, then σ_h2^a and σ_h3^a if the patch solved for them
            for (total, part) in sigma.iter_mut().zip(&solution.sigma) {
                for j in 0..n {
                    total[cell * n + j] += part[t * n + j];
                }
            }
        }
    }
    // σ_h1 = total − σ_h2 − σ_h3
    for j in 0..sigma[0].len() {
        sigma[0][j] -= sigma[1][j] + sigma[2][j];
    }
    let compatibility = if scale > 0.0 { defect / scale } else { 0.0 };
    Ok(Reconstruction { order, n_basis: nb, sigma, compatibility, compatibility_at })
}

/// Role of every facet.
fn facet_roles(problem: &Problem, topology: &Topology, facets: &[SampledFacet]) -> Vec<Role> {
    let mesh = &problem.mesh;
    let mut role = vec![Role::Free; topology.n_facets()];
    for f in 0..mesh.n_facets() {
        let e = topology.tagged_facet[f];
        let tag = mesh.facet_tags[f];
        if let Some(bc) = problem.dirichlet.iter().find(|bc| bc.tag == tag) {
            role[e] = Role::Dirichlet(bc.fix);
        } else if let Some(i) = problem.neumann.iter().position(|bc| bc.tag == tag) {
            role[e] = Role::Neumann(i);
        }
    }
    for (k, sampled) in facets.iter().enumerate() {
        role[sampled.facet.index] = Role::Contact(k);
    }
    role
}

/// ψ_a (barycentric coordinate of local vertex `ia`) at reference point ξ.
fn hat(ia: usize, xi: Point) -> f64 {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]][ia]
}

/// Reference gradient of the barycentric coordinate of local vertex `ia`.
fn hat_gradient(ia: usize) -> Vector {
    [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]][ia]
}

/// The data of the patch problem of the k-th vertex.
fn patch_input<'a>(ctx: &'a Context, k: usize) -> PatchInput<'a> {
    let mesh = &ctx.problem.mesh;
    let order = mesh.order;
    let (nb, nl) = (lagrange::n_basis(order), afw::n_lower(order));
    let a = ctx.topology.vertices[k];
    let cells = ctx.topology.patch(k);
    let cases = patch_cases(ctx, a, cells);
    let mut target = vec![vec![0.0; cells.len() * COMPONENTS * nb]; cases];
    let mut divergence = vec![vec![0.0; cells.len() * nl * 2]; cases];
    let (wt, wd) = (COMPONENTS * nb, 2 * nl);
    for (t, &c) in cells.iter().enumerate() {
        let ia = local_vertex(mesh, c, a);
        let data = &ctx.volume[c][ia * (wt + wd)..(ia + 1) * (wt + wd)];
        target[0][t * wt..(t + 1) * wt].copy_from_slice(&data[..wt]);
        divergence[0][t * wd..(t + 1) * wd].copy_from_slice(&data[wt..]);
    }
    let (faces, fixed) = patch_faces(ctx, a, cells, cases);
    let origin = mesh.points[a];
    let size = cells.iter().map(|&c| mesh.cell_diameter(c)).fold(0.0, f64::max);
    PatchInput {
        order,
        n_basis: nb,
        n_lower: nl,
        cells: cells.iter().map(|&c| &ctx.integrals[c]).collect(),
        faces,
        target,
        divergence,
        lower_nodes: cells
            .iter()
            .flat_map(|&c| afw::lower_nodes(order).iter().map(move |&x| ctx.maps[c].to_physical(x)))
            .collect(),
        rigid: free_rigid_motions(&fixed, origin, size),
        origin,
        area: cells.iter().map(|&c| ctx.maps[c].area()).sum(),
        rotation_correction: order == 1,
    }
}

/// The right-hand sides of the patch of vertex a: all of them (docs/method.md §4.3) if a face
/// through a lies on Γ_C, else the total alone, since the data of σ_h2 and σ_h3 vanish on the
/// patch and so do their patch solutions.
fn patch_cases(ctx: &Context, a: usize, cells: &[usize]) -> usize {
    let mesh = &ctx.problem.mesh;
    // facet i of a cell is opposite to its vertex i
    let on_contact = cells.iter().any(|&c| {
        (0..3)
            .any(|i| mesh.cell(c)[i] != a && matches!(ctx.facet_role[ctx.topology.cell_facets[c][i]], Role::Contact(_)))
    });
    if on_contact {
        ctx.cases
    } else {
        1
    }
}

fn local_vertex(mesh: &Mesh, c: usize, a: usize) -> usize {
    mesh.cell(c)[..3].iter().position(|&v| v == a).expect("the patch cell contains its vertex")
}

/// (ψ_a σ(u_h), φ_k E_c)_T and (−ψ_a f + σ(u_h)∇ψ_a, ψ_m e_i)_T on cell c for each of its
/// vertices a (local index ia): `[ia · (4 n_basis + 2 n_lower) + …]`, the 4 n_basis target
/// moments, then the 2 n_lower divergence moments at `m · 2 + i`.
fn volume_data(ctx: &Context, c: usize) -> Vec<f64> {
    let mesh = &ctx.problem.mesh;
    let order = mesh.order;
    let (nb, nl) = (lagrange::n_basis(order), afw::n_lower(order));
    let (wt, wd) = (COMPONENTS * nb, 2 * nl);
    let map = &ctx.maps[c];
    let material = ctx.problem.materials[c];
    let (lambda, mu) = material.lame();
    let mut nodal = Vec::new();
    ctx.u.relative(mesh.cell(c), &mut nodal);
    let grad_hat: [Vector; 3] = std::array::from_fn(|ia| map.physical_gradient(hat_gradient(ia)));
    let rule = triangle_cached(volume_degree(ctx.problem));
    let (mut phi, mut psi, mut grads) = ([0.0; 6], [0.0; 3], [[0.0; 2]; 6]);
    let mut out = vec![0.0; 3 * (wt + wd)];
    for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
        let w = w * map.det.abs();
        let s = stress(displacement_gradient(map, order, xi, &nodal, &mut grads[..nb]), lambda, mu);
        let sigma = [s[0], s[2], s[2], s[1]]; // xx, xy, yx, yy
        let f = ctx.problem.body_force_at(c, map.to_physical(xi));
        lagrange::values(order, xi, &mut phi[..nb]);
        afw::lower_values(order, xi, &mut psi[..nl]);
        for (ia, data) in out.chunks_exact_mut(wt + wd).enumerate() {
            let (target, divergence) = data.split_at_mut(wt);
            let h = hat(ia, xi);
            for cc in 0..COMPONENTS {
                for kk in 0..nb {
                    target[cc * nb + kk] += h * sigma[cc] * phi[kk] * w; // (ψ_a σ(u_h), φ_k E_c)
                }
            }
            for i in 0..D {
                let g = -h * f[i] + sigma[2 * i] * grad_hat[ia][0] + sigma[2 * i + 1] * grad_hat[ia][1]; // g_a,i
                for m in 0..nl {
                    divergence[m * 2 + i] += g * psi[m] * w;
                }
            }
        }
    }
    out
}

/// A Dirichlet face of a patch: its end points and its fixed components.
type FixedFace = ([Point; 2], [bool; 2]);

/// The faces of the patch with `cases` right-hand sides and the (face end points, fixed
/// components) of its Dirichlet faces.
fn patch_faces(ctx: &Context, a: usize, cells: &[usize], cases: usize) -> (Vec<PatchFace>, Vec<FixedFace>) {
    let mesh = &ctx.problem.mesh;
    let mut faces = Vec::new();
    let mut fixed = Vec::new();
    let mut seen = Vec::new();
    for (t, &c) in cells.iter().enumerate() {
        let vertices = &mesh.cell(c)[..3];
        for i in 0..3 {
            let e = ctx.topology.cell_facets[c][i];
            if seen.contains(&e) {
                continue;
            }
            seen.push(e);
            let [va, vb] = mesh.cell_type().facets()[i];
            let (pa, pb) = (mesh.points[vertices[va]], mesh.points[vertices[vb]]);
            let length = distance(pa, pb);
            let normal = Segment::new(pa, pb).outward_normal(mesh.points[vertices[i]]);
            let contains_a = vertices[i] != a;
            let other = ctx.topology.facet_cells[e].into_iter().find(|&o| o != c && o != NONE);
            let moments0 = edge_moments(mesh.order, va, vb);
            let nodes = [pa, pb, [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]];
            let (t2, kind, moments1) = match other.and_then(|o| cells.iter().position(|&x| x == o)) {
                Some(t2) => {
                    let ja = local_vertex(mesh, cells[t2], vertices[va]);
                    let jb = local_vertex(mesh, cells[t2], vertices[vb]);
                    (t2, FaceKind::Interior, edge_moments(mesh.order, ja, jb))
                }
                None if !contains_a => (0, FaceKind::Opposite, &[] as &[f64]),
                None => {
                    let ends = [vertices[va], vertices[vb]];
                    match boundary_trace(ctx, e, a, ends, normal, cases) {
                        Some(kind) => {
                            if let Role::Dirichlet(fix) = ctx.facet_role[e] {
                                fixed.push(([pa, pb], fix));
                            }
                            (0, kind, &[] as &[f64])
                        }
                        None => {
                            fixed.push(([pa, pb], [true; 2]));
                            continue;
                        }
                    }
                }
            };
            faces.push(PatchFace { cells: [t, t2], moments: [moments0, moments1], length, normal, nodes, kind });
        }
    }
    (faces, fixed)
}

/// The trace condition of a boundary face containing a with `cases` right-hand sides (None:
/// Dirichlet in both components).
fn boundary_trace(
    ctx: &Context,
    e: usize,
    a: usize,
    ends: [usize; 2],
    normal: Vector,
    cases: usize,
) -> Option<FaceKind> {
    let order = ctx.problem.mesh.order;
    let mut data = vec![vec![0.0; 2 * (order + 1)]; cases];
    let active = match ctx.facet_role[e] {
        Role::Dirichlet(fix) if fix == [true; 2] => return None,
        Role::Dirichlet(fix) => [!fix[0], !fix[1]],
        Role::Neumann(i) => {
            traction_moments(ctx, &ctx.problem.neumann[i].traction, a, ends, normal, &mut data[0]);
            [true; 2]
        }
        Role::Contact(k) => {
            contact_moments(ctx, k, a, ends, &mut data);
            [true; 2]
        }
        Role::Free => [true; 2],
    };
    Some(FaceKind::Trace { active, data })
}

/// ∫_F ψ_a g_N,i q_m for a traction on the face with ends A, B (parameter s from A to B).
fn traction_moments(ctx: &Context, traction: &Traction, a: usize, ends: [usize; 2], normal: Vector, out: &mut [f64]) {
    let mesh = &ctx.problem.mesh;
    let (pa, pb) = (mesh.points[ends[0]], mesh.points[ends[1]]);
    let length = distance(pa, pb);
    let mut q = [0.0; 3];
    for (s, w) in traction_rule(traction, [pa, pb], mesh.order) {
        let x = [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
        let psi = if ends[0] == a { 1.0 - s } else { s };
        let g = traction.at(x, normal);
        lagrange::segment_values(mesh.order, s, &mut q);
        for m in 0..=mesh.order {
            for i in 0..D {
                out[m * 2 + i] += psi * g[i] * q[m] * w * length;
            }
        }
    }
}

/// ∫_F ψ_a t_i q_m for the three cases on contact facet k, with the samples of its datum.
fn contact_moments(ctx: &Context, k: usize, a: usize, ends: [usize; 2], data: &mut [Vec<f64>]) {
    let mesh = &ctx.problem.mesh;
    let SampledFacet { facet, samples } = &ctx.facets[k];
    let reversed = facet.ends[0] != ends[0];
    let mut q = [0.0; 3];
    for sample in samples {
        let s = if reversed { 1.0 - sample.r } else { sample.r };
        let psi = if ends[0] == a { 1.0 - s } else { s };
        let [t1, t2, t3] = sample.t;
        let t = [[t1[0] + t2[0] + t3[0], t1[1] + t2[1] + t3[1]], t2, t3];
        lagrange::segment_values(mesh.order, s, &mut q);
        for (case, out) in data.iter_mut().enumerate() {
            for m in 0..=mesh.order {
                for i in 0..D {
                    out[m * 2 + i] += psi * t[case][i] * q[m] * sample.weight;
                }
            }
        }
    }
}

/// Rigid motions z(x) = (a_x − b y, a_y + b x) (x relative to `origin`) that vanish in the
/// fixed components of the given Dirichlet faces.
fn free_rigid_motions(fixed: &[FixedFace], origin: Point, size: f64) -> Vec<[f64; 3]> {
    let constraints = fixed.iter().flat_map(|(ends, fix)| {
        let directions = [[1.0, 0.0], [0.0, 1.0]].into_iter().zip(*fix).filter(|(_, f)| *f);
        ends.iter().flat_map(move |&x| directions.clone().map(move |(d, _)| (x, d)))
    });
    rigid::free_motions(constraints, origin, size).into_iter().map(|[ax, ay, b]| [ax, ay, b / size]).collect()
}
