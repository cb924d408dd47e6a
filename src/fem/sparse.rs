//! Sparse matrix pattern built once per mesh, and assembly into it.
//!
//! The pattern couples every pair of free dofs whose nodes share a cell; it is stored in
//! compressed sparse column form with sorted row indices, so that a value is found by binary
//! search in its column. The same pattern (and hence the same symbolic factorisation) serves
//! every matrix assembled on the mesh.

use super::dofs::{DofMap, FIXED};
use crate::mesh::Mesh;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};

/// Symmetric sparsity pattern of the free dofs.
#[derive(Debug, Clone)]
pub struct SparsePattern {
    symbolic: SymbolicSparseColMat<usize>,
}

impl SparsePattern {
    /// Pattern coupling the free dofs of the nodes of each cell of `mesh`.
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> Self {
        let neighbours = node_neighbours(mesh);
        let mut col_ptr = Vec::with_capacity(dofs.n_free + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for (dof, &col) in dofs.free.iter().enumerate() {
            if col == FIXED {
                continue;
            }
            for &m in &neighbours[dof / 2] {
                row_idx.extend((0..2).map(|c| dofs.free[2 * m + c]).filter(|&r| r != FIXED));
            }
            col_ptr.push(row_idx.len());
        }
        let n = dofs.n_free;
        SparsePattern { symbolic: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx) }
    }

    /// Matrix dimension.
    pub fn n(&self) -> usize {
        self.symbolic.nrows()
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.symbolic.compute_nnz()
    }

    /// Position of entry (row, col) in the value array. Panics if it is not in the pattern.
    pub fn position(&self, row: usize, col: usize) -> usize {
        let start = self.symbolic.col_ptr()[col];
        let rows = &self.symbolic.row_idx()[start..self.symbolic.col_ptr()[col + 1]];
        start + rows.binary_search(&row).expect("entry outside the sparsity pattern")
    }

    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// The matrix with this pattern and the given values.
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic(), values)
    }
}

/// Sorted list of the nodes sharing a cell with each node (itself included).
fn node_neighbours(mesh: &Mesh) -> Vec<Vec<usize>> {
    let mut neighbours = vec![Vec::new(); mesh.n_points()];
    for c in 0..mesh.n_cells() {
        let cell = mesh.cell(c);
        for &a in cell {
            neighbours[a].extend_from_slice(cell);
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    neighbours
}

/// A linear system K x = b over the free dofs, filled element by element.
#[derive(Debug, Clone)]
pub struct LinearSystem {
    pub values: Vec<f64>,
    pub rhs: Vec<f64>,
}

impl LinearSystem {
    /// Zero matrix and right-hand side on `pattern`.
    pub fn zeros(pattern: &SparsePattern) -> Self {
        LinearSystem { values: vec![0.0; pattern.nnz()], rhs: vec![0.0; pattern.n()] }
    }

    /// Adds a local matrix `k` (row-major, `dofs.len()`²) and load `f` acting on the global
    /// dofs `local`. Constrained columns move to the right-hand side: b_i −= K_ij g_j.
    pub fn add(&mut self, pattern: &SparsePattern, map: &DofMap, local: &[usize], k: &[f64], f: &[f64]) {
        let n = local.len();
        for (i, &gi) in local.iter().enumerate() {
            let row = map.free[gi];
            if row == FIXED {
                continue;
            }
            self.rhs[row] += f[i];
            for (j, &gj) in local.iter().enumerate() {
                let kij = k[i * n + j];
                match map.free[gj] {
                    FIXED => self.rhs[row] -= kij * map.fixed_value[gj],
                    col => self.values[pattern.position(row, col)] += kij,
                }
            }
        }
    }

    /// Adds a local load `f` on the global dofs `local`.
    pub fn add_load(&mut self, map: &DofMap, local: &[usize], f: &[f64]) {
        for (&g, &fi) in local.iter().zip(f) {
            if map.free[g] != FIXED {
                self.rhs[map.free[g]] += fi;
            }
        }
    }
}

/// Global dofs of a list of nodes: [2n₀, 2n₀+1, 2n₁, 2n₁+1, …].
pub fn vector_dofs(nodes: &[usize], out: &mut Vec<usize>) {
    out.clear();
    out.extend(nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::unit_square;

    #[test]
    fn pattern_is_symmetric_and_complete() {
        let mesh = unit_square(2, 2);
        let map = DofMap::new(mesh.n_points(), &[(0, 0.0), (1, 0.5)]);
        let pattern = SparsePattern::new(&mesh, &map);
        assert_eq!(pattern.n(), 2 * mesh.n_points() - 2);
        let mut dofs = Vec::new();
        for c in 0..mesh.n_cells() {
            vector_dofs(mesh.cell(c), &mut dofs);
            for &i in &dofs {
                for &j in &dofs {
                    let (r, s) = (map.free[i], map.free[j]);
                    if r != FIXED && s != FIXED {
                        pattern.position(r, s);
                        pattern.position(s, r);
                    }
                }
            }
        }
    }
}
