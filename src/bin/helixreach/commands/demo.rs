//! `helixreach demo` (not implemented yet).

/// Arguments of `helixreach demo`.
#[derive(Debug, clap::Args)]
pub struct Args {}

/// Run `helixreach demo`.
pub fn run(_args: Args) -> anyhow::Result<()> {
    anyhow::bail!("`helixreach demo` is not implemented yet")
}
