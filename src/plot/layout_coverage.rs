//! Coverage versus the number of clamp placements K: the exact optimum (branch and bound; a
//! hollow marker where the search budget ran out and the value is only a lower bound) and the
//! greedy choice, as a percentage of the direction set, with an optional reference line (e.g.
//! the union of the seed's hand-chosen clamp positions).

use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Coverage at one K.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// K.
    pub k: usize,
    /// Directions covered by greedy.
    pub greedy: usize,
    /// Directions covered by the exact search.
    pub exact: usize,
    /// Whether the exact search finished.
    pub proven: bool,
}

/// Render the curve into `out`; `total` directions, `reference` an optional horizontal line.
pub fn render(points: &[Point], total: usize, reference: Option<usize>, out: &Path) -> Result<()> {
    if points.is_empty() || total == 0 {
        return Err(Error::invalid(
            "coverage points",
            points.len(),
            "need at least one K and a non-empty direction set",
        ));
    }
    super::save(
        &Curve {
            points,
            total,
            reference,
        },
        out,
    )
}

struct Curve<'a> {
    points: &'a [Point],
    total: usize,
    reference: Option<usize>,
}

impl Figure for Curve<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 760)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let pct = |n: usize| 100.0 * n as f64 / self.total as f64;
        let kmax = self.points.iter().map(|p| p.k).max().unwrap_or(1) as f64;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Coverage of {} directions versus placements", self.total),
                (FAMILY, style::TITLE),
            )
            .margin(20)
            .margin_right(40)
            .x_label_area_size(70)
            .y_label_area_size(100)
            .build_cartesian_2d(0.5..kmax + 0.5, 0.0..100.0)?;
        chart
            .configure_mesh()
            .x_desc("placements K")
            .y_desc("directions testable (%)")
            .axis_desc_style((FAMILY, style::AXIS))
            .label_style((FAMILY, style::TICK))
            .x_labels(self.points.len().min(20))
            .x_label_formatter(&|v| format!("{v:.0}"))
            .bold_line_style(style::LIGHT_GREY)
            .light_line_style(TRANSPARENT)
            .draw()?;
        let ex: Vec<(f64, f64)> = self
            .points
            .iter()
            .map(|p| (p.k as f64, pct(p.exact)))
            .collect();
        let gr: Vec<(f64, f64)> = self
            .points
            .iter()
            .map(|p| (p.k as f64, pct(p.greedy)))
            .collect();
        let (c_ex, c_gr) = (style::BLUE, style::VERMILLION);
        chart
            .draw_series(LineSeries::new(ex.clone(), c_ex.stroke_width(3)))?
            .label("exact (branch and bound; open = budget hit)")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], c_ex.stroke_width(3))
            });
        chart.draw_series(self.points.iter().zip(&ex).map(|(p, &xy)| {
            if p.proven {
                Circle::new(xy, 7, c_ex.filled())
            } else {
                Circle::new(xy, 7, c_ex.stroke_width(2))
            }
        }))?;
        chart
            .draw_series(LineSeries::new(gr.clone(), c_gr.stroke_width(2)))?
            .label("greedy")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], c_gr.stroke_width(2))
            });
        chart.draw_series(
            gr.iter()
                .map(|&xy| TriangleMarker::new(xy, 7, c_gr.filled())),
        )?;
        if let Some(r) = self.reference {
            let y = pct(r);
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![(0.5, y), (kmax + 0.5, y)],
                    style::GREY.stroke_width(2),
                )))?
                .label(format!("reference positions, union ({y:.1} %)"))
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 22, y)], style::GREY.stroke_width(2))
                });
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        Ok(())
    }
}
