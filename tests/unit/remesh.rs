//! Remeshing a `.geo` file with per-cell target sizes, against the real gmsh 4.8 library.

use damfem::geometry::distance;
use damfem::io::gmsh::{self, GmshError, MeshOptions, SizeField};
use damfem::mesh::Mesh;
use std::path::{Path, PathBuf};

fn geo(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("geo").join(name)
}

fn order(order: usize) -> MeshOptions {
    MeshOptions { order, ..MeshOptions::default() }
}

fn mesh(name: &str, order_: usize) -> Mesh {
    gmsh::mesh_geo(&geo(name), &order(order_), false, false).unwrap()
}

/// Remeshes `path` with the per-cell sizes h(T) on `mesh`.
fn remesh(path: &Path, mesh: &Mesh, h: impl Fn(usize) -> f64) -> Mesh {
    let sizes: Vec<f64> = (0..mesh.n_cells()).map(h).collect();
    let field = SizeField::from_cells(mesh, &sizes).unwrap();
    gmsh::remesh_geo(path, &order(mesh.order), &field, false, false).unwrap()
}

fn centroid(mesh: &Mesh, c: usize) -> [f64; 2] {
    let [a, b, d] = mesh.cell_vertices(c);
    [(a[0] + b[0] + d[0]) / 3.0, (a[1] + b[1] + d[1]) / 3.0]
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum()
}

/// Mean diameter of the cells whose centroid satisfies `inside`.
fn mean_diameter(mesh: &Mesh, inside: impl Fn([f64; 2]) -> bool) -> f64 {
    let cells: Vec<usize> = (0..mesh.n_cells()).filter(|&c| inside(centroid(mesh, c))).collect();
    assert!(!cells.is_empty());
    cells.iter().map(|&c| mesh.cell_diameter(c)).sum::<f64>() / cells.len() as f64
}

/// Scene A refined to h(T)/2 within 5 m of the heel of the toe, (32, 0).
const TOE: [f64; 2] = [32.0, 0.0];
const RADIUS: f64 = 5.0;

fn scene_a_refined_at_toe() -> (Mesh, Mesh) {
    let old = mesh("scene_a.geo", 2);
    let near = |c| distance(centroid(&old, c), TOE) < RADIUS;
    let new = remesh(&geo("scene_a.geo"), &old, |c| old.cell_diameter(c) * if near(c) { 0.5 } else { 1.0 });
    (old, new)
}

fn sorted(mut names: Vec<&str>) -> Vec<&str> {
    names.sort_unstable();
    names
}

#[test]
fn physical_groups_lengths_and_area_survive() {
    let (old, new) = scene_a_refined_at_toe();
    assert_eq!(new.order, 2);
    assert_eq!(sorted(new.group_names(1)), sorted(old.group_names(1)));
    assert_eq!(sorted(new.group_names(2)), sorted(old.group_names(2)));
    let downstream = 35f64.hypot(50.0);
    for (name, length) in [("base", 32.0), ("toe", 8.0), ("downstream", downstream), ("crest", 5.0), ("upstream", 50.0)]
    {
        let tag = new.group(1, name).unwrap().tag;
        let measured = new.boundary_length(tag);
        assert!((measured - length).abs() < 1e-9 * length, "{name}: {measured} ≠ {length}");
    }
    let area = 0.5 * (40.0 + 5.0) * 50.0;
    for mesh in [&old, &new] {
        assert!((total_area(mesh) - area).abs() < 1e-9 * area, "area {}", total_area(mesh));
    }
    assert!(new.cell_tags.iter().all(|&t| t == new.group(2, "concrete").unwrap().tag));
}

#[test]
fn sizes_are_followed() {
    let (old, new) = scene_a_refined_at_toe();
    let near = |x| distance(x, TOE) < RADIUS;
    let far = |x| distance(x, TOE) >= RADIUS;
    let refinement = mean_diameter(&old, near) / mean_diameter(&new, near);
    let change = mean_diameter(&new, far) / mean_diameter(&old, far);
    println!(
        "cells {} → {}, near: h_old/h_new = {refinement:.3}, far: h_new/h_old = {change:.3}",
        old.n_cells(),
        new.n_cells()
    );
    assert!((1.5..3.0).contains(&refinement), "refinement {refinement}");
    assert!((0.7..1.3).contains(&change), "change {change}");
}

#[test]
fn halving_every_size_quadruples_the_cells() {
    let path = geo("unit_square.geo");
    let old = mesh("unit_square.geo", 1);
    let same = remesh(&path, &old, |c| old.cell_diameter(c));
    let halved = remesh(&path, &old, |c| 0.5 * old.cell_diameter(c));
    let ratio = halved.n_cells() as f64 / same.n_cells() as f64;
    println!("cells {} → {} (h_T), {} (h_T/2): ratio {ratio:.2}", old.n_cells(), same.n_cells(), halved.n_cells());
    assert!((3.0..5.5).contains(&ratio), "ratio {ratio}");
    // later sessions mesh with the sizes of the file again
    assert_eq!(mesh("unit_square.geo", 1).n_cells(), old.n_cells());
}

#[test]
fn options_still_scale_and_bound_the_sizes() {
    let path = geo("unit_square.geo");
    let old = mesh("unit_square.geo", 1);
    let field = SizeField::from_cells(&old, &vec![0.1; old.n_cells()]).unwrap();
    let cells = |options: MeshOptions| gmsh::remesh_geo(&path, &options, &field, false, false).unwrap().n_cells();
    let base = cells(order(1)) as f64;
    let halved = cells(MeshOptions { size_factor: 0.5, ..order(1) }) as f64;
    let capped = cells(MeshOptions { size_max: Some(0.05), ..order(1) }) as f64;
    let raised = cells(MeshOptions { size_min: Some(0.2), ..order(1) }) as f64;
    println!("cells {base}: size_factor 0.5 {halved}, size_max 0.05 {capped}, size_min 0.2 {raised}");
    assert!((3.0..5.5).contains(&(halved / base)) && (3.0..5.5).contains(&(capped / base)));
    assert!((3.0..5.5).contains(&(base / raised)));
}

fn bad_size_field(error: Result<impl std::fmt::Debug, GmshError>, expected: &str) {
    match error {
        Err(e @ GmshError::BadSizeField { .. }) => assert!(e.to_string().contains(expected), "{e}"),
        other => panic!("expected a size field error containing {expected:?}, got {other:?}"),
    }
}

#[test]
fn bad_sizes_are_errors() {
    let old = mesh("unit_square.geo", 2);
    let n = old.n_cells();
    for (c, h, expected) in
        [(3, f64::NAN, "cell 3 has size NaN"), (0, 0.0, "cell 0 has size 0"), (7, -0.1, "cell 7 has size -0.1")]
    {
        let mut sizes = vec![0.1; n];
        sizes[c] = h;
        bad_size_field(SizeField::from_cells(&old, &sizes), expected);
    }
    bad_size_field(SizeField::from_cells(&old, &vec![0.1; n - 1]), &format!("{} sizes for {n} cells", n - 1));
    bad_size_field(SizeField::from_cells(&old, &vec![f64::INFINITY; n]), "cell 0 has size inf");

    let good = SizeField::from_cells(&old, &vec![0.1; n]).unwrap();
    let path = geo("unit_square.geo");
    let remesh = |field: &SizeField| gmsh::remesh_geo(&path, &order(1), field, false, false);
    let mut field = good.clone();
    field.sizes.pop();
    bad_size_field(remesh(&field), &format!("{} sizes for {} points", field.points.len() - 1, field.points.len()));
    let mut field = good.clone();
    field.sizes[2] = f64::NAN;
    bad_size_field(remesh(&field), "point 2 at");
    let mut field = good.clone();
    field.triangles[5][1] = field.points.len();
    bad_size_field(remesh(&field), "triangle 5 refers to point");
    let field = SizeField { points: vec![], triangles: vec![], sizes: vec![] };
    bad_size_field(remesh(&field), "no triangles");
    assert!(remesh(&good).is_ok());
}

/// A fresh, empty directory for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("damfem-remesh-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn our_field_replaces_the_background_field_of_the_file() {
    // the file asks for sizes 0.02 everywhere, through a field and through a view at index 0
    let own = r#"
View "decoy" { ST(0, 1, 0, 0, 0, 1, 0, 0, 0){0.02, 0.02, 0.02}; ST(1, 1, 0, 0, 1, 1, 0, 0, 0){0.02, 0.02, 0.02}; };
Field[1] = MathEval;
Field[1].F = "0.02";
Field[2] = PostView;
Field[2].ViewIndex = 0;
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeFromPoints = 1;
Mesh.MeshSizeExtendFromBoundary = 1;
"#;
    let square = std::fs::read_to_string(geo("unit_square.geo")).unwrap();
    let path = temp_dir("background").join("square_with_field.geo");
    std::fs::write(&path, format!("{square}{own}")).unwrap();
    let own_sizes = gmsh::mesh_geo(&path, &order(1), false, false).unwrap();

    let old = mesh("unit_square.geo", 1);
    let plain = remesh(&geo("unit_square.geo"), &old, |_| 0.25);
    let ours = remesh(&path, &old, |_| 0.25);
    println!(
        "cells: file's field {}, ours on the plain file {}, ours on the file {}",
        own_sizes.n_cells(),
        plain.n_cells(),
        ours.n_cells()
    );
    assert!(own_sizes.n_cells() > 1000);
    assert_eq!(ours.n_cells(), plain.n_cells());
    let mean = mean_diameter(&ours, |_| true);
    assert!((0.2..0.4).contains(&mean), "mean diameter {mean}");
}

/// The same geometry and size field give the same mesh whichever thread asks, including threads
/// other than the one that initialised gmsh (gmsh's OpenMP team size is per thread).
#[test]
fn remeshing_is_reproducible_across_threads() {
    let old = mesh("hertz.geo", 2);
    let remesh_hertz =
        || remesh(&geo("hertz.geo"), &old, |c| old.cell_diameter(c) * if c % 3 == 0 { 0.5 } else { 1.0 });
    let here = remesh_hertz();
    let elsewhere: Vec<Mesh> = std::thread::scope(|s| {
        let threads: Vec<_> = (0..3).map(|_| s.spawn(remesh_hertz)).collect();
        threads.into_iter().map(|t| t.join().unwrap()).collect()
    });
    for other in &elsewhere {
        assert_eq!(other.cell_nodes, here.cell_nodes);
        assert_eq!(other.points, here.points);
    }
}
