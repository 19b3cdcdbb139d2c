//! The detection of one recorded run: the seed's error e versus s, loading and unloading, with
//! the predicted s* (continuum, dotted), the detected snap (dashed, loading colour) and the
//! return (dashed, unloading colour). Input: the per-sample CSV of `helixreach detect --out`
//! ([`crate::records::detect::read_detect_samples`]) and the marks from its JSON summary.

use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use crate::records::detect::SamplePoint;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The vertical marks of the figure.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Marks {
    /// The continuum s* of the direction.
    pub s_predicted: Option<f64>,
    /// The detected snap.
    pub s_snap: Option<f64>,
    /// The detected return.
    pub s_return: Option<f64>,
}

/// Render e versus s of `points` (the samples with an e) with `marks` into `out`.
pub fn render(points: &[SamplePoint], marks: &Marks, out: &Path) -> Result<()> {
    if points.is_empty() {
        return Err(Error::invalid("samples", 0, "no sample with an error e"));
    }
    if let Some(p) = points
        .iter()
        .find(|p| !(p.s.is_finite() && p.e.is_finite()))
    {
        return Err(Error::invalid(
            "sample",
            format!("(s = {}, e = {})", p.s, p.e),
            "non-finite sample",
        ));
    }
    super::save(&Detection { points, marks }, out)
}

struct Detection<'a> {
    points: &'a [SamplePoint],
    marks: &'a Marks,
}

impl Figure for Detection<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 820)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let s_hi = self
            .points
            .iter()
            .map(|p| p.s)
            .chain(self.marks.s_predicted)
            .fold(1e-9, f64::max);
        let e_hi = self.points.iter().map(|p| p.e).fold(1e-9, f64::max) * 1.05;
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Snap detection: marker error along the ray",
                (FAMILY, style::TITLE),
            )
            .margin(20)
            .margin_right(40)
            .x_label_area_size(80)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..s_hi * 1.02, 0.0..e_hi)?;
        super::draw_axes(
            &mut chart,
            "distance along the ray ‖S‖ = s",
            "helix error e",
        )?;
        for (loading, c, name) in [
            (true, style::BLUE, "loading"),
            (false, style::VERMILLION, "unloading"),
        ] {
            let pts: Vec<(f64, f64)> = self
                .points
                .iter()
                .filter(|p| p.loading == loading)
                .map(|p| (p.s, p.e))
                .collect();
            let mark = if loading {
                self.marks.s_snap
            } else {
                self.marks.s_return
            };
            let label = match mark {
                Some(v) => format!(
                    "{name}: {} at s = {v:.4} (dashed)",
                    if loading { "snap" } else { "return" }
                ),
                None => format!("{name}: none detected"),
            };
            chart
                .draw_series(LineSeries::new(pts, c.stroke_width(2)))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x - 4, y), (x + 22, y)], c.stroke_width(3))
                });
            if let Some(v) = mark.filter(|v| v.is_finite()) {
                chart.draw_series(DashedLineSeries::new(
                    [(v, 0.0), (v, e_hi)],
                    10,
                    6,
                    c.stroke_width(2),
                ))?;
            }
        }
        if let Some(v) = self.marks.s_predicted.filter(|v| v.is_finite()) {
            chart
                .draw_series(DottedLineSeries::new([(v, 0.0), (v, e_hi)], 0, 9, |p| {
                    Circle::new(p, 2, style::BLACK.filled())
                }))?
                .label(format!("predicted s* = {v:.4} (dotted)"))
                .legend(|(x, y)| Circle::new((x + 9, y), 3, style::BLACK.filled()));
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}
