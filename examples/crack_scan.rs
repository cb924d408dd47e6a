//! The crack–uplift map: the length open at the heel against the crack that the reservoir
//! pressure fills.
//!
//! What it shows: one load combination of `geo/scene_a_combinations.toml` (P2, the file's mesh
//! sizes), solved as `damfem solve` does (the δ path of the scene), then solved again from the
//! last solution with the crack s_c = 0, 0.25, …, 6 m held fixed (docs/method.md §1.8). For
//! each s_c: the open length at the heel, g(s_c) = open − s_c (the crack settles where g
//! changes sign), the effective normal force N and the stick and slip lengths. An optional
//! friction coefficient F replaces the scene's (a large one makes the closed joint stick).
//!
//! Run: `cargo run --release --example crack_scan -- COMBINATION [F]` from the crate root,
//! e.g. `-- drains_blocked` or `-- usual 5`; prints one line per crack.

use anyhow::{Context, Result};
use damfem::contact::projection::Smoothing;
use damfem::contact::{continuation, ContactProblem, JointLaw};
use damfem::io::gmsh::mesh_geo;
use damfem::scene::Scene;
use damfem::solve::newton;
use std::path::Path;

fn main() -> Result<()> {
    let mut args = std::env::args().skip(1);
    let name = args.next().context("usage: crack_scan COMBINATION [F]")?;
    let friction: Option<f64> = args.next().map(|f| f.parse()).transpose()?;
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("geo/scene_a_combinations.toml");
    let scene = Scene::load(&file)?.combination(&name)?;
    let mesh = mesh_geo(&scene.geometry, &scene.mesh_options(), false, false)?;
    let (problem, joint) = scene.problem(mesh)?;
    let mut joint = joint.context("the scene has a joint")?;
    if let Some(friction) = friction {
        joint.laws.iter_mut().for_each(|c| c.law = JointLaw::Coulomb { friction });
    }
    let disc = problem.discretise();
    let path = scene.continuation(&problem, &disc.topology);
    let mut contact = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: path.delta });
    let x0 = vec![0.0; disc.dofs.n_free];
    let (mut x, _) = continuation(&mut contact, path.delta, path.delta_start, x0, &path.newton)?;
    println!("{name}, {:?}, δ = {:.3e} Pa", joint.laws[0].law, path.delta);
    for i in 0..=24 {
        let crack = 0.25 * i as f64;
        contact.nitsche.uplift.first_mut().context("the joint has uplift")?.diagram.crack = crack;
        x = newton(&contact, x, &path.newton)?.x;
        let open = contact.crack_lengths(&x)[0];
        let faces = contact.face_states(&x);
        let normal: f64 = faces.iter().map(|f| f.pressure * f.length).sum();
        let stick: f64 = faces.iter().map(|f| f.stick_length).sum();
        let slip: f64 = faces.iter().map(|f| f.slip_length).sum();
        println!(
            "s_c {crack:5.2} m  open {open:7.4} m  g {:8.4} m  N {normal:.4e} N/m  stick {stick:5.2} m  slip {slip:5.2} m",
            open - crack
        );
    }
    Ok(())
}
