//! Rigid motions of the plane, r(x) = (a_x − b p_y, a_y + b p_x) with p = (x − x₀)/L, and of
//! space, r(x) = a + ω × p, and the constraints r ↦ r(x)·d that hold them (fixed
//! displacement components, normal supports).

use crate::geometry::tetrahedron::cross;
use crate::geometry::{Point, Point3, Vector};
use nalgebra::{Matrix3, Matrix6, Vector3, Vector6};

/// The rigid motions (a_x, a_y, b) that the functionals r ↦ r(x)·d of `constraints`
/// (point x, direction d) leave free, the least constrained first: the eigenvectors of the
/// Gram matrix Σ v vᵀ, v = (d_x, d_y, −p_y d_x + p_x d_y), whose eigenvalues are round-off,
/// ≤ 10⁻¹⁰ (1 + the largest). Points are scaled by the `origin` x₀ and `size` L, so b is a
/// rotation per unit of L.
pub fn free_motions(constraints: impl IntoIterator<Item = (Point, Vector)>, origin: Point, size: f64) -> Vec<[f64; 3]> {
    let mut gram = Matrix3::<f64>::zeros();
    for (x, d) in constraints {
        let (px, py) = ((x[0] - origin[0]) / size, (x[1] - origin[1]) / size);
        let v = Vector3::new(d[0], d[1], -py * d[0] + px * d[1]);
        gram += v * v.transpose();
    }
    let eigen = gram.symmetric_eigen();
    let tolerance = 1e-10 * (1.0 + eigen.eigenvalues.amax());
    let mut free: Vec<usize> = (0..3).filter(|&j| eigen.eigenvalues[j] <= tolerance).collect();
    free.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    free.into_iter()
        .map(|j| {
            let v = eigen.eigenvectors.column(j);
            [v[0], v[1], v[2]]
        })
        .collect()
}

/// The rigid motions (a, ω) of space that the functionals r ↦ r(x)·d = a·d + ω·(p × d) of
/// `constraints` leave free, the least constrained first, as [`free_motions`] finds them in
/// the plane.
pub fn free_motions_3d(
    constraints: impl IntoIterator<Item = (Point3, Point3)>,
    origin: Point3,
    size: f64,
) -> Vec<[f64; 6]> {
    let mut gram = Matrix6::<f64>::zeros();
    for (x, d) in constraints {
        let p = std::array::from_fn(|r| (x[r] - origin[r]) / size);
        let m = cross(p, d);
        let v = Vector6::new(d[0], d[1], d[2], m[0], m[1], m[2]);
        gram += v * v.transpose();
    }
    let eigen = gram.symmetric_eigen();
    let tolerance = 1e-10 * (1.0 + eigen.eigenvalues.amax());
    let mut free: Vec<usize> = (0..6).filter(|&j| eigen.eigenvalues[j] <= tolerance).collect();
    free.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    free.into_iter().map(|j| std::array::from_fn(|k| eigen.eigenvectors.column(j)[k])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn supports_leave_free_what_they_do_not_hold() {
        let (origin, size) = ([0.0, 0.0], 1.0);
        // one vertical support: both a translation along x and the rotation stay free
        assert_eq!(free_motions([([0.0, 0.0], [0.0, 1.0])], origin, size).len(), 2);
        // a base on rollers (two vertical supports): the translation along x only
        let rollers = [([-1.0, 0.0], [0.0, 1.0]), ([1.0, 0.0], [0.0, 1.0])];
        let free = free_motions(rollers, origin, size);
        assert_eq!(free.len(), 1);
        assert!((free[0][0].abs() - 1.0).abs() < 1e-12 && free[0][1].abs() < 1e-12 && free[0][2].abs() < 1e-12);
        // and a horizontal support besides: nothing
        let held = rollers.into_iter().chain([([0.0, 1.0], [1.0, 0.0])]);
        assert!(free_motions(held, origin, size).is_empty());
    }

    #[test]
    fn rollers_of_a_solid_leave_free_what_they_do_not_hold() {
        let z = [0.0, 0.0, 1.0];
        // three vertical rollers under a block: the translations along x and y and the
        // rotation about z stay free
        let base = [([0.0, 0.0, 0.0], z), ([1.0, 0.0, 0.0], z), ([0.0, 1.0, 0.0], z)];
        let free = free_motions_3d(base, [0.0; 3], 1.0);
        assert_eq!(free.len(), 3);
        assert!(free.iter().all(|v| v[2].abs() < 1e-12 && v[3].abs() < 1e-12 && v[4].abs() < 1e-12));
        // with rollers along x at two points of the face y = 0 and along y at one point:
        // nothing
        let x = [1.0, 0.0, 0.0];
        let sides = [([0.0, 0.0, 0.5], x), ([0.0, 1.0, 0.5], x), ([0.5, 0.0, 0.5], [0.0, 1.0, 0.0])];
        assert!(free_motions_3d(base.into_iter().chain(sides), [0.0; 3], 1.0).is_empty());
    }
}
