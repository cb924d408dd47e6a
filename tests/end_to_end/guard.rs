//! Limits and leftovers through the `damfem` binary: the cell limit of an adaptive run, the
//! files of a failed or concurrent run, inputs that are not regular files, and values beyond
//! any dam. Each ends with exit code 1 and one sentence naming the flag, key or file and no
//! file left behind, or with a result and a sentence saying where it stopped.

use super::cli::{assert_ok, damfem, repo, stderr, TempDir};
use std::ffi::OsStr;

/// The JSON file `path`.
fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

// Source: geo/scene_a.toml adapted with a cell limit of 8000, far below what 20 steps reach
// (about 10⁶ cells). Goal: the run stops after the step whose next mesh would exceed the
// limit, saying so in one sentence naming --max-cells, with every step written and no mesh
// beyond about the limit, where remeshes from a size field skipped the estimate and grew
// without bound. Parameters: P1, equidistribution.
#[test]
fn adapt_stops_at_the_cell_limit() {
    let tmp = TempDir::new("adapt-cell-limit");
    let (scene, dir) = (repo("geo/scene_a.toml"), tmp.join("out"));
    let mut args: Vec<&OsStr> =
        ["adapt", "--order", "1", "--steps", "20", "--max-cells", "8000"].iter().map(OsStr::new).collect();
    args.extend([scene.as_os_str(), OsStr::new("-o"), dir.as_os_str()]);
    let out = damfem(&args);
    assert_ok(&out);
    let progress = stderr(&out);
    let said: Vec<&str> = progress.lines().filter(|l| l.contains("--max-cells")).collect();
    assert_eq!(said.len(), 1, "{progress}");
    assert!(said[0].contains("stopped after step") && said[0].contains("limit of 8000 cells"), "{progress}");
    let history = json(&dir.join("history.json"));
    let steps = history["steps"].as_array().unwrap();
    assert!(steps.len() < 20, "{} steps", steps.len());
    assert!(steps.iter().all(|s| s["cells"].as_u64().unwrap() < 8800), "{steps:?}");
    let (last, before) = steps.split_last().unwrap();
    assert!(last["cell_limit"]["cells"].as_f64().unwrap() > 8000.0, "{last}");
    assert!(before.iter().all(|s| s["cell_limit"].is_null()));
    let pvd = std::fs::read_to_string(dir.join("scene_a.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet").count(), steps.len());
}
