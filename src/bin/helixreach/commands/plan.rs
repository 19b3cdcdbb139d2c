//! `helixreach plan` (not implemented yet).

/// Arguments of `helixreach plan`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach plan`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach plan` is not implemented yet")
}
