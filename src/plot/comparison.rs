//! Measured versus simulated boundary, in the style of the seed paper's comparison figure: the
//! simulated boundary points s*·S̄ (grey, a point cloud of the surface) with the measured snap
//! points (filled vermillion) and their mirror images (κ, −τ, −ω) (open vermillion: the
//! boundary is symmetric under the mirror, so a measured point also tests its image), seen
//! along each axis (orthographic views onto the τ-ω, κ-ω and κ-τ planes), and the ω = 0
//! section: the boundary curve of the directions nearest ω̂ = 0 ([`super::section::omega_slice`])
//! with the measured points of |ω̂| below the same band.

use super::records::BoundaryRow;
use super::section::omega_slice;
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::directions::Direction;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Render the comparison of the boundary `boundary` with measured points `(direction,
/// s_measured)`.
pub fn render(boundary: &[BoundaryRow], measured: &[(Direction, f64)], out: &Path) -> Result<()> {
    let pts: Vec<[f64; 3]> = boundary
        .iter()
        .filter(|r| r.s_star.is_finite())
        .map(|r| {
            [
                r.s_star * r.dir.kappa,
                r.s_star * r.dir.tau,
                r.s_star * r.dir.omega,
            ]
        })
        .collect();
    if pts.len() < 3 {
        return Err(Error::invalid(
            "boundary",
            format!("{} rows", boundary.len()),
            "need at least three directions with finite s*",
        ));
    }
    if let Some((d, s)) = measured.iter().find(|(_, s)| !(s.is_finite() && *s > 0.0)) {
        return Err(Error::invalid(
            "s_measured",
            s,
            format!(
                "direction ({}, {}, {}) must have a finite s > 0",
                d.kappa, d.tau, d.omega
            ),
        ));
    }
    let meas: Vec<[f64; 3]> = measured
        .iter()
        .map(|(d, s)| [s * d.kappa, s * d.tau, s * d.omega])
        .collect();
    let dirs: Vec<Direction> = boundary.iter().map(|r| r.dir).collect();
    let (slice, band) = omega_slice(&dirs);
    let mut section: Vec<(f64, f64)> = slice
        .iter()
        .map(|&i| &boundary[i])
        .filter(|r| r.s_star.is_finite())
        .map(|r| (r.s_star * r.dir.kappa, r.s_star * r.dir.tau))
        .collect();
    section.sort_by(|a, b| a.1.atan2(a.0).total_cmp(&b.1.atan2(b.0)));
    let meas_section: Vec<(f64, f64)> = measured
        .iter()
        .filter(|(d, _)| d.omega.abs() <= band.max(0.02))
        .map(|(d, s)| (s * d.kappa, s * d.tau))
        .collect();
    let mut lim = pts
        .iter()
        .chain(&meas)
        .flat_map(|p| p.iter().map(|x| x.abs()))
        .fold(0.0, f64::max);
    // Very large s* near κ = 0 would squash the view: clip the axes at 1.2× the measured range
    // when there are measurements, or at three times the median radius.
    let mut radii: Vec<f64> = pts
        .iter()
        .map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
        .collect();
    radii.sort_by(f64::total_cmp);
    lim = lim.min(3.0 * radii[radii.len() / 2]);
    if let Some(m) = meas
        .iter()
        .flat_map(|p| p.iter().map(|x| x.abs()))
        .reduce(f64::max)
    {
        lim = lim.max(1.2 * m);
    }
    super::save(
        &Comparison {
            pts,
            meas,
            section,
            meas_section,
            band,
            lim: lim.max(super::style::guard::SCALE_FLOOR),
        },
        out,
    )
}

struct Comparison {
    pts: Vec<[f64; 3]>,
    meas: Vec<[f64; 3]>,
    section: Vec<(f64, f64)>,
    meas_section: Vec<(f64, f64)>,
    band: f64,
    lim: f64,
}

impl Figure for Comparison {
    fn size(&self) -> (u32, u32) {
        (1500, 1400)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let root = root.titled(
            "Measured snap points (filled) and mirror images (κ, −τ, −ω) (open) on the simulated boundary",
            (FAMILY, style::TITLE * 0.85),
        )?;
        let panels = root.split_evenly((2, 2));
        let l = self.lim;
        // (panel, axis indices, axis names, ranges)
        let views: [(usize, usize, &str, &str, &str, bool); 3] = [
            (1, 2, "τ", "ω", "view along κ", false),
            (0, 2, "κ", "ω", "view along τ", true),
            (0, 1, "κ", "τ", "view along ω", true),
        ];
        for (k, &(a, b, na, nb, title, kappa_x)) in views.iter().enumerate() {
            let xr = if kappa_x { 0.0..l } else { -l..l };
            let mut chart = ChartBuilder::on(&panels[k])
                .caption(title, (FAMILY, style::AXIS))
                .margin(12)
                .x_label_area_size(50)
                .y_label_area_size(60)
                .build_cartesian_2d(xr, -l..l)?;
            chart
                .configure_mesh()
                .x_desc(na)
                .y_desc(nb)
                .label_style(style::text(style::TICK))
                .axis_desc_style(style::text(style::AXIS))
                .light_line_style(style::LIGHT_GREY)
                .draw()?;
            let inside = |x: f64, y: f64| x.abs() <= l && y.abs() <= l;
            chart.draw_series(
                self.pts
                    .iter()
                    .filter(|p| inside(p[a], p[b]))
                    .map(|p| Circle::new((p[a], p[b]), 2, style::GREY.filled())),
            )?;
            chart.draw_series(self.meas.iter().map(|p| {
                let m = [p[0], -p[1], -p[2]];
                Circle::new((m[a], m[b]), 5, style::VERMILLION.stroke_width(2))
            }))?;
            chart.draw_series(
                self.meas
                    .iter()
                    .map(|p| Circle::new((p[a], p[b]), 5, style::VERMILLION.filled())),
            )?;
        }
        let mut chart = ChartBuilder::on(&panels[3])
            .caption(
                format!("section ω = 0 (|ω̂| ≤ {:.3})", self.band.max(0.02)),
                (FAMILY, style::AXIS),
            )
            .margin(12)
            .x_label_area_size(50)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..l, -l..l)?;
        chart
            .configure_mesh()
            .x_desc("κ")
            .y_desc("τ")
            .label_style(style::text(style::TICK))
            .axis_desc_style(style::text(style::AXIS))
            .light_line_style(style::LIGHT_GREY)
            .draw()?;
        chart
            .draw_series(LineSeries::new(
                self.section
                    .iter()
                    .filter(|p| p.0.abs() <= l && p.1.abs() <= l)
                    .copied(),
                style::BLUE.stroke_width(3),
            ))?
            .label("simulated boundary")
            .legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], style::BLUE.stroke_width(3))
            });
        chart
            .draw_series(
                self.meas_section
                    .iter()
                    .map(|p| Circle::new(*p, 6, style::VERMILLION.filled())),
            )?
            .label("measured")
            .legend(|(x, y)| Circle::new((x + 10, y), 6, style::VERMILLION.filled()));
        chart.draw_series(
            self.meas_section
                .iter()
                .map(|p| Circle::new((p.0, -p.1), 6, style::VERMILLION.stroke_width(2))),
        )?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(style::BLACK)
            .label_font(style::text(style::LEGEND))
            .draw()?;
        Ok(())
    }
}
