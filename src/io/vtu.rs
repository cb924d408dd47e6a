//! VTK XML unstructured grids (`.vtu`) for ParaView, written through `vtkio`.
//!
//! Files are VTK XML version 1.0 with inline base64 binary arrays (64-bit headers, no
//! compression), which VTK 9 and ParaView read. Points are stored in 3D, with z = 0 in the
//! plane. Cells are `VTK_TRIANGLE` / `VTK_QUADRATIC_TRIANGLE` in the plane, `VTK_TETRA` /
//! `VTK_QUADRATIC_TETRA` in a solid; boundary facets `VTK_LINE` / `VTK_QUADRATIC_EDGE` in the
//! plane, `VTK_TRIANGLE` / `VTK_QUADRATIC_TRIANGLE` in a solid. The node orders coincide with
//! those of [`Mesh`], but for the 10-node tetrahedron's last two edge nodes: gmsh puts edge 32
//! before edge 31, VTK edge 13 before edge 23, so nodes 8 and 9 swap.
//!
//! Every file carries field data (VTK's `FieldData`, meshio's `field_data`): an `Int32` array
//! (tag, dimension) named after each physical group of the mesh, the convention meshio uses for
//! gmsh's groups, and for every point and cell array, the tags included, a `UInt8` array named
//! `<array> [<unit>]` that holds the unit's UTF-8 bytes. Both are numeric arrays, which meshio
//! reads as VTK does (meshio refuses VTK's string arrays).
//!
//! Every field is checked before anything is written: a wrong length or a NaN/infinite value is
//! an [`OutputError`] naming the field, and no file is created. Files are written atomically.

use super::atomic::{write_output, OutputError};
use super::pvd::escape;
use crate::geometry::Vector;
use crate::mesh::Mesh;
use std::borrow::Cow;
use std::path::Path;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataArray, DataSet, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

/// A named array with `components` values per point or per cell, in `unit`.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    pub name: String,
    /// The unit of the values, e.g. "Pa", "m", "1" for a pure number.
    pub unit: &'static str,
    pub components: usize,
    /// `n × components` values, the components of each point or cell contiguous.
    pub values: Vec<f64>,
}

impl Field {
    /// One value per point or cell.
    pub fn scalar(name: impl Into<String>, unit: &'static str, values: Vec<f64>) -> Self {
        Field { name: name.into(), unit, components: 1, values }
    }

    /// A plane vector per point or cell, stored with z = 0 so ParaView can warp by it.
    pub fn vector(name: impl Into<String>, unit: &'static str, values: Vec<Vector>) -> Self {
        let values = values.iter().flat_map(|v| [v[0], v[1], 0.0]).collect();
        Field { name: name.into(), unit, components: 3, values }
    }

    /// A vector of space per point or cell.
    pub fn vector3(name: impl Into<String>, unit: &'static str, values: Vec<[f64; 3]>) -> Self {
        Field { name: name.into(), unit, components: 3, values: values.into_flattened() }
    }
}

/// Connectivity of the cells of one output file and the tag array attached to them.
struct Grid<'a> {
    nodes: Cow<'a, [usize]>,
    nodes_per_cell: usize,
    cell_type: CellType,
    tag_name: &'static str,
    tags: &'a [i32],
}

/// The VTK type of the simplices of dimension `dim` and degree `order`.
fn simplex_type(dim: usize, order: usize) -> CellType {
    match (dim, order) {
        (1, 1) => CellType::Line,
        (1, _) => CellType::QuadraticEdge,
        (2, 1) => CellType::Triangle,
        (2, _) => CellType::QuadraticTriangle,
        (_, 1) => CellType::Tetra,
        (_, _) => CellType::QuadraticTetra,
    }
}

/// The cells of `mesh` in VTK's node order.
fn vtk_cell_nodes<const D: usize>(mesh: &Mesh<D>) -> Cow<'_, [usize]> {
    if D < 3 || mesh.order == 1 {
        return Cow::Borrowed(&mesh.cell_nodes);
    }
    let nodes =
        mesh.cell_nodes.chunks_exact(10).flat_map(|c| [c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], c[9], c[8]]);
    Cow::Owned(nodes.collect())
}

/// Writes the cells of `mesh` with cell data `material` (the cell tags) and the given fields.
pub fn write_mesh_vtu<const D: usize>(
    path: &Path,
    mesh: &Mesh<D>,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), OutputError> {
    let cell_type = simplex_type(D, mesh.order);
    let grid = Grid {
        nodes: vtk_cell_nodes(mesh),
        nodes_per_cell: mesh.nodes_per_cell(),
        cell_type,
        tag_name: "material",
        tags: &mesh.cell_tags,
    };
    write_grid(path, mesh, &grid, point_data, cell_data)
}

/// Writes the boundary facets of `mesh` with cell data `physical_tag` and the given fields.
///
/// The point array is the whole mesh's, so point fields of the mesh can be reused.
pub fn write_boundary_vtu<const D: usize>(
    path: &Path,
    mesh: &Mesh<D>,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), OutputError> {
    let cell_type = simplex_type(D - 1, mesh.order);
    let grid = Grid {
        nodes: Cow::Borrowed(&mesh.facet_nodes),
        nodes_per_cell: mesh.nodes_per_facet(),
        cell_type,
        tag_name: "physical_tag",
        tags: &mesh.facet_tags,
    };
    write_grid(path, mesh, &grid, point_data, cell_data)
}

/// Validates, encodes and atomically writes one unstructured grid.
fn write_grid<const D: usize>(
    path: &Path,
    mesh: &Mesh<D>,
    grid: &Grid,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<(), OutputError> {
    check_points(path, mesh)?;
    check_grid(path, mesh, grid)?;
    check_fields(path, "point", mesh.n_points(), point_data, None)?;
    check_fields(path, "cell", grid.tags.len(), cell_data, Some(grid.tag_name))?;
    let metadata = field_data(path, mesh, grid, point_data, cell_data)?;
    let piece = piece(mesh, grid, point_data, cell_data);
    write_output(path, &with_field_data(path, encode(path, piece)?, &metadata)?)
}

/// The unit of the tag arrays `material` and `physical_tag`.
const TAG_UNIT: &str = "physical group tag";

/// The `FieldData` element of a grid: the physical groups of `mesh` and the unit of every
/// array. Err: two arrays of the same name (a group named as a unit array).
fn field_data<const D: usize>(
    path: &Path,
    mesh: &Mesh<D>,
    grid: &Grid,
    point_data: &[Field],
    cell_data: &[Field],
) -> Result<String, OutputError> {
    let groups = mesh.groups.iter().map(|g| (g.name.clone(), "Int32", format!("{} {}", g.tag, g.dim)));
    let fields = std::iter::once((grid.tag_name, TAG_UNIT))
        .chain(point_data.iter().chain(cell_data).map(|f| (f.name.as_str(), f.unit)));
    let units = fields.map(|(name, unit)| (format!("{name} [{unit}]"), "UInt8", bytes(unit)));
    let arrays: Vec<(String, &str, String)> = groups.chain(units).collect();
    let mut xml = String::from("    <FieldData>\n");
    for (k, (name, kind, values)) in arrays.iter().enumerate() {
        if arrays[..k].iter().any(|a| &a.0 == name) {
            let reason = format!("two field data arrays named `{name}` (a physical group and a unit)");
            return Err(OutputError::Invalid { path: path.to_path_buf(), reason });
        }
        let tuples = values.split(' ').count();
        xml += &format!(
            "      <DataArray type=\"{kind}\" Name=\"{}\" NumberOfTuples=\"{tuples}\" format=\"ascii\">{values}</DataArray>\n",
            escape(name)
        );
    }
    Ok(xml + "    </FieldData>\n")
}

/// The UTF-8 bytes of `text` as decimal numbers separated by spaces.
fn bytes(text: &str) -> String {
    text.bytes().map(|b| b.to_string()).collect::<Vec<_>>().join(" ")
}

/// `xml` with the `FieldData` element `metadata` as the first child of `UnstructuredGrid`.
fn with_field_data(path: &Path, xml: Vec<u8>, metadata: &str) -> Result<Vec<u8>, OutputError> {
    const GRID: &[u8] = b"<UnstructuredGrid>";
    let at = xml.windows(GRID.len()).position(|w| w == GRID).ok_or_else(|| OutputError::Encode {
        path: path.to_path_buf(),
        message: "no <UnstructuredGrid> element to hold the field data".into(),
    })? + GRID.len();
    let newline = usize::from(xml.get(at) == Some(&b'\n'));
    let (head, tail) = xml.split_at(at + newline);
    let separator = if newline == 1 { "" } else { "\n" };
    Ok([head, separator.as_bytes(), metadata.as_bytes(), tail].concat())
}

/// The points, cells, tags and fields of one grid in `vtkio`'s model.
fn piece<const D: usize>(
    mesh: &Mesh<D>,
    grid: &Grid,
    point_data: &[Field],
    cell_data: &[Field],
) -> UnstructuredGridPiece {
    let tags = DataArray::new(grid.tag_name, 1).with_data(grid.tags.to_vec());
    let cell = std::iter::once(Attribute::DataArray(tags)).chain(cell_data.iter().map(attribute)).collect();
    let points: Vec<f64> = mesh
        .points
        .iter()
        .flat_map(|p| std::array::from_fn::<f64, 3, _>(|r| p.get(r).copied().unwrap_or(0.0)))
        .collect();
    UnstructuredGridPiece {
        points: points.into(),
        cells: cells(grid),
        data: Attributes { point: point_data.iter().map(attribute).collect(), cell },
    }
}

/// The VTK XML text of a single-piece unstructured grid.
fn encode(path: &Path, piece: UnstructuredGridPiece) -> Result<Vec<u8>, OutputError> {
    let vtk = Vtk {
        version: Version::new((1, 0)),
        title: String::new(),
        byte_order: ByteOrder::native(),
        data: DataSet::inline(piece),
        file_path: None,
    };
    let mut bytes = Vec::new();
    vtk.write_xml(&mut bytes).map_err(|e| OutputError::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    signed_indices(path, bytes)
}

/// Declares the connectivity and offsets Int64, as VTK's own writers do (readers such as
/// meshio turn UInt64 indices into floats). `vtkio` writes them UInt64; the bytes of indices
/// below 2⁶³ are the same in both types, so only the declared type changes.
fn signed_indices(path: &Path, bytes: Vec<u8>) -> Result<Vec<u8>, OutputError> {
    let text = String::from_utf8(bytes)
        .map_err(|e| OutputError::Encode { path: path.to_path_buf(), message: format!("not UTF-8 XML: {e}") })?;
    let text = ["connectivity", "offsets"].iter().fold(text, |text, name| {
        text.replacen(&format!("type=\"UInt64\" Name=\"{name}\""), &format!("type=\"Int64\" Name=\"{name}\""), 1)
    });
    Ok(text.into_bytes())
}

fn cells(grid: &Grid) -> Cells {
    let n = grid.tags.len();
    Cells {
        cell_verts: VertexNumbers::XML {
            connectivity: grid.nodes.iter().map(|&i| i as u64).collect(),
            offsets: (1..=n).map(|c| (c * grid.nodes_per_cell) as u64).collect(),
        },
        types: vec![grid.cell_type; n],
    }
}

fn attribute(field: &Field) -> Attribute {
    Attribute::DataArray(DataArray::new(field.name.as_str(), field.components as u32).with_data(field.values.clone()))
}

fn check_points<const D: usize>(path: &Path, mesh: &Mesh<D>) -> Result<(), OutputError> {
    match first_non_finite(mesh.points.iter().flatten()) {
        Some((i, value)) => Err(OutputError::NonFinite {
            path: path.to_path_buf(),
            location: format!("the coordinates of point {}", i / D),
            value,
        }),
        None => Ok(()),
    }
}

/// Checks the connectivity against the tag count and the number of points.
fn check_grid<const D: usize>(path: &Path, mesh: &Mesh<D>, grid: &Grid) -> Result<(), OutputError> {
    let reason = if grid.nodes.len() != grid.tags.len() * grid.nodes_per_cell {
        format!(
            "{} connectivity entries for {} cells of {} nodes",
            grid.nodes.len(),
            grid.tags.len(),
            grid.nodes_per_cell
        )
    } else if let Some(&node) = grid.nodes.iter().find(|&&i| i >= mesh.n_points()) {
        format!("node {node} is out of range ({} points)", mesh.n_points())
    } else {
        return Ok(());
    };
    Err(OutputError::Invalid { path: path.to_path_buf(), reason })
}

/// Checks each field's shape, finiteness and the uniqueness of the names (`reserved` included).
fn check_fields(
    path: &Path,
    kind: &str,
    count: usize,
    fields: &[Field],
    reserved: Option<&str>,
) -> Result<(), OutputError> {
    let mut names: Vec<&str> = reserved.into_iter().collect();
    for field in fields {
        if names.contains(&field.name.as_str()) {
            return Err(OutputError::Invalid {
                path: path.to_path_buf(),
                reason: format!("duplicate {kind} field `{}`", field.name),
            });
        }
        names.push(&field.name);
        check_field(path, kind, count, field)?;
    }
    Ok(())
}

fn check_field(path: &Path, kind: &str, count: usize, field: &Field) -> Result<(), OutputError> {
    let (name, len, components) = (&field.name, field.values.len(), field.components);
    let reason = if components == 0 {
        format!("{kind} field `{name}` has 0 components")
    } else if len != count * components {
        format!(
            "{kind} field `{name}` has {len} values, expected {count} {kind}s × {components} \
             components = {}",
            count * components
        )
    } else {
        return check_finite(path, kind, field);
    };
    Err(OutputError::Invalid { path: path.to_path_buf(), reason })
}

fn check_finite(path: &Path, kind: &str, field: &Field) -> Result<(), OutputError> {
    match first_non_finite(&field.values) {
        Some((i, value)) => Err(OutputError::NonFinite {
            path: path.to_path_buf(),
            location: format!("{kind} field `{}` at {kind} {}", field.name, i / field.components),
            value,
        }),
        None => Ok(()),
    }
}

/// Index and value of the first NaN or infinite value.
fn first_non_finite<'a>(values: impl IntoIterator<Item = &'a f64>) -> Option<(usize, f64)> {
    values.into_iter().copied().enumerate().find(|(_, v)| !v.is_finite())
}
