//! End-to-end tests of the `damfem` binary: every scene of geo/, the mesh command, the help
//! texts, and one test per kind of bad input (one-line error, no panic, no output left behind).

use super::support::{
    assert_error, assert_nothing_written, assert_ok, assert_refused, assert_solve_fails, check_summary, check_warnings,
    damfem, edited_scene, fixture, hidden_files, repo, spawned_until, stderr, TempDir,
};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The scene files of geo/.
fn scenes() -> Vec<PathBuf> {
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(repo("geo"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenes.sort();
    assert!(!scenes.is_empty());
    scenes
}

// Every scene of geo/ passes `check`, which lists the curves and regions on stdout (and with
// -q prints nothing).
#[test]
fn every_scene_checks() {
    for scene in scenes() {
        let out = damfem(&["check".as_ref(), scene.as_os_str()]);
        assert_ok(&out);
        let table = String::from_utf8_lossy(&out.stdout);
        assert!(table.lines().last().is_some_and(|l| l.ends_with(": ok")), "{table}");
        assert!(table.lines().any(|l| l.starts_with("curve ")) && table.lines().any(|l| l.starts_with("region ")));
        let quiet = damfem(&["check".as_ref(), "-q".as_ref(), scene.as_os_str()]);
        assert_ok(&quiet);
        assert!(quiet.stdout.is_empty() && quiet.stderr.is_empty(), "{}", stderr(&quiet));
    }
}

// `damfem check` lists each load combination with its water and the uplift diagram at the
// heel, the drain line and the toe. Source: geo/dam_combinations.toml (base 47.6 m from x = 0
// to 47.6 at y = 0, drains 10 m from the heel, E = 0.66, tailwater 5 m; usual and earthquake
// 57 m, flood 61 m with the crest under water; earthquake 0.1 g, its crack rule unchanged).
// Expected: USACE EM 1110-2-2100 with the crack closed, H3 = H2 + (1 − E)(H1 − H2)(L − X)/L at
// the drain line, as ρ_w g × head, to the 5 digits printed; each combination's crack rule.
#[test]
fn check_lists_the_combinations_water_and_uplift() {
    let out = damfem(&["check".as_ref(), repo("geo/dam_combinations.toml").as_os_str()]);
    assert_ok(&out);
    let table = String::from_utf8_lossy(&out.stdout);
    let line = |kind: &str, case: &str| {
        let start = format!("{kind:<8} {case:<20} ");
        table.lines().find(|l| l.starts_with(&start)).unwrap_or_else(|| panic!("no {start:?} in {table}")).to_string()
    };
    let (l, x, e, h2) = (47.6, 10.0, 0.66, 5.0);
    let gamma_w = 1000.0 * 9.81;
    for (case, h1, acceleration) in
        [("scene", 57.0, 0.0), ("usual", 57.0, 0.0), ("flood", 61.0, 0.0), ("earthquake", 57.0, 0.1)]
    {
        let case = if case == "scene" { case.to_string() } else { format!("combination {case}") };
        let water = line("water", &case);
        assert!(water.contains(&format!("upstream {h1:.3} m")), "{water}");
        assert!(water.contains(&format!("downstream {h2:.3} m")), "{water}");
        assert_eq!(water.contains(&format!("crest {h1:.3} m")), h1 == 61.0, "{water}");
        assert!(water.ends_with(&format!("acceleration [{acceleration}, 0] g")), "{water}");
        let uplift = line("uplift", &case);
        let h3 = h2 + (1.0 - e) * (h1 - h2) * (l - x) / l;
        let rule = match acceleration == 0.0 {
            true => "full",
            false => "unchanged (that of the state before the earthquake, solved first)",
        };
        let expected = format!(
            "base: headwater {h1:.3} m, tailwater {h2:.3} m, crack {rule}; heel at s = 0.000 m (0.000, 0.000): p_u {:.4e} Pa; \
             drain line at s = 10.000 m (10.000, 0.000): p_u {:.4e} Pa, efficiency 0.66; toe at s = 47.600 m (47.600, \
             0.000): p_u {:.4e} Pa",
            gamma_w * h1,
            gamma_w * h3,
            gamma_w * h2
        );
        assert!(uplift.ends_with(&expected), "{uplift}\nagainst {expected}");
    }
}

// Every scene of geo/ solves and writes <stem>.vtu, <stem>_boundary.vtu and a sound summary.json.
#[test]
fn every_scene_solves() {
    for scene in scenes() {
        let stem = scene.file_stem().unwrap().to_str().unwrap();
        let tmp = TempDir::new(&format!("solve-{stem}"));
        let out = damfem(&["solve".as_ref(), "-q".as_ref(), scene.as_os_str(), "-o".as_ref(), tmp.0.as_os_str()]);
        assert_ok(&out);
        for file in [format!("{stem}.vtu"), format!("{stem}_boundary.vtu")] {
            assert!(tmp.join(&file).is_file(), "{stem}: no {file}");
        }
        check_summary(&tmp.0);
        assert!(hidden_files(&tmp.0).is_empty());
    }
}

// --order 1 and --size-factor override the scene: fewer nodes, P1 recorded in the summary.
#[test]
fn order_and_size_factor_override_the_scene() {
    let tmp = TempDir::new("order");
    let scene = repo("geo/scene_a.toml");
    let run = |dir: &str, extra: &[&str]| {
        let mut args: Vec<&OsStr> = vec!["solve".as_ref(), "-q".as_ref(), scene.as_os_str()];
        args.extend(extra.iter().map(OsStr::new));
        let out_dir = tmp.join(dir);
        args.extend(["-o".as_ref(), out_dir.as_os_str()]);
        assert_ok(&damfem(&args));
        check_summary(&out_dir)
    };
    let p2 = run("p2", &[]);
    let p1 = run("p1", &["--order", "1", "--size-factor", "2"]);
    assert_eq!(p2["order"], 2);
    assert_eq!(p1["order"], 1);
    assert!(p1["nodes"].as_u64() < p2["nodes"].as_u64());
}

// A bare .geo solves with the roles given by its curve names Gamma_D, Gamma_N, Gamma_C.
#[test]
fn bare_geo_solves_with_conventional_roles() {
    let tmp = TempDir::new("bare");
    let geo = fixture("bare.geo");
    let check = damfem(&["check".as_ref(), geo.as_os_str()]);
    assert_ok(&check);
    let roles = String::from_utf8_lossy(&check.stdout);
    for role in ["Gamma_D", "Dirichlet", "Gamma_N", "Neumann", "Gamma_C", "Contact"] {
        assert!(roles.contains(role), "{role} not in: {roles}");
    }
    let out = damfem(&["solve".as_ref(), "-q".as_ref(), geo.as_os_str(), "-o".as_ref(), tmp.0.as_os_str()]);
    assert_ok(&out);
    assert!(tmp.join("bare.vtu").is_file());
    assert!(check_summary(&tmp.0)["max_displacement"].as_f64().unwrap() > 0.0);
}

// `damfem mesh` writes the .msh and the mesh .vtu files, and no hidden temporary file.
#[test]
fn mesh_writes_msh_and_vtu() {
    let tmp = TempDir::new("mesh");
    let scene = repo("geo/scene_a.toml");
    let out = damfem(&["mesh".as_ref(), scene.as_os_str(), "-o".as_ref(), tmp.0.as_os_str()]);
    assert_ok(&out);
    let msh = tmp.join("scene_a.msh");
    assert!(std::fs::read_to_string(&msh).unwrap().starts_with("$MeshFormat"));
    assert!(String::from_utf8_lossy(&out.stdout).contains("scene_a.msh"));
    assert!(tmp.join("scene_a_mesh.vtu").is_file());
    assert!(tmp.join("scene_a_boundary.vtu").is_file());
    assert_eq!(hidden_files(&tmp.0), Vec::<String>::new());
}

// The help of the main command lists the subcommands; each subcommand's documents its options.
#[test]
fn help_texts() {
    let out = damfem(&["--help"]);
    assert_ok(&out);
    let main = String::from_utf8_lossy(&out.stdout);
    for command in ["mesh", "check", "solve", "adapt"] {
        assert!(main.contains(command), "{command} not in: {main}");
    }
    for command in ["mesh", "check", "solve", "adapt"] {
        let out = damfem(&[command, "--help"]);
        assert_ok(&out);
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(help.contains("--order"), "{command}: {help}");
        assert!(help.contains("--allow-system-calls"), "{command}: {help}");
        // `check` writes nothing, so only mesh and solve take an output directory
        if command != "check" {
            assert!(help.contains("--output"), "{command}: {help}");
        }
    }
    // strength reduction divides every joint's strength; `safety` reduces one plane's
    let solve =
        String::from_utf8_lossy(&damfem(&["solve", "--help"]).stdout).split_whitespace().collect::<Vec<_>>().join(" ");
    for words in ["every joint", "the weakest plane's", "damfem safety", "[safety] joint"] {
        assert!(solve.contains(words), "{words:?} not in: {solve}");
    }
}

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

/// `damfem adapt geo/scene_a.toml --order 1 --steps 3 [extra] -o dir`.
fn adapt_scene_a_p1(dir: &TempDir, extra: &[&str]) -> Output {
    let scene = repo("geo/scene_a.toml");
    let mut args = vec![OsStr::new("adapt"), scene.as_os_str()];
    args.extend(["--order", "1", "--steps", "3"].iter().chain(extra).map(OsStr::new));
    args.extend([OsStr::new("-o"), dir.0.as_os_str()]);
    damfem(&args)
}

#[test]
fn adapt_writes_every_step_its_history_and_figures() {
    let dir = TempDir::new("adapt");
    let out = adapt_scene_a_p1(&dir, &[]);
    assert_ok(&out);
    let progress = stderr(&out);
    assert_eq!(progress.lines().filter(|l| l.starts_with("step ")).count(), 3, "{progress}");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.lines().next().is_some_and(|l| l.contains("N_reg") && l.contains("N_lin")), "{table}");
    for step in 0..3 {
        for kind in ["", "_boundary", "_dg"] {
            assert!(dir.join(&format!("scene_a_{step:02}{kind}.vtu")).is_file(), "step {step}{kind}");
        }
    }
    for file in ["scene_a.pvd", "scene_a_boundary.pvd", "scene_a_dg.pvd"] {
        let pvd = std::fs::read_to_string(dir.join(file)).unwrap();
        assert_eq!(pvd.matches("<DataSet").count(), 3, "{file}");
    }
    let csv = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);
    assert!(csv.starts_with("step,cells,unknowns,eta_osc"));
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    assert!(steps[2]["unknowns"].as_u64() > steps[0]["unknowns"].as_u64());
    assert!(history["error"].is_null());
    for figure in ["scene_a_eta.svg", "scene_a_eta.png", "scene_a_time.svg", "scene_a_time.png"] {
        assert!(dir.join(figure).is_file(), "{figure}");
    }
    // the η axes carry their unit; each component keeps its palette slot (η_reg the 6th,
    // η_lin the 7th) whether or not the components before it are zero
    let svg = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    let (eta, time) = (svg("scene_a_eta.svg"), svg("scene_a_time.svg"));
    assert!(eta.contains("estimator [Pa m]") && time.contains("η_tot [Pa m]"));
    let last = &steps[2]["eta"];
    for (component, colour) in [("reg", "#8C564B"), ("lin", "#E377C2")] {
        assert!(last[component].as_f64().unwrap() > 0.0, "η_{component} = 0: {last}");
        assert!(eta.contains(&format!("stroke=\"{colour}\"")), "η_{component} not in {colour}");
    }
    assert!(hidden_files(&dir.0).is_empty());
}

#[test]
fn adapt_stops_when_the_largest_estimators_sit_at_the_smallest_size() {
    // Scene A with gmsh's smallest size 1 cm: the cells at the anchored toe cannot follow
    // the 4-fold shrinking that equidistribution asks of them at its corner
    let dir = TempDir::new("adapt-stall");
    let scene = std::fs::read_to_string(repo("geo/scene_a.toml")).unwrap();
    let geometry = repo("geo/scene_a.geo");
    let scene = scene
        .replace("geometry = \"scene_a.geo\"", &format!("geometry = {:?}", geometry.display().to_string()))
        .replace("[mesh]\n", "[mesh]\nsize_min = 0.01\n");
    std::fs::write(dir.join("stall.toml"), scene).unwrap();
    let out = damfem(&[
        OsStr::new("adapt"),
        dir.join("stall.toml").as_os_str(),
        OsStr::new("--order"),
        OsStr::new("1"),
        OsStr::new("--steps"),
        OsStr::new("10"),
        OsStr::new("-o"),
        dir.join("out").as_os_str(),
    ]);
    assert_ok(&out);
    let progress = stderr(&out);
    assert!(progress.contains("stopped after step") && progress.contains("smallest size 1.00e-2 m"), "{progress}");
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/history.json")).unwrap()).unwrap();
    let steps = history["steps"].as_array().unwrap();
    assert!(steps.len() < 10, "{} steps", steps.len());
    let (last, before) = steps.split_last().unwrap();
    assert!(before.iter().all(|s| s["stall"].is_null()));
    assert!(last["stall"]["cells"].as_u64().unwrap() >= 1 && last["stall"]["share"].as_f64().unwrap() >= 0.25);
}

/// The JSON file `path`.
fn json_file(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

/// The index of the step of smallest η_tot in `<dir>/history.json`, and every η_tot.
fn smallest_eta(dir: &Path) -> (usize, Vec<f64>) {
    let history = json_file(&dir.join("history.json"));
    let eta: Vec<f64> =
        history["steps"].as_array().unwrap().iter().map(|s| s["eta"]["tot"].as_f64().unwrap()).collect();
    ((0..eta.len()).min_by(|&a, &b| eta[a].total_cmp(&eta[b])).unwrap(), eta)
}

// An adaptive run whose last mesh is not its best. Source: geo/scene_a.toml with gmsh's
// smallest size 1.5 m, above every size of its .geo, so that the first mesh is uniform at that
// size and no cell can be refined, and adapt.bulk = 1 (equidistribution then aims at the same
// η_tot): the cells below the target are coarsened, by up to 2, and η_tot rises at every step
// (measured at P1: 7.88·10⁶, 8.36·10⁶, 9.36·10⁶, 1.05·10⁷ Pa m on 1 158, 380, 170, 100
// unknowns). Goal: `adapt` names the step of smallest η_tot of history.json on stderr with its
// VTU file; summary.json stays the last step's and its `best_step` gives that step's η_tot,
// unknowns, crack and resultant as history.json has them, and its file, which exists; `safety`
// on the same scene names it in safety.json and report.md; a run whose last step has the
// smallest η_tot (the file's scene) writes `best_step: null` and no line. Parameters: P1, four
// meshes (`safety`: three).
#[test]
fn adapt_and_safety_name_a_step_tighter_than_the_last() {
    let tmp = TempDir::new("best-step");
    let scene = edited_scene(&tmp, "scene_a", |s| {
        s.replace("[mesh]\n", "[mesh]\nsize_min = 1.5\n") + "\n[adapt]\nbulk = 1.0\n"
    });
    let run = |command: &str, steps: &[&str], scene: &Path, dir: &Path| {
        let mut args: Vec<&OsStr> =
            [command, "--order", "1"].into_iter().chain(steps.iter().copied()).map(OsStr::new).collect();
        args.extend([scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]);
        let out = damfem(&args);
        assert_ok(&out);
        stderr(&out)
    };
    let dir = tmp.join("adapt");
    let progress = run("adapt", &["--steps", "4"], &scene, &dir);
    let (best, eta) = smallest_eta(&dir);
    assert!(eta[best] < eta[eta.len() - 1], "η_tot {eta:?}: the last step has the smallest");
    let step = json_file(&dir.join("history.json"))["steps"][best].clone();
    let summary = json_file(&dir.join("summary.json"));
    assert_eq!(summary["step"], eta.len() - 1, "the summary is the last step's");
    let b = &summary["best_step"];
    assert_eq!((&b["step"], &b["eta_tot"], &b["unknowns"]), (&step["step"], &step["eta"]["tot"], &step["unknowns"]));
    assert_eq!((&b["crack_length"], &b["resultant"]), (&step["crack_length"], &step["resultant"]));
    assert!(b["resultant"]["normal_force"].as_f64().unwrap() > 0.0, "{b}");
    let file = PathBuf::from(b["file"].as_str().unwrap());
    assert_eq!(file, dir.join(format!("scene_a_{best:02}.vtu")));
    assert!(file.is_file());
    let line = format!("step {best} has the smallest eta_tot, {:.3e} Pa m", eta[best]);
    assert!(progress.contains(&line) && progress.contains(&format!("in {}", file.display())), "{progress}");
    let dir = tmp.join("safety");
    let progress = run("safety", &["--max-steps", "3"], &scene, &dir);
    let (best, eta) = smallest_eta(&dir);
    assert!(eta[best] < eta[eta.len() - 1], "η_tot {eta:?}: the last step has the smallest");
    let report = json_file(&dir.join("safety.json"));
    assert_eq!(report["best_step"]["step"], best, "{report}");
    assert!(progress.contains(&format!("step {best} has the smallest eta_tot")), "{progress}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let sentence = format!("Step {best} has the smallest η_tot of the run, {:.3e} Pa m", eta[best]);
    assert!(md.contains(&sentence) && md.contains(&format!("`scene_a_{best:02}.vtu`")), "{md}");
    let dir = tmp.join("falling");
    let progress = run("adapt", &["--steps", "2"], &repo("geo/scene_a.toml"), &dir);
    let (best, eta) = smallest_eta(&dir);
    assert_eq!(best, eta.len() - 1, "η_tot {eta:?}");
    assert!(json_file(&dir.join("summary.json"))["best_step"].is_null());
    assert!(!progress.contains("has the smallest eta_tot"), "{progress}");
}

/// The `unknowns` of every step of `<dir>/history.json`.
fn history_unknowns(dir: &Path) -> Vec<u64> {
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    history["steps"].as_array().unwrap().iter().map(|s| s["unknowns"].as_u64().unwrap()).collect()
}

#[test]
fn adapt_compares_with_uniform_refinement_on_one_figure() {
    let dir = TempDir::new("adapt-uniform");
    let out = adapt_scene_a_p1(&dir, &["--compare-uniform"]);
    assert_ok(&out);
    let uniform_dir = dir.join("uniform");
    for file in ["scene_a_00.vtu", "scene_a.pvd", "history.csv", "history.json", "scene_a_eta.png"] {
        assert!(dir.join(file).is_file() && uniform_dir.join(file).is_file(), "{file}");
    }
    let adaptive = history_unknowns(&dir.0);
    let uniform = history_unknowns(&uniform_dir);
    // the same first mesh; uniform stops at the first mesh beyond the adaptive run's last
    assert_eq!(uniform[0], adaptive[0], "uniform {uniform:?}, adaptive {adaptive:?}");
    assert!(uniform.windows(2).all(|w| w[1] > w[0]), "uniform {uniform:?}");
    let last = *adaptive.last().unwrap();
    assert!(*uniform.last().unwrap() > last && uniform[..uniform.len() - 1].iter().all(|&n| n <= last));
    let figure = dir.join("scene_a_adaptive_uniform.svg");
    assert!(dir.join("scene_a_adaptive_uniform.png").is_file());
    let svg = std::fs::read_to_string(&figure).unwrap();
    assert!(svg.contains("adaptive, slope") && svg.contains("uniform, slope"), "legend without slopes");
    assert!(stderr(&out).contains(&figure.display().to_string()), "{}", stderr(&out));
    assert!(hidden_files(&dir.0).is_empty() && hidden_files(&uniform_dir).is_empty());
}

#[test]
fn adapt_refuses_to_compare_uniform_with_itself() {
    let out = damfem(&[
        OsStr::new("adapt"),
        repo("geo/scene_a.toml").as_os_str(),
        OsStr::new("--uniform"),
        OsStr::new("--compare-uniform"),
    ]);
    assert_error(&out, &["adapt.compare_uniform", "adapt.refinement must be \"adaptive\""]);
}

#[test]
fn adapt_needs_a_geo_file() {
    let dir = TempDir::new("adapt-msh");
    assert_ok(&damfem(&[
        OsStr::new("mesh"),
        repo("geo/unit_square.toml").as_os_str(),
        OsStr::new("-o"),
        dir.0.as_os_str(),
    ]));
    let out =
        damfem(&[OsStr::new("adapt"), dir.join("unit_square.msh").as_os_str(), OsStr::new("-o"), dir.0.as_os_str()]);
    assert_error(&out, &["unit_square.msh", "needs a .geo file"]);
}

#[test]
fn adapt_rejects_a_bad_marking_fraction() {
    let out =
        damfem(&[OsStr::new("adapt"), repo("geo/scene_a.toml").as_os_str(), OsStr::new("--bulk"), OsStr::new("1.5")]);
    assert_error(&out, &["--bulk = 1.5", "(0, 1]", "adapt.bulk"]);
}

#[test]
fn adapt_reports_a_newton_failure_and_keeps_the_history() {
    let dir = TempDir::new("adapt-newton");
    let scene = dir.join("limited.toml");
    let text = std::fs::read_to_string(repo("geo/scene_a.toml")).unwrap();
    let geometry = repo("geo/scene_a.geo");
    let text = text
        .replace("geometry = \"scene_a.geo\"", &format!("geometry = {:?}", geometry.display().to_string()))
        .replace("[contact]", "[contact]\nmax_iter = 1");
    std::fs::write(&scene, text).unwrap();
    let out = damfem(&[OsStr::new("adapt"), scene.as_os_str(), OsStr::new("-o"), dir.0.as_os_str(), OsStr::new("-q")]);
    assert_error(&out, &["limited.toml", "adaptive step 0", "Newton did not converge in 1 step(s)"]);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    assert!(history["error"].as_str().unwrap().contains("Newton"));
    assert!(history["steps"].as_array().unwrap().is_empty());
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

// 3-D inputs are refused with "3-D": a .geo with a volume, a .msh with z != 0; also by `mesh`.
#[test]
fn three_dimensional_inputs() {
    assert_refused("volume", "mesh", &fixture("volume.geo"), &[], &["volume.geo", "3-D"]);
    let tmp = TempDir::new("tilted");
    let msh = tmp.join("tilted.msh");
    let body = std::fs::read_to_string(fixture("square.msh")).unwrap();
    std::fs::write(&msh, body.replace("\n4 0 1 0\n", "\n4 0 1 0.5\n")).unwrap();
    assert_refused("tilted-out", "solve", &msh, &[], &["tilted.msh", "3-D"]);
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

// A rerun into the same directory removes the step files of the earlier run (here a step 07
// the new run does not reach), and the history is written before the collections: when a
// collection cannot be written, history.json already has the step.
#[test]
fn adapt_rerun_removes_earlier_steps_and_writes_the_history_first() {
    let tmp = TempDir::new("adapt-rerun");
    std::fs::create_dir_all(&tmp.0).unwrap();
    let stale = tmp.join("scene_a_07_boundary.vtu");
    let kept = tmp.join("scene_a_notes.vtu");
    std::fs::write(&stale, "earlier run").unwrap();
    std::fs::write(&kept, "not a step file").unwrap();
    std::fs::create_dir(tmp.join("scene_a.pvd")).unwrap();
    let scene = repo("geo/scene_a.toml");
    let args = ["adapt".as_ref(), scene.as_os_str(), "--order".as_ref(), "1".as_ref(), "--steps".as_ref()];
    let out = damfem(&[&args[..], &["1".as_ref(), "-q".as_ref(), "-o".as_ref(), tmp.0.as_os_str()]].concat());
    assert_error(&out, &["scene_a.pvd"]);
    assert!(!stale.exists(), "the earlier run's step file is left");
    assert!(kept.exists(), "a file that is not a step file was removed");
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("history.json")).unwrap()).unwrap();
    assert_eq!(history["steps"].as_array().unwrap().len(), 1, "{history}");
}

/// `damfem args` sent SIGINT once `file` exists (within five minutes); it must end with 130.
fn interrupted(args: &[&OsStr], file: &Path) -> Output {
    let child = spawned_until(args, file, std::time::Duration::from_millis(20));
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().unwrap();
    assert!(kill.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    out
}

// SIGINT during an adaptive run: the process ends with 130, no hidden temporary file is left,
// and history.json keeps the completed steps and records "interrupted".
#[test]
fn adapt_interrupted_keeps_its_steps_and_says_so() {
    let tmp = TempDir::new("adapt-sigint");
    let scene = repo("geo/scene_a.toml");
    let args = [OsStr::new("adapt"), scene.as_os_str(), OsStr::new("--order"), OsStr::new("1"), OsStr::new("--steps")];
    let out = interrupted(
        &[&args[..], &[OsStr::new("40"), OsStr::new("-q"), OsStr::new("-o"), tmp.0.as_os_str()]].concat(),
        &tmp.join("scene_a_01_dg.vtu"),
    );
    assert!(stderr(&out).contains("interrupted by SIGINT"), "{}", stderr(&out));
    assert!(hidden_files(&tmp.0).is_empty(), "{:?}", hidden_files(&tmp.0));
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("history.json")).unwrap()).unwrap();
    assert_eq!(history["error"], "interrupted");
    assert!(!history["steps"].as_array().unwrap().is_empty());
}

// SIGINT during the second load combination of `damfem safety`. Source: geo/scene_a_combinations.toml
// (its combinations in alphabetical order: drains_blocked first). Goal: the run ends with 130,
// and report.md and safety.json, written again after every combination, keep the first one's
// row; no hidden temporary file is left. Parameters: P1, mesh sizes × 2.
#[test]
fn safety_interrupted_keeps_the_combinations_it_finished() {
    let tmp = TempDir::new("safety-sigint");
    let scene = repo("geo/scene_a_combinations.toml");
    let args =
        [OsStr::new("safety"), scene.as_os_str(), OsStr::new("--order"), OsStr::new("1"), OsStr::new("--size-factor")];
    interrupted(
        &[&args[..], &[OsStr::new("2"), OsStr::new("-q"), OsStr::new("-o"), tmp.0.as_os_str()]].concat(),
        &tmp.join("report.md"),
    );
    let report = std::fs::read_to_string(tmp.join("report.md")).unwrap();
    assert!(report.contains("[drains_blocked](drains_blocked/report.md)"), "{report}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("safety.json")).unwrap()).unwrap();
    let text = json.to_string();
    assert!(text.contains("drains_blocked") && text.contains("solved"), "{text}");
    assert!(hidden_files(&tmp.0).is_empty(), "{:?}", hidden_files(&tmp.0));
}

// The closing lines of `solve`, its results on stdout, headline what converges (displacement,
// contact length, joint forces, crack at the heel, resultant), not the maximum of the singular
// stress field.
#[test]
fn solve_headlines_converging_numbers() {
    let tmp = TempDir::new("headline");
    let scene = repo("geo/scene_a.toml");
    let out = damfem(&[OsStr::new("solve"), scene.as_os_str(), OsStr::new("-o"), tmp.0.as_os_str()]);
    assert_ok(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("von Mises"), "{text}");
    let last = text.lines().find(|l| l.starts_with("contact length")).unwrap_or_else(|| panic!("{text}"));
    assert!(last.contains("joint forces"), "{last}");
    assert!(text.lines().any(|l| l.starts_with("crack ") && l.contains("resultant at")), "{text}");
    let summary = check_summary(&tmp.0);
    assert!(last.contains(&format!("{:.4} m", summary["contact"]["contact_length"].as_f64().unwrap())), "{last}");
    // summary.json keeps the maximum with its place, where the anchor begins (x = 32 m), and
    // says that it is mesh-dependent: it grows when the mesh is refined
    let at = |s: &serde_json::Value| [0, 1].map(|i| s["max_von_mises_at"][i].as_f64().unwrap());
    let [x, y] = at(&summary);
    assert!((x - 32.0).hypot(y) < 1.0, "max von Mises at ({x}, {y})");
    assert!(summary["max_von_mises_note"].as_str().unwrap().contains("mesh-dependent"));
    let fine = TempDir::new("headline-fine");
    let out = damfem(&[
        OsStr::new("solve"),
        OsStr::new("-q"),
        scene.as_os_str(),
        OsStr::new("--size-factor"),
        OsStr::new("0.5"),
        OsStr::new("-o"),
        fine.0.as_os_str(),
    ]);
    assert_ok(&out);
    let refined = check_summary(&fine.0);
    let [x, y] = at(&refined);
    assert!((x - 32.0).hypot(y) < 0.5, "max von Mises at ({x}, {y}) on the finer mesh");
    let grows = refined["max_von_mises"].as_f64().unwrap() / summary["max_von_mises"].as_f64().unwrap();
    assert!(grows > 1.1, "max von Mises × {grows} under refinement");
}

// `--effectivity` writes η_tot, the sharp reference and I_eff = η_tot / reference under
// `effectivity`: the references are increasing lower bounds on growing spaces, the last two
// agree within 2 %, and η_tot lies above them (the bound holds).
#[test]
fn effectivity_reports_a_converged_reference_below_eta() {
    let tmp = TempDir::new("effectivity");
    let out_dir = tmp.join("out");
    let scene = repo("geo/scene_a.toml");
    let args =
        ["solve", "-q", scene.to_str().unwrap(), "--order", "1", "--effectivity", "-o", out_dir.to_str().unwrap()];
    assert_ok(&damfem(&args));
    let summary = check_summary(&out_dir);
    let e = &summary["effectivity"];
    let number = |key: &str| e[key].as_f64().unwrap_or_else(|| panic!("{key} in {e}"));
    let list = |key: &str| -> Vec<f64> { e[key].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect() };
    let (references, unknowns) = (list("references"), list("unknowns"));
    assert!(references.len() >= 2 && references.len() == unknowns.len(), "{e}");
    assert!(references.windows(2).all(|w| w[1] >= w[0]), "not increasing: {references:?}");
    assert!(unknowns.windows(2).all(|w| w[1] > w[0]), "spaces not growing: {unknowns:?}");
    let [previous, last] = [references[references.len() - 2], references[references.len() - 1]];
    assert_eq!(e["converged"], true, "{e}");
    assert!(last - previous <= 0.02 * last, "{references:?}");
    assert_eq!(number("reference"), last);
    assert_eq!(number("eta_tot"), summary["estimate"]["global"]["tot"].as_f64().unwrap());
    assert!(number("i_eff") >= 1.0, "eta_tot below the reference: {e}");
    assert!((number("i_eff") - number("eta_tot") / last).abs() <= 1e-12 * number("i_eff"));
}

// `adapt --effectivity` records I_eff at every step: in the `i_eff` column of history.csv,
// in history.json, on each step's progress line and in the closing table; every index is at
// least 1 (η_tot bounds the sharp lower bound). Without the flag the column stays empty.
#[test]
fn adapt_effectivity_records_i_eff_at_every_step() {
    let column = |dir: &TempDir| -> Vec<String> {
        let csv = std::fs::read_to_string(dir.join("history.csv")).unwrap();
        let k = csv.lines().next().unwrap().split(',').position(|c| c == "i_eff").expect("i_eff column");
        csv.lines().skip(1).map(|l| l.split(',').nth(k).unwrap().to_string()).collect()
    };
    let plain = TempDir::new("adapt-plain");
    assert_ok(&adapt_scene_a_p1(&plain, &[]));
    assert!(column(&plain).iter().all(String::is_empty), "{:?}", column(&plain));
    let dir = TempDir::new("adapt-effectivity");
    let out = adapt_scene_a_p1(&dir, &["--effectivity"]);
    assert_ok(&out);
    let indices: Vec<f64> = column(&dir).iter().map(|v| v.parse().unwrap()).collect();
    assert_eq!(indices.len(), 3);
    assert!(indices.iter().all(|&i| i >= 1.0), "{indices:?}");
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("history.json")).unwrap()).unwrap();
    for (step, &i) in history["steps"].as_array().unwrap().iter().zip(&indices) {
        assert!((step["i_eff"].as_f64().unwrap() - i).abs() <= 1e-4 * i, "{step}");
    }
    let progress = stderr(&out);
    assert_eq!(progress.lines().filter(|l| l.starts_with("step ") && l.contains("I_eff")).count(), 3, "{progress}");
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.lines().next().is_some_and(|l| l.contains("I_eff")), "{table}");
}

// With -v, gmsh's messages and one line per Newton iterate on stderr (k = 0 … steps at every
// δ of the path; at size factor 2, too few unknowns for coarse levels), in `solve` and `adapt`;
// with -q, nothing at all. summary.json and the
// history.json of both commands state their units, and summary.json names the numeric tags
// of the VTU files.
#[test]
fn verbose_shows_newton_steps_quiet_shows_nothing_and_json_states_units() {
    let tmp = TempDir::new("verbose");
    let scene = repo("geo/scene_a.toml");
    let run = |flag: &str| {
        let args = [OsStr::new("solve"), OsStr::new(flag), scene.as_os_str(), OsStr::new("--size-factor")];
        damfem(&[&args[..], &[OsStr::new("2"), OsStr::new("-o"), tmp.0.as_os_str()]].concat())
    };
    let out = run("-v");
    assert_ok(&out);
    let text = stderr(&out);
    // gmsh's own messages go to stderr too, not among the results on stdout
    assert!(text.contains("gmsh: Info: Meshing 1D"), "{text}");
    assert!(!String::from_utf8_lossy(&out.stdout).contains("Info"), "{}", String::from_utf8_lossy(&out.stdout));
    let residuals: Vec<f64> = text
        .lines()
        .filter_map(|l| l.strip_prefix("newton "))
        .map(|l| l.rsplit(' ').next().unwrap().parse().unwrap())
        .collect();
    let summary = check_summary(&tmp.0);
    let stages = summary["contact"]["stages"].as_array().unwrap();
    let iterates: u64 = stages.iter().map(|s| s[1].as_u64().unwrap() + 1).sum();
    assert_eq!(residuals.len() as u64, iterates, "{text}");
    assert!(residuals[0] > 0.1 && *residuals.last().unwrap() <= 1e-10, "{text}");
    let tags = &summary["tags"];
    assert_eq!(tags["material"].as_object().unwrap().values().collect::<Vec<_>>(), ["concrete"]);
    let mut curves: Vec<&str> =
        tags["physical_tag"].as_object().unwrap().values().map(|v| v.as_str().unwrap()).collect();
    curves.sort_unstable();
    assert_eq!(curves, ["base", "crest", "downstream", "toe", "upstream"]);
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(tmp.join("history.json")).unwrap()).unwrap();
    assert_eq!(history["units"]["residual"].as_str().unwrap().split(' ').next(), Some("N/m"));

    let out = run("-q");
    assert_ok(&out);
    assert!(out.stdout.is_empty() && out.stderr.is_empty(), "{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));

    let adapted = tmp.join("adapt");
    let out = damfem(&[
        OsStr::new("adapt"),
        OsStr::new("-v"),
        scene.as_os_str(),
        OsStr::new("--steps"),
        OsStr::new("1"),
        OsStr::new("-o"),
        adapted.as_os_str(),
    ]);
    assert_ok(&out);
    assert!(stderr(&out).lines().filter(|l| l.starts_with("newton ")).count() >= 2, "{}", stderr(&out));
    let history: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(adapted.join("history.json")).unwrap()).unwrap();
    assert!(history["units"]["estimator"].as_str().unwrap().starts_with("Pa m"));
    // -q silences the closing table of `adapt` and the .msh path of `mesh` too
    let steps = [OsStr::new("--steps"), OsStr::new("1")];
    for (command, extra) in [("adapt", &steps[..]), ("mesh", &[][..])] {
        let mut args =
            vec![OsStr::new(command), OsStr::new("-q"), scene.as_os_str(), OsStr::new("-o"), adapted.as_os_str()];
        args.extend(extra);
        let out = damfem(&args);
        assert_ok(&out);
        let printed = format!("{}{}", String::from_utf8_lossy(&out.stdout), stderr(&out));
        assert!(printed.is_empty(), "{command}: {printed}");
    }
}

// The Nitsche variants the estimator does not cover. Source: docs/method.md §4.2 and §5.2 (the
// bound needs θ = 0: ψ_a z is a test function of the discrete problem only then).
// Goal: an estimate asked of a scene with θ ≠ 0 (`solve --estimate` or `--effectivity`,
// `adapt`, `safety`, which estimate every mesh) is refused before meshing, in one line naming
// the flag or the key (of `[contact]` or of the joint) and the file, with no output directory;
// `solve` without an estimate still takes θ ≠ 0.
// Parameters: Scene A and the lift joint of geo/dam_lift_joint.toml, θ = 1 and −1, P1.
#[test]
fn estimate_refuses_a_nitsche_variant_it_does_not_cover() {
    let tmp = TempDir::new("theta-estimate");
    let scene_a = repo("geo/scene_a.toml");
    let flag = assert_refused(
        "theta-flag",
        "solve",
        &scene_a,
        &["--estimate", "--theta", "1"],
        &["--theta = 1", "command line", "contact.theta", "theta = 0"],
    );
    assert!(!flag.contains("scene_a.toml"), "the scene is not at fault: {flag}");
    let skew = edited_scene(&tmp, "scene_a", |s| s.replace("theta = 0.0", "theta = -1.0"));
    for (command, extra) in [("solve", &["--effectivity"][..]), ("adapt", &[]), ("safety", &[])] {
        assert_refused("theta-key", command, &skew, extra, &["contact.theta = -1", "scene_a.toml", "theta = 0"]);
    }
    let lift = edited_scene(&tmp, "dam_lift_joint", |s| s.replace("theta = 0.0", "theta = 1.0"));
    assert_refused("theta-joint", "adapt", &lift, &[], &["joints.lift.theta = 1", "dam_lift_joint.toml", "theta = 0"]);
    let out = tmp.join("out");
    let args = [OsStr::new("solve"), OsStr::new("-q"), skew.as_os_str(), OsStr::new("--order"), OsStr::new("1")];
    assert_ok(&damfem(&[&args[..], &[OsStr::new("-o"), out.as_os_str()]].concat()));
}
