//! The ω = 0 section of the stability boundary: the curve s*·(κ̂, τ̂) in the κ-τ plane around the
//! stable region (shaded), with the reachable part highlighted — one panel per roll mode of the
//! reachability records.
//!
//! # Which directions form the section
//! A dedicated ω = 0 direction set (|ω̂| ≤ 1e-9, at least three rays) is used as is. Otherwise the
//! directions within a band |ω̂| < w are projected onto the plane ω = 0 (the point s*·S̄ loses its ω
//! component), with w = clamp(40/N, 0.005, 0.15) for N directions: on an equal-area set the band
//! holds about w·N directions (Archimedes: the zone |ω̂| < w covers the fraction w of the
//! half-sphere). The band used is printed on the figure.
//!
//! # Highlighting
//! Each boundary point takes the class of the reachability ray nearest in the angle
//! ψ = atan2(τ̂, κ̂) (within three times the median spacing of the reach rays): the boundary is
//! drawn thick green where testable, sky blue where partial, vermillion where blocked. Each reach
//! ray's reached segment [0, s_reached] is drawn thin in its class colour.

use super::records::{BoundaryRow, ReachClass, ReachRow};
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::directions::Direction;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Tolerance of a dedicated ω = 0 direction set on |ω̂|.
const EXACT: f64 = 1e-9;

/// The directions of the ω = 0 section: the indices into `dirs` and the band half-width used
/// (0 for an exact set).
///
/// ```
/// use helixreach::directions::fibonacci;
/// use helixreach::plot::section::omega_slice;
/// let d = fibonacci(10_000, false).unwrap();
/// let (idx, w) = omega_slice(&d);
/// assert_eq!(w, 0.005);
/// assert!(idx.iter().all(|&i| d[i].omega.abs() < w));
/// // Equal area: about w·N directions fall in the band.
/// assert!((idx.len() as f64 - 50.0).abs() < 10.0, "{}", idx.len());
/// ```
pub fn omega_slice(dirs: &[Direction]) -> (Vec<usize>, f64) {
    let exact: Vec<usize> = (0..dirs.len())
        .filter(|&i| dirs[i].omega.abs() <= EXACT)
        .collect();
    if exact.len() >= 3 {
        return (exact, 0.0);
    }
    let w = (40.0 / dirs.len().max(1) as f64).clamp(0.005, 0.15);
    let band = (0..dirs.len())
        .filter(|&i| dirs[i].omega.abs() < w)
        .collect();
    (band, w)
}

fn psi(d: &Direction) -> f64 {
    d.tau.atan2(d.kappa)
}

/// Render the ω = 0 section of `boundary`, highlighting what `reach` (may be empty) can test.
pub fn render(boundary: &[BoundaryRow], reach: &[ReachRow], out: &Path) -> Result<()> {
    let dirs: Vec<Direction> = boundary.iter().map(|b| b.dir).collect();
    let (idx, band) = omega_slice(&dirs);
    let mut curve: Vec<(f64, f64, f64)> = idx
        .iter()
        .map(|&i| {
            let b = &boundary[i];
            (psi(&b.dir), b.s_star * b.dir.kappa, b.s_star * b.dir.tau)
        })
        .collect();
    curve.sort_by(|a, b| a.0.total_cmp(&b.0));
    let finite = curve.iter().filter(|c| c.1.is_finite()).count();
    if finite < 2 {
        return Err(Error::invalid(
            "boundary",
            format!("{} rows", boundary.len()),
            format!(
                "the ω = 0 section needs at least two directions with |ω̂| < {} and finite s*; \
                 found {finite} (use a direction set in the ω = 0 plane)",
                if band > 0.0 { band } else { EXACT }
            ),
        ));
    }
    let mut modes: Vec<String> = Vec::new();
    for r in reach {
        if !modes.contains(&r.roll_mode) {
            modes.push(r.roll_mode.clone());
        }
    }
    let panels = if modes.is_empty() {
        vec![PanelData {
            mode: None,
            rays: Vec::new(),
            reach_band: 0.0,
        }]
    } else {
        modes
            .iter()
            .map(|m| {
                let rows: Vec<&ReachRow> = reach.iter().filter(|r| &r.roll_mode == m).collect();
                let rd: Vec<Direction> = rows.iter().map(|r| r.dir).collect();
                let (ri, rb) = omega_slice(&rd);
                let mut rays: Vec<Ray> = ri
                    .iter()
                    .map(|&i| Ray {
                        psi: psi(&rows[i].dir),
                        dir: (rows[i].dir.kappa, rows[i].dir.tau),
                        s_reached: rows[i].s_reached,
                        class: rows[i].class,
                    })
                    .collect();
                rays.sort_by(|a, b| a.psi.total_cmp(&b.psi));
                PanelData {
                    mode: Some(m.clone()),
                    rays,
                    reach_band: rb,
                }
            })
            .collect()
    };
    super::save(
        &Section {
            curve,
            band,
            panels,
        },
        out,
    )
}

/// A run of boundary points of one class.
type Piece = (Option<ReachClass>, Vec<(f64, f64)>);

struct Ray {
    psi: f64,
    dir: (f64, f64),
    s_reached: f64,
    class: ReachClass,
}

struct PanelData {
    mode: Option<String>,
    rays: Vec<Ray>,
    reach_band: f64,
}

struct Section {
    /// (ψ, κ, τ) sorted by ψ; κ, τ infinite where s* = ∞.
    curve: Vec<(f64, f64, f64)>,
    band: f64,
    panels: Vec<PanelData>,
}

/// Plot-area height (px); the width follows the data so that κ and τ share one scale.
const PLOT_H: f64 = 680.0;
/// Width of the label areas and margins around a plot area (px).
const PANEL_EXTRA: u32 = 140;
const LEGEND_W: u32 = 400;

fn class_color(c: ReachClass) -> RGBColor {
    match c {
        ReachClass::Testable => style::GREEN,
        ReachClass::Partial => style::SKY_BLUE,
        ReachClass::Blocked => style::VERMILLION,
        ReachClass::Undecided => style::GREY,
    }
}

/// Display window: (κ max, |τ| max, plot width px), equal scale on both axes.
struct Window {
    k_hi: f64,
    t_abs: f64,
    plot_w: f64,
    cap: f64,
}

impl Section {
    fn finite(&self) -> Vec<(f64, f64)> {
        self.curve
            .iter()
            .filter(|c| c.1.is_finite())
            .map(|c| (c.1, c.2))
            .collect()
    }

    fn window(&self) -> Window {
        let finite = self.finite();
        // The whole finite curve, but not more than 3× its median radius (a few near-axis rays
        // with very large s* would otherwise squeeze the section into a corner).
        let mut radii: Vec<f64> = finite.iter().map(|p| p.0.hypot(p.1)).collect();
        radii.sort_by(f64::total_cmp);
        let cap = 3.0 * radii[radii.len() / 2];
        let k_hi = (finite.iter().map(|p| p.0).fold(0.0, f64::max).min(cap) * 1.08)
            .max(super::style::guard::MIN_EXTENT);
        let t_abs = (finite
            .iter()
            .map(|p| p.1.abs())
            .fold(0.0, f64::max)
            .min(cap)
            * 1.08)
            .max(super::style::guard::MIN_EXTENT);
        let plot_w = (PLOT_H * k_hi / (2.0 * t_abs)).clamp(320.0, 900.0);
        let scale = (k_hi / plot_w).max(2.0 * t_abs / PLOT_H);
        Window {
            k_hi: scale * plot_w,
            t_abs: 0.5 * scale * PLOT_H,
            plot_w,
            cap,
        }
    }

    fn panel_w(&self) -> u32 {
        self.window().plot_w as u32 + PANEL_EXTRA
    }

    /// Class of the boundary point at angle ψ, from the nearest reach ray.
    fn class_at(&self, rays: &[Ray], psi: f64) -> Option<ReachClass> {
        if rays.is_empty() {
            return None;
        }
        let mut gaps: Vec<f64> = rays.windows(2).map(|w| w[1].psi - w[0].psi).collect();
        gaps.sort_by(f64::total_cmp);
        let spacing = gaps
            .get(gaps.len() / 2)
            .copied()
            .unwrap_or(0.1)
            .max(super::style::guard::MIN_LAYOUT);
        let nearest = rays
            .iter()
            .min_by(|a, b| (a.psi - psi).abs().total_cmp(&(b.psi - psi).abs()))?;
        ((nearest.psi - psi).abs() <= 3.0 * spacing).then_some(nearest.class)
    }
}

fn band_words(w: f64) -> String {
    format!(
        "rays within {:.1}° of the plane ω = 0, projected",
        w.asin().to_degrees()
    )
}

impl Figure for Section {
    fn size(&self) -> (u32, u32) {
        (
            self.panel_w() * self.panels.len() as u32 + LEGEND_W,
            PLOT_H as u32 + 220,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let finite = self.finite();
        let Window {
            k_hi, t_abs, cap, ..
        } = self.window();
        let root = root.margin(8, 0, 0, 0).titled(
            "ω = 0 section of the stability boundary",
            (FAMILY, style::TITLE),
        )?;
        let (w, _) = root.dim_in_pixel();
        let (maps, legend) = root.split_horizontally(w - LEGEND_W);
        let areas = maps.split_evenly((1, self.panels.len()));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            let caption = match &panel.mode {
                Some(m) if !m.is_empty() => {
                    let n = panel.rays.len().max(1) as f64;
                    let t = panel
                        .rays
                        .iter()
                        .filter(|r| r.class == ReachClass::Testable)
                        .count() as f64;
                    format!("roll mode {m}: {:.0} % testable", 100.0 * t / n)
                }
                Some(_) => "reachability".to_string(),
                None => "boundary only".to_string(),
            };
            let mut chart = ChartBuilder::on(area)
                .caption(caption, (FAMILY, style::AXIS * 0.9))
                .margin(12)
                .margin_right(28)
                .x_label_area_size(70)
                .y_label_area_size(90)
                .build_cartesian_2d(0.0..k_hi, -t_abs..t_abs)?;
            super::draw_axes(&mut chart, "curvature κ", "torsion τ")?;
            let clip = |p: (f64, f64)| (p.0.min(k_hi), p.1.clamp(-t_abs, t_abs));
            // Stable region.
            let mut poly = vec![(0.0, 0.0)];
            poly.extend(finite.iter().map(|p| clip(*p)));
            chart.draw_series([Polygon::new(poly, style::SKY_BLUE.mix(0.18).filled())])?;
            // Reached segments.
            for r in &panel.rays {
                let s = r.s_reached.min(3.0 * cap);
                if s > 0.0 {
                    chart.draw_series(LineSeries::new(
                        [(0.0, 0.0), clip((s * r.dir.0, s * r.dir.1))],
                        class_color(r.class).mix(0.45).stroke_width(2),
                    ))?;
                }
            }
            // Boundary, in pieces of constant class.
            let mut piece: Vec<(f64, f64)> = Vec::new();
            let mut piece_class: Option<Option<ReachClass>> = None;
            let mut pieces: Vec<Piece> = Vec::new();
            for c in &self.curve {
                if !c.1.is_finite() {
                    if piece.len() > 1 {
                        pieces.push((piece_class.flatten(), std::mem::take(&mut piece)));
                    }
                    piece.clear();
                    piece_class = None;
                    continue;
                }
                let cls = self.class_at(&panel.rays, c.0);
                let p = clip((c.1, c.2));
                if piece_class.is_some_and(|pc| pc != cls) {
                    // Close the piece at this point so consecutive pieces join.
                    piece.push(p);
                    pieces.push((piece_class.flatten(), std::mem::take(&mut piece)));
                }
                piece_class = Some(cls);
                piece.push(p);
            }
            if piece.len() > 1 {
                pieces.push((piece_class.flatten(), piece));
            }
            chart.draw_series(LineSeries::new(
                finite.iter().map(|p| clip(*p)),
                style::BLACK.stroke_width(2),
            ))?;
            for (cls, pts) in &pieces {
                if let Some(c) = cls {
                    chart.draw_series(LineSeries::new(
                        pts.iter().copied(),
                        class_color(*c).stroke_width(7),
                    ))?;
                }
            }
            chart.draw_series([Circle::new((0.0, 0.0), 7, style::BLACK.filled())])?;
        }

        // Legend column.
        let font = |s: f64| style::text(s).pos(Pos::new(HPos::Left, VPos::Center));
        let mut y = 90;
        let x = 20;
        legend.draw(&Rectangle::new(
            [(x, y - 10), (x + 32, y + 10)],
            style::SKY_BLUE.mix(0.3).filled(),
        ))?;
        legend.draw(&Text::new(
            "stable (inside the boundary)",
            (x + 44, y),
            font(style::LEGEND),
        ))?;
        y += 38;
        legend.draw(&PathElement::new(
            vec![(x, y), (x + 32, y)],
            style::BLACK.stroke_width(2),
        ))?;
        legend.draw(&Text::new(
            "boundary s*·S",
            (x + 44, y),
            font(style::LEGEND),
        ))?;
        y += 38;
        if self.panels.iter().any(|p| p.mode.is_some()) {
            for (cls, text) in [
                (ReachClass::Testable, "testable (reaches past s*)"),
                (ReachClass::Partial, "partial (stops before s*)"),
                (ReachClass::Blocked, "blocked"),
            ] {
                let c = class_color(cls);
                legend.draw(&PathElement::new(
                    vec![(x, y), (x + 32, y)],
                    c.stroke_width(7),
                ))?;
                legend.draw(&Text::new(text, (x + 44, y), font(style::LEGEND)))?;
                y += 38;
            }
            legend.draw(&PathElement::new(
                vec![(x, y), (x + 32, y)],
                style::GREEN.mix(0.45).stroke_width(2),
            ))?;
            legend.draw(&Text::new(
                "reached part of a ray",
                (x + 44, y),
                font(style::LEGEND),
            ))?;
            y += 38;
        }
        legend.draw(&Circle::new((x + 16, y), 7, style::BLACK.filled()))?;
        legend.draw(&Text::new(
            "straight rod (origin)",
            (x + 44, y),
            font(style::LEGEND),
        ))?;
        y += 60;
        let mut notes = Vec::new();
        if self.band > 0.0 {
            notes.push(format!("boundary: {}", band_words(self.band)));
        }
        for p in &self.panels {
            if let (Some(m), true) = (&p.mode, p.reach_band > 0.0) {
                notes.push(format!("reach ({m}): {}", band_words(p.reach_band)));
            }
        }
        for n in notes {
            // Wrap at about 34 characters.
            let mut line = String::new();
            for word in n.split(' ') {
                if line.chars().count() + word.chars().count() > 34 {
                    legend.draw(&Text::new(line.clone(), (x, y), font(style::LEGEND * 0.85)))?;
                    y += 28;
                    line.clear();
                }
                if !line.is_empty() {
                    line.push(' ');
                }
                line.push_str(word);
            }
            legend.draw(&Text::new(line, (x, y), font(style::LEGEND * 0.85)))?;
            y += 40;
        }
        Ok(())
    }
}
