//! Helpers shared by the integration tests: where the seed experiment's real data lives.
//!
//! The data is `../shared/seed-data/` beside the crate (CI keeps `shared/` beside the clone), or
//! the folder named by `HELIXREACH_SEED_DATA`. A missing folder fails the test loudly: the tests
//! that read it assert facts about the real rig and must not pass without it.

pub mod png;

use std::path::PathBuf;

/// The seed-data folder (holding `trajectories.csv`); panics naming where it looked.
#[allow(dead_code)]
pub fn seed_dir() -> PathBuf {
    let mut dirs = vec![PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/seed-data")];
    if let Ok(d) = std::env::var("HELIXREACH_SEED_DATA") {
        dirs.insert(0, PathBuf::from(d));
    }
    for d in &dirs {
        if d.join("trajectories.csv").is_file() {
            return d.clone();
        }
    }
    panic!("the seed data is missing: looked in {dirs:?} (set HELIXREACH_SEED_DATA to the seed-data folder)");
}

/// One file of the seed data; panics when it is missing.
#[allow(dead_code)]
pub fn seed_data(file: &str) -> PathBuf {
    let p = seed_dir().join(file);
    assert!(p.exists(), "seed data file {} is missing", p.display());
    p
}
