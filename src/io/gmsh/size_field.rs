//! [`SizeField`]: target mesh sizes that drive gmsh's mesher through a background field.

use super::{GmshError, MeshOptions, TRIANGLE_AREA};
use crate::geometry::Point;
use crate::mesh::Mesh;

/// Target mesh sizes as a piecewise-linear field on the triangles of a previous mesh
/// (continuous where triangles share points; [`SizeField::from_cells`] shares none).
#[derive(Debug, Clone, PartialEq)]
pub struct SizeField {
    /// Vertex coordinates.
    pub points: Vec<Point>,
    /// Point indices of each triangle.
    pub triangles: Vec<[usize; 3]>,
    /// Target size h(xᵢ) at each point; h is linear on each triangle.
    pub sizes: Vec<f64>,
}

impl SizeField {
    /// From per-cell target sizes h_T on `mesh` (P1 or P2; only the 3 vertices of each cell
    /// are used): h is constant on each cell, every triangle having its own three points, so
    /// that each cell asks for its own target exactly (a vertex value shared by the cells
    /// around it, e.g. their minimum, would bias the sizes). Fails unless there is one
    /// positive finite h_T per cell.
    pub fn from_cells(mesh: &Mesh, cell_sizes: &[f64]) -> Result<SizeField, GmshError> {
        if cell_sizes.len() != mesh.n_cells() {
            return Err(bad(format!("{} sizes for {} cells", cell_sizes.len(), mesh.n_cells())));
        }
        if let Some((c, h)) = cell_sizes.iter().enumerate().find(|&(_, &h)| !positive(h)) {
            return Err(bad(format!("cell {c} has size {h}, expected a positive finite number")));
        }
        let n = mesh.n_cells();
        let mut field = SizeField {
            points: Vec::with_capacity(3 * n),
            triangles: Vec::with_capacity(n),
            sizes: Vec::with_capacity(3 * n),
        };
        for (c, &h) in cell_sizes.iter().enumerate() {
            let first = field.points.len();
            field.points.extend(mesh.cell_vertices(c));
            field.sizes.extend([h; 3]);
            field.triangles.push([first, first + 1, first + 2]);
        }
        Ok(field)
    }

    /// The triangles of the cells `keep` of a field made by [`SizeField::from_cells`].
    pub fn of_cells(&self, keep: impl Fn(usize) -> bool) -> SizeField {
        let kept: Vec<usize> = (0..self.triangles.len()).filter(|&c| keep(c)).collect();
        SizeField {
            points: kept.iter().flat_map(|&c| self.triangles[c].map(|i| self.points[i])).collect(),
            triangles: (0..kept.len()).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]).collect(),
            sizes: kept.iter().flat_map(|&c| self.triangles[c].map(|i| self.sizes[i])).collect(),
        }
    }

    /// Checks that there are triangles, one size per point, finite coordinates, positive finite
    /// sizes and triangles that refer to existing points.
    pub(super) fn validate(&self) -> Result<(), GmshError> {
        let n = self.points.len();
        if self.sizes.len() != n {
            return Err(bad(format!("{} sizes for {n} points", self.sizes.len())));
        }
        if self.triangles.is_empty() {
            return Err(bad("it has no triangles".into()));
        }
        if let Some((t, i)) =
            self.triangles.iter().enumerate().find_map(|(t, v)| v.iter().find(|&&i| i >= n).map(|i| (t, i)))
        {
            return Err(bad(format!("triangle {t} refers to point {i}, but there are {n} points")));
        }
        for (i, (&[x, y], &h)) in self.points.iter().zip(&self.sizes).enumerate() {
            if !(x.is_finite() && y.is_finite() && positive(h)) {
                let expected = "expected finite coordinates and a positive finite size";
                return Err(bad(format!("point {i} at ({x}, {y}) has size {h}, {expected}")));
            }
        }
        Ok(())
    }

    /// Estimated number of triangles gmsh makes from this field under `options` (a remesh: the
    /// size factor, and the bounds where given): Σ_T |T| / (√3/4 h²), 1/h² averaged over the
    /// corners of T.
    pub fn cells(&self, options: &MeshOptions) -> f64 {
        let (min, max) = (options.size_min.unwrap_or(0.0), options.size_max.unwrap_or(f64::INFINITY));
        self.cells_within(min, max, options.size_factor)
    }

    /// [`SizeField::cells`] with gmsh's sizes: factor × h bounded to [`min`, `max`].
    pub(super) fn cells_within(&self, min: f64, max: f64, factor: f64) -> f64 {
        let density = |i: usize| (factor * self.sizes[i].clamp(min, max.max(min))).powi(-2);
        let cell = |&[a, b, c]: &[usize; 3]| {
            let ([xa, ya], [xb, yb], [xc, yc]) = (self.points[a], self.points[b], self.points[c]);
            let area = 0.5 * ((xb - xa) * (yc - ya) - (xc - xa) * (yb - ya)).abs();
            area * (density(a) + density(b) + density(c)) / 3.0
        };
        self.triangles.iter().map(cell).sum::<f64>() / TRIANGLE_AREA
    }

    /// Largest target size, maxᵢ h(xᵢ).
    pub(super) fn max_size(&self) -> f64 {
        self.sizes.iter().copied().fold(0.0, f64::max)
    }

    /// gmsh list data of scalar triangles ("ST"): x₁ x₂ x₃ y₁ y₂ y₃ z₁ z₂ z₃ h₁ h₂ h₃ per triangle, z = 0.
    pub(super) fn list_data(&self) -> Vec<f64> {
        let mut data = Vec::with_capacity(12 * self.triangles.len());
        for triangle in &self.triangles {
            data.extend(triangle.map(|i| self.points[i][0]));
            data.extend(triangle.map(|i| self.points[i][1]));
            data.extend([0.0; 3]);
            data.extend(triangle.map(|i| self.sizes[i]));
        }
        data
    }
}

fn positive(h: f64) -> bool {
    h.is_finite() && h > 0.0
}

fn bad(reason: String) -> GmshError {
    GmshError::BadSizeField { reason }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cell_count_of_a_field_is_its_integral_of_one_over_the_area_of_a_cell() {
        let mesh = crate::mesh::structured::unit_square(4, 1);
        let field = SizeField::from_cells(&mesh, &vec![0.01; mesh.n_cells()]).unwrap();
        let uniform = 1.0 / (TRIANGLE_AREA * 1e-4);
        assert!((field.cells(&MeshOptions::default()) - uniform).abs() < 1e-9 * uniform);
        // the bounds and the factor act as in gmsh: factor × h bounded to [min, max]
        let bounded = MeshOptions { size_min: Some(0.02), size_factor: 2.0, ..MeshOptions::default() };
        assert!((field.cells(&bounded) - uniform / 16.0).abs() < 1e-9 * uniform);
        let half = field.of_cells(|c| c % 2 == 0);
        assert!((half.cells(&MeshOptions::default()) - uniform / 2.0).abs() < 1e-9 * uniform);
    }
}
