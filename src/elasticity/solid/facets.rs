//! Loads on the boundary triangles of a solid: their outward normals, and ∫_F g · φ_i with
//! the kink of a water pressure (the plane z = H_w) cut out of the triangle, so that the rule
//! integrates a piecewise polynomial exactly.
//!
//! A boundary triangle F with vertices a, b, c is x(ξ, η) = a + ξ (b − a) + η (c − a) on the
//! reference triangle, dS = 2 |A_F| dξ dη with A_F = ½ (b − a) × (c − a); its nodes are
//! ordered as those of a plane cell, so the plane Lagrange basis serves.

use crate::fem::{lagrange, quadrature};
use crate::geometry::tetrahedron::{norm3, triangle_area_vector, FACES};
use crate::geometry::{dot, sub, Point, Point3, Vector3};
use crate::mesh::Mesh;
use std::collections::HashMap;

/// The outward unit normal of every boundary facet: its area vector, turned away from the
/// fourth vertex of the cell it bounds. Err(f): facet f bounds no cell.
pub fn outward_normals(mesh: &Mesh<3>) -> Result<Vec<Vector3>, usize> {
    let key = |nodes: [usize; 3]| {
        let mut k = nodes;
        k.sort_unstable();
        k
    };
    let mut opposite: HashMap<[usize; 3], Point3> =
        (0..mesh.n_facets()).map(|f| (key(std::array::from_fn(|k| mesh.facet(f)[k])), [f64::NAN; 3])).collect();
    for c in 0..mesh.n_cells() {
        let cell = mesh.cell(c);
        for (i, face) in FACES.iter().enumerate() {
            if let Some(point) = opposite.get_mut(&key(face.map(|k| cell[k]))) {
                *point = mesh.points[cell[i]];
            }
        }
    }
    (0..mesh.n_facets())
        .map(|f| {
            let inside = opposite[&key(std::array::from_fn(|k| mesh.facet(f)[k]))];
            let v = mesh.facet_vertices(f);
            let area = triangle_area_vector(v);
            let n = area.map(|x| x / norm3(area));
            match dot(n, sub(v[0], inside)) {
                s if s > 0.0 => Ok(n),
                s if s < 0.0 => Ok(n.map(|x| -x)),
                _ => Err(f),
            }
        })
        .collect()
}

/// The parts of the reference triangle where the affine function with vertex values `depth`
/// is ≥ 0, as triangles (none, one or two).
pub fn wet_parts(depth: [f64; 3]) -> Vec<[Point; 3]> {
    let corners: [Point; 3] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
    let mut polygon = Vec::with_capacity(4);
    for k in 0..3 {
        let j = (k + 1) % 3;
        let (p, q, dp, dq) = (corners[k], corners[j], depth[k], depth[j]);
        if dp >= 0.0 {
            polygon.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let t = dp / (dp - dq);
            polygon.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    (1..polygon.len().saturating_sub(1)).map(|k| [polygon[0], polygon[k], polygon[k + 1]]).collect()
}

/// F_{3i+a} += ∫ g_a φ_i over the `parts` (triangles of the reference triangle) of the
/// boundary triangle with vertices `v`, with the rule exact to `degree` on each part; `phi`
/// is scratch of length n_basis.
pub fn traction_load(
    v: [Point3; 3],
    order: usize,
    parts: &[[Point; 3]],
    degree: usize,
    g: impl Fn(Point3) -> Vector3,
    phi: &mut [f64],
    out: &mut [f64],
) {
    let rule = quadrature::triangle_cached(degree);
    let jacobian = 2.0 * norm3(triangle_area_vector(v));
    let (e1, e2) = (sub(v[1], v[0]), sub(v[2], v[0]));
    for &[p0, p1, p2] in parts {
        let (d1, d2) = (sub(p1, p0), sub(p2, p0));
        let part = (d1[0] * d2[1] - d1[1] * d2[0]).abs();
        for (xi, &w) in rule.points.iter().zip(&rule.weights) {
            let r = [p0[0] + xi[0] * d1[0] + xi[1] * d2[0], p0[1] + xi[0] * d1[1] + xi[1] * d2[1]];
            let x = std::array::from_fn(|k| v[0][k] + r[0] * e1[k] + r[1] * e2[k]);
            let gx = g(x);
            lagrange::values(order, r, phi);
            for (i, &p) in phi.iter().enumerate() {
                for a in 0..3 {
                    out[3 * i + a] += gx[a] * p * w * part * jacobian;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Source: the area of the part of the reference triangle (area ½) below a line. Goal: the
    /// wet parts cover exactly the region where the depth is ≥ 0. Parameters: depths that cut
    /// off one corner, two corners, none and all.
    #[test]
    fn the_wet_parts_are_the_region_under_water() {
        let area = |parts: &[[Point; 3]]| {
            parts
                .iter()
                .map(|[a, b, c]| 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs())
                .sum::<f64>()
        };
        assert_eq!(area(&wet_parts([1.0, 2.0, 3.0])), 0.5);
        assert!(wet_parts([-1.0, -2.0, -3.0]).is_empty());
        // depth 1 − 2ξ − 2η ≥ 0: the corner triangle of legs ½, area ⅛
        assert!((area(&wet_parts([1.0, -1.0, -1.0])) - 0.125).abs() < 1e-15);
        // its complement
        assert!((area(&wet_parts([-1.0, 1.0, 1.0])) - 0.375).abs() < 1e-15);
    }
}
