//! The rig's rod as the rod of the commands that simulate: a rod given by a rig file equals the
//! same rod given by flags, bad rods are errors naming the rig file and field, and the
//! simulated centerline is placed at the rig's clamp (checked against the exact helix).

use helixreach::helix::Helix;
use helixreach::math::{Mat3, Vec3};
use helixreach::planning::rig::{Rig, EMBEDDED_RIGS};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn cli(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .expect("run helixreach")
}

fn ok(out: &Output) {
    assert!(
        out.status.success(),
        "exit {:?}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The embedded seed rig's TOML with the `[rod]` table replaced by `rod`, and the robot given
/// as the built-in name (so the file works from any directory).
fn seed_rig_with_rod(rod: &str) -> String {
    let text = EMBEDDED_RIGS
        .iter()
        .find(|(n, _)| *n == "sawyer-seed")
        .unwrap()
        .1;
    let start = text.find("[rod]").unwrap();
    let end = start + text[start..].find("[motor]").unwrap();
    format!("{}[rod]\n{rod}\n\n{}", &text[..start], &text[end..])
}

/// The command was refused (exit 2) with every needle in its error.
fn refused(o: &Output, needles: &[&str]) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    for n in needles {
        assert!(e.contains(n), "{n:?} missing from: {e}");
    }
}

fn write_rig(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const GOOD_ROD: &str =
    "length = 0.4\nradius = 1.0e-3\nyoungs_modulus = 2.0e9\npoisson = 0.25\ndensity = 1500.0";

#[test]
fn bad_rods_are_errors_naming_the_rig_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("radius = 1.0e-3", "radius = -1.0e-3", "rod.radius"),
        ("poisson = 0.25", "poisson = 0.6", "rod.poisson"),
        ("poisson = 0.25", "poisson = -1.0", "rod.poisson"),
        ("density = 1500.0", "density = 0.0", "rod.density"),
        (
            "youngs_modulus = 2.0e9",
            "youngs_modulus = nan",
            "rod.youngs_modulus",
        ),
        ("length = 0.4", "length = inf", "rod.length"),
    ];
    for (k, (from, to, field)) in cases.iter().enumerate() {
        let text = seed_rig_with_rod(&GOOD_ROD.replace(from, to));
        let path = write_rig(dir.path(), &format!("bad{k}.toml"), &text);
        let e = Rig::from_file(&path).unwrap_err().to_string();
        assert!(
            e.contains(&path.display().to_string()) && e.contains(field),
            "{to}: {e}"
        );
        // The commands that simulate report it the same way (exit 2, no panic).
        let p = path.to_str().unwrap();
        for args in [
            vec!["simulate", "--direction", "1,1,1", "--rig", p, "--out"],
            vec![
                "boundary",
                "--method",
                "der",
                "--fibonacci",
                "4",
                "--rig",
                p,
                "--out",
            ],
            vec!["bifurcation", "--fibonacci", "4", "--rig", p, "--out"],
        ] {
            let out_file = dir.path().join(format!("o{k}.csv"));
            let mut a = args.clone();
            a.push(out_file.to_str().unwrap());
            let out = cli(&a);
            assert_eq!(out.status.code(), Some(2), "{a:?}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(err.contains(field) && err.contains(p), "{a:?}: {err}");
            assert!(!err.contains("panicked"), "{err}");
            assert!(!out_file.exists());
        }
    }
    // A good rod loads.
    let path = write_rig(dir.path(), "good.toml", &seed_rig_with_rod(GOOD_ROD));
    let rig = Rig::from_file(&path).unwrap();
    assert_eq!(rig.rod.nu, 0.25);
    assert_eq!(rig.rod.radius, 1.0e-3);
}

#[test]
fn a_rod_given_by_the_rig_gives_the_same_series_and_boundary_as_the_same_rod_by_flags() {
    let dir = tempfile::tempdir().unwrap();
    let rig = write_rig(dir.path(), "r.toml", &seed_rig_with_rod(GOOD_ROD));
    let rig = rig.to_str().unwrap();
    let run = |extra: &[&str], name: &str| -> String {
        let out = dir.path().join(name);
        let mut a = vec![
            "simulate",
            "--direction",
            "1,1,1",
            "--n-edges",
            "12",
            "--dt",
            "0.02",
            "--speed",
            "1",
            "--s-max",
            "2",
            "--record-ds",
            "0.1",
            "--out",
            out.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        ok(&cli(&a));
        std::fs::read_to_string(&out).unwrap()
    };
    let flags = [
        "--length",
        "0.4",
        "--radius",
        "1e-3",
        "--youngs-modulus",
        "2e9",
        "--nu",
        "0.25",
        "--density",
        "1500",
    ];
    let by_rig = run(&["--rig", rig], "rig.csv");
    let by_flags = run(&flags, "flags.csv");
    assert_eq!(by_rig, by_flags);
    // The flags matter (the comparison above can fail): the default rod's series differs.
    assert_ne!(by_rig, run(&[], "default.csv"));
    // With gravity the rig's clamp orientation (rod up: gravity along −d3) is the flags'
    // default (gravity along −z of the clamp frame).
    let mut g = flags.to_vec();
    g.push("--gravity");
    assert_eq!(
        run(&["--rig", rig, "--gravity"], "rig_g.csv"),
        run(&g, "flags_g.csv")
    );

    // The DER boundary: the rig's ν, on the paper's three directions.
    let dirs = dir.path().join("dirs.csv");
    std::fs::write(
        &dirs,
        "dir_kappa,dir_tau,dir_omega\n0.594,0.698,0.4\n1,1,-1\n1,1,1\n",
    )
    .unwrap();
    let b = |extra: &[&str], name: &str| -> String {
        let out = dir.path().join(name);
        let mut a = vec![
            "boundary",
            "--method",
            "der",
            "--n-edges",
            "20",
            "--tol",
            "1e-6",
            "--directions",
            dirs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        ok(&cli(&a));
        std::fs::read_to_string(&out).unwrap()
    };
    let by_rig = b(&["--rig", rig], "b_rig.csv");
    assert_eq!(by_rig, b(&["--nu", "0.25"], "b_flags.csv"));
    // The rig's ν reached the solver (the default ν = 0.33 gives another file).
    assert_ne!(by_rig, b(&[], "b_default.csv"));
    // With gravity: the rig's rod and clamp (rod up) are the flags' rod held up; the weight
    // moves s* (the file differs from the gravity-free one).
    let mut g = flags.to_vec();
    g.push("--gravity");
    let rig_g = b(&["--rig", rig, "--gravity"], "b_rig_g.csv");
    assert_eq!(rig_g, b(&g, "b_flags_g.csv"));
    assert_ne!(rig_g, by_rig);
    // Gravity needs the DER rod.
    let out = cli(&["boundary", "--fibonacci", "3", "--gravity", "--out", "-"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--method der"));
}

/// Parse the centerline CSV into rows of named fields.
fn read_centerline(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn centerline_at_small_s_is_the_exact_helix_at_the_rigs_clamp() {
    let dir = tempfile::tempdir().unwrap();
    let series = dir.path().join("s.csv");
    let cl = dir.path().join("c.csv");
    let n = 24;
    let ns = n.to_string();
    ok(&cli(&[
        "simulate",
        "--rig",
        "sawyer-seed",
        "--direction",
        "0.594,0.698,0.4",
        "--n-edges",
        &ns,
        "--speed",
        "0.2",
        "--dt",
        "0.01",
        "--s-max",
        "1.5",
        "--record-ds",
        "0.1",
        "--damping",
        "5",
        "--out",
        series.to_str().unwrap(),
        "--centerline",
        cl.to_str().unwrap(),
        "--centerline-stride",
        "5",
    ]));
    let rows = read_centerline(&cl);
    let rig = Rig::load("sawyer-seed").unwrap();
    let (o, r, len) = (
        rig.clamp.translation.vector,
        rig.clamp_rotation(),
        rig.rod.length,
    );
    let c = 1.0 / (1.0 + rig.rod.nu);
    let d = Vec3::new(0.594, 0.698, 0.4).normalize();
    let f = |row: &std::collections::HashMap<String, String>, k: &str| -> f64 {
        row[k].parse().unwrap()
    };
    // Samples 0, 5, 10, 15 (s = 0, 0.5, 1.0, 1.5), n + 1 nodes each.
    assert_eq!(rows.len(), 4 * (n + 1));
    let mut worst_at_last = 0.0f64;
    for row in &rows {
        let s = f(row, "s");
        let i: usize = row["node"].parse().unwrap();
        if i == 0 || i == n {
            continue; // the straddling clamps' outer nodes lie outside [0, L]
        }
        let arc = f(row, "arc") / len;
        let h = Helix::new(s * d.x, s * d.y, s * d.z).unwrap();
        let exact = o + r * (len * h.position(arc));
        let x = Vec3::new(f(row, "x"), f(row, "y"), f(row, "z"));
        let err = (x - exact).norm() / len;
        // DER at n = 24 and a slow, damped drive: O(1/n²) discretization and a small lag.
        assert!(err < 2e-3 * s.max(0.05), "s = {s}, node {i}: {err:e}");
        if s > 1.4 {
            worst_at_last = worst_at_last.max(err);
            // The tangent column is the base-frame tangent of the helix there.
            let t = Vec3::new(f(row, "tx"), f(row, "ty"), f(row, "tz"));
            // Edge i is centred half an edge past node i.
            let fr: Mat3 = h.material_frame(arc + 0.5 / (n as f64 - 1.0), c);
            let t_exact = r * fr.column(2);
            assert!((t - t_exact).norm() < 2e-2, "node {i}: {t} vs {t_exact}");
        }
    }
    // The check has teeth: the clamp pose matters at the resolution of the comparison (the
    // unplaced helix is metres away).
    assert!(o.norm() > 0.5 && worst_at_last < 2e-3 * 1.5);
    // The last node's frame is empty (no edge starts there).
    let last = rows.iter().find(|r| r["node"] == ns).unwrap();
    assert_eq!(last["tx"], "");
}

#[test]
fn rod_reports_the_gravito_bending_ratio_of_the_rigs_rod() {
    let out = cli(&["rod", "--rig", "sawyer-seed"]);
    ok(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // The seed rig's nitinol rod, by the formula written out here: h = 1.5875/2 mm.
    let (h, e, rho, g, l): (f64, f64, f64, f64, f64) = (0.79375e-3, 67.5e9, 6450.0, 9.81, 0.51);
    let ratio = (h * h * e / (8.0 * rho * g)).cbrt() / l;
    let a = &v["assessment"];
    assert!((a["lgb_over_l"].as_f64().unwrap() - ratio).abs() < 1e-12 * ratio);
    let w = a["weight_per_length"].as_f64().unwrap();
    assert!((w - 0.5 / ratio.powi(3)).abs() < 1e-12 * w);
    // 0.86: above the seed's 0.6, below the measured threshold.
    assert_eq!(a["negligible"], false);
    assert_eq!(
        v["clamp"]["orientation"]
            .as_str()
            .unwrap()
            .split(' ')
            .nth(1),
        Some("up")
    );
    // A rig holding the rod horizontally, and a rod stiff enough for gravity to be negligible.
    let dir = tempfile::tempdir().unwrap();
    let text = seed_rig_with_rod(GOOD_ROD)
        .replace("d1 = [0.0, 1.0, 0.0]", "d1 = [0.0, 0.0, 1.0]")
        .replace("d3 = [0.0, 0.0, 1.0]", "d3 = [1.0, 0.0, 0.0]");
    let p = write_rig(dir.path(), "h.toml", &text);
    let out = cli(&["rod", "--rig", p.to_str().unwrap(), "--g", "1e-3"]);
    ok(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(
        v["clamp"]["orientation"]
            .as_str()
            .unwrap()
            .split(' ')
            .nth(1),
        Some("horizontal")
    );
    assert_eq!(v["assessment"]["negligible"], true);
    // Bad input: a clear error naming the flag's field.
    let out = cli(&["rod", "--preset", "nitinol", "--density", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("density"));
}

#[test]
fn der_to_a_requested_accuracy_meets_it_against_the_continuum_or_names_the_n_needed() {
    use helixreach::boundary::{continuum, der};
    use helixreach::directions::Direction;
    let p = der::DerBoundaryParams {
        n_edges: 25,
        tol_rel: 1e-9,
        ..Default::default()
    };
    // The paper's three directions: within the requested 1e-3 of the continuum (an
    // independent method), and the estimate bounds the actual error.
    for (k, t, w) in [(0.594, 0.698, 0.4), (1.0, 1.0, -1.0), (1.0, 1.0, 1.0)] {
        let d = Direction::new(k, t, w).unwrap();
        let c = continuum::critical_s(&d, 1e-10).unwrap().s_star;
        let r = der::critical_s_to_rel_tol(&d, &p, 1e-3, 800).unwrap();
        let err = (r.s_star - c).abs() / c;
        assert!(
            r.richardson_rel <= 1e-3 && err <= 1e-3,
            "{d:?}: {r:?} vs {c}"
        );
        assert!(
            err <= 2.0 * r.richardson_rel + 1e-6,
            "{d:?}: {err} vs {r:?}"
        );
        // A tighter request needs a finer rod.
        let fine = der::critical_s_to_rel_tol(&d, &p, 1e-5, 3200).unwrap();
        assert!(fine.n_edges > r.n_edges);
        assert!(
            (fine.s_star - c).abs() / c <= 1e-5,
            "{d:?}: {fine:?} vs {c}"
        );
    }
    // A bound too small for the request: an error naming the n needed, never a capped number.
    let d = Direction::new(1.0, 1.0, 1.0).unwrap();
    let e = der::critical_s_to_rel_tol(&d, &p, 1e-7, 100)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("max_n_edges") && e.contains("needs n_edges"),
        "{e}"
    );
}

/// `bifurcation --rel-tol`: n chosen per direction as the boundary's, the s* of every row within
/// the request of the continuum s* (an independent method), the row naming its n; a bound too
/// small for the request is a `degenerate` row naming the n needed, never a capped answer.
#[test]
fn bifurcation_to_a_requested_accuracy_meets_it_against_the_continuum() {
    use helixreach::boundary::continuum;
    use helixreach::directions::Direction;
    let dir = tempfile::tempdir().unwrap();
    let dirs = dir.path().join("dirs.csv");
    std::fs::write(
        &dirs,
        "dir_kappa,dir_tau,dir_omega\n0.594,0.698,0.4\n1,1,-1\n1,1,1\n",
    )
    .unwrap();
    let run = |max_n: &str, name: &str| -> Vec<Vec<String>> {
        let out = dir.path().join(name);
        ok(&cli(&[
            "bifurcation",
            "--directions",
            dirs.to_str().unwrap(),
            "--n-edges",
            "25",
            "--rel-tol",
            "1e-3",
            "--max-n-edges",
            max_n,
            "--no-return",
            "--out",
            out.to_str().unwrap(),
        ]));
        std::fs::read_to_string(&out)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    for r in run("800", "ok.csv") {
        let d = Direction::new(
            r[0].parse().unwrap(),
            r[1].parse().unwrap(),
            r[2].parse().unwrap(),
        )
        .unwrap();
        let c = continuum::critical_s(&d, 1e-10).unwrap().s_star;
        let s: f64 = r[3].parse().unwrap();
        assert!((s - c).abs() / c <= 1e-3, "{r:?} vs continuum {c}");
        assert!(r[8].starts_with("n=") && r[8].contains("rel_err="), "{r:?}");
        assert_ne!(r[4], "degenerate", "{r:?}");
    }
    // n ≤ 25 cannot give a second resolution: every row is degenerate and names the bound.
    for r in run("40", "capped.csv") {
        assert_eq!(r[4], "degenerate", "{r:?}");
        assert!(r.join(",").contains("max_n_edges"), "{r:?}");
    }
}

/// `reach`, `plan`, `layout` and `campaign` plan with the boundary of the rig's rod: the
/// gravity-free one above L_gb/L = 0.6, stating gravity's estimated shift of s* (the seed rig:
/// L_gb/L = 0.86, about 1.6 %; see the test of the estimate in `tests/rod.rs`) and warning
/// when it exceeds the margin; refused below 0.6, naming `boundary --method der --gravity`
/// and `--boundary` — and a boundary computed with gravity is then accepted, at its own
/// azimuth only.
#[test]
fn planning_commands_use_the_boundary_of_the_rigs_rod() {
    let dir = tempfile::tempdir().unwrap();
    let rod = |e: &str| {
        format!(
            "length = 0.51\ndiameter = 1.5875e-3\nyoungs_modulus = {e}\npoisson = 0.33\n\
             density = 6450.0"
        )
    };
    // L_gb/L ∝ E^(1/3): 13.3 GPa gives 0.50, 36.5 GPa 0.70 (the seed's 67.5 GPa: 0.86).
    let soft = write_rig(dir.path(), "soft.toml", &seed_rig_with_rod(&rod("13.3e9")));
    let middle = write_rig(
        dir.path(),
        "middle.toml",
        &seed_rig_with_rod(&rod("36.5e9")),
    );
    let (soft, middle) = (soft.to_str().unwrap(), middle.to_str().unwrap());
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let dirs = out("dirs.csv");
    std::fs::write(
        &dirs,
        "dir_kappa,dir_tau,dir_omega\n1,1,-1\n0.594,0.698,0.4\n",
    )
    .unwrap();
    let gravity_way_out = ["L_gb/L", "0.50", "--gravity", "--boundary"];
    let r1 = out("r1.csv");
    refused(
        &cli(&["reach", "--rig", soft, "--directions", &dirs, "--out", &r1]),
        &gravity_way_out,
    );
    assert!(!Path::new(&r1).exists(), "a refused sweep writes nothing");
    refused(
        &cli(&[
            "plan",
            "--rig",
            soft,
            "--direction",
            "1,1,-1",
            "--out",
            &out("p.csv"),
        ]),
        &gravity_way_out,
    );
    refused(
        &cli(&[
            "layout",
            "--rig",
            soft,
            "--directions",
            &dirs,
            "--out",
            &out("lay"),
        ]),
        &gravity_way_out,
    );
    refused(
        &cli(&[
            "campaign",
            "--rig",
            soft,
            "--directions",
            &dirs,
            "--out",
            &out("camp"),
        ]),
        &gravity_way_out,
    );
    // A given s* is the user's boundary.
    ok(&cli(&[
        "plan",
        "--rig",
        soft,
        "--direction",
        "1,1,-1",
        "--s-star",
        "5",
        "--allow-partial",
        "--out",
        &out("p.csv"),
    ]));
    // The boundary with gravity, then the sweep on it (the rig plans at azimuth 0 only).
    let b = out("b.csv");
    ok(&cli(&[
        "boundary",
        "--method",
        "der",
        "--gravity",
        "--rig",
        soft,
        "--directions",
        &dirs,
        "--n-edges",
        "30",
        "--out",
        &b,
    ]));
    let o = cli(&[
        "reach",
        "--rig",
        soft,
        "--directions",
        &dirs,
        "--boundary",
        &b,
        "--out",
        &out("r2.csv"),
    ]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("computed with gravity"));
    refused(
        &cli(&[
            "reach",
            "--rig",
            soft,
            "--directions",
            &dirs,
            "--boundary",
            &b,
            "--azimuths",
            "2",
            "--out",
            &out("r3.csv"),
        ]),
        &["azimuth", "gravity"],
    );
    // Between 0.6 and 1.1: gravity-free, with a warning past the margin (even with --quiet).
    let o = cli(&[
        "reach",
        "--rig",
        middle,
        "--fibonacci",
        "1",
        "--quarter",
        "--out",
        &out("r4.csv"),
    ]);
    ok(&o);
    assert!(String::from_utf8_lossy(&o.stderr).contains("within the margin"));
    let o = cli(&[
        "--quiet",
        "reach",
        "--rig",
        middle,
        "--fibonacci",
        "1",
        "--quarter",
        "--margin",
        "0.02",
        "--out",
        &out("r5.csv"),
    ]);
    ok(&o);
    let e = String::from_utf8_lossy(&o.stderr);
    for n in [
        "warning",
        "L_gb/L = 0.70",
        "more than the margin",
        "--boundary",
    ] {
        assert!(e.contains(n), "{n:?} missing from: {e}");
    }
}

/// Rows of a CSV as maps from column name to field.
fn read_rows(path: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let head = r.headers().unwrap().clone();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            head.iter()
                .zip(rec.iter())
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

/// Gravity makes s* depend on the ray's azimuth when the rod is not vertical, so `reach` with
/// several azimuths takes one boundary with gravity per azimuth and plans each azimuth to its
/// own s*: every row carries the s* of the boundary of its chosen azimuth, and the row is the
/// one of the two single-azimuth sweeps, each run on its own boundary, that the order of
/// `plan_best` picks (the first testable azimuth; else testable > partial > blocked, then
/// farther, then cheaper, then the first azimuth). A missing azimuth, two files at
/// one azimuth, or a gravity-free file among them are refused, naming the way out.
#[test]
fn reach_with_azimuths_plans_each_azimuth_to_its_own_gravity_boundary() {
    let dir = tempfile::tempdir().unwrap();
    // L_gb/L = 0.50 (gravity required), the rod held horizontally along −x of the base, its
    // clamp raised to where the Sawyer reaches the straight rod's end.
    let rod = "length = 0.51\ndiameter = 1.5875e-3\nyoungs_modulus = 13.3e9\npoisson = 0.33\n\
               density = 6450.0";
    // Azimuths 0 and 3π/2: on this rig each wins some of the directions below.
    let a2 = (1.5 * std::f64::consts::PI).to_string();
    let horizontal = seed_rig_with_rod(rod)
        .replace(
            "origin = [0.85, -0.15, -0.144]",
            "origin = [0.95, -0.15, 0.1]",
        )
        .replace("d1 = [0.0, 1.0, 0.0]", "d1 = [0.0, 0.0, 1.0]")
        .replace("d3 = [0.0, 0.0, 1.0]", "d3 = [-1.0, 0.0, 0.0]");
    assert!(horizontal.contains("choices = [0.0]"));
    let rig0 = write_rig(dir.path(), "h0.toml", &horizontal);
    let rig_a2 = write_rig(
        dir.path(),
        "ha2.toml",
        &horizontal.replace("choices = [0.0]", &format!("choices = [{a2}]")),
    );
    let both = write_rig(
        dir.path(),
        "hboth.toml",
        &horizontal.replace("choices = [0.0]", &format!("choices = [0.0, {a2}]")),
    );
    let (rig0, rig_a2, both) = (
        rig0.to_str().unwrap(),
        rig_a2.to_str().unwrap(),
        both.to_str().unwrap(),
    );
    let out = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let dirs = out("dirs.csv");
    std::fs::write(
        &dirs,
        "dir_kappa,dir_tau,dir_omega\n1,1,-1\n0.594,0.698,0.4\n1,0.2,0.1\n1,0.5,-0.5\n0.5,0.1,1\n",
    )
    .unwrap();
    let boundary = |azimuth: &str, name: &str| {
        let b = out(name);
        ok(&cli(&[
            "boundary",
            "--method",
            "der",
            "--gravity",
            "--rig",
            rig0,
            "--azimuth",
            azimuth,
            "--directions",
            &dirs,
            "--n-edges",
            "30",
            "--out",
            &b,
        ]));
        b
    };
    let (b0, b_a2) = (boundary("0", "b0.csv"), boundary(&a2, "ba2.csv"));
    let s_of = |path: &str| -> Vec<f64> {
        read_rows(path)
            .iter()
            .map(|r| r["s_star"].parse().unwrap())
            .collect()
    };
    let (s0, s_a2) = (s_of(&b0), s_of(&b_a2));
    assert!(
        s0.iter()
            .zip(&s_a2)
            .any(|(a, b)| (a / b - 1.0).abs() > 1e-3),
        "a horizontal rod's s* must depend on the azimuth: {s0:?} vs {s_a2:?}"
    );
    let reach = |rig: &str, files: &[&str], name: &str| {
        let o = out(name);
        let mut args = vec!["reach", "--rig", rig, "--directions", &dirs, "--out", &o];
        for f in files {
            args.extend(["--boundary", f]);
        }
        let res = cli(&args);
        (res, o)
    };
    let (res, r_both) = reach(both, &[&b0, &b_a2], "both.csv");
    ok(&res);
    assert!(
        String::from_utf8_lossy(&res.stderr).contains("its own s*"),
        "{}",
        String::from_utf8_lossy(&res.stderr)
    );
    let (res, r0) = reach(rig0, &[&b0], "r0.csv");
    ok(&res);
    let (res, r_a2) = reach(rig_a2, &[&b_a2], "ra2.csv");
    ok(&res);
    let rank = |c: &str| match c {
        "testable" => 3,
        "undecided" => 2,
        "partial" => 1,
        "blocked" => 0,
        other => panic!("class {other}"),
    };
    let (rows, rows0, rows_a2) = (read_rows(&r_both), read_rows(&r0), read_rows(&r_a2));
    assert_eq!(rows.len(), 5);
    let show = |r: &[std::collections::HashMap<String, String>]| -> Vec<String> {
        r.iter()
            .map(|r| {
                format!(
                    "{} {} {} {}",
                    r["azimuth"], r["s_star"], r["class"], r["s_reached"]
                )
            })
            .collect()
    };
    eprintln!(
        "both {:?}\nazimuth 0 {:?}\nazimuth 3pi/2 {:?}",
        show(&rows),
        show(&rows0),
        show(&rows_a2)
    );
    let mut chosen = [0usize; 2];
    for k in 0..5 {
        let (row, a, b) = (&rows[k], &rows0[k], &rows_a2[k]);
        let az: f64 = row["azimuth"].parse().unwrap();
        let own = if az.abs() < 1e-9 { s0[k] } else { s_a2[k] };
        assert!(
            az.abs() < 1e-9 || (az - 1.5 * std::f64::consts::PI).abs() < 1e-9,
            "azimuth {az}"
        );
        chosen[usize::from(az.abs() > 1e-9)] += 1;
        let s: f64 = row["s_star"].parse().unwrap();
        assert_eq!(s, own, "row {k}: planned to the s* of its own azimuth");
        let key = |r: &std::collections::HashMap<String, String>| {
            (
                rank(&r["class"]),
                r["s_reached"].parse::<f64>().unwrap(),
                -r["path_cost"].parse::<f64>().unwrap(),
            )
        };
        // The first testable azimuth in order ends the search; else the better one.
        let better = if a["class"] != "testable" && key(b).partial_cmp(&key(a)).unwrap().is_gt() {
            b
        } else {
            a
        };
        for col in [
            "class",
            "s_reached",
            "azimuth",
            "s_star",
            "cause",
            "path_cost",
        ] {
            assert_eq!(row[col], better[col], "row {k}, column {col}");
        }
    }
    assert!(
        chosen.iter().all(|&n| n > 0),
        "each azimuth must win some ray for the test to discriminate: {chosen:?}"
    );
    // An azimuth without its boundary.
    refused(&reach(both, &[&b0], "x1.csv").0, &["azimuth", "--boundary"]);
    // The same azimuth twice.
    let b0_again = out("b0_again.csv");
    std::fs::copy(&b0, &b0_again).unwrap();
    std::fs::copy(format!("{b0}.meta.json"), format!("{b0_again}.meta.json")).unwrap();
    refused(
        &reach(both, &[&b0, &b0_again], "x2.csv").0,
        &["b0_again.csv", "one boundary per azimuth"],
    );
    // A gravity-free boundary among them.
    let free = out("free.csv");
    ok(&cli(&["boundary", "--directions", &dirs, "--out", &free]));
    refused(
        &reach(both, &[&b0, &free], "x3.csv").0,
        &["free.csv", "no gravity"],
    );
}
