//! One module per subcommand, and the options every subcommand takes ([`Global`]).

/// `eprintln!` unless `--quiet`: progress and status lines (what was written, how long it took).
/// Errors, warnings and verdicts are printed with `eprintln!` whatever `--quiet` says.
macro_rules! status {
    ($($t:tt)*) => {
        if !$crate::commands::global().quiet {
            eprintln!($($t)*);
        }
    };
}

/// The `Examples:` section that ends a subcommand's `--help` (clap `after_help`), one command
/// line per argument. A line starting `$ ` runs in seconds in an empty directory, after the
/// `$ ` lines before it (`tests/help_examples.rs` runs every one with `sh`); a line starting
/// `> ` takes longer or needs files of your own, and is shown only.
macro_rules! examples {
    ($($line:literal),+ $(,)?) => {
        concat!(
            "Examples (`$`: runs in seconds, in order, in an empty directory; `>`: longer, or needs your files):\n",
            $("  ", $line, "\n"),+
        )
    };
}

pub mod args;
pub mod bifurcation;
pub mod boundary;
pub mod campaign;
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
pub mod rig;
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

/// Options of every subcommand, defined once (`global = true`: accepted before or after the
/// subcommand's name).
#[derive(Debug, Clone, Copy, Default, clap::Args)]
pub struct Global {
    /// Worker threads of the parallel stages (1..=1024; default: one per core). Every output is
    /// identical for any thread count.
    #[arg(long, global = true, value_name = "N", value_parser = parse_threads)]
    pub threads: Option<usize>,
    /// No progress or status lines on stderr (errors, warnings and verdicts are still printed).
    #[arg(long, global = true)]
    pub quiet: bool,
}

/// `--threads N`, checked against [`helixreach::limits::MAX_THREADS`].
fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s
        .parse()
        .map_err(|e| format!("--threads `{s}`: not a count ({e})"))?;
    helixreach::limits::check_range("--threads", n, 1, helixreach::limits::MAX_THREADS)
        .map_err(|e| e.to_string())
}

static GLOBAL: std::sync::OnceLock<Global> = std::sync::OnceLock::new();

/// Record the global options of this run (once, before the subcommand runs).
pub fn set_global(g: Global) {
    let _ = GLOBAL.set(g);
}

/// The global options of this run (the defaults before [`set_global`]).
pub fn global() -> Global {
    GLOBAL.get().copied().unwrap_or_default()
}

/// Run `go` on a pool of `threads` worker threads (default: rayon's global pool, one per core):
/// every parallel map of the library run from `go` — the sweep driver's workers, the study's
/// stages, the layout's evaluation, the render — uses that pool.
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    go: impl FnOnce() -> anyhow::Result<T> + Send,
) -> anyhow::Result<T> {
    let par = helixreach::par::Par::from_option(threads)?;
    par.install(go)
        .map_err(|e| anyhow::anyhow!("--threads: {e}"))?
}

/// Gravity for a planning command (`reach`, `plan`, `layout`, `campaign`) on `rig` (named
/// `rig_name` in messages): [`helixreach::rod::gravity::planning_gravity`] with the smallest
/// margin planned to (`margin`, else the rig's), the boundary table's gravity if one is given,
/// and the azimuths planned at. Prints the verdict on stderr (a warning, whatever `--quiet`,
/// when gravity may move s* past the margin); an error when the gravity-free boundary would
/// not do.
pub fn gravity_gate(
    rig: &helixreach::planning::rig::Rig,
    rig_name: &str,
    margin: Option<f64>,
    table: Option<&helixreach::sweep::reach::BoundaryTable>,
    azimuths: &[f64],
) -> anyhow::Result<()> {
    let p = &rig.planner;
    let m = margin.unwrap_or_else(|| p.margin.min(p.margin_supercritical.unwrap_or(p.margin)));
    let g = helixreach::rod::gravity::planning_gravity(
        &rig.rod,
        rig_name,
        m,
        &table.map(|t| t.gravity()).unwrap_or_default(),
        azimuths,
    )?;
    if g.beyond_margin() {
        eprintln!("warning: gravity: {g}");
    } else {
        status!("gravity: {g}");
    }
    Ok(())
}
