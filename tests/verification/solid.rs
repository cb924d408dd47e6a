//! The solid (tetrahedra, P1 and P2) against exact solutions and fitted rates, on gmsh's
//! unstructured meshes of geo/block3d.geo (2 m × 1 m × 1 m).

use crate::common::fitted_rate;
use damfem::elasticity::solid::kernels::displacement_gradient;
use damfem::elasticity::solid::{Solid, SolidBody, SolidDirichlet, SolidNeumann};
use damfem::elasticity::Material;
use damfem::fem::tabulate::Tabulation;
use damfem::geometry::{Point3, TetMap, Vector3};
use damfem::io::gmsh::{mesh_geo_any, AnyMesh, MeshOptions};
use damfem::mesh::Mesh;
use damfem::scene::Scene;
use std::path::Path;
use std::sync::Arc;

const CONCRETE: Material = Material { young: 3.0e10, poisson: 0.2, density: 2400.0 };

fn block(order: usize, size_factor: f64) -> Mesh<3> {
    let options = MeshOptions { order, size_factor, ..Default::default() };
    match mesh_geo_any(Path::new("geo/block3d.geo"), &options, false, false).unwrap() {
        AnyMesh::Solid(mesh) => mesh,
        AnyMesh::Plane(_) => panic!("block3d.geo has a volume"),
    }
}

fn tag(mesh: &Mesh<3>, name: &str) -> i32 {
    mesh.group(2, name).unwrap_or_else(|| panic!("no surface {name}")).tag
}

fn roller(mesh: &Mesh<3>, name: &str, component: usize) -> SolidDirichlet {
    SolidDirichlet { tag: tag(mesh, name), fix: std::array::from_fn(|a| a == component), value: Arc::new(|_| [0.0; 3]) }
}

fn max_nodal_error(mesh: &Mesh<3>, u_h: &[Vector3], u: impl Fn(Point3) -> Vector3) -> f64 {
    let scale = mesh.points.iter().map(|&x| u(x).iter().fold(0.0f64, |m, v| m.max(v.abs()))).fold(0.0, f64::max);
    let error = mesh.points.iter().zip(u_h).map(|(&x, uh)| (0..3).map(|a| (uh[a] - u(x)[a]).abs()).fold(0.0, f64::max));
    error.fold(0.0, f64::max) / scale
}

/// Source: uniaxial compression, σ_zz = −q, the other stresses 0: u = (ν q x / E, ν q y / E,
/// −q z / E), linear. The scene file geo/block3d.toml (rollers on x = 0, y = 0, z = 0; q = 1 MPa
/// on the top), meshed by gmsh.
/// Goal: P1 and P2 reproduce u at every node to round-off (relative 1e-12).
/// Parameters: E = 30 GPa, ν = 0.2, the file's mesh sizes.
#[test]
fn a_block_under_uniform_pressure_is_exact_in_p1_and_p2() {
    let scene = Scene::load(Path::new("geo/block3d.toml")).unwrap();
    for order in [1, 2] {
        let solid = scene.solid(block(order, 1.0)).unwrap();
        let solution = solid.solve(None).unwrap();
        let strain = 1e6 / CONCRETE.young;
        let exact = |x: Point3| [0.2 * strain * x[0], 0.2 * strain * x[1], -strain * x[2]];
        let error = max_nodal_error(&solid.mesh, &solution.displacement, exact);
        println!("P{order}: {} tetrahedra, relative nodal error {error:.2e}", solid.mesh.n_cells());
        assert!(error < 1e-12, "P{order}: {error}");
        for s in solid.cell_stress(&solution.displacement) {
            assert!((s[2] + 1e6).abs() < 1e-5 && s[0].abs() < 1e-5 && s[5].abs() < 1e-5, "{s:?}");
        }
    }
}

/// Source: a column of height H under its weight, u_x = u_y = 0 by rollers on its four sides,
/// u_z = 0 at its foot, its top free: u_z = −ρ g (H z − z²/2) / (λ + 2μ), quadratic.
/// Goal: P2 exact at the nodes to round-off (1e-11); P1 converging at rate 2 at the nodes
/// (fitted over three meshes, ±0.5: nodal values of an unstructured mesh superconverge
/// irregularly).
/// Parameters: the block of geo/block3d.geo, H = 1 m, ρ = 2400 kg/m³, g = 9.81 m/s².
#[test]
fn a_column_under_its_weight_is_exact_in_p2() {
    let solve = |order: usize, size_factor: f64| {
        let mesh = block(order, size_factor);
        let dirichlet = ["xmin", "xmax", "ymin", "ymax"]
            .iter()
            .enumerate()
            .map(|(k, name)| roller(&mesh, name, k / 2))
            .chain([roller(&mesh, "bottom", 2)])
            .collect();
        let materials = vec![CONCRETE; mesh.n_cells()];
        let solid = Solid { mesh, materials, dirichlet, neumann: vec![], body: SolidBody::Weight(9.81) };
        let solution = solid.solve(None).unwrap();
        let (lambda, mu) = CONCRETE.lame();
        let exact = |x: Point3| [0.0, 0.0, -CONCRETE.density * 9.81 * (x[2] - 0.5 * x[2] * x[2]) / (lambda + 2.0 * mu)];
        (mean_size(&solid.mesh), max_nodal_error(&solid.mesh, &solution.displacement, exact))
    };
    let (_, p2) = solve(2, 1.0);
    println!("P2: relative nodal error {p2:.2e}");
    assert!(p2 < 1e-11, "P2: {p2}");
    let runs: Vec<(f64, f64)> = [1.0, 0.5, 0.25].iter().map(|&f| solve(1, f)).collect();
    let (h, e): (Vec<f64>, Vec<f64>) = runs.into_iter().unzip();
    let rate = fitted_rate(&h, &e);
    println!("P1: nodal errors {e:?}, rate {rate:.2}");
    assert!(e[2] < e[1] && e[1] < e[0] && (rate - 2.0).abs() < 0.5, "P1 rate {rate}");
}

/// The manufactured field u = ∇φ + (x³, 0, x³), φ = e^{√2 x} cos y cos z (Δφ = 0, so ∇φ
/// carries no body force): f = −∇·σ(u) = (−6 (λ + 2μ) x, 0, −6 μ x).
fn manufactured(x: Point3) -> Vector3 {
    let (e, r) = ((2f64.sqrt() * x[0]).exp(), 2f64.sqrt());
    [
        r * e * x[1].cos() * x[2].cos() + x[0].powi(3),
        -e * x[1].sin() * x[2].cos(),
        -e * x[1].cos() * x[2].sin() + x[0].powi(3),
    ]
}

fn manufactured_gradient(x: Point3) -> [Vector3; 3] {
    let (e, r) = ((2f64.sqrt() * x[0]).exp(), 2f64.sqrt());
    let (cy, sy, cz, sz) = (x[1].cos(), x[1].sin(), x[2].cos(), x[2].sin());
    let phi = e * cy * cz;
    let (xy, xz, yz) = (-r * e * sy * cz, -r * e * cy * sz, e * sy * sz);
    let cubic = 3.0 * x[0] * x[0];
    [[2.0 * phi + cubic, xy, xz], [xy, -phi, yz], [xz + cubic, yz, -phi]]
}

/// The mean cell size (|Ω| / cells)^{1/3}.
fn mean_size(mesh: &Mesh<3>) -> f64 {
    let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.cell_volume(c)).sum();
    (volume / mesh.n_cells() as f64).cbrt()
}

/// (h, L² error, H¹ error) of the manufactured field on the block at `size_factor`.
fn manufactured_errors(order: usize, size_factor: f64) -> (f64, f64, f64) {
    let mesh = block(order, size_factor);
    let (lambda, mu) = CONCRETE.lame();
    let exact: Arc<dyn Fn(Point3) -> Vector3 + Send + Sync> = Arc::new(manufactured);
    let dirichlet = (mesh.groups.iter().filter(|g| g.dim == 2))
        .map(|g| SolidDirichlet { tag: g.tag, fix: [true; 3], value: exact.clone() })
        .collect();
    let body = SolidBody::Field(Arc::new(move |x: Point3| [-6.0 * (lambda + 2.0 * mu) * x[0], 0.0, -6.0 * mu * x[0]]));
    let materials = vec![CONCRETE; mesh.n_cells()];
    let solid = Solid { mesh, materials, dirichlet, neumann: Vec::<SolidNeumann>::new(), body };
    let u = solid.solve(None).unwrap().displacement;
    let mesh = &solid.mesh;
    let tab = Tabulation::tetrahedron(order, 2 * order + 3);
    let (mut l2, mut h1, mut grads) = (0.0, 0.0, vec![[0.0; 3]; tab.n_basis]);
    for c in 0..mesh.n_cells() {
        let map = TetMap::new(mesh.cell_vertices(c));
        let nodal: Vec<Vector3> = mesh.cell(c).iter().map(|&n| u[n]).collect();
        for q in 0..tab.n_points() {
            let (x, w) = (map.to_physical(tab.points[q]), tab.weights[q] * map.det.abs());
            let uh = (0..3).map(|a| tab.phi(q).iter().zip(&nodal).map(|(p, v)| p * v[a]).sum::<f64>());
            l2 += uh.zip(manufactured(x)).map(|(a, b)| (a - b).powi(2)).sum::<f64>() * w;
            let g = displacement_gradient(&map, order, tab.points[q], &nodal, &mut grads);
            let exact = manufactured_gradient(x);
            h1 += (0..9).map(|k| (g[k / 3][k % 3] - exact[k / 3][k % 3]).powi(2)).sum::<f64>() * w;
        }
    }
    (mean_size(mesh), l2.sqrt(), h1.sqrt())
}

/// Source: the manufactured field above, u = exact on the whole boundary.
/// Goal: fitted rates |u − u_h|_{H¹} ~ h^p and ‖u − u_h‖_{L²} ~ h^{p+1}, h the mean cell size
/// (|Ω| / cells)^{1/3}, within ±0.2 on gmsh's unstructured tetrahedra.
/// Parameters: λ, μ of E = 30 GPa, ν = 0.2; size factors 1, ½, ¼ (P1) and 0.6, 0.4, 0.3 (P2).
#[test]
fn manufactured_rates_on_tetrahedra() {
    for (order, factors) in [(1, [1.0, 0.5, 0.25]), (2, [0.6, 0.4, 0.3])] {
        let runs: Vec<(f64, f64, f64)> = factors.iter().map(|&f| manufactured_errors(order, f)).collect();
        let h: Vec<f64> = runs.iter().map(|r| r.0).collect();
        let (l2, h1): (Vec<f64>, Vec<f64>) = runs.iter().map(|r| (r.1, r.2)).unzip();
        let (rate_l2, rate_h1) = (fitted_rate(&h, &l2), fitted_rate(&h, &h1));
        println!("P{order}: L2 {l2:?} rate {rate_l2:.3}; H1 {h1:?} rate {rate_h1:.3}");
        assert!((rate_h1 - order as f64).abs() <= 0.2, "P{order} H1 rate {rate_h1}");
        assert!((rate_l2 - (order + 1) as f64).abs() <= 0.2, "P{order} L2 rate {rate_l2}");
    }
}

/// The cell that holds x and the reference coordinates of x in it (barycentric coordinates
/// ≥ −1e-10).
fn locate(mesh: &Mesh<3>, x: Point3) -> (usize, TetMap, Point3) {
    for c in 0..mesh.n_cells() {
        let map = TetMap::new(mesh.cell_vertices(c));
        let d: Vector3 = std::array::from_fn(|r| x[r] - map.origin[r]);
        let xi: Point3 = std::array::from_fn(|r| (0..3).map(|k| map.inv_t[k][r] * d[k]).sum());
        if xi.iter().all(|&l| l >= -1e-10) && xi.iter().sum::<f64>() <= 1.0 + 1e-10 {
            return (c, map, xi);
        }
    }
    panic!("{x:?} lies in no cell")
}

/// u_h at x: the P_p interpolant on the cell that holds x.
fn displacement_at(mesh: &Mesh<3>, u: &[Vector3], x: Point3) -> Vector3 {
    let mut phi = vec![0.0; damfem::fem::tetrahedron::n_basis(mesh.order)];
    let (c, _, xi) = locate(mesh, x);
    damfem::fem::tetrahedron::values(mesh.order, xi, &mut phi);
    std::array::from_fn(|a| mesh.cell(c).iter().zip(&phi).map(|(&n, p)| p * u[n][a]).sum())
}

/// σ(u_h) at x as (σ_xx, σ_zz, σ_xz), the components of the section's plane.
fn stress_at(solid: &Solid, u: &[Vector3], x: Point3) -> [f64; 3] {
    let mesh = &solid.mesh;
    let (c, map, xi) = locate(mesh, x);
    let nodal: Vec<Vector3> = mesh.cell(c).iter().map(|&n| u[n]).collect();
    let mut grads = vec![[0.0; 3]; damfem::fem::tetrahedron::n_basis(mesh.order)];
    let (lambda, mu) = solid.materials[c].lame();
    let s = damfem::elasticity::solid::kernels::stress(
        displacement_gradient(&map, mesh.order, xi, &nodal, &mut grads),
        lambda,
        mu,
    );
    [s[0], s[2], s[4]]
}

/// Source: the plane-strain section tests/data/monolith_section.toml, solved in 2D with P2 at
/// a quarter of its mesh sizes, against geo/monolith.toml (the section extruded by 15 m,
/// rollers u_y = 0 on both sides) in 3D.
/// Goal: max |u| and the displacement at three points of the mid-plane y = 7.5 m (the crest's
/// upstream corner, mid-height of the upstream face, the downstream ground 20 m past the toe)
/// within 0.5 % of the section's with P2 tetrahedra, and closer on the finer of two meshes; the
/// in-plane stresses (σ_xx, σ_zz, σ_xz) at three points inside the dam and the rock within
/// 0.5 % of their size |σ| there.
/// Parameters: 3D P2 at size factors 1 and 0.7 (about 25 000 and 70 000 unknowns).
#[test]
fn the_extruded_monolith_reproduces_its_plane_strain_section() {
    use damfem::fem::transfer::interpolate;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let section = Scene::load(&root.join("tests/data/monolith_section.toml")).unwrap();
    let (plane, _) = section.problem(crate::common::mesh_scene(&section, 2, 0.25)).unwrap();
    let disc = plane.discretise();
    let x = plane.solve_linear(&disc).unwrap();
    let u2 = plane.displacement(&disc, &x);
    let points = [[0.0, 50.0], [0.0, 25.0], [60.0, 0.0]];
    let at2 = interpolate(&plane.mesh, &u2, &points);
    let inside = [[10.0, 10.0], [20.0, 5.0], [20.0, -10.0]];
    let locator = damfem::fem::transfer::Locator::new(&plane.mesh);
    let sigma2: Vec<[f64; 3]> = inside
        .iter()
        .map(|&p| {
            let (c, xi) = locator.locate(p);
            let map = damfem::geometry::AffineMap::new(plane.mesh.cell_vertices(c));
            let nodal: Vec<[f64; 2]> = plane.mesh.cell(c).iter().map(|&n| u2[n]).collect();
            let mut grads = vec![[0.0; 2]; 6];
            let g = damfem::elasticity::kernels::displacement_gradient(&map, 2, xi, &nodal, &mut grads);
            let (lambda, mu) = plane.materials[c].lame();
            let s = damfem::elasticity::kernels::stress(g, lambda, mu);
            [s[0], s[1], s[2]]
        })
        .collect();
    let max2 = u2.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    let monolith = Scene::load(&root.join("geo/monolith.toml")).unwrap();
    let mut errors = Vec::new();
    for factor in [1.0, 0.7] {
        let options = MeshOptions { order: 2, size_factor: factor, ..Default::default() };
        let AnyMesh::Solid(mesh) = mesh_geo_any(&monolith.geometry, &options, false, false).unwrap() else {
            panic!("monolith.geo has volumes")
        };
        let solid = monolith.solid(mesh).unwrap();
        let solution = solid.solve(None).unwrap();
        let u3 = &solution.displacement;
        let max3 = u3.iter().map(|&v| damfem::geometry::norm3(v)).fold(0.0, f64::max);
        let mut worst = (max3 - max2).abs() / max2;
        for (p, v2) in points.iter().zip(&at2) {
            let v3 = displacement_at(&solid.mesh, u3, [p[0], 7.5, p[1]]);
            let gap = (v3[0] - v2[0]).hypot(v3[2] - v2[1]) / v2[0].hypot(v2[1]);
            worst = worst.max(gap);
            println!(
                "factor {factor}: u at {p:?}: 3D ({:.5e}, {:.5e}), 2D ({:.5e}, {:.5e})",
                v3[0], v3[2], v2[0], v2[1]
            );
        }
        for (p, s2) in inside.iter().zip(&sigma2) {
            let s3 = stress_at(&solid, u3, [p[0], 7.5, p[1]]);
            let size = s2.iter().map(|x| x * x).sum::<f64>().sqrt();
            let gap = (0..3).map(|k| (s3[k] - s2[k]).abs()).fold(0.0, f64::max) / size;
            worst = worst.max(gap);
            println!("factor {factor}: σ at {p:?}: 3D {s3:?}, 2D {s2:?}, gap {gap:.2e}");
        }
        println!(
            "factor {factor}: {} unknowns, max |u| 3D {max3:.6e} 2D {max2:.6e}, worst gap {worst:.2e}",
            solution.unknowns
        );
        errors.push(worst);
    }
    assert!(errors[1] < 5e-3 && errors[1] < errors[0], "gaps {errors:?}");
}

/// Source: the same system solved by sparse Cholesky and by CG with PETSc's GAMG
/// (src/solve/petsc), relative residual 1e-10.
/// Goal: the iterative solution is the direct one to 1e-8 of max |u| (the monolith, dam and
/// rock, P2) and the block's exact linear field to 1e-8.
/// Parameters: geo/monolith.toml and geo/block3d.toml at their sizes, P2.
#[test]
fn the_iterative_solver_agrees_with_cholesky() {
    use damfem::elasticity::solid::Solver;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let monolith = Scene::load(&root.join("geo/monolith.toml")).unwrap();
    let options = MeshOptions { order: 2, ..Default::default() };
    let AnyMesh::Solid(mesh) = mesh_geo_any(&monolith.geometry, &options, false, false).unwrap() else {
        panic!("monolith.geo has volumes")
    };
    let solid = monolith.solid(mesh).unwrap();
    let direct = solid.solve(Some(Solver::Direct)).unwrap();
    let iterative = solid.solve(Some(Solver::Iterative)).unwrap();
    let scale = direct.displacement.iter().map(|&v| damfem::geometry::norm3(v)).fold(0.0, f64::max);
    let gap = (direct.displacement.iter().zip(&iterative.displacement))
        .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    println!(
        "monolith: {} unknowns, {:?} CG iterations, gap {:.2e}",
        direct.unknowns,
        iterative.iterations,
        gap / scale
    );
    assert!(iterative.iterations.is_some_and(|k| k > 0) && gap < 1e-8 * scale, "gap {gap:e}");
    let block = Scene::load(&root.join("geo/block3d.toml")).unwrap().solid(block(2, 1.0)).unwrap();
    let solution = block.solve(Some(Solver::Iterative)).unwrap();
    let strain = 1e6 / CONCRETE.young;
    let error = max_nodal_error(&block.mesh, &solution.displacement, |x| {
        [0.2 * strain * x[0], 0.2 * strain * x[1], -strain * x[2]]
    });
    println!("block: {:?} CG iterations, relative nodal error {error:.2e}", solution.iterations);
    assert!(error < 1e-8, "{error}");
}

/// Source: the statics of the monolith (geo/monolith.toml): the supports carry the weight,
/// Σ ρ g |T| over the cells, and the water's thrust on the upstream face, ρ_w g W H²/2 with
/// W = 15 m and H = 45 m (the face is vertical, x = 0).
/// Goal: the sum of the reactions of the Dirichlet surfaces is (−thrust, 0, weight) to 1e-9
/// of the weight, P1 and P2, direct and iterative.
#[test]
fn the_reactions_balance_the_weight_and_the_water() {
    use damfem::elasticity::solid::Solver;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let monolith = Scene::load(&root.join("geo/monolith.toml")).unwrap();
    for (order, solver) in [(1, Solver::Direct), (2, Solver::Direct), (2, Solver::Iterative)] {
        let options = MeshOptions { order, ..Default::default() };
        let AnyMesh::Solid(mesh) = mesh_geo_any(&monolith.geometry, &options, false, false).unwrap() else {
            panic!("monolith.geo has volumes")
        };
        let solid = monolith.solid(mesh).unwrap();
        let u = solid.solve(Some(solver)).unwrap().displacement;
        let total =
            solid.reactions(&u).unwrap().iter().fold([0.0; 3], |s, (_, r)| [s[0] + r[0], s[1] + r[1], s[2] + r[2]]);
        let mesh = &solid.mesh;
        let weight: f64 = (0..mesh.n_cells()).map(|c| solid.materials[c].density * 9.81 * mesh.cell_volume(c)).sum();
        let thrust = 1000.0 * 9.81 * 15.0 * 45.0 * 45.0 / 2.0;
        let gaps = [total[0] + thrust, total[1], total[2] - weight].map(|g| g.abs() / weight);
        println!("P{order} {solver:?}: reactions {total:?}, weight {weight:.6e}, thrust {thrust:.6e}, gaps {gaps:?}");
        assert!(gaps.iter().all(|&g| g < 1e-9), "P{order} {solver:?}: {gaps:?}");
    }
}
