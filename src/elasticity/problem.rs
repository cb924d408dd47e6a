//! The plane-strain boundary value problem and its Galerkin solution.
//!
//! Find u_h ∈ V_h, u_h = g_D on Γ_D (nodal interpolation), such that for all v_h ∈ V_h,0
//!
//!   (σ(u_h), ε(v_h)) = (f, v_h) + (g_N, v_h)_{Γ_N}.
//!
//! Boundary conditions refer to physical curve tags of the mesh. A Dirichlet condition may
//! fix one component only (a roller).

use super::kernels;
use super::material::Material;
use crate::fem::affine::AffineMap;
use crate::fem::dofs::DofMap;
use crate::fem::quadrature::gauss_segment;
use crate::fem::sparse::{vector_dofs, LinearSystem, Local, SparsePattern};
use crate::fem::tabulate::Tabulation;
use crate::mesh::{Mesh, Topology};
use std::sync::Arc;

/// A vector field x ↦ v(x).
pub type VectorFn = Arc<dyn Fn([f64; 2]) -> [f64; 2] + Send + Sync>;

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
    /// A constant vector [Pa].
    Constant([f64; 2]),
    /// Water pressure p = ρ_w g (H_w − y)₊ acting along −n (g points along −y).
    Hydrostatic {
        density: f64,
        gravity: f64,
        level: f64,
    },
    /// Any field of x.
    Field(VectorFn),
}

impl Traction {
    /// g_N at point x of a facet with outward normal n.
    pub fn at(&self, x: [f64; 2], n: [f64; 2]) -> [f64; 2] {
        match self {
            Traction::Constant(t) => *t,
            Traction::Hydrostatic {
                density,
                gravity,
                level,
            } => {
                let p = density * gravity * (level - x[1]).max(0.0);
                [-p * n[0], -p * n[1]]
            }
            Traction::Field(f) => f(x),
        }
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
    /// Self-weight f = (0, −ρ g) with the density of each material.
    Gravity(f64),
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

/// Dof numbering and matrix pattern of a problem, built once per mesh.
pub struct Discretisation {
    pub topology: Topology,
    pub dofs: DofMap,
    pub pattern: SparsePattern,
}

impl Problem {
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
                    constraints.extend((0..2).filter(|&a| bc.fix[a]).map(|a| (2 * n + a, g[a])));
                }
            }
        }
        let dofs = DofMap::new(self.mesh.n_points(), &constraints);
        let pattern = SparsePattern::new(&self.mesh, &dofs);
        Discretisation {
            topology,
            dofs,
            pattern,
        }
    }

    /// Assembles K and F over the free dofs, with Dirichlet values moved to the right.
    pub fn assemble(&self, disc: &Discretisation) -> LinearSystem {
        let mut system = LinearSystem::zeros(&disc.pattern);
        self.add_stiffness_and_body_force(disc, &mut system);
        self.add_tractions(disc, &mut system);
        system
    }

    fn add_stiffness_and_body_force(&self, disc: &Discretisation, system: &mut LinearSystem) {
        let p = self.mesh.order;
        let stiff_tab = Tabulation::new(p, 2 * p - 2);
        let load_tab = Tabulation::new(p, 2 * p + 2);
        let nb = stiff_tab.n_basis;
        let kernel = |c: usize, local: &mut Local| {
            let map = AffineMap::new(self.mesh.cell_vertices(c));
            let (lambda, mu) = self.materials[c].lame();
            let mut grads = [[0.0; 2]; 6];
            kernels::stiffness(
                &map,
                &stiff_tab,
                lambda,
                mu,
                &mut grads[..nb],
                &mut local.matrix,
            );
            match &self.body_force {
                BodyForce::None => local.load.fill(0.0),
                BodyForce::Gravity(g) => {
                    let w = -self.materials[c].density * g;
                    kernels::body_load(&map, &load_tab, |_| [0.0, w], &mut local.load)
                }
                BodyForce::Field(field) => {
                    kernels::body_load(&map, &load_tab, |x| field(x), &mut local.load)
                }
            }
        };
        let dofs_of = |c: usize, out: &mut Vec<usize>| vector_dofs(self.mesh.cell(c), out);
        system.assemble(
            &disc.pattern,
            &disc.dofs,
            self.mesh.n_cells(),
            2 * nb,
            dofs_of,
            kernel,
        );
    }

    fn add_tractions(&self, disc: &Discretisation, system: &mut LinearSystem) {
        let p = self.mesh.order;
        let rule = gauss_segment(p + 2);
        let mut phi = vec![0.0; p + 1];
        let mut f = vec![0.0; 2 * (p + 1)];
        let mut local = Vec::new();
        for bc in &self.neumann {
            for facet in (0..self.mesh.n_facets()).filter(|&k| self.mesh.facet_tags[k] == bc.tag) {
                let nodes = self.mesh.facet(facet);
                let n = disc.topology.outward_normal(&self.mesh, facet);
                let ends = [self.mesh.points[nodes[0]], self.mesh.points[nodes[1]]];
                kernels::traction_load(ends, p, &rule, |x| bc.traction.at(x, n), &mut phi, &mut f);
                vector_dofs(nodes, &mut local);
                system.add_load(&disc.dofs, &local, &f);
            }
        }
    }

    /// Nodal displacements from the free unknowns.
    pub fn displacement(&self, disc: &Discretisation, x: &[f64]) -> Vec<[f64; 2]> {
        disc.dofs
            .expand(x)
            .chunks_exact(2)
            .map(|u| [u[0], u[1]])
            .collect()
    }
}
