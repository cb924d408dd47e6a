//! gmsh interface against the real gmsh 4.8 library; tests run in parallel through the lock.

use damfem::geometry::distance;
use damfem::io::gmsh::{self, GmshError, MeshOptions, Session};
use damfem::mesh::Mesh;
use std::collections::HashSet;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

fn order(order: usize) -> MeshOptions {
    MeshOptions { order, ..MeshOptions::default() }
}

/// A fresh, empty directory for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("damfem-gmsh-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn mesh_square(order_: usize) -> Mesh {
    gmsh::mesh_geo(&data("square.geo"), &order(order_), false, false).unwrap()
}

/// The unit square of `square.geo` with `body` added: a small valid `.geo`.
fn square_with(body: &str) -> String {
    let square = std::fs::read_to_string(data("square.geo")).unwrap();
    format!("{square}{body}\n")
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.n_cells()).map(|c| mesh.cell_area(c)).sum()
}

/// Distinct vertices and edges of the cells.
fn vertices_and_edges(mesh: &Mesh) -> (usize, usize) {
    let mut vertices = HashSet::<usize>::new();
    let mut edges = HashSet::new();
    for c in 0..mesh.n_cells() {
        let v = &mesh.cell(c)[..3];
        vertices.extend(v);
        for i in 0..3 {
            let (a, b) = (v[i], v[(i + 1) % 3]);
            edges.insert((a.min(b), a.max(b)));
        }
    }
    (vertices.len(), edges.len())
}

fn midpoint(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
}

/// Every cell is counter-clockwise, with nodes 3, 4, 5 at the middles of edges 01, 12, 20.
fn check_p2_cells(mesh: &Mesh) {
    assert_eq!(mesh.order, 2);
    for c in 0..mesh.n_cells() {
        assert!(mesh.cell_area(c) > 0.0, "cell {c} is not counter-clockwise");
        let n = mesh.cell(c);
        for (i, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
            let expected = midpoint(mesh.points[n[a]], mesh.points[n[b]]);
            assert!(distance(mesh.points[n[3 + i]], expected) < 1e-12, "cell {c} edge {i}");
        }
    }
}

#[test]
fn square_counts_groups_area_and_lengths() {
    let mesh = mesh_square(1);
    assert_eq!((mesh.order, mesh.n_points(), mesh.n_cells(), mesh.n_facets()), (1, 25, 32, 16));
    for (dim, name) in [(1, "bottom"), (1, "right"), (1, "top"), (1, "left"), (2, "domain")] {
        let group = mesh.group(dim, name).unwrap_or_else(|| panic!("no group {name}"));
        assert_eq!(group.dim, dim);
        if dim == 1 {
            assert!((mesh.boundary_length(group.tag) - 1.0).abs() < 1e-12, "{name}");
        }
    }
    assert_eq!(mesh.group_names(1), ["bottom", "right", "top", "left"]);
    let domain = mesh.group(2, "domain").unwrap().tag;
    assert!(mesh.cell_tags.iter().all(|&t| t == domain));
    assert!((total_area(&mesh) - 1.0).abs() < 1e-12);
    assert!((0..mesh.n_cells()).all(|c| mesh.cell_area(c) > 0.0));
    let used: HashSet<_> = mesh.cell_nodes.iter().collect();
    assert_eq!(used.len(), mesh.n_points(), "nodes are compact and all used");
}

#[test]
fn order_two_midpoints_sit_on_straight_edges() {
    let linear = gmsh::mesh_geo(&data("quarter_disk.geo"), &order(1), false, false).unwrap();
    let mesh = gmsh::mesh_geo(&data("quarter_disk.geo"), &order(2), false, false).unwrap();
    assert_eq!(mesh.order, 2);
    assert_eq!(mesh.n_cells(), linear.n_cells());
    let (vertices, edges) = vertices_and_edges(&mesh);
    assert_eq!(vertices, linear.n_points());
    assert_eq!(mesh.n_points(), vertices + edges);
    check_p2_cells(&mesh);
    let arc = mesh.group(1, "arc").unwrap().tag;
    for f in (0..mesh.n_facets()).filter(|&f| mesh.facet_tags[f] == arc) {
        let [a, b, m] = [0, 1, 2].map(|i| mesh.points[mesh.facet(f)[i]]);
        assert!((distance([0.0, 0.0], a) - 1.0).abs() < 1e-9, "end points on the circle");
        assert!(distance(m, midpoint(a, b)) < 1e-12, "midpoint on the chord");
        assert!(distance([0.0, 0.0], m) < 1.0 - 1e-6, "midpoint inside the circle");
    }
}

#[test]
fn clockwise_surfaces_give_counter_clockwise_cells() {
    let dir = temp_dir("clockwise");
    let text = std::fs::read_to_string(data("square.geo")).unwrap();
    let text = text.replace("{1, 2, 3, 4};", "{-4, -3, -2, -1};");
    let path = write(&dir, "clockwise.geo", &text);
    let mesh = gmsh::mesh_geo(&path, &order(2), false, false).unwrap();
    check_p2_cells(&mesh);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn written_msh_reads_back_the_same() {
    let dir = temp_dir("write");
    let msh = dir.join("square.msh");
    let mut session = Session::new(false).unwrap();
    session.open_geo(&data("square.geo"), false).unwrap();
    session.set_options(&order(2)).unwrap();
    session.generate().unwrap();
    let mesh = session.mesh().unwrap();
    session.write(&msh).unwrap();
    drop(session);
    let back = gmsh::read_msh(&msh, false).unwrap();
    assert_eq!(back.order, 2);
    assert_eq!((back.n_points(), back.n_cells(), back.n_facets()), (mesh.n_points(), mesh.n_cells(), mesh.n_facets()));
    assert_eq!((mesh.n_points(), mesh.n_facets()), (81, 16));
    assert_eq!(back.groups, mesh.groups);
    assert!((total_area(&back) - 1.0).abs() < 1e-12);
    let missing_dir = dir.join("no/such/dir/out.msh");
    let mut session = Session::new(false).unwrap();
    session.open_msh(&msh).unwrap();
    let err = session.write(&missing_dir).unwrap_err();
    assert!(matches!(err, GmshError::Write { .. }), "{err}");
    drop(session);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn syntax_error_reports_gmsh_message_and_gmsh_stays_usable() {
    let path = data("syntax_error.geo");
    let err = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap_err();
    let GmshError::Open { message, .. } = &err else {
        panic!("expected an open error, got {err:?}");
    };
    assert_eq!(message, "line 3: syntax error (;)");
    assert_eq!(err.to_string(), format!("cannot open {}: line 3: syntax error (;)", path.display()));
    // an error thrown while parsing would leave gmsh 4.8 busy, ignoring later opens
    assert_eq!(mesh_square(1).n_cells(), 32);
}

#[test]
fn missing_files_are_not_found() {
    let path = data("missing.geo");
    let err = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(err, GmshError::NotFound { .. }));
    assert_eq!(err.to_string(), format!("cannot open {}: file not found", path.display()));
    let err = gmsh::read_msh(&data("missing.msh"), false).unwrap_err();
    assert!(matches!(err, GmshError::NotFound { .. }));
}

#[test]
fn system_calls_are_refused_unless_allowed() {
    let dir = temp_dir("system-call");
    let pwned = dir.join("pwned");
    let call = format!("SystemCall \"touch {}\";", pwned.display());
    let direct = write(&dir, "direct.geo", &square_with(&call));
    write(&dir, "evil.geo", &format!("// helper\n{call}\n"));
    let included = write(&dir, "main.geo", &square_with("Include \"evil.geo\";"));
    for (path, file, line) in [(&direct, "direct.geo", 19), (&included, "evil.geo", 2)] {
        let err = gmsh::mesh_geo(path, &MeshOptions::default(), false, false).unwrap_err();
        let GmshError::SystemCall { path: at, line: l, .. } = &err else {
            panic!("expected a refusal, got {err:?}");
        };
        assert!(at.ends_with(file) && *l == line, "{err}");
        assert!(!pwned.exists(), "the command must not run");
    }
    let mesh = gmsh::mesh_geo(&included, &MeshOptions::default(), false, true).unwrap();
    assert_eq!(mesh.n_cells(), 32);
    assert!(pwned.exists(), "with allow_system_calls the command runs");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn skipped_block_trick_is_refused() {
    // gmsh 4.8's `If` skipper ignores strings: it stops at the "EndIf" inside the string, so
    // gmsh reads `b = "; // ";` then runs what its lexer would see as a comment
    let dir = temp_dir("skip-trick");
    let pwned = dir.join("pwned");
    let trick = format!("If (0)\n  a = \"EndIf\nb = \"; // \"; SystemCall 'touch {}';\nEndIf", pwned.display());
    let path = write(&dir, "trick.geo", &square_with(&trick));
    let err = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(err, GmshError::SystemCall { line: 21, .. }), "{err}");
    assert!(!pwned.exists());
    let mut session = Session::new(false).unwrap();
    session.open_geo(&path, true).unwrap();
    assert!(pwned.exists(), "gmsh runs the SystemCall hidden in the comment");
    drop(session);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn option_files_and_disguised_meshes_are_refused() {
    let dir = temp_dir("disguised");
    let pwned = dir.join("pwned");
    let call = format!("SystemCall \"touch {}\";\n", pwned.display());
    let geo = write(&dir, "a.geo", &square_with(""));
    write(&dir, "a.geo.opt", &call);
    let err = gmsh::mesh_geo(&geo, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(err, GmshError::SystemCall { line: 1, .. }), "{err}");
    let fake = write(&dir, "fake.msh", &call);
    let err = gmsh::read_msh(&fake, false).unwrap_err();
    assert!(matches!(err, GmshError::NotMsh { .. }), "{err}");
    let exit = write(&dir, "exit.geo", &square_with("Exit;"));
    let err = gmsh::mesh_geo(&exit, &MeshOptions::default(), false, false).unwrap_err();
    assert!(err.to_string().contains("uses Exit"), "{err}");
    assert!(!pwned.exists());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn geo_without_trailing_newline_keeps_last_statement() {
    let path = data("no_newline.geo");
    assert!(!std::fs::read(&path).unwrap().ends_with(b"\n"));
    let mesh = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap();
    let domain = mesh.group(2, "domain").expect("last statement read").tag;
    assert!(mesh.n_cells() > 0 && mesh.cell_tags.iter().all(|&t| t == domain));
}

#[test]
fn meshing_failures_are_errors() {
    for (file, words) in [("bowtie.geo", "recover the edge"), ("open_loop.geo", "closed loop")] {
        let err = gmsh::mesh_geo(&data(file), &MeshOptions::default(), false, false).unwrap_err();
        let GmshError::Meshing { message, .. } = &err else {
            panic!("{file}: expected a meshing error, got {err:?}");
        };
        assert!(message.contains(words), "{file}: {message}");
        assert!(err.to_string().starts_with("cannot mesh "), "{err}");
    }
    assert_eq!(mesh_square(2).n_points(), 81);
}

#[test]
fn unsupported_meshes_are_errors() {
    let dir = temp_dir("unsupported");
    let quads = write(&dir, "quads.geo", &square_with("Recombine Surface{1};"));
    let err = gmsh::mesh_geo(&quads, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(&err, GmshError::Unsupported { element, .. } if element.contains("Quadrilateral")), "{err}");
    let loose = "Point(5) = {2, 0, 0}; Point(6) = {3, 0, 0}; Line(5) = {5, 6};\n\
                 Physical Curve(\"loose\") = {5};";
    let detached = write(&dir, "detached.geo", &square_with(loose));
    let err = gmsh::mesh_geo(&detached, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(&err, GmshError::DetachedCurve { group, .. } if group == "loose"), "{err}");
    let empty = write(&dir, "points.geo", "Point(1) = {0, 0, 0};\n");
    let err = gmsh::mesh_geo(&empty, &MeshOptions::default(), false, false).unwrap_err();
    assert!(matches!(err, GmshError::NoTriangles { .. }), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn surfaces_without_group_have_tag_zero() {
    let dir = temp_dir("untagged");
    let text = std::fs::read_to_string(data("square.geo")).unwrap();
    let text = text.replace("Physical Surface(\"domain\") = {1};", "");
    let path = write(&dir, "untagged.geo", &text);
    let mesh = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap();
    assert_eq!(mesh.n_cells(), 32);
    assert!(mesh.cell_tags.iter().all(|&t| t == 0));
    assert!(mesh.group_names(2).is_empty());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn options_are_validated_and_applied() {
    let bad = MeshOptions { order: 3, ..MeshOptions::default() };
    let err = gmsh::mesh_geo(&data("quarter_disk.geo"), &bad, false, false).unwrap_err();
    assert_eq!(err.to_string(), "invalid mesh option order = 3: expected 1 or 2");
    let coarse = gmsh::mesh_geo(&data("quarter_disk.geo"), &order(1), false, false).unwrap();
    let fine = MeshOptions { size_factor: 0.5, ..MeshOptions::default() };
    let fine = gmsh::mesh_geo(&data("quarter_disk.geo"), &fine, false, false).unwrap();
    assert!(fine.n_cells() > 3 * coarse.n_cells());
    let capped = MeshOptions { size_max: Some(0.05), ..MeshOptions::default() };
    let capped = gmsh::mesh_geo(&data("quarter_disk.geo"), &capped, false, false).unwrap();
    assert!((0..capped.n_cells()).all(|c| capped.cell_diameter(c) < 0.05 * 1.5));
    // a size set by the file is kept, and does not leak into the next session
    let dir = temp_dir("options");
    let text = std::fs::read_to_string(data("quarter_disk.geo")).unwrap();
    let path = write(&dir, "small.geo", &format!("{text}Mesh.MeshSizeMax = 0.05;\n"));
    let small = gmsh::mesh_geo(&path, &MeshOptions::default(), false, false).unwrap();
    assert_eq!(small.n_cells(), capped.n_cells());
    let again = gmsh::mesh_geo(&data("quarter_disk.geo"), &order(1), false, false).unwrap();
    assert_eq!(again.n_cells(), coarse.n_cells());
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn parallel_sessions_do_not_interfere() {
    let threads: Vec<_> = (0..8).map(|i| std::thread::spawn(move || mesh_square(1 + i % 2))).collect();
    for (i, thread) in threads.into_iter().enumerate() {
        let mesh = thread.join().unwrap();
        let expected = if i % 2 == 0 { 25 } else { 81 };
        assert_eq!((mesh.n_points(), mesh.n_cells()), (expected, 32), "thread {i}");
    }
}
