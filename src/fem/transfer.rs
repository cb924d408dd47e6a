//! Transfer of a finite element field to the points of another, non-nested mesh.
//!
//! A point `p` is located in a cell `T` of the mesh, `p = F_T(ξ)`, and the field is evaluated
//! there: `u(p) = Σᵢ u_{nᵢ} φ̂ᵢ(ξ)` over the nodes `nᵢ` of `T`.
//!
//! Location uses a uniform grid of buckets of about `h × h`, `h = √(|B| / n_cells)`, over the
//! bounding box `B` of the mesh. Each cell is listed in every bucket its bounding box meets, so
//! the bucket of `p` lists every cell holding `p`; `p` is in `T` if its barycentric coordinates
//! satisfy `λᵢ ≥ −10⁻¹²`. On a strongly graded mesh a bucket may list many small cells: a bucket
//! listing more than 32 is split by a finer grid of the same kind over its box, recursively, when
//! that shortens its lists.
//!
//! A point in no cell (outside the mesh) goes to the cell nearest in Euclidean distance: rings
//! of buckets around the bucket of `p` are searched until the best distance found is at most
//! the distance from `p` to the buckets not yet searched.

use super::lagrange;
use crate::geometry::{bounding_box, dot, sub, CellType, Point, Vector, D};
use crate::mesh::Mesh;
use rayon::prelude::*;

/// A point lies in a cell if its barycentric coordinates there satisfy `λᵢ ≥ −TOL`.
const TOL: f64 = 1e-12;

/// A bucket listing more cells is split by a finer grid.
const CROWDED: usize = 32;

/// Levels of finer grids below the grid over the whole mesh.
const MAX_DEPTH: usize = 6;

/// Uniform grid of `shape[0] × shape[1]` buckets of size `h[0] × h[1]` over the box `[lo, hi]`;
/// bucket `(i, j)` is `[lo₀ + i h₀, lo₀ + (i + 1) h₀] × [lo₁ + j h₁, lo₁ + (j + 1) h₁]`.
#[derive(Debug, Clone, Copy)]
struct Grid {
    lo: Point,
    hi: Point,
    h: [f64; 2],
    shape: [usize; 2],
}

impl Grid {
    /// Grid over the box `[lo, hi]` with about `n` buckets of about `√(|B| / n)` square.
    fn new(lo: Point, hi: Point, n: usize) -> Self {
        let extent = sub(hi, lo);
        let side = (extent[0] * extent[1] / n as f64).sqrt();
        assert!(side > 0.0, "mesh with a degenerate bounding box {lo:?}, {hi:?}");
        let shape = extent.map(|e| ((e / side).ceil() as usize).max(1));
        Self { lo, hi, h: [0, 1].map(|k| extent[k] / shape[k] as f64), shape }
    }

    /// Grid over bucket `b` of `coarse` with about `n` buckets.
    fn over_bucket(coarse: &Grid, b: usize, n: usize) -> Self {
        let [i, j] = [b % coarse.shape[0], b / coarse.shape[0]];
        let lo = [coarse.edge(0, i), coarse.edge(1, j)];
        Self::new(lo, [coarse.edge(0, i + 1), coarse.edge(1, j + 1)], n)
    }

    fn len(&self) -> usize {
        self.shape[0] * self.shape[1]
    }

    /// The bucket `(i, j)` holding `p`, clamped to the grid.
    fn bucket_of(&self, p: Point) -> [usize; 2] {
        [0, 1].map(|k| ((p[k] - self.lo[k]) / self.h[k]).floor().clamp(0.0, (self.shape[k] - 1) as f64) as usize)
    }

    /// Index `i + shape[0] j` of bucket `(i, j)`.
    fn index(&self, [i, j]: [usize; 2]) -> usize {
        i + self.shape[0] * j
    }

    /// Index of bucket `(i, j)`, or `None` outside the grid.
    fn checked_index(&self, i: isize, j: isize) -> Option<usize> {
        let inside = (0..self.shape[0] as isize).contains(&i) && (0..self.shape[1] as isize).contains(&j);
        inside.then(|| self.index([i as usize, j as usize]))
    }

    /// Buckets meeting the box `[lo, hi]`.
    fn buckets_meeting(self, [lo, hi]: [Point; 2]) -> impl Iterator<Item = usize> {
        let ([i0, j0], [i1, j1]) = (self.bucket_of(lo), self.bucket_of(hi));
        (j0..=j1).flat_map(move |j| (i0..=i1).map(move |i| self.index([i, j])))
    }

    /// Buckets at Chebyshev distance `r` from bucket `centre`: rows `j₀ ± r`, then columns `i₀ ± r`.
    fn ring(&self, centre: [usize; 2], r: usize) -> impl Iterator<Item = usize> + '_ {
        let ([i0, j0], r) = (centre.map(|c| c as isize), r as isize);
        let step = (2 * r).max(1) as usize;
        let rows = (j0 - r..=j0 + r).step_by(step).flat_map(move |j| (i0 - r..=i0 + r).map(move |i| (i, j)));
        let columns = (i0 - r..=i0 + r)
            .step_by(step)
            .filter(move |_| r > 0)
            .flat_map(move |i| (j0 - r + 1..j0 + r).map(move |j| (i, j)));
        rows.chain(columns).filter_map(|(i, j)| self.checked_index(i, j))
    }

    /// Squared distance from `p` to the buckets farther than `r` from `centre` (∞ if none):
    /// the minimum over the strips of the grid left, right, below and above the searched square.
    fn unsearched_distance2(&self, p: Point, centre: [usize; 2], r: usize) -> f64 {
        let mut d2 = f64::INFINITY;
        for k in 0..D {
            let (first, last) = (centre[k].saturating_sub(r), (centre[k] + r).min(self.shape[k] - 1));
            let mut strip = |a: usize, b: usize| {
                let mut corners = [self.lo, self.hi];
                corners[0][k] = self.edge(k, a);
                corners[1][k] = self.edge(k, b);
                d2 = d2.min(box_distance2(p, corners));
            };
            if first > 0 {
                strip(0, first);
            }
            if last + 1 < self.shape[k] {
                strip(last + 1, self.shape[k]);
            }
        }
        d2
    }

    /// Coordinate `lo_k + i h_k` of the `i`-th bucket boundary along axis `k` (`hi_k` for the last).
    fn edge(&self, k: usize, i: usize) -> f64 {
        if i == self.shape[k] {
            self.hi[k]
        } else {
            self.lo[k] + i as f64 * self.h[k]
        }
    }
}

/// The cells meeting each bucket of a grid, in compressed rows; a crowded bucket of a graded
/// mesh is split by a finer grid of its own.
#[derive(Debug, Clone)]
struct Buckets {
    grid: Grid,
    /// The cells listed in bucket `b` are `cells[start[b]..start[b + 1]]`.
    start: Vec<usize>,
    cells: Vec<usize>,
    /// Finer buckets of the crowded buckets, sorted by bucket.
    finer: Vec<(usize, Buckets)>,
}

impl Buckets {
    /// Lists `cells` (bounding boxes `boxes[c]`) by bucket of `grid`, then splits the crowded
    /// buckets, up to `depth` levels.
    fn new(grid: Grid, cells: &[usize], boxes: &[[Point; 2]], depth: usize) -> Self {
        Self::lists(grid, cells, boxes).refined(boxes, depth)
    }

    /// These buckets with their crowded buckets split, up to `depth` levels.
    fn refined(mut self, boxes: &[[Point; 2]], depth: usize) -> Self {
        if depth > 0 {
            let finer = (0..self.grid.len())
                .filter(|&b| self.list(b).len() > CROWDED)
                .filter_map(|b| self.split(b, boxes, depth - 1).map(|finer| (b, finer)))
                .collect();
            self.finer = finer;
        }
        self
    }

    /// Compressed rows of the buckets of `grid` meeting the bounding box of each of `cells`.
    fn lists(grid: Grid, cells: &[usize], boxes: &[[Point; 2]]) -> Self {
        let mut start = vec![0; grid.len() + 1];
        for b in cells.iter().flat_map(|&c| grid.buckets_meeting(boxes[c])) {
            start[b + 1] += 1;
        }
        for b in 0..grid.len() {
            start[b + 1] += start[b];
        }
        let mut next = start.clone();
        let mut listed = vec![0; start[grid.len()]];
        for &c in cells {
            for b in grid.buckets_meeting(boxes[c]) {
                listed[next[b]] = c;
                next[b] += 1;
            }
        }
        Self { grid, start, cells: listed, finer: Vec::new() }
    }

    /// A finer grid over bucket `b` with as many buckets as the `L` cells `b` lists, if its longest
    /// list is at most `3L/4` and it lists at most `16 L` entries (not so when many cells cover `b`).
    fn split(&self, b: usize, boxes: &[[Point; 2]], depth: usize) -> Option<Self> {
        let list = self.list(b);
        let finer = Self::lists(Grid::over_bucket(&self.grid, b, list.len()), list, boxes);
        let helps = 4 * finer.longest() <= 3 * list.len() && finer.cells.len() <= 16 * list.len();
        helps.then(|| finer.refined(boxes, depth))
    }

    /// The cells listed in bucket `b`.
    fn list(&self, b: usize) -> &[usize] {
        &self.cells[self.start[b]..self.start[b + 1]]
    }

    fn longest(&self) -> usize {
        (0..self.grid.len()).map(|b| self.list(b).len()).max().unwrap_or(0)
    }

    /// The list of the finest bucket holding `p`: it holds every cell whose bounding box holds `p`.
    fn holding(&self, p: Point) -> &[usize] {
        let b = self.grid.index(self.grid.bucket_of(p));
        match self.finer.binary_search_by_key(&b, |f| f.0) {
            Ok(k) => self.finer[k].1.holding(p),
            Err(_) => self.list(b),
        }
    }
}

/// Finds the cell of a mesh that holds a point: a uniform grid of buckets over the cells' bounding boxes.
/// Crowded buckets are split by finer grids.
#[derive(Debug, Clone)]
pub struct Locator<'a> {
    mesh: &'a Mesh,
    buckets: Buckets,
}

impl<'a> Locator<'a> {
    /// Buckets for the cells of `mesh`, about as many buckets as cells.
    pub fn new(mesh: &'a Mesh) -> Self {
        Self::of_cells(mesh, &(0..mesh.n_cells()).collect::<Vec<_>>())
    }

    /// Buckets for the given `cells` of `mesh` only: points are located among them.
    pub fn of_cells(mesh: &'a Mesh, cells: &[usize]) -> Self {
        assert!(!cells.is_empty(), "cannot locate points in a mesh without cells");
        let boxes: Vec<[Point; 2]> = (0..mesh.n_cells()).map(|c| bounding_box(mesh.cell_vertices(c))).collect();
        let [lo, hi] = bounding_box(cells.iter().flat_map(|&c| boxes[c]));
        Self { mesh, buckets: Buckets::new(Grid::new(lo, hi, cells.len()), cells, &boxes, MAX_DEPTH) }
    }

    /// The cell holding `p` and the reference coordinates ξ of p in it. A point outside the mesh
    /// (a curved boundary meshed by different chords, round-off) gets the nearest cell, with ξ
    /// moved to the point of that cell nearest to `p` (ξ in the reference triangle).
    pub fn locate(&self, p: Point) -> (usize, Point) {
        let holding = self.buckets.holding(p).iter().find_map(|&c| {
            let l = barycentric(self.mesh.cell_vertices(c), p);
            l.iter().all(|&l| l >= -TOL).then_some((c, [l[1], l[2]]))
        });
        holding.unwrap_or_else(|| self.nearest(p))
    }

    /// The cell nearest to `p` and ξ of its point nearest to `p`, searched by rings of buckets of
    /// the coarsest grid around the bucket of `p` until no unsearched bucket can hold a nearer cell.
    fn nearest(&self, p: Point) -> (usize, Point) {
        let (grid, centre) = (&self.buckets.grid, self.buckets.grid.bucket_of(p));
        let mut best = (f64::INFINITY, 0, [1.0 / 3.0; 2]);
        for r in 0.. {
            for b in grid.ring(centre, r) {
                for &c in self.buckets.list(b) {
                    let (d2, xi) = nearest_point(self.mesh.cell_vertices(c), p);
                    if d2 < best.0 {
                        best = (d2, c, xi);
                    }
                }
            }
            if best.0 <= grid.unsearched_distance2(p, centre, r) {
                break;
            }
        }
        (best.1, best.2)
    }
}

/// Values at `points` of the finite element field with nodal values `values` (one per node of
/// `mesh`, its order's Lagrange basis).
pub fn interpolate(mesh: &Mesh, values: &[Vector], points: &[Point]) -> Vec<Vector> {
    assert_eq!(values.len(), mesh.n_points(), "one value per node of the mesh");
    let locator = Locator::new(mesh);
    points
        .par_iter()
        .map(|&p| {
            let (c, xi) = locator.locate(p);
            evaluate(mesh, values, c, xi)
        })
        .collect()
}

/// Values at `points` of the field with nodal values `values`, each point located among the
/// cells of `mesh` with its own physical surface tag `tags[i]` (among all cells if `mesh` has
/// none of that tag). A point on a joint between two bodies lies in cells of both sides, whose
/// displacements differ by the jump: it takes the value of its own side.
pub fn interpolate_by_tag(mesh: &Mesh, values: &[Vector], points: &[Point], tags: &[i32]) -> Vec<Vector> {
    assert_eq!(values.len(), mesh.n_points(), "one value per node of the mesh");
    assert_eq!(points.len(), tags.len(), "one tag per point");
    let mut by_tag: Vec<(i32, Vec<usize>)> = Vec::new();
    for (c, &tag) in mesh.cell_tags.iter().enumerate() {
        match by_tag.iter_mut().find(|(t, _)| *t == tag) {
            Some((_, cells)) => cells.push(c),
            None => by_tag.push((tag, vec![c])),
        }
    }
    let locators: Vec<(i32, Locator)> =
        by_tag.iter().map(|(tag, cells)| (*tag, Locator::of_cells(mesh, cells))).collect();
    let all = Locator::new(mesh);
    points
        .par_iter()
        .zip(tags)
        .map(|(&p, tag)| {
            let locator = locators.iter().find(|(t, _)| t == tag).map_or(&all, |(_, l)| l);
            let (c, xi) = locator.locate(p);
            evaluate(mesh, values, c, xi)
        })
        .collect()
}

/// `u(F_c(ξ)) = Σᵢ u_{nᵢ} φ̂ᵢ(ξ)` over the nodes `nᵢ` of cell `c`.
fn evaluate(mesh: &Mesh, values: &[Vector], c: usize, xi: Point) -> Vector {
    let mut phi = [0.0; 6];
    lagrange::values(mesh.order, xi, &mut phi);
    mesh.cell(c).iter().zip(phi).fold([0.0; 2], |u, (&n, f)| [u[0] + f * values[n][0], u[1] + f * values[n][1]])
}

/// Barycentric coordinates of `p` in the triangle `v`: `(λ₁, λ₂) = J⁻¹ (p − v₀)`, `λ₀ = 1 − λ₁ − λ₂`.
fn barycentric(v: [Point; 3], p: Point) -> [f64; 3] {
    let (a, b, d) = (sub(v[1], v[0]), sub(v[2], v[0]), sub(p, v[0]));
    let det = a[0] * b[1] - a[1] * b[0];
    let (l1, l2) = ((d[0] * b[1] - d[1] * b[0]) / det, (a[0] * d[1] - a[1] * d[0]) / det);
    [1.0 - l1 - l2, l1, l2]
}

/// Squared distance from `p` to the triangle `v`, and ξ of the triangle's point nearest to `p`:
/// `p` itself inside, else the projection `vᵢ + t (vⱼ − vᵢ)`, `t ∈ [0, 1]`, on the nearest edge.
fn nearest_point(v: [Point; 3], p: Point) -> (f64, Point) {
    let l = barycentric(v, p);
    if l.iter().all(|&l| l >= 0.0) {
        return (0.0, [l[1], l[2]]);
    }
    let on_edge = |&[i, j]: &[usize; 2]| {
        let (e, d) = (sub(v[j], v[i]), sub(p, v[i]));
        let t = (dot(d, e) / dot(e, e)).clamp(0.0, 1.0);
        let r = [d[0] - t * e[0], d[1] - t * e[1]];
        let mut l = [0.0; 3];
        l[i] = 1.0 - t;
        l[j] = t;
        (dot(r, r), [l[1], l[2]])
    };
    (CellType::Triangle.edges().iter().map(on_edge)).min_by(|a, b| a.0.total_cmp(&b.0)).expect("three edges")
}

/// Squared distance from `p` to the box `[lo, hi]`.
fn box_distance2(p: Point, [lo, hi]: [Point; 2]) -> f64 {
    (0..D).map(|k| (lo[k] - p[k]).max(p[k] - hi[k]).max(0.0).powi(2)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured::{rectangle, unit_square};

    /// Source: docs/method.md §5.3 (the displacement moved to the next mesh). Goal: on two
    /// blocks that touch along y = 1 with their own copies of its nodes (a joint), a point on
    /// the joint takes the value of the block of its tag, where the plain location takes one
    /// block's value for both. Parameters: [0, 1]² (tag 1, u = (0, 0)) and [0, 1] × [1, 2] (tag
    /// 2, u = (1, 2)), 3 × 3 cells each, P1 and P2, points at x ∈ {0, 0.3, 0.5, 1} on y = 1.
    #[test]
    fn points_on_a_joint_take_their_own_side() {
        for order in [1, 2] {
            let (mut mesh, upper) =
                (rectangle(0.0, 1.0, 0.0, 1.0, 3, 3, order), rectangle(0.0, 1.0, 1.0, 2.0, 3, 3, order));
            let offset = mesh.n_points();
            mesh.cell_tags = vec![1; mesh.n_cells()];
            mesh.points.extend(&upper.points);
            mesh.cell_nodes.extend(upper.cell_nodes.iter().map(|n| n + offset));
            mesh.cell_tags.extend(vec![2; upper.n_cells()]);
            let values: Vec<Vector> =
                (0..mesh.n_points()).map(|n| if n < offset { [0.0; 2] } else { [1.0, 2.0] }).collect();
            let points: Vec<Point> = [0.0, 0.3, 0.5, 1.0].iter().flat_map(|&x| [[x, 1.0], [x, 1.0]]).collect();
            let tags: Vec<i32> = (0..points.len()).map(|i| 1 + (i % 2) as i32).collect();
            for (u, tag) in interpolate_by_tag(&mesh, &values, &points, &tags).into_iter().zip(&tags) {
                assert_eq!(u, if *tag == 1 { [0.0; 2] } else { [1.0, 2.0] }, "P{order}, tag {tag}");
            }
            let plain = interpolate(&mesh, &values, &points);
            assert!(plain.chunks(2).all(|pair| pair[0] == pair[1]), "P{order}: one side for both copies");
        }
    }

    #[test]
    fn rings_cover_the_grid_once() {
        let grid = Grid::new([0.0; 2], [5.0, 3.0], 15);
        for centre in [[0, 0], [2, 1], [4, 2], [3, 0]] {
            let mut count = vec![0; grid.len()];
            for b in (0..5).flat_map(|r| grid.ring(centre, r)) {
                count[b] += 1;
            }
            assert!(count.iter().all(|&n| n == 1), "centre {centre:?}: {count:?}");
        }
    }

    #[test]
    fn unsearched_distance_bounds_the_strips() {
        let grid = Grid::new([0.0; 2], [5.0, 3.0], 15);
        assert_eq!(grid.unsearched_distance2([2.5, 1.5], [2, 1], 0), 0.25);
        assert_eq!(grid.unsearched_distance2([2.5, 1.5], [2, 1], 1), 2.25);
        assert_eq!(grid.unsearched_distance2([2.5, 1.5], [2, 1], 2), f64::INFINITY);
        // p left of the grid, centre clamped to column 0: the strip j = 0 is at distance (3, 0.5)
        assert_eq!(grid.unsearched_distance2([-3.0, 1.5], [0, 1], 0), 9.25);
    }

    #[test]
    fn nearest_point_projects_on_edges_and_vertices() {
        let v = [[0.0, 0.0], [2.0, 0.0], [0.0, 1.0]];
        assert_eq!(nearest_point(v, [1.0, -1.0]), (1.0, [0.5, 0.0]));
        assert_eq!(nearest_point(v, [3.0, -1.0]), (2.0, [1.0, 0.0]));
        assert_eq!(nearest_point(v, [-1.0, 2.0]), (2.0, [0.0, 1.0]));
        assert_eq!(nearest_point(v, [0.5, 0.25]), (0.0, [0.25, 0.25]));
        let (d2, xi) = nearest_point(v, [2.0, 1.0]);
        assert!((d2 - 0.8).abs() < 1e-15 && (xi[0] - 0.8).abs() < 1e-15 && (xi[1] - 0.2).abs() < 1e-15);
    }

    #[test]
    fn buckets_hold_a_few_cells() {
        let mesh = unit_square(20, 1);
        let buckets = Locator::new(&mesh).buckets;
        let n = buckets.grid.len();
        assert!(n >= mesh.n_cells() && n < 2 * mesh.n_cells());
        assert!(buckets.cells.len() <= 8 * n && buckets.longest() <= 12 && buckets.finer.is_empty());
    }

    /// The longest list of a bucket with no finer grid.
    fn longest_leaf(buckets: &Buckets) -> usize {
        let split = |b: usize| buckets.finer.binary_search_by_key(&b, |f| f.0).is_ok();
        let coarse = (0..buckets.grid.len()).filter(|&b| !split(b)).map(|b| buckets.list(b).len()).max().unwrap_or(0);
        buckets.finer.iter().map(|(_, f)| longest_leaf(f)).fold(coarse, usize::max)
    }

    #[test]
    fn crowded_buckets_of_a_graded_mesh_are_split() {
        // x ↦ x |x|⁴: cells from ~10⁻⁶ at the origin to ~1 at the corners
        let mut mesh = rectangle(-1.0, 1.0, -1.0, 1.0, 30, 30, 1);
        mesh.points.iter_mut().for_each(|p| *p = p.map(|x| x * p[0].hypot(p[1]).powi(4)));
        let buckets = Locator::new(&mesh).buckets;
        assert!(buckets.longest() > mesh.n_cells() / 5);
        assert!(longest_leaf(&buckets) <= 2 * CROWDED, "{}", longest_leaf(&buckets));
    }
}
