//! `helixreach plot` (not implemented yet).

/// Arguments of `helixreach plot`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach plot`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach plot` is not implemented yet")
}
