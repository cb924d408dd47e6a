//! Assembly and Cholesky solve time per unknown, P1 and P2, from 10⁴ to 10⁶ unknowns.
//!
//! What it shows: how the cost of the linear elasticity solve grows with the number of
//! unknowns N, and the peak memory. Problem: unit square, clamped on all sides, unit body
//! force, structured meshes (no gmsh), μ = λ = 1.
//!
//! Run: `cargo run --release --example elasticity_scaling [max_unknowns]`
//! Key numbers: unknowns per second of assembly, solve seconds at 10⁶ unknowns, peak memory
//! per 10⁶ unknowns, and the fitted exponent of time against N. The CPU time of the assembly
//! (user + system, all threads) is the steadier figure on a machine shared with other jobs.

use damfem::elasticity::{BodyForce, Dirichlet, Material, Problem};
use damfem::mesh::structured::unit_square;
use damfem::solve::Cholesky;
use std::sync::Arc;
use std::time::Instant;

/// Peak resident memory of this process so far, in MiB (Linux VmHWM).
fn peak_memory_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("VmHWM:")).map(|l| l.to_string()))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|v| v.parse::<f64>().ok()))
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// User + system CPU time of this process so far (all threads), in seconds.
fn cpu_seconds() -> f64 {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: getrusage writes into the struct it is given
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut usage) };
    let seconds = |t: libc::timeval| t.tv_sec as f64 + 1e-6 * t.tv_usec as f64;
    seconds(usage.ru_utime) + seconds(usage.ru_stime)
}

fn problem(n: usize, order: usize) -> Problem {
    let mesh = unit_square(n, order);
    Problem {
        materials: vec![Material { density: 1.0, ..Material::from_lame(1.0, 1.0) }; mesh.n_cells()],
        dirichlet: (1..=4).map(|tag| Dirichlet { tag, fix: [true; 2], value: Arc::new(|_| [0.0; 2]) }).collect(),
        neumann: vec![],
        body_force: BodyForce::Acceleration([0.0, -1.0]),
        mesh,
    }
}

fn slope(x: &[f64], y: &[f64]) -> f64 {
    let (lx, ly): (Vec<f64>, Vec<f64>) = (x.iter().map(|v| v.ln()).collect(), y.iter().map(|v| v.ln()).collect());
    let m = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / m, ly.iter().sum::<f64>() / m);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    sxy / lx.iter().map(|a| (a - mx).powi(2)).sum::<f64>()
}

fn main() {
    let max_unknowns: f64 = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(1.1e6);
    println!("| degree | unknowns | assembly [s] | unknowns/s (assembly) | assembly CPU [s] | symbolic + numeric Cholesky + solve [s] | peak memory [MiB] |");
    println!("|---|---|---|---|---|---|---|");
    for order in [1, 2] {
        let (mut sizes, mut totals) = (Vec::new(), Vec::new());
        // N ≈ 2 (p n)² unknowns on an n × n grid of degree p
        for target in [1e4, 1e5, 1e6] {
            if target > max_unknowns {
                break;
            }
            let n = ((target / 2.0).sqrt() / order as f64).round() as usize;
            // 1. Mesh and discretise
            let problem = problem(n, order);
            // 2. Assemble
            let (start, cpu) = (Instant::now(), cpu_seconds());
            let disc = problem.discretise();
            let system = problem.assemble(&disc);
            let (assembly, assembly_cpu) = (start.elapsed().as_secs_f64(), cpu_seconds() - cpu);
            // 3. Solve
            let start = Instant::now();
            let x = Cholesky::analyse(&disc.pattern)
                .and_then(|c| c.solve(&disc.pattern, &system.values, &system.rhs))
                .expect("SPD system");
            let solve = start.elapsed().as_secs_f64();
            assert!(x.iter().all(|v| v.is_finite()));
            let unknowns = disc.dofs.n_free;
            println!(
                "| P{order} | {unknowns} | {assembly:.3} | {:.3e} | {assembly_cpu:.3} | {solve:.3} | {:.0} |",
                unknowns as f64 / assembly,
                peak_memory_mib()
            );
            sizes.push(unknowns as f64);
            totals.push(assembly + solve);
        }
        if sizes.len() > 1 {
            println!(
                "| P{order} | fitted exponent of (assembly + solve) time against N: {:.2} | | | | | |",
                slope(&sizes, &totals)
            );
        }
    }
}
