//! `helixreach simulate` (not implemented yet).

/// Arguments of `helixreach simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach simulate`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach simulate` is not implemented yet")
}
