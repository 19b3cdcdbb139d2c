//! `helixreach merge`: join the shard outputs of `helixreach boundary` or `helixreach reach`
//! (`--shard I/N` writes the contiguous block I of the directions) into one CSV in direction
//! order. Give the files in shard order (0/N, 1/N, …). Every file must have the same header; a
//! key (the first `--key-columns` fields, the direction) present twice is an error. The output is
//! written atomically.

use anyhow::{bail, Context};
use std::collections::HashSet;
use std::path::PathBuf;

/// Arguments of `helixreach merge`.
#[derive(Debug, clap::Args)]
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
}

/// Run `helixreach merge`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let mut header: Option<csv::StringRecord> = None;
    let mut seen = HashSet::new();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut n = 0usize;
    for p in &a.inputs {
        let mut rdr = csv::Reader::from_path(p).with_context(|| format!("{}", p.display()))?;
        let h = rdr
            .headers()
            .with_context(|| format!("{}: reading the header", p.display()))?
            .clone();
        if a.key_columns == 0 || a.key_columns > h.len() {
            bail!(
                "{}: --key-columns {} must be in 1..={}",
                p.display(),
                a.key_columns,
                h.len()
            );
        }
        match &header {
            None => {
                w.write_record(&h)?;
                header = Some(h);
            }
            Some(h0) if *h0 != h => bail!(
                "{}: header `{}` differs from `{}` of {}",
                p.display(),
                h.iter().collect::<Vec<_>>().join(","),
                h0.iter().collect::<Vec<_>>().join(","),
                a.inputs[0].display()
            ),
            Some(_) => {}
        }
        for (k, rec) in rdr.records().enumerate() {
            let rec = rec.with_context(|| format!("{}:{}", p.display(), k + 2))?;
            let key: Vec<String> = rec.iter().take(a.key_columns).map(str::to_string).collect();
            if !seen.insert(key.clone()) {
                bail!(
                    "{}:{}: key `{}` already present in an earlier input (overlapping shards?)",
                    p.display(),
                    k + 2,
                    key.join(",")
                );
            }
            w.write_record(&rec)?;
            n += 1;
        }
    }
    let bytes = w.into_inner().context("serializing the merged CSV")?;
    helixreach::io::write_atomic(&a.out, &bytes)?;
    eprintln!(
        "merge: {n} rows from {} files -> {}",
        a.inputs.len(),
        a.out.display()
    );
    Ok(())
}
