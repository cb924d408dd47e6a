//! Reference elements: Lagrange bases on a distorted triangle, quadrature exactness, affine maps.

use damfem::fem::lagrange::{gradients, n_basis, reference_nodes, values};
use damfem::fem::quadrature::{gauss_segment, triangle, triangle_cached};
use damfem::geometry::AffineMap;
use damfem::verify::rng::Rng;

const VERTICES: [[f64; 2]; 3] = [[0.1, 0.2], [1.3, 0.4], [0.35, 1.1]];

fn map() -> AffineMap {
    AffineMap::new(VERTICES)
}

/// `ξ = J⁻¹ (x − origin)`, with `J⁻¹ = (J⁻ᵀ)ᵀ`.
fn to_reference(m: &AffineMap, x: [f64; 2]) -> [f64; 2] {
    let d = [x[0] - m.origin[0], x[1] - m.origin[1]];
    let t = &m.inv_t;
    [t[0][0] * d[0] + t[1][0] * d[1], t[0][1] * d[0] + t[1][1] * d[1]]
}

/// Deterministic points inside the reference triangle (the seeded generator, folded).
fn random_points(count: usize) -> Vec<[f64; 2]> {
    let mut rng = Rng::new(0x2545_f491_4f6c_dd1d);
    let mut next = move || rng.uniform();
    (0..count)
        .map(|_| {
            let (u, v) = (next(), next());
            if u + v > 1.0 {
                [1.0 - u, 1.0 - v]
            } else {
                [u, v]
            }
        })
        .collect()
}

/// Physical basis values at physical point `x`: `φᵢ(x) = φ̂ᵢ(F⁻¹(x))`.
fn physical_values(order: usize, m: &AffineMap, x: [f64; 2]) -> Vec<f64> {
    let mut phi = vec![0.0; n_basis(order)];
    values(order, to_reference(m, x), &mut phi);
    phi
}

fn physical_gradients(order: usize, m: &AffineMap, xi: [f64; 2]) -> Vec<[f64; 2]> {
    let mut g = vec![[0.0; 2]; n_basis(order)];
    gradients(order, xi, &mut g);
    g.iter().map(|&r| m.physical_gradient(r)).collect()
}

#[test]
fn nodes_map_to_vertices_and_edge_midpoints() {
    let m = map();
    let nodes = reference_nodes(2);
    for (i, v) in VERTICES.iter().enumerate() {
        let x = m.to_physical(nodes[i]);
        assert!((x[0] - v[0]).abs() < 1e-15 && (x[1] - v[1]).abs() < 1e-15);
    }
    for (k, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
        let x = m.to_physical(nodes[3 + k]);
        let mid = [0.5 * (VERTICES[i][0] + VERTICES[j][0]), 0.5 * (VERTICES[i][1] + VERTICES[j][1])];
        assert!((x[0] - mid[0]).abs() < 1e-15 && (x[1] - mid[1]).abs() < 1e-15);
    }
}

#[test]
fn nodality_on_distorted_triangle() {
    let m = map();
    for order in 1..=2 {
        for (j, &node) in reference_nodes(order).iter().enumerate() {
            let phi = physical_values(order, &m, m.to_physical(node));
            for (i, &p) in phi.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!((p - expected).abs() < 1e-13, "order {order}: φ{i}(x{j}) = {p}");
            }
        }
    }
}

#[test]
fn partition_of_unity_and_zero_gradient_sum() {
    let m = map();
    for order in 1..=2 {
        for xi in random_points(50) {
            let phi = physical_values(order, &m, m.to_physical(xi));
            assert!((phi.iter().sum::<f64>() - 1.0).abs() < 1e-13);
            let g = physical_gradients(order, &m, xi);
            let s = g.iter().fold([0.0, 0.0], |a, d| [a[0] + d[0], a[1] + d[1]]);
            assert!(s[0].abs() < 1e-12 && s[1].abs() < 1e-12, "order {order}: Σ∇φ = {s:?}");
        }
    }
}

#[test]
fn physical_gradients_match_central_differences() {
    let m = map();
    let h = 1e-5;
    for order in 1..=2 {
        for xi in random_points(30) {
            let x = m.to_physical(xi);
            let g = physical_gradients(order, &m, xi);
            for d in 0..2 {
                let (mut xp, mut xm) = (x, x);
                xp[d] += h;
                xm[d] -= h;
                let (fp, fm) = (physical_values(order, &m, xp), physical_values(order, &m, xm));
                for i in 0..n_basis(order) {
                    let fd = (fp[i] - fm[i]) / (2.0 * h);
                    let err = (fd - g[i][d]).abs();
                    assert!(err < 1e-7, "order {order}, φ{i}, ∂{d}: error {err:e}");
                }
            }
        }
    }
}

fn factorial(n: usize) -> f64 {
    (1..=n).map(|k| k as f64).product()
}

/// Relative error of the rule on `∫_T̂ x^a y^b = a! b! / (a + b + 2)!`.
fn monomial_error(points: &[[f64; 2]], weights: &[f64], a: usize, b: usize) -> f64 {
    let exact = factorial(a) * factorial(b) / factorial(a + b + 2);
    let approx: f64 = points.iter().zip(weights).map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32)).sum();
    ((approx - exact) / exact).abs()
}

#[test]
fn triangle_rules_exact_up_to_their_degree() {
    for degree in 1..=12 {
        let r = triangle_cached(degree);
        assert_eq!(r.degree, degree);
        for a in 0..=degree {
            for b in 0..=degree - a {
                let e = monomial_error(&r.points, &r.weights, a, b);
                assert!(e < 1e-13, "degree {degree}: x^{a} y^{b} error {e:e}");
            }
        }
    }
}

#[test]
fn triangle_rules_are_not_exact_beyond_2n_minus_2() {
    for degree in 0..=12 {
        let r = triangle(degree);
        let n = (r.points.len() as f64).sqrt().round() as usize;
        let top = 2 * n - 1;
        assert!(top <= degree + 2);
        for a in 0..=top {
            let e = monomial_error(&r.points, &r.weights, a, top - a);
            assert!(e > 1e-10, "degree {degree}: x^{a} y^{} unexpectedly exact", top - a);
        }
    }
    let even = triangle(4);
    assert!(monomial_error(&even.points, &even.weights, 5, 0) > 1e-10);
}

fn segment_integral(n: usize, f: impl Fn(f64) -> f64) -> f64 {
    let g = gauss_segment(n);
    g.points.iter().zip(&g.weights).map(|(&x, w)| w * f(x)).sum()
}

#[test]
fn gauss_segment_exact_to_2n_minus_1() {
    for n in 1..=12 {
        assert_eq!(gauss_segment(n).points.len(), n);
        for k in 0..2 * n as i32 {
            let e = (segment_integral(n, |x| x.powi(k)) * (k + 1) as f64 - 1.0).abs();
            assert!(e < 1e-13, "n = {n}: x^{k} error {e:e}");
        }
    }
}

/// Degree 2n fails: the squared node polynomial `ω² = Π (x − xᵢ)²` has
/// `∫₀¹ ω² = (n!)⁴ / ((2n + 1) ((2n)!)²) > 0` but vanishes at every node.
#[test]
fn gauss_segment_not_exact_at_2n() {
    for n in 1..=12 {
        let nodes = gauss_segment(n).points;
        let omega2 = |x: f64| nodes.iter().map(|&p| (x - p) * (x - p)).product::<f64>();
        let exact = factorial(n).powi(4) / ((2 * n + 1) as f64 * factorial(2 * n).powi(2));
        assert_eq!(segment_integral(n, omega2), 0.0);
        let e = (segment_integral(n + 1, omega2) - exact).abs() / exact;
        assert!(e < 1e-9, "n = {n}: (n+1)-point rule on ω² error {e:e}");
    }
    for n in 1..=4 {
        let k = 2 * n as i32;
        let e = (segment_integral(n, |x| x.powi(k)) * (k + 1) as f64 - 1.0).abs();
        assert!(e > 1e-10, "n = {n}: x^{k} unexpectedly exact");
    }
}

#[test]
fn quadrature_on_physical_triangle() {
    let m = map();
    let area = 0.5
        * ((VERTICES[1][0] - VERTICES[0][0]) * (VERTICES[2][1] - VERTICES[0][1])
            - (VERTICES[2][0] - VERTICES[0][0]) * (VERTICES[1][1] - VERTICES[0][1]));
    assert!((m.area() - area).abs() < 1e-15);
    let r = triangle_cached(4);
    let one: f64 = r.weights.iter().map(|w| w * m.det.abs()).sum();
    assert!((one - area).abs() < 1e-14);
    let centroid_x = VERTICES.iter().map(|v| v[0]).sum::<f64>() / 3.0;
    let int_x: f64 = r.points.iter().zip(&r.weights).map(|(&p, w)| w * m.det.abs() * m.to_physical(p)[0]).sum();
    assert!((int_x - area * centroid_x).abs() < 1e-14);
}
