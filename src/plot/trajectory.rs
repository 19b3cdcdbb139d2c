//! One planned trajectory: every joint angle and the motor angle versus the distance along the
//! ray s, one small panel each, with the joint limits drawn as dashed lines and the range beyond
//! them shaded.
//!
//! Limits are matched to panels by order (`q0` ↔ the first non-`motor` limit, …); a limit named
//! `motor` belongs to the motor panel. Without limits the panels show the data range only.

use super::records::{JointLimit, TrajectoryRow};
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Optional annotations of the trajectory figure.
#[derive(Debug, Clone, Default)]
pub struct TrajectoryOptions {
    /// Joint limits (rad), in chain order; a limit named `motor` applies to the motor.
    pub limits: Vec<JointLimit>,
    /// The boundary s* of the ray, drawn as a vertical line when given.
    pub s_star: Option<f64>,
    /// Extra words for the title (e.g. the direction and roll mode).
    pub subtitle: String,
}

/// Render the trajectory `rows` into `out`.
pub fn render(rows: &[TrajectoryRow], opts: &TrajectoryOptions, out: &Path) -> Result<()> {
    let Some(first) = rows.first() else {
        return Err(Error::invalid(
            "trajectory",
            0,
            "the trajectory has no rows",
        ));
    };
    let nq = first.q.len();
    if nq == 0 {
        return Err(Error::invalid(
            "trajectory",
            0,
            "the trajectory has no joints",
        ));
    }
    for (i, r) in rows.iter().enumerate() {
        if r.q.len() != nq {
            return Err(Error::invalid(
                format!("trajectory row {i}"),
                r.q.len(),
                format!("expected {nq} joints like the first row"),
            ));
        }
        if !r.s.is_finite() || r.q.iter().any(|q| !q.is_finite()) {
            return Err(Error::invalid(
                format!("trajectory row {i}"),
                format!("s = {}, q = {:?}", r.s, r.q),
                "non-finite value",
            ));
        }
    }
    for l in &opts.limits {
        if !(l.lower.is_finite() && l.upper.is_finite() && l.lower < l.upper) {
            return Err(Error::invalid(
                format!("limit of {}", l.name),
                format!("[{}, {}]", l.lower, l.upper),
                "must be finite with lower < upper",
            ));
        }
    }
    let mut panels = Vec::new();
    let mut joint_limits = opts.limits.iter().filter(|l| l.name != "motor");
    for j in 0..nq {
        let lim = joint_limits.next();
        panels.push(Panel {
            title: match lim {
                Some(l) if !l.name.is_empty() => format!("q{j} ({})", l.name),
                _ => format!("q{j}"),
            },
            values: rows.iter().map(|r| (r.s, r.q[j])).collect(),
            limit: lim.map(|l| (l.lower, l.upper)),
            motor: false,
        });
    }
    if rows.iter().all(|r| r.motor.is_finite()) {
        panels.push(Panel {
            title: "motor angle".into(),
            values: rows.iter().map(|r| (r.s, r.motor)).collect(),
            limit: opts
                .limits
                .iter()
                .find(|l| l.name == "motor")
                .map(|l| (l.lower, l.upper)),
            motor: true,
        });
    }
    super::save(
        &Trajectory {
            panels,
            s_star: opts.s_star.filter(|v| v.is_finite()),
            subtitle: opts.subtitle.clone(),
        },
        out,
    )
}

struct Panel {
    title: String,
    values: Vec<(f64, f64)>,
    limit: Option<(f64, f64)>,
    motor: bool,
}

struct Trajectory {
    panels: Vec<Panel>,
    s_star: Option<f64>,
    subtitle: String,
}

const COLS: usize = 2;

impl Figure for Trajectory {
    fn size(&self) -> (u32, u32) {
        let rows = self.panels.len().div_ceil(COLS) as u32;
        (1400, 150 + 270 * rows)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let title = if self.subtitle.is_empty() {
            "Planned trajectory: joint and motor angles along the ray".to_string()
        } else {
            format!("Planned trajectory — {}", self.subtitle)
        };
        let root = root
            .margin(8, 0, 0, 0)
            .titled(&title, (FAMILY, style::TITLE))?;
        let (_, h) = root.dim_in_pixel();
        let (grid, key) = root.split_vertically(h - 50);
        let nrows = self.panels.len().div_ceil(COLS);
        let areas = grid.split_evenly((nrows, COLS));
        let s_lo = self.panels[0]
            .values
            .iter()
            .map(|v| v.0)
            .fold(f64::INFINITY, f64::min);
        let mut s_hi = self.panels[0]
            .values
            .iter()
            .map(|v| v.0)
            .fold(f64::NEG_INFINITY, f64::max);
        if let Some(s) = self.s_star {
            s_hi = s_hi.max(s);
        }
        if s_hi.partial_cmp(&s_lo) != Some(std::cmp::Ordering::Greater) {
            s_hi = s_lo + 1.0;
        }
        for (k, (panel, area)) in self.panels.iter().zip(areas.iter()).enumerate() {
            let (mut lo, mut hi) = panel
                .values
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v.1), b.max(v.1))
                });
            if let Some((l, u)) = panel.limit {
                lo = lo.min(l);
                hi = hi.max(u);
            }
            if hi - lo <= super::style::guard::MIN_EXTENT || (hi - lo).is_nan() {
                lo -= 0.5;
                hi += 0.5;
            }
            let pad = 0.06 * (hi - lo);
            let (lo, hi) = (lo - pad, hi + pad);
            let bottom_row = k / COLS == nrows - 1 || k + COLS >= self.panels.len();
            let mut chart = ChartBuilder::on(area)
                .caption(&panel.title, (FAMILY, style::LEGEND))
                .margin(8)
                .margin_right(24)
                .x_label_area_size(if bottom_row { 62 } else { 30 })
                .y_label_area_size(95)
                .build_cartesian_2d(s_lo..s_hi, lo..hi)?;
            let mut mesh = chart.configure_mesh();
            mesh.y_desc("angle (rad)")
                .axis_desc_style((FAMILY, style::TICK))
                .label_style((FAMILY, style::TICK * 0.85))
                .x_label_formatter(&style::fmt_tick)
                .y_label_formatter(&style::fmt_tick)
                .bold_line_style(style::LIGHT_GREY)
                .light_line_style(TRANSPARENT)
                .x_labels(6)
                .y_labels(5);
            if bottom_row {
                mesh.x_desc("distance along the ray s");
            }
            mesh.draw()?;
            let c = if panel.motor {
                style::BLACK
            } else {
                style::BLUE
            };
            if let Some((l, u)) = panel.limit {
                let shade = style::VERMILLION.mix(0.12);
                chart.draw_series([
                    Rectangle::new([(s_lo, lo), (s_hi, l)], shade.filled()),
                    Rectangle::new([(s_lo, u), (s_hi, hi)], shade.filled()),
                ])?;
                for v in [l, u] {
                    chart.draw_series(DashedLineSeries::new(
                        [(s_lo, v), (s_hi, v)],
                        10,
                        6,
                        style::VERMILLION.stroke_width(2),
                    ))?;
                }
            }
            if let Some(s) = self.s_star {
                chart.draw_series(DashedLineSeries::new(
                    [(s, lo), (s, hi)],
                    6,
                    6,
                    style::GREY.stroke_width(2),
                ))?;
            }
            chart.draw_series(LineSeries::new(
                panel.values.iter().copied(),
                c.stroke_width(3),
            ))?;
        }
        // Key for the guides, in one row under the panels.
        let key_font = style::text(style::LEGEND * 0.9);
        let mut entries = vec![("joint angle", style::BLUE, false)];
        if self.panels.iter().any(|p| p.motor) {
            entries.push(("motor angle", style::BLACK, false));
        }
        if self.panels.iter().any(|p| p.limit.is_some()) {
            entries.push(("joint limit (beyond it shaded)", style::VERMILLION, true));
        }
        if self.s_star.is_some() {
            entries.push(("stability boundary s*", style::GREY, true));
        }
        let (w, _) = key.dim_in_pixel();
        let slot = w as i32 / entries.len() as i32;
        for (i, (text, color, dashed)) in entries.into_iter().enumerate() {
            let x = 30 + i as i32 * slot;
            let y = 25;
            if dashed {
                key.draw(&PathElement::new(
                    vec![(x, y), (x + 12, y)],
                    color.stroke_width(3),
                ))?;
                key.draw(&PathElement::new(
                    vec![(x + 20, y), (x + 32, y)],
                    color.stroke_width(3),
                ))?;
            } else {
                key.draw(&PathElement::new(
                    vec![(x, y), (x + 32, y)],
                    color.stroke_width(3),
                ))?;
            }
            key.draw(&Text::new(
                text.to_string(),
                (x + 44, y),
                key_font.clone().pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}
