//! Transfer of fields between non-nested meshes: exactness on polynomials, points on edges and
//! outside the mesh, strongly graded meshes checked against a brute-force search, scale.

use damfem::fem::transfer::{interpolate, Locator};
use damfem::geometry::AffineMap;
use damfem::mesh::midpoints::elevate_to_p2;
use damfem::mesh::structured::{rectangle, unit_square};
use damfem::mesh::Mesh;
use damfem::verify::rng::Rng;

/// A P1 mesh of the unit square with n × n squares whose interior vertices are moved by up to
/// `amplitude / n` in each direction: not nested in any structured mesh.
fn perturbed_square(n: usize, amplitude: f64, seed: u64) -> Mesh {
    let mut mesh = unit_square(n, 1);
    let mut rng = Rng::new(seed);
    let on_boundary = |x: f64| x == 0.0 || x == 1.0;
    for p in mesh.points.iter_mut().filter(|p| !on_boundary(p[0]) && !on_boundary(p[1])) {
        *p = p.map(|x| x + amplitude * (2.0 * rng.uniform() - 1.0) / n as f64);
    }
    assert!((0..mesh.n_cells()).all(|c| mesh.cell_area(c) > 0.0), "perturbation folded a cell");
    mesh
}

fn linear(x: [f64; 2]) -> [f64; 2] {
    [1.0 + 2.0 * x[0] - 3.0 * x[1], -0.5 + x[0] + 4.0 * x[1]]
}

fn quadratic(x: [f64; 2]) -> [f64; 2] {
    let [a, b] = x;
    [1.0 - a + 2.0 * b + 3.0 * a * b - a * a + 0.5 * b * b, 2.0 * a * a - b * b + a * b - a]
}

fn max_error(values: &[[f64; 2]], points: &[[f64; 2]], f: impl Fn([f64; 2]) -> [f64; 2]) -> f64 {
    values.iter().zip(points).map(|(u, &p)| (u[0] - f(p)[0]).abs().max((u[1] - f(p)[1]).abs())).fold(0.0, f64::max)
}

fn nodal(mesh: &Mesh, f: impl Fn([f64; 2]) -> [f64; 2]) -> Vec<[f64; 2]> {
    mesh.points.iter().map(|&p| f(p)).collect()
}

/// Euclidean distance from `p` to the triangle `v` (0 inside), by its edges.
fn distance_to_triangle(v: [[f64; 2]; 3], p: [f64; 2]) -> f64 {
    let side = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let s = [side(v[0], v[1]), side(v[1], v[2]), side(v[2], v[0])];
    if s.iter().all(|&s| s >= 0.0) || s.iter().all(|&s| s <= 0.0) {
        return 0.0;
    }
    (0..3).map(|i| distance_to_segment(v[i], v[(i + 1) % 3], p)).fold(f64::INFINITY, f64::min)
}

fn distance_to_segment(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    let (e, d) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let t = ((d[0] * e[0] + d[1] * e[1]) / (e[0] * e[0] + e[1] * e[1])).clamp(0.0, 1.0);
    (d[0] - t * e[0]).hypot(d[1] - t * e[1])
}

/// `ξ = J⁻¹ (x − origin)`.
fn to_reference(m: &AffineMap, x: [f64; 2]) -> [f64; 2] {
    let (d, t) = ([x[0] - m.origin[0], x[1] - m.origin[1]], &m.inv_t);
    [t[0][0] * d[0] + t[1][0] * d[1], t[0][1] * d[0] + t[1][1] * d[1]]
}

/// Checks `locate(p)` against all cells: the located point `F_c(ξ)` is in cell c and as near
/// to `p` as the nearest cell; inside the mesh, `p` itself is in c.
fn check_against_brute_force(mesh: &Mesh, points: &[[f64; 2]]) {
    let locator = Locator::new(mesh);
    for &p in points {
        let (c, xi) = locator.locate(p);
        let nearest =
            (0..mesh.n_cells()).map(|c| distance_to_triangle(mesh.cell_vertices(c), p)).fold(f64::INFINITY, f64::min);
        let map = AffineMap::new(mesh.cell_vertices(c));
        let x = map.to_physical(xi);
        assert!(xi[0] >= -1e-12 && xi[1] >= -1e-12 && xi[0] + xi[1] <= 1.0 + 1e-12, "ξ = {xi:?} for {p:?}");
        // round-off of x ↦ ξ ↦ x grows with the aspect ratio diam² / (2 area) of the cell
        let h = mesh.cell_diameter(c);
        let tolerance = 1e-14 * (1.0 + nearest + h * h * h / (2.0 * mesh.cell_area(c)));
        let found = (x[0] - p[0]).hypot(x[1] - p[1]);
        assert!((found - nearest).abs() <= tolerance, "{p:?}: cell {c} at {found}, nearest {nearest}");
        if nearest == 0.0 {
            let l = to_reference(&map, p);
            assert!(l[0].min(l[1]).min(1.0 - l[0] - l[1]) >= -1e-12, "{p:?} is not in cell {c}: ξ = {l:?}");
        }
    }
}

#[test]
fn p1_linear_field_is_reproduced_on_a_non_nested_mesh() {
    let source = perturbed_square(7, 0.2, 1);
    let target = perturbed_square(11, 0.2, 2);
    let u = interpolate(&source, &nodal(&source, linear), &target.points);
    assert!(max_error(&u, &target.points, linear) < 1e-12);
}

#[test]
fn p2_quadratic_field_is_reproduced_on_a_non_nested_mesh() {
    let source = elevate_to_p2(&perturbed_square(5, 0.2, 3));
    let target = elevate_to_p2(&perturbed_square(8, 0.2, 4));
    let u = interpolate(&source, &nodal(&source, quadratic), &target.points);
    assert!(max_error(&u, &target.points, quadratic) < 1e-12);
    // a P2 field is not reproduced by P1 interpolation on the same cells
    let p1 = perturbed_square(5, 0.2, 3);
    let u = interpolate(&p1, &nodal(&p1, quadratic), &target.points);
    assert!(max_error(&u, &target.points, quadratic) > 1e-3);
}

#[test]
fn points_on_edges_and_outside_take_the_nearest_cell() {
    let mesh = unit_square(4, 1);
    let values = nodal(&mesh, linear);
    let mut points: Vec<[f64; 2]> = mesh.points.clone();
    let edge_points = (0..mesh.n_cells()).flat_map(|c| {
        let v = mesh.cell_vertices(c);
        (0..3).map(move |i| {
            let (a, b) = (v[i], v[(i + 1) % 3]);
            [0.3 * a[0] + 0.7 * b[0], 0.3 * a[1] + 0.7 * b[1]]
        })
    });
    points.extend(edge_points);
    for d in [1e-9, 1e-3, 0.4] {
        for s in [0.0, 0.3, 0.5, 1.0] {
            points.extend([[s, -d], [1.0 + d, s], [s, 1.0 + d], [-d, s], [-d, -d], [1.0 + d, 1.0 + 2.0 * d]]);
        }
    }
    let u = interpolate(&mesh, &values, &points);
    let clamped: Vec<[f64; 2]> = points.iter().map(|p| p.map(|x| x.clamp(0.0, 1.0))).collect();
    assert!(max_error(&u, &clamped, linear) < 1e-12);
    check_against_brute_force(&mesh, &points);
    // far away, squared distances to neighbouring cells agree to round-off: any of them will do
    let far = [[1e6, -3e5], [-1e8, 0.5], [0.5, 4e7], [1e300, 1e300], [f64::NAN, 0.5]];
    assert!(interpolate(&mesh, &values, &far[..3]).iter().flatten().all(|u| u.is_finite()));
    let locator = Locator::new(&mesh);
    assert!(far.iter().all(|&p| locator.locate(p).0 < mesh.n_cells()));
}

/// `g(x) = (e^{a x} − 1) / (e^a − 1)`: spacings from `a / (e^a − 1)` to `a e^a / (e^a − 1)` times 1/n.
fn exponential(x: f64, a: f64) -> f64 {
    (a * x).exp_m1() / a.exp_m1()
}

/// The mesh of [-1, 1]² with 40 × 40 squares moved by `map`, and points: `map` of uniform points
/// of [-1.1, 1.1]² (dense where the mesh is) and uniform points around the bounding box.
fn graded(map: impl Fn([f64; 2]) -> [f64; 2], seed: u64) -> (Mesh, Vec<[f64; 2]>) {
    let mut mesh = rectangle(-1.0, 1.0, -1.0, 1.0, 40, 40, 1);
    mesh.points.iter_mut().for_each(|p| *p = map(*p));
    assert!((0..mesh.n_cells()).all(|c| mesh.cell_area(c) > 0.0));
    let mut rng = Rng::new(seed);
    let mut points: Vec<[f64; 2]> =
        (0..700).map(|_| map([2.2 * rng.uniform() - 1.1, 2.2 * rng.uniform() - 1.1])).collect();
    let (lo, hi) = mesh.points.iter().fold(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    });
    points.extend((0..300).map(|_| [0, 1].map(|k| lo[k] + (1.2 * rng.uniform() - 0.1) * (hi[k] - lo[k]))));
    (mesh, points)
}

#[test]
fn strongly_graded_meshes_locate_like_brute_force() {
    // radial grading x |x|⁴: cells from ~10⁻⁷ at the origin to ~1 at the corners, aspect ratio ≤ 5
    let (mesh, points) = graded(|p| p.map(|x| x * p[0].hypot(p[1]).powi(4)), 5);
    check_against_brute_force(&mesh, &points);
    // exponential grading in x and y, sheared: from ~10⁻⁶ to ~0.3, slivers of aspect ratio ~10⁵
    let shear = |[x, y]: [f64; 2]| [x + 0.3 * y, y - 0.2 * x];
    let (mesh, points) = graded(|p| shear(p.map(|x| exponential(0.5 * (x + 1.0), 12.0))), 6);
    check_against_brute_force(&mesh, &points);
    let u = interpolate(&mesh, &nodal(&mesh, linear), &mesh.points);
    assert!(max_error(&u, &mesh.points, linear) < 1e-12);
}

#[test]
fn hundred_thousand_points_in_a_hundred_thousand_cells() {
    let source = perturbed_square(224, 0.2, 6);
    assert!(source.n_cells() > 100_000);
    let mut rng = Rng::new(7);
    let points: Vec<[f64; 2]> = (0..100_000).map(|_| [rng.uniform(), rng.uniform()]).collect();
    let u = interpolate(&source, &nodal(&source, linear), &points);
    assert!(max_error(&u, &points, linear) < 1e-12);
}
