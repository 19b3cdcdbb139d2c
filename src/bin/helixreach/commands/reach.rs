//! `helixreach reach` (not implemented yet).

/// Arguments of `helixreach reach`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach reach`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach reach` is not implemented yet")
}
