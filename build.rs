//! Build script: the git commit the binary is built from, for `helixreach --version`.
//!
//! Sets `HELIXREACH_COMMIT` to `git rev-parse --short HEAD`, or `unknown` when the source is not
//! a git checkout or git is not installed (never fails the build). Reruns when `HEAD` or the
//! branch it points to moves (only paths that exist are watched: a missing one would rerun the
//! script on every build).

use std::path::{Path, PathBuf};
use std::process::Command;

fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .current_dir(dir)
        .args(args)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    let dir = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_else(|| ".".into()));
    let commit = git(&dir, &["rev-parse", "--short", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=HELIXREACH_COMMIT={commit}");
    let abs = |p: String| {
        let p = PathBuf::from(p);
        if p.is_absolute() {
            p
        } else {
            dir.join(p)
        }
    };
    let mut watch = Vec::new();
    if let Some(git_dir) = git(&dir, &["rev-parse", "--git-dir"]).map(abs) {
        watch.push(git_dir.join("HEAD"));
    }
    if let (Some(common), Some(branch)) = (
        git(&dir, &["rev-parse", "--git-common-dir"]).map(abs),
        git(&dir, &["symbolic-ref", "-q", "HEAD"]),
    ) {
        watch.push(common.join(&branch));
        watch.push(common.join("packed-refs"));
    }
    for p in watch.iter().filter(|p| p.exists()) {
        println!("cargo:rerun-if-changed={}", p.display());
    }
}
