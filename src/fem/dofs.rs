//! Degrees of freedom of vector-valued Lagrange fields.
//!
//! Node n carries the d displacement components as dofs d n + a (a = 0 for x, 1 for y, 2 for
//! z; d = 2 in the plane, 3 in a solid). Dofs with a
//! Dirichlet value are eliminated: the remaining *free* dofs are numbered 0..n_free in
//! increasing dof order, which keeps the matrix bandwidth of the node numbering.

/// Marker for a constrained dof in [`DofMap::free`].
pub const FIXED: usize = usize::MAX;

/// Numbering of free dofs and the values of the constrained ones.
#[derive(Debug, Clone)]
pub struct DofMap {
    /// Free index of each dof, or [`FIXED`].
    pub free: Vec<usize>,
    /// Prescribed value of each constrained dof (0 on free dofs).
    pub fixed_value: Vec<f64>,
    /// Number of free dofs.
    pub n_free: usize,
    /// Components per node d.
    pub components: usize,
}

impl DofMap {
    /// Dof map of `n_nodes` nodes of `components` components each, with `constraints` =
    /// (dof, value) pairs. A dof constrained twice keeps the last value.
    pub fn new(n_nodes: usize, components: usize, constraints: &[(usize, f64)]) -> Self {
        let n_dofs = components * n_nodes;
        let mut fixed = vec![false; n_dofs];
        let mut fixed_value = vec![0.0; n_dofs];
        for &(dof, value) in constraints {
            fixed[dof] = true;
            fixed_value[dof] = value;
        }
        let mut n_free = 0;
        let free = fixed
            .iter()
            .map(|&f| {
                if f {
                    FIXED
                } else {
                    n_free += 1;
                    n_free - 1
                }
            })
            .collect();
        DofMap { free, fixed_value, n_free, components }
    }

    pub fn n_dofs(&self) -> usize {
        self.free.len()
    }

    /// Full dof vector from the free unknowns: u = x on free dofs, g on constrained ones.
    pub fn expand(&self, x: &[f64]) -> Vec<f64> {
        self.free.iter().zip(&self.fixed_value).map(|(&k, &g)| if k == FIXED { g } else { x[k] }).collect()
    }
}
