//! `helixreach ik` (not implemented yet).

/// Arguments of `helixreach ik`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach ik`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach ik` is not implemented yet")
}
