//! The seed experiment's data as the tests and examples read it: the subset kept in the
//! repository under `tests/data/seed/` (see its `SOURCE.md`), the trajectory files stored
//! gzip-compressed (`trajectories/*.txt.gz`) and unpacked on first use into a folder of the build
//! (each file written to a temp name and renamed, so concurrent test processes agree). Nothing is
//! read from outside the repository.

use std::io::Read;
use std::path::{Path, PathBuf};

/// The subset kept in the repository.
pub fn packed_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/seed")
}

/// Unpack the seed subset into `dest` (once: files already there are kept) and return `dest`,
/// which then holds `trajectories.csv`, `trajectories/*.txt`, `measured_boundary.csv` and
/// `bifurcation_examples.csv` as the seed ships them. Panics naming the file on any error: a
/// test without its data must fail.
pub fn unpack(dest: &Path) -> PathBuf {
    let src = packed_dir();
    let traj = dest.join("trajectories");
    std::fs::create_dir_all(&traj).unwrap_or_else(|e| panic!("create {}: {e}", traj.display()));
    let mut files: Vec<(PathBuf, PathBuf)> = [
        "trajectories.csv",
        "measured_boundary.csv",
        "bifurcation_examples.csv",
    ]
    .iter()
    .map(|n| (src.join(n), dest.join(n)))
    .collect();
    let packed = src.join("trajectories");
    for e in std::fs::read_dir(&packed).unwrap_or_else(|e| panic!("read {}: {e}", packed.display()))
    {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if let Some(txt) = name.strip_suffix(".gz") {
            files.push((p.clone(), traj.join(txt)));
        }
    }
    for (from, to) in files {
        if to.is_file() {
            continue;
        }
        let raw = std::fs::read(&from).unwrap_or_else(|e| panic!("read {}: {e}", from.display()));
        let bytes = if from.extension().is_some_and(|x| x == "gz") {
            let mut out = Vec::new();
            flate2::read::GzDecoder::new(raw.as_slice())
                .read_to_end(&mut out)
                .unwrap_or_else(|e| panic!("gunzip {}: {e}", from.display()));
            out
        } else {
            raw
        };
        let tmp = to.with_extension(format!("{}.tmp", std::process::id()));
        std::fs::write(&tmp, &bytes).unwrap_or_else(|e| panic!("write {}: {e}", tmp.display()));
        std::fs::rename(&tmp, &to).unwrap_or_else(|e| panic!("rename to {}: {e}", to.display()));
    }
    dest.to_path_buf()
}
