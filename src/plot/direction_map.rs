//! A map of search directions on the half-sphere κ̂ ≥ 0, coloured by the reachability class and
//! the blocking cause, one panel per roll mode, with the experiment's directions marked.
//!
//! # Projection
//! Lambert azimuthal equal-area projection centred on the κ̂ axis: a unit direction with
//! κ̂ = cos θ and azimuth φ = atan2(ω̂, τ̂) in the τ̂-ω̂ plane maps to the point at radius
//! r = 2 sin(θ/2)/√2 = √(1 − κ̂) and angle φ. The centre is the pure-curvature direction κ̂ = 1,
//! the rim is the great circle κ̂ = 0, +τ̂ points right and +ω̂ up. Equal area means equal
//! fractions of the map's area are equal fractions of directions, so the coloured areas read
//! directly as coverage. When every direction has τ̂ ≥ 0 (the experiment's quarter-sphere) only
//! the right half-disk is drawn.
//!
//! # Encoding
//! Testable rays are filled green; partial rays are rings and blocked rays filled dots, both in
//! the colour of the cause that stopped them (Okabe–Ito palette); undecided rays (the search
//! hit its node bound) are light grey dots outlined in black. Marked directions (the experiment's) are black
//! crosses. The legend gives each category's share per roll mode.

use super::records::{BlockCause, ReachClass, ReachRow};
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::directions::Direction;
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// The equal-area map coordinates (x, y) in the unit disk of a direction (see the module docs).
///
/// ```
/// use helixreach::directions::Direction;
/// use helixreach::plot::direction_map::project;
/// let (x, y) = project(&Direction::new(1.0, 0.0, 0.0).unwrap());
/// assert!(x.abs() < 1e-15 && y.abs() < 1e-15);          // κ̂ axis at the centre
/// let (x, y) = project(&Direction::new(0.0, 0.0, 1.0).unwrap());
/// assert!(x.abs() < 1e-15 && (y - 1.0).abs() < 1e-15);  // +ω̂ on the rim, up
/// ```
pub fn project(d: &Direction) -> (f64, f64) {
    let r = (1.0 - d.kappa).max(0.0).sqrt();
    let rho = d.tau.hypot(d.omega);
    if rho == 0.0 {
        (0.0, 0.0)
    } else {
        (r * d.tau / rho, r * d.omega / rho)
    }
}

/// Render the direction map of `rows`, marking `marked` directions (may be empty) as black
/// rings named `marked_label` in the legend (e.g. "experiment's directions").
pub fn render(
    rows: &[ReachRow],
    marked: &[Direction],
    marked_label: &str,
    out: &Path,
) -> Result<()> {
    if rows.is_empty() {
        return Err(Error::invalid(
            "reach rows",
            0,
            "need at least one direction",
        ));
    }
    let mut modes: Vec<String> = Vec::new();
    for r in rows {
        if !modes.contains(&r.roll_mode) {
            modes.push(r.roll_mode.clone());
        }
    }
    let on = |tau: f64| tau >= -crate::math::tol::ON_QUARTER;
    let half = rows.iter().all(|r| on(r.dir.tau)) && marked.iter().all(|d| on(d.tau));
    let panels = modes
        .iter()
        .map(|m| {
            let pts: Vec<(f64, f64, Category)> = rows
                .iter()
                .filter(|r| &r.roll_mode == m)
                .map(|r| {
                    let (x, y) = project(&r.dir);
                    (x, y, Category::of(r))
                })
                .collect();
            Panel {
                mode: m.clone(),
                pts,
            }
        })
        .collect();
    super::save(
        &DirectionMap {
            panels,
            marked: marked.iter().map(project).collect(),
            marked_label: marked_label.to_string(),
            half,
        },
        out,
    )
}

enum Marker {
    Dot(RGBColor),
    Ring(RGBColor),
    None,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Category {
    Testable,
    Partial(Option<BlockCause>),
    Blocked(Option<BlockCause>),
    Undecided,
}

impl Category {
    fn of(r: &ReachRow) -> Category {
        match r.class {
            ReachClass::Testable => Category::Testable,
            ReachClass::Partial => Category::Partial(r.cause),
            ReachClass::Blocked => Category::Blocked(r.cause),
            ReachClass::Undecided => Category::Undecided,
        }
    }
}

/// The fill of an undecided ray.
fn undecided_color() -> RGBColor {
    style::lighten(style::GREY, 0.55)
}

fn cause_color(c: Option<BlockCause>) -> RGBColor {
    match c {
        None => style::GREY,
        Some(BlockCause::NoIk) => style::ORANGE,
        Some(BlockCause::JointLimit) => style::VERMILLION,
        Some(BlockCause::SelfCollision) => style::PURPLE,
        Some(BlockCause::SceneCollision) => style::BLUE,
        Some(BlockCause::RodCollision) => style::YELLOW,
        Some(BlockCause::Discontinuity) => style::BLACK,
        Some(BlockCause::WaypointLimit) => style::SKY_BLUE,
    }
}

/// Legend words for a cause.
fn cause_label(c: BlockCause) -> &'static str {
    match c {
        BlockCause::NoIk => "no IK solution",
        BlockCause::JointLimit => "joint limit",
        BlockCause::SelfCollision => "self-collision",
        BlockCause::SceneCollision => "scene collision",
        BlockCause::RodCollision => "rod collision",
        BlockCause::Discontinuity => "discontinuity",
        BlockCause::WaypointLimit => "waypoint limit",
    }
}

struct Panel {
    mode: String,
    pts: Vec<(f64, f64, Category)>,
}

struct DirectionMap {
    panels: Vec<Panel>,
    marked: Vec<(f64, f64)>,
    marked_label: String,
    half: bool,
}

const R: i32 = 330;
const LEGEND_W: i32 = 330;
const MODE_COL_W: i32 = 110;

impl DirectionMap {
    fn panel_w(&self) -> i32 {
        if self.half {
            R + 170
        } else {
            2 * R + 140
        }
    }
    fn legend_w(&self) -> i32 {
        LEGEND_W + MODE_COL_W * self.panels.len() as i32
    }
}

/// A black × of half-size `r` on a white halo (the marked directions).
fn cross<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (x, y): (i32, i32),
    r: i32,
) -> DrawResult<DB> {
    for (w, c) in [(7, WHITE), (3, style::BLACK)] {
        root.draw(&PathElement::new(
            vec![(x - r, y - r), (x + r, y + r)],
            c.stroke_width(w),
        ))?;
        root.draw(&PathElement::new(
            vec![(x - r, y + r), (x + r, y - r)],
            c.stroke_width(w),
        ))?;
    }
    Ok(())
}

impl Figure for DirectionMap {
    fn size(&self) -> (u32, u32) {
        let w = self.panel_w() * self.panels.len() as i32 + self.legend_w();
        (w as u32, (2 * R + 230) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let root = root.titled(
            "Directions by reachability (equal-area map, κ ≥ 0)",
            (FAMILY, style::TITLE),
        )?;
        let font = |s: f64| style::text(s);
        let centred = |s: f64| font(s).pos(Pos::new(HPos::Center, VPos::Center));
        let max_n = self
            .panels
            .iter()
            .map(|p| p.pts.len())
            .max()
            .unwrap_or(1)
            .max(1);
        // Marker radius: a disk of the map's area per direction, slightly shrunk.
        let area = std::f64::consts::PI * (R * R) as f64 * if self.half { 0.5 } else { 1.0 };
        let rm = (0.8 * (area / max_n as f64 / std::f64::consts::PI).sqrt()).clamp(1.5, 9.0);
        let rm_i = rm.round().max(1.0) as i32;
        let ring = rm >= 3.0;

        for (k, panel) in self.panels.iter().enumerate() {
            let x0 = k as i32 * self.panel_w();
            let cx = x0 + if self.half { 70 } else { R + 70 };
            let cy = R + 80;
            let to_px = |x: f64, y: f64| {
                (
                    cx + (x * R as f64).round() as i32,
                    cy - (y * R as f64).round() as i32,
                )
            };
            let caption = if panel.mode.is_empty() {
                format!("{} directions", panel.pts.len())
            } else {
                format!("roll mode: {} ({} directions)", panel.mode, panel.pts.len())
            };
            root.draw(&Text::new(
                caption,
                (x0 + self.panel_w() / 2, 30),
                centred(style::AXIS),
            ))?;
            // Background disk (or half-disk) and guides.
            let (a0, a1) = disk_span(self.half);
            let bg = disk_background(
                &root,
                self.half,
                (cx, cy),
                &to_px,
                "κ/s",
                &font(style::TICK * 0.75).color(&style::darken(style::GREY, 0.3)),
            )?;
            let mut a = a0;
            while a <= a1 + style::guard::SAME {
                let t = a.to_radians();
                root.draw(&PathElement::new(
                    vec![to_px(0.0, 0.0), to_px(t.cos(), t.sin())],
                    style::GREY.stroke_width(1),
                ))?;
                a += 45.0;
            }
            // Directions.
            for &(x, y, cat) in &panel.pts {
                let p = to_px(x, y);
                match cat {
                    Category::Testable => {
                        root.draw(&Circle::new(p, rm_i, style::GREEN.filled()))?;
                    }
                    Category::Blocked(c) => {
                        root.draw(&Circle::new(p, rm_i, cause_color(c).filled()))?;
                    }
                    Category::Undecided => {
                        root.draw(&Circle::new(p, rm_i, undecided_color().filled()))?;
                        root.draw(&Circle::new(p, rm_i, style::BLACK.stroke_width(1)))?;
                    }
                    Category::Partial(c) => {
                        if ring {
                            let w = (rm / 3.0).round().max(1.0) as u32;
                            root.draw(&Circle::new(
                                p,
                                rm_i - w as i32 / 2,
                                cause_color(c).stroke_width(w),
                            ))?;
                        } else {
                            root.draw(&Circle::new(
                                p,
                                rm_i,
                                style::lighten(cause_color(c), 0.55).filled(),
                            ))?;
                        }
                    }
                }
            }
            for &(x, y) in &self.marked {
                cross(&root, to_px(x, y), rm_i + 6)?;
            }
            root.draw(&PathElement::new(bg, style::BLACK.stroke_width(2)))?;
            // Axis words.
            let lab = |text: &str, x: f64, y: f64| -> DrawResult<DB> {
                let (px, py) = to_px(x, y);
                root.draw(&Text::new(
                    text.to_string(),
                    (px, py),
                    centred(style::AXIS * 0.85),
                ))
            };
            lab("+τ", 1.1, 0.0)?;
            lab("+ω", 0.0, 1.08)?;
            lab("−ω", 0.0, -1.08)?;
            if !self.half {
                lab("−τ", -1.1, 0.0)?;
            }
            let (px, py) = to_px(0.0, 0.0);
            root.draw(&Circle::new((px, py), 4, style::BLACK.filled()))?;
            root.draw(&Text::new(
                "+κ".to_string(),
                if self.half {
                    (px - 10, py)
                } else {
                    (px + 8, py - 8)
                },
                font(style::AXIS * 0.85).pos(Pos::new(
                    if self.half { HPos::Right } else { HPos::Left },
                    if self.half {
                        VPos::Center
                    } else {
                        VPos::Bottom
                    },
                )),
            ))?;
            root.draw(&Text::new(
                "rim: κ = 0".to_string(),
                (x0 + self.panel_w() / 2, 2 * R + 150),
                centred(style::TICK),
            ))?;
        }

        // Legend with each category's share per roll mode.
        let lx = self.panel_w() * self.panels.len() as i32 + 10;
        let mut y = 60;
        let col = |k: usize| lx + LEGEND_W - 10 + MODE_COL_W * k as i32;
        for (k, p) in self.panels.iter().enumerate() {
            let name = if p.mode.is_empty() {
                "share"
            } else {
                p.mode.as_str()
            };
            root.draw(&Text::new(
                name.to_string(),
                (col(k) + MODE_COL_W / 2, y),
                centred(style::LEGEND),
            ))?;
        }
        y += 36;
        let share = |p: &Panel, f: &dyn Fn(Category) -> bool| {
            let n = p.pts.iter().filter(|q| f(q.2)).count();
            (n, 100.0 * n as f64 / p.pts.len().max(1) as f64)
        };
        let dark = style::darken(style::GREY, 0.2);
        type Filter = Box<dyn Fn(Category) -> bool>;
        let mut entries: Vec<(String, Marker, Filter, bool)> = vec![
            (
                "testable".into(),
                Marker::Dot(style::GREEN),
                Box::new(|c| c == Category::Testable),
                true,
            ),
            (
                "partial (ring)".into(),
                Marker::Ring(dark),
                Box::new(|c| matches!(c, Category::Partial(_))),
                true,
            ),
            (
                "blocked (dot)".into(),
                Marker::Dot(dark),
                Box::new(|c| matches!(c, Category::Blocked(_))),
                true,
            ),
            (
                "undecided (search bound)".into(),
                Marker::Dot(undecided_color()),
                Box::new(|c| c == Category::Undecided),
                false,
            ),
            (
                "stopped by (partial + blocked):".into(),
                Marker::None,
                Box::new(|_| false),
                true,
            ),
        ];
        for cause in BlockCause::ALL {
            entries.push((
                cause_label(cause).into(),
                Marker::Dot(cause_color(Some(cause))),
                Box::new(
                    move |c| matches!(c, Category::Partial(x) | Category::Blocked(x) if x == Some(cause)),
                ),
                false,
            ));
        }
        for (text, marker, f, always) in &entries {
            let counts: Vec<(usize, f64)> = self.panels.iter().map(|p| share(p, f)).collect();
            if !always && counts.iter().all(|c| c.0 == 0) {
                continue;
            }
            let m = (lx + 14, y);
            match marker {
                Marker::Dot(c) => root.draw(&Circle::new(m, 8, c.filled()))?,
                Marker::Ring(c) => root.draw(&Circle::new(m, 7, c.stroke_width(3)))?,
                Marker::None => {}
            }
            let tx = if matches!(marker, Marker::None) {
                lx + 4
            } else {
                lx + 34
            };
            root.draw(&Text::new(
                text.clone(),
                (tx, y),
                font(style::LEGEND).pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
            if !matches!(marker, Marker::None) {
                for (k, (_, pct)) in counts.iter().enumerate() {
                    root.draw(&Text::new(
                        format!("{pct:.1} %"),
                        (col(k) + MODE_COL_W - 12, y),
                        font(style::LEGEND).pos(Pos::new(HPos::Right, VPos::Center)),
                    ))?;
                }
            }
            y += 34;
        }
        if !self.marked.is_empty() {
            y += 8;
            cross(&root, (lx + 14, y), 10)?;
            root.draw(&Text::new(
                format!("{} ({})", self.marked_label, self.marked.len()),
                (lx + 34, y),
                font(style::LEGEND).pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}

/// Azimuth span (degrees) of the map: the half-disk τ ≥ 0 or the whole disk.
pub(crate) fn disk_span(half: bool) -> (f64, f64) {
    if half {
        (-90.0, 90.0)
    } else {
        (-180.0, 180.0)
    }
}

/// The map's grey background disk (or half-disk) and the κ guide circles at κ = 0.25, 0.5, 0.75
/// labelled `{label}={κ}`; returns the outline, for the caller to stroke on top.
pub(crate) fn disk_background<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    half: bool,
    centre: (i32, i32),
    to_px: &dyn Fn(f64, f64) -> (i32, i32),
    label: &str,
    label_style: &TextStyle<'_>,
) -> std::result::Result<Vec<(i32, i32)>, DrawingAreaErrorKind<DB::ErrorType>> {
    let (a0, a1) = disk_span(half);
    let arc = |r: f64| -> Vec<(i32, i32)> {
        (0..=180)
            .map(|i| {
                let a = (a0 + (a1 - a0) * i as f64 / 180.0).to_radians();
                to_px(r * a.cos(), r * a.sin())
            })
            .collect()
    };
    let mut bg = arc(1.0);
    if half {
        bg.push(centre);
    }
    root.draw(&Polygon::new(
        bg.clone(),
        RGBColor(0xf4, 0xf4, 0xf4).filled(),
    ))?;
    for kap in [0.25, 0.5, 0.75] {
        let r = (1.0f64 - kap).sqrt();
        root.draw(&PathElement::new(arc(r), style::GREY.stroke_width(1)))?;
        let (lx, ly) = to_px(
            r * (-40f64).to_radians().cos(),
            r * (-40f64).to_radians().sin(),
        );
        root.draw(&Text::new(
            format!("{label}={kap}"),
            (lx + 4, ly + 2),
            label_style.clone(),
        ))?;
    }
    Ok(bg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_is_equal_area() {
        // Equal-area: the share of a uniform direction set inside map radius ρ is the share of
        // the disk's area, ρ². The Fibonacci lattice is uniform by construction (Archimedes).
        let d = crate::directions::fibonacci(40_000, false).unwrap();
        for rho in [0.3, 0.5, 0.8, 0.95] {
            let inside = d
                .iter()
                .filter(|s| {
                    let (x, y) = project(s);
                    x.hypot(y) < rho
                })
                .count() as f64
                / d.len() as f64;
            assert!((inside - rho * rho).abs() < 2e-3, "ρ = {rho}: {inside}");
        }
        // And the azimuth is preserved: the quadrant τ̂ > 0, ω̂ > 0 maps to x > 0, y > 0.
        for s in &d {
            let (x, y) = project(s);
            assert!(x * s.tau >= 0.0 && y * s.omega >= 0.0);
            assert!(x.hypot(y) <= 1.0 + 1e-12);
        }
    }
}
