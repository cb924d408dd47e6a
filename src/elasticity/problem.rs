//! The plane-strain boundary value problem and its Galerkin solution.
//!
//! Find u_h ∈ V_h, u_h = g_D on Γ_D (nodal interpolation), such that for all v_h ∈ V_h,0
//!
//!   (σ(u_h), ε(v_h)) = (f, v_h) + (g_N, v_h)_{Γ_N}.
//!
//! Boundary conditions refer to physical curve tags of the mesh. A Dirichlet condition may
//! fix one component only (a roller).

use super::displacement::Displacement;
use super::kernels;
use super::material::Material;
use super::rigid;
use crate::fem::dofs::{DofMap, FIXED};
use crate::fem::quadrature::{gauss_segment_cached, split_rule, Rule1d};
use crate::fem::sparse::{vector_dofs, LinearSystem, Local, SparsePattern};
use crate::fem::tabulate::Tabulation;
use crate::fem::transfer::interpolate_by_tag;
use crate::geometry::{bounding_box, distance, norm, AffineMap, Point, Vector, D};
use crate::mesh::{Mesh, Topology};
use crate::solve::{two_sum, Cholesky, SolveError};
use rayon::prelude::*;
use std::sync::Arc;

/// A vector field x ↦ v(x).
pub type VectorFn = Arc<dyn Fn(Point) -> Vector + Send + Sync>;

/// Prescribed displacement on the facets tagged `tag`, for the components marked in `fix`.
#[derive(Clone)]
pub struct Dirichlet {
    pub tag: i32,
    pub fix: [bool; 2],
    pub value: VectorFn,
}

/// Traction g_N on a Neumann boundary.
#[derive(Clone)]
pub enum Traction {
    /// A constant vector \[Pa\].
    Constant(Vector),
    /// Water pressure p = ρ_w g (H_w − y)₊ acting along −n (g points along −y).
    Hydrostatic { density: f64, gravity: f64, level: f64 },
    /// The water pressure of `Hydrostatic` with Westergaard's added pressure of a horizontal
    /// pseudo-static acceleration a_x (in g) on the face of a reservoir of depth H:
    /// p = ρ_w g z + (7/8) a_n cos θ ρ_w g √(H z), z = (H_w − y)₊, a_n = −a_x n_x = a_x cos θ
    /// the acceleration towards the water (a suction where the face moves away from it), θ the
    /// face's angle from the vertical: on an inclined face the added pressure, along the
    /// normal, is the vertical face's times cos²θ (CADAM3D's cos² correction).
    Westergaard { density: f64, gravity: f64, level: f64, depth: f64, acceleration: f64 },
    /// Silt: a horizontal earth pressure p = `gradient` (level − y)₊ against the face,
    /// g_N = −p (n_x, 0) (its horizontal force is p times the face's vertical projection).
    Silt { gradient: f64, level: f64 },
    /// Ice: a horizontal pressure p = F / t against the face between `bottom` = level − t and
    /// `top` = level, g_N = −p (n_x, 0): the ice sheet's line load F spread over its thickness t.
    Ice { pressure: f64, bottom: f64, top: f64 },
    /// Several of them on one curve, added.
    Sum(Vec<Traction>),
    /// Any field of x.
    Field(VectorFn),
}

impl Traction {
    /// Parameters s ∈ (0, 1) of the segment a → b where g_N has a kink: the water level of
    /// a hydrostatic pressure. Quadrature on a facet is split there.
    pub fn kinks(&self, [a, b]: [Point; 2]) -> Vec<f64> {
        let at_level = |level: f64| {
            let s = (level - a[1]) / (b[1] - a[1]);
            (b[1] != a[1] && s > 0.0 && s < 1.0).then_some(s)
        };
        match self {
            Traction::Hydrostatic { level, .. }
            | Traction::Westergaard { level, .. }
            | Traction::Silt { level, .. } => at_level(*level).into_iter().collect(),
            Traction::Ice { bottom, top, .. } => [*bottom, *top].into_iter().filter_map(at_level).collect(),
            Traction::Sum(parts) => {
                let mut kinks: Vec<f64> = parts.iter().flat_map(|t| t.kinks([a, b])).collect();
                kinks.sort_by(f64::total_cmp);
                kinks.dedup();
                kinks
            }
            Traction::Constant(_) | Traction::Field(_) => vec![],
        }
    }

    /// The parts of a sum, or the traction itself.
    pub fn parts(&self) -> &[Traction] {
        match self {
            Traction::Sum(parts) => parts,
            other => std::slice::from_ref(other),
        }
    }

    /// g_N at point x of a facet with outward normal n.
    pub fn at(&self, x: Point, n: Vector) -> Vector {
        match self {
            Traction::Constant(t) => *t,
            Traction::Hydrostatic { density, gravity, level } => {
                let p = density * gravity * (level - x[1]).max(0.0);
                [-p * n[0], -p * n[1]]
            }
            Traction::Westergaard { density, gravity, level, .. } => {
                let p = density * gravity * (level - x[1]).max(0.0);
                let added = self.hydrodynamic(x, n);
                [-p * n[0] + added[0], -p * n[1] + added[1]]
            }
            Traction::Silt { gradient, level } => [-gradient * (level - x[1]).max(0.0) * n[0], 0.0],
            Traction::Ice { pressure, bottom, top } => match (bottom..=top).contains(&&x[1]) {
                true => [-pressure * n[0], 0.0],
                false => [0.0; 2],
            },
            Traction::Sum(parts) => parts.iter().map(|t| t.at(x, n)).fold([0.0; 2], |s, g| [s[0] + g[0], s[1] + g[1]]),
            Traction::Field(f) => f(x),
        }
    }

    /// Westergaard's added pressure of g_N at x, −(7/8) a_n cos θ ρ_w g √(H z) n, cos θ = |n_x|
    /// (0 for the other tractions).
    pub fn hydrodynamic(&self, x: Point, n: Vector) -> Vector {
        match self {
            Traction::Westergaard { density, gravity, level, depth, acceleration } => {
                let z = (level - x[1]).max(0.0);
                let p = 0.875 * (-acceleration * n[0]) * n[0].abs() * density * gravity * (depth * z).sqrt();
                [-p * n[0], -p * n[1]]
            }
            Traction::Sum(parts) => {
                parts.iter().map(|t| t.hydrodynamic(x, n)).fold([0.0; 2], |s, g| [s[0] + g[0], s[1] + g[1]])
            }
            _ => [0.0; 2],
        }
    }

    /// The water level of Westergaard's pressure among the parts, where √z is singular.
    fn westergaard_level(&self) -> Option<f64> {
        self.parts().iter().find_map(|t| match t {
            Traction::Westergaard { level, .. } => Some(*level),
            _ => None,
        })
    }
}

/// Traction on the facets tagged `tag`.
#[derive(Clone)]
pub struct Neumann {
    pub tag: i32,
    pub traction: Traction,
}

/// Volume force f.
#[derive(Clone)]
pub enum BodyForce {
    None,
    /// f = ρ a with the density of each material: self-weight for a = (0, −g), plus a
    /// pseudo-static acceleration.
    Acceleration(Vector),
    Field(VectorFn),
}

/// Everything that defines the discrete problem.
#[derive(Clone)]
pub struct Problem {
    pub mesh: Mesh,
    /// Material of each cell.
    pub materials: Vec<Material>,
    pub dirichlet: Vec<Dirichlet>,
    pub neumann: Vec<Neumann>,
    pub body_force: BodyForce,
}

/// Degree of the triangle rule for the body force (f, v): exact for f ∈ P_{p+6}. The
/// estimator integrates its divergence data with the same rule, so that the discrete
/// equilibrium it reconstructs is exactly the one that was solved.
pub fn load_degree(order: usize) -> usize {
    2 * order + 6
}

/// The rule (s, weight) on [0, 1] for tractions (g_N, v)_F on the facet with end points
/// `ends`: p + 4 Gauss points on each piece between the kinks of g_N. The estimator uses the
/// same rule.
pub fn traction_rule(traction: &Traction, ends: [Point; 2], order: usize) -> Vec<(f64, f64)> {
    let gauss = gauss_segment_cached(order + 4);
    match traction.westergaard_level() {
        Some(level) => graded_at_surface(gauss, traction.kinks(ends), ends, level),
        None => split_rule(gauss, traction.kinks(ends)),
    }
}

/// The rule of [`split_rule`], but on a wet piece whose shallow end e lies at the water surface
/// (√z there) in s = e + (f − e) u², f the deep end: √z ∝ u, so the integrand is a
/// polynomial in u, which the p + 4 Gauss points in u integrate exactly for p ≤ 2.
fn graded_at_surface(gauss: &Rule1d, mut cuts: Vec<f64>, ends: [Point; 2], level: f64) -> Vec<(f64, f64)> {
    let depth = |s: f64| level - (ends[0][1] + s * (ends[1][1] - ends[0][1]));
    cuts.extend([0.0, 1.0]);
    cuts.sort_by(f64::total_cmp);
    let points = || gauss.points.iter().zip(&gauss.weights);
    cuts.windows(2)
        .filter(|w| w[1] > w[0])
        .flat_map(|w| {
            let (shallow, deep) = if depth(w[0]) <= depth(w[1]) { (w[0], w[1]) } else { (w[1], w[0]) };
            let at_surface = depth(shallow).abs() <= 1e-12 * (1.0 + level.abs()) && depth(deep) > 0.0;
            let piece: Vec<(f64, f64)> = match at_surface {
                true => points()
                    .map(|(&u, &wu)| (shallow + (deep - shallow) * u * u, wu * 2.0 * u * (w[1] - w[0])))
                    .collect(),
                false => points().map(|(&s, &ws)| (w[0] + s * (w[1] - w[0]), ws * (w[1] - w[0]))).collect(),
            };
            piece
        })
        .collect()
}

/// The free unknowns of a refined linear solve as the unevaluated sum x + lo, x = fl(x + lo).
#[derive(Debug, Clone)]
pub struct Refined {
    pub x: Vec<f64>,
    pub lo: Vec<f64>,
}

impl Refined {
    /// The nodal displacements hi + lo (lo = 0 on Dirichlet dofs).
    pub fn displacement(&self, problem: &Problem, disc: &Discretisation) -> Displacement {
        let lo = disc.dofs.free.iter().map(|&k| if k == FIXED { 0.0 } else { self.lo[k] });
        let lo: Vec<f64> = lo.collect();
        Displacement {
            hi: problem.displacement(disc, &self.x),
            lo: Some(lo.chunks_exact(2).map(|u| [u[0], u[1]]).collect()),
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Dof numbering and matrix pattern of a problem, built once per mesh.
pub struct Discretisation {
    pub topology: Topology,
    pub dofs: DofMap,
    pub pattern: SparsePattern,
}

/// The element rules of the stiffness (degree 2(p − 1)) and of the body load
/// ([`load_degree`]), with the integrals of the basis of the latter.
struct CellKernel {
    stiffness: Tabulation,
    load: Tabulation,
    load_integrals: Vec<f64>,
}

impl CellKernel {
    fn new(order: usize) -> Self {
        let load = Tabulation::new(order, load_degree(order));
        CellKernel { stiffness: Tabulation::new(order, 2 * order - 2), load_integrals: load.integrals(), load }
    }
}

impl Problem {
    /// The body force f(x) [N/m³] at the point `x` of cell `c`.
    pub fn body_force_at(&self, c: usize, x: Point) -> Vector {
        match &self.body_force {
            BodyForce::None => [0.0; 2],
            BodyForce::Acceleration(a) => a.map(|a| self.materials[c].density * a),
            BodyForce::Field(field) => field(x),
        }
    }

    /// Solves the problem without contact: K x = b by sparse Cholesky; the free unknowns.
    pub fn solve_linear(&self, disc: &Discretisation) -> Result<Vec<f64>, SolveError> {
        let system = self.assemble(disc);
        Cholesky::analyse(&disc.pattern)?.solve(&disc.pattern, &system.values, &system.rhs)
    }

    /// Solves K x = b by sparse Cholesky, then one step of iterative refinement into a
    /// correction below the rounding of x: lo = K⁻¹ r with r = F − K x the difference-form
    /// [`Problem::residual`], and (x, lo) renormalised by TwoSum so that x = fl(x + lo). A
    /// double x solves the discrete equation only to about ε E |u_h| per vertex; the pair
    /// x + lo solves it to the round-off of the strain (docs/method.md §5.2).
    pub fn solve_refined(&self, disc: &Discretisation) -> Result<Refined, SolveError> {
        let system = self.assemble(disc);
        let cholesky = Cholesky::analyse(&disc.pattern)?;
        let factors = cholesky.factor(&disc.pattern, &system.values)?;
        let solve = |b: &[f64]| -> Result<Vec<f64>, SolveError> {
            let mut m = faer::Mat::from_fn(b.len(), 1, |i, _| b[i]);
            factors.solve_in_place(&mut m)?;
            Ok((0..b.len()).map(|i| m[(i, 0)]).collect())
        };
        let x = solve(&system.rhs)?;
        let r = self.residual(disc, &self.displacement(disc, &x).into());
        let (x, lo) = x.iter().zip(solve(&r)?).map(|(&x, d)| two_sum(x, d)).unzip();
        Ok(Refined { x, lo })
    }

    /// Number of displacement unknowns 2 × nodes (constrained ones included).
    pub fn n_dofs(&self) -> usize {
        2 * self.mesh.n_points()
    }

    /// Topology, dof map (Dirichlet values interpolated at the nodes) and sparsity pattern.
    pub fn discretise(&self) -> Discretisation {
        let topology = Topology::new(&self.mesh);
        let mut constraints = Vec::new();
        for bc in &self.dirichlet {
            for f in (0..self.mesh.n_facets()).filter(|&f| self.mesh.facet_tags[f] == bc.tag) {
                for &n in self.mesh.facet(f) {
                    let g = (bc.value)(self.mesh.points[n]);
                    constraints.extend((0..D).filter(|&a| bc.fix[a]).map(|a| (2 * n + a, g[a])));
                }
            }
        }
        let dofs = DofMap::new(self.mesh.n_points(), 2, &constraints);
        let pattern = SparsePattern::new(&self.mesh, &dofs);
        Discretisation { topology, dofs, pattern }
    }

    /// Assembles K and F over the free dofs, with Dirichlet values moved to the right.
    pub fn assemble(&self, disc: &Discretisation) -> LinearSystem {
        self.assemble_on(disc, &disc.pattern)
    }

    /// [`Problem::assemble`] on `pattern`, a pattern of `disc`'s dofs that holds its own.
    pub fn assemble_on(&self, disc: &Discretisation, pattern: &SparsePattern) -> LinearSystem {
        let mut system = LinearSystem::zeros(pattern);
        self.add_stiffness_and_body_force(disc, pattern, &mut system);
        self.add_tractions(disc, &mut system);
        system
    }

    fn add_stiffness_and_body_force(&self, disc: &Discretisation, pattern: &SparsePattern, system: &mut LinearSystem) {
        let kernel = CellKernel::new(self.mesh.order);
        let nb = kernel.stiffness.n_basis;
        let dofs_of = |c: usize, out: &mut Vec<usize>| vector_dofs(self.mesh.cell(c), out);
        system.assemble(pattern, &disc.dofs, self.mesh.n_cells(), 2 * nb, dofs_of, |c, local| {
            self.cell_terms(&kernel, c, local)
        });
    }

    /// The element stiffness K_T and body load f_T of cell c into `local`.
    fn cell_terms(&self, kernel: &CellKernel, c: usize, local: &mut Local) {
        let map = AffineMap::new(self.mesh.cell_vertices(c));
        let (lambda, mu) = self.materials[c].lame();
        // physical gradients: at most 4 points (the rule of degree 2) × 6 basis functions
        let mut grads = [[0.0; 2]; 24];
        let grads = &mut grads[..kernel.stiffness.gradients.len()];
        kernels::stiffness(&map, &kernel.stiffness, lambda, mu, grads, &mut local.matrix);
        match &self.body_force {
            BodyForce::None => local.load.fill(0.0),
            // constant on the cell: ∫_T f φ_i = f |det J| m_i
            BodyForce::Acceleration(_) => {
                let f = self.body_force_at(c, map.origin);
                kernels::constant_body_load(&map, &kernel.load_integrals, f, &mut local.load)
            }
            BodyForce::Field(_) => {
                kernels::body_load(&map, &kernel.load, |x| self.body_force_at(c, x), &mut local.load)
            }
        }
    }

    /// The residual F − K u of the free rows for the nodal displacements `u`, cell by cell in
    /// difference form: K_T u_T = K_T d_T with d_k = u_k − u_0 ([`Displacement::relative`]),
    /// since K_T annihilates translations. Its round-off is then ε |K_T| |d_T|, the size of
    /// the strain, instead of ε |K_T| |u_T|.
    pub fn residual(&self, disc: &Discretisation, u: &Displacement) -> Vec<f64> {
        let kernel = CellKernel::new(self.mesh.order);
        let n = 2 * kernel.stiffness.n_basis;
        let mut r = vec![0.0; disc.dofs.n_free];
        let mut add = |nodes: &[usize], f: &[f64]| {
            for (k, &fk) in nodes.iter().flat_map(|&node| [2 * node, 2 * node + 1]).zip(f) {
                if disc.dofs.free[k] != FIXED {
                    r[disc.dofs.free[k]] += fk;
                }
            }
        };
        // f_T − K_T d_T of every cell in parallel, added in cell order (the same bits on any
        // number of threads)
        let cells: Vec<Vec<f64>> = (0..self.mesh.n_cells())
            .into_par_iter()
            .map_init(
                || (Local::new(n), Vec::new()),
                |(local, d), c| {
                    self.cell_terms(&kernel, c, local);
                    u.relative(self.mesh.cell(c), d);
                    let d: Vec<f64> = d.iter().flatten().copied().collect();
                    (0..n).map(|i| local.load[i] - dot(&local.matrix[i * n..(i + 1) * n], &d)).collect()
                },
            )
            .collect();
        for (c, f) in cells.iter().enumerate() {
            add(self.mesh.cell(c), f);
        }
        self.traction_loads(&disc.topology, add);
        r
    }

    fn add_tractions(&self, disc: &Discretisation, system: &mut LinearSystem) {
        let mut local = Vec::new();
        self.traction_loads(&disc.topology, |nodes, f| {
            vector_dofs(nodes, &mut local);
            system.add_load(&disc.dofs, &local, f);
        });
    }

    /// Visits each Neumann facet with its nodes and load vector ∫_F g_N·φ_i (x, y interleaved).
    fn traction_loads(&self, topology: &Topology, mut visit: impl FnMut(&[usize], &[f64])) {
        let p = self.mesh.order;
        let mut phi = vec![0.0; p + 1];
        let mut f = vec![0.0; 2 * (p + 1)];
        for bc in &self.neumann {
            for facet in (0..self.mesh.n_facets()).filter(|&k| self.mesh.facet_tags[k] == bc.tag) {
                let nodes = self.mesh.facet(facet);
                let n = topology.outward_normal(&self.mesh, facet);
                let ends = [self.mesh.points[nodes[0]], self.mesh.points[nodes[1]]];
                let rule = traction_rule(&bc.traction, ends, p);
                kernels::traction_load(ends, p, &rule, |x| bc.traction.at(x, n), &mut phi, &mut f);
                visit(nodes, &f);
            }
        }
    }

    /// The resultant of the loads, ∫_Ω f + ∫_{Γ_N} g_N \[N/m\]: the sum of the load vector's
    /// components (the basis is a partition of unity).
    pub fn load_resultant(&self, topology: &Topology) -> Vector {
        let mut resultant = [0.0; 2];
        let mut add = |load: &[f64]| load.iter().enumerate().for_each(|(i, v)| resultant[i % 2] += v);
        if !matches!(self.body_force, BodyForce::None) {
            let p = self.mesh.order;
            let tab = Tabulation::new(p, load_degree(p));
            let mut load = vec![0.0; 2 * tab.n_basis];
            for c in 0..self.mesh.n_cells() {
                let map = AffineMap::new(self.mesh.cell_vertices(c));
                kernels::body_load(&map, &tab, |x| self.body_force_at(c, x), &mut load);
                add(&load);
            }
        }
        self.traction_loads(topology, |_, f| add(f));
        resultant
    }

    /// A stress scale S \[Pa\] of the loads: the largest of max|g_N|, max|f| · diam(Ω) and
    /// max E |g_D| / diam(Ω), sampled at the boundary nodes and cell centroids. Used to set
    /// the regularisation δ, which must never scale with E alone.
    pub fn stress_scale(&self, topology: &Topology) -> f64 {
        let mesh = &self.mesh;
        let [lo, hi] = bounding_box(mesh.points.iter().copied());
        let diam = distance(lo, hi);
        let traction = self.neumann.iter().flat_map(|bc| {
            (0..mesh.n_facets()).filter(move |&f| mesh.facet_tags[f] == bc.tag).flat_map(move |f| {
                let n = topology.outward_normal(mesh, f);
                mesh.facet(f).iter().map(move |&node| norm(bc.traction.at(mesh.points[node], n)))
            })
        });
        let body = (0..mesh.n_cells()).map(|c| norm(self.body_force_at(c, mesh.cell_centroid(c))) * diam);
        let young = self.materials.iter().map(|m| m.young).fold(0.0, f64::max);
        let imposed = self.dirichlet.iter().flat_map(|bc| {
            (0..mesh.n_facets()).filter(move |&f| mesh.facet_tags[f] == bc.tag).flat_map(move |f| {
                mesh.facet(f).iter().map(move |&node| young * norm((bc.value)(mesh.points[node])) / diam)
            })
        });
        traction.chain(body).chain(imposed).fold(0.0, f64::max)
    }

    /// The rigid motion r = a + b(−y, x) that the Dirichlet conditions and the normal
    /// `supports` (point, unit normal) leave free, if any, in words. The functionals
    /// r ↦ r_a(x_n) of the constrained dofs and r ↦ r(x)·n of the supports must span the
    /// 3-dimensional space of rigid motions: their Gram matrix must be nonsingular.
    pub fn free_rigid_motion(&self, supports: &[(Point, Vector)]) -> Option<String> {
        self.free_rigid_motion_of(&vec![true; self.mesh.n_points()], supports)
    }

    /// [`Problem::free_rigid_motion`] of the body of the nodes marked in `body`: its Dirichlet
    /// nodes and the `supports` (which the caller takes on that body).
    pub fn free_rigid_motion_of(&self, body: &[bool], supports: &[(Point, Vector)]) -> Option<String> {
        let mesh = &self.mesh;
        let points: Vec<Point> = (0..mesh.n_points()).filter(|&k| body[k]).map(|k| mesh.points[k]).collect();
        let n = points.len() as f64;
        let centre = points.iter().fold([0.0; 2], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
        let size = points.iter().map(|p| distance(*p, centre)).fold(f64::MIN_POSITIVE, f64::max);
        let fixed = self.dirichlet.iter().flat_map(|bc| {
            let facets = (0..mesh.n_facets()).filter(move |&f| mesh.facet_tags[f] == bc.tag);
            facets.flat_map(|f| mesh.facet(f).iter()).filter(|&&node| body[node]).flat_map(move |&node| {
                let directions = [[1.0, 0.0], [0.0, 1.0]].into_iter().zip(bc.fix).filter(|(_, fixed)| *fixed);
                directions.map(move |(d, _)| (mesh.points[node], d))
            })
        });
        let v = *rigid::free_motions(fixed.chain(supports.iter().copied()), centre, size).first()?;
        let parts: Vec<&str> = [(v[0], "a translation along x"), (v[1], "a translation along y"), (v[2], "a rotation")]
            .into_iter()
            .filter(|(c, _)| c.abs() > 0.1)
            .map(|(_, name)| name)
            .collect();
        Some(parts.join(" combined with "))
    }

    /// Nodal displacements from the free unknowns.
    pub fn displacement(&self, disc: &Discretisation, x: &[f64]) -> Vec<Vector> {
        nodal(&disc.dofs.expand(x))
    }

    /// The free unknowns of the displacement `u` of `old` interpolated at the nodes of this
    /// problem's mesh (its Dirichlet values are this problem's), each node from the cells of
    /// `old` with the physical surface of its own cells: the two copies of a node on a joint
    /// between two bodies take the values of their own sides.
    pub fn interpolated(&self, disc: &Discretisation, old: &Mesh, u: &[Vector]) -> Vec<f64> {
        let mesh = &self.mesh;
        let mut tags = vec![0; mesh.n_points()];
        for c in 0..mesh.n_cells() {
            for &n in mesh.cell(c) {
                tags[n] = mesh.cell_tags[c];
            }
        }
        let values = interpolate_by_tag(old, u, &mesh.points, &tags);
        let mut x = vec![0.0; disc.dofs.n_free];
        for (dof, &k) in disc.dofs.free.iter().enumerate() {
            if k != FIXED {
                x[k] = values[dof / 2][dof % 2];
            }
        }
        x
    }
}

/// The nodal displacements of the values `u_full` of every dof (2i + a).
pub fn nodal(u_full: &[f64]) -> Vec<Vector> {
    u_full.chunks_exact(2).map(|u| [u[0], u[1]]).collect()
}
