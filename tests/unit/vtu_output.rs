//! VTU and PVD output: files written by `damfem::io` re-read with `vtkio`.

use damfem::io::atomic::OutputError;
use damfem::io::pvd::write_pvd;
use damfem::io::vtu::{write_boundary_vtu, write_mesh_vtu, Field};
use damfem::mesh::{structured::unit_square, Mesh};
use std::fs;
use std::path::{Path, PathBuf};
use vtkio::model::{Attribute, CellType, DataArray, DataSet, Piece, UnstructuredGridPiece, Vtk};

/// A fresh empty directory for test `name`.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("vtu_output").join(name);
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn read_piece(path: &Path) -> UnstructuredGridPiece {
    let vtk = Vtk::import(path).unwrap();
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else {
        panic!("not an unstructured grid");
    };
    assert_eq!(pieces.len(), 1);
    let Piece::Inline(piece) = pieces.remove(0) else {
        panic!("piece not inline");
    };
    *piece
}

fn arrays(attributes: &[Attribute]) -> Vec<&DataArray> {
    attributes
        .iter()
        .map(|a| match a {
            Attribute::DataArray(array) => array,
            Attribute::Field { .. } => panic!("unexpected field attribute"),
        })
        .collect()
}

fn names(attributes: &[Attribute]) -> Vec<&str> {
    attributes.iter().map(|a| a.name()).collect()
}

fn f64s(array: &DataArray) -> Vec<f64> {
    array.data.clone().into_vec::<f64>().unwrap()
}

fn i32s(array: &DataArray) -> Vec<i32> {
    array.data.clone().into_vec::<i32>().unwrap()
}

fn connectivity(piece: &UnstructuredGridPiece) -> Vec<usize> {
    let (connectivity, _) = piece.cells.cell_verts.clone().into_xml();
    connectivity.into_iter().map(|i| i as usize).collect()
}

fn displacement(mesh: &Mesh) -> Field {
    Field::vector("displacement", "m", mesh.points.iter().map(|p| [0.1 * p[0], -0.2 * p[1]]).collect())
}

fn check_points(piece: &UnstructuredGridPiece, mesh: &Mesh) {
    assert_eq!(piece.num_points(), mesh.n_points());
    let expected: Vec<f64> = mesh.points.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    assert_eq!(piece.points.clone().into_vec::<f64>().unwrap(), expected);
    let point = arrays(&piece.data.point);
    assert_eq!(names(&piece.data.point), ["displacement"]);
    assert_eq!(point[0].num_comp(), 3);
    assert_eq!(f64s(point[0]), displacement(mesh).values);
}

#[test]
fn mesh_round_trip_p1_and_p2() {
    let dir = scratch("mesh");
    for (order, cell_type) in [(1, CellType::Triangle), (2, CellType::QuadraticTriangle)] {
        let mut mesh = unit_square(3, order);
        mesh.cell_tags[0] = 7;
        let area = Field::scalar("area", "1", (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).collect());
        let path = dir.join(format!("p{order}.vtu"));
        write_mesh_vtu(&path, &mesh, &[displacement(&mesh)], std::slice::from_ref(&area)).unwrap();

        let piece = read_piece(&path);
        check_points(&piece, &mesh);
        assert_eq!(piece.cells.types, vec![cell_type; mesh.n_cells()]);
        assert_eq!(connectivity(&piece), mesh.cell_nodes);
        assert_eq!(names(&piece.data.cell), ["material", "area"]);
        let cell = arrays(&piece.data.cell);
        assert_eq!(i32s(cell[0]), mesh.cell_tags);
        assert_eq!(cell[1].num_comp(), 1);
        assert_eq!(f64s(cell[1]), area.values);
    }
}

#[test]
fn boundary_round_trip_p1_and_p2() {
    let dir = scratch("boundary");
    for (order, cell_type) in [(1, CellType::Line), (2, CellType::QuadraticEdge)] {
        let mesh = unit_square(2, order);
        let length = Field::scalar("length", "1", (0..mesh.n_facets()).map(|f| mesh.facet_length(f)).collect());
        let path = dir.join(format!("p{order}_boundary.vtu"));
        write_boundary_vtu(&path, &mesh, &[displacement(&mesh)], std::slice::from_ref(&length)).unwrap();

        let piece = read_piece(&path);
        check_points(&piece, &mesh);
        assert_eq!(piece.cells.types, vec![cell_type; mesh.n_facets()]);
        assert_eq!(connectivity(&piece), mesh.facet_nodes);
        assert_eq!(names(&piece.data.cell), ["physical_tag", "length"]);
        let cell = arrays(&piece.data.cell);
        assert_eq!(i32s(cell[0]), mesh.facet_tags);
        assert_eq!(f64s(cell[1]), length.values);
    }
}

#[test]
fn unwritable_directory_is_an_error_naming_the_path() {
    let dir = scratch("unwritable");
    let mesh = unit_square(1, 1);
    let blocker = dir.join("regular_file");
    fs::write(&blocker, "").unwrap();
    for path in [blocker.join("out.vtu"), PathBuf::from("/proc/damfem_test_out.vtu")] {
        let err = write_mesh_vtu(&path, &mesh, &[], &[]).unwrap_err();
        assert!(matches!(err, OutputError::Io { .. }), "{err:?}");
        let prefix = format!("cannot write {}: ", path.display());
        assert!(err.to_string().starts_with(&prefix), "{err}");
        assert!(!path.exists());
    }
    assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
}

#[test]
fn non_finite_values_are_rejected_before_writing() {
    let dir = scratch("nan");
    let mesh = unit_square(2, 2);
    let path = dir.join("nan.vtu");
    let mut u = displacement(&mesh);
    u.values[3 * 4 + 1] = f64::NAN;
    let err = write_mesh_vtu(&path, &mesh, &[u], &[]).unwrap_err();
    assert!(matches!(err, OutputError::NonFinite { .. }), "{err:?}");
    let message = err.to_string();
    assert!(message.contains("point field `displacement` at point 4"), "{message}");

    let stress = Field::scalar("stress", "1", vec![f64::INFINITY; mesh.n_cells()]);
    let err = write_boundary_vtu(&path, &mesh, &[], &[stress]).unwrap_err();
    assert!(err.to_string().contains("`stress`"), "{err}");
    assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
}

#[test]
fn field_length_and_name_are_checked() {
    let dir = scratch("length");
    let mesh = unit_square(2, 1);
    let path = dir.join("bad.vtu");
    let short = Field::scalar("pressure", "1", vec![0.0; mesh.n_points() - 1]);
    let err = write_mesh_vtu(&path, &mesh, &[short], &[]).unwrap_err();
    assert!(matches!(err, OutputError::Invalid { .. }), "{err:?}");
    assert!(err.to_string().contains("point field `pressure` has 8 values"), "{err}");

    let clash = Field::scalar("material", "1", vec![0.0; mesh.n_cells()]);
    let err = write_mesh_vtu(&path, &mesh, &[], &[clash]).unwrap_err();
    assert!(err.to_string().contains("duplicate cell field `material`"), "{err}");
    assert!(!path.exists());
}

#[test]
fn pvd_lists_relative_data_sets() {
    let dir = scratch("pvd");
    let mesh = unit_square(1, 2);
    fs::create_dir(dir.join("steps")).unwrap();
    let entries: Vec<(f64, PathBuf)> =
        [0.0, 0.5].into_iter().enumerate().map(|(i, t)| (t, dir.join(format!("steps/step_{i}.vtu")))).collect();
    for (_, file) in &entries {
        write_mesh_vtu(file, &mesh, &[], &[]).unwrap();
    }
    let pvd = dir.join("series.pvd");
    write_pvd(&pvd, &entries).unwrap();

    let text = fs::read_to_string(&pvd).unwrap();
    assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\""));
    assert!(text.contains("<DataSet timestep=\"0\" file=\"steps/step_0.vtu\"/>"));
    assert!(text.contains("<DataSet timestep=\"0.5\" file=\"steps/step_1.vtu\"/>"));
    assert_eq!(text.matches("<DataSet ").count(), 2);
    assert!(text.trim_end().ends_with("</Collection>\n</VTKFile>"));

    let err = write_pvd(&dir.join("nan.pvd"), &[(f64::NAN, entries[0].1.clone())]).unwrap_err();
    assert!(matches!(err, OutputError::NonFinite { .. }), "{err:?}");
    assert!(!dir.join("nan.pvd").exists());
}

/// The text of the ascii `DataArray` named `name` inside the `FieldData` element of `xml`.
fn field_data_array<'a>(xml: &'a str, kind: &str, name: &str) -> Option<&'a str> {
    let start = xml.find("<FieldData>")?;
    let block = &xml[start..xml.find("</FieldData>")?];
    let open = format!("<DataArray type=\"{kind}\" Name=\"{name}\" ");
    let at = block.find(&open)?;
    let text = &block[at..];
    Some(&text[text.find('>')? + 1..text.find("</DataArray>")?])
}

#[test]
fn field_data_names_the_groups_and_gives_the_units() {
    let dir = scratch("field_data");
    let mut mesh = unit_square(2, 1);
    mesh.groups[1].name = "base & <joint>".into();
    let area = Field::scalar("area", "m^2", (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).collect());
    let path = dir.join("named.vtu");
    write_mesh_vtu(&path, &mesh, &[displacement(&mesh)], &[area]).unwrap();
    let xml = fs::read_to_string(&path).unwrap();
    // every group as (tag, dim), its name escaped
    assert_eq!(field_data_array(&xml, "Int32", "domain"), Some("1 2"));
    let base = mesh.groups[1].tag;
    assert_eq!(field_data_array(&xml, "Int32", "base &amp; &lt;joint&gt;"), Some(format!("{base} 1").as_str()));
    assert_eq!(field_data_array(&xml, "Int32", "left"), Some(format!("{} 1", mesh.groups[4].tag).as_str()));
    // every array's unit, its bytes as the values
    let unit = |name: &str| {
        let text = field_data_array(&xml, "UInt8", name).unwrap_or_else(|| panic!("no {name}"));
        String::from_utf8(text.split(' ').map(|b| b.parse::<u8>().unwrap()).collect()).unwrap()
    };
    assert_eq!(unit("displacement [m]"), "m");
    assert_eq!(unit("area [m^2]"), "m^2");
    assert_eq!(unit("material [physical group tag]"), "physical group tag");
    let field_data = &xml[xml.find("<FieldData>").unwrap()..xml.find("</FieldData>").unwrap()];
    assert_eq!(field_data.matches("<DataArray type=\"UInt8\"").count(), 3);
    // the grid still reads back whole
    assert_eq!(read_piece(&path).num_points(), mesh.n_points());
}

#[test]
fn a_group_named_as_a_unit_array_is_refused() {
    let dir = scratch("field_data_clash");
    let mut mesh = unit_square(1, 1);
    mesh.groups[0].name = "material [physical group tag]".into();
    let path = dir.join("clash.vtu");
    let err = write_mesh_vtu(&path, &mesh, &[], &[]).unwrap_err();
    assert!(matches!(err, OutputError::Invalid { .. }), "{err:?}");
    assert!(err.to_string().contains("two field data arrays named `material [physical group tag]`"), "{err}");
    assert!(!path.exists());
}
