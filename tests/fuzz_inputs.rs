//! A fuzz-style corpus of malformed inputs (issue 13): direction and boundary CSVs, rig TOML,
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
  <link name="base"/>
  <link name="tip"/>
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
