//! `helixreach merge`: join the shard outputs of a sweep (`boundary`, `reach`, … run with
//! `--shard I/N`) into one CSV in item order. Give the files in shard order (0/N, 1/N, …).
//! Refused (see `helixreach::sweep::merge`): an input without its settings record
//! (`F.meta.json`) or whose bytes do not match it, a row that breaks its column's rule, inputs made
//! with different settings, a missing, repeated or misplaced shard, an unfinished shard, a key
//! present twice. The output is locked and written atomically; an existing output is replaced
//! only with `--force`.

use std::path::PathBuf;

/// Arguments of `helixreach merge`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach boundary --fibonacci 10 --shard 0/2 --out part0.csv",
    "$ helixreach boundary --fibonacci 10 --shard 1/2 --out part1.csv",
    "$ helixreach merge --out boundary.csv part0.csv part1.csv"
))]
pub struct Args {
    /// Shard outputs, in shard order.
    #[arg(required = true, num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// Number of leading key columns (the direction: dir_kappa,dir_tau,dir_omega).
    #[arg(long, default_value_t = 3)]
    pub key_columns: usize,
    /// Output CSV.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace an existing output.
    #[arg(long)]
    pub force: bool,
}

/// Run `helixreach merge`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let s = helixreach::sweep::merge::merge(&a.inputs, a.key_columns, &a.out, a.force)?;
    status!(
        "merge: {} rows from {} shards -> {}",
        s.rows,
        s.shards,
        a.out.display()
    );
    Ok(())
}
