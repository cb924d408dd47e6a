//! Sparse matrix pattern built once per mesh, and parallel assembly into it.
//!
//! The pattern couples every pair of free dofs whose nodes share a cell; it is stored in
//! compressed sparse column form with sorted row indices, so that a value is found by binary
//! search in its column. The same pattern (and hence the same symbolic factorisation) serves
//! every matrix assembled on the mesh.
//!
//! Assembly is parallel without locks: the free dofs are cut into contiguous ranges, and each
//! task owns the matrix columns and right-hand-side rows of its range. A task visits the cells
//! that touch its range, in increasing order, and keeps the entries that fall into it; a cell
//! straddling two ranges is computed by both. Every entry thus sums the same terms in the same
//! order on any number of threads.

use super::dofs::{DofMap, FIXED};
use crate::mesh::Mesh;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use rayon::prelude::*;

/// Symmetric sparsity pattern of the free dofs.
#[derive(Debug, Clone)]
pub struct SparsePattern {
    symbolic: SymbolicSparseColMat<usize>,
}

impl SparsePattern {
    /// Pattern coupling the free dofs of the nodes of each cell of `mesh`. The two columns of
    /// a node hold the same rows: the free dofs of its neighbours, in order.
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> Self {
        Self::from_neighbours(node_neighbours(mesh), dofs)
    }

    /// Pattern coupling the free dofs of the nodes of each cell of `mesh` and of each node
    /// set of `couplings` (the two cells that a two-body contact term joins).
    pub fn with_couplings(mesh: &Mesh, dofs: &DofMap, couplings: &[Vec<usize>]) -> Self {
        let mut neighbours = node_neighbours(mesh);
        for group in couplings {
            for &n in group {
                neighbours[n].extend(group);
            }
        }
        for list in &mut neighbours {
            list.sort_unstable();
            list.dedup();
        }
        Self::from_neighbours(neighbours, dofs)
    }

    /// Pattern coupling the free dofs of each node with those of its sorted `neighbours`.
    fn from_neighbours(neighbours: Vec<Vec<usize>>, dofs: &DofMap) -> Self {
        let free = &dofs.free;
        let free_of = |m: usize| [free[2 * m], free[2 * m + 1]].into_iter().filter(|&r| r != FIXED);
        let length: Vec<usize> =
            neighbours.par_iter().map(|list| list.iter().flat_map(|&m| free_of(m)).count()).collect();
        let columns: Vec<usize> = (0..dofs.n_dofs()).filter(|&dof| free[dof] != FIXED).collect();
        let mut col_ptr = Vec::with_capacity(columns.len() + 1);
        col_ptr.push(0);
        for &dof in &columns {
            col_ptr.push(col_ptr.last().unwrap() + length[dof / 2]);
        }
        let mut row_idx = vec![0; *col_ptr.last().unwrap()];
        let mut slices = Vec::with_capacity(columns.len());
        let mut rest = row_idx.as_mut_slice();
        for (&dof, window) in columns.iter().zip(col_ptr.windows(2)) {
            let (column, tail) = rest.split_at_mut(window[1] - window[0]);
            slices.push((dof, column));
            rest = tail;
        }
        slices.into_par_iter().for_each(|(dof, column)| {
            for (r, m) in column.iter_mut().zip(neighbours[dof / 2].iter().flat_map(|&m| free_of(m))) {
                *r = m;
            }
        });
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

    /// y = A x for the matrix with this pattern and the given values.
    pub fn multiply(&self, values: &[f64], x: &[f64], y: &mut [f64]) {
        y.fill(0.0);
        let (col_ptr, row_idx) = (self.symbolic.col_ptr(), self.symbolic.row_idx());
        for (col, &xc) in x.iter().enumerate() {
            for k in col_ptr[col]..col_ptr[col + 1] {
                y[row_idx[k]] += values[k] * xc;
            }
        }
    }

    /// The matrix with this pattern and the given values.
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic(), values)
    }
}

/// Sorted list of the nodes sharing a cell with each node (itself included).
fn node_neighbours(mesh: &Mesh) -> Vec<Vec<usize>> {
    let npc = mesh.nodes_per_cell();
    let mut offsets = vec![0usize; mesh.n_points() + 1];
    for &n in &mesh.cell_nodes {
        offsets[n + 1] += 1;
    }
    for k in 0..mesh.n_points() {
        offsets[k + 1] += offsets[k];
    }
    let mut fill = offsets.clone();
    let mut node_cells = vec![0; mesh.cell_nodes.len()];
    for (k, &n) in mesh.cell_nodes.iter().enumerate() {
        node_cells[fill[n]] = k / npc;
        fill[n] += 1;
    }
    (0..mesh.n_points())
        .into_par_iter()
        .map(|n| {
            let mut list: Vec<usize> =
                node_cells[offsets[n]..offsets[n + 1]].iter().flat_map(|&c| mesh.cell(c).iter().copied()).collect();
            list.sort_unstable();
            list.dedup();
            list
        })
        .collect()
}

/// Local contribution of one cell: global dofs, matrix (row-major, n × n) and load (n).
pub struct Local {
    pub dofs: Vec<usize>,
    pub matrix: Vec<f64>,
    pub load: Vec<f64>,
}

impl Local {
    /// Buffers for `n` local dofs.
    pub fn new(n: usize) -> Self {
        Local { dofs: Vec::with_capacity(n), matrix: vec![0.0; n * n], load: vec![0.0; n] }
    }
}

/// A linear system K x = b over the free dofs.
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

    /// Adds Σ_cells of the local contributions. `dofs_of(c, out)` writes the global dofs of
    /// cell c in node pairs (x, y), as [`vector_dofs`]; `kernel(c, local)` fills
    /// `local.matrix` and `local.load` for those dofs.
    /// Constrained columns move to the right-hand side: b_i −= K_ij g_j.
    pub fn assemble<D, K>(
        &mut self,
        pattern: &SparsePattern,
        map: &DofMap,
        n_cells: usize,
        n_local: usize,
        dofs_of: D,
        kernel: K,
    ) where
        D: Fn(usize, &mut Vec<usize>) + Sync,
        K: Fn(usize, &mut Local) + Sync,
    {
        let ranges = column_ranges(pattern.n(), 4 * rayon::current_num_threads());
        let cells = cells_of_ranges(map, &ranges, n_cells, &dofs_of);
        let col_ptr = pattern.symbolic.col_ptr();
        let mut values_rest = self.values.as_mut_slice();
        let mut rhs_rest = self.rhs.as_mut_slice();
        let mut tasks = Vec::with_capacity(ranges.len());
        for (&(c0, c1), cells) in ranges.iter().zip(&cells) {
            let (v, vr) = values_rest.split_at_mut(col_ptr[c1] - col_ptr[c0]);
            let (b, br) = rhs_rest.split_at_mut(c1 - c0);
            tasks.push(((c0, c1), cells, v, b));
            (values_rest, rhs_rest) = (vr, br);
        }
        tasks.into_par_iter().for_each(|((c0, c1), cells, values, rhs)| {
            let offset = col_ptr[c0];
            let mut local = Local::new(n_local);
            for &c in cells {
                dofs_of(c, &mut local.dofs);
                kernel(c, &mut local);
                scatter(pattern, map, &local, (c0, c1), offset, values, rhs);
            }
        });
    }

    /// Adds a local load `f` on the global dofs `local` (serial; for boundary terms).
    pub fn add_load(&mut self, map: &DofMap, local: &[usize], f: &[f64]) {
        for (&g, &fi) in local.iter().zip(f) {
            if map.free[g] != FIXED {
                self.rhs[map.free[g]] += fi;
            }
        }
    }
}

/// Adds the entries of `local` whose column (matrix) or row (load) lies in `range`. Local
/// dofs come in node pairs (x, y): when both rows of node i are free, rows r and r + 1 are
/// adjacent in every column, so one search finds the pair.
fn scatter(
    pattern: &SparsePattern,
    map: &DofMap,
    local: &Local,
    range: (usize, usize),
    offset: usize,
    values: &mut [f64],
    rhs: &mut [f64],
) {
    let n = local.dofs.len();
    for (j, &gj) in local.dofs.iter().enumerate() {
        let col = map.free[gj];
        if col == FIXED || !(range.0..range.1).contains(&col) {
            continue;
        }
        rhs[col - range.0] += local.load[j];
        debug_assert!(n.is_multiple_of(2), "local dofs come in node pairs");
        for (i, pair) in local.dofs.chunks_exact(2).enumerate() {
            let (ix, iy) = (2 * i, 2 * i + 1);
            match [map.free[pair[0]], map.free[pair[1]]] {
                [rx, ry] if rx != FIXED && ry == rx + 1 => {
                    let p = pattern.position(rx, col) - offset;
                    values[p] += local.matrix[ix * n + j];
                    values[p + 1] += local.matrix[iy * n + j];
                }
                rows => {
                    for (row, (&g, i)) in rows.into_iter().zip(pair.iter().zip([ix, iy])) {
                        match row {
                            // symmetric pattern: row `col` collects −K_{col,i} g_i
                            FIXED => rhs[col - range.0] -= local.matrix[j * n + i] * map.fixed_value[g],
                            row => values[pattern.position(row, col) - offset] += local.matrix[i * n + j],
                        }
                    }
                }
            }
        }
    }
}

/// The cells that touch each of the contiguous `ranges` of free dofs, in increasing order.
fn cells_of_ranges(
    map: &DofMap,
    ranges: &[(usize, usize)],
    n_cells: usize,
    dofs_of: impl Fn(usize, &mut Vec<usize>),
) -> Vec<Vec<usize>> {
    let mut cells = vec![Vec::new(); ranges.len()];
    let range_of = |dof: usize| ranges.partition_point(|&(_, end)| end <= dof);
    let (mut dofs, mut touched) = (Vec::new(), Vec::new());
    for c in 0..n_cells {
        dofs_of(c, &mut dofs);
        touched.clear();
        touched.extend(dofs.iter().map(|&g| map.free[g]).filter(|&k| k != FIXED).map(range_of));
        touched.sort_unstable();
        touched.dedup();
        for &r in &touched {
            cells[r].push(c);
        }
    }
    cells
}

/// Cuts 0..n into at most `parts` contiguous ranges.
fn column_ranges(n: usize, parts: usize) -> Vec<(usize, usize)> {
    let size = n.div_ceil(parts.max(1)).max(1);
    (0..n).step_by(size).map(|a| (a, (a + size).min(n))).collect()
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

    #[test]
    fn parallel_assembly_matches_serial_sum() {
        // K_ij = (i+1)(j+2) on each cell (non-symmetric), f_i = i + 1, one constrained dof
        let mesh = unit_square(5, 2);
        let map = DofMap::new(mesh.n_points(), &[(3, 0.7)]);
        let pattern = SparsePattern::new(&mesh, &map);
        let mut system = LinearSystem::zeros(&pattern);
        let n = 12;
        let kernel = |_: usize, l: &mut Local| {
            for i in 0..n {
                l.load[i] = (i + 1) as f64;
                for j in 0..n {
                    l.matrix[i * n + j] = ((i + 1) * (j + 2)) as f64;
                }
            }
        };
        system.assemble(&pattern, &map, mesh.n_cells(), n, |c, d| vector_dofs(mesh.cell(c), d), kernel);
        let mut expected = vec![0.0; pattern.nnz()];
        let mut rhs = vec![0.0; pattern.n()];
        let mut dofs = Vec::new();
        for c in 0..mesh.n_cells() {
            vector_dofs(mesh.cell(c), &mut dofs);
            for (i, &gi) in dofs.iter().enumerate() {
                let Some(row) = Some(map.free[gi]).filter(|&r| r != FIXED) else {
                    continue;
                };
                rhs[row] += (i + 1) as f64;
                for (j, &gj) in dofs.iter().enumerate() {
                    let kij = ((i + 1) * (j + 2)) as f64;
                    match map.free[gj] {
                        FIXED => rhs[row] -= kij * 0.7,
                        col => expected[pattern.position(row, col)] += kij,
                    }
                }
            }
        }
        assert_eq!(system.values, expected);
        let worst = rhs.iter().zip(&system.rhs).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-9, "rhs differs by {worst}");
    }
}
