//! The quick stability sweep (examples/stability.rs) run in-process: every combination
//! either converges or stops with the solver's reason, nothing panics, no NaN/inf reaches
//! u, the stresses or the contact states, and the tables are written.

#[allow(dead_code)]
#[path = "../../examples/stability.rs"]
mod driver;

use damfem::verify::sweep::{broken, write_tables, Status};
use driver::Plan;

#[test]
fn quick_sweep_converges_or_explains_and_stays_finite() {
    let plan = Plan::new(true);
    let rows = driver::run(&plan);
    println!("{}", driver::markdown(&plan, &rows));
    assert!(rows.len() >= 20, "the quick sweep has {} rows", rows.len());
    for row in &rows {
        let name = format!("{} / {}", row.group, row.case);
        match row.status {
            Status::Converged => {
                assert!(row.solution.is_some(), "{name}: converged without a solution");
                let r = row.rel_residual.expect("a converged row has a residual");
                assert!(r.is_finite() && r <= 1e-8, "{name}: relative residual {r}");
            }
            Status::Stagnated | Status::Failed => {
                assert!(!row.reason.trim().is_empty(), "{name}: stopped without a reason");
                assert!(!row.reason_short.trim().is_empty(), "{name}: no short reason");
            }
            Status::Panicked => panic!("{name}: {}", row.reason),
        }
        assert_ne!(row.finite(), Some(false), "{name}: NaN/inf in {:?}", row.solution.as_ref().map(|s| &s.nonfinite));
    }
    assert!(broken(&rows).is_empty());

    // properties that must hold, not findings: the base case converges, the dimensionless
    // runs reproduce the SI answer, the Cholesky solves of Scene B agree with LU
    let base = &rows[0];
    assert_eq!((base.group.as_str(), base.status), ("base", Status::Converged));
    for row in rows.iter().filter(|r| r.group == "units" || r.group == "contrast") {
        assert_eq!(row.status, Status::Converged, "{} / {}: {}", row.group, row.case, row.reason);
        assert_eq!(row.matches, Some(true), "{} / {}: Δu = {:?}, ΔL_c = {:?}", row.group, row.case, row.du, row.dl);
    }

    // the tables: one markdown line and one CSV line per row
    let dir = std::env::temp_dir().join(format!("damfem-stability-{}", std::process::id()));
    let md = dir.join("stability.md");
    let csv = write_tables(&driver::markdown(&plan, &rows), &rows, &md).expect("tables written");
    let table_lines = std::fs::read_to_string(&md).unwrap().lines().filter(|l| l.starts_with("| ")).count();
    assert_eq!(table_lines, rows.len() + 1, "markdown rows + header");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with("group,case,"));
    assert!(text.lines().count() > rows.len(), "CSV rows + header");
    std::fs::remove_dir_all(&dir).unwrap();
}
