//! One pose format in and out: `fk` prints `x,y,z,qw,qx,qy,qz` (or the 4×4 matrix with
//! `--matrix`) and `ik --pose` reads exactly that (`--matrix` too). Checked against the rotation
//! of the quaternion by its textbook formula and against FK of every IK solution.

use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");
const Q: &str = "0.3,-1.1,0.2,1.4,-0.3,-0.6,0.5";

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn ok(args: &[&str]) -> String {
    let o = run(args);
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).unwrap()
}

fn nums(s: &str) -> Vec<f64> {
    s.split([',', '\n'])
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().unwrap())
        .collect()
}

#[test]
fn fk_quaternion_and_matrix_are_the_same_pose() {
    let quat = ok(&["fk", "--robot", "sawyer", "--joints", Q]);
    assert_eq!(quat.lines().count(), 1);
    let p = nums(&quat);
    assert_eq!(p.len(), 7);
    let (w, x, y, z) = (p[3], p[4], p[5], p[6]);
    assert!(w >= 0.0);
    assert!((w * w + x * x + y * y + z * z - 1.0).abs() < 1e-14);
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mat = ok(&["fk", "--robot", "sawyer", "--joints", Q, "--matrix"]);
    let rows: Vec<Vec<f64>> = mat.lines().map(nums).collect();
    assert_eq!(rows.len(), 4);
    assert_eq!(rows[3], [0.0, 0.0, 0.0, 1.0]);
    for i in 0..3 {
        assert_eq!(rows[i][3], p[i], "translation {i}");
        for j in 0..3 {
            assert!((rows[i][j] - r[i][j]).abs() < 1e-14, "R[{i}][{j}]");
        }
    }
}

/// FK of each solution of `ik` is the pose it was asked for.
fn solutions_reach(csv: &str, want: &[f64]) -> usize {
    let mut n = 0;
    for row in csv.lines().skip(1) {
        let v = nums(row);
        let q: Vec<String> = v[..7].iter().map(|x| x.to_string()).collect();
        let got = nums(&ok(&["fk", "--robot", "sawyer", "--joints", &q.join(",")]));
        for i in 0..3 {
            assert!(
                (got[i] - want[i]).abs() < 1e-8,
                "{row}: position {got:?} vs {want:?}"
            );
        }
        // q and −q are the same rotation; fk prints qw ≥ 0.
        let dot: f64 = (3..7).map(|k| got[k] * want[k]).sum();
        assert!(
            dot.abs() > 1.0 - 1e-12,
            "{row}: rotation {got:?} vs {want:?}"
        );
        n += 1;
    }
    n
}

#[test]
fn ik_reads_what_fk_prints() {
    let quat = ok(&["fk", "--robot", "sawyer", "--joints", Q]);
    let want = nums(&quat);
    let small = ["--samples", "2", "--restarts", "10", "--robot", "sawyer"];
    let mut a = vec!["--quiet", "ik", "--pose", quat.trim()];
    a.extend(small);
    assert!(solutions_reach(&ok(&a), &want) > 0);
    let mat = ok(&["fk", "--robot", "sawyer", "--joints", Q, "--matrix"]);
    let mut a = vec!["--quiet", "ik", "--matrix", "--pose", &mat];
    a.extend(small);
    assert!(solutions_reach(&ok(&a), &want) > 0);
}

#[test]
fn bad_poses_are_refused_naming_pose() {
    for (args, want) in [
        (vec!["--pose", "0.5,0,0.3,2,0,0,0"], "unit quaternion"),
        (vec!["--pose", "0.5,0,0.3,1,0,0"], "expected 7"),
        (
            vec!["--matrix", "--pose", "1 0 0 0 0 1 0 0 0 0 -1 0 0 0 0 1"],
            "reflection",
        ),
        (
            vec!["--matrix", "--pose", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0"],
            "expected 16",
        ),
        (
            vec!["--matrix", "--pose", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1"],
            "0 0 0 1",
        ),
        (
            vec!["--matrix", "--pose", "1 0.1 0 0 0 1 0 0 0 0 1 0 0 0 0 1"],
            "orthonormal",
        ),
    ] {
        let mut a = vec!["ik", "--robot", "sawyer"];
        a.extend(&args);
        let o = run(&a);
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains("--pose") && e.contains(want), "{a:?}: {e}");
    }
}
