//! Nitsche terms of unilateral contact with a rigid foundation on Γ_C, with the joint's
//! tangential law (friction, §1.7) and uplift (§1.8); across a joint between two bodies
//! (§1.10) the same terms with the jump \[v\] = v¹ − v²∘Π in place of v, on the pieces of the
//! slave facets that face one master cell each, σ^n and σ^t being the slave's.
//!
//! The contact direction ν is the outward normal n of each face unless the foundation's normal
//! is prescribed (a constant ν, for curved bodies on a flat foundation). With v^n = v·ν,
//! σ^n(v) = (σ(v)n)·ν, the uplift p_u (0 without), P_γ(v) = σ^n(v) + p_u − γ(v^n − g) and a
//! projection [·] (regularised or not), the θ-method adds to the elasticity residual, for each
//! contact face F (docs/method.md §1.3, §1.8),
//!
//!   R_F(u; v) = −(θ/γ) ∫_F (σ^n(u) + p_u) σ^n(v) + (1/γ) ∫_F [P_γ(u)] (θ σ^n(v) − γ v^n) + ∫_F p_u v^n,
//!
//! and its derivative in the direction w,
//!
//!   J_F(u; w, v) = −(θ/γ) ∫_F σ^n(w) σ^n(v) + (1/γ) ∫_F ∂[P_γ(u)] (σ^n(w) − γ w^n)(θ σ^n(v) − γ v^n).
//!
//! γ|_F = γ₀ E / h_F. The terms read u_h through a [`FaceDisplacement`]: σ^n from nodal
//! differences, u_h·ν − g from the jump at the cells' first nodes, compensated, plus the
//! differences (docs/method.md §5.2), so that P_γ(u_h) carries no rounding of |u_h| itself.
//! P_γ(u_h) is a polynomial of degree p along a straight face, so each face
//! is split at the roots of P_γ(u_h) = b for every breakpoint b of the projection, and each
//! piece is integrated with the Gauss rule of [`JointLaw::face_points`], exact for the
//! polynomial integrands.
//!
//! The faces are built in `faces`, the quadrature split at the kinks in `kinks`, and the face
//! terms R_F, J_F in `terms`.

mod faces;
mod kinks;
mod terms;

use faces::{face, pieces};
pub use kinks::crossings;

use super::bond::NormalLaw;
use super::law::{JointLaw, Tangential};
use super::projection::Smoothing;
use super::uplift::Uplift;
use super::CurveUplift;
use super::{ContactJoint, CurveLaw};
use crate::elasticity::Material;
use crate::fem::lagrange;
use crate::fem::sparse::vector_dofs;
use crate::geometry::{dot, sub, tangent, AffineMap, Point, Segment, Vector, D};
use crate::mesh::{Mesh, Topology};
use crate::solve::two_sum;

/// Normal gap to the foundation, g(x) = g₀ + ∇g · x (u^n ≤ g).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Gap {
    pub constant: f64,
    pub gradient: Vector,
}

impl Gap {
    pub fn at(&self, x: Point) -> f64 {
        self.constant + self.gradient[0] * x[0] + self.gradient[1] * x[1]
    }
}

/// Parameters of the Nitsche method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NitscheParameters {
    /// γ₀ in γ = γ₀ E / h_F.
    pub gamma0: f64,
    /// θ ∈ {1, 0, −1}: symmetric, incomplete (the default), skew-symmetric.
    pub theta: f64,
    pub gap: Gap,
    /// Prescribed contact direction ν (unit, from the body into the foundation); `None`: the
    /// outward normal of each face.
    pub direction: Option<Vector>,
}

impl NitscheParameters {
    /// The default γ₀: as accurate as γ₀ = 100 on the Hertz case and Scene A, with fewer Newton
    /// steps, one decade above the least γ₀ at which θ = 0 converged (docs/results.md, "The
    /// Nitsche parameter").
    pub const GAMMA0: f64 = 10.0;
}

impl Default for NitscheParameters {
    fn default() -> Self {
        NitscheParameters { gamma0: Self::GAMMA0, theta: 0.0, gap: Gap::default(), direction: None }
    }
}

/// A contact face and what its integrals need.
#[derive(Debug, Clone)]
pub struct ContactFace {
    /// Boundary facet index in the mesh.
    pub facet: usize,
    /// The cell owning the face.
    pub cell: usize,
    /// The index of the face's curve in [`Nitsche::laws`].
    pub curve: usize,
    pub map: AffineMap,
    /// Reference coordinates (in the cell) of the face's end points.
    pub ends: [Point; 2],
    pub normal: Vector,
    /// Contact direction ν: the prescribed one or `normal`.
    pub direction: Vector,
    pub length: f64,
    /// γ = γ₀ E / h_F.
    pub gamma: f64,
    pub lambda: f64,
    pub mu: f64,
    /// On a joint between two bodies, this face is the piece of the slave facet `facet` that
    /// faces one master cell, `opposite`.
    pub opposite: Option<Opposite>,
}

/// The master side of a piece of a slave face (docs/method.md §1.10): the master cell and the
/// reference coordinates, in it, of the points that the piece's ends project onto along ν.
#[derive(Debug, Clone)]
pub struct Opposite {
    /// The master facet and its cell.
    pub facet: usize,
    pub cell: usize,
    pub map: AffineMap,
    pub ends: [Point; 2],
}

/// Shape data of the cell basis at one point of a face.
pub struct FacePoint {
    pub x: Point,
    /// g − g₀, the gap at the point less its value g₀ at the face's origin
    /// ([`Nitsche::gap_origin`]): ∇g·(x − x₀), with (y − x)·ν − (y₀ − x₀)·ν on a joint.
    pub gap: f64,
    /// σ^n(φ_i e_a) = (σ(φ_i e_a)n)·ν = λ ∂_a φ_i (n·ν) + μ((∇φ_i·n) ν_a + (∇φ_i·ν) n_a) at index
    /// 2i + a.
    pub sigma_n: Vec<f64>,
    /// (φ_i e_a) · ν = φ_i ν_a at index 2i + a.
    pub u_n: Vec<f64>,
    /// σ^t(φ_i e_a) = (σ(φ_i e_a)n)·τ and (φ_i e_a)·τ along the tangent τ = (−ν_y, ν_x).
    pub sigma_t: Vec<f64>,
    pub u_t: Vec<f64>,
}

/// The displacement of a contact face's cells as the Nitsche terms read it (docs/method.md
/// §5.2): the nodal differences u_k − u_0 of each cell (index 2i + a, the master cell's after
/// the slave's, each from its own first node), and the jump at the first nodes along ν less the
/// gap there, (u¹_0 − u²_0)·ν − g₀, and along τ, (u¹_0 − u²_0)·τ (u² = 0 on a rigid
/// foundation), summed in compensated arithmetic. Then, with Σ_k φ_k = 1,
/// u_h·ν − g = ((u¹_0 − u²_0)·ν − g₀) + Σ_k φ_k (u_k − u_0)·ν − (g − g₀): no term carries the
/// rounding ε |u_h| of the nodal values. An increment w = u − u_prev ([`Nitsche::increment`])
/// takes no gap.
#[derive(Debug, Clone)]
pub struct FaceDisplacement {
    pub relative: Vec<f64>,
    pub normal: f64,
    pub tangential: f64,
}

/// All contact faces of a mesh, with the law and Nitsche parameters of each curve.
#[derive(Debug, Clone)]
pub struct Nitsche {
    /// The law and parameters of each curve, indexed by [`ContactFace::curve`].
    pub laws: Vec<CurveLaw>,
    /// The uplift diagrams, each on its curves ([`CurveUplift`]).
    pub uplift: Vec<CurveUplift>,
    /// The index in `uplift` of the diagram on each curve (None: no uplift there).
    uplift_of: Vec<Option<usize>>,
    pub faces: Vec<ContactFace>,
    pub order: usize,
    /// The nodal displacements (dof 2i + a) of the state u_0 that the friction law measures
    /// slip from (None: rest, the law on the total u^t); on a load path, the last converged
    /// state ([`Nitsche::set_slip_origin`]).
    slip_origin: Option<Vec<f64>>,
    /// u_0 on each face's cells (empty without a slip origin).
    origin_faces: Vec<FaceDisplacement>,
}

impl Nitsche {
    /// Contact faces: the boundary facets of the curves of `joint`; on a joint between two
    /// bodies, the pieces of the slave facets that face one master cell each.
    pub fn new(mesh: &Mesh, topology: &Topology, materials: &[Material], joint: &ContactJoint) -> Self {
        let slave = |curve: usize| {
            let tag = std::slice::from_ref(&joint.tags[curve]);
            mesh.facets_tagged(tag)
                .map(move |f| face(mesh, topology, materials, f, curve, &joint.laws[curve].parameters))
        };
        let mut faces = Vec::new();
        for curve in 0..joint.tags.len() {
            match joint.masters.get(curve) {
                None => faces.extend(slave(curve)),
                // each slave curve faces its own master curve
                Some(master) => {
                    let master: Vec<(usize, usize)> = mesh
                        .facets_tagged(std::slice::from_ref(master))
                        .map(|f| (f, topology.tagged_cell(f)))
                        .collect();
                    faces.extend(slave(curve).flat_map(|face| pieces(mesh, topology, &face, &master)));
                }
            }
        }
        let mut uplift_of = vec![None; joint.tags.len()];
        for (d, up) in joint.uplift.iter().enumerate() {
            up.curves.iter().for_each(|&curve| uplift_of[curve] = Some(d));
        }
        let (laws, uplift, order) = (joint.laws.clone(), joint.uplift.clone(), mesh.order);
        let mut nitsche =
            Nitsche { laws, uplift, uplift_of, faces, order, slip_origin: None, origin_faces: Vec::new() };
        nitsche.set_slip_origin(mesh, joint.slip_origin.clone());
        nitsche
    }

    /// Makes the friction law act on the slip from the state of nodal displacements `u0` (dof
    /// 2i + a; None: from rest): P^t_γ(u) = σ^t(u) − γ (u^t − u^t_0) (docs/method.md §1.11).
    pub fn set_slip_origin(&mut self, mesh: &Mesh, u0: Option<Vec<f64>>) {
        let mut dofs = Vec::new();
        self.origin_faces = match &u0 {
            None => Vec::new(),
            Some(u0) => (0..self.faces.len())
                .map(|k| {
                    self.face_dofs(mesh, k, &mut dofs);
                    let values: Vec<f64> = dofs.iter().map(|&g| u0[g]).collect();
                    self.local(k, &values, None)
                })
                .collect(),
        };
        self.slip_origin = u0;
    }

    /// The nodal displacements of the state the friction law measures slip from (None: rest).
    pub fn slip_origin(&self) -> Option<&[f64]> {
        self.slip_origin.as_deref()
    }

    /// The joint law of face `k`: its curve's.
    pub fn law(&self, k: usize) -> JointLaw {
        self.laws[self.faces[k].curve].law
    }

    /// The normal law of face `k`: its curve's bond at the face's γ, or plain contact.
    pub fn normal_law(&self, k: usize) -> NormalLaw {
        NormalLaw::new(self.laws[self.faces[k].curve].bond, self.faces[k].gamma)
    }

    /// The Nitsche parameters of face `k`: its curve's.
    pub fn parameters(&self, k: usize) -> &NitscheParameters {
        &self.laws[self.faces[k].curve].parameters
    }

    /// θ of face `k`.
    pub fn theta(&self, k: usize) -> f64 {
        self.parameters(k).theta
    }

    /// Whether some face has a tangential traction.
    pub fn has_friction(&self) -> bool {
        self.laws.iter().any(|c| c.law.has_friction())
    }

    /// Whether some curve has a bond.
    pub fn has_bond(&self) -> bool {
        self.laws.iter().any(|c| c.bond.is_some())
    }

    /// Whether some face's law softens as the joint opens: a cohesion lost
    /// ([`JointLaw::softens`]), or a bond.
    pub fn softens(&self) -> bool {
        self.laws.iter().any(|c| c.law.softens() || c.bond.is_some())
    }

    /// Number of local dofs of a face: those of the owning cell, and of the master cell on a
    /// joint between two bodies.
    pub fn n_local(&self) -> usize {
        let cells = if self.faces.first().is_some_and(|f| f.opposite.is_some()) { 2 } else { 1 };
        2 * cells * lagrange::n_basis(self.order)
    }

    /// The global dofs of face `k` (index 2i + a of the local vectors): its cell's, then the
    /// master cell's.
    pub fn face_dofs(&self, mesh: &Mesh, k: usize, dofs: &mut Vec<usize>) {
        let face = &self.faces[k];
        vector_dofs(mesh.cell(face.cell), dofs);
        if let Some(opposite) = &face.opposite {
            dofs.extend(mesh.cell(opposite.cell).iter().flat_map(|&n| [2 * n, 2 * n + 1]));
        }
    }

    /// The physical point at parameter s ∈ [0, 1] of face `k`.
    pub fn position(&self, k: usize, s: f64) -> Point {
        let face = &self.faces[k];
        face.map.to_physical(Segment::new(face.ends[0], face.ends[1]).point(s))
    }

    /// Basis data at parameter s ∈ [0, 1] of face `k`.
    pub fn point(&self, k: usize, s: f64) -> FacePoint {
        let face = &self.faces[k];
        let nb = lagrange::n_basis(self.order);
        let xi = Segment::new(face.ends[0], face.ends[1]).point(s);
        let mut phi = [0.0; 6];
        let mut grads = [[0.0; 2]; 6];
        lagrange::values(self.order, xi, &mut phi[..nb]);
        lagrange::gradients(self.order, xi, &mut grads[..nb]);
        let n = face.normal;
        // σ^d(φ e_a) = (σ(φ e_a)n)·d = λ ∂_a φ (n·d) + μ((∇φ·n) d_a + (∇φ·d) n_a) and (φ e_a)·d
        let along = |d: Vector| {
            let n_d = dot(n, d);
            let (mut sigma, mut value) = (vec![0.0; 2 * nb], vec![0.0; 2 * nb]);
            for i in 0..nb {
                let g = face.map.physical_gradient(grads[i]);
                let (gn, gd) = (dot(g, n), dot(g, d));
                for a in 0..D {
                    sigma[2 * i + a] = face.lambda * g[a] * n_d + face.mu * (gn * d[a] + gd * n[a]);
                    value[2 * i + a] = phi[i] * d[a];
                }
            }
            (sigma, value)
        };
        let nu = face.direction;
        let tau = tangent(nu);
        let (mut sigma_n, mut u_n) = along(nu);
        let (mut sigma_t, mut u_t) = along(tau);
        // g − g₀ = ∇g·Jξ from the cell's origin x₀: without the rounding ε|x| of the point itself
        let offset = linear(&face.map, xi);
        let gradient = self.parameters(k).gap.gradient;
        let mut gap = dot(gradient, offset);
        if let Some(opposite) = &face.opposite {
            // the jump [v] = v¹(x) − v²(y) at the point y of the master cell facing x:
            // −φ²_j(y) ν_a and −φ²_j(y) τ_a; σ^n(v) and σ^t(v) are the slave's
            let eta = Segment::new(opposite.ends[0], opposite.ends[1]).point(s);
            lagrange::values(self.order, eta, &mut phi[..nb]);
            for phi_j in &phi[..nb] {
                u_n.extend(nu.map(|nu_a| -phi_j * nu_a));
                u_t.extend(tau.map(|tau_a| -phi_j * tau_a));
            }
            sigma_n.resize(4 * nb, 0.0);
            sigma_t.resize(4 * nb, 0.0);
            // g = (y − x)·ν, from the two cells' origins: (y₀ − x₀)·ν is in g₀
            let [y, x] = [linear(&opposite.map, eta), offset];
            gap += dot(sub(y, x), nu);
        }
        FacePoint { x: face.map.to_physical(xi), gap, sigma_n, u_n, sigma_t, u_t }
    }

    /// g₀, the gap at the origin x₀ of face k's cell: g(x₀), plus (y₀ − x₀)·ν on a joint, y₀
    /// the origin of the master cell.
    pub fn gap_origin(&self, k: usize) -> f64 {
        let face = &self.faces[k];
        let (x0, nu) = (face.map.origin, face.direction);
        let apart = face.opposite.as_ref().map_or(0.0, |o| {
            let y0 = o.map.origin;
            dot(sub(y0, x0), nu)
        });
        self.parameters(k).gap.at(x0) + apart
    }

    /// The [`FaceDisplacement`] of face k for the local nodal values `hi` + `lo` (index 2i + a,
    /// as [`Nitsche::face_dofs`]; `lo` None: a double u_h).
    pub fn local(&self, k: usize, hi: &[f64], lo: Option<&[f64]>) -> FaceDisplacement {
        self.relative_to(k, hi, lo, self.gap_origin(k))
    }

    /// The [`FaceDisplacement`] of the increment w = (hi − hi_prev) + lo from the local values
    /// `hi_prev` to `hi` + `lo`: no gap.
    pub fn increment(&self, k: usize, hi: &[f64], lo: Option<&[f64]>, hi_prev: &[f64]) -> FaceDisplacement {
        let w: Vec<f64> = hi.iter().zip(hi_prev).map(|(a, b)| a - b).collect();
        self.relative_to(k, &w, lo, 0.0)
    }

    /// Nodal differences of `hi` + `lo` per cell, and the jump of the first nodes along ν less
    /// `g0` and along τ, each as the compensated sum of the exact products hi·d (by FMA), lo·d
    /// and −g0.
    fn relative_to(&self, k: usize, hi: &[f64], lo: Option<&[f64]>, g0: f64) -> FaceDisplacement {
        let block = 2 * lagrange::n_basis(self.order);
        let lo_at = |i: usize| lo.map_or(0.0, |lo| lo[i]);
        let relative = (0..hi.len())
            .map(|i| {
                let first = i / block * block + i % 2;
                (hi[i] - hi[first]) + (lo_at(i) - lo_at(first))
            })
            .collect();
        let nu = self.faces[k].direction;
        let jump = |d: Vector, offset: f64| {
            let mut terms = vec![-offset];
            // the slave's first node, then minus the master's
            for (first, sign) in (0..hi.len()).step_by(block).zip([1.0, -1.0]) {
                for a in 0..D {
                    let product = sign * hi[first + a] * d[a];
                    terms.extend([
                        product,
                        (sign * hi[first + a]).mul_add(d[a], -product),
                        sign * lo_at(first + a) * d[a],
                    ]);
                }
            }
            compensated_sum(&terms)
        };
        FaceDisplacement { relative, normal: jump(nu, g0), tangential: jump(tangent(nu), 0.0) }
    }

    /// P_γ(u_h) = σ^n(u_h) + p_u − γ(u_h^n − g) at a face point, with σ^n(u_h) from the nodal
    /// differences and u_h^n − g = (u¹_0 − u²_0)·ν − g₀ + Σ_k φ_k (u_k − u_0)·ν − (g − g₀)
    /// ([`FaceDisplacement`]).
    pub fn p_gamma(&self, k: usize, point: &FacePoint, u: &FaceDisplacement) -> f64 {
        let gamma = self.faces[k].gamma;
        let sigma_n = dof_dot(&point.sigma_n, &u.relative);
        let gap = u.normal + (dof_dot(&point.u_n, &u.relative) - point.gap);
        sigma_n + self.uplift_at(k, point.x) - gamma * gap
    }

    /// P_γ(u) − P_γ(u_prev) = σ^n(w) − γ w^n at a face point, for the increment w = u − u_prev
    /// ([`Nitsche::increment`]).
    pub fn p_increment(&self, k: usize, point: &FacePoint, w: &FaceDisplacement) -> f64 {
        dof_dot(&point.sigma_n, &w.relative) - self.faces[k].gamma * (w.normal + dof_dot(&point.u_n, &w.relative))
    }

    /// The index in `uplift` of the diagram on face `k`'s curve, if any.
    pub fn uplift_index(&self, k: usize) -> Option<usize> {
        self.uplift_of[self.faces[k].curve]
    }

    /// The uplift diagram on face `k`'s curve, if any.
    pub fn diagram(&self, k: usize) -> Option<&Uplift> {
        self.uplift_index(k).map(|d| &self.uplift[d].diagram)
    }

    /// The uplift p_u of face `k`'s curve at a point x of it (0 without uplift there).
    pub fn uplift_at(&self, k: usize, x: Point) -> f64 {
        self.diagram(k).map_or(0.0, |up| up.pressure(up.distance(x), up.crack))
    }

    /// P^t_γ(u_h) = σ^t(u_h) − γ (u_h^t − u^t_0) at a face point, u_h^t = (u¹_0 − u²_0)·τ +
    /// Σ_k φ_k (u_k − u_0)·τ and u^t_0 that of the slip origin (0 without one).
    pub fn p_tangential(&self, k: usize, point: &FacePoint, u: &FaceDisplacement) -> f64 {
        let origin = self.origin_faces.get(k).map_or(0.0, |u0| u0.tangential + dof_dot(&point.u_t, &u0.relative));
        self.t_increment(k, point, u) + self.faces[k].gamma * origin
    }

    /// P^t_γ(u) − P^t_γ(u_prev) = σ^t(w) − γ w^t at a face point, for the increment w = u − u_prev
    /// ([`Nitsche::increment`]).
    pub fn t_increment(&self, k: usize, point: &FacePoint, w: &FaceDisplacement) -> f64 {
        dof_dot(&point.sigma_t, &w.relative) - self.faces[k].gamma * (w.tangential + dof_dot(&point.u_t, &w.relative))
    }

    /// u_h·ν and u_h·τ at a face point (the jump on a joint).
    pub fn displacement_at(&self, k: usize, point: &FacePoint, u: &FaceDisplacement) -> [f64; 2] {
        [
            u.normal + self.gap_origin(k) + dof_dot(&point.u_n, &u.relative),
            u.tangential + dof_dot(&point.u_t, &u.relative),
        ]
    }

    /// The joint law's tangential traction Π_S(P^t_γ(u_h)) at a face point.
    pub fn tangential(&self, k: usize, point: &FacePoint, u: &FaceDisplacement, smoothing: Smoothing) -> Tangential {
        let (p_n, p_t) = (self.p_gamma(k, point, u), self.p_tangential(k, point, u));
        self.law(k).tangential(p_n, p_t, smoothing, &self.normal_law(k))
    }

    /// The Γ_C traction t = (N(P_γ(u_h)) − p_u) ν + Π_S(P^t_γ(u_h)) τ at a face point, N the
    /// face's normal law with the smoothing q (`Smoothing::NONE`: the exact traction).
    pub fn traction(&self, k: usize, point: &FacePoint, u: &FaceDisplacement, smoothing: Smoothing) -> Vector {
        let normal = self.normal_law(k).value(self.p_gamma(k, point, u), smoothing) - self.uplift_at(k, point.x);
        let tangential = if self.law(k).has_friction() { self.tangential(k, point, u, smoothing).value } else { 0.0 };
        self.along(k, normal, tangential)
    }

    /// The traction linearised at `u_prev`, evaluated at u = u_prev + `step`:
    /// t(u_prev) + t'(u_prev) w with w = u − u_prev ([`Nitsche::increment`]), the Γ_C traction
    /// of the Newton step from `u_prev`.
    pub fn linearised_traction(
        &self,
        k: usize,
        point: &FacePoint,
        u_prev: &FaceDisplacement,
        step: &FaceDisplacement,
        smoothing: Smoothing,
    ) -> Vector {
        let [normal, tangential] = self.linearised(k, point, u_prev, step, smoothing);
        self.along(k, normal - self.uplift_at(k, point.x), tangential)
    }

    /// N(P_γ(u_prev)) + N'(P_γ(u_prev)) P_γ'(w) and, with friction, Π(u_prev) + ∂_tΠ P^t_γ'(w) +
    /// ∂_nΠ P_γ'(w) (else 0), for the increment w = `step`: the linearised projections.
    fn linearised(
        &self,
        k: usize,
        point: &FacePoint,
        u_prev: &FaceDisplacement,
        step: &FaceDisplacement,
        smoothing: Smoothing,
    ) -> [f64; 2] {
        let (p_prev, dp) = (self.p_gamma(k, point, u_prev), self.p_increment(k, point, step));
        let law = self.normal_law(k);
        let normal = law.value(p_prev, smoothing) + law.derivative(p_prev, smoothing) * dp;
        let tangential = if self.law(k).has_friction() {
            let t = self.tangential(k, point, u_prev, smoothing);
            t.value + t.d_tangential * self.t_increment(k, point, step) + t.d_normal * dp
        } else {
            0.0
        };
        [normal, tangential]
    }

    /// t_n ν + t_t τ on face k, τ = (−ν_y, ν_x).
    fn along(&self, k: usize, normal: f64, tangential: f64) -> Vector {
        let nu = self.faces[k].direction;
        [normal * nu[0] - tangential * nu[1], normal * nu[1] + tangential * nu[0]]
    }
}

/// Jξ: the point of reference coordinates ξ relative to the map's origin.
fn linear(map: &AffineMap, xi: Point) -> Vector {
    let j = map.jacobian;
    [j[0][0] * xi[0] + j[0][1] * xi[1], j[1][0] * xi[0] + j[1][1] * xi[1]]
}

/// Σ terms in compensated arithmetic (TwoSum on each addition, the errors summed apart): as
/// accurate as if summed in twice the working precision, then rounded.
fn compensated_sum(terms: &[f64]) -> f64 {
    let (mut sum, mut error) = (0.0, 0.0);
    for &t in terms {
        let (s, e) = two_sum(sum, t);
        (sum, error) = (s, error + e);
    }
    sum + error
}

/// Σ a_i b_i over the dofs of a face's cells.
pub(super) fn dof_dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
