//! The bifurcation type over the search directions: an equal-area map (the projection of
//! [`super::direction_map::project`], κ̂ axis at the centre, +τ̂ right, +ω̂ up) with
//! supercritical rays as blue squares, degenerate ones grey, and subcritical ones as dots
//! coloured by the hysteresis width `s* − s_return` (viridis, colour bar on the right;
//! vermillion rings where no `s_return` is reported: not computed, or not trusted — the CSV's
//! `reason` says which, e.g. the DER rod's snap met the clamp). Labelled directions (the seed's DER examples) are
//! marked with their label: × subcritical, ○ supercritical.
//!
//! Records: [`BifurcationRow`]s, read from the CSV of `helixreach bifurcation` by
//! [`read_bifurcation`] (columns `dir_kappa,dir_tau,dir_omega,s_star,type,hysteresis`; others
//! ignored), and labelled directions by [`read_labelled`] (`dir_kappa,dir_tau,dir_omega,type`).

use super::direction_map::{disk_background, project};
use super::style::{self, FAMILY};
use super::{DrawResult, Figure};
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::io::{bad_line, parse_field, CsvInput};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// One direction of a bifurcation CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct BifurcationRow {
    /// The direction.
    pub dir: Direction,
    /// `subcritical`, `supercritical` or `degenerate`.
    pub kind: String,
    /// `s* − s_return`, when computed.
    pub hysteresis: Option<f64>,
}

impl BifurcationRow {
    /// The row of a [`crate::bifurcation::classify`] result for `dir`.
    pub fn from_result(dir: Direction, b: &crate::bifurcation::Bifurcation) -> Self {
        let h = b.hysteresis();
        BifurcationRow {
            dir,
            kind: b.kind.name().to_string(),
            hysteresis: h.is_finite().then_some(h),
        }
    }

    /// The row of one of the seed's labelled directions (no hysteresis drawn: a label).
    pub fn from_label(l: &crate::bifurcation::survey::SeedLabel) -> Self {
        BifurcationRow {
            dir: l.dir,
            kind: l.kind.name().to_string(),
            hysteresis: None,
        }
    }
}

/// Read the rows of a `helixreach bifurcation` CSV.
pub fn read_bifurcation(path: &Path) -> Result<Vec<BifurcationRow>> {
    read_rows(path, true)
}

/// Read labelled directions (`dir_kappa,dir_tau,dir_omega,type`, e.g. the seed's
/// `bifurcation_examples.csv`).
pub fn read_labelled(path: &Path) -> Result<Vec<BifurcationRow>> {
    read_rows(path, false)
}

fn read_rows(path: &Path, with_hysteresis: bool) -> Result<Vec<BifurcationRow>> {
    let mut t = CsvInput::open(path)?;
    let hint = "header must contain dir_kappa,dir_tau,dir_omega,type";
    let cols = [
        t.column("dir_kappa", hint)?,
        t.column("dir_tau", hint)?,
        t.column("dir_omega", hint)?,
    ];
    let it = t.column("type", hint)?;
    let ih = if with_hysteresis {
        Some(t.column("hysteresis", "the CSV of helixreach bifurcation")?)
    } else {
        None
    };
    let mut out = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| bad_line(path, line, "record", e.to_string()))?;
        let names = ["dir_kappa", "dir_tau", "dir_omega"];
        let mut v = [0.0; 3];
        for i in 0..3 {
            v[i] = parse_field(path, line, &rec, cols[i], names[i])?;
        }
        let dir = Direction::new(v[0], v[1], v[2])
            .map_err(|e| bad_line(path, line, "direction", e.to_string()))?;
        let kind = rec.get(it).unwrap_or("").to_string();
        if !["subcritical", "supercritical", "degenerate"].contains(&kind.as_str()) {
            return Err(bad_line(
                path,
                line,
                "type",
                format!("`{kind}` is not subcritical, supercritical or degenerate"),
            ));
        }
        let hysteresis = match ih {
            Some(c) if !rec.get(c).unwrap_or("").is_empty() => {
                let h = parse_field(path, line, &rec, c, "hysteresis")?;
                if !h.is_finite() {
                    return Err(bad_line(
                        path,
                        line,
                        "hysteresis",
                        format!("{h} is not finite"),
                    ));
                }
                Some(h)
            }
            _ => None,
        };
        out.push(BifurcationRow {
            dir,
            kind,
            hysteresis,
        });
    }
    Ok(out)
}

/// Render the map of `rows`, marking `labelled` directions with their label.
pub fn render(rows: &[BifurcationRow], labelled: &[BifurcationRow], out: &Path) -> Result<()> {
    if rows.is_empty() {
        return Err(Error::invalid(
            "bifurcation rows",
            0,
            "need at least one direction",
        ));
    }
    let half = rows
        .iter()
        .chain(labelled)
        .all(|r| r.dir.tau >= -crate::math::tol::ON_QUARTER);
    let h_max = rows
        .iter()
        .filter_map(|r| r.hysteresis)
        .fold(0.0f64, f64::max)
        .max(super::style::guard::SCALE_FLOOR);
    super::save(
        &Map {
            rows,
            labelled,
            half,
            h_max,
        },
        out,
    )
}

struct Map<'a> {
    rows: &'a [BifurcationRow],
    labelled: &'a [BifurcationRow],
    half: bool,
    h_max: f64,
}

const R: i32 = 360;

impl Figure for Map<'_> {
    fn size(&self) -> (u32, u32) {
        let w = if self.half { R + 200 } else { 2 * R + 160 };
        ((w + 420) as u32, (2 * R + 200) as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let root = root.titled(
            "Bifurcation type at s* (equal-area map of directions, DER statics)",
            (FAMILY, style::TITLE),
        )?;
        let font = style::text;
        let cx = if self.half { 70 } else { R + 70 };
        let cy = R + 60;
        let to_px = |x: f64, y: f64| {
            (
                cx + (x * R as f64).round() as i32,
                cy - (y * R as f64).round() as i32,
            )
        };
        let bg = disk_background(
            &root,
            self.half,
            (cx, cy),
            &to_px,
            "κ̂",
            &font(style::TICK * 0.75),
        )?;
        // Ratio guides τ/κ = 0.3, 0.5, 1 on the ω = 0 line are the x axis itself: tick them.
        for ratio in [0.3f64, 0.5, 1.0] {
            let d = Direction::new(1.0, ratio, 0.0).expect("finite");
            let (x, y) = project(&d);
            let p = to_px(x, y);
            root.draw(&PathElement::new(
                vec![(p.0, p.1 - 6), (p.0, p.1 + 6)],
                style::BLACK.stroke_width(2),
            ))?;
            root.draw(&Text::new(
                format!("τ/κ={ratio}"),
                (p.0, p.1 + 10),
                font(style::TICK * 0.7).pos(Pos::new(HPos::Center, VPos::Top)),
            ))?;
        }
        let n = self.rows.len().max(1) as f64;
        let area = std::f64::consts::PI * (R * R) as f64 * if self.half { 0.5 } else { 1.0 };
        let rm = (0.8 * (area / n / std::f64::consts::PI).sqrt()).clamp(2.0, 10.0) as i32;
        let mut counts = [0usize; 3];
        let mut no_return = 0usize;
        for r in self.rows {
            let (x, y) = project(&r.dir);
            let p = to_px(x, y);
            match r.kind.as_str() {
                "supercritical" => {
                    counts[1] += 1;
                    root.draw(&Rectangle::new(
                        [(p.0 - rm, p.1 - rm), (p.0 + rm, p.1 + rm)],
                        style::BLUE.filled(),
                    ))?;
                }
                "subcritical" => {
                    counts[0] += 1;
                    match r.hysteresis {
                        Some(h) => root.draw(&Circle::new(
                            p,
                            rm,
                            style::viridis((h / self.h_max).clamp(0.0, 1.0)).filled(),
                        ))?,
                        None => {
                            no_return += 1;
                            root.draw(&Circle::new(p, rm, style::VERMILLION.stroke_width(2)))?
                        }
                    }
                }
                _ => {
                    counts[2] += 1;
                    root.draw(&Circle::new(p, rm, style::GREY.filled()))?;
                }
            }
        }
        for l in self.labelled {
            let (x, y) = project(&l.dir);
            let (px, py) = to_px(x, y);
            let r = rm + 5;
            if l.kind == "supercritical" {
                root.draw(&Circle::new((px, py), r, WHITE.stroke_width(6)))?;
                root.draw(&Circle::new((px, py), r, style::BLACK.stroke_width(3)))?;
            } else {
                for (w, c) in [(6, WHITE), (3, style::BLACK)] {
                    root.draw(&PathElement::new(
                        vec![(px - r, py - r), (px + r, py + r)],
                        c.stroke_width(w),
                    ))?;
                    root.draw(&PathElement::new(
                        vec![(px - r, py + r), (px + r, py - r)],
                        c.stroke_width(w),
                    ))?;
                }
            }
        }
        root.draw(&PathElement::new(bg, style::BLACK.stroke_width(2)))?;
        let lab = |text: &str, x: f64, y: f64| {
            let (px, py) = to_px(x, y);
            Text::new(
                text.to_string(),
                (px, py),
                font(style::AXIS * 0.85).pos(Pos::new(HPos::Center, VPos::Center)),
            )
        };
        root.draw(&lab("+τ", 1.1, 0.0))?;
        root.draw(&lab("+ω", 0.0, 1.07))?;
        root.draw(&lab("−ω", 0.0, -1.07))?;
        if !self.half {
            root.draw(&lab("−τ", -1.1, 0.0))?;
        }
        // Legend and colour bar.
        let lx = if self.half { R + 220 } else { 2 * R + 180 };
        let mut y = 40;
        let entry = |y: i32, text: String| {
            Text::new(
                text,
                (lx + 34, y),
                font(style::LEGEND).pos(Pos::new(HPos::Left, VPos::Center)),
            )
        };
        root.draw(&Rectangle::new(
            [(lx + 6, y - 8), (lx + 22, y + 8)],
            style::BLUE.filled(),
        ))?;
        root.draw(&entry(y, format!("supercritical ({})", counts[1])))?;
        y += 34;
        root.draw(&Circle::new((lx + 14, y), 8, style::viridis(0.6).filled()))?;
        root.draw(&entry(y, format!("subcritical ({})", counts[0])))?;
        y += 34;
        if no_return > 0 {
            root.draw(&Circle::new(
                (lx + 14, y),
                8,
                style::VERMILLION.stroke_width(2),
            ))?;
            root.draw(&entry(y, format!("  of which no s_return ({no_return})")))?;
            y += 34;
        }
        root.draw(&Circle::new((lx + 14, y), 8, style::GREY.filled()))?;
        root.draw(&entry(y, format!("degenerate ({})", counts[2])))?;
        y += 34;
        if !self.labelled.is_empty() {
            root.draw(&entry(y, "seed's labelled runs:".into()))?;
            y += 30;
            for (w, c) in [(6, WHITE), (3, style::BLACK)] {
                root.draw(&PathElement::new(
                    vec![(lx + 6, y - 8), (lx + 22, y + 8)],
                    c.stroke_width(w),
                ))?;
                root.draw(&PathElement::new(
                    vec![(lx + 6, y + 8), (lx + 22, y - 8)],
                    c.stroke_width(w),
                ))?;
            }
            root.draw(&entry(y, "labelled subcritical".into()))?;
            y += 30;
            root.draw(&Circle::new((lx + 14, y), 9, style::BLACK.stroke_width(3)))?;
            root.draw(&entry(y, "labelled supercritical".into()))?;
            y += 40;
        }
        root.draw(&Text::new(
            "hysteresis s* − s_return".to_string(),
            (lx + 4, y),
            font(style::LEGEND).pos(Pos::new(HPos::Left, VPos::Center)),
        ))?;
        y += 24;
        let bar_h = 300;
        for i in 0..bar_h {
            let t = 1.0 - i as f64 / bar_h as f64;
            root.draw(&Rectangle::new(
                [(lx + 10, y + i), (lx + 40, y + i + 1)],
                style::viridis(t).filled(),
            ))?;
        }
        for k in 0..=4 {
            let t = k as f64 / 4.0;
            let py = y + ((1.0 - t) * bar_h as f64) as i32;
            root.draw(&Text::new(
                format!("{:.2}", t * self.h_max),
                (lx + 48, py),
                font(style::TICK).pos(Pos::new(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}
