//! `helixreach helix` (not implemented yet).

/// Arguments of `helixreach helix`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach helix`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach helix` is not implemented yet")
}
