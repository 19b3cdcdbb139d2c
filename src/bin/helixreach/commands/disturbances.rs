//! `helixreach disturbances` (not implemented yet).

/// Arguments of `helixreach disturbances`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach disturbances`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach disturbances` is not implemented yet")
}
