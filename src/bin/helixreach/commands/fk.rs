//! `helixreach fk` (not implemented yet).

/// Arguments of `helixreach fk`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach fk`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach fk` is not implemented yet")
}
