//! The geometry that every layer shares: the dimension [`D`], points and vectors as
//! `[f64; D]` with their arithmetic, the affine map of a cell ([`AffineMap`]), the straight
//! facet ([`Segment`]), the frame of a facet's normal, one bounding box, second-order tensors
//! ([`Tensor`]: ε = [`sym_grad`], [`trace`], [`ddot`]) and the reference cell's vertex, edge and
//! facet tables ([`CellType`]).
//!
//! The plane domain (plane strain) has D = 2; the solid one ([`tetrahedron`]) has three
//! dimensions, with points [`Point3`], its cells tetrahedra and its facets triangles. The
//! operations that read the same in both ([`sub`], [`dot`]) take any dimension.

mod affine;
mod cell;
mod segment;
mod tensor;
pub mod tetrahedron;

pub use affine::AffineMap;
pub use cell::CellType;
pub use segment::Segment;
pub use tensor::{ddot, sym_grad, trace, Tensor};
pub use tetrahedron::{distance3, norm3, Point3, TetMap, Vector3};

/// The dimension of the domain.
pub const D: usize = 2;

/// A point of the plane \[m\].
pub type Point = [f64; D];

/// A vector of the plane.
pub type Vector = [f64; D];

/// a − b.
pub fn sub<const N: usize>(a: [f64; N], b: [f64; N]) -> [f64; N] {
    std::array::from_fn(|i| a[i] - b[i])
}

/// a · b.
pub fn dot<const N: usize>(a: [f64; N], b: [f64; N]) -> f64 {
    (1..N).fold(a[0] * b[0], |s, i| s + a[i] * b[i])
}

/// |v|, without overflow or underflow in the squares.
pub fn norm(v: Vector) -> f64 {
    v[0].hypot(v[1])
}

/// |b − a|.
pub fn distance(a: Point, b: Point) -> f64 {
    norm(sub(b, a))
}

/// The tangent τ = (−n_y, n_x) of a unit normal n: n turned counter-clockwise, so that (n, τ)
/// is a right-handed frame.
pub fn tangent(n: Vector) -> Vector {
    [-n[1], n[0]]
}

/// The smallest box \[lower, upper\] that holds `points` (\[+∞, −∞\] of none).
pub fn bounding_box(points: impl IntoIterator<Item = Point>) -> [Point; 2] {
    points.into_iter().fold([[f64::INFINITY; D], [f64::NEG_INFINITY; D]], |[lo, hi], p| {
        [[lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])]]
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_frame_of_a_normal_is_right_handed_and_orthonormal() {
        let n = [0.6, -0.8];
        let t = tangent(n);
        assert_eq!(dot(n, t), 0.0);
        assert!((norm(t) - 1.0).abs() < 1e-15);
        // n × τ = n_x τ_y − n_y τ_x = 1
        assert!((n[0] * t[1] - n[1] * t[0] - 1.0).abs() < 1e-15);
    }

    #[test]
    fn the_bounding_box_holds_its_points() {
        let [lo, hi] = bounding_box([[1.0, -2.0], [-3.0, 4.0], [0.5, 0.5]]);
        assert_eq!((lo, hi), ([-3.0, -2.0], [1.0, 4.0]));
        assert_eq!(distance([0.0, 0.0], [3.0, 4.0]), 5.0);
    }
}
