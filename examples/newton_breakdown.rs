//! Where the time of one contact Newton step goes, what reusing the symbolic LU saves, and
//! how a Newton step compares with the bonded linear solve, on Scene A at 10⁴ to 10⁶ unknowns.
//!
//! What it shows: Scene A (`geo/scene_a.toml`: gravity dam, Nitsche contact on the base, P2)
//! meshed by gmsh at size factors giving ≈ 10⁴, 10⁵ and, with `--million`, 10⁶ unknowns.
//! At each size, in one process:
//! - the converged contact solve from a zero initial guess with the CLI's settings
//!   (δ = 10⁻⁴ × stress scale, γ₀ = 100, θ = 0, rtol = 10⁻¹⁰): its number of Newton steps;
//! - the parts of one Newton step at the converged state, as Newton takes it: residual +
//!   Jacobian evaluation (`NonlinearSystem::evaluate`), the dense LU of the Schur complement S_R
//!   on the rows R of the contact terms (`LayerSchur::factor`; R is the part of the contact
//!   layer on Γ_C for θ = 0), the two solves of the step and its refinement
//!   (`SchurFactors::solve`), and the residual-only evaluation of an accepted full step of the
//!   line search; and, once per mesh, the Cholesky factorisation of the stiffness with the layer
//!   last and the dense blocks of its trailing factor (`NonlinearSystem::schur`);
//! - the same step with the LU of the Schur complement S = S₀ + C on the whole layer (a
//!   `LayerSchur` with R = L, as for θ ≠ 0): what the rows R save;
//! - the same step by the sparse LU of the whole Jacobian (the fallback): numeric LU with the
//!   symbolic factorisation reused (`SparseLu::factor`) and its two solves (`LuFactors::solve`);
//! - the same LU refactored from scratch (`SparseLu::analyse` + numeric) and the saving of
//!   reuse per step: the symbolic analysis over a step from scratch, both timed in one block
//!   (and, noisier, 1 − step / step from scratch over two separately timed numeric LUs);
//! - the error estimate of the converged iterate (`estimate_iterate`: the stress
//!   reconstruction with its three right-hand sides and the six estimators) and the ratio
//!   estimate / Newton step;
//! - the linear elasticity solve on the same mesh with the base bonded (clamped):
//!   `Problem::assemble`, then `Cholesky` symbolic + numeric + solve, and the ratio
//!   step / Cholesky solve.
//!
//! Timings are medians over repetitions that interleave all the measured operations, so
//! that the ratios (medians of the per-repetition ratios) compare operations run under the
//! same machine load.
//!
//! Run: `cargo run --release --example newton_breakdown -- [--million] [--repeats N] [OUTPUT]`
//! from the crate root (OUTPUT defaults to `out/newton_breakdown.md`, N to 7; per-repetition
//! timings go to stderr). `--million` adds the 10⁶-unknown mesh (size factor 0.086,
//! 1 000 782 unknowns): there faer's numeric LU alone needs more than 6.3 GiB and, under a
//! 7 GB limit, fails with OutOfMemory (the bonded Cholesky takes 14.5 s and 2.6 GiB), so it
//! is off by default; with the memory, expect about an hour (≈ 30 Newton steps).
//!
//! Key numbers (`--repeats 3`, 2 cores, shared machine at load 3 to 6; 10⁴ = 9 846 and 10⁵ =
//! 99 608 unknowns, contact layers of 480 and 1 560 dofs, rows R of 192 and 624):
//! - Newton's step by the Schur complement on R costs 0.24 bonded Cholesky solves at 10⁴ and
//!   10⁵ (0.0081 s and 0.146 s), mostly its two solves; the LU of S_R costs 19 and 9.6 times
//!   less than the LU of S on the whole layer, the step 2.5 and 1.9 times less; the
//!   once-per-mesh factorisation with the layer last costs about two Cholesky solves at 10⁵;
//! - the step by sparse LU costs 3.2 and 3.4 bonded Cholesky solves, its numeric LU 87–92 %
//!   of it; reusing the symbolic LU saves 18–19 % of that step;
//! - the converged contact solve takes 22 Newton steps at 10⁴ and 28 at 10⁵.

use damfem::contact::projection::Smoothing;
use damfem::contact::{solve_by_continuation, ContactProblem};
use damfem::estimate::estimate_iterate;
use damfem::io::atomic::write_output;
use damfem::io::gmsh::{mesh_geo, MeshOptions};
use damfem::scene::{Role, Scene};
use damfem::solve::{Cholesky, LayerSchur, NonlinearSystem, SparseLu};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Size factors of Scene A giving ≈ 10⁴, 10⁵ and 10⁶ free unknowns at P2 (found by meshing).
const SIZE_FACTORS: [(f64, &str); 3] = [(0.9, "10⁴"), (0.275, "10⁵"), (0.086, "10⁶")];

/// Peak resident memory of this process so far, in MiB (Linux VmHWM).
fn peak_memory_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).map(|l| l.to_string()))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|v| v.parse::<f64>().ok()))
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|a| a * a).sum::<f64>().sqrt()
}

/// Runs `f` and returns its value with its wall time in seconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let clock = Instant::now();
    let value = f();
    (value, clock.elapsed().as_secs_f64())
}

/// One repetition of every measured operation, in seconds.
#[derive(Default, Clone, Copy)]
struct Sample {
    evaluate: f64,
    schur_factor: f64,
    schur_solve: f64,
    whole_factor: f64,
    whole_solve: f64,
    residual: f64,
    numeric: f64,
    solve: f64,
    symbolic: f64,
    scratch: f64,
    cholesky_symbolic: f64,
    cholesky_solve: f64,
    estimate: f64,
}

impl Sample {
    /// One Newton step as Newton takes it: by the Schur complement on the contact layer.
    fn step_schur(&self) -> f64 {
        self.evaluate + self.schur_factor + self.schur_solve + self.residual
    }
    /// The same step with the LU of the Schur complement on the whole layer.
    fn step_whole(&self) -> f64 {
        self.evaluate + self.whole_factor + self.whole_solve + self.residual
    }
    /// One Newton step by sparse LU with the symbolic LU reused.
    fn step(&self) -> f64 {
        self.evaluate + self.numeric + self.solve + self.residual
    }
    /// The same step with the LU refactored from scratch.
    fn step_scratch(&self) -> f64 {
        self.evaluate + self.scratch + self.solve + self.residual
    }
    fn cholesky(&self) -> f64 {
        self.cholesky_symbolic + self.cholesky_solve
    }
}

/// Everything reported for one mesh.
struct Row {
    label: &'static str,
    size_factor: f64,
    unknowns: usize,
    nonzeros: usize,
    bonded_unknowns: usize,
    contact_faces: usize,
    /// Dofs of the contact layer and of its rows R, and the once-per-mesh Cholesky with the
    /// layer last and its dense blocks.
    layer: usize,
    rows: usize,
    schur_setup: f64,
    /// The once-per-mesh factorisation with R = L.
    whole_setup: f64,
    newton_steps: usize,
    contact_solve: f64,
    /// Mean time of a Newton step inside the converged solve (`NewtonTimings` / steps).
    in_situ_step: f64,
    assemble_bonded: f64,
    median: Sample,
    step_schur: f64,
    step_schur_over_cholesky: f64,
    step_whole: f64,
    /// LU of S over LU of S_R, and the step on the whole layer over the step on R.
    whole_over_rows_lu: f64,
    whole_over_rows_step: f64,
    step: f64,
    step_scratch: f64,
    /// Share of the symbolic analysis in an LU from scratch (both timed in one block).
    saving_factor: f64,
    /// Share of the symbolic analysis in a step from scratch: what reuse saves per step.
    saving_step: f64,
    /// 1 − step / step from scratch, from two separately timed numeric LUs (noisier).
    saving_step_direct: f64,
    step_over_cholesky: f64,
    step_over_assemble_cholesky: f64,
    estimate_over_step: f64,
    contact_over_cholesky: f64,
    peak_mib: f64,
}

fn measure(scene: &Scene, size_factor: f64, label: &'static str, repeats: usize) -> Row {
    // 1. Mesh Scene A with gmsh at this size factor; the contact problem and its pattern
    let options = MeshOptions {
        order: scene.mesh.order,
        size_factor,
        size_min: scene.mesh.size_min,
        size_max: scene.mesh.size_max,
        algorithm: scene.mesh.algorithm,
    };
    let (mesh, mesh_seconds) =
        timed(|| mesh_geo(&scene.geometry, &options, false, false).expect("gmsh meshes Scene A"));
    let (problem, joint) = scene.problem(mesh.clone()).expect("Scene A is valid");
    let joint = joint.expect("Scene A has a contact curve");
    let disc = problem.discretise();
    let pattern = &disc.pattern;
    eprintln!(
        "[{label}] size factor {size_factor}: {} nodes, {} cells, {} unknowns, {} nonzeros (gmsh {mesh_seconds:.1} s)",
        problem.mesh.n_points(),
        problem.mesh.n_cells(),
        disc.dofs.n_free,
        pattern.nnz()
    );

    // 2. Converged contact solve from zero with the CLI's settings: number of Newton steps
    let settings = scene.continuation(&problem, &disc.topology);
    let (solution, contact_solve) =
        timed(|| solve_by_continuation(&problem, &disc, &joint, &settings).expect("Newton converges on Scene A"));
    let newton_steps = solution.newton_steps();
    let in_situ_step = solution
        .stages
        .iter()
        .map(|st| st.report.seconds)
        .map(|t| t.assemble + t.factor + t.solve + t.line_search)
        .sum::<f64>()
        / newton_steps.max(1) as f64;
    eprintln!(
        "[{label}] contact solve: {newton_steps} Newton steps at δ = {:.3e} Pa in {contact_solve:.2} s, contact length {:.3} m",
        settings.delta,
        solution.contact_length()
    );

    // 3. The nonlinear system at the converged state, as Newton sees it
    let system = ContactProblem::new(&problem, &disc, &joint, Smoothing { delta: settings.delta });
    let contact_faces = system.nitsche.faces.len();
    let x = solution.x.clone();
    let n = pattern.n();
    let (mut residual, mut jacobian, mut trial_residual) = (vec![0.0; n], vec![0.0; pattern.nnz()], vec![0.0; n]);
    let lu = SparseLu::analyse(pattern).expect("symbolic LU");
    let (schur, schur_setup) = timed(|| system.schur().expect("the layer of Scene A is factorised dense"));
    let (layer, rows) = (schur.layer_size(), schur.rows());
    let stiffness = problem.assemble_on(&disc, pattern).values;
    let whole_layer = system.layer();
    let (whole, whole_setup) = timed(|| {
        LayerSchur::new(pattern, &stiffness, &whole_layer, &whole_layer).expect("the whole layer is factorised dense")
    });
    eprintln!(
        "[{label}] contact layer: {layer} dofs, {rows} rows R, Cholesky with the layer last and its blocks in {schur_setup:.2} s"
    );

    // 4. The bonded linear problem on the same mesh: the contact curve clamped
    let mut bonded_scene = scene.clone();
    for b in bonded_scene.boundary.values_mut().filter(|b| b.role == Role::Contact) {
        b.role = Role::Dirichlet;
    }
    let (bonded, _) = bonded_scene.problem(mesh).expect("the bonded scene is valid");
    let bonded_disc = bonded.discretise();
    let (bonded_system, assemble_bonded) = timed(|| bonded.assemble(&bonded_disc));

    // 5. Repetitions interleaving every operation
    let mut samples = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let mut s = Sample::default();
        ((), s.evaluate) = timed(|| system.evaluate(&x, &mut residual, Some(&mut jacobian)));
        let minus_r: Vec<f64> = residual.iter().map(|v| -v).collect();
        // one Newton step by the Schur complement: the dense LU, the solve and its refinement,
        // on the rows R and on the whole layer
        let step = |layer: &LayerSchur| {
            let (factors, factor) = timed(|| layer.factor(&jacobian).expect("Schur LU"));
            let (delta, solve) = timed(|| {
                let delta = factors.solve(&minus_r).expect("Schur solve");
                factors.solve(&delta).expect("Schur solve"); // stands for the refinement's solve
                delta
            });
            (delta, factor, solve)
        };
        let delta_schur;
        (delta_schur, s.schur_factor, s.schur_solve) = step(schur);
        let delta_whole;
        (delta_whole, s.whole_factor, s.whole_solve) = step(&whole);
        let difference: Vec<f64> = delta_whole.iter().zip(&delta_schur).map(|(a, b)| a - b).collect();
        assert!(norm(&difference) <= 1e-8 * norm(&delta_whole), "the steps on R and on the whole layer disagree");
        // the same step by sparse LU with the symbolic factorisation reused
        let (factors, numeric) = timed(|| lu.factor(pattern, &jacobian).expect("numeric LU"));
        s.numeric = numeric;
        let (delta, solve) = timed(|| {
            let delta = factors.solve(&minus_r);
            factors.solve(&delta); // stands for the refinement's solve
            delta
        });
        s.solve = solve;
        let difference: Vec<f64> = delta.iter().zip(&delta_schur).map(|(a, b)| a - b).collect();
        assert!(norm(&difference) <= 1e-8 * norm(&delta).max(f64::MIN_POSITIVE), "Schur and LU steps disagree");
        drop(factors);
        let trial: Vec<f64> = x.iter().zip(&delta).map(|(a, d)| a + d).collect();
        ((), s.residual) = timed(|| system.evaluate(&trial, &mut trial_residual, None));
        // the same factorisation from scratch: symbolic analysis + numeric
        let clock = Instant::now();
        let symbolic = SparseLu::analyse(pattern).expect("symbolic LU");
        s.symbolic = clock.elapsed().as_secs_f64();
        let scratch = symbolic.factor(pattern, &jacobian).expect("numeric LU");
        s.scratch = clock.elapsed().as_secs_f64();
        let delta_scratch = scratch.solve(&minus_r);
        drop(scratch);
        let difference: Vec<f64> = delta.iter().zip(&delta_scratch).map(|(a, b)| a - b).collect();
        assert!(norm(&difference) <= 1e-8 * norm(&delta).max(f64::MIN_POSITIVE), "reused and scratch LU disagree");
        // the bonded linear solve: Cholesky symbolic, then numeric + solve
        let (cholesky, cholesky_symbolic) =
            timed(|| Cholesky::analyse(&bonded_disc.pattern).expect("symbolic Cholesky"));
        s.cholesky_symbolic = cholesky_symbolic;
        let (u, cholesky_solve) = timed(|| {
            cholesky.solve(&bonded_disc.pattern, &bonded_system.values, &bonded_system.rhs).expect("SPD bonded system")
        });
        s.cholesky_solve = cholesky_solve;
        assert!(u.iter().all(|v| v.is_finite()));
        // the error estimate of the converged iterate
        let state = solution.linearisation(&problem, &disc);
        let (estimate, seconds) =
            timed(|| estimate_iterate(&problem, &disc, &x, Some(&state)).expect("the estimate of Scene A"));
        s.estimate = seconds;
        assert!(estimate.estimators.global().tot.is_finite());
        eprintln!(
            "[{label}] repetition {}: evaluate {:.4}, Schur LU {:.4}, Schur solves {:.4}, LU numeric {:.4}, solves {:.4}, LU symbolic {:.4}, LU from scratch {:.4}, Cholesky {:.4}, estimate {:.4} s",
            samples.len() + 1,
            s.evaluate,
            s.schur_factor,
            s.schur_solve,
            s.numeric,
            s.solve,
            s.symbolic,
            s.scratch,
            s.cholesky(),
            s.estimate
        );
        samples.push(s);
    }
    let pick = |f: &dyn Fn(&Sample) -> f64| median(samples.iter().map(f).collect());
    let median_sample = Sample {
        evaluate: pick(&|s| s.evaluate),
        schur_factor: pick(&|s| s.schur_factor),
        schur_solve: pick(&|s| s.schur_solve),
        whole_factor: pick(&|s| s.whole_factor),
        whole_solve: pick(&|s| s.whole_solve),
        residual: pick(&|s| s.residual),
        numeric: pick(&|s| s.numeric),
        solve: pick(&|s| s.solve),
        symbolic: pick(&|s| s.symbolic),
        scratch: pick(&|s| s.scratch),
        cholesky_symbolic: pick(&|s| s.cholesky_symbolic),
        cholesky_solve: pick(&|s| s.cholesky_solve),
        estimate: pick(&|s| s.estimate),
    };
    let cholesky = median_sample.cholesky();
    Row {
        label,
        size_factor,
        unknowns: n,
        nonzeros: pattern.nnz(),
        bonded_unknowns: bonded_disc.dofs.n_free,
        contact_faces,
        layer,
        rows,
        schur_setup,
        whole_setup,
        newton_steps,
        contact_solve,
        in_situ_step,
        assemble_bonded,
        median: median_sample,
        step_schur: pick(&Sample::step_schur),
        step_schur_over_cholesky: pick(&|s| s.step_schur() / s.cholesky()),
        step_whole: pick(&Sample::step_whole),
        whole_over_rows_lu: pick(&|s| s.whole_factor / s.schur_factor),
        whole_over_rows_step: pick(&|s| s.step_whole() / s.step_schur()),
        step: pick(&Sample::step),
        step_scratch: pick(&Sample::step_scratch),
        saving_factor: pick(&|s| s.symbolic / s.scratch),
        saving_step: pick(&|s| s.symbolic / s.step_scratch()),
        saving_step_direct: pick(&|s| 1.0 - s.step() / s.step_scratch()),
        step_over_cholesky: pick(&|s| s.step() / s.cholesky()),
        step_over_assemble_cholesky: pick(&|s| s.step() / (assemble_bonded + s.cholesky())),
        estimate_over_step: pick(&|s| s.estimate / s.step_schur()),
        contact_over_cholesky: contact_solve / cholesky,
        peak_mib: peak_memory_mib(),
    }
}

fn table(rows: &[Row], repeats: usize) -> String {
    let mut out = String::new();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    out += &format!(
        "## Newton step breakdown, Scene A (P2, contact on the base), median of {repeats} repetitions, {threads} threads\n\n"
    );
    out += "Times in seconds, at the converged state. Newton's step = evaluate F, J + dense LU of the \
            Schur complement S_R on the rows R of the contact terms + two solves (the step and its \
            refinement) + one residual evaluation (full step accepted by the line search); once per mesh, \
            the Cholesky factorisation of the stiffness with the layer last and its dense blocks.\n\n";
    out += "| target | unknowns | contact layer [dofs] | rows R [dofs] | once per mesh: Cholesky, layer last, and its blocks | evaluate F, J | LU of S_R | two solves | **step** | bonded: Cholesky symbolic + numeric + solve | **step / Cholesky solve** (≤ 1.5) | contact solve [s] | Newton steps |\n";
    out += "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let m = &r.median;
        out += &format!(
            "| {} | {} | {} | {} | {:.3} | {:.4} | {:.4} | {:.4} | **{:.4}** | {:.4} | **{:.2}** | {:.2} | {} |\n",
            r.label,
            r.unknowns,
            r.layer,
            r.rows,
            r.schur_setup,
            m.evaluate,
            m.schur_factor,
            m.schur_solve,
            r.step_schur,
            m.cholesky(),
            r.step_schur_over_cholesky,
            r.contact_solve,
            r.newton_steps,
        );
    }
    out += "\nThe same step with the LU of the Schur complement S = S₀ + C on the whole layer (R = L, \
            as for θ ≠ 0), in the same repetitions.\n\n";
    out += "| target | unknowns | once per mesh: Cholesky, layer last, and S₀ | LU of S | two solves | **step** | LU of S / LU of S_R | step / step on R |\n";
    out += "|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let m = &r.median;
        out += &format!(
            "| {} | {} | {:.3} | {:.4} | {:.4} | **{:.4}** | {:.1} | {:.2} |\n",
            r.label,
            r.unknowns,
            r.whole_setup,
            m.whole_factor,
            m.whole_solve,
            r.step_whole,
            r.whole_over_rows_lu,
            r.whole_over_rows_step,
        );
    }
    out += "\nThe same step by the sparse LU of the whole Jacobian (the fallback above 6 000 layer dofs): \
            evaluate F, J + numeric LU + two triangular solves + one residual evaluation.\n\n";
    out += "| target | size factor | unknowns | nnz(J) | contact faces | evaluate F, J | evaluate F | LU numeric (symbolic reused) | two solves | **LU step** | LU symbolic | LU from scratch (symbolic + numeric) | LU step from scratch | bonded: unknowns | bonded: assemble | bonded: Cholesky symbolic + numeric + solve |\n";
    out += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let m = &r.median;
        out += &format!(
            "| {} | {} | {} | {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | **{:.4}** | {:.4} | {:.4} | {:.4} | {} | {:.4} | {:.4} |\n",
            r.label,
            r.size_factor,
            r.unknowns,
            r.nonzeros,
            r.contact_faces,
            m.evaluate,
            m.residual,
            m.numeric,
            m.solve,
            r.step,
            m.symbolic,
            m.scratch,
            r.step_scratch,
            r.bonded_unknowns,
            r.assemble_bonded,
            m.cholesky(),
        );
    }
    out += "\nRatios (medians of the per-repetition ratios) and the converged contact solve \
            (zero initial guess, CLI settings: δ = 10⁻⁴ × stress scale, γ₀ = 100, θ = 0, rtol = 10⁻¹⁰). \
            Saving of reuse per step = LU symbolic / step from scratch, both timed in the same block; \
            the direct difference 1 − step / step from scratch compares two separately timed numeric \
            LUs and carries the load noise of the machine.\n\n";
    out += "| target | unknowns | share of LU step: evaluate F, J / LU / solves / evaluate F | saving of reuse: LU (symbolic / LU from scratch) | saving of reuse: LU step (direct difference in brackets) | LU step / Cholesky solve | LU step / (assemble + Cholesky) | **Newton steps** | contact solve [s] | mean step in the solve [s] | contact solve / Cholesky solve | estimate [s] | **estimate / Newton's step** (≤ 0.5) | peak memory [MiB] |\n";
    out += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for r in rows {
        let m = &r.median;
        let share = |t: f64| 100.0 * t / r.step;
        out += &format!(
            "| {} | {} | {:.1} % / {:.1} % / {:.1} % / {:.1} % | {:.0} % | **{:.0} %** ({:.0} %) | **{:.2}** | {:.2} | **{}** | {:.2} | {:.4} | {:.1} | {:.4} | **{:.2}** | {:.0} |\n",
            r.label,
            r.unknowns,
            share(m.evaluate),
            share(m.numeric),
            share(m.solve),
            share(m.residual),
            100.0 * r.saving_factor,
            100.0 * r.saving_step,
            100.0 * r.saving_step_direct,
            r.step_over_cholesky,
            r.step_over_assemble_cholesky,
            r.newton_steps,
            r.contact_solve,
            r.in_situ_step,
            r.contact_over_cholesky,
            m.estimate,
            r.estimate_over_step,
            r.peak_mib,
        );
    }
    out
}

fn main() {
    let mut million = false;
    let mut repeats = 7;
    let mut output = PathBuf::from("out/newton_breakdown.md");
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--million" => million = true,
            "--repeats" => {
                repeats = args.next().and_then(|v| v.parse().ok()).filter(|&r| r > 0).expect("--repeats N, N ≥ 1")
            }
            flag if flag.starts_with("--") => {
                panic!("unknown option {flag}; usage: newton_breakdown [--million] [--repeats N] [OUTPUT]")
            }
            _ => output = PathBuf::from(arg),
        }
    }
    let scene = Scene::load(Path::new("geo/scene_a.toml")).expect("run from the crate root: geo/scene_a.toml");
    let sizes = if million { &SIZE_FACTORS[..] } else { &SIZE_FACTORS[..2] };
    let rows: Vec<Row> = sizes.iter().map(|&(factor, label)| measure(&scene, factor, label, repeats)).collect();
    let text = table(&rows, repeats);
    println!("{text}");
    if let Some(dir) = output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).expect("create the output directory");
    }
    write_output(&output, text.as_bytes()).expect("write the table");
    eprintln!("table written to {}", output.display());
}
