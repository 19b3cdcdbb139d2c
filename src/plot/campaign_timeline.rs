//! A campaign's timeline ([`crate::planning::campaign`]): one row per session, hours from the
//! session's start on x; each run a bar coloured by its placement (a white edge where it
//! starts), the move into it (robot motion and handling) a grey bar before it.

use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One bar of the timeline.
pub use crate::planning::campaign::TimelineBar as Bar;

/// Render the timeline into `out` (`.png` or `.svg`); `session_s` the session length (a dashed
/// line).
pub fn render(bars: &[Bar], session_s: f64, out: &Path) -> Result<()> {
    let sessions = bars.iter().map(|b| b.session).max().unwrap_or(0);
    if sessions == 0 || !(session_s.is_finite() && session_s > 0.0) {
        return Err(Error::invalid(
            "campaign timeline",
            bars.len(),
            "needs at least one run and a positive session length",
        ));
    }
    super::save(
        &Timeline {
            bars,
            sessions,
            session_s,
        },
        out,
    )
}

struct Timeline<'a> {
    bars: &'a [Bar],
    sessions: usize,
    session_s: f64,
}

impl Figure for Timeline<'_> {
    fn size(&self) -> (u32, u32) {
        (1400, 260 + 60 * self.sessions.min(40) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let h = 3600.0;
        let xmax = self
            .bars
            .iter()
            .map(|b| b.end_s)
            .fold(self.session_s, f64::max)
            / h;
        let n = self.sessions as f64;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Campaign: {} runs in {} sessions",
                    self.bars.iter().filter(|b| b.placement.is_some()).count(),
                    self.sessions
                ),
                (FAMILY, style::TITLE),
            )
            .margin(20)
            .margin_right(40)
            .x_label_area_size(70)
            .y_label_area_size(110)
            .build_cartesian_2d(0.0..xmax * 1.02, 0.5..n + 0.5)?;
        chart
            .configure_mesh()
            .x_desc("time from the session's start (h)")
            .y_desc("session")
            .axis_desc_style((FAMILY, style::AXIS))
            .label_style((FAMILY, style::TICK))
            .y_labels(self.sessions.min(40))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .bold_line_style(style::LIGHT_GREY)
            .light_line_style(TRANSPARENT)
            .draw()?;
        chart.draw_series(self.bars.iter().map(|b| {
            let y = b.session as f64;
            let colour = match b.placement {
                Some(p) => style::series(p - 1).filled(),
                None => style::GREY.filled(),
            };
            Rectangle::new([(b.start_s / h, y - 0.35), (b.end_s / h, y + 0.35)], colour)
        }))?;
        // A thin white edge at the start of every run, so that consecutive runs of one
        // placement stay apart.
        chart.draw_series(self.bars.iter().filter(|b| b.placement.is_some()).map(|b| {
            let (x, y) = (b.start_s / h, b.session as f64);
            PathElement::new(vec![(x, y - 0.35), (x, y + 0.35)], WHITE.stroke_width(1))
        }))?;
        let x = self.session_s / h;
        chart.draw_series(DashedLineSeries::new(
            vec![(x, 0.5), (x, n + 0.5)],
            8,
            6,
            style::GREY.stroke_width(2),
        ))?;
        Ok(())
    }
}
