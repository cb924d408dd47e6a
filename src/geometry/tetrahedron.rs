//! The solid's geometry: points of space, the reference tetrahedron's vertex, edge and face
//! tables, and the affine map of a tetrahedron.
//!
//! Reference tetrahedron: vertices (0,0,0), (1,0,0), (0,1,0), (0,0,1). Its edges in gmsh's
//! order, where a 10-node tetrahedron puts its midpoint nodes (node 4 + i on edge i):
//! 01, 12, 20, 30, 32, 31. Face i is opposite vertex i, its vertices ordered so that their
//! normal (b − a) × (c − a) points out of a positively oriented cell.
//!
//! Map: x = v0 + J ξ with the columns of J equal to v1 − v0, v2 − v0, v3 − v0; ∇φ = J⁻ᵀ ∇̂φ̂
//! and dx = |det J| dξ.

/// A point of space \[m\]; z is the vertical axis.
pub type Point3 = [f64; 3];

/// A vector of space.
pub type Vector3 = [f64; 3];

/// The local vertices of each edge in gmsh's order.
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [3, 0], [3, 2], [3, 1]];

/// The local vertices of face i (opposite vertex i), counter-clockwise seen from outside.
pub const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

/// a × b.
pub fn cross(a: Vector3, b: Vector3) -> Vector3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// |v|.
pub fn norm3(v: Vector3) -> f64 {
    super::dot(v, v).sqrt()
}

/// |b − a|.
pub fn distance3(a: Point3, b: Point3) -> f64 {
    norm3(super::sub(b, a))
}

/// The vector area ½ (b − a) × (c − a) of the triangle a, b, c: its normal times its area.
pub fn triangle_area_vector([a, b, c]: [Point3; 3]) -> Vector3 {
    cross(super::sub(b, a), super::sub(c, a)).map(|x| 0.5 * x)
}

/// Affine map of the reference tetrahedron onto a physical one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TetMap {
    /// Image of the reference origin (vertex 0).
    pub origin: Point3,
    /// `J[r][c] = ∂x_r / ∂ξ_c`.
    pub jacobian: [[f64; 3]; 3],
    /// `det J` (positive for a positively oriented cell).
    pub det: f64,
    /// `J⁻ᵀ`.
    pub inv_t: [[f64; 3]; 3],
}

impl TetMap {
    /// Map sending the reference vertices to `v`. Panics on a flat tetrahedron.
    pub fn new(v: [Point3; 4]) -> Self {
        let e: [Vector3; 3] = std::array::from_fn(|k| super::sub(v[k + 1], v[0]));
        let jacobian = std::array::from_fn(|r| std::array::from_fn(|c| e[c][r]));
        // the rows of J⁻¹ are the cofactor vectors e_j × e_k over det: J⁻ᵀ has them as columns
        let cof = [cross(e[1], e[2]), cross(e[2], e[0]), cross(e[0], e[1])];
        let det = super::dot(e[0], cof[0]);
        assert!(det != 0.0, "flat tetrahedron {v:?}");
        let inv_t = std::array::from_fn(|r| std::array::from_fn(|c| cof[c][r] / det));
        TetMap { origin: v[0], jacobian, det, inv_t }
    }

    /// `x = origin + J ξ`.
    pub fn to_physical(&self, xi: Point3) -> Point3 {
        std::array::from_fn(|r| self.origin[r] + super::dot(self.jacobian[r], xi))
    }

    /// `∇φ = J⁻ᵀ ∇̂φ̂`.
    pub fn physical_gradient(&self, ref_grad: Vector3) -> Vector3 {
        std::array::from_fn(|r| super::dot(self.inv_t[r], ref_grad))
    }

    /// Volume `|det J| / 6`.
    pub fn volume(&self) -> f64 {
        self.det.abs() / 6.0
    }
}

/// The signed volume det[v1 − v0, v2 − v0, v3 − v0] / 6 (positive for a positive cell).
pub fn signed_volume(v: [Point3; 4]) -> f64 {
    let e: [Vector3; 3] = std::array::from_fn(|k| super::sub(v[k + 1], v[0]));
    super::dot(e[0], cross(e[1], e[2])) / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    const CELL: [Point3; 4] = [[0.1, 0.2, -0.3], [1.3, 0.4, 0.1], [0.35, 1.1, 0.2], [0.2, 0.3, 0.9]];

    #[test]
    fn jacobian_times_inverse_transpose_is_identity() {
        let m = TetMap::new(CELL);
        for r in 0..3 {
            for c in 0..3 {
                let s: f64 = (0..3).map(|k| m.inv_t[k][r] * m.jacobian[k][c]).sum();
                assert!((s - if r == c { 1.0 } else { 0.0 }).abs() < 1e-14, "{r} {c}: {s}");
            }
        }
        assert!((m.volume() - signed_volume(CELL)).abs() < 1e-15 && m.det > 0.0);
        for (k, v) in CELL.iter().enumerate().skip(1) {
            let mut xi = [0.0; 3];
            xi[k - 1] = 1.0;
            assert!(distance3(m.to_physical(xi), *v) < 1e-15);
        }
    }

    #[test]
    fn every_face_points_out_of_its_cell_and_every_edge_is_listed_once() {
        let centroid: Point3 = std::array::from_fn(|r| CELL.iter().map(|v| v[r]).sum::<f64>() / 4.0);
        for (i, face) in FACES.iter().enumerate() {
            assert!(!face.contains(&i));
            let n = triangle_area_vector(face.map(|k| CELL[k]));
            assert!(super::super::dot(n, super::super::sub(CELL[face[0]], centroid)) > 0.0, "face {i}");
        }
        let mut pairs: Vec<[usize; 2]> = EDGES.iter().map(|&[a, b]| [a.min(b), a.max(b)]).collect();
        pairs.sort_unstable();
        pairs.dedup();
        assert_eq!(pairs.len(), 6);
        // the sum of a closed surface's vector areas vanishes
        let total = FACES
            .iter()
            .map(|f| triangle_area_vector(f.map(|k| CELL[k])))
            .fold([0.0; 3], |s, a| [s[0] + a[0], s[1] + a[1], s[2] + a[2]]);
        assert!(norm3(total) < 1e-15);
    }
}
