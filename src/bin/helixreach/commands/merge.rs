//! `helixreach merge` (not implemented yet).

/// Arguments of `helixreach merge`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach merge`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach merge` is not implemented yet")
}
