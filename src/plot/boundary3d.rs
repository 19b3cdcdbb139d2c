//! The stability boundary as a surface in (κ, τ, ω) space: the points s*·S̄ over the direction
//! set, seen in an orthographic 3-D projection, coloured by s*, with a cutaway that opens the
//! quadrant of (τ, ω) facing the camera so that the stable region (the side of the origin, the straight rod) shows
//! as shaded cut faces.
//!
//! # From scattered directions to a surface
//! The records are scattered directions (a Fibonacci lattice, a quarter-sphere, a CSV). They are
//! resampled on a regular grid in (θ, φ), θ the angle from the κ̂ axis and φ = atan2(ω̂, τ̂), by
//! inverse-square-angle weighting of the four nearest records within 2.5 lattice spacings
//! (spacing √(2π/N) on the half-sphere); grid points with no record in reach (outside a
//! quarter-sphere, say) or next to a record with s* = ∞ are left open. Very large s* (near the
//! degenerate plane κ = 0) are clipped at three times the median for display; the figure says
//! when that happens.
//!
//! # Projection
//! Orthographic, camera in the direction c = (cos e·cos a, cos e·sin a, sin e) of (κ, τ, ω) with
//! azimuth a = −50° from +κ toward +τ and elevation e = 25° (so the camera looks across the
//! boundary's long axis, whose big lobes lie where τ·ω > 0); screen right r = (−sin a, cos a, 0),
//! up u = c × r. Faces are painted far to near (painter's algorithm on the mean depth c·p); world
//! units are equal on all three axes, so the surface is not distorted.

use super::records::BoundaryRow;
use super::style::{self, guard};
use super::{DrawResult, Figure};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::f64::consts::PI;
use std::path::Path;

type P3 = [f64; 3];

const N_THETA: usize = 24;
/// Camera azimuth from +κ toward +τ (deg): looking from τ < 0, across the boundary's long
/// axis (its big lobes lie where τ·ω > 0).
const CAMERA_AZIMUTH_DEG: f64 = -50.0;
/// Camera elevation above the κ-τ plane (deg).
const CAMERA_ELEVATION_DEG: f64 = 25.0;
/// A multiple of 4 so that φ = 0 and φ = 90° (the cut planes) are grid lines.
const N_PHI: usize = 96;
/// Largest number of records used for resampling (a regular stride through the rows).
const MAX_SAMPLES: usize = 6000;

/// Render the boundary surface of `rows` into `out`.
pub fn render(rows: &[BoundaryRow], out: &Path) -> Result<()> {
    let finite: Vec<&BoundaryRow> = rows.iter().filter(|r| r.s_star.is_finite()).collect();
    if finite.len() < 3 {
        return Err(Error::invalid(
            "boundary",
            format!("{} rows", rows.len()),
            format!(
                "the surface needs at least three directions with finite s*; found {}",
                finite.len()
            ),
        ));
    }
    let mut s_sorted: Vec<f64> = finite.iter().map(|r| r.s_star).collect();
    s_sorted.sort_by(f64::total_cmp);
    let median = s_sorted[s_sorted.len() / 2];
    let s_min = s_sorted[0];
    let cap = (3.0 * median).min(*s_sorted.last().unwrap_or(&median));
    let clipped = s_sorted.iter().filter(|s| **s > cap).count();
    let n_inf = rows.len() - finite.len();

    let stride = rows.len().div_ceil(MAX_SAMPLES).max(1);
    let samples: Vec<(P3, f64)> = rows
        .iter()
        .step_by(stride)
        .map(|r| ([r.dir.kappa, r.dir.tau, r.dir.omega], r.s_star))
        .collect();
    let grid = resample(&samples, cap);
    let method = rows
        .iter()
        .map(|r| r.method.as_str())
        .find(|m| !m.is_empty())
        .unwrap_or("")
        .to_string();
    super::save(
        &Boundary3d {
            grid,
            s_min,
            cap,
            clipped,
            n_inf,
            n_rows: rows.len(),
            method,
        },
        out,
    )
}

/// Resample scattered `(direction, s*)` records on the (θ, φ) grid (row-major, θ slow), each
/// vertex the point s·u and its value s (clipped at `cap`); `None` where no record is in reach
/// or a neighbour is unstable (s* = ∞). See the module docs.
fn resample(samples: &[(P3, f64)], cap: f64) -> Vec<Option<(P3, f64)>> {
    let spacing = (2.0 * PI / samples.len() as f64).sqrt();
    let reach = (2.5 * spacing).max(1.2 * (PI / 2.0) / N_THETA as f64);

    // Resample on the (θ, φ) grid.
    let mut grid = vec![None; (N_THETA + 1) * (N_PHI + 1)];
    let mut near: Vec<(f64, f64)> = Vec::with_capacity(8);
    for i in 0..=N_THETA {
        let th = 0.5 * PI * i as f64 / N_THETA as f64;
        for j in 0..=N_PHI {
            let ph = -PI + 2.0 * PI * j as f64 / N_PHI as f64;
            let u = [th.cos(), th.sin() * ph.cos(), th.sin() * ph.sin()];
            near.clear();
            for (d, s) in samples {
                let dot = (u[0] * d[0] + u[1] * d[1] + u[2] * d[2]).clamp(-1.0, 1.0);
                let ang = dot.acos();
                if ang <= reach {
                    near.push((ang, *s));
                }
            }
            near.sort_by(|a, b| a.0.total_cmp(&b.0));
            near.truncate(4);
            if near.is_empty() || near.iter().any(|n| !n.1.is_finite()) {
                continue;
            }
            let (mut wsum, mut vsum) = (0.0, 0.0);
            for (a, s) in &near {
                let w = 1.0 / (a * a + guard::SPAN_FLOOR);
                wsum += w;
                vsum += w * s.min(cap);
            }
            let s = vsum / wsum;
            grid[i * (N_PHI + 1) + j] = Some([s * u[0], s * u[1], s * u[2]]).map(|p| (p, s));
        }
    }
    grid
}

struct Boundary3d {
    grid: Vec<Option<(P3, f64)>>,
    s_min: f64,
    cap: f64,
    clipped: usize,
    n_inf: usize,
    n_rows: usize,
    method: String,
}

struct Camera {
    c: P3,
    r: P3,
    u: P3,
    scale: f64,
    ox: f64,
    oy: f64,
}

fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Camera {
    fn new() -> Camera {
        let (a, e) = (
            CAMERA_AZIMUTH_DEG.to_radians(),
            CAMERA_ELEVATION_DEG.to_radians(),
        );
        let c = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
        let r = [-a.sin(), a.cos(), 0.0];
        // u = c × r
        let u = [
            c[1] * r[2] - c[2] * r[1],
            c[2] * r[0] - c[0] * r[2],
            c[0] * r[1] - c[1] * r[0],
        ];
        Camera {
            c,
            r,
            u,
            scale: 1.0,
            ox: 0.0,
            oy: 0.0,
        }
    }
    fn screen(&self, p: P3) -> (f64, f64) {
        (dot(p, self.r), dot(p, self.u))
    }
    fn px(&self, p: P3) -> (i32, i32) {
        let (x, y) = self.screen(p);
        (
            (self.ox + self.scale * x).round() as i32,
            (self.oy - self.scale * y).round() as i32,
        )
    }
    fn depth(&self, p: P3) -> f64 {
        dot(p, self.c)
    }
}

enum Face {
    Surface([P3; 4], f64),
    Cut([P3; 3]),
}

impl Figure for Boundary3d {
    fn size(&self) -> (u32, u32) {
        (1300, 1020)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let font = |s: f64| style::text(s);
        let at = |h, v| Pos::new(h, v);
        let title = format!(
            "Stability boundary s*·S in (κ, τ, ω){}",
            if self.method.is_empty() {
                String::new()
            } else {
                format!(" — {}", self.method)
            }
        );
        root.draw(&Text::new(
            title,
            (650, 28),
            font(style::TITLE).pos(at(HPos::Center, VPos::Center)),
        ))?;

        let mut cam = Camera::new();
        // The cut wedge: the quadrant of φ = atan2(ω̂, τ̂) that faces the camera.
        let phi_cam = cam.c[2].atan2(cam.c[1]);
        let quadrant = (((phi_cam + PI) / (0.5 * PI)).floor() as usize).min(3);
        let (j_cut0, j_cut1) = (quadrant * N_PHI / 4, (quadrant + 1) * N_PHI / 4);
        let in_wedge = |j: usize| j > j_cut0 && j < j_cut1;
        let g = |i: usize, j: usize| self.grid[i * (N_PHI + 1) + j];

        // Box extents from what is drawn (the surface outside the wedge, and the origin).
        let mut lo = [0.0f64; 3];
        let mut hi = [0.0f64; 3];
        for i in 0..=N_THETA {
            for j in (0..=N_PHI).filter(|j| !in_wedge(*j)) {
                if let Some((p, _)) = g(i, j) {
                    for a in 0..3 {
                        lo[a] = lo[a].min(p[a]);
                        hi[a] = hi[a].max(p[a]);
                    }
                }
            }
        }
        for a in 0..3 {
            let pad = 0.05 * (hi[a] - lo[a]).max(guard::MIN_LAYOUT);
            hi[a] += pad;
            if a > 0 {
                lo[a] -= pad;
            }
        }
        let corners: Vec<P3> = (0..8)
            .map(|m| {
                [
                    if m & 1 == 0 { lo[0] } else { hi[0] },
                    if m & 2 == 0 { lo[1] } else { hi[1] },
                    if m & 4 == 0 { lo[2] } else { hi[2] },
                ]
            })
            .collect();
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in &corners {
            let (x, y) = cam.screen(*p);
            x0 = x0.min(x);
            x1 = x1.max(x);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
        // Plot region (px) left of the colour bar, with room for tick labels and axis titles.
        let (rx0, rx1, ry0, ry1) = (120.0, 1000.0, 80.0, 830.0);
        cam.scale = ((rx1 - rx0) / (x1 - x0)).min((ry1 - ry0) / (y1 - y0));
        cam.ox = 0.5 * (rx0 + rx1) - cam.scale * 0.5 * (x0 + x1);
        cam.oy = 0.5 * (ry0 + ry1) + cam.scale * 0.5 * (y0 + y1);

        // Back faces of the box with grid lines.
        let ticks = [
            style::nice_ticks(lo[0], hi[0], 5),
            style::nice_ticks(lo[1], hi[1], 6),
            style::nice_ticks(lo[2], hi[2], 6),
        ];
        for axis in 0..3 {
            // The face perpendicular to `axis` on the side away from the camera.
            let v = if cam.c[axis] > 0.0 {
                lo[axis]
            } else {
                hi[axis]
            };
            let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
            let pt = |sa: f64, sb: f64| {
                let mut p = [0.0; 3];
                p[axis] = v;
                p[a] = sa;
                p[b] = sb;
                p
            };
            let face = vec![
                cam.px(pt(lo[a], lo[b])),
                cam.px(pt(hi[a], lo[b])),
                cam.px(pt(hi[a], hi[b])),
                cam.px(pt(lo[a], hi[b])),
            ];
            root.draw(&Polygon::new(
                face.clone(),
                RGBColor(0xf6, 0xf6, 0xf6).filled(),
            ))?;
            for &t in &ticks[a] {
                root.draw(&PathElement::new(
                    vec![cam.px(pt(t, lo[b])), cam.px(pt(t, hi[b]))],
                    style::LIGHT_GREY.stroke_width(1),
                ))?;
            }
            for &t in &ticks[b] {
                root.draw(&PathElement::new(
                    vec![cam.px(pt(lo[a], t)), cam.px(pt(hi[a], t))],
                    style::LIGHT_GREY.stroke_width(1),
                ))?;
            }
            let mut closed = face;
            closed.push(closed[0]);
            root.draw(&PathElement::new(closed, style::GREY.stroke_width(1)))?;
        }

        // Faces: the surface outside the cut wedge, and the two cut faces.
        let mut faces: Vec<(f64, Face)> = Vec::new();
        for i in 0..N_THETA {
            for j in 0..N_PHI {
                if j >= j_cut0 && j < j_cut1 {
                    continue;
                }
                let (Some(a), Some(b), Some(c), Some(d)) =
                    (g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1))
                else {
                    continue;
                };
                let quad = [a.0, b.0, c.0, d.0];
                let depth = quad.iter().map(|p| cam.depth(*p)).sum::<f64>() / 4.0;
                faces.push((depth, Face::Surface(quad, 0.25 * (a.1 + b.1 + c.1 + d.1))));
            }
        }
        let mut have_cut = false;
        for j in [j_cut0, j_cut1] {
            for i in 0..N_THETA {
                if let (Some(a), Some(b)) = (g(i, j), g(i + 1, j)) {
                    let tri = [[0.0; 3], a.0, b.0];
                    let depth = tri.iter().map(|p| cam.depth(*p)).sum::<f64>() / 3.0;
                    faces.push((depth, Face::Cut(tri)));
                    have_cut = true;
                }
            }
        }
        faces.sort_by(|a, b| a.0.total_cmp(&b.0));
        let cut_fill = style::lighten(style::SKY_BLUE, 0.55);
        let span = (self.cap - self.s_min).max(guard::SPAN_FLOOR);
        for (_, f) in &faces {
            match f {
                Face::Surface(q, s) => {
                    let col = style::viridis((s - self.s_min) / span);
                    let poly: Vec<(i32, i32)> = q.iter().map(|p| cam.px(*p)).collect();
                    root.draw(&Polygon::new(poly.clone(), col.filled()))?;
                    let mut closed = poly;
                    closed.push(closed[0]);
                    root.draw(&PathElement::new(
                        closed,
                        style::darken(col, 0.15).stroke_width(1),
                    ))?;
                }
                Face::Cut(t) => {
                    let poly: Vec<(i32, i32)> = t.iter().map(|p| cam.px(*p)).collect();
                    root.draw(&Polygon::new(poly.clone(), cut_fill.filled()))?;
                    // Outline only the outer (boundary) edge of the fan.
                    root.draw(&PathElement::new(
                        vec![poly[1], poly[2]],
                        style::BLACK.stroke_width(2),
                    ))?;
                }
            }
        }

        // The origin and the stable side.
        let o = cam.px([0.0; 3]);
        root.draw(&Circle::new(o, 7, style::BLACK.filled()))?;
        if have_cut {
            // "stable" at the screen centroid of the larger cut face.
            let mut best: Option<(f64, (i32, i32))> = None;
            for j in [j_cut0, j_cut1] {
                let mut poly = vec![o];
                poly.extend((0..=N_THETA).filter_map(|i| g(i, j)).map(|p| cam.px(p.0)));
                let n = poly.len();
                let area = 0.5
                    * (0..n)
                        .map(|k| {
                            let (a, b) = (poly[k], poly[(k + 1) % n]);
                            a.0 as f64 * b.1 as f64 - b.0 as f64 * a.1 as f64
                        })
                        .sum::<f64>()
                        .abs();
                let cx = poly.iter().map(|p| p.0 as f64).sum::<f64>() / n as f64;
                let cy = poly.iter().map(|p| p.1 as f64).sum::<f64>() / n as f64;
                if best.is_none_or(|b| area > b.0) {
                    best = Some((area, (cx as i32, cy as i32)));
                }
            }
            if let Some((_, c)) = best {
                root.draw(&Text::new(
                    "stable".to_string(),
                    c,
                    font(style::AXIS).pos(at(HPos::Center, VPos::Center)),
                ))?;
            }
        }
        root.draw(&Text::new(
            "straight rod".to_string(),
            (o.0 - 14, o.1),
            font(style::LEGEND).pos(at(HPos::Right, VPos::Center)),
        ))?;

        // Box edges toward the viewer carry the tick labels.
        let front = |axis: usize| {
            if cam.c[axis] > 0.0 {
                hi[axis]
            } else {
                lo[axis]
            }
        };
        let back = |axis: usize| {
            if cam.c[axis] > 0.0 {
                lo[axis]
            } else {
                hi[axis]
            }
        };
        let tick_font = font(style::TICK);
        let label_axis = |axis: usize, fixed: P3, outward: P3, name: &str| -> DrawResult<DB> {
            let (dx, dy) = cam.screen(outward);
            let n = dx.hypot(dy).max(guard::SPAN_FLOOR);
            let (dx, dy) = (dx / n, -dy / n);
            let anchor_h = if dx > 0.3 {
                HPos::Left
            } else if dx < -0.3 {
                HPos::Right
            } else {
                HPos::Center
            };
            let anchor_v = if dy > 0.3 {
                VPos::Top
            } else if dy < -0.3 {
                VPos::Bottom
            } else {
                VPos::Center
            };
            for &t in &ticks[axis] {
                let mut p = fixed;
                p[axis] = t;
                let (x, y) = cam.px(p);
                root.draw(&PathElement::new(
                    vec![(x, y), (x + (8.0 * dx) as i32, y + (8.0 * dy) as i32)],
                    style::BLACK.stroke_width(1),
                ))?;
                root.draw(&Text::new(
                    style::tick_label(t),
                    (x + (14.0 * dx) as i32, y + (14.0 * dy) as i32),
                    tick_font.clone().pos(at(anchor_h, anchor_v)),
                ))?;
            }
            let mut p = fixed;
            p[axis] = 0.5 * (lo[axis] + hi[axis]);
            let (x, y) = cam.px(p);
            let title = if axis == 2 {
                // Vertical axis: the title runs upward beside the tick labels.
                font(style::AXIS)
                    .transform(FontTransform::Rotate270)
                    .pos(at(HPos::Center, VPos::Center))
            } else {
                font(style::AXIS).pos(at(anchor_h, anchor_v))
            };
            let off = if axis == 2 { 75.0 } else { 60.0 };
            root.draw(&Text::new(
                name.to_string(),
                (x + (off * dx) as i32, y + (off * dy) as i32),
                title,
            ))?;
            let mut a = fixed;
            a[axis] = lo[axis];
            let mut b = fixed;
            b[axis] = hi[axis];
            root.draw(&PathElement::new(
                vec![cam.px(a), cam.px(b)],
                style::BLACK.stroke_width(2),
            ))
        };
        let sgn = |axis: usize| if cam.c[axis] > 0.0 { 1.0 } else { -1.0 };
        label_axis(
            0,
            [0.0, front(1), back(2)],
            [0.0, sgn(1), -sgn(2)],
            "curvature κ",
        )?;
        label_axis(
            1,
            [front(0), 0.0, back(2)],
            [sgn(0), 0.0, -sgn(2)],
            "torsion τ",
        )?;
        // ω on the vertical edge that is rightmost on screen.
        let edge = [
            (lo[0], lo[1]),
            (lo[0], hi[1]),
            (hi[0], lo[1]),
            (hi[0], hi[1]),
        ]
        .into_iter()
        .max_by(|a, b| {
            cam.screen([a.0, a.1, 0.0])
                .0
                .total_cmp(&cam.screen([b.0, b.1, 0.0]).0)
        })
        .unwrap_or((lo[0], hi[1]));
        label_axis(
            2,
            [edge.0, edge.1, 0.0],
            [cam.r[0], cam.r[1], 0.0],
            "twisting moment ω",
        )?;

        // Colour bar.
        // Beside the box's right edge (after the ω tick labels and title), at most at 1170 px.
        let box_right = corners.iter().map(|p| cam.px(*p).0).max().unwrap_or(1000);
        let bx0 = (box_right + 190).min(1170);
        let (bx1, by0, by1) = (bx0 + 30, 140, 760);
        for k in 0..(by1 - by0) {
            let t = 1.0 - k as f64 / (by1 - by0) as f64;
            root.draw(&PathElement::new(
                vec![(bx0, by0 + k), (bx1, by0 + k)],
                style::viridis(t).stroke_width(1),
            ))?;
        }
        root.draw(&Rectangle::new(
            [(bx0, by0), (bx1, by1)],
            style::BLACK.stroke_width(1),
        ))?;
        for t in style::nice_ticks(self.s_min, self.cap, 5) {
            let y = by1
                - ((t - self.s_min) / (self.cap - self.s_min).max(guard::SPAN_FLOOR)
                    * (by1 - by0) as f64)
                    .round() as i32;
            root.draw(&PathElement::new(
                vec![(bx1, y), (bx1 + 6, y)],
                style::BLACK.stroke_width(1),
            ))?;
            root.draw(&Text::new(
                style::tick_label(t),
                (bx1 + 10, y),
                tick_font.clone().pos(at(HPos::Left, VPos::Center)),
            ))?;
        }
        root.draw(&Text::new(
            "s*".to_string(),
            ((bx0 + bx1) / 2, by0 - 36),
            font(style::AXIS).pos(at(HPos::Center, VPos::Center)),
        ))?;

        // Footnotes.
        let mut notes = vec![format!(
            "{} directions; cut open at τ {} 0, ω {} 0 to show the stable side (shaded)",
            self.n_rows,
            if quadrant == 1 || quadrant == 2 {
                ">"
            } else {
                "<"
            },
            if quadrant >= 2 { ">" } else { "<" }
        )];
        if self.clipped > 0 {
            notes.push(format!(
                "{} with s* > {:.1} (3× median) drawn at {:.1}",
                plural(self.clipped, "direction"),
                self.cap,
                self.cap
            ));
        }
        if self.n_inf > 0 {
            notes.push(format!(
                "{} stable up to the search limit (s* = ∞): left open",
                plural(self.n_inf, "direction")
            ));
        }
        for (k, n) in notes.iter().enumerate() {
            root.draw(&Text::new(
                n.clone(),
                (30, 920 + 28 * k as i32),
                font(style::LEGEND * 0.85).pos(at(HPos::Left, VPos::Center)),
            ))?;
        }
        Ok(())
    }
}

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(n: usize, f: impl Fn(P3) -> f64) -> Vec<(P3, f64)> {
        crate::directions::fibonacci(n, false)
            .unwrap()
            .iter()
            .map(|d| {
                let u = [d.kappa, d.tau, d.omega];
                (u, f(u))
            })
            .collect()
    }

    #[test]
    fn resampling_reproduces_smooth_fields() {
        // A constant s* is a hemisphere of that radius: every vertex exactly on it.
        let grid = resample(&samples(2000, |_| 5.0), 100.0);
        assert!(
            grid.iter().all(|g| g.is_some()),
            "holes in a full half-sphere"
        );
        for (p, s) in grid.iter().flatten() {
            assert!((dot(*p, *p).sqrt() - 5.0).abs() < 1e-12 && (s - 5.0).abs() < 1e-12);
        }
        // A smooth field is interpolated to within the lattice resolution (spacing ≈ 0.056 rad,
        // so a field of slope 2 per radian may be off by about 0.1 at most).
        let f = |u: P3| 6.0 + 2.0 * u[0] + u[2];
        let grid = resample(&samples(2000, f), 100.0);
        for i in 0..=N_THETA {
            for j in 0..=N_PHI {
                let (p, s) = grid[i * (N_PHI + 1) + j].unwrap();
                let u = [p[0] / s, p[1] / s, p[2] / s];
                assert!((s - f(u)).abs() < 0.1, "vertex ({i},{j}): {s} vs {}", f(u));
            }
        }
    }

    #[test]
    fn quarter_data_leaves_the_other_quarter_open_and_inf_makes_holes() {
        let q: Vec<(P3, f64)> = crate::directions::fibonacci(1000, true)
            .unwrap()
            .iter()
            .map(|d| {
                (
                    [d.kappa, d.tau, d.omega],
                    if d.omega > 0.9 { f64::INFINITY } else { 7.0 },
                )
            })
            .collect();
        let grid = resample(&q, 100.0);
        for i in 1..=N_THETA {
            for j in 0..=N_PHI {
                let phi = -PI + 2.0 * PI * j as f64 / N_PHI as f64;
                let th = 0.5 * PI * i as f64 / N_THETA as f64;
                let tau = th.sin() * phi.cos();
                let omega = th.sin() * phi.sin();
                let v = grid[i * (N_PHI + 1) + j];
                if tau < -0.2 || omega > 0.95 {
                    assert!(
                        v.is_none(),
                        "vertex ({i},{j}) τ̂={tau} ω̂={omega} should be open"
                    );
                }
                if tau > 0.2 && omega < 0.8 {
                    assert!(
                        v.is_some(),
                        "vertex ({i},{j}) τ̂={tau} ω̂={omega} should be drawn"
                    );
                }
            }
        }
    }
}
