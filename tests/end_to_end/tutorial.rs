//! The tutorial example runs: Scene A from scene to ParaView file, with a guaranteed,
//! equilibrated estimate.

#[allow(dead_code)]
#[path = "../../examples/tutorial.rs"]
mod example;

#[test]
fn the_tutorial_runs_scene_a_end_to_end() {
    let dir = std::env::temp_dir().join(format!("damfem-tutorial-{}", std::process::id()));
    let output = dir.join("tutorial.vtu");
    let summary = example::run(&output).unwrap_or_else(|e| panic!("{e:#}"));
    let vtu = std::fs::read_to_string(&output).expect("the VTU file");
    std::fs::remove_dir_all(&dir).ok();
    for name in ["displacement", "von_mises", "eta_tot"] {
        assert!(vtu.contains(&format!("Name=\"{name}\"")), "{name} missing from the VTU file");
    }
    // the heel lifts off: part of the 32 m contact base is open, part closed
    assert!(summary.contact_length > 5.0 && summary.contact_length < 32.0, "contact length {}", summary.contact_length);
    assert!(summary.eta_tot.is_finite() && summary.eta_tot > 0.0, "eta_tot {}", summary.eta_tot);
    assert!(summary.equilibration < 1e-10, "equilibration {}", summary.equilibration);
    assert!(summary.newton_steps > 0 && summary.unknowns > 1000);
}
