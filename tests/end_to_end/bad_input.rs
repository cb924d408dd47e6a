//! End-to-end tests of bad input to the `damfem` binary: one test per kind (one-line error
//! naming the file, group, key or flag at fault, no panic, no output left behind).

use super::support::{
    assert_error, assert_nothing_written, assert_ok, assert_refused, assert_solve_fails, check_warnings, damfem,
    edited_scene, fixture, repo, stderr, TempDir,
};
use std::ffi::OsStr;
use std::path::Path;

// (a) A missing scene file is named in the error.
#[test]
fn missing_scene_file() {
    let scene = repo("geo/no_such_scene.toml");
    assert_solve_fails("missing", &scene, &["no_such_scene.toml", "not found"]);
}

// (a) A scene whose geometry is missing names the geometry file.
#[test]
fn missing_geometry_file() {
    let scene = fixture("missing_geometry.toml");
    assert_solve_fails("missing-geometry", &scene, &["no_such_geometry.geo", "not found"]);
}

// (b) A .geo syntax error shows gmsh's message with the file and line.
#[test]
fn geo_syntax_error() {
    let geo = fixture("syntax_error.geo");
    assert_solve_fails("syntax", &geo, &["syntax_error.geo", "line 3", "syntax error"]);
}

// (c) A boundary naming an absent physical group lists the groups that exist.
#[test]
fn unknown_physical_group() {
    let scene = fixture("unknown_group.toml");
    assert_solve_fails("group", &scene, &["unknown_group.toml", "'heel'", "bottom, right, top, left"]);
}

// (d) A scene without a Dirichlet boundary is refused.
#[test]
fn no_dirichlet_boundary() {
    let scene = fixture("no_dirichlet.toml");
    assert_solve_fails("dirichlet", &scene, &["no_dirichlet.toml", "no Dirichlet"]);
}

// (e) E <= 0 is refused, naming the material and E.
#[test]
fn non_positive_young_modulus() {
    let scene = fixture("zero_young.toml");
    assert_solve_fails("young", &scene, &["zero_young.toml", "'domain'", "E = 0", "positive"]);
}

// (e) nu = 0.5 is refused, naming the material and nu.
#[test]
fn poisson_ratio_out_of_range() {
    let scene = fixture("poisson_half.toml");
    assert_solve_fails("poisson", &scene, &["poisson_half.toml", "'domain'", "nu = 0.5", "(-1, 0.5)"]);
}

// (f) An unknown scene key is named with its line.
#[test]
fn unknown_scene_key() {
    let scene = fixture("unknown_key.toml");
    assert_solve_fails("key", &scene, &["unknown_key.toml", "line 6", "gravty"]);
}

// (g) An output directory that cannot be created is named in the error.
#[test]
fn unwritable_output_directory() {
    let scene = repo("geo/unit_square.toml");
    let proc_dir = Path::new("/proc/damfem-test");
    let out = damfem(&["solve".as_ref(), "-q".as_ref(), scene.as_os_str(), "-o".as_ref(), proc_dir.as_os_str()]);
    assert_error(&out, &["/proc/damfem-test", "output directory"]);
    assert!(!proc_dir.exists());

    let tmp = TempDir::new("unwritable");
    std::fs::write(tmp.join("file"), "").unwrap();
    let below_file = tmp.join("file").join("out");
    let out = damfem(&["solve".as_ref(), "-q".as_ref(), scene.as_os_str(), "-o".as_ref(), below_file.as_os_str()]);
    assert_error(&out, &["file/out", "output directory"]);
    let names: Vec<_> = std::fs::read_dir(&tmp.0).unwrap().collect();
    assert_eq!(names.len(), 1, "only the regular file may remain");
}

// (h) A geometry gmsh cannot mesh shows gmsh's message, for solve and for mesh.
#[test]
fn unmeshable_geometry() {
    let geo = fixture("unmeshable.geo");
    assert_solve_fails("unmeshable", &geo, &["cannot mesh", "unmeshable.geo", "recover the edge"]);
    let tmp = TempDir::new("unmeshable-mesh");
    let out_dir = tmp.join("out");
    let out = damfem(&["mesh".as_ref(), "-q".as_ref(), geo.as_os_str(), "-o".as_ref(), out_dir.as_os_str()]);
    assert_error(&out, &["cannot mesh", "unmeshable.geo"]);
    assert_nothing_written(&out_dir);
}

// (i) SystemCall in a .geo is refused unless --allow-system-calls, which then runs it.
#[test]
fn system_calls_need_permission() {
    let tmp = TempDir::new("system-call");
    let marker = tmp.join("pwned");
    let geo = tmp.join("system_call.geo");
    let body = std::fs::read_to_string(fixture("bare.geo")).unwrap();
    let call = format!("SystemCall \"touch {}\";\n", marker.display());
    std::fs::write(&geo, call + &body).unwrap();

    let message =
        assert_solve_fails("system-call-refused", &geo, &["system_call.geo", "line 1", "--allow-system-calls"]);
    assert!(message.contains("SystemCall"), "{message}");
    assert!(!marker.exists(), "the SystemCall ran without permission");

    let out_dir = tmp.join("out");
    let out = damfem(&[
        "solve".as_ref(),
        "-q".as_ref(),
        "--allow-system-calls".as_ref(),
        geo.as_os_str(),
        "-o".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert_ok(&out);
    assert!(marker.exists(), "--allow-system-calls did not run the SystemCall");
}

// `damfem mesh` of a geometry without triangles fails and leaves no .msh behind.
#[test]
fn mesh_without_triangles_leaves_nothing() {
    let tmp = TempDir::new("no-surface");
    let out_dir = tmp.join("out");
    let geo = fixture("no_surface.geo");
    let out = damfem(&["mesh".as_ref(), "-q".as_ref(), geo.as_os_str(), "-o".as_ref(), out_dir.as_os_str()]);
    assert_error(&out, &["no_surface.geo", "no triangles"]);
    assert_nothing_written(&out_dir);
}

// Dirichlet conditions that leave a rigid motion free (u_x fixed everywhere) are refused.
#[test]
fn rigid_motion_left_free() {
    let scene = fixture("only_x_fixed.toml");
    assert_solve_fails("rigid", &scene, &["only_x_fixed.toml", "rigid"]);
}

// A bare .geo without Dirichlet curve explains the naming convention (Gamma_D), not scene syntax.
#[test]
fn bare_geo_without_dirichlet_names_the_convention() {
    let tmp = TempDir::new("bare-no-dirichlet");
    let geo = tmp.join("no_gamma_d.geo");
    let body = std::fs::read_to_string(fixture("bare.geo")).unwrap();
    std::fs::write(&geo, body.replace("\"Gamma_D\"", "\"bottom\"")).unwrap();
    assert_solve_fails("bare-no-dirichlet-out", &geo, &["no Dirichlet", "Gamma_D"]);
}

// --order 1 on a degree-2 .msh input is refused (it would drop the midpoint nodes), never
// silently ignored; raising a degree-1 .msh is tested in tests/python/test_msh.py.
#[test]
fn order_option_on_msh_input() {
    let tmp = TempDir::new("msh-order");
    let geo = fixture("bare.geo");
    let mesh_dir = tmp.join("mesh");
    assert_ok(&damfem(&["mesh".as_ref(), "-q".as_ref(), geo.as_os_str(), "-o".as_ref(), mesh_dir.as_os_str()]));
    let msh = mesh_dir.join("bare.msh");
    let out_dir = tmp.join("out");
    let out = damfem(&[
        "solve".as_ref(),
        "-q".as_ref(),
        "--order".as_ref(),
        "1".as_ref(),
        msh.as_os_str(),
        "-o".as_ref(),
        out_dir.as_os_str(),
    ]);
    assert_error(&out, &["--order 1", "bare.msh", "not lowered"]);
    assert_nothing_written(&out_dir);
}

// A contact direction that is zero, or that points into the body on a contact curve, is refused
// with the key and the curve named.
#[test]
fn bad_contact_direction() {
    let tmp = TempDir::new("bad-direction");
    let hertz = std::fs::read_to_string(repo("geo/hertz.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/hertz.geo").display().to_string());
    let hertz = hertz.replace("geometry = \"hertz.geo\"", &geometry);
    for (name, direction, expected) in [
        ("zero", "[0.0, 0.0]", ["contact.direction", "non-zero"]),
        ("upwards", "[0.0, 1.0]", ["contact.direction", "'Gamma_C'"]),
    ] {
        let scene = tmp.join(&format!("{name}.toml"));
        std::fs::write(&scene, hertz.replace("direction = [0.0, -1.0]", &format!("direction = {direction}"))).unwrap();
        let message = assert_solve_fails(&format!("bad-direction-{name}"), &scene, &expected);
        assert!(message.contains(&format!("{name}.toml")), "{message}");
    }
}

// The [contact] keys that only `damfem solve` reads are refused by `damfem adapt`, which
// chooses δ itself, rather than ignored.
#[test]
fn adapt_refuses_the_keys_of_solve() {
    let tmp = TempDir::new("adapt-solve-keys");
    let text = std::fs::read_to_string(repo("geo/scene_a.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/scene_a.geo").display().to_string());
    let text = text.replace("geometry = \"scene_a.geo\"", &geometry);
    for (line, expected) in [
        ("delta = 1.0", ["contact.delta", "damfem solve", "adapt.delta0"]),
        ("delta_start = 0.1", ["contact.delta_start", "damfem solve", "adapt.delta0"]),
        ("projection = \"semismooth\"", ["contact.projection", "damfem solve", "adapt.delta0"]),
    ] {
        let key = expected[0];
        let scene = tmp.join("scene.toml");
        std::fs::write(&scene, text.replace("[contact]", &format!("[contact]\n{line}"))).unwrap();
        let out = tmp.join("out");
        let result = damfem(&[OsStr::new("adapt"), scene.as_os_str(), OsStr::new("-o"), out.as_os_str()]);
        assert_error(&result, &expected);
        assert!(!out.join("history.json").exists(), "{key}: no output");
    }
}

// Contact on the interface between two meshed surfaces (a dam on a meshed rock block) is
// refused, saying to give the curve a [joints] table for a joint or to remove the role for a
// bonded interface; with a bare geometry, to rename the curve.
#[test]
fn contact_between_two_meshed_bodies() {
    let scene = fixture("interior_contact.toml");
    let message = assert_refused("interior-contact", "solve", &scene, &[], &["interior_contact.toml", "'joint'"]);
    for words in ["'concrete' and 'rock'", "[joints.joint]", "remove its role", "bonded"] {
        assert!(message.contains(words), "{words:?} not in {message}");
    }
    let tmp = TempDir::new("interior-contact-bare");
    let geo = tmp.join("dam_on_rock.geo");
    let body = std::fs::read_to_string(repo("geo/scene_b.geo")).unwrap();
    let body = body.replace("\"joint\"", "\"Gamma_C\"").replace("\"rock_bottom\"", "\"Gamma_D\"");
    std::fs::write(&geo, body).unwrap();
    assert_refused("interior-contact-bare-out", "check", &geo, &[], &["'Gamma_C'", "rename the curve"]);
}

// Non-finite scene numbers and vectors with three components are refused with their key.
#[test]
fn non_finite_numbers_and_long_vectors() {
    let level = fixture("level_nan.toml");
    assert_refused(
        "level-nan",
        "solve",
        &level,
        &[],
        &["level_nan.toml", "boundary.upstream.hydrostatic.level", "finite"],
    );
    let traction = fixture("traction_3d.toml");
    assert_refused("traction-3d", "solve", &traction, &[], &["boundary.upstream.traction", "3 components"]);
    let tmp = TempDir::new("gravity-inf");
    let scene = tmp.join("gravity.toml");
    let body = std::fs::read_to_string(fixture("level_nan.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/scene_a.geo").display().to_string());
    let body = body.replace("geometry = \"../../../geo/scene_a.geo\"", &geometry);
    std::fs::write(&scene, body.replace("level = nan", "level = 70.0") + "\n[loads]\ngravity = inf\n").unwrap();
    assert_refused("gravity-inf-out", "solve", &scene, &[], &["loads.gravity = inf", "finite"]);
}

// One curve in two physical groups with different roles is refused, naming both groups.
#[test]
fn one_curve_with_two_roles() {
    let scene = fixture("two_roles.toml");
    assert_refused("two-roles", "check", &scene, &[], &["'base' (dirichlet)", "'loaded' (neumann)", "share a segment"]);
}

// mesh.size_min above mesh.size_max is refused, naming both keys.
#[test]
fn size_min_above_size_max() {
    let scene = fixture("size_min_above_max.toml");
    assert_refused("size-order", "mesh", &scene, &[], &["mesh.size_min = 5", "mesh.size_max = 1"]);
}

// A folded .msh (a node moved across an edge, so that triangles overlap) and a .msh with a
// duplicate node tag are refused; the same mesh unfolded is read.
#[test]
fn folded_or_duplicate_msh() {
    assert_ok(&damfem(&["check".as_ref(), "-q".as_ref(), fixture("square.msh").as_os_str()]));
    assert_refused("folded", "solve", &fixture("folded.msh"), &[], &["folded.msh", "folded", "(1.5, 0.5)"]);
    assert_refused("duplicate", "solve", &fixture("duplicate_node.msh"), &[], &["duplicate node 5", "own tag"]);
}

// A .msh with z != 0 and no volume is neither a section nor a solid: refused, naming z.
#[test]
fn a_tilted_plane_is_refused() {
    let tmp = TempDir::new("tilted");
    let msh = tmp.join("tilted.msh");
    let body = std::fs::read_to_string(fixture("square.msh")).unwrap();
    std::fs::write(&msh, body.replace("\n4 0 1 0\n", "\n4 0 1 0.5\n")).unwrap();
    assert_refused("tilted-out", "solve", &msh, &[], &["tilted.msh", "not plane", "z ranges"]);
}

// A directory given as the scene or as the scene's geometry says "is a directory".
#[test]
fn directory_as_geometry() {
    let tmp = TempDir::new("directory");
    let dir = tmp.join("dam.geo");
    std::fs::create_dir_all(&dir).unwrap();
    assert_refused("directory-scene", "check", &dir, &[], &["dam.geo", "is a directory"]);
    let scene = tmp.join("scene.toml");
    std::fs::write(&scene, "geometry = \"dam.geo\"\n").unwrap();
    assert_refused("directory-geometry", "solve", &scene, &[], &["dam.geo", "is a directory"]);
}

// Absurd sizes are refused before gmsh meshes: the estimated cell count against the limit,
// which --max-cells raises or lowers; coordinates of 1e300 against the coordinate limit.
// Each case ends in bounded time.
#[test]
fn absurd_sizes_and_coordinates() {
    let start = std::time::Instant::now();
    let scene = repo("geo/scene_a.toml");
    assert_refused("factor", "solve", &scene, &["--size-factor", "1e-9"], &["scene_a.geo", "triangles", "--max-cells"]);
    assert_refused("limit", "mesh", &scene, &["--max-cells", "100"], &["limit of 100"]);
    let tmp = TempDir::new("sizes");
    let tiny = tmp.join("tiny.geo");
    let body = std::fs::read_to_string(fixture("bare.geo")).unwrap();
    std::fs::write(&tiny, body.replace("0.25}", "1e-12}")).unwrap();
    assert_refused("tiny-out", "check", &tiny, &[], &["tiny.geo", "triangles"]);
    let far = tmp.join("far.geo");
    std::fs::write(&far, body.replace("{2, 0, 0", "{1e300, 0, 0")).unwrap();
    assert_refused("far-out", "check", &far, &[], &["far.geo", "beyond the limit"]);
    assert!(start.elapsed().as_secs() < 60, "took {:?}", start.elapsed());
    let out = damfem(&["check".as_ref(), "-q".as_ref(), scene.as_os_str(), "--max-cells".as_ref(), "3000000".as_ref()]);
    assert_ok(&out);
}

// A .geo whose reading never ends (a loop of 10⁹ iterations) stops at the gmsh time limit
// with one error naming the file and --mesh-time-limit, in every command that meshes, and
// leaves no output directory; a limit longer than 5 s is stated once gmsh has worked 5 s; a
// limit of 0 s is refused.
#[test]
fn endless_geo_stops_at_the_time_limit() {
    let tmp = TempDir::new("endless");
    let geo = tmp.join("endless.geo");
    let body = std::fs::read_to_string(fixture("bare.geo")).unwrap();
    std::fs::write(&geo, format!("For i In {{1:1000000000}}\n  x = i;\nEndFor\n{body}")).unwrap();
    for command in ["mesh", "check", "solve", "adapt"] {
        let start = std::time::Instant::now();
        let keywords = ["endless.geo", "time limit of 1 s", "--mesh-time-limit"];
        assert_refused(&format!("endless-{command}"), command, &geo, &["--mesh-time-limit", "1"], &keywords);
        assert!(start.elapsed().as_secs() < 20, "{command} took {:?}", start.elapsed());
    }
    // a limit beyond the notice's delay is stated while gmsh works, then the limit ends it
    let out = damfem(&["check".as_ref(), geo.as_os_str(), "--mesh-time-limit".as_ref(), "7".as_ref()]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    let note = "gmsh is still reading and meshing";
    assert!(err.contains(note) && err.contains("stopped at 7 s") && err.contains("time limit of 7 s"), "{err}");
    let scene = repo("geo/scene_a.toml");
    assert_refused("time-limit-zero", "check", &scene, &["--mesh-time-limit", "0"], &["--mesh-time-limit 0"]);
    assert_ok(&damfem(&[
        "check".as_ref(),
        "-q".as_ref(),
        scene.as_os_str(),
        "--mesh-time-limit".as_ref(),
        "5".as_ref(),
    ]));
}

// `check` warns about boundary curves without a role and surfaces without a material (with the
// defaults assumed), not about bonded interior curves; --strict makes them one error.
#[test]
fn check_warns_about_defaults_and_strict_refuses() {
    let scene_b = repo("geo/scene_b.toml");
    let warnings = check_warnings(&scene_b, &[]);
    for curve in ["'downstream'", "'crest'", "'ground'"] {
        assert!(warnings.iter().any(|w| w.contains(curve) && w.contains("traction-free")), "{curve}: {warnings:?}");
    }
    assert!(!warnings.iter().any(|w| w.contains("'joint'") || w.contains("'bonded'")), "{warnings:?}");
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert_refused("strict", "check", &scene_b, &["--strict"], &["scene_b.toml", "--strict", "'crest'", "'ground'"]);
    let bare = check_warnings(&fixture("bare.geo"), &[]);
    assert!(bare.iter().any(|w| w.contains("surface 'block' has no material") && w.contains("E = 3e10")), "{bare:?}");
    assert!(check_warnings(&repo("geo/scene_a.toml"), &[]).is_empty());
}

// `check` warns when gamma0 is below the range where Nitsche's method is known to be stable
// for theta = 0 (not for theta = -1), and when P1 meets nu > 0.45 (not P2).
#[test]
fn check_warns_about_unstable_parameters() {
    let tmp = TempDir::new("parameters");
    let small = edited_scene(&tmp, "scene_a", |s| s.replace("gamma0 = 100.0", "gamma0 = 0.001"));
    let warnings = check_warnings(&small, &["--order", "1"]);
    assert!(warnings.len() == 1 && warnings[0].contains("contact.gamma0 = 0.001"), "{warnings:?}");
    let skew = edited_scene(&tmp, "scene_a", |s| {
        s.replace("gamma0 = 100.0", "gamma0 = 0.001").replace("theta = 0.0", "theta = -1.0")
    });
    assert!(check_warnings(&skew, &["--order", "1"]).is_empty());
    let locking = edited_scene(&tmp, "unit_square", |s| s.replace("nu = 0.25", "nu = 0.49"));
    let warnings = check_warnings(&locking, &["--order", "1"]);
    assert!(warnings.len() == 1 && warnings[0].contains("nu = 0.49") && warnings[0].contains("P1"), "{warnings:?}");
    assert!(check_warnings(&locking, &["--order", "2"]).is_empty());
}

// A value given on the command line is blamed as the flag, not as the scene key it overrides;
// negative numbers are parsed as values and then checked.
#[test]
fn command_line_values_are_blamed_as_flags() {
    let scene = repo("geo/scene_a.toml");
    for (name, command, extra, flag, key) in [
        ("flag-gamma0", "solve", ["--gamma0", "-1"], "--gamma0 = -1", "contact.gamma0"),
        ("flag-theta", "solve", ["--theta", "2"], "--theta = 2", "contact.theta"),
        ("flag-delta", "solve", ["--delta", "-1e3"], "--delta = -1000", "contact.delta"),
        ("flag-bulk", "adapt", ["--bulk", "-0.5"], "--bulk = -0.5", "adapt.bulk"),
        ("flag-steps", "adapt", ["--steps", "0"], "--steps = 0", "adapt.steps"),
        ("flag-max-steps", "safety", ["--max-steps", "0"], "--max-steps = 0", "adapt.steps"),
        ("flag-tol-relative", "safety", ["--tol-relative", "-0.1"], "--tol-relative = -0.1", "adapt.tol_relative"),
    ] {
        let message = assert_refused(name, command, &scene, &extra, &[flag, "command line", key]);
        assert!(!message.contains("scene_a.toml"), "the scene is not at fault: {message}");
    }
}

// A Newton run that does not converge names the scene and the likely cause, lists a few
// residuals rather than all of them, and keeps them in history.json.
#[test]
fn solve_reports_a_newton_failure_and_keeps_the_residuals() {
    let tmp = TempDir::new("solve-newton");
    let scene = tmp.join("limited.toml");
    let text = std::fs::read_to_string(repo("geo/scene_a.toml")).unwrap();
    let geometry = format!("geometry = {:?}", repo("geo/scene_a.geo").display().to_string());
    let text = text.replace("geometry = \"scene_a.geo\"", &geometry);
    std::fs::write(&scene, text.replace("[contact]", "[contact]\nmax_iter = 12\nrtol = 1e-30")).unwrap();
    let out = tmp.join("out");
    let result = damfem(&[OsStr::new("solve"), OsStr::new("-q"), scene.as_os_str(), OsStr::new("-o"), out.as_os_str()]);
    let message = assert_error(&result, &["limited.toml", "12 step(s)", "contact.max_iter = 12", "history.json"]);
    assert!(message.contains("(6 more)"), "twelve residuals are shortened: {message}");
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("history.json")).unwrap()).unwrap();
    assert_eq!(history["relative_residuals"].as_array().unwrap().len(), 12);
    assert!(history["error"].as_str().unwrap().contains("Newton"));
    assert!(!out.join("summary.json").exists());
}

// An Include that reads a file being read already is named as a recursion, with the file and line.
#[test]
fn include_recursion_is_named() {
    let tmp = TempDir::new("include-recursion");
    std::fs::write(tmp.join("a.geo"), "Include \"b.geo\";\n").unwrap();
    std::fs::write(tmp.join("b.geo"), "Point(1) = {0, 0, 0};\nInclude \"a.geo\";\n").unwrap();
    assert_refused(
        "include-recursion-out",
        "mesh",
        &tmp.join("a.geo"),
        &[],
        &["b.geo: line 2", "\"a.geo\"", "recursion"],
    );
}

// A TOML error keeps its excerpt lines (indented under the error line); no line of an error is
// cut, however long.
#[test]
fn toml_errors_keep_their_lines_and_long_lines_whole() {
    let tmp = TempDir::new("toml-lines");
    let scene = tmp.join("unclosed.toml");
    std::fs::write(&scene, "[mesh]\norder = 1\nsize_factor = [\n1,\n").unwrap();
    let message = assert_refused("toml-lines-out", "check", &scene, &[], &["unclosed.toml", "line 4"]);
    assert!(message.lines().count() > 2, "the excerpt is kept: {message}");
    assert!(message.lines().any(|l| l.trim_start().starts_with("4 | 1,")), "{message}");
    let scene = tmp.join("long.toml");
    std::fs::write(&scene, format!("[mesh]\norder = \"{}\"\n", "x".repeat(5000))).unwrap();
    let message = assert_refused("toml-long-out", "check", &scene, &[], &["long.toml"]);
    assert!(message.contains(&"x".repeat(5000)), "{message}");
}
