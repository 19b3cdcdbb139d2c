//! Figures: every kind renders from synthetic but plausible CSVs, through the `helixreach plot`
//! CLI, into PNG and SVG. Checks are on the output files only: the PNG decodes with the `png`
//! crate to the promised size, is not blank (share of non-white pixels, number of distinct
//! colours), shows the categorical colours the data call for; the SVG carries the axis texts
//! in the embedded font family. Bad input gives errors that name the file, column and value.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::Command;

mod common;
use common::png::Png;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");

/// Okabe–Ito bluish green: the figures' colour for "testable".
const GREEN: [u8; 3] = [0x00, 0x9E, 0x73];
/// Okabe–Ito vermillion: blocked by a joint limit / joint-limit lines.
const VERMILLION: [u8; 3] = [0xD5, 0x5E, 0x00];

impl Png {
    /// Share of non-white pixels in a `px`-wide frame along the image border (clipping check:
    /// a figure that runs off the canvas leaves ink on its border).
    fn border_ink(&self, px: u32) -> f64 {
        let mut n = 0;
        let mut ink = 0;
        for y in 0..self.height {
            for x in 0..self.width {
                if x < px || y < px || x >= self.width - px || y >= self.height - px {
                    n += 1;
                    if self.rgb[(y * self.width + x) as usize] != [255, 255, 255] {
                        ink += 1;
                    }
                }
            }
        }
        ink as f64 / n as f64
    }
}

fn fibonacci(n: usize, quarter: bool) -> Vec<[f64; 3]> {
    helixreach::directions::fibonacci(n, quarter)
        .unwrap()
        .iter()
        .map(|d| [d.kappa, d.tau, d.omega])
        .collect()
}

/// A plausible boundary: s* = 2π on the κ axis, ≈ 8.99 on the ω axis, finite toward τ, as an
/// ellipsoid-like surface; exact τ-axis rays are stable (∞).
fn synthetic_s_star(d: [f64; 3]) -> f64 {
    if d[0] == 0.0 && d[2] == 0.0 {
        return f64::INFINITY;
    }
    let (a, b, c) = (2.0 * PI, 9.0 * PI, 8.9868);
    1.0 / ((d[0] / a).powi(2) + (d[1] / b).powi(2) + (d[2] / c).powi(2)).sqrt()
}

fn boundary_csv(dirs: &[[f64; 3]]) -> String {
    let mut s = String::from(
        "dir_kappa,dir_tau,dir_omega,s_star,kappa,tau,omega,method,resolution,est_error\n",
    );
    for d in dirs {
        let st = synthetic_s_star(*d);
        let p = if st.is_finite() {
            [st * d[0], st * d[1], st * d[2]]
        } else {
            [f64::INFINITY; 3]
        };
        writeln!(
            s,
            "{},{},{},{},{},{},{},continuum,tol=1e-10,{}",
            d[0],
            d[1],
            d[2],
            st,
            p[0],
            p[1],
            p[2],
            1e-10 * st
        )
        .unwrap();
    }
    s
}

/// A plausible reachability pattern on the quarter-sphere for one roll mode: testable near the
/// κ̂ axis, partial around it, blocked toward τ̂ by a cause that depends on the region.
fn reach_csv(dirs: &[[f64; 3]], modes: &[&str]) -> String {
    let mut s = String::from(
        "dir_kappa,dir_tau,dir_omega,s_star,s_reached,class,cause,azimuth,roll_mode,n_waypoints,path_cost,max_joint_step\n",
    );
    for (m, mode) in modes.iter().enumerate() {
        let reach_angle = 0.8 + 0.35 * m as f64; // the motor mode reaches farther
        for d in dirs {
            let st = synthetic_s_star(*d);
            let ang = d[0].clamp(-1.0, 1.0).acos();
            let (class, cause, reached) = if ang < reach_angle {
                ("testable", "none", 1.1 * st)
            } else if ang < reach_angle + 0.3 {
                let cause = if d[2] > 0.0 {
                    "joint_limit"
                } else {
                    "self_collision"
                };
                ("partial", cause, 0.5 * st)
            } else {
                let cause = match ((d[2] * 3.0).floor() as i32).rem_euclid(4) {
                    0 => "no_ik",
                    1 => "joint_limit",
                    2 => "scene_collision",
                    _ => "rod_collision",
                };
                ("blocked", cause, 0.0)
            };
            writeln!(
                s,
                "{},{},{},{st},{reached},{class},{cause},0,{mode},{},{},{}",
                d[0],
                d[1],
                d[2],
                if reached > 0.0 { 400 } else { 0 },
                1.5,
                0.02
            )
            .unwrap();
        }
    }
    s
}

fn series_csv(s_jump: f64, seed: u64) -> String {
    let mut out = String::from("t,s,kappa,tau,omega,error,energy\n");
    let mut x = seed;
    for i in 0..=600 {
        let s = 14.0 * i as f64 / 600.0;
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = ((x >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 2e-3;
        let e = 0.004 * s + 0.6 / (1.0 + (-(s - s_jump) * 8.0).exp()) + noise;
        let k = s / 3f64.sqrt();
        writeln!(
            out,
            "{},{s},{k},{k},{k},{e},{}",
            0.05 * i as f64,
            0.5 * s * s
        )
        .unwrap();
    }
    out
}

fn speed_csv() -> String {
    let mut s = String::from("method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n");
    for (k, tol) in [1e-4, 1e-6, 1e-8, 1e-10].iter().enumerate() {
        writeln!(
            s,
            "continuum,tol={tol:e},{},{},{}",
            4e-6 * (1.0 + k as f64),
            tol * 0.8,
            tol * 0.2
        )
        .unwrap();
    }
    for n in [25, 50, 100, 200] {
        let e = 0.3 / (n * n) as f64;
        writeln!(
            s,
            "der,n={n},{},{},{}",
            2e-5 * (n as f64).powf(1.3),
            e,
            0.4 * e
        )
        .unwrap();
    }
    writeln!(s, "dynamics,n=50 v=0.01,2.5,0.012,0.006").unwrap();
    writeln!(s, "continuum,reference,5e-6,0,0").unwrap();
    s
}

fn trajectory_csv() -> (String, String) {
    let mut s = String::from("t,q0,q1,q2,q3,q4,q5,q6,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz\n");
    for i in 0..=300 {
        let u = i as f64 / 300.0;
        let sv = 9.0 * u;
        let q: Vec<f64> = (0..7)
            .map(|j| 0.3 * j as f64 - 1.0 + (0.8 + 0.1 * j as f64) * (2.0 * u + j as f64).sin())
            .collect();
        let motor = sv / 3f64.sqrt() * 1.33;
        write!(s, "{}", 0.1 * i as f64).unwrap();
        for v in &q {
            write!(s, ",{v}").unwrap();
        }
        writeln!(s, ",{motor},{sv},0.1,0.2,0.3,0.85,-0.15,0.3,1,0,0,0").unwrap();
    }
    let mut lim = String::from("joint,lower,upper\n");
    for j in 0..7 {
        writeln!(
            lim,
            "right_j{j},{},{}",
            -1.6 - 0.2 * j as f64,
            1.7 + 0.1 * j as f64
        )
        .unwrap();
    }
    lim.push_str("motor,-100,100\n");
    (s, lim)
}

struct Fixture {
    _dir: tempfile::TempDir,
    root: PathBuf,
}

impl Fixture {
    fn new() -> Fixture {
        let dir = tempfile::tempdir().unwrap();
        // HELIXREACH_PLOT_KEEP=DIR keeps the figures for inspection (one subfolder per test).
        let root = match std::env::var_os("HELIXREACH_PLOT_KEEP") {
            Some(keep) => {
                let name = std::thread::current()
                    .name()
                    .unwrap_or("t")
                    .replace("::", "_");
                let p = PathBuf::from(keep).join(name);
                std::fs::create_dir_all(&p).unwrap();
                p
            }
            None => dir.path().to_path_buf(),
        };
        let half = fibonacci(1500, false);
        let mut half_with_axis = half.clone();
        half_with_axis.push([0.0, 1.0, 0.0]);
        std::fs::write(root.join("boundary.csv"), boundary_csv(&half_with_axis)).unwrap();
        // A dedicated ω = 0 fan for the section.
        let fan: Vec<[f64; 3]> = (0..=90)
            .map(|i| {
                let a = -PI / 2.0 + PI * i as f64 / 90.0;
                [a.cos().max(0.0), a.sin(), 0.0]
            })
            .collect();
        std::fs::write(root.join("section.csv"), boundary_csv(&fan)).unwrap();
        let quarter = fibonacci(600, true);
        std::fs::write(
            root.join("reach.csv"),
            reach_csv(&quarter, &["fixed", "motor"]),
        )
        .unwrap();
        std::fs::write(
            root.join("reach_fan.csv"),
            reach_csv(&fan, &["fixed", "motor"]),
        )
        .unwrap();
        std::fs::write(
            root.join("marked.csv"),
            "dir_kappa,dir_tau,dir_omega\n1,1,1\n0.594,0.698,0.4\n1,1,-1\n",
        )
        .unwrap();
        std::fs::write(root.join("paper_dir_1.csv"), series_csv(8.4, 1)).unwrap();
        std::fs::write(root.join("paper_dir_2.csv"), series_csv(10.1, 2)).unwrap();
        std::fs::write(root.join("speed.csv"), speed_csv()).unwrap();
        let (t, l) = trajectory_csv();
        std::fs::write(root.join("traj.csv"), t).unwrap();
        std::fs::write(root.join("limits.csv"), l).unwrap();
        Fixture { _dir: dir, root }
    }

    fn p(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    /// Run `helixreach plot` with `args`; returns (success, stderr).
    fn plot(&self, args: &[&str]) -> (bool, String) {
        let out = Command::new(BIN)
            .arg("plot")
            .args(args)
            .current_dir(&self.root)
            .output()
            .unwrap();
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    }

    /// Render `kind` as PNG and SVG; check both; return the PNG and the SVG text.
    fn render_both(&self, kind: &str, inputs: &[&str], svg_texts: &[&str]) -> (Png, String) {
        self.render_named(kind, kind, inputs, svg_texts)
    }

    fn render_named(
        &self,
        kind: &str,
        stem: &str,
        inputs: &[&str],
        svg_texts: &[&str],
    ) -> (Png, String) {
        let mut png_path = None;
        let mut svg = String::new();
        for ext in ["png", "svg"] {
            let out = format!("{stem}.{ext}");
            let mut args = vec![kind];
            args.extend_from_slice(inputs);
            args.extend_from_slice(&["--out", &out]);
            let (ok, err) = self.plot(&args);
            assert!(ok, "plot {kind} -> {ext} failed: {err}");
            if ext == "svg" {
                svg = std::fs::read_to_string(self.p(&out)).unwrap();
            } else {
                png_path = Some(self.p(&out));
            }
        }
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(
            svg.contains("font-family=\"sans-serif\""),
            "{kind}: SVG text must use the sans-serif family"
        );
        for t in svg_texts {
            assert!(svg.contains(t), "{kind}: SVG lacks the text `{t}`");
        }
        // No temp files left behind.
        let leftovers: Vec<_> = std::fs::read_dir(&self.root)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp"))
            .collect();
        assert!(leftovers.is_empty(), "temp files left: {leftovers:?}");
        let png = Png::read(&png_path.unwrap());
        assert!(
            png.width >= 800 && png.height >= 700,
            "{kind}: {}x{}",
            png.width,
            png.height
        );
        let ink = png.non_white_fraction();
        assert!(ink > 0.03, "{kind}: PNG nearly blank ({ink})");
        let colours = png.distinct_colours();
        assert!(colours > 60, "{kind}: only {colours} distinct colours");
        // Nothing drawn on the outermost 3 px (figures keep a margin).
        assert!(
            png.border_ink(3) < 0.02,
            "{kind}: ink on the border ({})",
            png.border_ink(3)
        );
        (png, svg)
    }
}

#[test]
fn boundary3d_renders() {
    let f = Fixture::new();
    let (png, svg) = f.render_both(
        "boundary3d",
        &["--input", "boundary.csv"],
        &[
            "curvature κ",
            "torsion τ",
            "twisting moment ω",
            "stable",
            "s*",
            "1 direction stable up to",
        ],
    );
    // The surface is coloured with viridis: its dark purple end (small s*) and a share of
    // mid-range teal must be present — check a broad hue class rather than exact pixels.
    let viridis_like = png
        .rgb
        .iter()
        .filter(|p| p[2] as i32 > p[0] as i32 + 20 && p[1] > 40 && p[2] > 80)
        .count() as f64
        / png.rgb.len() as f64;
    assert!(
        viridis_like > 0.05,
        "surface colours cover only {viridis_like}"
    );
    assert!(
        svg.matches("<polygon").count() > 500,
        "surface has too few faces"
    );
}

#[test]
fn directions_renders_both_roll_modes_with_classes() {
    let f = Fixture::new();
    let (png, svg) = f.render_both(
        "directions",
        &["--input", "reach.csv", "--input2", "marked.csv"],
        &[
            "roll mode: fixed",
            "roll mode: motor",
            "testable",
            "partial",
            "joint limit",
            "directions (3)",
            "+τ",
            "+ω",
        ],
    );
    assert!(
        png.count(GREEN) > 2000,
        "testable dots missing: {}",
        png.count(GREEN)
    );
    assert!(png.count(VERMILLION) > 100, "joint-limit dots missing");
    // The quarter-sphere is drawn as half-disks: no "−τ" label.
    assert!(!svg.contains("−τ"));
    // Shares printed in the legend match the data (the motor mode reaches farther).
    let reach = helixreach::plot::read_reach(&f.p("reach.csv")).unwrap();
    for mode in ["fixed", "motor"] {
        let rows: Vec<_> = reach.iter().filter(|r| r.roll_mode == mode).collect();
        let t = rows
            .iter()
            .filter(|r| r.class == helixreach::plot::ReachClass::Testable)
            .count() as f64
            / rows.len() as f64;
        let text = format!("{:.1} %", 100.0 * t);
        assert!(
            svg.contains(&text),
            "legend lacks {mode}'s testable share {text}"
        );
    }
}

/// Undecided rays (the search hit its node bound) are their own category: listed in the legend
/// with their share, not drawn as partial rays.
#[test]
fn directions_show_undecided_rays_as_their_own_category() {
    let f = Fixture::new();
    let quarter: Vec<[f64; 3]> = helixreach::directions::fibonacci(200, true)
        .unwrap()
        .iter()
        .map(|d| [d.kappa, d.tau, d.omega])
        .collect();
    let mut csv = reach_csv(&quarter, &["motor"]);
    // Every partial ray becomes undecided (no cause).
    csv = csv
        .lines()
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            if c.len() > 6 && c[5] == "partial" {
                let mut c = c.clone();
                c[5] = "undecided";
                c[6] = "none";
                c.join(",")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let n_undecided = csv.lines().filter(|l| l.contains(",undecided,")).count();
    assert!(n_undecided > 5, "{n_undecided}");
    std::fs::write(f.p("reach_undecided.csv"), csv).unwrap();
    let share = format!("{:.1} %", 100.0 * n_undecided as f64 / quarter.len() as f64);
    f.render_both(
        "directions",
        &["--input", "reach_undecided.csv"],
        &["undecided (search bound)", &share],
    );
}

#[test]
fn section_renders_with_and_without_reach() {
    let f = Fixture::new();
    let (png, _) = f.render_both(
        "section",
        &["--input", "section.csv", "--input2", "reach_fan.csv"],
        &[
            "curvature κ",
            "torsion τ",
            "roll mode fixed",
            "roll mode motor",
            "stable (inside the boundary)",
            "testable (reaches past s*)",
        ],
    );
    assert!(
        png.count(GREEN) > 500,
        "testable boundary part not highlighted"
    );
    // From a Fibonacci half-sphere the section uses a band, and says so.
    let (_, svg) = f.render_named(
        "section",
        "section_band",
        &["--input", "boundary.csv"],
        &["rays within", "boundary only"],
    );
    assert!(!svg.contains("roll mode"));
}

#[test]
fn error_vs_s_renders_series_with_labels() {
    let f = Fixture::new();
    f.render_both(
        "error-vs-s",
        &[
            "--input",
            "paper_dir_1.csv",
            "--input",
            "paper_dir_2.csv",
            "--label",
            "S = [1,1,1]/√3",
            "--label",
            "S = [0.594,0.698,0.4]",
        ],
        &[
            "helix error e",
            "distance along the ray ‖S‖ = s",
            "S = [1,1,1]/√3",
            "S = [0.594,0.698,0.4]",
        ],
    );
    // Without labels, file stems are used.
    f.render_named(
        "error-vs-s",
        "error_one",
        &["--input", "paper_dir_1.csv"],
        &["paper_dir_1"],
    );
}

#[test]
fn speed_error_renders_log_log() {
    let f = Fixture::new();
    f.render_both(
        "speed-error",
        &["--input", "speed.csv"],
        &[
            "time per direction (s)",
            "relative error",
            "continuum",
            "der",
            "dynamics",
            "n=100",
            "drawn at",
        ],
    );
}

#[test]
fn trajectory_renders_joints_motor_and_limits() {
    let f = Fixture::new();
    let (png, _) = f.render_both(
        "trajectory",
        &["--input", "traj.csv", "--input2", "limits.csv"],
        &[
            "q0 (right_j0)",
            "q6 (right_j6)",
            "motor angle",
            "joint limit",
            "distance along the ray s",
            "angle (rad)",
        ],
    );
    assert!(png.count(VERMILLION) > 1000, "limit lines missing");
    let (_, svg) = f.render_named(
        "trajectory",
        "traj_nolimits",
        &["--input", "traj.csv"],
        &["q3"],
    );
    assert!(!svg.contains("joint limit"));
}

#[test]
fn bad_input_gives_clear_errors() {
    let f = Fixture::new();
    // Unknown kind: clap lists the valid ones.
    let (ok, err) = f.plot(&["contour", "--input", "boundary.csv", "--out", "x.png"]);
    assert!(
        !ok && err.contains("boundary3d") && err.contains("speed-error"),
        "{err}"
    );
    // Bad extension.
    let (ok, err) = f.plot(&["boundary3d", "--input", "boundary.csv", "--out", "x.pdf"]);
    assert!(
        !ok && err.contains("x.pdf") && err.contains(".png or .svg"),
        "{err}"
    );
    // Missing file.
    let (ok, err) = f.plot(&["speed-error", "--input", "nope.csv", "--out", "x.png"]);
    assert!(
        !ok && err.contains("nope.csv") && err.contains("not found"),
        "{err}"
    );
    // Missing column: a reach CSV given where a boundary CSV is expected still works (it has
    // the columns), but a series CSV does not.
    let (ok, err) = f.plot(&["boundary3d", "--input", "paper_dir_1.csv", "--out", "x.png"]);
    assert!(
        !ok && err.contains("paper_dir_1.csv") && err.contains("missing column `dir_kappa`"),
        "{err}"
    );
    // A bad value names the line and column.
    std::fs::write(
        f.p("bad.csv"),
        "method,resolution,time_per_direction_s,max_rel_err,median_rel_err\nder,n=5,-1,0.1,0.1\n",
    )
    .unwrap();
    let (ok, err) = f.plot(&["speed-error", "--input", "bad.csv", "--out", "x.png"]);
    assert!(
        !ok && err.contains("bad.csv:2") && err.contains("time_per_direction_s"),
        "{err}"
    );
    // Too few section directions.
    std::fs::write(
        f.p("tiny.csv"),
        "dir_kappa,dir_tau,dir_omega,s_star\n1,0,0.5,6\n",
    )
    .unwrap();
    let (ok, err) = f.plot(&["section", "--input", "tiny.csv", "--out", "x.svg"]);
    assert!(!ok && err.contains("ω = 0 section"), "{err}");
    assert!(
        !f.p("x.png").exists() && !f.p("x.svg").exists(),
        "no figure on error"
    );
}

/// The heat map's legend names the reach bound only when some of its circle lies inside the
/// plotted window (the committed seed heat map listed a bound drawn nowhere).
#[test]
fn heatmap_legend_names_the_reach_bound_only_when_visible() {
    use helixreach::plot::layout_heatmap::{render, Cell, Heatmap};
    let tmp = tempfile::tempdir().expect("tempdir");
    let cells: Vec<Cell> = (0..4)
        .flat_map(|i| {
            (0..4).map(move |j| Cell {
                x: 0.7 + 0.05 * i as f64,
                y: -0.2 + 0.05 * j as f64,
                fraction: (i + j) as f64 / 6.0,
            })
        })
        .collect();
    let mut h = Heatmap {
        cells,
        chosen: vec![(0.75, -0.1)],
        references: vec![],
        base: (0.0, 0.0),
        reach_radius: 5.0,
        total: 10,
    };
    let label = "reach bound at the clamp height";
    let far = tmp.path().join("far.svg");
    render(&h, &far).expect("render");
    let text = std::fs::read_to_string(&far).expect("svg");
    assert!(
        !text.contains(label),
        "bound 5 m away is listed in the legend"
    );
    // A radius of 0.8 m crosses the candidate block (x 0.7–0.85 m): visible, listed.
    h.reach_radius = 0.8;
    let near = tmp.path().join("near.svg");
    render(&h, &near).expect("render");
    let text = std::fs::read_to_string(&near).expect("svg");
    assert!(
        text.contains(label),
        "visible bound missing from the legend"
    );
}
