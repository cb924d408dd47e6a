//! Command-line interface: `damfem mesh`, `damfem check`, `damfem solve`, `damfem adapt`,
//! `damfem safety`.
//!
//! Library errors become one plain sentence on stderr; progress goes to stderr (one line per
//! stage with its time), results to stdout and the output directory. The exit code tells the
//! outcomes apart: 0 a result, 1 bad input (or a file that cannot be read or written), 3 the
//! dam does not hold (no equilibrium beyond a load factor λ* < 1: a result of its own), 4 the
//! solver failed (Newton, the crack's fixed point or the load path stopped without a verdict).

mod adapt;
mod check;
mod common;
pub mod interrupt;
mod lock;
mod mesh;
mod output;
mod safety;
mod settings;
mod solid;
mod solve;

use crate::adapt::AdaptError;
use crate::contact::ContactError;
use crate::safety::strength::StrengthError;
use crate::scene::SceneError;
use clap::{Parser, Subcommand};

/// Plane-strain finite elements for concrete dams, from gmsh geometry to ParaView files.
#[derive(Parser, Debug)]
#[command(name = "damfem", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Mesh a scene or a .geo file with gmsh and write the .msh and a .vtu of the mesh
    Mesh(mesh::Args),
    /// Validate a scene against its geometry (mesh it, check groups, roles and materials) without solving
    Check(check::Args),
    /// Solve the elasticity problem of a scene and write ParaView files
    Solve(solve::Args),
    /// Solve, estimate the error and refine the mesh until the estimate is small enough
    Adapt(adapt::Args),
    /// Dam safety: refine adaptively, then report the joint's forces, crack, resultant, base
    /// stresses and sliding safety factors
    Safety(safety::Args),
}

/// Runs the command line `args` and returns the process exit code.
pub fn run<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { 2 } else { 0 };
        }
    };
    let result = match cli.command {
        Command::Mesh(a) => mesh::run(a),
        Command::Check(a) => check::run(a),
        Command::Solve(a) => solve::run(a),
        Command::Adapt(a) => adapt::run(a),
        Command::Safety(a) => safety::run(a),
    };
    lock::release();
    match result {
        Ok(()) => 0,
        Err(e) => {
            common::remove_created_dirs();
            let code = exit_code(&e);
            let label = if code == DOES_NOT_HOLD { "verdict" } else { "error" };
            eprintln!("{label}: {}", message(&format!("{e:#}")));
            code
        }
    }
}

/// The exit code of a dam that does not hold.
pub const DOES_NOT_HOLD: i32 = 3;
/// The exit code of a solver that failed.
pub const SOLVER_FAILED: i32 = 4;

/// The exit code of the error `e`: [`DOES_NOT_HOLD`], [`SOLVER_FAILED`], or 1.
fn exit_code(e: &anyhow::Error) -> i32 {
    let of_contact = |c: &ContactError| match c {
        ContactError::NoEquilibrium(_) | ContactError::LiftOff { .. } => DOES_NOT_HOLD,
        _ => SOLVER_FAILED,
    };
    let code = e.chain().find_map(|link| {
        if let Some(c) = link.downcast_ref::<ContactError>() {
            return Some(of_contact(c));
        }
        if let Some(SceneError::NoEquilibrium { .. }) = link.downcast_ref::<SceneError>() {
            return Some(DOES_NOT_HOLD);
        }
        if link.is::<common::SolverFailed>() || link.is::<StrengthError>() {
            return Some(SOLVER_FAILED);
        }
        match link.downcast_ref::<AdaptError>()? {
            AdaptError::Contact(c) => Some(of_contact(c)),
            AdaptError::Newton { .. } | AdaptError::Finish(_) | AdaptError::Regularisation { .. } => {
                Some(SOLVER_FAILED)
            }
            _ => None,
        }
    });
    code.unwrap_or(1)
}

/// An error message as printed: the lines after the first indented, none cut.
fn message(text: &str) -> String {
    text.trim_end().lines().collect::<Vec<_>>().join("\n  ")
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::CommandFactory;

    #[test]
    fn error_lines_are_kept_whole_and_indented() {
        let long = "x".repeat(1000);
        let text = super::message(&format!("first\n{long}\nlast\n"));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines, ["first".to_string(), format!("  {long}"), "  last".to_string()]);
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }
}
