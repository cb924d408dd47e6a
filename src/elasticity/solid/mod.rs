//! Linear elasticity of a solid on tetrahedra (P1, P2).
//!
//! Find u_h ∈ V_h, u_h = g_D on Γ_D (nodal interpolation, per fixed component), such that for
//! all v_h ∈ V_h,0
//!
//!   (σ(u_h), ε(v_h)) = (f, v_h) + (g_N, v_h)_{Γ_N},   σ = λ tr ε I + 2μ ε.
//!
//! The vertical axis is z: the weight is f = −ρ g e_z and a water pressure
//! p = ρ_w g (H_w − z)₊ acts along −n. K u = F is solved by sparse Cholesky, as in the plane.

pub mod facets;
pub mod kernels;

use super::material::Material;
use super::rigid::free_motions_3d;
use crate::fem::dofs::{DofMap, FIXED};
use crate::fem::sparse::{components_dofs, LinearSystem, Local, SparsePattern};
use crate::fem::tabulate::Tabulation;
use crate::fem::{lagrange, tetrahedron};
use crate::geometry::{distance3, Point3, TetMap, Vector3};
use crate::mesh::Mesh;
use crate::solve::petsc::{cg_gamg, Csr};
use crate::solve::{Cholesky, SolveError};
use std::sync::Arc;

/// A vector field of space x ↦ v(x).
pub type SolidField = Arc<dyn Fn(Point3) -> Vector3 + Send + Sync>;

/// Prescribed displacement on the facets tagged `tag`, for the components marked in `fix`.
#[derive(Clone)]
pub struct SolidDirichlet {
    pub tag: i32,
    pub fix: [bool; 3],
    pub value: SolidField,
}

/// Traction g_N on a Neumann surface.
#[derive(Clone)]
pub enum SolidTraction {
    /// A constant vector \[Pa\].
    Constant(Vector3),
    /// Water pressure p = ρ_w g (H_w − z)₊ along −n.
    Hydrostatic { density: f64, gravity: f64, level: f64 },
    /// Any field of x.
    Field(SolidField),
}

impl SolidTraction {
    /// g_N at x on a facet of outward normal n.
    pub fn at(&self, x: Point3, n: Vector3) -> Vector3 {
        match self {
            SolidTraction::Constant(t) => *t,
            SolidTraction::Hydrostatic { density, gravity, level } => {
                let p = density * gravity * (level - x[2]).max(0.0);
                n.map(|n| -p * n)
            }
            SolidTraction::Field(g) => g(x),
        }
    }
}

/// g_N on the facets tagged `tag`.
#[derive(Clone)]
pub struct SolidNeumann {
    pub tag: i32,
    pub traction: SolidTraction,
}

/// The body force.
#[derive(Clone)]
pub enum SolidBody {
    /// The weight −ρ g e_z of each cell's material, g \[m/s²\].
    Weight(f64),
    /// Any field of x \[N/m³\].
    Field(SolidField),
}

/// The boundary value problem of a solid.
#[derive(Clone)]
pub struct Solid {
    pub mesh: Mesh<3>,
    /// The material of each cell.
    pub materials: Vec<Material>,
    pub dirichlet: Vec<SolidDirichlet>,
    pub neumann: Vec<SolidNeumann>,
    pub body: SolidBody,
}

/// The assembled system of a solid: its dofs, the pattern of K and K u = F on the free dofs.
pub struct SolidSystem {
    pub dofs: DofMap,
    pub pattern: SparsePattern,
    pub system: LinearSystem,
}

/// How K u = F is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// Sparse Cholesky (faer).
    Direct,
    /// CG with PETSc's algebraic multigrid, to ‖r‖ ≤ [`ITERATIVE_RTOL`] ‖F‖.
    Iterative,
}

impl Solver {
    /// The solver of a system of `unknowns`: direct below [`ITERATIVE_FROM`], iterative from it.
    pub fn for_size(unknowns: usize) -> Solver {
        if unknowns < ITERATIVE_FROM {
            Solver::Direct
        } else {
            Solver::Iterative
        }
    }
}

/// The size from which the iterative solver is the faster (docs/results.md, "Solids").
pub const ITERATIVE_FROM: usize = 100_000;

/// The physical gradients of the stiffness rule: its 4 points (degree 2) × the 10 P2 basis
/// functions.
const STIFFNESS_GRADIENTS: usize = 4 * 10;

/// The relative residual of the iterative solve.
pub const ITERATIVE_RTOL: f64 = 1e-10;

/// A solution: the nodal displacements and the size of the system solved.
#[derive(Debug, Clone)]
pub struct SolidSolution {
    pub displacement: Vec<Vector3>,
    /// Free unknowns.
    pub unknowns: usize,
    /// Stored entries of the stiffness matrix (both triangles).
    pub nonzeros: usize,
    pub solver: Solver,
    /// CG iterations of the iterative solver.
    pub iterations: Option<usize>,
    /// The processes that solved: 1, or the iterative solver's team (`solve::petsc`).
    pub processes: usize,
}

/// Why a solid cannot be solved.
#[derive(Debug, thiserror::Error)]
pub enum SolidError {
    #[error("boundary triangle {facet} (physical surface {tag}) is not a face of any tetrahedron")]
    DetachedFacet { facet: usize, tag: i32 },
    #[error(transparent)]
    Solve(#[from] SolveError),
}

/// The system on every dof, in node blocks: the free rows of K and F, and d u_i = d g_i on a
/// Dirichlet dof i, d the mean diagonal of K.
fn whole_system(dofs: &DofMap, pattern: &SparsePattern, system: &LinearSystem) -> (Csr, Vec<f64>) {
    let symbolic = pattern.symbolic();
    let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
    let full_of: Vec<usize> = (0..dofs.n_dofs()).filter(|&i| dofs.free[i] != FIXED).collect();
    let diagonal =
        (0..pattern.n()).map(|k| system.values[pattern.position(k, k)]).sum::<f64>() / pattern.n().max(1) as f64;
    let mut csr =
        Csr { row_ptr: vec![0], col_idx: Vec::with_capacity(row_idx.len()), values: Vec::with_capacity(row_idx.len()) };
    let mut rhs = Vec::with_capacity(dofs.n_dofs());
    for (i, &k) in dofs.free.iter().enumerate() {
        if k == FIXED {
            csr.col_idx.push(i as i32);
            csr.values.push(diagonal);
            rhs.push(diagonal * dofs.fixed_value[i]);
        } else {
            // K is symmetric: column k of the pattern is row k
            csr.col_idx.extend(row_idx[col_ptr[k]..col_ptr[k + 1]].iter().map(|&r| full_of[r] as i32));
            csr.values.extend_from_slice(&system.values[col_ptr[k]..col_ptr[k + 1]]);
            rhs.push(system.rhs[k]);
        }
        csr.row_ptr.push(csr.col_idx.len() as i32);
    }
    (csr, rhs)
}

impl Solid {
    /// The dof map: the Dirichlet values interpolated at the nodes of their facets.
    pub fn dofs(&self) -> DofMap {
        let mut constraints = Vec::new();
        for bc in &self.dirichlet {
            for f in self.mesh.facets_tagged(&[bc.tag]) {
                for &n in self.mesh.facet(f) {
                    let g = (bc.value)(self.mesh.points[n]);
                    constraints.extend((0..3).filter(|&a| bc.fix[a]).map(|a| (3 * n + a, g[a])));
                }
            }
        }
        DofMap::new(self.mesh.n_points(), 3, &constraints)
    }

    /// K and F on the free dofs of `dofs`, assembled in parallel over the cells.
    pub fn assemble(&self, dofs: &DofMap, pattern: &SparsePattern) -> Result<LinearSystem, SolidError> {
        let rules = self.cell_rules();
        let mut system = LinearSystem::zeros(pattern);
        let mesh = &self.mesh;
        let dofs_of = |c: usize, out: &mut Vec<usize>| components_dofs::<3>(mesh.cell(c), out);
        let n_local = 3 * tetrahedron::n_basis(mesh.order);
        system.assemble(pattern, dofs, mesh.n_cells(), n_local, dofs_of, |c, local| self.cell_system(c, &rules, local));
        self.add_tractions(|local, f| system.add_load(dofs, local, f))?;
        Ok(system)
    }

    /// The rules of the cell kernel: the stiffness's (degree 2p − 2) and the body load's.
    fn cell_rules(&self) -> [Tabulation<3>; 2] {
        let p = self.mesh.order;
        // the weight is constant on a cell: φ_i's degree p is integrated exactly
        let load_degree = match self.body {
            SolidBody::Weight(_) => p,
            SolidBody::Field(_) => p + 4,
        };
        [Tabulation::tetrahedron(p, 2 * p - 2), Tabulation::tetrahedron(p, load_degree)]
    }

    /// Cell c's stiffness K_e and body load F_e into `local`, with the `rules` of [`Self::cell_rules`].
    fn cell_system(&self, c: usize, [stiffness, load]: &[Tabulation<3>; 2], local: &mut Local) {
        let map = TetMap::new(self.mesh.cell_vertices(c));
        let material = self.materials[c];
        let (lambda, mu) = material.lame();
        let mut grads = [[0.0; 3]; STIFFNESS_GRADIENTS];
        let nb = stiffness.n_basis;
        kernels::stiffness(&map, stiffness, lambda, mu, &mut grads[..stiffness.n_points() * nb], &mut local.matrix);
        match &self.body {
            SolidBody::Weight(g) => {
                kernels::body_load(&map, load, |_| [0.0, 0.0, -material.density * g], &mut local.load)
            }
            SolidBody::Field(f) => kernels::body_load(&map, load, |x| f(x), &mut local.load),
        }
    }

    /// The loads ∫_F g_N · φ_i of each Neumann facet F, handed to `add` with the facet's dofs;
    /// a water pressure's facets cut at the water plane.
    fn add_tractions(&self, mut add: impl FnMut(&[usize], &[f64])) -> Result<(), SolidError> {
        let mesh = &self.mesh;
        let p = mesh.order;
        let normals = facets::outward_normals(mesh)
            .map_err(|facet| SolidError::DetachedFacet { facet, tag: mesh.facet_tags[facet] })?;
        let whole = [[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]];
        let (mut phi, mut f, mut local) = (vec![0.0; lagrange::n_basis(p)], Vec::new(), Vec::new());
        for bc in &self.neumann {
            for facet in mesh.facets_tagged(&[bc.tag]) {
                let v = mesh.facet_vertices(facet);
                let (parts, degree) = match &bc.traction {
                    SolidTraction::Constant(_) => (whole.to_vec(), p),
                    SolidTraction::Hydrostatic { level, .. } => (facets::wet_parts(v.map(|x| level - x[2])), p + 1),
                    SolidTraction::Field(_) => (whole.to_vec(), p + 4),
                };
                f.clear();
                f.resize(3 * phi.len(), 0.0);
                let n = normals[facet];
                facets::traction_load(v, p, &parts, degree, |x| bc.traction.at(x, n), &mut phi, &mut f);
                components_dofs::<3>(mesh.facet(facet), &mut local);
                add(&local, &f);
            }
        }
        Ok(())
    }

    /// The dofs, the pattern and K u = F assembled on them.
    pub fn system(&self) -> Result<SolidSystem, SolidError> {
        let dofs = self.dofs();
        let pattern = SparsePattern::new(&self.mesh, &dofs);
        let system = self.assemble(&dofs, &pattern)?;
        Ok(SolidSystem { dofs, pattern, system })
    }

    /// Solves K u = F by `solver`, or by the solver of its size ([`Solver::for_size`]).
    pub fn solve(&self, solver: Option<Solver>) -> Result<SolidSolution, SolidError> {
        self.solve_system(&self.system()?, solver)
    }

    /// Solves the assembled `system` by `solver`, or by the solver of its size.
    pub fn solve_system(&self, system: &SolidSystem, solver: Option<Solver>) -> Result<SolidSolution, SolidError> {
        let SolidSystem { dofs, pattern, system } = system;
        let solver = solver.unwrap_or(Solver::for_size(dofs.n_free));
        let (u, iterations, processes) = match solver {
            Solver::Direct => {
                (dofs.expand(&Cholesky::analyse(pattern)?.solve(pattern, &system.values, &system.rhs)?), None, 1)
            }
            Solver::Iterative => {
                let (matrix, rhs) = whole_system(dofs, pattern, system);
                let coordinates: Vec<f64> = self.mesh.points.iter().flatten().copied().collect();
                let solution = cg_gamg(&matrix, &rhs, &coordinates, 3, ITERATIVE_RTOL)?;
                let u = solution.x.iter().zip(&dofs.free).zip(&dofs.fixed_value);
                let u = u.map(|((&x, &k), &g)| if k == FIXED { g } else { x }).collect();
                (u, Some(solution.iterations), solution.processes)
            }
        };
        Ok(SolidSolution {
            displacement: u.chunks_exact(3).map(|u| [u[0], u[1], u[2]]).collect(),
            unknowns: dofs.n_free,
            nonzeros: pattern.nnz(),
            solver,
            iterations,
            processes,
        })
    }

    /// The reaction force \[N\] of each Dirichlet surface, in the order of `dirichlet`:
    /// R = K u − F on its fixed dofs, summed element by element over the cells and the Neumann
    /// facets that touch a fixed node; a node that two surfaces fix counts for the first.
    pub fn reactions(&self, u: &[Vector3]) -> Result<Vec<(i32, Vector3)>, SolidError> {
        let mesh = &self.mesh;
        let mut fixed = vec![false; mesh.n_points()];
        for f in mesh.facets_tagged(&self.dirichlet.iter().map(|bc| bc.tag).collect::<Vec<_>>()) {
            mesh.facet(f).iter().for_each(|&n| fixed[n] = true);
        }
        let rules = self.cell_rules();
        let mut local = Local::new(3 * tetrahedron::n_basis(mesh.order));
        let mut r = vec![0.0; 3 * mesh.n_points()];
        for c in (0..mesh.n_cells()).filter(|&c| mesh.cell(c).iter().any(|&n| fixed[n])) {
            components_dofs::<3>(mesh.cell(c), &mut local.dofs);
            self.cell_system(c, &rules, &mut local);
            let n = local.dofs.len();
            for (i, &gi) in local.dofs.iter().enumerate() {
                let ku: f64 =
                    local.dofs.iter().enumerate().map(|(j, &gj)| local.matrix[i * n + j] * u[gj / 3][gj % 3]).sum();
                r[gi] += ku - local.load[i];
            }
        }
        self.add_tractions(|dofs, f| dofs.iter().zip(f).for_each(|(&g, &fi)| r[g] -= fi))?;
        let mut claimed = vec![false; r.len()];
        let reaction = |bc: &SolidDirichlet, claimed: &mut [bool]| {
            let mut total = [0.0; 3];
            for f in mesh.facets_tagged(std::slice::from_ref(&bc.tag)) {
                for &n in mesh.facet(f) {
                    for a in (0..3).filter(|&a| bc.fix[a]) {
                        let dof = 3 * n + a;
                        if !std::mem::replace(&mut claimed[dof], true) {
                            total[a] += r[dof];
                        }
                    }
                }
            }
            (bc.tag, total)
        };
        Ok(self.dirichlet.iter().map(|bc| reaction(bc, &mut claimed)).collect())
    }

    /// The first body (connected set of cells) whose Dirichlet conditions leave a rigid motion
    /// free, with that motion in words: the functionals r ↦ r_a(x_n) of its constrained dofs
    /// must span the six rigid motions of space.
    pub fn free_rigid_motion(&self) -> Option<(usize, String)> {
        let mesh = &self.mesh;
        let bodies = mesh.bodies();
        let mut body_of_node = vec![0; mesh.n_points()];
        for (c, &body) in bodies.iter().enumerate() {
            mesh.cell(c).iter().for_each(|&n| body_of_node[n] = body);
        }
        (0..=bodies.iter().copied().max().unwrap_or(0)).find_map(|b| {
            let points: Vec<Point3> =
                (0..mesh.n_points()).filter(|&n| body_of_node[n] == b).map(|n| mesh.points[n]).collect();
            let count = points.len() as f64;
            let centre: Point3 = std::array::from_fn(|r| points.iter().map(|p| p[r]).sum::<f64>() / count);
            let size = points.iter().map(|&p| distance3(p, centre)).fold(f64::MIN_POSITIVE, f64::max);
            let fixed = self.dirichlet.iter().flat_map(|bc| {
                let nodes =
                    mesh.facets_tagged(std::slice::from_ref(&bc.tag)).flat_map(|f| mesh.facet(f).iter().copied());
                let nodes = nodes.filter(|&n| body_of_node[n] == b);
                nodes.flat_map(move |n| {
                    (0..3)
                        .filter(|&a| bc.fix[a])
                        .map(move |a| (mesh.points[n], std::array::from_fn(|k| f64::from(u8::from(k == a)))))
                })
            });
            let v = *free_motions_3d(fixed, centre, size).first()?;
            let names = ["a translation along x", "a translation along y", "a translation along z"];
            let turns = ["a rotation about x", "a rotation about y", "a rotation about z"];
            let parts: Vec<&str> =
                names.iter().chain(&turns).zip(v).filter(|(_, c)| c.abs() > 0.1).map(|(n, _)| *n).collect();
            Some((b, parts.join(" combined with ")))
        })
    }

    /// The cell means of σ(u_h) in Voigt order: σ(u_h) is affine on a cell for p ≤ 2, so its
    /// mean is its value at the centroid.
    pub fn cell_stress(&self, u: &[Vector3]) -> Vec<[f64; 6]> {
        let mesh = &self.mesh;
        let mut grads = vec![[0.0; 3]; tetrahedron::n_basis(mesh.order)];
        (0..mesh.n_cells())
            .map(|c| {
                let map = TetMap::new(mesh.cell_vertices(c));
                let nodal: Vec<Vector3> = mesh.cell(c).iter().map(|&n| u[n]).collect();
                let g = kernels::displacement_gradient(&map, mesh.order, [0.25; 3], &nodal, &mut grads);
                let (lambda, mu) = self.materials[c].lame();
                kernels::stress(g, lambda, mu)
            })
            .collect()
    }
}
