//! A battery of random gravity-dam sections against their exact limit equilibrium.
//!
//! What it shows: for each case of `damfem::verify::battery` (a section of height 20–120 m on
//! a rigid foundation or a meshed rock block, with its reservoir, tailwater, uplift,
//! pseudo-static acceleration and joint law drawn from the seed), the outcome of `damfem solve`
//! (a result, the verdict that the dam does not hold, a numerical failure or an error), its
//! Newton steps and FS_LE against the exact FS = (c L_c + F N)/|T| of the section's statics,
//! N = R·ν − U and T = −R·τ (the module's doc). Case i is that of seed S + i.
//!
//! Run: `cargo build --release` (the binary it runs, target/release/damfem, or the one named
//! by the environment variable DAMFEM), then `cargo run --release --example dam_battery [--
//! --cases N --seed S --keep DIR]` from the crate root (defaults: 200 cases, seed 1; the cases'
//! files and outputs go into DIR/seed_<seed>/ with `--keep`, else into a temporary directory
//! removed at the end; with `--strength-reduction` each case runs `damfem solve
//! --strength-reduction`, and the summary gives the largest distance of FS from FS_SR's
//! bracket of the c = 0 results; with `--bond σ_t,G_f` every joint has that bond, against the
//! same statics). Prints one row per case and a closing summary: the share of cases with
//! a result where they hold or a verdict where they do not (either within 2 % of FS = 1), the
//! largest FS error of the results with c = 0, the median and largest Newton steps (the most
//! on one mesh, and summed over the levels of nested iteration), and each case that went wrong
//! with its exit code and message.

use anyhow::{bail, Context, Result};
use damfem::contact::Bond;
use damfem::verify::battery::{cases, header, row, run_with, summary, DamCase, Record};
use std::path::PathBuf;

/// The options: cases, seed, and the directory to keep.
struct Options {
    cases: usize,
    seed: u64,
    keep: Option<PathBuf>,
    strength_reduction: bool,
    bond: Option<Bond>,
}

/// The usage line.
const USAGE: &str =
    "usage: dam_battery [--cases N (200)] [--seed S (1)] [--keep DIR] [--strength-reduction] [--bond SIGMA_T,G_F]";

fn options() -> Result<Option<Options>> {
    let mut options = Options { cases: 200, seed: 1, keep: None, strength_reduction: false, bond: None };
    let mut args = std::env::args().skip(1);
    while let Some(flag) = args.next() {
        match flag.as_str() {
            "--help" | "-h" => return Ok(None),
            "--strength-reduction" => {
                options.strength_reduction = true;
                continue;
            }
            _ => {}
        }
        let value = args.next().with_context(|| format!("{flag} needs a value; {USAGE}"))?;
        match flag.as_str() {
            "--cases" => options.cases = value.parse()?,
            "--seed" => options.seed = value.parse()?,
            "--keep" => options.keep = Some(value.into()),
            "--bond" => {
                let (t, g) = value.split_once(',').with_context(|| format!("--bond {value}: give SIGMA_T,G_F"))?;
                options.bond = Some(Bond { tensile_strength: t.parse()?, fracture_energy: g.parse()? });
            }
            _ => bail!("unknown option {flag}; {USAGE}"),
        }
    }
    Ok(Some(options))
}

fn main() -> Result<()> {
    let Some(options) = options()? else {
        println!("{USAGE}");
        return Ok(());
    };
    let binary = std::env::var_os("DAMFEM")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/release/damfem"));
    if !binary.is_file() {
        bail!("no damfem binary at {}: run `cargo build --release` or set DAMFEM", binary.display());
    }
    let temporary = std::env::temp_dir().join(format!("dam-battery-{}", std::process::id()));
    let root = options.keep.clone().unwrap_or_else(|| temporary.clone());
    println!("{}", header());
    let mut records = Vec::new();
    let extra: &[&str] = if options.strength_reduction { &["--strength-reduction"] } else { &[] };
    for case in cases(options.seed, options.cases) {
        let case = DamCase { bond: options.bond, ..case };
        let dir = root.join(format!("seed_{}", case.seed));
        let record = Record::new(case.clone(), run_with(&binary, &case, &dir, extra)?);
        println!("{}", row(&record));
        records.push(record);
    }
    print!("\n{}", summary(&records));
    if options.keep.is_none() {
        std::fs::remove_dir_all(&temporary)?;
    }
    Ok(())
}
