//! Layout and drawing of snapshots: a grid of orthographic panels with a common scale.
//!
//! # Layout
//! A *block* is one snapshot: a header (its title lines), one panel per view, a footer (its
//! clearances). [`Arrangement::Strip`] puts the blocks side by side with the views stacked in
//! each (frames left to right); [`Arrangement::Row`] is one block with the views side by side
//! (a single scene, a GIF frame). Every panel of a sheet has the same size and the same scale
//! (pixels per metre), chosen so that every snapshot of the sheet fits every view; each view
//! is centred on its own bounds. [`Layout::pixel`] is the one world → pixel map the drawing
//! uses.
//!
//! # Drawing
//! Bodies are filled convex outlines (the hull of [`Solid::outline_points`]) drawn far to near
//! by the depth of their centres (painter's order); the rod's segments join that order. A body's
//! colour is lightened with its depth (far = pale): the arm in two alternating grey-blues, the
//! fixed base in grey, the motor in reddish purple, obstacles in tan, the clamp in dark grey,
//! the rod in vermillion (3 px). Each clearance is a line between its two closest points with
//! dots at the ends, over a white halo (self black, scene green, rod–arm blue); a collision (distance 0) is
//! circled.
//!
//! [`Solid::outline_points`]: super::Solid::outline_points

use super::scene::{ClearanceKind, Part, Scene, Snapshot};
use super::View;
use crate::error::{Error, Result};
use crate::math::{Real, Vec3};
use crate::plot::style;
use crate::plot::DrawResult;
use plotters::coord::Shift;
use plotters::prelude::*;

/// How blocks and views are arranged (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrangement {
    /// Frames left to right, views stacked.
    Strip,
    /// One frame, views side by side.
    Row,
}

/// Drawing options.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// The views, in order.
    pub views: Vec<View>,
    /// Panel size in pixels (width, height), each between 200 and 2000.
    pub panel: (u32, u32),
    /// Write link names on the links.
    pub labels: bool,
    /// Title of the sheet.
    pub title: String,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            views: View::ALL.to_vec(),
            panel: (400, 380),
            labels: false,
            title: String::new(),
        }
    }
}

impl RenderOptions {
    /// Check the sizes and the view list.
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("panel width", self.panel.0),
            ("panel height", self.panel.1),
        ] {
            if !(200..=2000).contains(&v) {
                return Err(Error::invalid(name, v, "must be between 200 and 2000 px"));
            }
        }
        if self.views.is_empty() {
            return Err(Error::invalid("views", "[]", "name at least one view"));
        }
        Ok(())
    }
}

const TITLE_H: i32 = 34;
const HEADER_LINE: i32 = 20;
const FOOTER_LINE: i32 = 19;
const LEGEND_H: i32 = 30;
/// Plot area inside a panel: left (tick labels), top (view name), right, bottom (ticks).
const PAD: (i32, i32, i32, i32) = (58, 26, 12, 40);

/// Arm colours (alternating), base, motor, obstacle, clamp, rod.
const ARM: [RGBColor; 2] = [RGBColor(0xA6, 0xB9, 0xCC), RGBColor(0x5F, 0x74, 0x8A)];
const BASE: RGBColor = RGBColor(0x8C, 0x8C, 0x8C);
const OBSTACLE: RGBColor = RGBColor(0xC9, 0xB2, 0x8E);
const CLAMP: RGBColor = RGBColor(0x40, 0x40, 0x40);

/// The colour of a clearance kind.
pub fn clearance_colour(k: ClearanceKind) -> RGBColor {
    match k {
        ClearanceKind::SelfCollision => style::BLACK,
        ClearanceKind::Scene => style::GREEN,
        ClearanceKind::RodArm => style::BLUE,
    }
}

/// The world → pixel map of a sheet (see the module docs).
#[derive(Debug, Clone)]
pub struct Layout {
    views: Vec<View>,
    arrangement: Arrangement,
    n_frames: usize,
    panel: (i32, i32),
    scale: Real,
    centers: Vec<[Real; 2]>,
    depth: Vec<(Real, Real)>,
    header_h: i32,
    footer_h: i32,
}

impl Layout {
    /// The layout fitting every snapshot of `snaps` in every view of `opts`. A strip holds every
    /// snapshot; a row holds one at a time (a GIF frame), at the scale fitting them all.
    pub fn new(
        snaps: &[Snapshot],
        opts: &RenderOptions,
        arrangement: Arrangement,
    ) -> Result<Layout> {
        opts.validate()?;
        if snaps.is_empty() {
            return Err(Error::invalid("frames", 0, "nothing to render"));
        }
        let (pw, ph) = (opts.panel.0 as i32, opts.panel.1 as i32);
        let (aw, ah) = ((pw - PAD.0 - PAD.2) as Real, (ph - PAD.1 - PAD.3) as Real);
        let mut pts = Vec::new();
        let mut centers = Vec::new();
        let mut depth = Vec::new();
        let mut scale = Real::INFINITY;
        for &v in &opts.views {
            let (mut lo, mut hi) = ([Real::INFINITY; 2], [Real::NEG_INFINITY; 2]);
            let (mut dlo, mut dhi) = (Real::INFINITY, Real::NEG_INFINITY);
            for s in snaps {
                pts.clear();
                for b in &s.bodies {
                    b.solid.outline_points(v, &mut pts);
                    let d = v.depth(&b.solid.center());
                    dlo = dlo.min(d);
                    dhi = dhi.max(d);
                }
                for p in &s.rod {
                    pts.push(v.project(p));
                }
                for p in &pts {
                    for k in 0..2 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
            }
            let w = (hi[0] - lo[0]).max(crate::plot::style::guard::MIN_LAYOUT);
            let h = (hi[1] - lo[1]).max(crate::plot::style::guard::MIN_LAYOUT);
            scale = scale.min(0.94 * (aw / w).min(ah / h));
            centers.push([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])]);
            depth.push((dlo, dhi.max(dlo + crate::plot::style::guard::MIN_EXTENT)));
        }
        if !scale.is_finite() {
            return Err(Error::invalid(
                "scene",
                "non-finite geometry",
                "cannot be drawn",
            ));
        }
        let lines = snaps
            .iter()
            .map(|s| s.title.len())
            .max()
            .unwrap_or(0)
            .max(1) as i32;
        Ok(Layout {
            views: opts.views.clone(),
            arrangement,
            n_frames: match arrangement {
                Arrangement::Strip => snaps.len(),
                Arrangement::Row => 1,
            },
            panel: (pw, ph),
            scale,
            centers,
            depth,
            header_h: 8 + lines * HEADER_LINE,
            footer_h: 8 + 3 * FOOTER_LINE,
        })
    }

    /// Sheet size in pixels.
    pub fn size(&self) -> (u32, u32) {
        let nv = self.views.len() as i32;
        let (w, h) = match self.arrangement {
            Arrangement::Strip => (self.n_frames as i32 * self.panel.0, nv * self.panel.1),
            Arrangement::Row => (nv * self.panel.0, self.panel.1),
        };
        (
            w as u32,
            (TITLE_H + self.header_h + h + self.footer_h + LEGEND_H) as u32,
        )
    }

    /// The common scale (pixels per metre).
    pub fn scale(&self) -> Real {
        self.scale
    }

    /// Top-left pixel of the block of frame `f`.
    fn block_origin(&self, f: usize) -> (i32, i32) {
        match self.arrangement {
            Arrangement::Strip => (f as i32 * self.panel.0, TITLE_H),
            Arrangement::Row => (0, TITLE_H),
        }
    }

    /// Top-left pixel of the panel of frame `f`, view index `v`.
    pub fn panel_origin(&self, f: usize, v: usize) -> (i32, i32) {
        let (bx, by) = self.block_origin(f);
        match self.arrangement {
            Arrangement::Strip => (bx, by + self.header_h + v as i32 * self.panel.1),
            Arrangement::Row => (bx + v as i32 * self.panel.0, by + self.header_h),
        }
    }

    /// Pixel (x right, y down) of the base-frame point `p` in the panel of frame `f`, view
    /// index `v`.
    pub fn pixel(&self, f: usize, v: usize, p: &Vec3) -> (i32, i32) {
        let (ox, oy) = self.panel_origin(f, v);
        let [u, w] = self.views[v].project(p);
        self.to_px(ox, oy, v, u, w)
    }

    fn to_px(&self, ox: i32, oy: i32, v: usize, u: Real, w: Real) -> (i32, i32) {
        let c = self.centers[v];
        let (aw, ah) = (self.panel.0 - PAD.0 - PAD.2, self.panel.1 - PAD.1 - PAD.3);
        let x = ox as Real + PAD.0 as Real + 0.5 * aw as Real + (u - c[0]) * self.scale;
        let y = oy as Real + PAD.1 as Real + 0.5 * ah as Real - (w - c[1]) * self.scale;
        (x.round() as i32, y.round() as i32)
    }

    /// Screen-metre range visible in view `v` (horizontal, vertical).
    fn visible(&self, v: usize) -> ([Real; 2], [Real; 2]) {
        let c = self.centers[v];
        let (aw, ah) = (
            (self.panel.0 - PAD.0 - PAD.2) as Real,
            (self.panel.1 - PAD.1 - PAD.3) as Real,
        );
        let (hw, hh) = (0.5 * aw / self.scale, 0.5 * ah / self.scale);
        ([c[0] - hw, c[0] + hw], [c[1] - hh, c[1] + hh])
    }
}

/// A 1-2-5 length within this of `x` (relative) counts as not above it: the rounding of
/// `log10`/`powf` must not turn `x = 2·10ᵏ` into `10ᵏ`.
const NICE_SLACK: Real = 1e-12;

/// The largest 1-2-5 length (1, 2 or 5 times a power of ten) not above `x` > 0.
fn nice_below(x: Real) -> Real {
    let mag = 10f64.powf(x.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|l| *l <= x * (1.0 + NICE_SLACK))
        .unwrap_or(mag)
}

/// Convex hull (monotone chain), counter-clockwise, of pixel points.
fn hull(mut p: Vec<(i32, i32)>) -> Vec<(i32, i32)> {
    p.sort_unstable();
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: (i32, i32), a: (i32, i32), b: (i32, i32)| -> i64 {
        (a.0 - o.0) as i64 * (b.1 - o.1) as i64 - (a.1 - o.1) as i64 * (b.0 - o.0) as i64
    };
    let mut h: Vec<(i32, i32)> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = h.len();
        let it: Box<dyn Iterator<Item = &(i32, i32)>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in it {
            while h.len() >= start + 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0 {
                h.pop();
            }
            h.push(q);
        }
        h.pop();
    }
    h
}

enum Item {
    Poly(Vec<(i32, i32)>, RGBColor, RGBColor),
    Seg((i32, i32), (i32, i32), RGBColor),
}

fn text_style(size: f64, c: RGBColor) -> TextStyle<'static> {
    TextStyle {
        color: c.to_backend_color(),
        ..style::text(size)
    }
}

/// Draw the whole sheet of `snaps` on `root` (white, of [`Layout::size`]).
pub(crate) fn draw_sheet<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    scene: &Scene,
    snaps: &[Snapshot],
    layout: &Layout,
    opts: &RenderOptions,
) -> DrawResult<DB> {
    let (w, h) = layout.size();
    root.draw(&Text::new(
        opts.title.clone(),
        (12, 7),
        text_style(20.0, style::BLACK),
    ))?;
    for (f, snap) in snaps.iter().enumerate() {
        let (bx, by) = layout.block_origin(f);
        for (k, line) in snap.title.iter().enumerate() {
            root.draw(&Text::new(
                line.clone(),
                (bx + 12, by + 4 + k as i32 * HEADER_LINE),
                text_style(if k == 0 { 16.0 } else { 14.0 }, style::BLACK),
            ))?;
        }
        for v in 0..layout.views.len() {
            draw_panel(root, scene, snap, layout, opts, f, v)?;
        }
        let (_, py) = layout.panel_origin(f, layout.views.len() - 1);
        let fy = match layout.arrangement {
            Arrangement::Strip => py + layout.panel.1 + 4,
            Arrangement::Row => py + layout.panel.1 + 4,
        };
        for (k, kind) in ClearanceKind::ALL.iter().enumerate() {
            let line = match snap.clearance(*kind) {
                Some(c) if c.distance <= 0.0 => {
                    format!("{} COLLISION: {} – {}", kind.as_str(), c.a, c.b)
                }
                Some(c) => format!("{} {:.3} m: {} – {}", kind.as_str(), c.distance, c.a, c.b),
                None => format!("{}: nothing checked", kind.as_str()),
            };
            let colour = clearance_colour(*kind);
            let y = fy + k as i32 * FOOTER_LINE;
            root.draw(&PathElement::new(
                vec![(bx + 12, y + 8), (bx + 30, y + 8)],
                colour.stroke_width(3),
            ))?;
            root.draw(&Text::new(
                line,
                (bx + 36, y),
                text_style(14.0, style::BLACK),
            ))?;
        }
    }
    // Legend.
    let ly = h as i32 - LEGEND_H + 6;
    let mut x = 12;
    let swatch = |x: i32, c: RGBColor, label: &str| -> DrawResult<DB> {
        root.draw(&Rectangle::new(
            [(x, ly + 2), (x + 16, ly + 14)],
            c.filled(),
        ))?;
        root.draw(&Text::new(
            label.to_string(),
            (x + 20, ly),
            text_style(14.0, style::BLACK),
        ))
    };
    let entries: [(RGBColor, &str); 7] = [
        (ARM[1], "arm"),
        (BASE, "base"),
        (style::PURPLE, "motor"),
        (style::VERMILLION, "rod"),
        (CLAMP, "clamp"),
        (OBSTACLE, "obstacle"),
        (style::lighten(ARM[1], 0.55), "far = paler"),
    ];
    for (c, label) in entries {
        swatch(x, c, label)?;
        x += 28 + 8 * label.chars().count() as i32;
        if x > w as i32 - 100 {
            break;
        }
    }
    Ok(())
}

fn body_colour(scene: &Scene, part: Part) -> RGBColor {
    match part {
        Part::Link(i) => {
            let links = scene.model().links();
            if scene.is_motor(i) {
                style::PURPLE
            } else if links[i].group == links[0].group {
                BASE
            } else {
                ARM[i % 2]
            }
        }
        Part::Obstacle(_) => OBSTACLE,
        Part::Clamp => CLAMP,
    }
}

fn draw_panel<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    scene: &Scene,
    snap: &Snapshot,
    layout: &Layout,
    opts: &RenderOptions,
    f: usize,
    v: usize,
) -> DrawResult<DB> {
    let view = layout.views[v];
    let (ox, oy) = layout.panel_origin(f, v);
    let (pw, ph) = layout.panel;
    let (x0, y0, x1, y1) = (ox + PAD.0, oy + PAD.1, ox + pw - PAD.2, oy + ph - PAD.3);
    let name = match view.axis_names() {
        Some(_) => format!("{} view", view.as_str()),
        None => "iso view (from +x, −y, +z)".to_string(),
    };
    root.draw(&Text::new(
        name,
        (x0, oy + 5),
        text_style(14.0, style::BLACK),
    ))?;
    let (dlo, dhi) = layout.depth[v];
    let shade = |c: RGBColor, d: Real| {
        style::lighten(c, 0.55 * (1.0 - (d - dlo) / (dhi - dlo)).clamp(0.0, 1.0))
    };

    let mut items: Vec<(Real, Item)> = Vec::with_capacity(snap.bodies.len() + snap.rod.len());
    let mut pts = Vec::new();
    for b in &snap.bodies {
        pts.clear();
        b.solid.outline_points(view, &mut pts);
        let px: Vec<(i32, i32)> = pts
            .iter()
            .map(|p| layout.to_px(ox, oy, v, p[0], p[1]))
            .collect();
        let d = view.depth(&b.solid.center());
        let c = shade(body_colour(scene, b.part), d);
        items.push((d, Item::Poly(hull(px), c, style::darken(c, 0.35))));
    }
    for w in snap.rod.windows(2) {
        let d = view.depth(&(0.5 * (w[0] + w[1])));
        items.push((
            d,
            Item::Seg(
                layout.pixel(f, v, &w[0]),
                layout.pixel(f, v, &w[1]),
                style::lighten(
                    style::VERMILLION,
                    0.3 * (1.0 - (d - dlo) / (dhi - dlo)).clamp(0.0, 1.0),
                ),
            ),
        ));
    }
    items.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (_, it) in &items {
        match it {
            Item::Poly(p, fill, edge) => {
                if p.len() >= 3 {
                    root.draw(&Polygon::new(p.clone(), fill.filled()))?;
                    let mut ring = p.clone();
                    ring.push(p[0]);
                    root.draw(&PathElement::new(ring, edge.stroke_width(1)))?;
                }
            }
            Item::Seg(a, b, c) => {
                root.draw(&PathElement::new(vec![*a, *b], c.stroke_width(3)))?;
            }
        }
    }
    // Clearance pairs.
    for c in &snap.clearances {
        let colour = clearance_colour(c.kind);
        let a = layout.pixel(f, v, &c.point_a);
        let b = layout.pixel(f, v, &c.point_b);
        root.draw(&PathElement::new(vec![a, b], WHITE.stroke_width(5)))?;
        root.draw(&PathElement::new(vec![a, b], colour.stroke_width(2)))?;
        root.draw(&Circle::new(a, 4, colour.filled()))?;
        root.draw(&Circle::new(b, 4, colour.filled()))?;
        if c.distance <= 0.0 {
            root.draw(&Circle::new(a, 10, colour.stroke_width(3)))?;
        }
    }
    if opts.labels {
        let mut seen = Vec::new();
        for b in &snap.bodies {
            if let Part::Link(i) = b.part {
                if seen.contains(&i) {
                    continue;
                }
                seen.push(i);
                let p = layout.pixel(f, v, &b.solid.center());
                root.draw(&Text::new(
                    scene.model().links()[i].name.clone(),
                    (p.0 + 3, p.1 - 6),
                    text_style(11.0, style::BLACK),
                ))?;
            }
        }
    }
    // Frame and axes.
    root.draw(&Rectangle::new(
        [(x0, y0), (x1, y1)],
        style::GREY.stroke_width(1),
    ))?;
    let (hr, vr) = layout.visible(v);
    let tick = text_style(13.0, style::BLACK);
    match view.axis_names() {
        Some((hn, vn)) => {
            for t in style::nice_ticks(hr[0], hr[1], 4) {
                let (x, _) = layout.to_px(ox, oy, v, t, vr[0]);
                root.draw(&PathElement::new(
                    vec![(x, y1), (x, y1 + 5)],
                    style::BLACK.stroke_width(1),
                ))?;
                root.draw(&Text::new(
                    style::tick_label(t),
                    (x - 4 * style::tick_label(t).chars().count() as i32, y1 + 7),
                    tick.clone(),
                ))?;
            }
            for t in style::nice_ticks(vr[0], vr[1], 4) {
                let (_, y) = layout.to_px(ox, oy, v, hr[0], t);
                root.draw(&PathElement::new(
                    vec![(x0 - 5, y), (x0, y)],
                    style::BLACK.stroke_width(1),
                ))?;
                let lab = style::tick_label(t);
                root.draw(&Text::new(
                    lab.clone(),
                    (x0 - 9 - 7 * lab.chars().count() as i32, y - 7),
                    tick.clone(),
                ))?;
            }
            root.draw(&Text::new(
                format!("{hn} (m)"),
                (x1 - 38, y1 + 22),
                text_style(13.0, style::BLACK),
            ))?;
            root.draw(&Text::new(
                format!("{vn} (m)"),
                (ox + 4, oy + 5),
                text_style(13.0, style::BLACK),
            ))?;
        }
        None => {
            // Scale bar (a 1-2-5 length near a quarter of the width) and an axis triad.
            let len = nice_below(0.25 * (hr[1] - hr[0]));
            let px = (len * layout.scale).round() as i32;
            let (bx, by) = (x0 + 10, y1 + 14);
            root.draw(&PathElement::new(
                vec![(bx, by), (bx + px, by)],
                style::BLACK.stroke_width(2),
            ))?;
            for x in [bx, bx + px] {
                root.draw(&PathElement::new(
                    vec![(x, by - 4), (x, by + 4)],
                    style::BLACK.stroke_width(2),
                ))?;
            }
            root.draw(&Text::new(
                format!("{} m", style::tick_label(len)),
                (bx + px + 6, by - 8),
                tick.clone(),
            ))?;
            let (r, u, _) = view.basis();
            let origin = (x1 - 40, y1 - 34);
            for (axis, name) in [(Vec3::x(), "x"), (Vec3::y(), "y"), (Vec3::z(), "z")] {
                let e = (
                    origin.0 + (24.0 * r.dot(&axis)).round() as i32,
                    origin.1 - (24.0 * u.dot(&axis)).round() as i32,
                );
                root.draw(&PathElement::new(
                    vec![origin, e],
                    style::BLACK.stroke_width(2),
                ))?;
                root.draw(&Text::new(name, (e.0 + 2, e.1 - 8), tick.clone()))?;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_lengths_and_hulls() {
        assert_eq!(nice_below(0.484), 0.2);
        assert_eq!(nice_below(0.5), 0.5);
        assert_eq!(nice_below(1.9), 1.0);
        // The hull of a square with an interior point is the square, counter-clockwise.
        let h = hull(vec![(0, 0), (10, 0), (10, 10), (0, 10), (5, 5), (10, 0)]);
        assert_eq!(h, vec![(0, 0), (10, 0), (10, 10), (0, 10)]);
    }
}
