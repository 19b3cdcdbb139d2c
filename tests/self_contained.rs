//! The tests, benches and examples read nothing outside the repository: a fresh clone, with no
//! folder beside it, passes its own tests. Every source file under `tests/`, `benches/` and
//! `examples/` is scanned for a path that leaves the repository (a parent-directory hop to a
//! sibling folder, or an absolute path of the development machine).

use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            if p.file_name().is_some_and(|n| n != "data") {
                sources(&p, out);
            }
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_test_bench_or_example_reads_outside_the_repository() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for d in ["tests", "benches", "examples"] {
        sources(&root.join(d), &mut files);
    }
    assert!(files.len() > 20, "found only {} sources", files.len());
    // Spelled in pieces so that this file does not match itself.
    let forbidden = [
        format!("{}/{}", "..", "shared"),
        format!("{}{}", "shared/", "seed-data"),
        format!("{}{}", "/work", "/"),
        format!("{}{}", "/home", "/"),
    ];
    let mut hits = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (n, line) in text.lines().enumerate() {
            for bad in &forbidden {
                if line.contains(bad.as_str()) {
                    hits.push(format!("{}:{}: {}", f.display(), n + 1, line.trim()));
                }
            }
        }
    }
    assert!(
        hits.is_empty(),
        "reads outside the repository:\n{}",
        hits.join("\n")
    );
}
