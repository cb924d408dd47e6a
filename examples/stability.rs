//! Numerical stability stress test of the Nitsche contact solver and the linear solver.
//!
//! What it shows: how the Newton/LU solve of Scene A (dam on a rigid foundation, Nitsche
//! contact on the base) behaves when one factor at a time moves away from a base case:
//! the Nitsche parameter γ₀ (1 … 10⁴) and the variant θ, the regularisation δ over eight
//! decades (S·10⁻¹ … S·10⁻⁸, S the stress scale of the loads), Poisson's ratio up to 0.499,
//! the mesh size over three levels, a randomly distorted mesh (the manufactured Signorini
//! problem V3 on the unit square, interior nodes moved by up to 35 % of h, fixed seed) and
//! SI against dimensionless units, and Coulomb friction over a decade of F and Mohr–Coulomb
//! cohesion on the frictional dam (Scene A held by its joint alone). Scene B (dam bonded to
//! a deformable rock) measures the material contrast up to 10³ through the sparse Cholesky
//! solve, checked by its residual and by an independent LU solve. The cases are a list of
//! `verify::cases::Case` values, which that module solves and compares. Every combination reports its Newton steps, final relative
//! residual, status (or the solver's own error text), a Hager–Higham estimate of the 1-norm
//! condition number of the final Jacobian, and the difference to a reference answer.
//!
//! Run: `cargo run --release --example stability -- [--quick] [OUTPUT.md]`
//! (default `out/stability.md`; the CSV goes next to it as `out/stability.csv`). `--quick`
//! runs a P1, coarse-mesh subset in seconds. The exit status is non-zero if any combination
//! panicked or produced a NaN/inf.
//!
//! Key number: the count of combinations that converged, stopped with a reason, or missed
//! their reference, printed on the last line ("N combinations: …").

use anyhow::Result;
use damfem::contact::JointLaw;
use damfem::verify::cases::{Case, Model, Role, Rule};
use damfem::verify::sweep::{broken, markdown_rows, summary, write_tables, Knobs, Row};
use std::path::PathBuf;

/// Water density ρ_w, gravity g and dam height H of Scene A: σ₀ = ρ_w g H.
const RHO_W: f64 = 1000.0;
const GRAVITY: f64 = 9.81;
const DAM_HEIGHT: f64 = 50.0;

/// Which values each factor takes.
#[derive(Debug, Clone)]
pub struct Plan {
    pub quick: bool,
    /// Degree and gmsh size factor of the base case (Scene A).
    pub order: usize,
    pub size: f64,
    pub gamma0: Vec<f64>,
    /// (θ, γ₀) pairs besides the base θ = 0.
    pub theta: Vec<(f64, f64)>,
    /// δ = S·10^−k for these k, solved directly from zero.
    pub delta_exponents: Vec<i32>,
    /// δ = S·10^−k reached by continuation from S·10⁻¹.
    pub continuation_exponents: Vec<i32>,
    /// Also δ = 0 (plain projection, semismooth Newton).
    pub semismooth: bool,
    pub nu: Vec<f64>,
    pub nu_orders: Vec<usize>,
    /// Degree and size factor of the reference solution at each ν.
    pub nu_reference: (usize, f64),
    /// γ₀ of an extra row at the largest ν (γ scaled up with the bulk modulus).
    pub nu_gamma0: f64,
    /// Size factors; the reference is the finest at the highest degree.
    pub sizes: Vec<f64>,
    pub size_orders: Vec<usize>,
    /// V3 on an n × n structured mesh, interior nodes moved by up to fraction · h.
    pub v3_n: usize,
    pub v3_orders: Vec<usize>,
    pub distortions: Vec<f64>,
    /// Coulomb coefficients F, and cohesions c [Pa] at the smallest F, on the frictional dam.
    pub friction: Vec<f64>,
    pub cohesion: Vec<f64>,
    /// Scene B: the rock's E is divided by these factors.
    pub rock_divisors: Vec<f64>,
    pub scene_b: (usize, f64),
}

impl Plan {
    /// The full sweep (P2 base) or the quick subset (P1, coarse meshes, fewer values).
    pub fn new(quick: bool) -> Plan {
        if quick {
            Plan {
                quick,
                order: 1,
                size: 2.0,
                gamma0: vec![1.0, 1e2, 1e4],
                theta: vec![(1.0, 1.0), (-1.0, 1.0)],
                delta_exponents: vec![1, 4, 8],
                continuation_exponents: vec![8],
                semismooth: false,
                nu: vec![0.3, 0.499],
                nu_orders: vec![1],
                nu_reference: (2, 2.0),
                nu_gamma0: 1e4,
                sizes: vec![4.0, 2.0, 1.0],
                size_orders: vec![1],
                v3_n: 8,
                v3_orders: vec![1],
                distortions: vec![0.0, 0.35],
                friction: vec![0.8391, 8.391],
                cohesion: vec![1e5],
                rock_divisors: vec![1.0, 1e3],
                scene_b: (1, 2.0),
            }
        } else {
            Plan {
                quick,
                order: 2,
                size: 1.0,
                gamma0: vec![1.0, 1e1, 1e2, 1e3, 1e4],
                theta: vec![(1.0, 1.0), (1.0, 1e2), (-1.0, 1.0), (-1.0, 1e2)],
                delta_exponents: (1..=8).collect(),
                continuation_exponents: vec![8],
                semismooth: true,
                nu: vec![0.0, 0.3, 0.49, 0.499],
                nu_orders: vec![1, 2],
                nu_reference: (2, 0.5),
                nu_gamma0: 1e4,
                sizes: vec![2.0, 1.0, 0.5],
                size_orders: vec![1, 2],
                v3_n: 16,
                v3_orders: vec![1, 2],
                distortions: vec![0.0, 0.2, 0.35],
                friction: vec![0.8391, 1.2, 2.5, 8.391],
                cohesion: vec![1e5, 1e6],
                rock_divisors: vec![1.0, 1e1, 1e2, 1e3],
                scene_b: (2, 1.0),
            }
        }
    }
}

/// Scene A (`nu`: Poisson's ratio if changed) at degree `order` and size factor `size`.
fn scene_a(order: usize, size: f64, nu: Option<f64>) -> Model {
    Model::Dam { file: "scene_a.toml", order, size, nu, scaled: None }
}

/// One case.
fn case(group: &'static str, label: String, model: Model, knobs: Knobs, role: Role) -> Case {
    Case { group, label, model, knobs, role }
}

/// The combinations of `plan`, in order: base, γ₀, θ, δ, ν, mesh size, distortion, units,
/// friction, material contrast.
pub fn cases(plan: &Plan) -> Vec<Case> {
    let (p, size) = (plan.order, plan.size);
    let base = scene_a(p, size, None);
    let against_base = || Role::Compared("base".into(), Rule::Parameter);
    let mut list = Vec::new();

    // 1. Base case: Scene A, γ₀ = 100, θ = 0, δ = 10⁻⁴ S, direct Newton from zero
    let label = format!("Scene A P{p}, size {size}, γ₀=100, θ=0, δ=1e-4·S");
    list.push(case("base", label, base, Knobs::default(), Role::Reference("base".into())));

    // 2. γ₀ sweep at θ = 0, then the θ variants at a small and the default γ₀
    for &gamma0 in &plan.gamma0 {
        list.push(case(
            "gamma0",
            format!("γ₀ = {gamma0:.0e}"),
            base,
            Knobs { gamma0, ..Knobs::default() },
            against_base(),
        ));
    }
    for &(theta, gamma0) in &plan.theta {
        let knobs = Knobs { gamma0, theta, ..Knobs::default() };
        list.push(case("theta", format!("θ = {theta}, γ₀ = {gamma0:.0e}"), base, knobs, against_base()));
    }

    // 3. δ over eight decades, direct; the smallest also by continuation; δ = 0
    for &k in &plan.delta_exponents {
        let knobs = Knobs { delta: 10f64.powi(-k), ..Knobs::default() };
        list.push(case("delta", format!("δ = 1e-{k}·S"), base, knobs, against_base()));
    }
    for &k in &plan.continuation_exponents {
        let knobs = Knobs { delta: 10f64.powi(-k), start: Some(0.1), ..Knobs::default() };
        list.push(case("delta", format!("δ = 1e-{k}·S, continuation from 1e-1·S"), base, knobs, against_base()));
    }
    if plan.semismooth {
        let knobs = Knobs { delta: 0.0, ..Knobs::default() };
        list.push(case("delta", "δ = 0 (semismooth)".into(), base, knobs, against_base()));
    }

    // 4. Poisson's ratio towards incompressibility, against P2 on a finer mesh at the same ν;
    //    the largest ν also with γ₀ scaled up with the bulk modulus
    let (ref_order, ref_size) = plan.nu_reference;
    let largest_nu = plan.nu.iter().copied().fold(f64::MIN, f64::max);
    for &nu in &plan.nu {
        let name = format!("ν = {nu}");
        let label = format!("ν = {nu}, reference P{ref_order} size {ref_size}");
        let model = scene_a(ref_order, ref_size, Some(nu));
        list.push(case("nu", label, model, Knobs::default(), Role::Reference(name.clone())));
        let mut variants: Vec<(usize, f64)> = plan.nu_orders.iter().map(|&o| (o, 100.0)).collect();
        if nu == largest_nu {
            variants.extend(plan.nu_orders.iter().map(|&o| (o, plan.nu_gamma0)));
        }
        for (order, gamma0) in variants {
            let label = format!("ν = {nu}, P{order} size {size}, γ₀ = {gamma0:.0e}");
            let role = Role::Compared(name.clone(), Rule::Discretisation);
            list.push(case("nu", label, scene_a(order, size, Some(nu)), Knobs { gamma0, ..Knobs::default() }, role));
        }
    }

    // 5. Mesh size over three levels; the reference is the finest mesh at the highest degree
    let finest = plan.sizes.iter().copied().fold(f64::INFINITY, f64::min);
    let top = plan.size_orders.iter().copied().max().unwrap_or(p);
    for &order in &plan.size_orders {
        for &s in &plan.sizes {
            let role = if order == top && s == finest {
                Role::Reference("mesh".into())
            } else {
                Role::Compared("mesh".into(), Rule::Discretisation)
            };
            list.push(case(
                "mesh",
                format!("P{order}, size factor {s}"),
                scene_a(order, s, None),
                Knobs::default(),
                role,
            ));
        }
    }

    // 6. Distorted meshes: V3 with interior vertices moved by up to a fraction of h
    let n = plan.v3_n;
    for &order in &plan.v3_orders {
        let name = format!("V3 P{order}");
        for &fraction in &plan.distortions {
            let label = format!("V3 {n}×{n} P{order}, vertices moved ≤ {:.0} % of h", 100.0 * fraction);
            let role = if fraction == 0.0 {
                Role::Reference(name.clone())
            } else {
                Role::Compared(name.clone(), Rule::Discretisation)
            };
            list.push(case("distorted", label, Model::V3 { n, order, fraction }, Knobs::default(), role));
        }
    }

    // 7. SI units against dimensionless ones (σ₀ = ρ_w g H, lengths by H), scaled back
    let sigma0 = RHO_W * GRAVITY * DAM_HEIGHT;
    for (label, length) in [("stresses / σ₀ = ρ_w g H", 1.0), ("stresses / σ₀, lengths / H", DAM_HEIGHT)] {
        let model = Model::Dam { file: "scene_a.toml", order: p, size, nu: None, scaled: Some((sigma0, length)) };
        let role = Role::Compared("base".into(), Rule::Units);
        list.push(case("units", format!("{label} (vs base in SI)"), model, Knobs::default(), role));
    }

    // 8. Friction: the frictional dam over a decade of F, then cohesion at the smallest F
    let dam = Model::Dam { file: "scene_a_friction.toml", order: p, size, nu: None, scaled: None };
    let smallest = plan.friction.iter().copied().fold(f64::INFINITY, f64::min);
    let laws = plan
        .friction
        .iter()
        .map(|&friction| JointLaw::Coulomb { friction })
        .chain(plan.cohesion.iter().map(|&cohesion| JointLaw::MohrCoulomb { friction: smallest, cohesion }));
    for law in laws {
        let knobs = Knobs { law, start: Some(0.1), max_iter: 100, ..Knobs::default() };
        let label = format!("frictional dam P{p} size {size}, {law:?}, δ from 1e-1·S to 1e-4·S");
        list.push(case("friction", label, dam, knobs, Role::Alone));
    }

    // 9. Material contrast: Scene B (bonded interface) with a softer rock, Cholesky vs LU
    let (order, size) = plan.scene_b;
    for &divisor in &plan.rock_divisors {
        let label = format!("Scene B P{order} size {size}, E_rock / {divisor:.0e} (E_c/E_r = {:.1e})", 1.5 * divisor);
        list.push(case("contrast", label, Model::Bonded { order, size, divisor }, Knobs::default(), Role::Alone));
    }
    list
}

/// Runs every combination of `plan`.
pub fn run(plan: &Plan) -> Vec<Row> {
    damfem::verify::cases::run(&cases(plan))
}

/// The markdown table with a short preamble.
pub fn markdown(plan: &Plan, rows: &[Row]) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "# Stability sweep ({} mode)\n\n\
         Base: Scene A (dam on a rigid foundation, Nitsche contact on the base), P{} with gmsh size factor {}, \
         γ₀ = 100, θ = 0, δ = 10⁻⁴ S (S = stress scale of the loads), direct Newton from u = 0 \
         (≤ 50 steps, rtol 10⁻¹⁰). One factor varies per row.\n\n\
         - Δu = max(max over the probe points |u − u_ref| / max |u_ref(probe)|, relative difference of max |u|); \
         ΔL_c = difference of contact lengths.\n\
         - Reference and tolerance: γ₀/θ/δ rows against the base (1 %, two contact faces); ν rows against P{} \
         size {} at the same ν and mesh rows against the finest P{} mesh (5 %, two faces of the coarser mesh); \
         distorted V3 against the undistorted grid (5 %); units against the base in SI (10⁻⁸ on u, 10⁻⁵ L_c on L_c); \
         Scene B Cholesky against an LU solve of the same system (10⁻⁸).\n\
         - cond₁: Hager–Higham estimate of ‖J‖₁‖J⁻¹‖₁ for the Jacobian at the answer (stiffness matrix for Scene B).\n\
         - finite: u, cell stresses and contact-face states free of NaN/inf.\n\
         - A combination whose Newton runs out of steps is retried (rows marked ↳): with rtol 10⁻⁸ if the \
         residual had reached 10⁻⁸, else by δ-continuation from 10⁻¹ S, then with 200 steps.\n\n",
        if plan.quick { "quick" } else { "full" },
        plan.order,
        plan.size,
        plan.nu_reference.0,
        plan.nu_reference.1,
        plan.size_orders.iter().max().unwrap_or(&plan.order),
    ));
    out.push_str(&markdown_rows(rows));
    out.push_str(&format!("\n{}\n", summary(rows)));
    out
}

#[derive(clap::Parser, Debug)]
#[command(about = "Stability sweep of the Nitsche contact solver (γ₀, θ, δ, ν, mesh, distortion, units, contrast)")]
struct Args {
    /// Fast subset: P1, coarse meshes, a few values of each factor
    #[arg(long)]
    quick: bool,
    /// Markdown output; the CSV is written next to it with extension .csv
    #[arg(default_value = "out/stability.md")]
    output: PathBuf,
}

fn main() -> Result<()> {
    use clap::Parser;
    let args = Args::parse();
    let plan = Plan::new(args.quick);
    eprintln!("stability sweep ({} mode)", if plan.quick { "quick" } else { "full" });
    let rows = run(&plan);
    let table = markdown(&plan, &rows);
    println!("{table}");
    let csv_path = write_tables(&table, &rows, &args.output).map_err(|e| anyhow::anyhow!(e))?;
    eprintln!("wrote {} and {}", args.output.display(), csv_path.display());
    let broken = broken(&rows);
    if !broken.is_empty() {
        anyhow::bail!("{} combination(s) panicked or produced NaN/inf:\n{}", broken.len(), broken.join("\n"));
    }
    Ok(())
}
