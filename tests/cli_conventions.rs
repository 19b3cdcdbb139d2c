//! The conventions every subcommand shares: the global `--threads N` (same bytes for any count,
//! bounded) and `--quiet` (nothing on stderr but errors, warnings and verdicts).

use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn ok(dir: &Path, args: &[&str]) -> Output {
    let out = run(dir, args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn same_bytes_for_one_and_two_threads() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The flag is global: before or after the subcommand's name.
    for (cmd, n) in [
        (&["reach", "--fibonacci", "6", "--quarter"][..], "6"),
        (&["boundary", "--fibonacci", "40"][..], "40"),
        (
            &["bifurcation", "--fibonacci", "3", "--n-edges", "20"][..],
            "3",
        ),
    ] {
        let one = format!("{}1.csv", cmd[0]);
        let two = format!("{}2.csv", cmd[0]);
        let mut a: Vec<&str> = cmd.to_vec();
        a.extend(["--threads", "1", "--out", &one]);
        ok(d, &a);
        let mut b: Vec<&str> = vec!["--threads", "2"];
        b.extend(cmd);
        b.extend(["--out", &two]);
        ok(d, &b);
        let x = std::fs::read(d.join(&one)).unwrap();
        let y = std::fs::read(d.join(&two)).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&x).lines().count(),
            n.parse::<usize>().unwrap() + 1
        );
        assert!(x == y, "{}: --threads 1 and 2 differ", cmd[0]);
    }
}

#[test]
fn threads_out_of_range_are_refused_on_every_command() {
    let dir = tempfile::tempdir().unwrap();
    for n in ["0", "1025", "5000"] {
        for cmd in [
            &["boundary", "--fibonacci", "3", "--out", "x.csv"][..],
            &["helix", "--kappa", "1", "--tau", "0", "--omega", "0"][..],
        ] {
            let mut a = cmd.to_vec();
            a.extend(["--threads", n]);
            let out = run(dir.path(), &a);
            assert_eq!(out.status.code(), Some(2), "{a:?}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(err.contains("--threads") && err.contains("1024"), "{err}");
        }
    }
    assert!(!dir.path().join("x.csv").exists());
}

#[test]
fn quiet_prints_nothing_on_stderr() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Without --quiet the sweeps say what they wrote ...
    let loud = ok(d, &["boundary", "--fibonacci", "5", "--out", "loud.csv"]);
    assert!(String::from_utf8_lossy(&loud.stderr).contains("loud.csv"));
    // ... with it, nothing (the outputs are the same).
    for cmd in [
        &["boundary", "--fibonacci", "5", "--out", "b.csv"][..],
        &["reach", "--fibonacci", "3", "--quarter", "--out", "r.csv"][..],
        &[
            "bifurcation",
            "--fibonacci",
            "2",
            "--n-edges",
            "20",
            "--out",
            "f.csv",
        ][..],
        &[
            "boundary",
            "--fibonacci",
            "5",
            "--shard",
            "0/2",
            "--out",
            "s0.csv",
        ][..],
        &[
            "boundary",
            "--fibonacci",
            "5",
            "--shard",
            "1/2",
            "--out",
            "s1.csv",
        ][..],
        &["merge", "--out", "m.csv", "s0.csv", "s1.csv"][..],
        &["ik", "--robot", "sawyer", "--pose", "0.6,0.1,0.3,0,1,0,0"][..],
        &[
            "rig",
            "init",
            "--robot",
            "panda",
            "--tip",
            "fer_link8",
            "--out",
            "rig.toml",
        ][..],
    ] {
        let mut a = vec!["--quiet"];
        a.extend(cmd);
        let out = ok(d, &a);
        assert!(
            out.stderr.is_empty(),
            "{a:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    assert_eq!(
        std::fs::read(d.join("b.csv")).unwrap(),
        std::fs::read(d.join("loud.csv")).unwrap()
    );
}

#[test]
fn quiet_keeps_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(
        d,
        &["--quiet", "boundary", "--fibonacci", "3", "--out", "b.csv"],
    );
    // The second run refuses to overwrite: the error is printed although --quiet.
    let out = run(
        d,
        &["--quiet", "boundary", "--fibonacci", "3", "--out", "b.csv"],
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("error:") && err.contains("b.csv"), "{err}");
    // An unreadable input, the same.
    let out = run(
        d,
        &[
            "check",
            "--quiet",
            "--rig",
            "sawyer-seed",
            "--trajectory",
            "nothing.csv",
        ],
    );
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("nothing.csv"), "{err}");
}

#[test]
fn a_file_of_joints_is_trajectory_and_joint_values_are_joints() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("j.txt"),
        "0 -1 0 1.5 0 -0.5 0\n0 -1 0 1.5 0 -0.5 0.01\n",
    )
    .unwrap();
    let new = ok(d, &["check", "--trajectory", "j.txt", "--report-only"]);
    // The earlier spelling still reads the file (hidden from --help), with the same report.
    let old = ok(d, &["check", "--joints", "j.txt", "--report-only"]);
    assert_eq!(new.stdout, old.stdout);
    let v: serde_json::Value = serde_json::from_slice(&new.stdout).unwrap();
    assert_eq!(v["rows"], 2, "{v}");
    let help = String::from_utf8(ok(d, &["check", "--help"]).stdout).unwrap();
    assert!(
        help.contains("--trajectory <FILE>") && !help.contains("--joints"),
        "{help}"
    );
    let help = String::from_utf8(ok(d, &["render", "--help"]).stdout).unwrap();
    assert!(help.contains("--trajectory"), "{help}");
    let help = String::from_utf8(ok(d, &["fk", "--help"]).stdout).unwrap();
    assert!(help.contains("--joints"), "{help}");
}

#[test]
fn version_names_the_commit() {
    let dir = tempfile::tempdir().unwrap();
    let out = ok(dir.path(), &["--version"]);
    let v = String::from_utf8(out.stdout).unwrap();
    // The reference: git itself, on the checkout the test was built from.
    let git = Command::new("git")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8(o.stdout).unwrap().trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    assert_eq!(
        v,
        format!("helixreach {} (commit {git})\n", env!("CARGO_PKG_VERSION"))
    );
}

/// One rule for `--margin` on every command that takes it: 0 ≤ M ≤ 1, the same message.
#[test]
fn one_margin_rule_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cmds: [&[&str]; 4] = [
        &["reach", "--fibonacci", "2", "--out", "r.csv"],
        &[
            "layout",
            "--fibonacci",
            "2",
            "--spacing",
            "0.2",
            "--out",
            "lay",
        ],
        &["plan", "--direction", "1,0,0", "--out", "p.csv"],
        &["campaign", "--fibonacci", "2", "--out", "camp"],
    ];
    for cmd in cmds {
        for bad in ["-0.1", "1.5", "NaN", "x"] {
            let mut a = vec!["--quiet"];
            a.extend(cmd);
            a.extend(["--margin", bad]);
            let o = run(d, &a);
            assert_eq!(o.status.code(), Some(2), "{a:?}");
            let e = String::from_utf8_lossy(&o.stderr);
            assert!(e.contains("--margin"), "{a:?}: {e}");
            if bad != "x" {
                assert!(e.contains("must lie in [0, 1]"), "{a:?}: {e}");
            }
        }
    }
    // 0 (drive exactly to the boundary) is a margin for reach and layout alike, and recorded.
    for cmd in &cmds[..2] {
        let mut a = vec!["--quiet"];
        a.extend(*cmd);
        a.extend(["--margin", "0"]);
        ok(d, &a);
    }
    for meta in ["r.csv.meta.json", "lay/rays.csv.meta.json"] {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.join(meta)).unwrap()).unwrap();
        let m = &v["settings"]["margin"];
        assert_eq!(m, "0", "{meta}: {v}");
    }
    assert!(!d.join("p.csv").exists());
}

/// `--out -` writes to standard output; a reader that stops early (`| head`) is not an error.
#[test]
fn out_dash_is_stdout_and_a_closed_pipe_is_not_an_error() {
    use std::process::Stdio;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cmds: [&[&str]; 5] = [
        &["boundary", "--fibonacci", "3"],
        &["reach", "--fibonacci", "2"],
        &["bifurcation", "--fibonacci", "2", "--n-edges", "20"],
        &[
            "simulate",
            "--direction",
            "1,0,0",
            "--n-edges",
            "10",
            "--s-max",
            "1",
        ],
        &["plan", "--direction", "0.6,0.8,0", "--allow-partial"],
    ];
    for cmd in cmds {
        let mut a = vec!["--quiet"];
        a.extend(cmd);
        a.extend(["--out", "-"]);
        let o = ok(d, &a);
        let text = String::from_utf8(o.stdout).unwrap();
        let first = text.lines().next().unwrap_or("");
        assert!(
            first.contains(','),
            "{a:?}: a CSV header first, got {first:?}"
        );
        // The same, its standard output closed before it writes.
        let mut child = Command::new(BIN)
            .current_dir(d)
            .args(&a)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        assert!(
            o.status.success(),
            "{a:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(
            o.stderr.is_empty(),
            "{a:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    // Nothing was written into the directory.
    assert_eq!(std::fs::read_dir(d).unwrap().count(), 0);
    // A JSON summary on a closed standard output (serde_json's own error) is no error either.
    let mut child = Command::new(BIN)
        .current_dir(d)
        .args([
            "--quiet",
            "simulate",
            "--direction",
            "1,0,0",
            "--n-edges",
            "10",
            "--s-max",
            "1",
            "--out",
            "s.csv",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(d.join("s.csv").exists());
}

/// `--azimuth` is radians on every command; simulate's earlier `--azimuth-deg` still reads
/// (hidden) and means the same helix.
#[test]
fn azimuth_is_radians_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sim = |name: &str, extra: &[&str]| -> Vec<f64> {
        let mut a = vec![
            "--quiet",
            "simulate",
            "--direction",
            "1,0,0",
            "--n-edges",
            "10",
            "--s-max",
            "1",
            "--rig",
            "sawyer-seed",
            "--out",
            "s.csv",
            "--force",
            "--centerline",
            name,
        ];
        a.extend(extra);
        ok(d, &a);
        let text = std::fs::read_to_string(d.join(name)).unwrap();
        text.lines()
            .skip(1)
            .flat_map(|l| {
                l.split(',')
                    .filter_map(|x| x.parse::<f64>().ok())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    let rad = sim("rad.csv", &["--azimuth", "1.5707963267948966"]);
    let deg = sim("deg.csv", &["--azimuth-deg", "90"]);
    let zero = sim("zero.csv", &[]);
    assert_eq!(rad.len(), deg.len());
    let diff = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    assert!(diff(&rad, &deg) < 1e-12, "{}", diff(&rad, &deg));
    assert!(diff(&rad, &zero) > 1e-3, "the azimuth turns the helix");
    for cmd in ["simulate", "plan", "check", "render", "detect"] {
        let help = String::from_utf8(ok(d, &[cmd, "--help"]).stdout).unwrap();
        assert!(
            help.contains("--azimuth <") && help.contains("rad"),
            "{cmd}"
        );
        assert!(!help.contains("--azimuth-deg"), "{cmd}");
    }
}

/// A `--boundary` table computed on other directions is refused before any work by every
/// command that reads one, naming the file.
#[test]
fn a_boundary_on_other_directions_is_refused_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(
        d,
        &["--quiet", "boundary", "--fibonacci", "7", "--out", "b7.csv"],
    );
    for cmd in [
        &["reach", "--fibonacci", "4", "--out", "r.csv"][..],
        &[
            "layout",
            "--fibonacci",
            "4",
            "--spacing",
            "0.2",
            "--out",
            "lay",
        ][..],
    ] {
        let mut a = vec!["--quiet"];
        a.extend(cmd);
        a.extend(["--boundary", "b7.csv"]);
        let o = run(d, &a);
        assert_eq!(o.status.code(), Some(2), "{a:?}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(
            e.contains("b7.csv: lists 0 of the 4 directions to run (4 missing"),
            "{a:?}: {e}"
        );
    }
    assert!(!d.join("r.csv").exists() && !d.join("lay").join("rays.csv").exists());
    // The table on the same set is used.
    ok(
        d,
        &["--quiet", "boundary", "--fibonacci", "4", "--out", "b4.csv"],
    );
    ok(
        d,
        &[
            "--quiet",
            "reach",
            "--fibonacci",
            "4",
            "--boundary",
            "b4.csv",
            "--out",
            "r.csv",
        ],
    );
    // A shard needs only its own block: a boundary made for the same shard fits.
    let b41 = [
        "--quiet",
        "boundary",
        "--fibonacci",
        "4",
        "--shard",
        "1/2",
        "--out",
        "b41.csv",
    ];
    ok(d, &b41);
    let shard = [
        "--quiet",
        "reach",
        "--fibonacci",
        "4",
        "--shard",
        "1/2",
        "--out",
        "r41.csv",
    ];
    let mut a = shard.to_vec();
    a.extend(["--boundary", "b7.csv"]);
    assert_eq!(run(d, &a).status.code(), Some(2));
    let mut a = shard.to_vec();
    a.extend(["--boundary", "b41.csv"]);
    ok(d, &a);
}

/// `reach` states its class counts, and rays left `undecided` by the search's node bound are a
/// warning (printed under `--quiet` too) naming the setting and its value; the counts are those
/// of the CSV it wrote.
#[test]
fn reach_states_its_classes_and_warns_of_undecided_rays() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rigs = Path::new(env!("CARGO_MANIFEST_DIR")).join("robots");
    let text = std::fs::read_to_string(rigs.join("sawyer-seed.toml")).unwrap();
    assert!(text.contains("max_search_nodes = 50000"));
    let small = text.replacen("max_search_nodes = 50000", "max_search_nodes = 2000", 1);
    std::fs::write(d.join("small.toml"), small).unwrap();
    for quiet in [false, true] {
        let mut args = vec![
            "reach",
            "--rig",
            "small.toml",
            "--fibonacci",
            "12",
            "--quarter",
            "--roll",
            "motor",
            "--force",
            "--out",
            "r.csv",
        ];
        if quiet {
            args.insert(0, "--quiet");
        }
        let out = ok(d, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        let csv = std::fs::read_to_string(d.join("r.csv")).unwrap();
        let mut lines = csv.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let ic = header.iter().position(|h| *h == "class").unwrap();
        let count = |c: &str| {
            csv.lines()
                .skip(1)
                .filter(|l| l.split(',').nth(ic) == Some(c))
                .count()
        };
        let undecided = count("undecided");
        assert!(undecided > 0, "{csv}");
        let rays = if undecided == 1 { "ray" } else { "rays" };
        let warning = format!(
            "warning: reach: {undecided} {rays} undecided: their search hit \
             planner.max_search_nodes = 2000"
        );
        assert!(err.contains(&warning), "{err}");
        let counts = format!(
            "reach: {} testable, {} partial, {} blocked, {undecided} undecided",
            count("testable"),
            count("partial"),
            count("blocked")
        );
        assert_eq!(err.contains(&counts), !quiet, "{err}");
    }
}
