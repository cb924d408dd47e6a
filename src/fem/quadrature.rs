//! Quadrature rules computed at run time (no tabulated data).
//!
//! * [`gauss_segment`]`(n)`: Gauss–Legendre rule with `n` points on `[0, 1]`, nodes found by
//!   Newton iteration on the Legendre polynomial `P_n`. Exact for polynomials of degree
//!   `≤ 2n − 1`; weights sum to 1.
//! * [`triangle`]`(d)`: collapsed (Duffy) product rule on the reference triangle
//!   `(0,0), (1,0), (0,1)`. With `x = u`, `y = (1 − u) v` and `dx dy = (1 − u) du dv`, a polynomial
//!   of total degree `d` becomes a polynomial of degree `≤ d + 1` in `u` and `≤ d` in `v`, so the
//!   tensor product of two `n`-point Gauss rules with `2n − 1 ≥ d + 1` is exact for every
//!   polynomial of total degree `≤ d` (in fact `≤ 2n − 2`). Weights sum to `1/2`.
//! * [`triangle_cached`]`(d)`: the same rule, built once per degree and shared.
//! * [`tetrahedron`]`(d)`: on the reference tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1),
//!   the centroid for d ≤ 1, the symmetric 4-point rule for d = 2 (the points a e_i + b Σ_{j≠i}
//!   e_j in barycentric coordinates, b = (5 − √5)/20, a = 1 − 3b, weights 1/24), and above the
//!   collapsed rule: with `x = u`, `y = (1 − u) v`, `z = (1 − u)(1 − v) w` and
//!   `dx dy dz = (1 − u)² (1 − v) du dv dw`, a polynomial of total degree `d` has degree
//!   `≤ d + 2` in `u`, `≤ d + 1` in `v` and `≤ d` in `w`: `n` Gauss points per direction with
//!   `2n − 1 ≥ d + 2` integrate it exactly. Weights sum to `1/6`.

use crate::geometry::{Point, Point3};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Highest degree served by [`triangle_cached`].
pub const MAX_CACHED_DEGREE: usize = 20;

/// One-dimensional rule on `[0, 1]`: `∫₀¹ f ≈ Σ wᵢ f(xᵢ)`.
#[derive(Debug, Clone)]
pub struct Rule1d {
    pub points: Vec<f64>,
    pub weights: Vec<f64>,
}

/// Rule on the reference triangle: `∫_T̂ f ≈ Σ wᵢ f(ξᵢ)`, exact for total degree `≤ degree`.
#[derive(Debug, Clone)]
pub struct TriangleRule {
    pub points: Vec<Point>,
    pub weights: Vec<f64>,
    /// Polynomial degree requested (and guaranteed to be integrated exactly).
    pub degree: usize,
}

/// Legendre polynomial `P_n(x)` and its derivative, by the three-term recurrence
/// `(k+1) P_{k+1} = (2k+1) x P_k − k P_{k−1}` and `P_n' = n (x P_n − P_{n−1}) / (x² − 1)`.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p_prev, mut p) = (1.0, x);
    for k in 1..n {
        let kf = k as f64;
        let p_next = ((2.0 * kf + 1.0) * x * p - kf * p_prev) / (kf + 1.0);
        p_prev = p;
        p = p_next;
    }
    let dp = n as f64 * (x * p - p_prev) / (x * x - 1.0);
    (p, dp)
}

/// `i`-th root of `P_n` on `[−1, 1]` (descending), by Newton from `cos(π (i + 3/4) / (n + 1/2))`.
fn legendre_root(n: usize, i: usize) -> (f64, f64) {
    let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
    for _ in 0..100 {
        let (p, dp) = legendre(n, x);
        let dx = p / dp;
        x -= dx;
        if dx.abs() < 1e-16 {
            break;
        }
    }
    let (_, dp) = legendre(n, x);
    (x, dp)
}

/// Gauss–Legendre rule with `n ≥ 1` points on `[0, 1]`, in increasing order.
///
/// The rule applied on each piece of [0, 1] cut at `cuts` (points inside (0, 1); the ends
/// are added): (s, weight), weights summing to 1. Integrates piecewise polynomials with
/// breaks at the cuts as exactly as the rule integrates polynomials.
pub fn split_rule(rule: &Rule1d, mut cuts: Vec<f64>) -> Vec<(f64, f64)> {
    cuts.push(0.0);
    cuts.push(1.0);
    cuts.sort_by(f64::total_cmp);
    cuts.windows(2)
        .filter(|w| w[1] > w[0])
        .flat_map(|w| {
            rule.points.iter().zip(&rule.weights).map(move |(&s, &ws)| (w[0] + s * (w[1] - w[0]), ws * (w[1] - w[0])))
        })
        .collect()
}

/// On `[−1, 1]` the nodes are the roots `tᵢ` of `P_n` with weights `2 / ((1 − tᵢ²) P_n'(tᵢ)²)`;
/// they are mapped by `x = (1 − t) / 2`, halving the weights. Exact to degree `2n − 1`.
pub fn gauss_segment(n: usize) -> Rule1d {
    assert!(n >= 1, "a Gauss rule needs at least one point");
    let (points, weights) = (0..n)
        .map(|i| {
            let (t, dp) = legendre_root(n, i);
            (0.5 * (1.0 - t), 1.0 / ((1.0 - t * t) * dp * dp))
        })
        .unzip();
    Rule1d { points, weights }
}

/// [`gauss_segment`]`(n)`, computed on first use and cached; `n ≤ MAX_CACHED_DEGREE`.
pub fn gauss_segment_cached(n: usize) -> &'static Rule1d {
    static CACHE: [OnceLock<Rule1d>; MAX_CACHED_DEGREE + 1] = [const { OnceLock::new() }; MAX_CACHED_DEGREE + 1];
    assert!(n <= MAX_CACHED_DEGREE, "gauss_segment_cached: {n} points > {MAX_CACHED_DEGREE}");
    CACHE[n].get_or_init(|| gauss_segment(n))
}

/// Collapsed Gauss rule exact for polynomials of total degree `≤ degree` on the reference
/// triangle: `n × n` points with the smallest `n` such that `2n − 1 ≥ degree + 1`.
///
/// Point `(uᵢ, (1 − uᵢ) vⱼ)`, weight `(1 − uᵢ) wᵢ wⱼ`.
pub fn triangle(degree: usize) -> TriangleRule {
    let n = (degree + 3) / 2;
    let g = gauss_segment(n);
    let mut points = Vec::with_capacity(n * n);
    let mut weights = Vec::with_capacity(n * n);
    for (&u, &wu) in g.points.iter().zip(&g.weights) {
        for (&v, &wv) in g.points.iter().zip(&g.weights) {
            points.push([u, (1.0 - u) * v]);
            weights.push((1.0 - u) * wu * wv);
        }
    }
    TriangleRule { points, weights, degree }
}

/// [`triangle`]`(degree)`, computed on first use and cached; `degree ≤ MAX_CACHED_DEGREE`.
pub fn triangle_cached(degree: usize) -> &'static TriangleRule {
    static CACHE: [OnceLock<TriangleRule>; MAX_CACHED_DEGREE + 1] = [const { OnceLock::new() }; MAX_CACHED_DEGREE + 1];
    assert!(degree <= MAX_CACHED_DEGREE, "triangle_cached: degree {degree} > {MAX_CACHED_DEGREE}");
    CACHE[degree].get_or_init(|| triangle(degree))
}

/// Rule on the reference tetrahedron: `∫_T̂ f ≈ Σ wᵢ f(ξᵢ)`, exact for total degree `≤ degree`.
#[derive(Debug, Clone)]
pub struct TetrahedronRule {
    pub points: Vec<Point3>,
    pub weights: Vec<f64>,
    pub degree: usize,
}

/// A rule exact for total degree `≤ degree` on the reference tetrahedron: the centroid
/// (degree ≤ 1), the symmetric 4-point rule (degree 2), or the collapsed Gauss rule of `n³`
/// points with the smallest `n` such that `2n − 1 ≥ degree + 2`.
///
/// Collapsed: point `(uᵢ, (1 − uᵢ) vⱼ, (1 − uᵢ)(1 − vⱼ) w_k)`, weight
/// `(1 − uᵢ)² (1 − vⱼ) wᵢ wⱼ w_k`.
pub fn tetrahedron(degree: usize) -> TetrahedronRule {
    match degree {
        0 | 1 => return TetrahedronRule { points: vec![[0.25; 3]], weights: vec![1.0 / 6.0], degree },
        2 => {
            let b = (5.0 - 5f64.sqrt()) / 20.0;
            let a = 1.0 - 3.0 * b;
            let points = vec![[b, b, b], [a, b, b], [b, a, b], [b, b, a]];
            return TetrahedronRule { points, weights: vec![1.0 / 24.0; 4], degree };
        }
        _ => {}
    }
    let n = (degree + 4) / 2;
    let g = gauss_segment(n);
    let rule = || g.points.iter().zip(&g.weights);
    let (mut points, mut weights) = (Vec::with_capacity(n * n * n), Vec::with_capacity(n * n * n));
    for (&u, &wu) in rule() {
        for (&v, &wv) in rule() {
            for (&w, &ww) in rule() {
                points.push([u, (1.0 - u) * v, (1.0 - u) * (1.0 - v) * w]);
                weights.push((1.0 - u) * (1.0 - u) * (1.0 - v) * wu * wv * ww);
            }
        }
    }
    TetrahedronRule { points, weights, degree }
}

/// [`tetrahedron`]`(degree)`, computed on first use and cached; `degree ≤ MAX_CACHED_DEGREE`.
pub fn tetrahedron_cached(degree: usize) -> &'static TetrahedronRule {
    static CACHE: [OnceLock<TetrahedronRule>; MAX_CACHED_DEGREE + 1] =
        [const { OnceLock::new() }; MAX_CACHED_DEGREE + 1];
    assert!(degree <= MAX_CACHED_DEGREE, "tetrahedron_cached: degree {degree} > {MAX_CACHED_DEGREE}");
    CACHE[degree].get_or_init(|| tetrahedron(degree))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Source: the Dirichlet integral ∫_T̂ x^a y^b z^c = a! b! c! / (a + b + c + 3)!.
    /// Goal: the tetrahedron rule of degree d integrates every monomial of degree ≤ d to
    /// round-off; its point count is 1 (d ≤ 1), 4 (d = 2) or the smallest the collapsed
    /// product allows.
    /// Parameters: d = 0..=12, all monomials of degree ≤ d.
    #[test]
    fn the_tetrahedron_rule_integrates_every_monomial_of_its_degree() {
        let factorial = |k: usize| (1..=k).map(|i| i as f64).product::<f64>();
        for d in 0..=12 {
            let rule = tetrahedron_cached(d);
            let n = (d + 4) / 2;
            let count = [1, 1, 4].get(d).copied().unwrap_or(n * n * n);
            assert!(2 * n > d + 2 && 2 * (n - 1) <= d + 2 && rule.points.len() == count);
            for a in 0..=d {
                for b in 0..=d - a {
                    for c in 0..=d - a - b {
                        let exact = factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
                        let quad: f64 = (rule.points.iter().zip(&rule.weights))
                            .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32))
                            .sum();
                        assert!((quad - exact).abs() <= 1e-14 * exact.max(1e-3), "d {d}: x^{a} y^{b} z^{c}");
                    }
                }
            }
        }
    }

    #[test]
    fn gauss_points_sorted_inside_and_symmetric() {
        for n in 1..=15 {
            let g = gauss_segment(n);
            assert!(g.points.windows(2).all(|w| w[0] < w[1]));
            assert!(g.points.iter().all(|&x| 0.0 < x && x < 1.0));
            for i in 0..n {
                assert!((g.points[i] + g.points[n - 1 - i] - 1.0).abs() < 1e-14);
                assert!((g.weights[i] - g.weights[n - 1 - i]).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn triangle_size_and_cache() {
        for d in 0..=MAX_CACHED_DEGREE {
            let n = (d + 3) / 2;
            assert!(2 * n >= d + 2 && (n == 1 || 2 * (n - 1) < d + 2));
            let r = triangle_cached(d);
            assert_eq!(r.points.len(), n * n);
            assert!(std::ptr::eq(r, triangle_cached(d)));
            let sum: f64 = r.weights.iter().sum();
            assert!((sum - 0.5).abs() < 1e-14);
        }
    }
}
