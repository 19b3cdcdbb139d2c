//! The README's two commands share one compiled dependency tree.
//!
//! `cargo run --release --features interop -- demo` builds the normal dependencies;
//! `cargo test --release --features interop` also activates the dev-dependencies, whose features
//! unify into shared crates. A crate built with a different feature set is a different unit and
//! compiles twice (serde "alloc" from criterion made the test build recompile serde and
//! everything above it). Cargo.toml enables those features in the `cli` build; this test asks
//! `cargo tree` (offline, from Cargo.lock) for the feature set of every crate in both builds and
//! fails naming each crate whose features differ.

use std::collections::BTreeMap;
use std::process::Command;

/// `package version -> features` of one resolution.
fn features(edges: &str) -> BTreeMap<String, String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let out = Command::new(cargo)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "tree",
            "--offline",
            "--locked",
            "--features",
            "interop",
            "--prefix",
            "none",
            "-f",
            "{p}|{f}",
            "-e",
            edges,
        ])
        .output()
        .expect("run cargo tree");
    assert!(
        out.status.success(),
        "cargo tree -e {edges} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut map = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        // Feature nodes print as `name feature "f"`; package nodes as `name vX (path)|f1,f2`.
        let Some((pkg, feats)) = line.split_once('|') else {
            continue;
        };
        let mut words = pkg.split_whitespace();
        let (Some(name), Some(version)) = (words.next(), words.next()) else {
            continue;
        };
        let feats = feats.trim_end_matches(" (*)").trim().to_string();
        map.insert(format!("{name} {version}"), feats);
    }
    map
}

#[test]
fn demo_and_test_builds_resolve_identical_features() {
    let demo = features("features,normal,build");
    let test = features("features,normal,build,dev");
    assert!(
        demo.len() > 50,
        "cargo tree listed only {} crates",
        demo.len()
    );
    assert!(demo.keys().any(|k| k.starts_with("serde ")));
    let differ: Vec<String> = demo
        .iter()
        .filter(|(k, f)| test.get(*k) != Some(f))
        .map(|(k, f)| format!("{k}: demo [{f}] vs test [{:?}]", test.get(k)))
        .collect();
    assert!(
        differ.is_empty(),
        "crates compiled twice (features differ between the demo and the test build); enable \
         the test build's features in Cargo.toml's `cli` feature:\n{}",
        differ.join("\n")
    );
}
