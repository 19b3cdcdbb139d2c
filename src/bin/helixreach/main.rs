//! `helixreach`: thin command-line glue over the library. Every subcommand lives in
//! `commands/<name>.rs` as an `Args` struct (clap) and a `run(args) -> anyhow::Result<()>`.
//! Machine-readable output goes to files or stdout; progress and errors go to stderr.
//! Exit code 0 on success, 2 on error; a broken pipe on stdout counts as success. A command
//! whose answer is "no" exits with its own code (`commands::Verdict`): `plan` 3 when the ray
//! cannot be driven to its target, `check` 64 + a bit per kind of finding.
//! `helixreach --version` prints the version and the git commit it was built from (`unknown`
//! when built outside a git checkout; see `build.rs`).

mod commands;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

/// Plan robotic stability experiments on elastic rods with helical centerlines.
#[derive(Debug, Parser)]
#[command(
    name = "helixreach",
    version = concat!(env!("CARGO_PKG_VERSION"), " (commit ", env!("HELIXREACH_COMMIT"), ")"),
    about
)]
struct Cli {
    /// `--threads`, `--quiet`: taken by every subcommand.
    #[command(flatten)]
    global: commands::Global,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// End pose of the rod for a helix (κ, τ, ω), or for every row of a CSV.
    Helix(commands::helix::Args),
    /// Stability boundary s* along a set of directions.
    Boundary(commands::boundary::Args),
    /// Subcritical snap or supercritical departure at s*, with the static return on unloading.
    Bifurcation(commands::bifurcation::Args),
    /// Measured snap points versus a simulated boundary (the paper's err per direction).
    Compare(commands::compare::Args),
    /// The snap from a recorded run (joints + tracked marker), or a batch of runs.
    Detect(commands::detect::Args),
    /// DER dynamics: drive the rod along one ray at finite speed.
    Simulate(commands::simulate::Args),
    /// A rig's rod and whether gravity matters for it (L_gb/L), as JSON.
    Rod(commands::rod::Args),
    /// The seed paper's disturbance study (its Fig. 5).
    Disturbances(commands::disturbances::Args),
    /// Forward kinematics of a URDF robot.
    Fk(commands::fk::Args),
    /// All inverse-kinematics solutions for a tool pose.
    Ik(commands::ik::Args),
    /// Print a robot's chain, limits and collision bodies.
    Robot(commands::robot::Args),
    /// Rig files: `rig init` writes a commented rig for a URDF arm.
    Rig(commands::rig::Args),
    /// Plan the joint + motor trajectory of one ray on a rig.
    Plan(commands::plan::Args),
    /// Validate a joint trajectory on a rig: limits, collisions, steps, pose error.
    Check(commands::check::Args),
    /// Reachability sweep of a rig over a direction set.
    Reach(commands::reach::Args),
    /// Every testable ray of a direction set planned, ordered and split into sessions.
    Campaign(commands::campaign::Args),
    /// Clamp placements that together cover a direction set (rig layout).
    Layout(commands::layout::Args),
    /// Join shard outputs of `reach` (or `boundary`).
    Merge(commands::merge::Args),
    /// Regenerate a figure from saved CSVs.
    Plot(commands::plot::Args),
    /// Snapshots of robot, rod and scene along a planned trajectory (strip, GIF, clearances).
    Render(commands::render::Args),
    /// The main job: boundary, reachability, dynamics and figures on the default rig.
    Demo(commands::demo::Args),
}

/// The error and its causes, each printed once: a cause whose text the message already holds
/// (e.g. the OS error inside a `path: OS error` message) is not repeated.
fn message(e: &anyhow::Error) -> String {
    let mut msg = e.to_string();
    for cause in e.chain().skip(1) {
        let t = cause.to_string();
        if !msg.contains(&t) {
            msg.push_str(": ");
            msg.push_str(&t);
        }
    }
    msg
}

/// The command line with every `--flag NUMBER` whose number is negative written `--flag=NUMBER`:
/// clap's own negative-number test does not know exponents (`--tau -1e-12`).
fn negative_values_joined() -> Vec<std::ffi::OsString> {
    let mut out: Vec<std::ffi::OsString> = Vec::new();
    for a in std::env::args_os() {
        let negative_number = a
            .to_str()
            .is_some_and(|t| t.starts_with('-') && t.parse::<f64>().is_ok());
        let after_long_flag = out
            .last()
            .and_then(|p| p.to_str())
            .is_some_and(|p| p.starts_with("--") && p.len() > 2 && !p.contains('='));
        if negative_number && after_long_flag {
            let flag = out.pop().unwrap_or_default();
            let mut joined = flag;
            joined.push("=");
            joined.push(&a);
            out.push(joined);
        } else {
            out.push(a);
        }
    }
    out
}

fn main() -> ExitCode {
    // A negative number after a flag is its value (`--tau -1e-12`, `--fibonacci -5`), never a
    // flag: every subcommand accepts negative numbers as values.
    let cmd = Cli::command().mut_subcommands(|s| s.allow_negative_numbers(true));
    let cli = match Cli::from_arg_matches(&cmd.get_matches_from(negative_values_joined())) {
        Ok(c) => c,
        Err(e) => e.exit(),
    };
    commands::set_global(cli.global);
    helixreach::robot::CollisionModel::set_announce(!cli.global.quiet);
    let result = commands::with_threads(cli.global.threads, || run(cli.command));
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // serde_json keeps the io::Error to itself: ask it for the kind.
            let broken = |k: Option<std::io::ErrorKind>| k == Some(std::io::ErrorKind::BrokenPipe);
            if e.chain().any(|c| {
                broken(c.downcast_ref::<std::io::Error>().map(|io| io.kind()))
                    || broken(
                        c.downcast_ref::<serde_json::Error>()
                            .and_then(|j| j.io_error_kind()),
                    )
            }) {
                return ExitCode::SUCCESS;
            }
            if let Some(v) = e.downcast_ref::<commands::Verdict>() {
                eprintln!("{v}");
                return ExitCode::from(v.code);
            }
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// Run one subcommand.
fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Helix(a) => commands::helix::run(a),
        Command::Boundary(a) => commands::boundary::run(a),
        Command::Bifurcation(a) => commands::bifurcation::run(a),
        Command::Compare(a) => commands::compare::run(a),
        Command::Detect(a) => commands::detect::run(a),
        Command::Simulate(a) => commands::simulate::run(a),
        Command::Rod(a) => commands::rod::run(a),
        Command::Disturbances(a) => commands::disturbances::run(a),
        Command::Fk(a) => commands::fk::run(a),
        Command::Ik(a) => commands::ik::run(a),
        Command::Robot(a) => commands::robot::run(a),
        Command::Rig(a) => commands::rig::run(a),
        Command::Plan(a) => commands::plan::run(a),
        Command::Campaign(a) => commands::campaign::run(a),
        Command::Check(a) => commands::check::run(a),
        Command::Reach(a) => commands::reach::run(a),
        Command::Layout(a) => commands::layout::run(a),
        Command::Merge(a) => commands::merge::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Render(a) => commands::render::run(a),
        Command::Demo(a) => commands::demo::run(a),
    }
}
