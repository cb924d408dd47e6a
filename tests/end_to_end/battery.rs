//! The battery of random gravity-dam sections (`damfem::verify::battery`) through the
//! `damfem` binary, against the exact limit equilibrium of each section.

use super::support::TempDir;
use damfem::contact::Bond;
use damfem::verify::battery::{cases, header, row, run, run_with, summary, DamCase, Record, STRENGTH_GAP};
use std::path::Path;

/// The seed of the battery, that of `cargo run --release --example dam_battery`.
const SEED: u64 = 1;

// Source: the first 20 cases of the battery of seed 1 (`damfem::verify::battery`: heights
// 20–120 m, rigid foundations and rock blocks, inclined bases, galleries, tailwater, drains,
// both crack rules, pseudo-static accelerations up to 0.2 g), each against the section's
// statics, FS = (c L_c + F N)/|T| with N = R·ν − U, T = −R·τ (the module's doc).
// Goal: every case gives a result or the verdict that the dam does not hold; a verdict only
// where FS < 1 and a result only where FS ≥ 1 (within 2 % of FS = 1 either); on the results
// with c = 0, |FS_LE − FS| ≤ 10⁻⁴ FS: the joint's forces balance the loads; every filled
// crack at its fixed point (open length = s_c within 10⁻³ L), or stopped at the drain line;
// every result's Newton steps add up (summary.json's total = its stages + the discarded
// attempts = the steps of its load path's states, `damfem::verify::battery::run`).
// Parameters: P1 and P2 as drawn, gmsh's sizes H/12 in the dam and H/48 at the heel and the
// toe, times 0.5 at P1 (a few thousand unknowns each).
#[test]
fn the_battery_matches_limit_equilibrium() {
    assert_matches_limit_equilibrium(&solved(cases(SEED, 20), "battery"));
}

// Source: the first 12 cases of the same battery with a bond on every joint, σ_t = 0.5 MPa
// and G_f = 100 N/m (docs/method.md §1.13): the bond changes the cracks, the uplift in them
// and the law, not the statics, and FS_LE counts the whole N, the bond's tension included.
// Goal: as `the_battery_matches_limit_equilibrium`, on dams the bond was not written for.
// Parameters: the battery's meshes.
#[test]
fn the_bonded_battery_matches_limit_equilibrium() {
    let bond = Some(Bond { tensile_strength: 5e5, fracture_energy: 100.0 });
    let bonded = cases(SEED, 12).into_iter().map(|case| DamCase { bond, ..case }).collect();
    assert_matches_limit_equilibrium(&solved(bonded, "battery-bonded"));
}

/// Each of `cases` solved by the binary in a directory of its own under a temporary one
/// named after `name`, beside its exact reference; the table printed.
fn solved(cases: Vec<DamCase>, name: &str) -> Vec<Record> {
    let tmp = TempDir::new(name);
    let damfem = Path::new(env!("CARGO_BIN_EXE_damfem"));
    let records: Vec<Record> = cases
        .into_iter()
        .map(|case| {
            let outcome = run(damfem, &case, &tmp.0.join(format!("seed_{}", case.seed))).unwrap();
            Record::new(case, outcome)
        })
        .collect();
    let rows: Vec<String> = records.iter().map(row).collect();
    println!("{}\n{}\n\n{}", header(), rows.join("\n"), summary(&records));
    records
}

/// Every record a result where it holds and a verdict where it does not, FS_LE within 10⁻⁴ of
/// the exact FS where c = 0, and every filled crack at its fixed point.
fn assert_matches_limit_equilibrium(records: &[Record]) {
    let wrong: Vec<&Record> = records.iter().filter(|r| !r.agrees()).collect();
    assert!(wrong.is_empty(), "{}", summary(records));
    let inexact: Vec<String> =
        records.iter().filter(|r| r.case.cohesion == 0.0 && r.error().is_some_and(|e| e > 1e-4)).map(row).collect();
    assert!(inexact.is_empty(), "FS_LE off the exact FS:\n{}\n{}", header(), inexact.join("\n"));
    let unsettled: Vec<String> = records.iter().filter(|r| r.unsettled()).map(row).collect();
    assert!(unsettled.is_empty(), "cracks off their fixed point:\n{}\n{}", header(), unsettled.join("\n"));
}

// Source: cases 9 and 12 of the battery (P1 dams on rock blocks of E_rock/E_concrete 0.90 and
// 0.16, friction alone, 0.14 g and 0.13 g, the first with its crack filled); where every Newton
// failure counted as a loss of equilibrium, two such dams had FS_SR 17 % and 6.5 % below FS_LE.
// Goal: N and T of the dam's statics do not
// depend on k, so FS_SR's bracket must hold the exact FS = F N/|T| within 0.5 %
// (docs/method.md §1.9). Parameters: the battery's meshes.
#[test]
fn the_strength_reduction_finds_the_limit_equilibrium_of_dams_on_rock() {
    let tmp = TempDir::new("battery-strength");
    let damfem = Path::new(env!("CARGO_BIN_EXE_damfem"));
    for seed in [9, 12] {
        let case = DamCase::new(seed);
        let outcome = run_with(damfem, &case, &tmp.0.join(format!("seed_{seed}")), &["--strength-reduction"]).unwrap();
        let record = Record::new(case, outcome);
        let gap = record.strength_gap().unwrap_or_else(|| panic!("seed {seed}: {}", record.run.message));
        assert!(gap <= STRENGTH_GAP, "seed {seed}: FS_SR in {:?} against FS = {}", record.run.strength, record.exact);
    }
}

// Source: case 23 of the battery (a rigid foundation, friction alone, FS = 1.117) with
// [contact] max_iter = 10, where Newton fails at k far short of the limit; before, each such
// failure counted as a loss of equilibrium and FS_SR's bracket ended there, with exit 0.
// Goal: either the bracket holds the exact FS = F N/|T| within 0.5 %, or the run says that the
// strength reduction stalled (exit 4): never a bracket off the limit with exit 0.
// Parameters: the battery's mesh.
#[test]
fn a_strength_reduction_that_newton_cannot_finish_says_so() {
    let tmp = TempDir::new("battery-stalled");
    let damfem = Path::new(env!("CARGO_BIN_EXE_damfem"));
    let case = DamCase::new(23);
    let dir = tmp.0.join("seed_23");
    let scene = case.write(&dir).unwrap();
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(text.contains("max_iter = 100"), "{text}");
    std::fs::write(&scene, text.replace("max_iter = 100", "max_iter = 10")).unwrap();
    let out = std::process::Command::new(damfem)
        .args(["solve", "case.toml", "-o", "out", "--strength-reduction"])
        .current_dir(&dir)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    match out.status.code() {
        Some(4) => assert!(stderr.contains("the strength reduction stalled"), "{stderr}"),
        Some(0) => {
            let summary = std::fs::read_to_string(dir.join("out/summary.json")).unwrap();
            let json: serde_json::Value = serde_json::from_str(&summary).unwrap();
            let sr = &json["strength_reduction"];
            let (held, failed) = (sr["held"].as_f64().unwrap(), sr["failed"].as_f64().unwrap());
            let fs = json["contact"]["sliding_safety_factor"].as_f64().unwrap();
            assert!(
                held <= fs * (1.0 + 5e-3) && failed >= fs * (1.0 - 5e-3),
                "FS_SR in [{held}, {failed}], FS_LE {fs}"
            );
        }
        code => panic!("exit {code:?}: {stderr}"),
    }
}
