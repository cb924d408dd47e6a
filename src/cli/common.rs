//! Options and steps shared by the subcommands.

use crate::contact::PathPoint;
use crate::io::gmsh::{self, AnyMesh};
use crate::io::input::check_regular;
use crate::mesh::midpoints::elevate_to_p2;
use crate::mesh::Mesh;
use crate::scene::Scene;
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};
use std::time::Instant;

/// Input and verbosity options of every subcommand.
#[derive(clap::Args, Debug, Clone)]
pub struct Input {
    /// Scene file (.toml), or a bare geometry (.geo) or mesh (.msh) with roles taken from its
    /// physical curve names (Gamma_D, Gamma_N, Gamma_C, or dirichlet, neumann, contact)
    pub scene: PathBuf,
    /// Element degree (1 or 2); overrides the scene's mesh.order, and raises a degree-1 .msh
    /// to degree 2
    #[arg(long)]
    pub order: Option<usize>,
    /// Factor on gmsh's mesh sizes; overrides the scene's mesh.size_factor
    #[arg(long)]
    pub size_factor: Option<f64>,
    /// Let the .geo file run shell commands (SystemCall, System); refused by default
    #[arg(long)]
    pub allow_system_calls: bool,
    /// Refuse to mesh when gmsh's mesh would have more than about N triangles, estimated
    /// before meshing (default 2000000)
    #[arg(long, value_name = "N")]
    pub max_cells: Option<usize>,
    /// Stop with an error when gmsh takes more than S seconds to read and mesh the geometry
    #[arg(long, value_name = "S", default_value_t = 300)]
    pub mesh_time_limit: u32,
    /// Run the scene under its load combination NAME ([combinations.NAME])
    #[arg(long, value_name = "NAME")]
    pub combination: Option<String>,
    /// Print nothing but errors
    #[arg(short, long, conflicts_with = "verbose")]
    pub quiet: bool,
    /// Also print gmsh's own messages and one line per Newton step
    #[arg(short, long)]
    pub verbose: bool,
}

impl Input {
    /// The scene: read from .toml, or the default scene of a .geo/.msh file. CLI options win.
    pub fn scene(&self) -> Result<Scene> {
        let path = &self.scene;
        check_regular(path).map_err(|e| anyhow::anyhow!("cannot open {}: {e}", path.display()))?;
        gmsh::set_cell_limit(self.max_cells.unwrap_or(gmsh::DEFAULT_CELL_LIMIT));
        anyhow::ensure!(self.mesh_time_limit > 0, "--mesh-time-limit 0: the time limit must be at least 1 s");
        gmsh::set_time_limit(Some(self.mesh_time_limit));
        let mut scene = match path.extension().and_then(|e| e.to_str()) {
            Some("toml") => Scene::load(path)?,
            Some("geo") | Some("msh") => Scene::for_geometry(path),
            _ => anyhow::bail!("{}: expected a scene (.toml), a geometry (.geo) or a mesh (.msh)", path.display()),
        };
        if let Some(name) = &self.combination {
            scene = scene.combination(name).with_context(|| format!("--combination {name}"))?;
        }
        let is_mesh = scene.geometry.extension().is_some_and(|e| e == "msh");
        if is_mesh && self.size_factor.is_some() {
            anyhow::bail!(
                "--size-factor applies to .geo geometries; {} is a mesh file with its own sizes",
                scene.geometry.display()
            );
        }
        if let Some(order) = self.order {
            anyhow::ensure!(order == 1 || order == 2, "--order {order}: the element degree must be 1 or 2");
            scene.mesh.order = order;
        }
        if let Some(factor) = self.size_factor {
            anyhow::ensure!(factor > 0.0 && factor.is_finite(), "--size-factor {factor}: must be positive and finite");
            scene.mesh.size_factor = factor;
        }
        Ok(scene)
    }

    /// `result`, its error named after the load combination `--combination` if given.
    pub fn in_combination<T>(&self, result: Result<T>) -> Result<T> {
        match &self.combination {
            Some(name) => result.with_context(|| format!("--combination {name}")),
            None => result,
        }
    }

    /// What the load path calls at every converged state, unless `-q`: one line on stderr,
    /// with the joint's forces under `-v`.
    pub fn path_trace(&self) -> Option<fn(&PathPoint)> {
        match (self.quiet, self.verbose) {
            (true, _) => None,
            (false, true) => Some(path_point_line),
            (false, false) => Some(path_progress_line),
        }
    }

    /// With `-v`, what Newton calls at every iterate: one line on stderr.
    pub fn newton_trace(&self) -> Option<fn(usize, f64)> {
        self.verbose.then_some(newton_step_line as fn(usize, f64))
    }

    /// Meshes the scene's geometry (or reads its .msh, at the degree of `--order` if given).
    pub fn mesh(&self, scene: &Scene) -> Result<Mesh> {
        let geometry = &scene.geometry;
        let mesh = if is_msh(geometry) {
            at_order(gmsh::read_msh(geometry, self.verbose)?, self.msh_order(scene), geometry)?
        } else {
            gmsh::mesh_geo(geometry, &scene.mesh_options(), self.verbose, self.allow_system_calls)?
        };
        Ok(mesh)
    }

    /// The degree asked of a .msh: `--order`, or the scene's `mesh.order`, with what asked it.
    fn msh_order(&self, scene: &Scene) -> Option<(usize, String)> {
        match self.order {
            Some(order) => Some((order, format!("--order {order}"))),
            None => {
                scene.given_order().map(|order| (order, format!("{}: mesh.order = {order}", scene.source.display())))
            }
        }
    }

    /// Meshes the scene's geometry (or reads its .msh) in its dimension: a plane mesh as
    /// [`Input::mesh`] gives it, or a solid's, a mesh file's raised to degree 2 as a plane one.
    pub fn model(&self, scene: &Scene) -> Result<AnyMesh> {
        let geometry = &scene.geometry;
        if !is_msh(geometry) {
            return Ok(gmsh::mesh_geo_any(geometry, &scene.mesh_options(), self.verbose, self.allow_system_calls)?);
        }
        match gmsh::read_msh_any(geometry, self.verbose)? {
            AnyMesh::Plane(mesh) => Ok(AnyMesh::Plane(at_order(mesh, self.msh_order(scene), geometry)?)),
            AnyMesh::Solid(mesh) => Ok(AnyMesh::Solid(at_order(mesh, self.msh_order(scene), geometry)?)),
        }
    }

    /// `scene` with the crack s₀ of its state before the earthquake where a seismic crack rule
    /// keeps it ([`Scene::pre_earthquake`]): that state solved on the scene's own mesh.
    pub fn before_earthquake(&self, scene: Scene) -> Result<Scene> {
        let Some(before) = scene.pre_earthquake() else { return Ok(scene) };
        let solve = || -> Result<Vec<f64>> {
            let (problem, joint) = before.problem(self.mesh(&before)?)?;
            let joint = joint.context("an uplift diagram without a joint")?;
            let disc = problem.discretise();
            let mut settings = before.continuation(&problem, &disc.topology);
            settings.newton.trace = self.newton_trace();
            if let Some(path) = settings.path.as_mut() {
                path.trace = self.path_trace();
            }
            let solution = before.solve_contact(&problem, &disc, &joint, &settings, self.allow_system_calls)?;
            Ok(solution.cracks.iter().map(|c| c.map_or(0.0, |c| c.length)).collect())
        };
        let describe = |cracks: &Vec<f64>| {
            let lengths: Vec<String> = cracks.iter().map(|s| format!("{s:.3} m")).collect();
            format!("before the earthquake: crack {}", lengths.join(", "))
        };
        let (cracks, _) = self.progress().stage("static", solve, describe).context(
            "the state before the earthquake (the same water, no acceleration), whose crack the seismic crack rule keeps",
        )?;
        Ok(scene.with_prior_cracks(cracks))
    }

    /// Progress reporter honouring `-q`.
    pub fn progress(&self) -> Progress {
        Progress { quiet: self.quiet }
    }
}

/// The mesh of the file `path` at degree `order` (the file's if `None`), given by `by` (the flag
/// or the key): a degree-1 mesh is raised to degree 2 as gmsh raises it (a node at the middle
/// of every straight edge, see [`elevate_to_p2`]); lowering, which would drop the file's
/// midpoint nodes, is refused.
fn is_msh(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "msh")
}

fn at_order<const D: usize>(mesh: Mesh<D>, order: Option<(usize, String)>, path: &Path) -> Result<Mesh<D>> {
    match order {
        None => Ok(mesh),
        Some((order, _)) if order == mesh.order => Ok(mesh),
        Some((2, _)) => Ok(elevate_to_p2(&mesh)),
        Some((_, by)) => anyhow::bail!(
            "{by}: {} holds degree-{} {}; a mesh file can be raised to degree 2, not lowered",
            path.display(),
            mesh.order,
            if D == 3 { "tetrahedra" } else { "triangles" }
        ),
    }
}

/// The output option of the subcommands that write files.
#[derive(clap::Args, Debug, Clone)]
pub struct Output {
    /// Output directory; overrides the scene's [output] directory (default: out)
    #[arg(short = 'o', long = "output", value_name = "DIR")]
    pub directory: Option<PathBuf>,
}

impl Output {
    /// The output directory of `scene`: `-o` if given, else the scene's `[output] directory`.
    /// Created if missing, and locked for this command (see the `lock` module).
    pub fn dir(&self, scene: &Scene) -> Result<PathBuf> {
        let dir = output_dir(self.directory.clone().unwrap_or_else(|| scene.output.directory.clone()))?;
        super::lock::lock(&dir)?;
        Ok(dir)
    }
}

/// Directories that [`output_dir`] created, deepest last.
static CREATED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Creates `dir` if missing and checks that it is writable; [`remove_created_dirs`] removes
/// what was created if the run fails before writing to it.
pub fn output_dir(dir: PathBuf) -> Result<PathBuf> {
    let missing = dir.ancestors().take_while(|d| !d.as_os_str().is_empty() && !d.exists());
    let mut missing: Vec<PathBuf> = missing.map(Path::to_path_buf).collect();
    missing.reverse();
    CREATED.lock().unwrap_or_else(PoisonError::into_inner).extend(missing);
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let probe = dir.join(".damfem-write-test");
    std::fs::write(&probe, b"").with_context(|| format!("cannot write to output directory {}", dir.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(dir)
}

/// Removes the directories [`output_dir`] created that are still empty (after a failure).
pub fn remove_created_dirs() {
    let created = std::mem::take(&mut *CREATED.lock().unwrap_or_else(PoisonError::into_inner));
    for dir in created.iter().rev() {
        // only empty directories are removed; a failure leaves the directory as it is
        let _ = std::fs::remove_dir(dir);
    }
}

/// Whether `file` is a name that damfem writes for the scene `name`: its ParaView files and
/// collections, the step files `<name>_NN*.vtu` of `adapt`, its figures, its mesh, and the
/// summaries, histories and reports of every command.
fn is_output_of(file: &str, name: &str) -> bool {
    const SHARED: [&str; 8] = [
        "summary.json",
        "history.json",
        "history.csv",
        "safety.json",
        "report.md",
        "joint.csv",
        "base_stresses.png",
        "base_stresses.svg",
    ];
    const KINDS: [&str; 14] = [
        ".vtu",
        "_boundary.vtu",
        "_dg.vtu",
        "_mesh.vtu",
        ".msh",
        ".pvd",
        "_boundary.pvd",
        "_dg.pvd",
        "_eta.svg",
        "_eta.png",
        "_time.svg",
        "_time.png",
        "_adaptive_uniform.svg",
        "_adaptive_uniform.png",
    ];
    // `_NN` and a kind of step file
    let step =
        |rest: &str| rest.starts_with('_') && rest.get(1..3).is_some_and(|n| n.bytes().all(|b| b.is_ascii_digit()));
    SHARED.contains(&file)
        || file.strip_prefix(name).is_some_and(|rest| KINDS.contains(&rest) || (step(rest) && rest.ends_with(".vtu")))
}

/// Removes the files that an earlier run of the scene `name` left in `dir` and in
/// `dir/uniform` (which goes too once empty), except `keep`, so that the directory shows one
/// run only; other files are left alone. Returns how many were removed.
pub fn remove_earlier_outputs(dir: &Path, name: &str, keep: &[PathBuf]) -> Result<usize> {
    let mut removed = 0;
    for dir in [dir.to_path_buf(), dir.join("uniform")] {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries {
            let path = entry?.path();
            let ours = path.file_name().and_then(|f| f.to_str()).is_some_and(|f| is_output_of(f, name));
            if ours && path.is_file() && !keep.contains(&path) {
                std::fs::remove_file(&path).with_context(|| format!("cannot remove {}", path.display()))?;
                removed += 1;
            }
        }
    }
    // only an empty directory is removed; one that holds other files stays
    let _ = std::fs::remove_dir(dir.join("uniform"));
    Ok(removed)
}

/// A converged state of the load path: λ, the joint's forces, contact length, crack and FS_LE
/// (above 10³ where the joint carries almost no shear), and its Newton steps.
fn path_point_line(p: &PathPoint) {
    let crack = p.crack.map_or(String::new(), |c| format!(", crack {c:.3} m"));
    let fs = p.sliding_safety_factor.map_or(String::new(), |f| match f > 1e3 {
        true => ", FS_LE > 1000".to_string(),
        false => format!(", FS_LE {f:.3}"),
    });
    eprintln!(
        "load       lambda {:.4}: N = {:.4e} N/m, T = {:.4e} N/m, contact {:.3} m{crack}{fs}, {} Newton steps",
        p.load_factor, p.normal_force, p.tangential_force, p.contact_length, p.newton_steps
    );
}

/// A converged state of the load path in short: λ, the crack and the Newton steps.
fn path_progress_line(p: &PathPoint) {
    let crack = p.crack.map_or(String::new(), |c| format!(", crack {c:.3} m"));
    eprintln!("load       lambda {:.4}{crack}, {} Newton steps", p.load_factor, p.newton_steps);
}

/// A Newton iterate's progress line: its number k and ‖F(x_k)‖ / scale.
fn newton_step_line(step: usize, relative_residual: f64) {
    eprintln!("newton     step {step:>3}, relative residual {relative_residual:.3e}");
}

/// File stem of the scene, used to name outputs.
pub fn stem(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "damfem".into())
}

/// A solver that stopped without an answer, with what was tried (exit code 4).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct SolverFailed(pub String);

/// How many warnings a command prints.
pub const SHOWN_WARNINGS: usize = 20;

/// What a command prints: one line per stage on stderr (name, what was done, and the wall
/// time), other progress on stderr, results on stdout; with -q, none of it.
pub struct Progress {
    quiet: bool,
}

impl Progress {
    /// Runs `stage`, then prints `name`, its description and its time.
    pub fn stage<T>(
        &self,
        name: &str,
        stage: impl FnOnce() -> Result<T>,
        describe: impl Fn(&T) -> String,
    ) -> Result<(T, f64)> {
        let start = Instant::now();
        let value = stage()?;
        let seconds = start.elapsed().as_secs_f64();
        if !self.quiet {
            eprintln!("{name:<10} {:<52} {seconds:>8.3} s", describe(&value));
        }
        Ok((value, seconds))
    }

    /// Prints the first [`SHOWN_WARNINGS`] warnings as "warning:" lines unless quiet, then how
    /// many more there are.
    pub fn warn(&self, warnings: &[String]) {
        for w in warnings.iter().take(SHOWN_WARNINGS) {
            self.say(&format!("warning: {w}"));
        }
        if warnings.len() > SHOWN_WARNINGS {
            self.say(&format!("warning: {} more warnings not shown", warnings.len() - SHOWN_WARNINGS));
        }
    }

    /// Prints a progress line on stderr unless quiet.
    pub fn say(&self, line: &str) {
        if !self.quiet {
            eprintln!("{line}");
        }
    }

    /// Prints a line of the results on stdout unless quiet.
    pub fn result(&self, line: &str) {
        if !self.quiet {
            println!("{line}");
        }
    }
}
