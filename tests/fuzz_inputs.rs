//! A fuzz-style corpus of malformed inputs: direction and boundary CSVs, rig TOML,
//! URDF, and extreme numbers (1e308, 1e400 → inf, -0, NaN, inf, huge integers). Every library
//! loader and a few CLI invocations must reject each one with an error — never a panic, never a
//! silent NaN — and the error must name the file, the field and the offending value.
//!
//! Each case lists the substrings its error must contain besides the file name (the field and
//! the value as written). Cases that are valid input (e.g. `-0`, 1e308 in a direction, which is
//! normalized) are checked to load to finite, normalized values instead.

use helixreach::directions::{read_csv, Direction};
use helixreach::planning::rig::Rig;
use helixreach::robot::RobotModel;
use helixreach::sweep::reach::BoundaryTable;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::process::Command;

/// What a case must produce.
enum Expect {
    /// An error containing the file name and these substrings.
    Err(&'static [&'static str]),
    /// Valid input.
    Ok,
}

struct Case {
    name: &'static str,
    text: String,
    expect: Expect,
}

fn case(name: &'static str, text: impl Into<String>, expect: Expect) -> Case {
    Case {
        name,
        text: text.into(),
        expect,
    }
}

/// Run `load` on every case (written to a file) and check the outcome; `valid` checks an `Ok`.
fn run_corpus<T>(
    cases: &[Case],
    ext: &str,
    load: impl Fn(&Path) -> helixreach::Result<T>,
    valid: impl Fn(&T) -> bool,
) {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for c in cases {
        let path = dir.path().join(format!("{}.{ext}", c.name));
        std::fs::write(&path, &c.text).unwrap();
        let r = catch_unwind(AssertUnwindSafe(|| load(&path)));
        let fname = path.file_name().unwrap().to_str().unwrap().to_string();
        match (r, &c.expect) {
            (Err(_), _) => failures.push(format!("{}: PANIC", c.name)),
            (Ok(Ok(v)), Expect::Ok) => {
                if !valid(&v) {
                    failures.push(format!("{}: loaded to invalid values", c.name));
                }
            }
            (Ok(Ok(_)), Expect::Err(_)) => failures.push(format!("{}: accepted", c.name)),
            (Ok(Err(e)), Expect::Ok) => failures.push(format!("{}: rejected: {e}", c.name)),
            (Ok(Err(e)), Expect::Err(needles)) => {
                let m = e.to_string();
                for n in std::iter::once(&fname.as_str()).chain(needles.iter()) {
                    if !m.contains(n) {
                        failures.push(format!("{}: `{n}` not in: {m}", c.name));
                    }
                }
            }
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

fn unit(d: &Direction) -> bool {
    let n = (d.kappa * d.kappa + d.tau * d.tau + d.omega * d.omega).sqrt();
    d.kappa >= 0.0 && (n - 1.0).abs() < 1e-12
}

const H: &str = "dir_kappa,dir_tau,dir_omega\n";

#[test]
fn malformed_direction_csvs_are_rejected_naming_file_field_and_value() {
    use Expect::{Err as E, Ok as K};
    let cases = vec![
        case("empty", "", E(&["dir_kappa"])),
        case("header_only", H, E(&["no directions"])),
        case(
            "missing_column",
            "dir_kappa,dir_tau\n1,0\n",
            E(&["dir_omega"]),
        ),
        case(
            "not_a_number",
            format!("{H}1,abc,0\n"),
            E(&[":2", "dir_tau", "abc"]),
        ),
        case(
            "empty_field",
            format!("{H}1,,0\n"),
            E(&[":2", "dir_tau", "``"]),
        ),
        case("nan", format!("{H}1,0,0\nNaN,1,0\n"), E(&[":3", "NaN"])),
        case("inf", format!("{H}inf,1,0\n"), E(&[":2", "inf"])),
        case("minus_inf", format!("{H}0,-inf,0\n"), E(&[":2", "inf"])),
        case(
            "overflow_1e400",
            format!("{H}1e400,0,0\n"),
            E(&[":2", "inf"]),
        ),
        case(
            "huge_integer",
            format!("{H}1{},0,0\n", "0".repeat(400)),
            E(&[":2", "inf"]),
        ),
        case("zero", format!("{H}0,0,0\n"), E(&[":2", "direction"])),
        case("negative_kappa", format!("{H}-1,0,0\n"), E(&[":2", "-1"])),
        case("ragged", format!("{H}1,0,0\n1,0\n"), E(&[":3"])),
        case("extreme_1e308", format!("{H}1e308,1e308,1e308\n"), K),
        case("tiny_1e-308", format!("{H}1e-308,0,1e-308\n"), K),
        case("minus_zero", format!("{H}-0,1,-0\n"), K),
        // A settings record (as a sweep output has) shifts the line numbers.
        case(
            "with_record",
            format!("# helixreach-settings {{}}\n{H}1,0,0\n1,x,0\n"),
            E(&[":4", "dir_tau", "`x`"]),
        ),
        case("padded", format!("{H} 1 , 2 , 3 \n"), K),
    ];
    run_corpus(&cases, "csv", read_csv, |v| v.iter().all(unit));
}

#[test]
fn malformed_boundary_tables_are_rejected_naming_file_field_and_value() {
    use Expect::{Err as E, Ok as K};
    let h = "dir_kappa,dir_tau,dir_omega,s_star\n";
    let cases = vec![
        case("no_s_star", H.to_string() + "1,0,0\n", E(&["s_star"])),
        case(
            "negative",
            format!("{h}1,0,0,-3\n"),
            E(&[":2", "s_star", "-3"]),
        ),
        case("zero", format!("{h}1,0,0,0\n"), E(&[":2", "s_star", "0"])),
        case(
            "minus_zero",
            format!("{h}1,0,0,-0\n"),
            E(&[":2", "s_star", "-0"]),
        ),
        case(
            "nan",
            format!("{h}1,0,0,NaN\n"),
            E(&[":2", "s_star", "NaN"]),
        ),
        case(
            "text",
            format!("{h}1,0,0,big\n"),
            E(&[":2", "s_star", "big"]),
        ),
        case(
            "bad_direction",
            format!("{h}NaN,0,0,3\n"),
            E(&[":2", "NaN"]),
        ),
        case("inf_is_stable", format!("{h}1,0,0,inf\n"), K),
        case("large", format!("{h}1,0,0,1e308\n"), K),
    ];
    run_corpus(&cases, "csv", BoundaryTable::read, |t| !t.is_empty());
}

fn rig_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/robots/sawyer-seed.toml"
    ))
    .unwrap()
}

#[test]
fn malformed_rig_tomls_are_rejected_naming_file_field_and_value() {
    use Expect::{Err as E, Ok as K};
    let base = rig_text();
    let sub = |from: &str, to: &str| {
        assert!(base.contains(from), "{from}");
        base.replacen(from, to, 1)
    };
    let cases = vec![
        case("syntax", "name = \"x\"\n[robot\n", E(&["line"])),
        case("empty", "", E(&["name"])),
        case(
            "string_length",
            sub("length = 0.51", "length = \"long\""),
            E(&["length", "long"]),
        ),
        case(
            "negative_length",
            sub("length = 0.51", "length = -0.51"),
            E(&["rod.length", "-0.51"]),
        ),
        case(
            "nan_length",
            sub("length = 0.51", "length = nan"),
            E(&["rod.length", "NaN"]),
        ),
        case(
            "inf_modulus",
            sub("youngs_modulus = 67.5e9", "youngs_modulus = inf"),
            E(&["youngs_modulus", "inf"]),
        ),
        case(
            "zero_density",
            sub("density = 6450.0", "density = -0.0"),
            E(&["density", "-0"]),
        ),
        case(
            "huge_margin",
            sub("margin = 0.10", "margin = 1e308"),
            E(&["margin", "1e308"]),
        ),
        case(
            "negative_count",
            sub("max_waypoints = 20000", "max_waypoints = -1"),
            E(&["max_waypoints", "-1"]),
        ),
        case(
            "huge_integer",
            sub(
                "max_waypoints = 20000",
                "max_waypoints = 99999999999999999999",
            ),
            E(&["max_waypoints"]),
        ),
        case(
            "too_many_waypoints",
            sub("max_waypoints = 20000", "max_waypoints = 100000000"),
            E(&["planner.max_waypoints", "100000000"]),
        ),
        case(
            "bad_roll",
            sub("mode = \"fixed\"", "mode = \"spin\""),
            E(&["spin"]),
        ),
        case(
            "nan_clamp",
            sub(
                "origin = [0.85, -0.15, -0.144]",
                "origin = [nan, -0.15, -0.144]",
            ),
            E(&["clamp", "NaN"]),
        ),
        case("valid", base.clone(), K),
    ];
    let load = |p: &Path| Rig::load(p.to_str().unwrap());
    run_corpus(&cases, "toml", load, |r: &Rig| r.rod.length > 0.0);
}

fn urdf(joint_limit: &str, origin: &str) -> String {
    format!(
        r#"<?xml version="1.0"?>
<robot name="r">
  <link name="base"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <link name="tip"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="tip"/>
    <origin xyz="{origin}" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    {joint_limit}
  </joint>
</robot>
"#
    )
}

#[test]
fn malformed_urdfs_are_rejected_naming_file_field_and_value() {
    use Expect::{Err as E, Ok as K};
    let lim =
        |l: &str, u: &str| format!(r#"<limit lower="{l}" upper="{u}" effort="1" velocity="1"/>"#);
    let cases = vec![
        case("not_xml", "<robot name=\"r\"><link", E(&["URDF"])),
        case("empty", "", E(&["URDF"])),
        case(
            "nan_limit",
            urdf(&lim("NaN", "1"), "0 0 0.1"),
            E(&["j1", "NaN"]),
        ),
        case(
            "inf_limit",
            urdf(&lim("-1", "inf"), "0 0 0.1"),
            E(&["j1", "inf"]),
        ),
        case(
            "reversed_limits",
            urdf(&lim("1", "-1"), "0 0 0.1"),
            E(&["j1", "1"]),
        ),
        case(
            "nan_origin",
            urdf(&lim("-1", "1"), "0 NaN 0.1"),
            E(&["j1", "NaN"]),
        ),
        case(
            "huge_origin",
            urdf(&lim("-1", "1"), "0 0 1e400"),
            E(&["j1", "inf"]),
        ),
        case(
            "text_origin",
            urdf(&lim("-1", "1"), "0 zero 0.1"),
            E(&["zero"]),
        ),
        case("valid", urdf(&lim("-1", "1"), "0 0 0.1"), K),
        // Finite, however absurd: accepted.
        case("valid_1e308", urdf(&lim("-1", "1"), "0 0 1e308"), K),
    ];
    let load = |p: &Path| RobotModel::from_urdf_file(p, Some("tip"));
    run_corpus(&cases, "urdf", load, |m: &RobotModel| m.dof() == 1);
}

/// The binary on a few malformed inputs: exit code 2 (not a panic's 101), the file named.
#[test]
fn cli_rejects_malformed_files_without_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let w = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_string()
    };
    let dirs = w("d.csv", &format!("{H}1,0,0\n1e400,0,0\n"));
    let pts = w("p.csv", "kappa,tau,omega\n1,NaN,0\n");
    let rig = w(
        "r.toml",
        &rig_text().replace("length = 0.51", "length = -1"),
    );
    let rob = w("u.urdf", "<robot");
    let bnd = w("b.csv", "dir_kappa,dir_tau,dir_omega,s_star\n1,0,0,nan\n");
    let kuka = w(
        "k.toml",
        &rig_text().replace("urdf = \"sawyer\"", "urdf = \"kuka\""),
    );
    let out = dir.path().join("o.csv");
    let out = out.to_str().unwrap();
    let runs: [(&[&str], &str); 7] = [
        (
            &[
                "plan",
                "--rig",
                &kuka,
                "--direction",
                "0.3,0.9,0.3",
                "--out",
                out,
            ],
            "kuka",
        ),
        (
            &["boundary", "--directions", &dirs, "--out", "-"],
            "d.csv:3",
        ),
        (&["helix", "--points", &pts], "p.csv:2"),
        (
            &[
                "plan",
                "--rig",
                &rig,
                "--direction",
                "0.3,0.9,0.3",
                "--out",
                out,
            ],
            "r.toml",
        ),
        (&["fk", "--robot", &rob, "--joints", "0"], "u.urdf"),
        (
            &[
                "reach",
                "--fibonacci",
                "2",
                "--boundary",
                &bnd,
                "--out",
                out,
            ],
            "b.csv:2",
        ),
        (
            &[
                "boundary",
                "--fibonacci",
                "2",
                "--nu",
                "1e308",
                "--out",
                "-",
            ],
            "1e308",
        ),
    ];
    for (args, needle) in runs {
        let o = Command::new(env!("CARGO_BIN_EXE_helixreach"))
            .args(args)
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.contains(needle), "{args:?}: `{needle}` not in {e}");
        assert!(!e.contains("panicked"), "{args:?}: {e}");
    }
}

/// Run the binary in `dir`, killing it after 30 s: a hang fails the test instead of blocking CI.
fn cli_30s(dir: &Path, args: &[&str]) -> std::process::Output {
    use std::time::{Duration, Instant};
    let mut child = Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .current_dir(dir)
        .env("RAYON_NUM_THREADS", "2")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > Duration::from_secs(30) {
            child.kill().unwrap();
            let o = child.wait_with_output().unwrap();
            panic!(
                "`helixreach {}` still running after 30 s; stderr: {}",
                args.join(" "),
                String::from_utf8_lossy(&o.stderr)
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Absurd sizes, steps and thread counts, overflowing vectors, deep nesting and repeated rows:
/// each is refused up front within seconds by an error naming the input (flag or file and
/// field) and the value — no panic, no abort, no hang, no silent answer.
#[test]
fn absurd_inputs_fail_fast_naming_the_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let w = |name: &str, text: &str| std::fs::write(d.join(name), text).unwrap();
    let rig_with = |from: &str, to: &str| {
        let base = rig_text();
        assert!(base.contains(from), "{from}");
        base.replacen(from, to, 1)
    };
    w(
        "seg.toml",
        &rig_with("segment_check_step = 0.02", "segment_check_step = 1e-9"),
    );
    w(
        "d1.toml",
        &rig_with("d1 = [0.0, 1.0, 0.0]", "d1 = [0.0, 1e308, 1e308]"),
    );
    let choices = format!("choices = [{}]", vec!["0.0"; 3601].join(", "));
    w("az.toml", &rig_with("choices = [0.0]", &choices));
    w(
        "axis.urdf",
        &urdf(
            r#"<limit lower="-1" upper="1" velocity="1" effort="1"/>"#,
            "0 0 0",
        )
        .replace(r#"<axis xyz="0 0 1"/>"#, r#"<axis xyz="1e308 1e308 0"/>"#),
    );
    let deep = format!(
        "<robot name=\"r\">{}{}</robot>",
        "<link name=\"a\">".repeat(40_000),
        "</link>".repeat(40_000)
    );
    w("deep.urdf", &deep);
    w("twice.csv", &format!("{H}1,1,1\n0,1,0\n2,2,2\n"));
    w(
        "twice_b.csv",
        "dir_kappa,dir_tau,dir_omega,s_star\n0,1,0,10\n0,2,0,11\n",
    );
    w("cols.csv", "dir_kappa,dir_tau,dir_omega,dir_tau\n1,1,1,2\n");
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        // Item 5: a ray speed whose one time step passes s_max.
        (
            vec![
                "simulate",
                "--direction",
                "1,1,1",
                "--speed",
                "1e300",
                "--s-max",
                "2",
                "--out",
                "s.csv",
            ],
            vec!["speed", "1e300", "s_max"],
        ),
        // Item 6: layout grids counted before they are allocated.
        (
            vec![
                "layout",
                "--fibonacci",
                "2",
                "--region",
                "0:1e10,0:1,0:1",
                "--out",
                "l1",
            ],
            vec!["candidate poses", "100000"],
        ),
        (
            vec![
                "layout",
                "--fibonacci",
                "2",
                "--region",
                "0:1e300,0:1,0:1",
                "--out",
                "l2",
            ],
            vec!["candidate poses", "100000"],
        ),
        (
            vec![
                "layout",
                "--fibonacci",
                "2",
                "--tilts",
                "10,20",
                "--headings",
                "9223372036854775808",
                "--out",
                "l3",
            ],
            vec!["headings", "9223372036854775808"],
        ),
        // Item 7: a URDF nested 40,000 deep.
        (
            vec!["fk", "--robot", "deep.urdf", "--joints", "0"],
            vec!["deep.urdf", "nest", "256"],
        ),
        // Item 8: steps and counts that would run for hours.
        (
            vec![
                "reach",
                "--rig",
                "seg.toml",
                "--fibonacci",
                "2",
                "--out",
                "r1.csv",
            ],
            vec!["seg.toml", "planner.segment_check_step", "1e-9"],
        ),
        (
            vec![
                "layout",
                "--fibonacci",
                "2",
                "--azimuths",
                "1000000",
                "--out",
                "l4",
            ],
            vec!["--azimuths", "1000000", "3600"],
        ),
        (
            vec![
                "boundary",
                "--fibonacci",
                "2",
                "--step",
                "1e-300",
                "--out",
                "b.csv",
            ],
            vec!["step", "1e-300"],
        ),
        (
            vec![
                "reach",
                "--rig",
                "az.toml",
                "--fibonacci",
                "2",
                "--out",
                "r4.csv",
            ],
            vec!["az.toml", "azimuth.choices", "3600"],
        ),
        // Item 9: thread counts.
        (
            vec![
                "reach",
                "--fibonacci",
                "2",
                "--threads",
                "1000000",
                "--out",
                "r2.csv",
            ],
            vec!["--threads", "1000000", "1024"],
        ),
        (
            vec![
                "reach",
                "--fibonacci",
                "2",
                "--threads",
                "0",
                "--out",
                "r2.csv",
            ],
            vec!["--threads", "0"],
        ),
        // Item 10: vectors whose norm overflows.
        (
            vec![
                "reach",
                "--rig",
                "d1.toml",
                "--fibonacci",
                "2",
                "--out",
                "r3.csv",
            ],
            vec!["d1.toml", "clamp.d1", "1e308"],
        ),
        (
            vec!["fk", "--robot", "axis.urdf", "--joints", "0"],
            vec!["axis.urdf", "joint j1 axis", "1e308"],
        ),
        // Item 12: two rows of one direction (after normalizing), both lines named.
        (
            vec!["boundary", "--directions", "twice.csv", "--out", "b2.csv"],
            vec!["twice.csv:4", "line 2"],
        ),
        // Item 14: a boundary table with two rows for one direction.
        (
            vec![
                "reach",
                "--fibonacci",
                "2",
                "--boundary",
                "twice_b.csv",
                "--out",
                "r5.csv",
            ],
            vec!["twice_b.csv:3", "line 2"],
        ),
        // Low: duplicate CSV columns.
        (
            vec!["boundary", "--directions", "cols.csv", "--out", "b3.csv"],
            vec!["cols.csv", "dir_tau", "twice"],
        ),
    ];
    for (args, needles) in cases {
        let o = cli_30s(d, &args);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        for n in needles {
            assert!(e.contains(n), "{args:?}: `{n}` not in {e}");
        }
    }
    // Nothing was written by the refused runs.
    for f in [
        "s.csv", "b.csv", "b2.csv", "r1.csv", "r2.csv", "r3.csv", "r5.csv",
    ] {
        assert!(!d.join(f).exists(), "{f}");
    }
}

/// A byte-order mark (spreadsheet exports) is not part of the first column's name.
#[test]
fn a_bom_before_the_header_is_not_a_column_name() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bom.csv");
    std::fs::write(&p, format!("\u{feff}{H}0,1,0\n")).unwrap();
    let d = read_csv(&p).unwrap();
    assert_eq!(d.len(), 1);
    assert_eq!((d[0].kappa, d[0].tau, d[0].omega), (0.0, 1.0, 0.0));
}

/// `check` of a joint file with a 1e308 rad step finishes within seconds (the segment between
/// the two rows is sampled at most `helixreach::limits::MAX_SEGMENT_SAMPLES` times).
#[test]
fn check_of_an_absurd_joint_step_finishes() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("j.txt"),
        "0 -1 0 1.5 0 -0.5 0\n0 -1 0 1.5 0 -0.5 1e308\n",
    )
    .unwrap();
    let o = cli_30s(dir.path(), &["check", "--trajectory", "j.txt"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!e.contains("panicked"), "{e}");
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap_or_default();
    assert!(
        o.status.code() != Some(0) || v["limit_violations"] == 1,
        "{e}"
    );
}

/// Low-severity cases of the "never lie" audit: each error names the file or flag, the field
/// and the value as given; negative numbers after a flag are its value.
#[test]
fn low_severity_inputs_name_file_field_and_value() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let w = |name: &str, text: &str| std::fs::write(d.join(name), text).unwrap();
    let rig_with = |from: &str, to: &str| {
        let base = rig_text();
        assert!(base.contains(from), "{from}");
        base.replacen(from, to, 1)
    };
    let lim = r#"<limit lower="-1" upper="1" velocity="1" effort="1"/>"#;
    w(
        "arr4.toml",
        &rig_with("d1 = [0.0, 1.0, 0.0]", "d1 = [0.0, 1.0, 0.0, 5.0]"),
    );
    w(
        "speed.toml",
        &rig_with("end_speed = 0.01", "end_speed = 1e-320"),
    );
    w(
        "weights.toml",
        &rig_with(
            "joint_weights = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]",
            "joint_weights = [1.0, 1.0, 1.0, 1e308, 1.0, 1.0, 1.0]",
        ),
    );
    w("nolimit.urdf", &urdf("", "0 0 0"));
    w(
        "vel.urdf",
        &urdf(
            r#"<limit lower="-1" upper="1" velocity="-2" effort="1"/>"#,
            "0 0 0",
        ),
    );
    w(
        "twice.urdf",
        &urdf(lim, "0 0 0").replace(
            "</robot>",
            r#"<link name="tip2"/><joint name="j1" type="fixed"><parent link="tip"/><child link="tip2"/></joint></robot>"#,
        ),
    );
    // A seed-like joint file, and timed joint-name CSVs whose time goes back or is NaN.
    let q = "0,-1,0,1.5,0,-0.5,0";
    w("j.txt", "0 -1 0 1.5 0 -0.5 0\n");
    let named = "t,right_j0,right_j1,right_j2,right_j3,right_j4,right_j5,right_j6\n";
    w("back.csv", &format!("{named}0.5,{q}\n0.25,{q}\n"));
    w("nan_t.csv", &format!("{named}0,{q}\nNaN,{q}\n"));
    let cases: Vec<(Vec<&str>, Vec<&str>)> = vec![
        // s_max is bounded where a scan over s would otherwise run for ever.
        (
            vec![
                "check",
                "--trajectory",
                "j.txt",
                "--direction",
                "1,1,1",
                "--s-max",
                "1e308",
            ],
            vec!["s_max", "1e308", "1e4"],
        ),
        // A time step longer than the whole ray is refused naming both.
        (
            vec![
                "simulate",
                "--direction",
                "1,1,1",
                "--dt",
                "1e3",
                "--out",
                "dt.csv",
            ],
            vec!["dt = 1000 s", "s_max = 40"],
        ),
        // Time going backwards, or not a number, names the file, line and column.
        (
            vec!["check", "--trajectory", "back.csv"],
            vec!["back.csv:3", "t:", "before the previous row's 0.5"],
        ),
        (
            vec!["check", "--trajectory", "nan_t.csv"],
            vec!["nan_t.csv:3", "t:", "`NaN` is not a finite value"],
        ),
        (
            vec![
                "reach",
                "--rig",
                "arr4.toml",
                "--fibonacci",
                "1",
                "--out",
                "a.csv",
            ],
            vec!["arr4.toml", "d1", "got 4"],
        ),
        (
            vec![
                "reach",
                "--rig",
                "speed.toml",
                "--fibonacci",
                "1",
                "--out",
                "a.csv",
            ],
            vec!["speed.toml", "planner.end_speed", "1e-320"],
        ),
        (
            vec![
                "reach",
                "--rig",
                "weights.toml",
                "--fibonacci",
                "1",
                "--out",
                "a.csv",
            ],
            vec!["weights.toml", "planner.joint_weights[3]", "1e308"],
        ),
        (
            vec!["fk", "--robot", "nolimit.urdf", "--joints", "0"],
            vec!["nolimit.urdf", "joint j1 limit"],
        ),
        (
            vec!["fk", "--robot", "vel.urdf", "--joints", "0"],
            vec!["vel.urdf", "joint j1 limit velocity", "-2"],
        ),
        (
            vec!["fk", "--robot", "twice.urdf", "--joints", "0"],
            vec!["twice.urdf", "joint j1", "share"],
        ),
        // Negative values are values, not flags.
        (
            vec!["boundary", "--fibonacci", "-5", "--out", "a.csv"],
            vec!["--fibonacci", "-5"],
        ),
        (
            vec![
                "boundary",
                "--fibonacci",
                "4",
                "--shard",
                "-1/2",
                "--out",
                "a.csv",
            ],
            vec!["--shard", "-1/2"],
        ),
        (
            vec![
                "boundary",
                "--fibonacci",
                "4",
                "--tol",
                "-1e-12",
                "--out",
                "a.csv",
            ],
            vec!["tol", "-1e-12"],
        ),
        // Derived quantities out of range name the fields they come from.
        (
            vec![
                "simulate",
                "--direction",
                "1,1,1",
                "--youngs-modulus",
                "1e308",
                "--out",
                "ym.csv",
            ],
            vec!["youngs_modulus = 1e308", "bending stiffness"],
        ),
        // simulate checks its output before anything else: with an output whose directory
        // cannot be made (a file is in its place) and an --n-edges past its bound, the output
        // is the error (the parameters, then the simulation, come after it).
        (
            vec![
                "simulate",
                "--direction",
                "1,1,1",
                "--n-edges",
                "100000000",
                "--out",
                "speed.toml/s.csv",
            ],
            vec!["speed.toml/s.csv", "cannot create its directory"],
        ),
    ];
    for (args, needles) in cases {
        let o = cli_30s(d, &args);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        for n in needles {
            assert!(e.contains(n), "{args:?}: `{n}` not in {e}");
        }
        if args.contains(&"speed.toml/s.csv") {
            assert!(!e.contains("n-edges"), "output not checked first: {e}");
        }
    }
    assert!(!d.join("a.csv").exists());
}
