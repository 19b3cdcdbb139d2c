//! Coverage heat map of candidate clamp positions over the bench plane (x-y of the robot base
//! frame, metres): each grid position is a square coloured (viridis) by the fraction of the
//! directions testable from it (the best over the heights and tilts at that x-y). The robot's
//! base (the first joint axis) is a grey disc, the dashed circle is the conservative reach bound
//! at the clamp height (nothing outside it can hold the straight rod), the chosen placements are
//! numbered black rings and reference positions (e.g. the seed's hand-chosen clamps) red crosses.
//! Axes have equal scale.

use super::style::{self, guard, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One grid position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// x (m, base frame).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Fraction of the directions testable, in [0, 1].
    pub fraction: f64,
}

/// The data of the heat map.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    /// Grid positions (several per x-y are merged by their maximum).
    pub cells: Vec<Cell>,
    /// Chosen placements (x, y), in order.
    pub chosen: Vec<(f64, f64)>,
    /// Reference positions (x, y).
    pub references: Vec<(f64, f64)>,
    /// The robot base (x, y).
    pub base: (f64, f64),
    /// Radius of the reach bound at the clamp height (m; 0 = not drawn).
    pub reach_radius: f64,
    /// Number of directions.
    pub total: usize,
}

/// Render the heat map into `out` (`.png` or `.svg`).
pub fn render(h: &Heatmap, out: &Path) -> Result<()> {
    if h.cells.is_empty() {
        return Err(Error::invalid(
            "cells",
            0,
            "need at least one candidate position",
        ));
    }
    for c in &h.cells {
        if !(c.x.is_finite() && c.y.is_finite() && (0.0..=1.0).contains(&c.fraction)) {
            return Err(Error::invalid(
                "cell",
                format!("({}, {}, {})", c.x, c.y, c.fraction),
                "needs finite x, y and a fraction in [0, 1]",
            ));
        }
    }
    // Merge by x-y (max), find the grid step.
    let mut merged: Vec<Cell> = Vec::new();
    for c in &h.cells {
        match merged
            .iter_mut()
            .find(|m| (m.x - c.x).abs() < guard::SAME && (m.y - c.y).abs() < guard::SAME)
        {
            Some(m) => m.fraction = m.fraction.max(c.fraction),
            None => merged.push(*c),
        }
    }
    let mut step = f64::INFINITY;
    for a in &merged {
        for b in &merged {
            for d in [(a.x - b.x).abs(), (a.y - b.y).abs()] {
                if d > guard::SAME {
                    step = step.min(d);
                }
            }
        }
    }
    if !step.is_finite() {
        step = 0.05;
    }
    super::save(&Map { h, merged, step }, out)
}

struct Map<'a> {
    h: &'a Heatmap,
    merged: Vec<Cell>,
    step: f64,
}

impl Map<'_> {
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pad = 0.6 * self.step;
        let mut xs = vec![self.h.base.0 - 0.15, self.h.base.0 + 0.15];
        let mut ys = vec![self.h.base.1 - 0.15, self.h.base.1 + 0.15];
        for c in &self.merged {
            xs.extend([c.x - pad, c.x + pad]);
            ys.extend([c.y - pad, c.y + pad]);
        }
        for p in self.h.chosen.iter().chain(&self.h.references) {
            xs.extend([p.0 - pad, p.0 + pad]);
            ys.extend([p.1 - pad, p.1 + pad]);
        }
        let lo = |v: &[f64]| v.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = |v: &[f64]| v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        ((lo(&xs), hi(&xs)), (lo(&ys), hi(&ys)))
    }
}

impl Figure for Map<'_> {
    fn size(&self) -> (u32, u32) {
        let ((x0, x1), (y0, y1)) = self.ranges();
        // Plot x (base frame) to the right, y up; keep equal scale within a sane size.
        let w = 1200.0;
        let h = (w - 260.0) * (y1 - y0) / (x1 - x0) + 288.0;
        (w as u32, h.clamp(500.0, 1600.0) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let ((x0, x1), (y0, y1)) = self.ranges();
        let best = self.merged.iter().map(|c| c.fraction).fold(0.0, f64::max);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Clamp placements: fraction of {} directions testable (best {:.1} %)",
                    self.h.total,
                    100.0 * best
                ),
                (FAMILY, style::TITLE * 0.85),
            )
            .margin(20)
            .margin_right(40)
            // Room for the footnote under the x-axis title.
            .margin_bottom(48)
            .x_label_area_size(70)
            .y_label_area_size(100)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc("x (m, robot base frame)")
            .y_desc("y (m)")
            .axis_desc_style((FAMILY, style::AXIS))
            .label_style((FAMILY, style::TICK))
            .x_label_formatter(&|v| format!("{v:.2}"))
            .y_label_formatter(&|v| format!("{v:.2}"))
            .bold_line_style(style::LIGHT_GREY)
            .light_line_style(TRANSPARENT)
            .draw()?;
        let half = 0.48 * self.step;
        chart.draw_series(self.merged.iter().map(|c| {
            let col = if c.fraction > 0.0 {
                style::viridis(c.fraction / best.max(guard::SPAN_FLOOR))
            } else {
                style::LIGHT_GREY
            };
            Rectangle::new(
                [(c.x - half, c.y - half), (c.x + half, c.y + half)],
                col.filled(),
            )
        }))?;
        // Base and reach bound.
        let (bx, by) = self.h.base;
        let circle = |r: f64| -> Vec<(f64, f64)> {
            (0..=180)
                .map(|i| {
                    let t = 2.0 * std::f64::consts::PI * i as f64 / 180.0;
                    (bx + r * t.cos(), by + r * t.sin())
                })
                .collect()
        };
        chart
            .draw_series(std::iter::once(Polygon::new(
                circle(0.1),
                style::GREY.filled(),
            )))?
            .label("robot base (first joint axis)")
            .legend(|(x, y)| Circle::new((x + 9, y), 8, style::GREY.filled()));
        // Only dashes inside the plotted window (plotters would clip them onto the frame); the
        // legend names the bound only when some of it is visible.
        let dashes: Vec<Vec<(f64, f64)>> = if self.h.reach_radius > 0.0 {
            circle(self.h.reach_radius)
                .chunks(2)
                .filter(|p| {
                    p.iter()
                        .all(|&(x, y)| x >= x0 && x <= x1 && y >= y0 && y <= y1)
                })
                .map(<[(f64, f64)]>::to_vec)
                .collect()
        } else {
            Vec::new()
        };
        if !dashes.is_empty() {
            chart
                .draw_series(
                    dashes
                        .into_iter()
                        .map(|p| PathElement::new(p, style::BLACK.stroke_width(2))),
                )?
                .label("reach bound at the clamp height")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], style::BLACK));
        }
        if !self.h.references.is_empty() {
            chart
                .draw_series(
                    self.h
                        .references
                        .iter()
                        .map(|&(x, y)| Cross::new((x, y), 9, style::VERMILLION.stroke_width(3))),
                )?
                .label("reference clamp positions")
                .legend(|(x, y)| Cross::new((x + 9, y), 7, style::VERMILLION.stroke_width(3)));
        }
        let font = (FAMILY, style::LEGEND).into_font();
        for (i, &(x, y)) in self.h.chosen.iter().enumerate() {
            chart.draw_series(std::iter::once(
                EmptyElement::at((x, y))
                    + Circle::new((0, 0), 14, style::BLACK.stroke_width(3))
                    + Text::new(format!("{}", i + 1), (13, -32), font.clone()),
            ))?;
        }
        super::draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        let (_, hpx) = root.dim_in_pixel();
        root.draw(&Text::new(
            format!(
                "squares: viridis from 0 (dark) to the best {:.1} % (yellow), grey = none; rings: chosen placements in order",
                100.0 * best
            ),
            (20, hpx as i32 - 28),
            (FAMILY, style::LEGEND * 0.8).into_font(),
        ))?;
        Ok(())
    }
}
