//! `helixreach demo --quick` end to end: into a temporary folder, then check that the report
//! exists in both forms, that its numbers parse and are consistent with the CSVs beside it, and
//! that every figure it lists exists and is a non-trivial image.

use serde_json::Value;
use std::collections::HashSet;
use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

/// (width, height, share of non-white pixels, distinct colours) of a PNG.
fn png_stats(path: &Path) -> (u32, u32, f64, usize) {
    let file = std::fs::File::open(path).unwrap();
    let mut dec = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .unwrap();
    let mut buf = vec![0; dec.output_buffer_size()];
    let info = dec.next_frame(&mut buf).unwrap();
    let ch = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("unexpected PNG colour type {other:?}"),
    };
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks(ch).collect();
    let ink = px.iter().filter(|p| p[..3] != [255, 255, 255]).count() as f64 / px.len() as f64;
    let colours = px
        .iter()
        .map(|p| [p[0], p[1], p[2]])
        .collect::<HashSet<_>>()
        .len();
    (info.width, info.height, ink, colours)
}

fn finite_numbers(v: &Value, path: &str, out: &mut Vec<(String, f64)>) {
    match v {
        Value::Number(n) => out.push((path.to_string(), n.as_f64().unwrap())),
        Value::Object(m) => {
            for (k, x) in m {
                finite_numbers(x, &format!("{path}.{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                finite_numbers(x, &format!("{path}[{i}]"), out);
            }
        }
        _ => {}
    }
}

#[test]
fn demo_quick_writes_report_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("figs");
    let res = Command::new(BIN)
        .args(["demo", "--quick", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert!(res.status.success(), "demo failed: {stderr}");
    // Progress goes to stderr, stage by stage.
    for stage in [
        "continuum boundary",
        "der check",
        "reachability",
        "dynamics",
        "trajectory",
        "figures",
    ] {
        assert!(
            stderr.contains(&format!("{stage}: start")),
            "no progress for {stage}: {stderr}"
        );
    }

    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert_eq!(json["settings"]["mode"], "quick");
    assert!(json["total_seconds"].as_f64().unwrap() > 0.0);
    let stages = json["stages"].as_object().unwrap();
    for name in [
        "continuum_boundary",
        "der_check",
        "reachability",
        "dynamics",
        "trajectory",
        "figures",
    ] {
        let s = &stages[name];
        let status = s["status"].as_str().unwrap();
        assert!(status == "done" || status == "skipped", "{name}: {status}");
        if status == "skipped" {
            // A skipped stage says why, in both reports.
            let reason = s["reason"].as_str().unwrap();
            assert!(!reason.is_empty());
            assert!(md.contains(reason), "report.md lacks the reason for {name}");
        }
    }
    // Every number in the report parses as a finite number or is an explicit ∞ / NaN stand-in
    // (JSON has no ∞: serde writes null, which is not a number and is skipped here).
    let mut nums = Vec::new();
    finite_numbers(&json, "", &mut nums);
    assert!(!nums.is_empty());
    for (p, v) in &nums {
        assert!(v.is_finite(), "{p} = {v}");
    }

    // Numbers agree with the CSVs they summarize.
    if stages["continuum_boundary"]["status"] == "done" {
        let c = &stages["continuum_boundary"];
        let rows = helixreach::plot::read_boundary(&out.join("boundary.csv")).unwrap();
        assert_eq!(
            c["directions"].as_u64().unwrap() as usize,
            rows.len() + c["failed"].as_u64().unwrap() as usize
        );
        let finite: Vec<f64> = rows
            .iter()
            .map(|r| r.s_star)
            .filter(|s| s.is_finite())
            .collect();
        let min = finite.iter().copied().fold(f64::INFINITY, f64::min);
        assert!((c["s_star_min"].as_f64().unwrap() - min).abs() <= 1e-12 * min);
        // The κ axis closes into a circle at 2π (an analytic limit, checked by the demo too).
        assert!(c["kappa_axis_rel_err_vs_2pi"].as_f64().unwrap() < 1e-6);
    }
    if stages["reachability"]["status"] == "done" {
        let rows = helixreach::plot::read_reach(&out.join("reach.csv")).unwrap();
        for mode in ["fixed", "motor"] {
            let r = &stages["reachability"][format!("roll_{mode}")];
            let n: Vec<_> = rows.iter().filter(|x| x.roll_mode == mode).collect();
            let testable = n
                .iter()
                .filter(|x| x.class == helixreach::plot::ReachClass::Testable)
                .count();
            assert_eq!(r["testable"].as_u64().unwrap() as usize, testable, "{mode}");
            let f = r["fraction_testable"].as_f64().unwrap();
            assert!((0.0..=1.0).contains(&f));
        }
    }

    // Every listed figure exists and is non-trivial; PNGs are listed with their SVG twins.
    let figures: Vec<&str> = json["figures"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect();
    let expect = [
        ("continuum_boundary", "boundary3d"),
        ("continuum_boundary", "section"),
        ("continuum_boundary", "speed_error"),
        ("reachability", "directions"),
        ("dynamics", "error_vs_s"),
        ("trajectory", "trajectory"),
    ];
    for (stage, fig) in expect {
        if stages[stage]["status"] == "done" {
            assert!(
                figures.contains(&format!("{fig}.png").as_str()),
                "missing {fig}.png"
            );
        }
    }
    for f in &figures {
        let p = out.join(f);
        assert!(p.is_file(), "{f} listed but missing");
        if f.ends_with(".png") {
            let (w, h, ink, colours) = png_stats(&p);
            assert!(w >= 800 && h >= 600, "{f}: {w}x{h}");
            assert!(
                ink > 0.03 && colours > 50,
                "{f} looks blank: ink {ink}, {colours} colours"
            );
            let svg = p.with_extension("svg");
            assert!(figures.contains(&svg.file_name().unwrap().to_str().unwrap()));
            let text = std::fs::read_to_string(&svg).unwrap();
            assert!(
                text.contains("<text") && text.len() > 5000,
                "{f}: SVG too small"
            );
            assert!(
                md.contains(&format!("]({f})")),
                "report.md does not embed {f}"
            );
        }
    }
}
