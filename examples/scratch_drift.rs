use damfem::adapt::marking::cell_size;
use damfem::io::gmsh::{mesh_geo, remesh_geo, MeshOptions, SizeField};
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use std::path::Path;

fn field(mesh: &Mesh, sizes: &[f64], mode: &str) -> SizeField {
    if mode == "const" {
        let mut f = SizeField { points: vec![], triangles: vec![], sizes: vec![] };
        for c in 0..mesh.n_cells() {
            let k = f.points.len();
            for &v in &mesh.cell(c)[..3] {
                f.points.push(mesh.points[v]);
                f.sizes.push(sizes[c]);
            }
            f.triangles.push([k, k + 1, k + 2]);
        }
        return f;
    }
    if mode == "min" {
        return SizeField::from_cells(mesh, sizes).unwrap();
    }
    let n = mesh.n_points();
    let (mut sum, mut weight, mut min) = (vec![0.0; n], vec![0.0; n], vec![f64::MAX; n]);
    for c in 0..mesh.n_cells() {
        let a = mesh.cell_area(c);
        for &v in &mesh.cell(c)[..3] {
            let w = if mode == "area" { a } else { 1.0 };
            sum[v] += w * sizes[c];
            weight[v] += w;
            min[v] = min[v].min(sizes[c]);
        }
    }
    let mut index = vec![usize::MAX; n];
    let mut f = SizeField { points: vec![], triangles: vec![], sizes: vec![] };
    for c in 0..mesh.n_cells() {
        let t = [0, 1, 2].map(|i| {
            let v = mesh.cell(c)[i];
            if index[v] == usize::MAX {
                index[v] = f.points.len();
                f.points.push(mesh.points[v]);
                f.sizes.push(match mode {
                    "geo" => (sum[v] / weight[v]),
                    _ => sum[v] / weight[v],
                });
            }
            index[v]
        });
        f.triangles.push(t);
    }
    f
}

fn mean_edge(mesh: &Mesh, c: usize) -> f64 {
    let v = mesh.cell_vertices(c);
    (0..3).map(|i| damfem::mesh::distance(v[i], v[(i + 1) % 3])).sum::<f64>() / 3.0
}

fn main() {
    let scene = Scene::load(Path::new("geo/scene_a.toml")).unwrap();
    let options = scene.mesh_options();
    let mut mesh = mesh_geo(&scene.geometry, &options, false, false).unwrap();
    let mode = std::env::args().nth(1).unwrap_or("min".into());
    let scale: f64 = std::env::args().nth(2).map_or(1.0, |s| s.parse().unwrap());
    println!("initial {}", mesh.n_cells());
    for i in 0..6 {
        let edge = std::env::var("EDGE").is_ok();
        let sizes: Vec<f64> =
            (0..mesh.n_cells()).map(|c| scale * if edge { mean_edge(&mesh, c) } else { cell_size(&mesh, c) }).collect();
        let f = field(&mesh, &sizes, &mode);
        mesh = remesh_geo(&scene.geometry, &MeshOptions { size_factor: 1.0, ..options.clone() }, &f, false, false)
            .unwrap();
        println!("{mode} remesh {i}: {}", mesh.n_cells());
    }
}
