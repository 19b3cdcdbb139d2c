//! Helpers shared by the integration tests: the seed experiment's real data, kept as a subset
//! in the repository (`tests/data/seed/`, see its `SOURCE.md`) and unpacked into the build's
//! test folder on first use ([`seed`]), and the dense reference of a ray's reachability
//! ([`dense_reference`]). Nothing is read from outside the repository.

pub mod dense_reference;
pub mod png;
pub mod robots;
pub mod seed;

use std::path::PathBuf;

/// The seed-data folder (holding `trajectories.csv`, `trajectories/`, `measured_boundary.csv`,
/// `bifurcation_examples.csv`), unpacked from `tests/data/seed/`.
#[allow(dead_code)]
pub fn seed_dir() -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    DIR.get_or_init(|| seed::unpack(&PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("seed-data")))
        .clone()
}

/// One file of the seed data; panics when it is missing.
#[allow(dead_code)]
pub fn seed_data(file: &str) -> PathBuf {
    let p = seed_dir().join(file);
    assert!(p.exists(), "seed data file {} is missing", p.display());
    p
}
