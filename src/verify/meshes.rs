//! Perturbed and graded meshes for stability studies.

use super::rng::Rng;
use crate::estimate::reference::refine::{bisect, Refinement};
use crate::geometry::{dot, norm, sub, Point};
use crate::mesh::Mesh;

/// Moves every interior vertex by a random vector of length up to `fraction · h` (uniform
/// direction and radius), then puts P2 midpoints back at the middle of their edges. On the
/// diagonal-split grid, fraction < 1/(2√2) ≈ 0.354 keeps every triangle positively oriented.
pub fn distort(mesh: &mut Mesh, fraction: f64, h: f64, seed: u64) {
    let mut on_boundary = vec![false; mesh.n_points()];
    for &n in &mesh.facet_nodes {
        on_boundary[n] = true;
    }
    let mut vertices: Vec<usize> = (0..mesh.n_cells()).flat_map(|c| mesh.cell(c)[..3].to_vec()).collect();
    vertices.sort_unstable();
    vertices.dedup();
    let mut rng = Rng::new(seed);
    for &v in vertices.iter().filter(|&&v| !on_boundary[v]) {
        let (r, angle) = (fraction * h * rng.uniform(), 2.0 * std::f64::consts::PI * rng.uniform());
        let p = mesh.points[v];
        mesh.points[v] = [p[0] + r * angle.cos(), p[1] + r * angle.sin()];
    }
    if mesh.order == 2 {
        for c in 0..mesh.n_cells() {
            let cell = mesh.cell(c).to_vec();
            for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                let (a, b) = (mesh.points[cell[i]], mesh.points[cell[j]]);
                mesh.points[cell[3 + k]] = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
            }
        }
    }
}

/// Smallest interior angle over the cells, in degrees, and the smallest signed area.
pub fn quality(mesh: &Mesh) -> (f64, f64) {
    let mut min_angle = 180.0f64;
    let mut min_area = f64::INFINITY;
    for c in 0..mesh.n_cells() {
        let v = mesh.cell_vertices(c);
        min_area = min_area.min(mesh.cell_area(c));
        for (i, &[j, k]) in mesh.cell_type().facets().iter().enumerate() {
            let (a, b, d) = (v[i], v[j], v[k]);
            let (e, f) = (sub(b, a), sub(d, a));
            let cos = dot(e, f) / (norm(e) * norm(f));
            min_angle = min_angle.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    (min_angle, min_area)
}

/// The degree-1 `mesh` bisected (newest-vertex bisection) at the cells within two diameters
/// of `point` until its smallest cell is `ratio` times smaller than its largest: a
/// shape-regular mesh graded by `ratio` towards `point`, like those of the adaptive loop.
/// On a mesh with dyadic vertices, every vertex stays dyadic.
pub fn graded(mesh: &Mesh, point: Point, ratio: f64) -> Mesh {
    let diameters = |m: &Mesh| (0..m.n_cells()).map(|c| m.cell_diameter(c)).collect::<Vec<_>>();
    let largest = diameters(mesh).into_iter().fold(0.0, f64::max);
    let mut current = Refinement {
        mesh: mesh.clone(),
        cell_parents: (0..mesh.n_cells()).collect(),
        facet_parents: (0..mesh.n_facets()).collect(),
    };
    loop {
        let h = diameters(&current.mesh);
        if h.iter().fold(f64::MAX, |m, &v| m.min(v)) * ratio <= largest {
            return current.mesh;
        }
        let near = |c: usize| crate::geometry::distance(current.mesh.cell_centroid(c), point) <= 2.0 * h[c];
        let marked: Vec<bool> = (0..h.len()).map(near).collect();
        current = bisect(&current, &marked);
    }
}

/// The 4 × 4 unit square graded by `ratio` towards its centre ([`graded`]), at degree `order`.
pub fn graded_unit_square(ratio: f64, order: usize) -> Mesh {
    let mesh = graded(&crate::mesh::structured::rectangle(0.0, 1.0, 0.0, 1.0, 4, 4, 1), [0.5, 0.5], ratio);
    if order == 2 {
        crate::mesh::midpoints::elevate_to_p2(&mesh)
    } else {
        mesh
    }
}
