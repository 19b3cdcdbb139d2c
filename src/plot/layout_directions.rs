//! The direction map coloured by clamp placement: every direction of a layout on the
//! equal-area map of [`crate::plot::direction_map`] (centre κ̂ = 1, +τ̂ right, +ω̂ up), filled
//! in the colour of the placement it is assigned to, grey rings where no placement tests it.
//! The legend gives each placement's share.

use super::direction_map::project;
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::directions::Direction;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Render `points` (direction, placement index 0-based or `None`) with `k` placements.
pub fn render(points: &[(Direction, Option<usize>)], k: usize, out: &Path) -> Result<()> {
    if points.is_empty() {
        return Err(Error::invalid(
            "directions",
            0,
            "need at least one direction",
        ));
    }
    if let Some((_, Some(p))) = points.iter().find(|(_, p)| p.is_some_and(|p| p >= k)) {
        return Err(Error::invalid(
            "placement",
            p + 1,
            format!("exceeds the number of placements {k}"),
        ));
    }
    super::save(&Map { points, k }, out)
}

struct Map<'a> {
    points: &'a [(Direction, Option<usize>)],
    k: usize,
}

impl Figure for Map<'_> {
    fn size(&self) -> (u32, u32) {
        (1100, 1000)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let quarter = self.points.iter().all(|(d, _)| d.tau >= 0.0);
        let x0 = if quarter { -0.05 } else { -1.05 };
        let n = self.points.len();
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("Directions by clamp placement ({n} directions, equal-area, centre κ̂ = 1)"),
                (FAMILY, style::TITLE * 0.8),
            )
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..1.05, -1.05..1.05)?;
        chart
            .configure_mesh()
            .x_desc("τ̂ →")
            .y_desc("ω̂ →")
            .axis_desc_style((FAMILY, style::AXIS))
            .label_style((FAMILY, style::TICK))
            .disable_mesh()
            .draw()?;
        let rim: Vec<(f64, f64)> = (0..=360)
            .map(|i| {
                let t = std::f64::consts::PI * (i as f64 / 180.0);
                (t.cos(), t.sin())
            })
            .filter(|p| !quarter || p.0 >= -crate::math::tol::ON_QUARTER)
            .collect();
        chart.draw_series(std::iter::once(PathElement::new(
            rim,
            style::GREY.stroke_width(2),
        )))?;
        let radius = if n > 3000 {
            3
        } else if n > 500 {
            5
        } else {
            8
        };
        let none: Vec<(f64, f64)> = self
            .points
            .iter()
            .filter(|(_, p)| p.is_none())
            .map(|(d, _)| project(d))
            .collect();
        chart
            .draw_series(
                none.iter()
                    .map(|&xy| Circle::new(xy, radius, style::GREY.stroke_width(2))),
            )?
            .label(format!(
                "no placement ({:.1} %)",
                100.0 * none.len() as f64 / n as f64
            ))
            .legend(|(x, y)| Circle::new((x + 9, y), 7, style::GREY.stroke_width(2)));
        for p in 0..self.k {
            let c = style::series(p);
            let pts: Vec<(f64, f64)> = self
                .points
                .iter()
                .filter(|(_, q)| *q == Some(p))
                .map(|(d, _)| project(d))
                .collect();
            chart
                .draw_series(pts.iter().map(|&xy| Circle::new(xy, radius, c.filled())))?
                .label(format!(
                    "placement {} ({:.1} %)",
                    p + 1,
                    100.0 * pts.len() as f64 / n as f64
                ))
                .legend(move |(x, y)| Circle::new((x + 9, y), 7, c.filled()));
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}
