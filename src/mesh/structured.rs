//! Structured triangle meshes of a rectangle, for unit tests that need no gmsh.
//!
//! The rectangle [x0, x1] × [y0, y1] is cut into nx × ny squares, each split along its
//! diagonal from lower-left to upper-right. Physical groups: surface `domain` (tag 1) and
//! curves `bottom` (1), `right` (2), `top` (3), `left` (4).

use super::{Mesh, PhysicalGroup};
use crate::geometry::Point;
use std::collections::HashMap;

/// Physical curve tags of the four sides.
pub const BOTTOM: i32 = 1;
pub const RIGHT: i32 = 2;
pub const TOP: i32 = 3;
pub const LEFT: i32 = 4;

/// Structured mesh of [x0, x1] × [y0, y1] with nx × ny squares and elements of degree `order`.
pub fn rectangle(x0: f64, x1: f64, y0: f64, y1: f64, nx: usize, ny: usize, order: usize) -> Mesh {
    assert!(order == 1 || order == 2, "order must be 1 or 2");
    let vertex = |i: usize, j: usize| j * (nx + 1) + i;
    let mut points: Vec<Point> = (0..=ny)
        .flat_map(|j| {
            (0..=nx).map(move |i| {
                let s = i as f64 / nx as f64;
                let t = j as f64 / ny as f64;
                [x0 + s * (x1 - x0), y0 + t * (y1 - y0)]
            })
        })
        .collect();
    let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
    let mut midpoint = |a: usize, b: usize, points: &mut Vec<Point>| {
        let key = (a.min(b), a.max(b));
        *midpoints.entry(key).or_insert_with(|| {
            let (pa, pb) = (points[a], points[b]);
            points.push([0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]);
            points.len() - 1
        })
    };
    let mut cell_nodes = Vec::new();
    let mut triangle = |a: usize, b: usize, c: usize, points: &mut Vec<Point>| {
        cell_nodes.extend([a, b, c]);
        if order == 2 {
            let m = [midpoint(a, b, points), midpoint(b, c, points), midpoint(c, a, points)];
            cell_nodes.extend(m);
        }
    };
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            triangle(a, b, c, &mut points);
            triangle(a, c, d, &mut points);
        }
    }
    let mut facet_nodes = Vec::new();
    let mut facet_tags = Vec::new();
    let sides: [(i32, Vec<(usize, usize)>); 4] = [
        (BOTTOM, (0..nx).map(|i| (vertex(i, 0), vertex(i + 1, 0))).collect()),
        (RIGHT, (0..ny).map(|j| (vertex(nx, j), vertex(nx, j + 1))).collect()),
        (TOP, (0..nx).rev().map(|i| (vertex(i + 1, ny), vertex(i, ny))).collect()),
        (LEFT, (0..ny).rev().map(|j| (vertex(0, j + 1), vertex(0, j))).collect()),
    ];
    for (tag, segments) in sides {
        for (a, b) in segments {
            facet_nodes.extend([a, b]);
            if order == 2 {
                facet_nodes.push(midpoint(a, b, &mut points));
            }
            facet_tags.push(tag);
        }
    }
    let groups = [(2, 1, "domain"), (1, BOTTOM, "bottom"), (1, RIGHT, "right"), (1, TOP, "top"), (1, LEFT, "left")]
        .into_iter()
        .map(|(dim, tag, name)| PhysicalGroup { dim, tag, name: name.to_string() })
        .collect();
    let n_cells = 2 * nx * ny;
    Mesh { points, order, cell_nodes, cell_tags: vec![1; n_cells], facet_nodes, facet_tags, groups }
}

/// Unit square (0, 1)² with n × n squares.
pub fn unit_square(n: usize, order: usize) -> Mesh {
    rectangle(0.0, 1.0, 0.0, 1.0, n, n, order)
}

/// Physical tags of [`two_blocks`]: the surfaces, and the two sides of the joint between them.
pub const LOWER: i32 = 1;
pub const UPPER: i32 = 2;
pub const JOINT: i32 = 5;
pub const JOINT_LOWER: i32 = 6;

/// Two blocks with their own nodes, stacked along y = `y_joint`: the lower one (surface
/// [`LOWER`]) is [0, 1] × [0, y_joint] with `nx_lower` × `ny` squares, the upper one ([`UPPER`])
/// [0, 1] × [y_joint, 1] with `nx_upper` × `ny`. The joint's sides are curves [`JOINT`] (the
/// upper block's bottom) and [`JOINT_LOWER`] (the lower block's top); the outer sides keep
/// [`BOTTOM`], [`RIGHT`], [`TOP`] and [`LEFT`]. `nx_lower ≠ nx_upper` gives non-matching sides.
pub fn two_blocks(nx_lower: usize, nx_upper: usize, ny: usize, y_joint: f64, order: usize) -> Mesh {
    let mut lower = rectangle(0.0, 1.0, 0.0, y_joint, nx_lower, ny, order);
    let upper = rectangle(0.0, 1.0, y_joint, 1.0, nx_upper, ny, order);
    lower.cell_tags.fill(LOWER);
    for tag in lower.facet_tags.iter_mut().filter(|t| **t == TOP) {
        *tag = JOINT_LOWER;
    }
    let offset = lower.n_points();
    lower.points.extend(&upper.points);
    lower.cell_nodes.extend(upper.cell_nodes.iter().map(|n| n + offset));
    lower.cell_tags.extend(std::iter::repeat_n(UPPER, upper.n_cells()));
    lower.facet_nodes.extend(upper.facet_nodes.iter().map(|n| n + offset));
    lower.facet_tags.extend(upper.facet_tags.iter().map(|&t| if t == BOTTOM { JOINT } else { t }));
    lower.groups = [(2, LOWER, "lower"), (2, UPPER, "upper"), (1, JOINT, "joint"), (1, JOINT_LOWER, "joint:lower")]
        .into_iter()
        .map(|(dim, tag, name)| PhysicalGroup { dim, tag, name: name.to_string() })
        .chain(upper.groups.into_iter().filter(|g| g.dim == 1))
        .collect();
    lower
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_area() {
        for order in [1, 2] {
            let m = rectangle(0.0, 2.0, 0.0, 1.0, 4, 3, order);
            assert_eq!(m.n_cells(), 24);
            assert_eq!(m.n_facets(), 14);
            let nv = 5 * 4;
            let ne = 4 * 4 + 5 * 3 + 12; // horizontal + vertical + diagonal edges
            assert_eq!(m.n_points(), if order == 1 { nv } else { nv + ne });
            let area: f64 = (0..m.n_cells()).map(|c| m.cell_area(c)).sum();
            assert!((area - 2.0).abs() < 1e-14);
            assert!((m.boundary_length(BOTTOM) - 2.0).abs() < 1e-14);
            assert!((m.boundary_length(LEFT) - 1.0).abs() < 1e-14);
        }
    }
}
