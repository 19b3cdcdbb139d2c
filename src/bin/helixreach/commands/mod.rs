//! One module per subcommand.

pub mod args;
pub mod bifurcation;
pub mod boundary;
pub mod check;
pub mod compare;
pub mod demo;
pub mod detect;
pub mod disturbances;
pub mod fk;
pub mod helix;
pub mod ik;
pub mod layout;
pub mod merge;
pub mod plan;
pub mod plot;
pub mod reach;
pub mod render;
pub mod robot;
pub mod rod;
pub mod rod_args;
pub mod simulate;

/// Exit code of `plan` when the ray cannot be driven to its target s (partial or blocked) and
/// `--allow-partial` was not given: nothing is written.
pub const EXIT_NOT_TESTABLE: u8 = 3;

/// A command whose answer is "no" (a partial plan, a check with findings): `main` prints the
/// message on stderr and exits with `code` (not 2, the code of a command that could not run).
#[derive(Debug)]
pub struct Verdict {
    /// The process exit code.
    pub code: u8,
    /// What was found, for stderr.
    pub message: String,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Verdict {}
