//! Sparse matrix pattern built once per mesh, and parallel assembly into it.
//!
//! The pattern couples every pair of free dofs whose nodes share a cell; it is stored in
//! compressed sparse column form with sorted row indices, so that a value is found by binary
//! search in its column (or, for the nodes of a cell, by one pass along it). The same pattern
//! (and hence the same symbolic factorisation) serves every matrix assembled on the mesh.
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
    /// Pattern coupling the free dofs of the nodes of each cell of `mesh`. The columns of
    /// a node hold the same rows: the free dofs of its neighbours, in order.
    pub fn new<const D: usize>(mesh: &Mesh<D>, dofs: &DofMap) -> Self {
        Self::with_couplings(mesh, dofs, &[])
    }

    /// Pattern coupling the free dofs of the nodes of each cell of `mesh` and of each node
    /// set of `couplings` (the two cells that a two-body contact term joins).
    pub fn with_couplings<const D: usize>(mesh: &Mesh<D>, dofs: &DofMap, couplings: &[Vec<usize>]) -> Self {
        let groups = Groups::new(mesh, couplings);
        let (free, nc) = (&dofs.free, dofs.components);
        let node_dofs = |m: usize| &free[nc * m..nc * (m + 1)];
        let n_free_of = |m: usize| node_dofs(m).iter().filter(|&&k| k != FIXED).count();
        // rows of each column of node n: the free dofs of its neighbours
        let rows_per_column: Vec<usize> = (0..mesh.n_points())
            .into_par_iter()
            .map_init(Vec::new, |list, n| {
                groups.neighbours(n, list);
                list.iter().map(|&m| n_free_of(m)).sum()
            })
            .collect();
        let mut col_ptr = Vec::with_capacity(dofs.n_free + 1);
        col_ptr.push(0);
        for (dof, &k) in free.iter().enumerate() {
            if k != FIXED {
                col_ptr.push(col_ptr[k] + rows_per_column[dof / nc]);
            }
        }
        // the columns of node n, and so their rows, are contiguous: [start[n], start[n + 1])
        let mut start = Vec::with_capacity(mesh.n_points() + 1);
        let mut columns_before = 0;
        for n in 0..=mesh.n_points() {
            start.push(col_ptr[columns_before]);
            columns_before += if n < mesh.n_points() { n_free_of(n) } else { 0 };
        }
        let mut row_idx = vec![0; *col_ptr.last().unwrap()];
        let blocks = node_blocks(mesh.n_points(), rayon::current_num_threads());
        split_at_ends(&mut row_idx, blocks.iter().map(|&(_, n1)| start[n1])).into_par_iter().zip(&blocks).for_each(
            |(rows, &(n0, n1))| {
                let (mut list, mut rest) = (Vec::new(), rows);
                for n in n0..n1 {
                    groups.neighbours(n, &mut list);
                    let node_rows;
                    (node_rows, rest) = rest.split_at_mut(start[n + 1] - start[n]);
                    let column = list.iter().flat_map(|&m| node_dofs(m)).copied().filter(|&r| r != FIXED);
                    for (r, row) in node_rows.iter_mut().zip(column.cycle()) {
                        *r = row;
                    }
                }
            },
        );
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

/// The node sets that couple their nodes: the cells of a mesh, then the extra `couplings`;
/// with the sets of each node in CSR form.
struct Groups<'a, const D: usize> {
    mesh: &'a Mesh<D>,
    couplings: &'a [Vec<usize>],
    offsets: Vec<usize>,
    of_node: Vec<usize>,
}

impl<'a, const D: usize> Groups<'a, D> {
    fn new(mesh: &'a Mesh<D>, couplings: &'a [Vec<usize>]) -> Self {
        let nodes = |g: usize| group_nodes(mesh, couplings, g);
        let n_groups = mesh.n_cells() + couplings.len();
        let mut offsets = vec![0; mesh.n_points() + 1];
        for g in 0..n_groups {
            nodes(g).iter().for_each(|&n| offsets[n + 1] += 1);
        }
        for n in 0..mesh.n_points() {
            offsets[n + 1] += offsets[n];
        }
        let mut fill = offsets.clone();
        let mut of_node = vec![0; offsets[mesh.n_points()]];
        for g in 0..n_groups {
            for &n in nodes(g) {
                of_node[fill[n]] = g;
                fill[n] += 1;
            }
        }
        Groups { mesh, couplings, offsets, of_node }
    }

    /// The sorted nodes that share a set with node n (n included), into `list`.
    fn neighbours(&self, n: usize, list: &mut Vec<usize>) {
        list.clear();
        for &g in &self.of_node[self.offsets[n]..self.offsets[n + 1]] {
            list.extend(group_nodes(self.mesh, self.couplings, g));
        }
        list.sort_unstable();
        list.dedup();
    }
}

/// Nodes of set g: cell g of `mesh`, then the `couplings`.
fn group_nodes<'a, const D: usize>(mesh: &'a Mesh<D>, couplings: &'a [Vec<usize>], g: usize) -> &'a [usize] {
    match g.checked_sub(mesh.n_cells()) {
        None => mesh.cell(g),
        Some(k) => &couplings[k],
    }
}

/// Cuts the nodes 0..n into about 8 `threads` contiguous blocks.
fn node_blocks(n: usize, threads: usize) -> Vec<(usize, usize)> {
    column_ranges(n, 8 * threads)
}

/// Cuts `data` into consecutive slices ending at the increasing offsets `ends`.
fn split_at_ends<T>(data: &mut [T], ends: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let (mut slices, mut rest, mut done) = (Vec::new(), data, 0);
    for end in ends {
        let slice;
        (slice, rest) = rest.split_at_mut(end - done);
        slices.push(slice);
        done = end;
    }
    slices
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
    /// cell c node by node, all components of a node together, as [`vector_dofs`]; `kernel(c, local)` fills
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
/// dofs come node by node (x, y\[, z\]), and the free dofs of a node are adjacent: the rows of
/// node i in a column of node j start at the same offset k_i in every column of node j. The
/// offsets of all nodes i come from one pass along the sorted rows of node j's column.
fn scatter(
    pattern: &SparsePattern,
    map: &DofMap,
    local: &Local,
    range: (usize, usize),
    offset: usize,
    values: &mut [f64],
    rhs: &mut [f64],
) {
    let (n, nc) = (local.dofs.len(), map.components);
    debug_assert!(n.is_multiple_of(nc) && n <= nc * MAX_NODES, "local dofs come node by node");
    let (col_ptr, row_idx) = (pattern.symbolic.col_ptr(), pattern.symbolic.row_idx());
    let owned = |k: usize| k != FIXED && (range.0..range.1).contains(&k);
    let first_free = |node: &[usize]| node.iter().map(|&g| map.free[g]).find(|&k| k != FIXED);
    // the nodes with a free row, by increasing first free row
    let mut first_row = [(0, 0); MAX_NODES];
    let mut n_rows = 0;
    for (i, node) in local.dofs.chunks_exact(nc).enumerate() {
        if let Some(r) = first_free(node) {
            first_row[n_rows] = (r, i);
            n_rows += 1;
        }
    }
    let first_row = &mut first_row[..n_rows];
    first_row.sort_unstable();
    let mut k = [0; MAX_NODES];
    for (j, column_node) in local.dofs.chunks_exact(nc).enumerate() {
        if !column_node.iter().any(|&g| owned(map.free[g])) {
            continue;
        }
        let first_column = first_free(column_node).expect("an owned column is free");
        let mut p = col_ptr[first_column];
        for &(r, i) in first_row.iter() {
            while row_idx[p] < r {
                p += 1;
            }
            assert!(row_idx[p] == r, "entry outside the sparsity pattern");
            k[i] = p - col_ptr[first_column];
        }
        for (b, col) in column_node.iter().map(|&g| map.free[g]).enumerate().filter(|&(_, col)| owned(col)) {
            let c = nc * j + b;
            rhs[col - range.0] += local.load[c];
            for (i, row_node) in local.dofs.chunks_exact(nc).enumerate() {
                let mut next = col_ptr[col] + k[i] - offset;
                for (a, &g) in row_node.iter().enumerate() {
                    match map.free[g] {
                        // symmetric pattern: row `col` collects −K_{col,i} g_i
                        FIXED => rhs[col - range.0] -= local.matrix[c * n + nc * i + a] * map.fixed_value[g],
                        _ => {
                            values[next] += local.matrix[(nc * i + a) * n + c];
                            next += 1;
                        }
                    }
                }
            }
        }
    }
}

/// The most nodes of a cell (the P2 tetrahedron).
const MAX_NODES: usize = 10;

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

/// Global dofs of a list of nodes of the plane: [2n₀, 2n₀+1, 2n₁, 2n₁+1, …].
pub fn vector_dofs(nodes: &[usize], out: &mut Vec<usize>) {
    components_dofs::<2>(nodes, out);
}

/// Global dofs of a list of nodes of D components: [D n₀, D n₀ + 1, …, D n₁, …].
pub fn components_dofs<const D: usize>(nodes: &[usize], out: &mut Vec<usize>) {
    out.clear();
    out.extend(nodes.iter().flat_map(|&n| std::array::from_fn::<usize, D, _>(|a| D * n + a)));
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::unit_square;

    #[test]
    fn pattern_is_symmetric_and_complete() {
        let mesh = unit_square(2, 2);
        let map = DofMap::new(mesh.n_points(), 2, &[(0, 0.0), (1, 0.5)]);
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

    /// Source: [`SparsePattern::with_couplings`]. Goal: a coupling set joins the free dofs of
    /// its nodes, which share no cell, and adds nothing else. Parameters: the 3 × 3 unit
    /// square (P1), the opposite corners 0 and 15 coupled, node 5 constrained in x.
    #[test]
    fn couplings_join_their_nodes_only() {
        let mesh = unit_square(3, 1);
        let map = DofMap::new(mesh.n_points(), 2, &[(10, 0.0)]);
        let plain = SparsePattern::new(&mesh, &map);
        let coupled = SparsePattern::with_couplings(&mesh, &map, &[vec![0, 15]]);
        let (corner, opposite) = ([map.free[0], map.free[1]], [map.free[30], map.free[31]]);
        for (r, s) in corner.into_iter().flat_map(|r| opposite.map(|s| (r, s))) {
            assert!(plain.symbolic().row_idx_of_col(s).all(|row| row != r), "corners share no cell");
            coupled.position(r, s);
            coupled.position(s, r);
        }
        assert_eq!(coupled.nnz(), plain.nnz() + 8);
    }

    #[test]
    fn parallel_assembly_matches_serial_sum() {
        // K_ij = (i+1)(j+2) on each cell (non-symmetric), f_i = i + 1, one constrained dof
        let mesh = unit_square(5, 2);
        let map = DofMap::new(mesh.n_points(), 2, &[(3, 0.7)]);
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
