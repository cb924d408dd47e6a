//! End-to-end tests of the `damfem` binary: every scene of geo/, the mesh command, the help
//! texts, the progress lines and the interrupted runs (bad input: bad_input.rs).

use super::support::{
    assert_error, assert_ok, assert_refused, check_summary, damfem, edited_scene, fixture, hidden_files, repo,
    spawned_until, stderr, TempDir,
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
        let roles = |l: &str| l.starts_with("curve ") || l.starts_with("surface ");
        assert!(table.lines().any(roles) && table.lines().any(|l| l.starts_with("region ")), "{table}");
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
