//! `damfem check`: validate a scene and each of its load combinations against its geometry
//! without solving.

use super::common::{Input, Progress};
use crate::contact::{ContactJoint, Uplift};
use crate::geometry::Vector;
use crate::io::gmsh::AnyMesh;
use crate::mesh::Mesh;
use crate::scene::{CrackKind, Scene, UpliftSection};
use anyhow::{Context, Result};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    input: Input,
    /// Treat the warnings (curves without a role, surfaces without a material, parameters
    /// outside their known range) as errors
    #[arg(long)]
    strict: bool,
}

pub fn run(args: Args) -> Result<()> {
    let input = &args.input;
    let progress = input.progress();
    let scene = input.scene()?;
    let (mesh, _) = progress.stage("mesh", || input.model(&scene), AnyMesh::describe)?;
    let mesh = match mesh {
        AnyMesh::Plane(mesh) => mesh,
        AnyMesh::Solid(mesh) => return check_solid(&scene, mesh, &progress),
    };
    let (problem, contact) = scene.problem(mesh.clone())?;
    let mut warnings = scene.warnings(&problem.mesh, contact.as_ref())?;
    let mut water = water_lines("scene", &scene, &problem.mesh, contact.as_ref());
    for name in scene.combinations.keys() {
        let (own, lines) = combination(&scene, name, &mesh).with_context(|| format!("combination {name}"))?;
        let new = own.into_iter().filter(|w| !warnings.contains(w)).map(|w| format!("combination {name}: {w}"));
        warnings.extend(new.collect::<Vec<_>>());
        water.extend(lines);
    }
    let mesh = &problem.mesh;
    progress.warn(&warnings);
    if args.strict && !warnings.is_empty() {
        anyhow::bail!("{}: --strict: {}", scene.source.display(), warnings.join("; "));
    }
    let roles = scene.roles(mesh)?;
    for (tag, name, b) in &roles {
        progress.result(&format!("curve    {name:<20} {:?}, length {:.4}", b.role, mesh.boundary_length(*tag)));
    }
    // the joint curves are those of the contact joint, in order
    for (curve, (name, joint)) in scene.joints.iter().enumerate() {
        let Some(tag) = mesh.group(1, name).map(|g| g.tag) else { continue };
        let uplift = (contact.iter().flat_map(|c| &c.uplift)).find(|up| up.curves.contains(&curve)).map_or(
            String::new(),
            |up| {
                let p = &up.diagram;
                format!(", uplift {:.4e} Pa at the heel {:?}", p.pressure(0.0, 0.0), p.line.heel)
            },
        );
        progress.result(&format!(
            "joint    {name:<20} {:?}, length {:.4}{uplift}",
            joint.law(),
            mesh.boundary_length(tag)
        ));
    }
    for g in mesh.groups.iter().filter(|g| g.dim == 2) {
        let m = problem.materials[mesh.cell_tags.iter().position(|&t| t == g.tag).unwrap_or(0)];
        progress
            .result(&format!("region   {:<20} E = {:.4e}, nu = {}, rho = {}", g.name, m.young, m.poisson, m.density));
    }
    for line in &water {
        progress.result(line);
    }
    progress.result(&format!("{}: ok", scene.source.display()));
    Ok(())
}

/// The roles of a solid's surfaces with their areas and the materials of its volumes.
fn check_solid(scene: &Scene, mesh: Mesh<3>, progress: &Progress) -> Result<()> {
    let solid = scene.solid(mesh)?;
    let mesh = &solid.mesh;
    progress.warn(&scene.solid_warnings(mesh)?);
    for (tag, name, b) in scene.roles(mesh)? {
        progress.result(&format!("surface  {name:<20} {:?}, area {:.4}", b.role, mesh.boundary_area(tag)));
    }
    for g in mesh.groups.iter().filter(|g| g.dim == 3) {
        let m = solid.materials[mesh.cell_tags.iter().position(|&t| t == g.tag).unwrap_or(0)];
        progress
            .result(&format!("region   {:<20} E = {:.4e}, nu = {}, rho = {}", g.name, m.young, m.poisson, m.density));
    }
    progress.result(&format!("{}: ok", scene.source.display()));
    Ok(())
}

/// The warnings and the water lines of the load combination `name` of `scene`, whose scene
/// and problem on `mesh` are built as `damfem safety` builds them.
fn combination(scene: &Scene, name: &str, mesh: &Mesh) -> Result<(Vec<String>, Vec<String>)> {
    let combined = scene.combination(name)?;
    let (problem, joint) = combined.problem(mesh.clone())?;
    let warnings = combined.warnings(&problem.mesh, joint.as_ref())?;
    Ok((warnings, water_lines(&format!("combination {name}"), &combined, &problem.mesh, joint.as_ref())))
}

/// The water of the case `case`: the level of each hydrostatic curve and the acceleration,
/// then of each uplift diagram its headwater and tailwater, drain line and the pressure at
/// the heel, the drains and the toe without a crack.
fn water_lines(case: &str, scene: &Scene, mesh: &Mesh, joint: Option<&ContactJoint>) -> Vec<String> {
    let levels: Vec<String> = (scene.boundary.iter())
        .filter_map(|(curve, b)| b.hydrostatic.map(|h| format!("{curve} {:.3} m", h.level)))
        .collect();
    let [a_x, a_y] = scene.loads.acceleration;
    let mut lines = vec![format!(
        "water    {case:<20} hydrostatic levels: {}; acceleration [{a_x}, {a_y}] g",
        if levels.is_empty() { "none".to_string() } else { levels.join(", ") }
    )];
    for up in joint.map_or(&[][..], |j| &j.uplift[..]) {
        let tags = &joint.expect("a joint has the diagrams").tags;
        let curves: Vec<&str> = (up.curves.iter())
            .filter_map(|&c| mesh.groups.iter().find(|g| g.dim == 1 && g.tag == tags[c]))
            .map(|g| g.name.as_str())
            .collect();
        let table = scene.uplift.as_ref().or_else(|| scene.joints.values().nth(up.curves[0])?.uplift.as_ref());
        let line = uplift_line(table, &up.diagram, scene.loads.acceleration);
        lines.push(format!("uplift   {case:<20} {}: {line}", curves.join(", ")));
    }
    lines
}

/// The heads and crack rule (under the acceleration `a`) of the uplift `table`, the drain line
/// of its `diagram` and p_u at the heel, the drains and the toe, with the crack closed.
fn uplift_line(table: Option<&UpliftSection>, diagram: &Uplift, a: Vector) -> String {
    let line = &diagram.line;
    let at = |what: &str, s: f64| {
        let x = line.point(s);
        format!("{what} at s = {s:.3} m ({:.3}, {:.3}): p_u {:.4e} Pa", x[0], x[1], diagram.pressure(s, 0.0))
    };
    let heads = table.map_or(String::new(), |u| {
        let tailwater = u.tailwater.map_or("none".into(), |t| format!("{t:.3} m"));
        let crack = match u.crack_kind(a) {
            CrackKind::Full => "full",
            CrackKind::Unchanged => "unchanged (that of the state before the earthquake, solved first)",
            CrackKind::Dry => "none (beyond the crack before the earthquake, solved first)",
            CrackKind::Ignore => "ignore",
        };
        format!("headwater {:.3} m, tailwater {tailwater}, crack {crack}; ", u.headwater)
    });
    let mut places = vec![at("heel", 0.0)];
    places.extend(diagram.drains.map(|d| format!("{}, efficiency {}", at("drain line", d.distance), d.efficiency)));
    places.push(at("toe", line.length));
    format!("{heads}{}", places.join("; "))
}
