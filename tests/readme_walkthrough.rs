//! The README's "Test your own robot" walk-through runs as written, on a real URDF with meshes:
//! the vendored UR5 (`tests/data/robots/`) stands for `my_arm.urdf`, its unpacked package folder
//! for `~/ws/src`, a 6-direction set for the 500 (seconds instead of minutes), and `moveit.csv`
//! is a two-row joint-name trajectory of the UR5. Every line must exit 0 and write its output.

mod common;

use common::robots::{self, ARMS};
use std::process::Command;

/// The shell lines of the first `sh` block after `heading` in the README.
fn block(readme: &str, heading: &str) -> Vec<String> {
    let at = readme
        .find(heading)
        .unwrap_or_else(|| panic!("README has no {heading:?}"));
    let rest = &readme[at..];
    let start = rest.find("```sh\n").expect("an sh block") + "```sh\n".len();
    let end = rest[start..].find("```").unwrap();
    rest[start..start + end]
        .lines()
        .map(|l| l.split(" # ").next().unwrap().trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn test_your_own_robot_walkthrough_runs() {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let lines = block(&readme, "## Test your own robot");
    assert!(lines.len() >= 4, "{lines:?}");
    let ur5 = ARMS.iter().find(|a| a.name == "ur5").unwrap();
    assert_eq!(ur5.tip, "tool0", "the README's tip");
    let urdf = robots::urdf(ur5);
    let pkg = robots::package_dir();
    let dir = tempfile::tempdir().unwrap();
    let joints = "shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,wrist_2_joint,wrist_3_joint";
    std::fs::write(
        dir.path().join("moveit.csv"),
        format!("time,{joints}\n0,0,-1.2,1.0,-1.2,-1.57,0\n1,0.1,-1.2,1.0,-1.2,-1.57,0\n"),
    )
    .unwrap();
    let bin_dir = std::path::Path::new(env!("CARGO_BIN_EXE_helixreach"))
        .parent()
        .unwrap()
        .to_path_buf();
    let path = format!(
        "{}:{}",
        bin_dir.display(),
        std::env::var("PATH").unwrap_or_default()
    );
    for line in &lines {
        assert!(line.starts_with("helixreach "), "{line}");
        let cmd = line
            .replace("my_arm.urdf", urdf.to_str().unwrap())
            .replace("~/ws/src", pkg.to_str().unwrap())
            .replace("--fibonacci 500", "--fibonacci 6");
        let o = Command::new("sh")
            .arg("-c")
            .arg(&cmd)
            .current_dir(dir.path())
            .env("PATH", &path)
            .env("RAYON_NUM_THREADS", "2")
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{line}\n{}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    for f in ["my_rig.toml", "my_reach.csv", "plan.csv", "rows.csv"] {
        assert!(dir.path().join(f).is_file(), "{f} not written");
    }
    let rows = std::fs::read_to_string(dir.path().join("rows.csv")).unwrap();
    let header = rows.lines().next().unwrap();
    assert!(
        header.contains("self_collision") && header.contains("self_pairs"),
        "{header}"
    );
}
