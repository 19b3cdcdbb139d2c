//! Helix error e versus the distance along the ray ‖S‖ = s, from DER dynamics series — the seed
//! paper's Fig. 4(b, c). The instability shows as a jump of e; a series' detected instability
//! distance s_dyn (when known) is drawn as a dashed vertical line in the series' colour, and a
//! reference s* (e.g. the continuum boundary) as a dotted one.

use super::records::Series;
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Render e versus s for every series in `series` (one curve each, legend from the labels).
pub fn render(series: &[Series], out: &Path) -> Result<()> {
    if series.is_empty() {
        return Err(Error::invalid("series", 0, "need at least one series"));
    }
    for s in series {
        if s.rows.is_empty() {
            return Err(Error::invalid(
                "series",
                &s.label,
                "the series has no samples",
            ));
        }
        if let Some(r) = s
            .rows
            .iter()
            .find(|r| !(r.s.is_finite() && r.error.is_finite()))
        {
            return Err(Error::invalid(
                "series sample",
                format!("(s = {}, e = {})", r.s, r.error),
                format!("non-finite sample in series `{}`", s.label),
            ));
        }
    }
    super::save(&ErrorVsS { series }, out)
}

struct ErrorVsS<'a> {
    series: &'a [Series],
}

impl Figure for ErrorVsS<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 820)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let all = || self.series.iter().flat_map(|s| s.rows.iter());
        let s_lo = all().map(|r| r.s).fold(f64::INFINITY, f64::min).min(0.0);
        let mut s_hi = all().map(|r| r.s).fold(f64::NEG_INFINITY, f64::max);
        let mut e_hi = all().map(|r| r.error).fold(0.0, f64::max);
        let e_lo = all().map(|r| r.error).fold(0.0, f64::min);
        if s_hi.partial_cmp(&s_lo) != Some(std::cmp::Ordering::Greater) {
            s_hi = s_lo + 1.0;
        }
        if e_hi.partial_cmp(&e_lo) != Some(std::cmp::Ordering::Greater) {
            e_hi = e_lo + 1.0;
        }
        let e_hi = e_hi + 0.05 * (e_hi - e_lo);

        let mut chart = ChartBuilder::on(root)
            .caption(
                "Helix error along the ray (DER dynamics)",
                (FAMILY, style::TITLE),
            )
            .margin(20)
            .margin_right(40)
            .x_label_area_size(80)
            .y_label_area_size(110)
            .build_cartesian_2d(s_lo..s_hi, e_lo..e_hi)?;
        super::draw_axes(
            &mut chart,
            "distance along the ray ‖S‖ = s",
            "helix error e",
        )?;

        for (i, s) in self.series.iter().enumerate() {
            let c = style::series(i);
            let mut label = s.label.clone();
            if let Some(v) = s.s_detected {
                label += &format!(": s_dyn = {v:.3} (dashed)");
            }
            if let Some(v) = s.s_reference {
                label += &format!(", s* = {v:.3} (dotted)");
            }
            chart
                .draw_series(LineSeries::new(
                    s.rows.iter().map(|r| (r.s, r.error)),
                    c.stroke_width(3),
                ))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x - 4, y), (x + 22, y)], c.stroke_width(3))
                });
            if let Some(v) = s.s_reference.filter(|v| v.is_finite()) {
                chart.draw_series(DottedLineSeries::new(
                    [(v, e_lo), (v, e_hi)],
                    0,
                    9,
                    move |p| Circle::new(p, 2, c.filled()),
                ))?;
            }
            if let Some(v) = s.s_detected.filter(|v| v.is_finite()) {
                chart.draw_series(DashedLineSeries::new(
                    [(v, e_lo), (v, e_hi)],
                    10,
                    6,
                    c.stroke_width(2),
                ))?;
            }
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}
