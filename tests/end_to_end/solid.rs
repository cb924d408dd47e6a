//! `damfem` on solids (geometries with volumes): mesh, check and solve work; the commands and
//! keys of plane sections are refused by name.

use crate::support::{assert_ok, assert_refused, check_warnings, damfem, edited_scene, repo, stderr, TempDir};
use std::ffi::OsStr;

/// Source: geo/monolith.toml, the Scene A section extruded by 15 m on a rock block, rollers
/// u_y = 0 on both sides (plane strain).
/// Goal: `solve` writes the tetrahedra and the boundary triangles with the displacement and
/// the stresses, and a summary of a 3-D P1 mesh (tests/python/test_solid_vtu.py reads them
/// back).
/// Parameters: the scene's P1 mesh.
#[test]
fn a_monolith_solves_in_plane_strain() {
    let tmp = TempDir::new("monolith");
    let out = tmp.join("out");
    let run = damfem(&[OsStr::new("solve"), repo("geo/monolith.toml").as_os_str(), OsStr::new("-o"), out.as_os_str()]);
    assert_ok(&run);
    assert!(stderr(&run).contains("3-D:") && stderr(&run).contains("tetrahedra"), "{}", stderr(&run));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!((summary["dimension"].as_u64(), summary["order"].as_u64()), (Some(3), Some(1)));
    assert!(summary["max_displacement"].as_f64().unwrap() > 1e-4, "{summary}");
    let reactions = summary["reactions"].as_object().expect("reactions by surface");
    let names: Vec<&str> = reactions.keys().map(String::as_str).collect();
    assert_eq!(names, ["rock_base", "rock_ends", "rock_sides", "sides"], "{summary}");
    let vtu = std::fs::read_to_string(out.join("monolith.vtu")).unwrap();
    for name in ["displacement", "sigma_zz", "sigma_xz", "von_mises", "sigma_3"] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "no {name}");
    }
    assert!(out.join("monolith_boundary.vtu").exists());
}

/// Goal: `mesh` and `check` take a solid; `check` names each surface's role and area.
#[test]
fn mesh_and_check_take_a_solid() {
    let tmp = TempDir::new("valley");
    let out = tmp.join("out");
    let scene = repo("geo/valley.toml");
    assert_ok(&damfem(&[OsStr::new("mesh"), scene.as_os_str(), OsStr::new("-o"), out.as_os_str()]));
    assert!(out.join("valley.msh").exists() && out.join("valley_mesh.vtu").exists());
    let check = damfem(&[OsStr::new("check"), scene.as_os_str()]);
    assert_ok(&check);
    let text = String::from_utf8_lossy(&check.stdout);
    assert!(text.contains("surface  upstream") && text.contains("area 2100.0000"), "{text}");
    assert!(text.contains("region   rock") && text.contains(": ok"), "{text}");
}

/// A scene edit: its name, the edit of geo/block3d.toml, the keywords of its error.
type Edit = (&'static str, fn(String) -> String, &'static [&'static str]);

/// Goal: what a solid does not have yet is refused in one sentence naming the command, flag
/// or key, and no output is left: `adapt` and `safety`, `--estimate` and `--friction`, a
/// contact role, load combinations, a vector of two or four components, supports that leave
/// a rigid motion free (the block without its roller along y), a load on a surface inside the
/// solid (tests/data/two_blocks.toml), two tables naming one volume, and `fix = "z"` in a plane
/// scene.
#[test]
fn what_a_solid_does_not_have_is_refused_by_name() {
    let scene = repo("geo/block3d.toml");
    for command in ["adapt", "safety"] {
        assert_refused(&format!("solid-{command}"), command, &scene, &[], &["block3d.geo", "3-D", "plane sections"]);
    }
    assert_refused("solid-estimate", "solve", &scene, &["--estimate"], &["--estimate", "solid"]);
    assert_refused("solid-friction", "solve", &scene, &["--friction", "0.7"], &["--friction", "solid"]);
    let section = repo("geo/scene_a.toml");
    assert_refused(
        "plane-iterative",
        "solve",
        &section,
        &["--solver", "iterative"],
        &["--solver iterative", "plane section"],
    );
    let tmp = TempDir::new("solid-keys");
    let edits: [Edit; 5] = [
        (
            "loose",
            |s| s.replace("[boundary.ymin]\nrole = \"dirichlet\"\nfix = \"y\"", "[boundary.ymin]\nrole = \"free\""),
            &["'block'", "a translation along y"],
        ),
        (
            "contact",
            |s| s.replace("[boundary.xmax]\nrole = \"free\"", "[boundary.xmax]\nrole = \"contact\""),
            &["boundary.xmax", "contact"],
        ),
        ("combined", |s| s + "\n[combinations.heavy]\nloads = { gravity = 9.81 }\n", &["[combinations]", "solid"]),
        (
            "two",
            |s| s.replace("traction = [0.0, 0.0, -1.0e6]", "traction = [0.0, -1.0e6]"),
            &["boundary.top.traction", "2 components", "give 3"],
        ),
        (
            "four",
            |s| s.replace("traction = [0.0, 0.0, -1.0e6]", "traction = [0.0, 0.0, 0.0, -1.0e6]"),
            &["boundary.top.traction", "4 components"],
        ),
    ];
    for (name, edit, keywords) in edits {
        let edited = edited_scene(&tmp, "block3d", edit);
        let moved = tmp.join(&format!("{name}.toml"));
        std::fs::rename(&edited, &moved).unwrap();
        assert_refused(&format!("solid-{name}"), "solve", &moved, &[], keywords);
    }
    let interior = repo("tests/data/two_blocks.toml");
    assert_refused("solid-interior", "solve", &interior, &[], &["boundary.middle", "inside the solid"]);
    let twice = edited_scene(&tmp, "block3d", |s| s + "\n[materials.BLOCK]\nE = 1.0e10\nnu = 0.2\nrho = 2400.0\n");
    assert_refused(
        "solid-twice",
        "solve",
        &twice,
        &[],
        &["[materials.block]", "[materials.BLOCK]", "same physical volume"],
    );
    let plane = edited_scene(&tmp, "scene_a", |s| {
        s.replace("[boundary.toe]\nrole = \"dirichlet\"", "[boundary.toe]\nrole = \"dirichlet\"\nfix = \"z\"")
    });
    assert_refused("plane-z", "solve", &plane, &[], &["boundary.toe.fix", "\"z\"", "plane section"]);
}

/// Source: geo/block3d.toml, whose exact solution is linear.
/// Goal: a degree-1 .msh of tetrahedra that `mesh.order = 2` asks for is raised to degree 2 as
/// gmsh raises it (the nodes of gmsh's own degree-2 mesh, 1 462) and solved exactly; a
/// degree-2 .msh asked for degree 1 is refused, naming the key.
#[test]
fn a_degree_one_msh_of_a_solid_is_raised_to_degree_two() {
    let tmp = TempDir::new("solid-msh");
    let (p1, p2) = (tmp.join("p1"), tmp.join("p2"));
    for (dir, order) in [(&p1, "1"), (&p2, "2")] {
        let scene = repo("geo/block3d.toml");
        let args = [OsStr::new("mesh"), scene.as_os_str(), OsStr::new("--order"), OsStr::new(order), OsStr::new("-q")];
        assert_ok(&damfem(&[&args[..], &[OsStr::new("-o"), dir.as_os_str()]].concat()));
    }
    let body = std::fs::read_to_string(repo("geo/block3d.toml")).unwrap();
    let raised = tmp.join("raised.toml");
    let msh = p1.join("block3d.msh").display().to_string();
    std::fs::write(&raised, body.replace("geometry = \"block3d.geo\"", &format!("geometry = {msh:?}"))).unwrap();
    let out = tmp.join("out");
    assert_ok(&damfem(&[OsStr::new("solve"), raised.as_os_str(), OsStr::new("-q"), OsStr::new("-o"), out.as_os_str()]));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!((summary["order"].as_u64(), summary["nodes"].as_u64()), (Some(2), Some(1462)), "{summary}");
    // u at (2, 1, 1): (2ν, ν, −1) q/E, ν = 0.2, q/E = 1e6/3e10
    let exact = (1e6 / 3e10) * (0.16f64 + 0.04 + 1.0).sqrt();
    assert!((summary["max_displacement"].as_f64().unwrap() - exact).abs() < 1e-12 * exact, "{summary}");
    let lowered = tmp.join("lowered.toml");
    let msh = p2.join("block3d.msh").display().to_string();
    let body =
        body.replace("geometry = \"block3d.geo\"", &format!("geometry = {msh:?}")).replace("order = 2", "order = 1");
    std::fs::write(&lowered, body).unwrap();
    assert_refused("solid-lowered", "solve", &lowered, &[], &["mesh.order = 1", "degree-2 tetrahedra", "not lowered"]);
}

/// Source: geo/monolith.toml in P2 (21 656 unknowns), solved by CG with GAMG.
/// Goal: the iterative solve on a team of two processes (this one and a worker it starts)
/// gives the solution of the solve on one process (RAYON_NUM_THREADS = 1): the same max |u|
/// and reactions to 10⁻⁸ (each solve is to a relative residual of 10⁻¹⁰); the summary and the
/// progress name the processes.
/// Parameters: `--order 2 --solver iterative`, 1 and 2 threads.
#[test]
fn two_processes_solve_as_one() {
    let (tmp, scene) = (TempDir::new("team"), repo("geo/monolith.toml"));
    let summary = |threads: &str| {
        let out = tmp.join(threads);
        let args = [OsStr::new("solve"), scene.as_os_str(), OsStr::new("-o"), out.as_os_str()];
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_damfem"))
            .args(args)
            .args(["--order", "2", "--solver", "iterative"])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert_ok(&run);
        let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
        (serde_json::from_str::<serde_json::Value>(&text).unwrap(), stderr(&run))
    };
    let ((one, _), (two, log)) = (summary("1"), summary("2"));
    assert_eq!((one["processes"].as_u64(), two["processes"].as_u64()), (Some(1), Some(2)), "{log}");
    assert!(log.contains("on 2 processes"), "{log}");
    let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-8 * scale;
    let u = one["max_displacement"].as_f64().unwrap();
    assert!(close(u, two["max_displacement"].as_f64().unwrap(), u), "{one} {two}");
    let reactions = |s: &serde_json::Value| -> Vec<f64> {
        let by_surface = s["reactions"].as_object().unwrap().values();
        by_surface.flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<_>>()).collect()
    };
    let (r1, r2) = (reactions(&one), reactions(&two));
    let scale = r1.iter().fold(0.0f64, |m, r| m.max(r.abs()));
    assert!(r1.iter().zip(&r2).all(|(&a, &b)| close(a, b, scale)), "{r1:?} {r2:?}");
}

/// Source: geo/monolith.toml with the rock's material and the crest's table taken out.
/// Goal: `check` and `solve` on a solid warn, as on a section, of a volume without a material
/// (naming the default it gets) and of a boundary surface without a role (traction-free);
/// the scene as shipped has no warning.
/// Parameters: the scene's P1 mesh.
#[test]
fn a_solid_warns_of_what_it_takes_by_default() {
    let tmp = TempDir::new("solid-warnings");
    assert_eq!(check_warnings(&repo("geo/monolith.toml"), &[]), Vec::<String>::new());
    let scene = edited_scene(&tmp, "monolith", |s| {
        let s = s.replace("[materials.rock]\nE = 2.0e10\nnu = 0.25\nrho = 2600.0\n", "");
        s.replace("[boundary.crest]\nrole = \"free\"\n", "")
    });
    let warnings = check_warnings(&scene, &[]);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings.iter().any(|w| w.contains("volume 'rock' has no material") && w.contains("default concrete")));
    assert!(warnings.iter().any(|w| w.contains("boundary surface 'crest' has no role")), "{warnings:?}");
    let out = tmp.join("out");
    let run = damfem(&[OsStr::new("solve"), scene.as_os_str(), OsStr::new("-o"), out.as_os_str()]);
    assert_ok(&run);
    assert!(stderr(&run).contains("warning: volume 'rock' has no material"), "{}", stderr(&run));
}

/// Source: geo/monolith.toml and geo/block3d.toml, meshed by gmsh.
/// Goal: the estimate of a solid's tetrahedra before meshing (the bounding box in regular
/// tetrahedra of the curves' mean segment, measured in 3D) bounds the count gmsh makes from
/// above, by at most 4 times, so that the cell limit refuses what is too large and no more.
/// Parameters: `--size-factor 0.5`; `--max-cells 1` to have the estimate printed.
#[test]
fn the_estimate_of_a_solid_bounds_its_tetrahedra_closely() {
    let tmp = TempDir::new("solid-estimate");
    for scene in ["geo/monolith.toml", "geo/block3d.toml"] {
        let (out, path) = (tmp.join("out"), repo(scene));
        let mesh = |extra: &[&str]| {
            let mut args = vec![OsStr::new("mesh"), path.as_os_str(), OsStr::new("-o"), out.as_os_str()];
            args.extend(["--size-factor", "0.5"].iter().chain(extra).map(OsStr::new));
            stderr(&damfem(&args))
        };
        let count = |text: &str, before: &str| -> f64 {
            let at = text.find(" tetrahedra").unwrap_or_else(|| panic!("{text}"));
            let word = text[..at].rsplit(before).next().unwrap();
            word.parse().unwrap_or_else(|_| panic!("{word:?} in {text}"))
        };
        let estimate = count(&mesh(&["--max-cells", "1"]), "about ");
        let made = count(&mesh(&[]), " ");
        assert!(made <= estimate && estimate <= 4.0 * made, "{scene}: estimate {estimate:e}, made {made}");
    }
}
