//! `helixreach boundary` (not implemented yet).

/// Arguments of `helixreach boundary`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach boundary`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach boundary` is not implemented yet")
}
