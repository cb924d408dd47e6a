//! Command-line interface: `damfem mesh`, `damfem check`, `damfem solve`, `damfem adapt`,
//! `damfem safety`.
//!
//! Library errors become one plain sentence on stderr and exit code 1; progress goes to
//! stderr (one line per stage with its time), results to stdout and the output directory.

mod adapt;
mod check;
mod common;
pub mod interrupt;
mod mesh;
mod output;
mod safety;
mod solve;

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
    match result {
        Ok(()) => 0,
        Err(e) => {
            common::remove_created_dirs();
            eprintln!("error: {}", message(&format!("{e:#}")));
            1
        }
    }
}

/// Longest line of an error message, in characters.
const MAX_LINE: usize = 300;

/// An error message as printed: each line capped at [`MAX_LINE`] characters, the lines after
/// the first indented.
fn message(text: &str) -> String {
    let cap = |line: &str| match line.char_indices().nth(MAX_LINE) {
        Some((end, _)) => format!("{}… ({} more characters)", &line[..end], line[end..].chars().count()),
        None => line.to_string(),
    };
    text.trim_end().lines().map(cap).collect::<Vec<_>>().join("\n  ")
}

#[cfg(test)]
mod tests {
    use super::Cli;
    use clap::CommandFactory;

    #[test]
    fn error_lines_are_capped_and_indented() {
        let long = "x".repeat(1000);
        let text = super::message(&format!("first\n{long}\nlast\n"));
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "first");
        assert_eq!(lines[1], format!("  {}… (700 more characters)", "x".repeat(300)));
        assert_eq!(lines[2], "  last");
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }
}
