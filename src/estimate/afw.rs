//! The Arnold–Falk–Winther stress element of degree p on one triangle, in broken form.
//!
//! Each row of an AFW stress lies in BDM_p = P_p(T)², the full polynomial space, so the
//! patch problems use broken P_p(T)^{2×2} stresses and impose normal-trace continuity by
//! face moments (docs/method.md §3). No Piola map, orientation signs or Nédélec basis are
//! needed; this element is written by hand because no crate provides it.
//!
//! A stress on T is τ = Σ_{c,k} s_{ck} φ_k E_c, with φ_k the Lagrange P_p basis and
//! E_c, c = 2i + j, the matrix unit of row i and column j (c = 0 xx, 1 xy, 2 yx, 3 yy).
//! Its coefficient of (c, k) sits at index c · n_basis + k. The multipliers are P_{p−1}
//! fields: the displacement r ∈ P_{p−1}(T)² (divergence) and the rotation m ∈ P_{p−1}(T)
//! (weak symmetry, tested against m J with J = [[0, 1], [−1, 0]]).

use crate::fem::lagrange;
use crate::fem::quadrature::{gauss_segment_cached, triangle_cached};
use crate::geometry::{AffineMap, Point, Vector};
use std::sync::OnceLock;

/// Number of stress components.
pub const COMPONENTS: usize = 4;

/// Dimension of P_{p−1} on a triangle.
pub fn n_lower(order: usize) -> usize {
    order * (order + 1) / 2
}

/// The P_{p−1} basis at reference point ξ: the constant 1 for p = 1, Lagrange P1 for p = 2.
pub fn lower_values(order: usize, xi: Point, out: &mut [f64]) {
    if order == 1 {
        out[0] = 1.0;
    } else {
        lagrange::values(order - 1, xi, out);
    }
}

/// Reference nodes of the P_{p−1} basis (the centroid for p = 1): a P1 field z is
/// z = Σ_m z(x_m) ψ_m for p = 2, and Π⁰z = z(centroid) for p = 1.
pub fn lower_nodes(order: usize) -> &'static [Point] {
    if order == 1 {
        &[[1.0 / 3.0, 1.0 / 3.0]]
    } else {
        lagrange::reference_nodes(order - 1)
    }
}

/// Integrals of the basis over one cell.
pub struct CellIntegrals {
    /// ∫_T φ_k φ_l, n_basis × n_basis, row-major.
    pub mass: Vec<f64>,
    /// C = L⁻¹ for the Cholesky factor M = L Lᵀ of `mass`, row-major and lower triangular:
    /// the functions χ_k = Σ_l C_kl φ_l are orthonormal in L²(T).
    pub orthonormal: Vec<f64>,
    /// ∫_T ∂_j φ_k ψ_m at `[(m · n_basis + k) · 2 + j]`.
    pub divergence: Vec<f64>,
    /// ∫_T φ_k ψ_m at `[m · n_basis + k]`.
    pub lower_mass: Vec<f64>,
    /// ∫_T ψ_m ψ_l, n_lower × n_lower.
    pub lower_gram: Vec<f64>,
}

/// The integrals of [`CellIntegrals`] on the cell mapped by `map`, as affine images of the
/// reference ones (computed once per degree): with d = |det J|, M = d M̂, C = Ĉ/√d (M = (√d L̂)(√d
/// L̂)ᵀ), ∫_T φ ψ = d ∫_T̂ φ̂ ψ̂, ∫_T ψ ψ = d ∫_T̂ ψ̂ ψ̂ and ∫_T ∂_j φ_k ψ_m = d Σ_r (J⁻ᵀ)_jr ∫_T̂ ∂̂_r φ̂_k ψ̂_m.
pub fn cell_integrals(order: usize, map: &AffineMap) -> CellIntegrals {
    let reference = reference_integrals(order);
    let d = map.det.abs();
    let scaled = |v: &[f64], factor: f64| v.iter().map(|x| x * factor).collect();
    let divergence = reference
        .divergence
        .chunks_exact(2)
        .flat_map(|g| {
            let g = map.physical_gradient([g[0], g[1]]);
            [g[0] * d, g[1] * d]
        })
        .collect();
    CellIntegrals {
        mass: scaled(&reference.mass, d),
        orthonormal: scaled(&reference.orthonormal, 1.0 / d.sqrt()),
        divergence,
        lower_mass: scaled(&reference.lower_mass, d),
        lower_gram: scaled(&reference.lower_gram, d),
    }
}

/// The [`CellIntegrals`] of the reference triangle (J = I), by quadrature exact for them
/// (degree 2p), computed once per degree; `divergence` holds ∫ ∂̂_r φ̂_k ψ̂_m.
fn reference_integrals(order: usize) -> &'static CellIntegrals {
    static CACHE: [OnceLock<CellIntegrals>; 3] = [const { OnceLock::new() }; 3];
    CACHE[order].get_or_init(|| {
        quadrature_integrals(order, &AffineMap::new(lagrange::reference_nodes(1).try_into().expect("three vertices")))
    })
}

/// The integrals of [`CellIntegrals`] on the cell mapped by `map`, by quadrature.
fn quadrature_integrals(order: usize, map: &AffineMap) -> CellIntegrals {
    let (nb, nl) = (lagrange::n_basis(order), n_lower(order));
    let rule = triangle_cached(2 * order);
    let (mut phi, mut grad, mut psi) = ([0.0; 6], [[0.0; 2]; 6], [0.0; 3]);
    let mut out = CellIntegrals {
        mass: vec![0.0; nb * nb],
        orthonormal: Vec::new(),
        divergence: vec![0.0; nl * nb * 2],
        lower_mass: vec![0.0; nl * nb],
        lower_gram: vec![0.0; nl * nl],
    };
    for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
        let w = w * map.det.abs();
        lagrange::values(order, xi, &mut phi[..nb]);
        lagrange::gradients(order, xi, &mut grad[..nb]);
        lower_values(order, xi, &mut psi[..nl]);
        for k in 0..nb {
            let g = map.physical_gradient(grad[k]);
            for l in 0..nb {
                out.mass[k * nb + l] += phi[k] * phi[l] * w;
            }
            for (m, &psi_m) in psi[..nl].iter().enumerate() {
                out.divergence[(m * nb + k) * 2] += g[0] * psi_m * w;
                out.divergence[(m * nb + k) * 2 + 1] += g[1] * psi_m * w;
                out.lower_mass[m * nb + k] += phi[k] * psi_m * w;
            }
        }
        for m in 0..nl {
            for l in 0..nl {
                out.lower_gram[m * nl + l] += psi[m] * psi[l] * w;
            }
        }
    }
    let factor = nalgebra::DMatrix::from_row_slice(nb, nb, &out.mass).cholesky().expect("the mass matrix is definite");
    let inverse = factor.l().solve_lower_triangular(&nalgebra::DMatrix::identity(nb, nb)).expect("L is invertible");
    out.orthonormal = inverse.transpose().as_slice().to_vec(); // column-major storage of the transpose = row-major
    out
}

/// ∫_F φ_k q_m over the edge from reference point `a` to `b` of a cell, with q_m the
/// Lagrange P_p basis of the edge (ends, then midpoint), at `[m · n_basis + k]`.
pub fn face_moments(order: usize, a: Point, b: Point, length: f64) -> Vec<f64> {
    let nb = lagrange::n_basis(order);
    let rule = gauss_segment_cached(order + 2);
    let (mut phi, mut q) = ([0.0; 6], [0.0; 3]);
    let mut out = vec![0.0; (order + 1) * nb];
    for (&s, &w) in rule.points.iter().zip(&rule.weights) {
        let xi = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
        lagrange::values(order, xi, &mut phi[..nb]);
        lagrange::segment_values(order, s, &mut q);
        for m in 0..=order {
            for k in 0..nb {
                out[m * nb + k] += phi[k] * q[m] * w * length;
            }
        }
    }
    out
}

/// [`face_moments`] per unit length over the edge from reference vertex `a` to reference
/// vertex `b` (local indices 0, 1, 2), computed once per degree: the moments over an edge of
/// length |F| are |F| times these.
pub fn edge_moments(order: usize, a: usize, b: usize) -> &'static [f64] {
    static CACHE: [OnceLock<Vec<Vec<f64>>>; 3] = [const { OnceLock::new() }; 3];
    let edges = CACHE[order].get_or_init(|| {
        let vertices = lagrange::reference_nodes(1);
        (0..9).map(|e| face_moments(order, vertices[e / 3], vertices[e % 3], 1.0)).collect()
    });
    &edges[a * 3 + b]
}

/// The stress with coefficients `s` (layout of the module doc) at reference point ξ, as
/// [τ_xx, τ_xy, τ_yx, τ_yy].
pub fn evaluate(order: usize, s: &[f64], xi: Point) -> [f64; 4] {
    let nb = lagrange::n_basis(order);
    let mut phi = [0.0; 6];
    lagrange::values(order, xi, &mut phi[..nb]);
    let mut tau = [0.0; 4];
    for (c, t) in tau.iter_mut().enumerate() {
        *t = (0..nb).map(|k| s[c * nb + k] * phi[k]).sum();
    }
    tau
}

/// Row-wise divergence ∇·τ at reference point ξ of the cell mapped by `map`.
pub fn divergence(order: usize, map: &AffineMap, s: &[f64], xi: Point) -> Vector {
    let nb = lagrange::n_basis(order);
    let mut grad = [[0.0; 2]; 6];
    lagrange::gradients(order, xi, &mut grad[..nb]);
    let mut div = [0.0; 2];
    for k in 0..nb {
        let g = map.physical_gradient(grad[k]);
        for (i, d) in div.iter_mut().enumerate() {
            *d += s[(2 * i) * nb + k] * g[0] + s[(2 * i + 1) * nb + k] * g[1]; // ∂_x τ_ix + ∂_y τ_iy
        }
    }
    div
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A distorted triangle for the property tests.
    fn map() -> AffineMap {
        AffineMap::new([[0.1, 0.2], [1.3, 0.4], [0.35, 1.1]])
    }

    #[test]
    fn divergence_integrals_match_pointwise_divergence() {
        // ∫ (∇·τ)_i ψ_m computed from the divergence table and by quadrature agree
        for order in [1, 2] {
            let map = map();
            let nb = lagrange::n_basis(order);
            let s: Vec<f64> = (0..4 * nb).map(|k| ((k * 7 + 3) % 11) as f64 - 5.0).collect();
            let ints = cell_integrals(order, &map);
            let rule = triangle_cached(2 * order);
            for m in 0..n_lower(order) {
                for i in 0..2 {
                    let table: f64 = (0..nb)
                        .map(|k| {
                            s[(2 * i) * nb + k] * ints.divergence[(m * nb + k) * 2]
                                + s[(2 * i + 1) * nb + k] * ints.divergence[(m * nb + k) * 2 + 1]
                        })
                        .sum();
                    let mut psi = [0.0; 3];
                    let direct: f64 = rule
                        .points
                        .iter()
                        .zip(&rule.weights)
                        .map(|(&xi, &w)| {
                            lower_values(order, xi, &mut psi);
                            divergence(order, &map, &s, xi)[i] * psi[m] * w * map.det.abs()
                        })
                        .sum();
                    assert!((table - direct).abs() < 1e-12 * (1.0 + direct.abs()), "p = {order}: {table} vs {direct}");
                }
            }
        }
    }

    #[test]
    fn divergence_maps_onto_lower_degree() {
        // ∇·: P_p(T)^{2×2} → P_{p−1}(T)² is onto: the divergence table has full row rank 2 n_lower
        for order in [1, 2] {
            let (nb, nl) = (lagrange::n_basis(order), n_lower(order));
            let ints = cell_integrals(order, &map());
            let rows = nalgebra::DMatrix::from_fn(2 * nl, 4 * nb, |r, col| {
                let (m, i) = (r / 2, r % 2);
                let (c, k) = (col / nb, col % nb);
                if c / 2 == i {
                    ints.divergence[(m * nb + k) * 2 + c % 2]
                } else {
                    0.0
                }
            });
            assert_eq!(rows.rank(1e-10), 2 * nl);
        }
    }

    #[test]
    fn orthonormal_basis_is_orthonormal() {
        // C M Cᵀ = I for the lower-triangular C
        for order in [1, 2] {
            let nb = lagrange::n_basis(order);
            let ints = cell_integrals(order, &map());
            let c = nalgebra::DMatrix::from_row_slice(nb, nb, &ints.orthonormal);
            let m = nalgebra::DMatrix::from_row_slice(nb, nb, &ints.mass);
            assert!((0..nb).all(|k| (k + 1..nb).all(|l| c[(k, l)] == 0.0)), "C is lower triangular");
            let product = &c * m * c.transpose();
            assert!((product - nalgebra::DMatrix::identity(nb, nb)).amax() < 1e-12, "p = {order}");
        }
    }

    /// Source: `cell_integrals` (affine images of the reference integrals). Goal: they agree
    /// with quadrature on the cell itself to round-off. Parameters: the distorted triangle of
    /// `map`, and the same triangle mirrored (det J < 0), p = 1, 2.
    #[test]
    fn mapped_integrals_match_quadrature_on_the_cell() {
        let mirrored = AffineMap::new([[0.1, 0.2], [0.35, 1.1], [1.3, 0.4]]);
        for map in [map(), mirrored] {
            for order in [1, 2] {
                let (mapped, direct) = (cell_integrals(order, &map), quadrature_integrals(order, &map));
                let pairs = [
                    (&mapped.mass, &direct.mass),
                    (&mapped.orthonormal, &direct.orthonormal),
                    (&mapped.divergence, &direct.divergence),
                    (&mapped.lower_mass, &direct.lower_mass),
                    (&mapped.lower_gram, &direct.lower_gram),
                ];
                for (a, b) in pairs {
                    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                    let worst = a.iter().zip(b.iter()).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
                    assert!(worst <= 1e-14 * scale, "p = {order}: {worst:e} of {scale:e}");
                }
            }
        }
    }

    /// Source: `edge_moments` (reference edge moments per unit length). Goal: times the
    /// length, they agree with `face_moments` on every oriented edge to round-off. Parameters:
    /// p = 1, 2, length 0.37.
    #[test]
    fn edge_moments_match_face_moments() {
        let vertices = lagrange::reference_nodes(1);
        for order in [1, 2] {
            for (a, b) in [(0, 1), (1, 0), (1, 2), (2, 1), (2, 0), (0, 2)] {
                let direct = face_moments(order, vertices[a], vertices[b], 0.37);
                let worst = edge_moments(order, a, b)
                    .iter()
                    .zip(&direct)
                    .fold(0.0_f64, |m, (x, y)| m.max((x * 0.37 - y).abs()));
                assert!(worst <= 1e-15, "p = {order}, edge {a}{b}: {worst:e}");
            }
        }
    }

    #[test]
    fn face_moments_are_local_to_the_face() {
        // moments on edge 12 vanish for the basis function of the opposite vertex 0
        for order in [1, 2] {
            let nb = lagrange::n_basis(order);
            let mom = face_moments(order, [1.0, 0.0], [0.0, 1.0], 2f64.sqrt());
            for m in 0..=order {
                assert!(mom[m * nb].abs() < 1e-15);
            }
            let total: f64 = mom.iter().sum();
            assert!((total - 2f64.sqrt()).abs() < 1e-13, "Σ φ_k = Σ q_m = 1 on the face");
        }
    }
}
