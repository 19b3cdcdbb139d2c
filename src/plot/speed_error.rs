//! Speed versus error of every boundary method (log-log): one colour per method, the maximum
//! relative error of s* as a filled marker joined across resolutions, the median as a hollow
//! marker of the same colour, each point labelled with its resolution.
//!
//! A relative error of exactly 0 (a method compared with itself) cannot sit on a log axis; it is
//! drawn at the bottom of the axis and the figure says so.

use super::records::SpeedErrorRow;
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Render the speed-versus-error figure of `rows` into `out` (`.png` or `.svg`).
pub fn render(rows: &[SpeedErrorRow], out: &Path) -> Result<()> {
    if rows.is_empty() {
        return Err(Error::invalid(
            "speed-error rows",
            0,
            "need at least one method row",
        ));
    }
    for r in rows {
        if !(r.time_per_direction_s.is_finite() && r.time_per_direction_s > 0.0) {
            return Err(Error::invalid(
                "time_per_direction_s",
                r.time_per_direction_s,
                format!("must be finite and > 0 ({} {})", r.method, r.resolution),
            ));
        }
        for (name, v) in [
            ("max_rel_err", r.max_rel_err),
            ("median_rel_err", r.median_rel_err),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::invalid(
                    name,
                    v,
                    format!("must be finite and >= 0 ({} {})", r.method, r.resolution),
                ));
            }
        }
    }
    super::save(&SpeedError { rows }, out)
}

struct SpeedError<'a> {
    rows: &'a [SpeedErrorRow],
}

fn log_range(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in vals {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    let (lo, hi) = (lo.log10().floor(), hi.log10().ceil());
    let hi = if hi <= lo { lo + 1.0 } else { hi };
    (10f64.powf(lo), 10f64.powf(hi))
}

impl Figure for SpeedError<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 860)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let positive = self
            .rows
            .iter()
            .flat_map(|r| [r.max_rel_err, r.median_rel_err])
            .filter(|v| *v > 0.0);
        let min_pos = positive.clone().fold(f64::INFINITY, f64::min);
        let floor = if min_pos.is_finite() {
            10f64.powf(min_pos.log10().floor() - 1.0)
        } else {
            // No positive error to scale the log axis to: a display default, not a tolerance.
            1e-16
        };
        let any_zero = self
            .rows
            .iter()
            .any(|r| r.max_rel_err == 0.0 || r.median_rel_err == 0.0);
        let clampz = |v: f64| if v > 0.0 { v } else { floor };
        let (x0, x1) = log_range(self.rows.iter().map(|r| r.time_per_direction_s));
        let (y0, y1) = log_range(
            self.rows
                .iter()
                .flat_map(|r| [clampz(r.max_rel_err), clampz(r.median_rel_err)]),
        );

        let mut chart = ChartBuilder::on(root)
            .caption(
                "Stability boundary methods: speed versus error",
                (FAMILY, style::TITLE),
            )
            .margin(20)
            .margin_right(40)
            .x_label_area_size(80)
            .y_label_area_size(120)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("time per direction (s)")
            .y_desc("relative error of s* vs. continuum reference")
            .axis_desc_style((FAMILY, style::AXIS))
            .label_style((FAMILY, style::TICK))
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .bold_line_style(style::LIGHT_GREY)
            .light_line_style(TRANSPARENT)
            .draw()?;

        let mut methods: Vec<&str> = Vec::new();
        for r in self.rows {
            if !methods.contains(&r.method.as_str()) {
                methods.push(&r.method);
            }
        }
        let label_font = (FAMILY, style::LEGEND * 0.85).into_font();
        for (i, m) in methods.iter().enumerate() {
            let c = style::series(i);
            // Rows of a method are joined in file order (a resolution sweep); rows with zero
            // error (references) stand alone.
            let pts: Vec<&SpeedErrorRow> = self.rows.iter().filter(|r| r.method == *m).collect();
            chart
                .draw_series(LineSeries::new(
                    pts.iter()
                        .filter(|r| r.max_rel_err > 0.0)
                        .map(|r| (r.time_per_direction_s, r.max_rel_err)),
                    c.stroke_width(3),
                ))?
                .label(format!("{m}: max (filled), median (open)"))
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(-4, 0), (22, 0)], c.stroke_width(3))
                        + Circle::new((9, 0), 6, c.filled())
                });
            chart.draw_series(pts.iter().map(|r| {
                Circle::new(
                    (r.time_per_direction_s, clampz(r.max_rel_err)),
                    7,
                    c.filled(),
                )
            }))?;
            chart.draw_series(pts.iter().map(|r| {
                Circle::new(
                    (r.time_per_direction_s, clampz(r.median_rel_err)),
                    7,
                    c.stroke_width(2),
                )
            }))?;
            chart.draw_series(pts.iter().map(|r| {
                EmptyElement::at((r.time_per_direction_s, clampz(r.max_rel_err)))
                    + Text::new(r.resolution.clone(), (10, -24), label_font.clone())
            }))?;
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        if any_zero {
            let (_, h) = root.dim_in_pixel();
            root.draw(&Text::new(
                format!("errors of exactly 0 are drawn at {floor:.0e}"),
                (20, h as i32 - 30),
                (FAMILY, style::LEGEND * 0.85).into_font(),
            ))?;
        }
        Ok(())
    }
}
