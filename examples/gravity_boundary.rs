//! DER statics with gravity on the seed paper's three directions: s* versus the
//! gravito-bending ratio `L_gb/L`, for the rod held up (gravity along −d3) and horizontal (the
//! clamp tangent d3 horizontal, d1 up, azimuth α = 0: the helix first curls upward), with the
//! gravity-free s* as the limit and slow dynamic runs marked.
//!
//! For each direction and clamp the nondimensional weight `w = ½(L/L_gb)³` is applied in the
//! helix frame ([`gravity_in_helix_frame`]) and s* found by [`critical_s_gravity`] at n edges
//! (default 40). The 1 % ratio is the largest sampled `L_gb/L` at which |s*/s*₀ − 1| ≥ 1 %,
//! interpolated log-linearly with its neighbour above (the horizontal rod taken at the worst of
//! α = 0, π/2, π, 3π/2). Dynamic points: `simulate_ray` at ray speed 0.005/s, Δt = 0.5 s, the
//! same n, paper-sim rod, read at the helix error's threshold crossing (`Detection::s_cross`).
//!
//! Writes `gravity_boundary.csv` and `gravity_boundary.png` / `.svg` into `--out DIR`
//! (default `figures/`) and prints the 1 % ratios as Markdown.
//!
//! Run: `cargo run --release --features plots --example gravity_boundary -- [--n-edges N]
//! [--out DIR]`

use helixreach::boundary::der::{
    critical_s, critical_s_gravity, gravity_in_helix_frame, DerBoundaryParams,
};
use helixreach::directions::Direction;
use helixreach::math::{Mat3, Real, Vec3};
use helixreach::rod::dynamics::{simulate_ray, PhysicalRod, SimParams};
use plotters::prelude::*;
use std::path::PathBuf;

/// The sampled `L_gb/L`.
const RATIOS: [Real; 14] = [
    0.4, 0.5, 0.6, 0.7, 0.8, 1.0, 1.2, 1.4, 1.7, 2.0, 2.5, 3.0, 5.0, 10.0,
];
/// The seed paper's three directions (Fig. 4(b, c), Fig. 5).
const DIRS: [[Real; 3]; 3] = [[0.594, 0.698, 0.4], [1.0, 1.0, -1.0], [1.0, 1.0, 1.0]];
/// Dynamic runs: (direction index, clamp index, L_gb/L).
const DYN: [(usize, usize, Real); 3] = [(1, 0, 1.0), (1, 0, 0.6), (0, 1, 1.0)];

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1).cloned())
    };
    let n: usize = arg("--n-edges").map_or(Ok(40), |x| x.parse())?;
    let out = PathBuf::from(arg("--out").unwrap_or_else(|| "figures".into()));
    let rod = PhysicalRod::paper_sim();
    let p = DerBoundaryParams {
        n_edges: n,
        nu: rod.nu,
        tol_rel: 1e-8,
        ..Default::default()
    };
    let clamps = [
        ("rod up", Mat3::identity()),
        (
            "rod horizontal",
            Mat3::from_columns(&[Vec3::z(), -Vec3::y(), Vec3::x()]),
        ),
    ];
    let azimuths = [
        0.0,
        0.5 * std::f64::consts::PI,
        std::f64::consts::PI,
        1.5 * std::f64::consts::PI,
    ];
    let t0 = std::time::Instant::now();
    let mut csv = String::from(
        "dir_kappa,dir_tau,dir_omega,clamp,azimuth,lgb_over_l,s_star,s_star_free,rel_shift\n",
    );
    // curves[d][c] = (ratio, s*/s*0) at α = 0; worst[d][c][k] = max over α of |shift|.
    let mut curves = vec![vec![Vec::new(); 2]; 3];
    let mut worst = vec![vec![vec![0.0; RATIOS.len()]; 2]; 3];
    let mut free = [0.0; 3];
    for (di, d) in DIRS.iter().enumerate() {
        let dir = Direction::new(d[0], d[1], d[2])?;
        let s0 = critical_s(&dir, &p)?.s_star;
        free[di] = s0;
        for (ci, (cname, clamp)) in clamps.iter().enumerate() {
            let alphas: &[Real] = if ci == 0 { &azimuths[..1] } else { &azimuths };
            for &alpha in alphas {
                for (k, &ratio) in RATIOS.iter().enumerate() {
                    let g = rod.gravity_for_ratio(ratio)?;
                    let w = gravity_in_helix_frame(&rod, clamp, alpha, &Vec3::new(0.0, 0.0, -g))?;
                    // A refused point (e.g. s* far beyond the gravity-free one, too coarse for
                    // n) is a NaN row, reported.
                    let s = critical_s_gravity(&dir, &p, w).map_or_else(
                        |err| {
                            eprintln!("{d:?} {cname} α = {alpha} L_gb/L = {ratio}: {err}");
                            Real::NAN
                        },
                        |r| r.s_star,
                    );
                    let rel = s / s0 - 1.0;
                    csv += &format!(
                        "{},{},{},{cname},{alpha},{ratio},{s},{s0},{rel}\n",
                        dir.kappa, dir.tau, dir.omega
                    );
                    if alpha == 0.0 && s.is_finite() {
                        curves[di][ci].push((ratio, s / s0));
                    }
                    if rel.is_finite() {
                        worst[di][ci][k] = Real::max(worst[di][ci][k], rel.abs());
                    }
                }
            }
        }
    }
    let statics_s = t0.elapsed().as_secs_f64();
    let mut dyn_points = Vec::new();
    for &(di, ci, ratio) in &DYN {
        let d = DIRS[di];
        let dir = Direction::new(d[0], d[1], d[2])?;
        let g = rod.gravity_for_ratio(ratio)?;
        let gh = gravity_in_helix_frame(&rod, &clamps[ci].1, 0.0, &Vec3::new(0.0, 0.0, -g))?;
        // The dynamics takes gravity in m/s² in the helix frame.
        let scale = rod.linear_density() * rod.length.powi(3) / rod.bending_stiffness();
        let sp = SimParams {
            n_edges: n,
            speed: 0.005,
            dt: 0.5,
            record_ds: 0.005,
            gravity: gh / scale,
            ..Default::default()
        };
        let sim = simulate_ray(&dir, &sp, &mut |_| {})?;
        let snap = sim.detection.map_or(Real::NAN, |x| x.s_cross);
        eprintln!(
            "dynamics {d:?} {} L_gb/L = {ratio}: snap {snap:.4} (s*0 = {:.4})",
            clamps[ci].0, free[di]
        );
        dyn_points.push((di, ci, ratio, snap / free[di]));
    }
    println!("| direction | gravity-free s* (n = {n}) | 1 % ratio, rod up | 1 % ratio, rod horizontal (worst α) |");
    println!("|---|---|---|---|");
    for (di, d) in DIRS.iter().enumerate() {
        let r: Vec<String> = (0..2).map(|ci| one_percent(&worst[di][ci])).collect();
        println!(
            "| ({}, {}, {}) | {:.4} | {} | {} |",
            d[0], d[1], d[2], free[di], r[0], r[1]
        );
    }
    eprintln!(
        "statics: {statics_s:.1} s wall for {} solves",
        3 * RATIOS.len() * 5
    );
    std::fs::create_dir_all(&out)?;
    helixreach::io::write_atomic(&out.join("gravity_boundary.csv"), csv.as_bytes())?;
    helixreach::plot::style::init_fonts();
    let png = out.join("gravity_boundary.png");
    draw(
        BitMapBackend::new(&png, (1300, 820)).into_drawing_area(),
        &curves,
        &dyn_points,
        n,
    )?;
    let svg = out.join("gravity_boundary.svg");
    draw(
        SVGBackend::new(&svg, (1300, 820)).into_drawing_area(),
        &curves,
        &dyn_points,
        n,
    )?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

/// The largest sampled ratio with a shift ≥ 1 %, interpolated log-linearly towards the next one.
fn one_percent(shift: &[Real]) -> String {
    let Some(k) = (0..RATIOS.len()).rev().find(|&k| shift[k] >= 0.01) else {
        return format!("< {}", RATIOS[0]);
    };
    if k + 1 == RATIOS.len() {
        return format!("> {}", RATIOS[k]);
    }
    let (a, b) = (shift[k].ln(), shift[k + 1].ln());
    let t = (a - 0.01f64.ln()) / (a - b);
    let r = (RATIOS[k].ln() + t * (RATIOS[k + 1].ln() - RATIOS[k].ln())).exp();
    format!("{r:.2}")
}

type Curves = Vec<Vec<Vec<(Real, Real)>>>;

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    curves: &Curves,
    dyn_points: &[(usize, usize, Real, Real)],
    n: usize,
) -> anyhow::Result<()> {
    use helixreach::plot::style::{series, text, AXIS, LEGEND, TICK, TITLE};
    let e = |e: &dyn std::fmt::Display| anyhow::anyhow!("{e}");
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let ys = curves
        .iter()
        .flatten()
        .flatten()
        .map(|p| p.1)
        .chain(dyn_points.iter().map(|p| p.3))
        .filter(|y| y.is_finite());
    let (lo, hi) = ys.fold((1.0f64, 1.0f64), |(a, b), y| (a.min(y), b.max(y)));
    // Off-scale points (s* jumping to the next loss of stability) are in the CSV only.
    let (lo, hi) = (lo.max(0.85) - 0.01, hi.min(1.03) + 0.09);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("DER statics with gravity on the seed's directions (n = {n}; off-scale points in the CSV)"),
            text(TITLE),
        )
        .margin(20)
        .x_label_area_size(70)
        .y_label_area_size(100)
        .build_cartesian_2d((0.35f64..12.0f64).log_scale(), lo..hi)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .x_desc("L_gb / L (log scale)")
        .x_label_formatter(&|x| format!("{x:.1}"))
        .x_labels(8)
        .y_desc("s* / s* without gravity")
        .label_style(text(TICK))
        .axis_desc_style(text(AXIS))
        .draw()
        .map_err(|x| e(&x))?;
    chart
        .draw_series(LineSeries::new(
            [(0.35, 1.0), (12.0, 1.0)],
            BLACK.stroke_width(2),
        ))
        .map_err(|x| e(&x))?
        .label("gravity-free limit")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 30, y)], BLACK.stroke_width(2)));
    for (di, d) in DIRS.iter().enumerate() {
        for (ci, cname) in ["up", "horizontal"].iter().enumerate() {
            let c = series(di);
            let pts: Vec<(Real, Real)> = curves[di][ci]
                .iter()
                .copied()
                .filter(|p| p.1 > lo && p.1 < hi)
                .collect();
            let style = c.stroke_width(if ci == 0 { 3 } else { 1 });
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), style))
                .map_err(|x| e(&x))?
                .label(format!("({}, {}, {}), rod {cname}", d[0], d[1], d[2]))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 30, y)], style));
            if ci == 0 {
                chart
                    .draw_series(pts.iter().map(|p| Circle::new(*p, 5, c.filled())))
                    .map_err(|x| e(&x))?;
            } else {
                chart
                    .draw_series(pts.iter().map(|p| TriangleMarker::new(*p, 6, c.filled())))
                    .map_err(|x| e(&x))?;
            }
        }
    }
    chart
        .draw_series(
            dyn_points
                .iter()
                .filter(|p| p.3.is_finite())
                .map(|p| Cross::new((p.2, p.3), 12, BLACK.stroke_width(3))),
        )
        .map_err(|x| e(&x))?
        .label("slow dynamic run (snap)")
        .legend(|(x, y)| Cross::new((x + 15, y), 8, BLACK.stroke_width(3)));
    chart
        .configure_series_labels()
        .label_font(text(LEGEND))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|x| e(&x))?;
    root.present().map_err(|x| e(&x))?;
    Ok(())
}
