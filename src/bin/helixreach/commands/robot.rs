//! `helixreach robot` (not implemented yet).

/// Arguments of `helixreach robot`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach robot`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach robot` is not implemented yet")
}
