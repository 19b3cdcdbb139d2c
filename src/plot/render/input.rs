//! The trajectory to render: the CSV that `helixreach plan` writes, checked against the rig, and
//! the choice of frames.
//!
//! # Columns
//! The robot's joints by their URDF names (any order), or `q0..q{n−1}` (the index header:
//! exactly the robot's count), and `s`, `kappa`, `tau`, `omega` are required; `t`, `motor`, `x,y,z` (the rod end in the base frame), `azimuth` and `phase`
//! (`load`, `reconfigure`, `hold`, `unload`) are used when present. Every value used must be
//! finite; an error names the file, the line and the field. At most
//! [`MAX_TRAJECTORY_ROWS`](crate::limits::MAX_TRAJECTORY_ROWS) rows (the one trajectory reader,
//! `records::trajectory`).
//!
//! # The helix of a row
//! The rod is the helix (κ, τ, ω) of the row on the rig's clamp, turned by the azimuth α about
//! the clamp tangent. α is the `azimuth` column when present; else it is recovered from the rod
//! end `x,y,z`: in the clamp frame the end is `Rz(α)·r(1)·L`, so α is the angle between the
//! horizontal parts of the measured and the unturned end, taken at the row where that part is
//! longest; else it is the caller's value (default 0). Every row's `x,y,z` must then lie within
//! [`END_TOLERANCE`] of the helix end, and the arm's tool (FK of the row's joints) within
//! [`END_TOLERANCE`] of it too — a trajectory planned for another clamp, rig or robot is refused,
//! never drawn wrong.
//!
//! # Frames
//! The default strip shows the first rows (in time order) where s reaches 0, ¼, ½, ¾ and 1 of s*,
//! the last row, and the middle row of every reconfiguration (a run of `phase = reconfigure`
//! rows, or, without the column, of rows at constant s whose joints move). A path with more
//! reconfigurations than the strip has room for ([`MAX_STRIP_FRAMES`] frames) shows an even
//! subset of them, the first and the last included, each labelled `reconfigure k of N`. s* is given, or the
//! continuum boundary along the trajectory's direction. `--frames N` instead takes N rows evenly
//! spaced in time (in row order without `t`).

use crate::error::{Error, Result};
use crate::io::bad_line;
use crate::math::{Real, Vec3};
use crate::plot::style::guard;
use crate::records::trajectory::read_trajectory_file;
use std::path::Path;

/// Largest distance (m) between a row's rod end and the helix end on the rig, and between the
/// arm's tool and the rod end.
pub const END_TOLERANCE: Real = 1e-3;
/// Most frames in a strip.
pub const MAX_STRIP_FRAMES: usize = 32;
/// Most frames in a GIF.
pub const MAX_GIF_FRAMES: usize = 2000;

pub use crate::planning::trajectory::Phase;

/// One row of a trajectory CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// 1-based line in the file.
    pub line: usize,
    /// Time (s); the row index when the file has no `t`.
    pub t: Real,
    /// Joint angles (rad).
    pub q: Vec<Real>,
    /// Motor angle (rad; NaN without the column).
    pub motor: Real,
    /// Distance along the ray.
    pub s: Real,
    /// (κ, τ, ω).
    pub kto: [Real; 3],
    /// Rod end (base frame), when the file has `x,y,z`.
    pub end: Option<Vec3>,
    /// Azimuth column, when present.
    pub azimuth: Option<Real>,
    /// Phase, when the file has the column.
    pub phase: Option<Phase>,
}

/// Read a trajectory CSV for a robot with `joint_names` (see the module docs): the one
/// trajectory reader ([`crate::records::trajectory::read_trajectory_file`]) with `s` and
/// `kappa,tau,omega` required.
pub fn read_trajectory(path: &Path, joint_names: &[String], robot: &str) -> Result<Vec<Row>> {
    let t = read_trajectory_file(path, joint_names, robot)?;
    let missing = |name: &str| {
        t.file_error(format!(
            "missing column `{name}` (a trajectory CSV as `helixreach plan` writes)"
        ))
    };
    let s = t.s.as_ref().ok_or_else(|| missing("s"))?;
    let kto = t.kto.as_ref().ok_or_else(|| missing("kappa,tau,omega"))?;
    Ok((0..t.rows())
        .map(|i| Row {
            line: t.lines[i],
            t: t.t.as_ref().map_or(i as Real, |v| v[i]),
            q: t.row(i).to_vec(),
            motor: t.motor.as_ref().map_or(Real::NAN, |v| v[i]),
            s: s[i],
            kto: kto[i],
            end: t.end.as_ref().map(|v| v[i]),
            azimuth: t.azimuth.as_ref().map(|v| v[i]),
            phase: t.phase.as_ref().map(|v| v[i]),
        })
        .collect())
}

/// Which rows to draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrameSelection {
    /// s = 0, ¼, ½, ¾, 1 of s* (s* given, or the continuum boundary), the end, every
    /// reconfiguration.
    Default {
        /// s* along the ray; `None` = the continuum boundary of the trajectory's direction.
        s_star: Option<Real>,
    },
    /// N rows evenly spaced in time.
    Even(usize),
}

/// A chosen frame: the row index and why it was chosen.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameChoice {
    /// Index into the rows.
    pub row: usize,
    /// Why (`s = ½ s*`, `end`, `reconfigure`, `t = 3.2 s`).
    pub label: String,
}

/// Whether row `i` is part of a reconfiguration (see the module docs).
fn reconfiguring(rows: &[Row], i: usize) -> bool {
    match rows[i].phase {
        Some(p) => p == Phase::Reconfigure,
        None => {
            i > 0
                && rows[i].s == rows[i - 1].s
                && rows[i]
                    .q
                    .iter()
                    .zip(&rows[i - 1].q)
                    .any(|(a, b)| (a - b).abs() > guard::SAME)
        }
    }
}

/// s* of the ray the rows follow (the continuum boundary along the direction of the row with the
/// largest s).
pub fn s_star_of_rows(rows: &[Row]) -> Result<Real> {
    let far = rows
        .iter()
        .max_by(|a, b| a.s.total_cmp(&b.s))
        .filter(|r| r.s > 0.0)
        .ok_or_else(|| {
            Error::invalid(
                "trajectory",
                "s = 0 on every row",
                "no direction to take s* from (pass s* explicitly)",
            )
        })?;
    let k = far.kto;
    let dir = crate::directions::Direction::new(k[0], k[1], k[2])?;
    crate::sweep::reach::s_star_of(&dir, None)
}

/// `n` indices evenly spaced in time over `rows` (nearest row to each time; deduplicated).
pub fn even_rows(rows: &[Row], n: usize) -> Vec<usize> {
    let (t0, t1) = (rows[0].t, rows[rows.len() - 1].t);
    let mut out: Vec<usize> = Vec::with_capacity(n);
    let mut j = 0;
    for k in 0..n {
        let tk = if n == 1 {
            t1
        } else {
            t0 + (t1 - t0) * k as Real / (n - 1) as Real
        };
        while j + 1 < rows.len() && (rows[j + 1].t - tk).abs() <= (rows[j].t - tk).abs() {
            j += 1;
        }
        if out.last() != Some(&j) {
            out.push(j);
        }
    }
    out
}

/// Choose the frames of a strip (see the module docs): at most [`MAX_STRIP_FRAMES`]. Errors on
/// `Even(0)` or more than [`MAX_STRIP_FRAMES`] even frames, and when s* cannot be found.
pub fn select_frames(rows: &[Row], sel: FrameSelection) -> Result<Vec<FrameChoice>> {
    if rows.is_empty() {
        return Err(Error::invalid("trajectory", "0 rows", "nothing to render"));
    }
    let mut out: Vec<FrameChoice> = Vec::new();
    match sel {
        FrameSelection::Even(n) => {
            if n == 0 || n > MAX_STRIP_FRAMES {
                return Err(Error::invalid(
                    "frames",
                    n,
                    format!("must be between 1 and {MAX_STRIP_FRAMES}"),
                ));
            }
            for i in even_rows(rows, n) {
                out.push(FrameChoice {
                    row: i,
                    label: format!("t = {:.1} s", rows[i].t),
                });
            }
        }
        FrameSelection::Default { s_star } => {
            let s_star = match s_star {
                Some(s) if s.is_finite() && s > 0.0 => s,
                Some(s) => return Err(Error::invalid("s_star", s, "must be finite and > 0")),
                None => s_star_of_rows(rows)?,
            };
            const NAMES: [&str; 5] = ["0", "¼ s*", "½ s*", "¾ s*", "s*"];
            for (k, name) in NAMES.iter().enumerate() {
                let target = s_star * k as Real / 4.0;
                if let Some(i) = rows
                    .iter()
                    .position(|r| r.s >= target * (1.0 - guard::SAME))
                {
                    out.push(FrameChoice {
                        row: i,
                        label: format!("s = {name}"),
                    });
                }
            }
            out.push(FrameChoice {
                row: rows.len() - 1,
                label: "end".into(),
            });
            // The middle row of every reconfiguration; past the strip's room, an even subset
            // (first and last kept), each labelled with its rank.
            let mut middles = Vec::new();
            let mut i = 0;
            while i < rows.len() {
                if reconfiguring(rows, i) {
                    let start = i;
                    while i + 1 < rows.len() && reconfiguring(rows, i + 1) {
                        i += 1;
                    }
                    middles.push((start + i) / 2);
                }
                i += 1;
            }
            let room = MAX_STRIP_FRAMES - out.len();
            let n = middles.len();
            if n <= room {
                out.extend(middles.into_iter().map(|row| FrameChoice {
                    row,
                    label: "reconfigure".into(),
                }));
            } else {
                for j in 0..room {
                    let k = if room == 1 {
                        0
                    } else {
                        j * (n - 1) / (room - 1)
                    };
                    out.push(FrameChoice {
                        row: middles[k],
                        label: format!("reconfigure {} of {n}", k + 1),
                    });
                }
            }
            out.sort_by_key(|f| f.row);
            // One frame per row: join the labels.
            let mut merged: Vec<FrameChoice> = Vec::new();
            for f in out {
                match merged.last_mut() {
                    Some(m) if m.row == f.row => {
                        m.label = format!("{}, {}", m.label, f.label);
                    }
                    _ => merged.push(f),
                }
            }
            out = merged;
        }
    }
    Ok(out)
}

/// [`resolve_azimuth`] recovers the azimuth from the rod ends only when the helix end's offset
/// from the clamp axis exceeds this (units of L; a straight rod has no azimuth to see).
const MIN_END_OFFSET: Real = 1e-6;

/// A recovered azimuth smaller than this (rad) is round-off and shown as 0.
const ZERO_AZIMUTH: Real = 1e-12;

/// The azimuth of the rows on `scene`'s rig (see the module docs): the `azimuth` column, else
/// recovered from the rod ends, else `fallback`.
pub fn resolve_azimuth(scene: &super::Scene, rows: &[Row], fallback: Real) -> Result<Real> {
    if let Some(a) = rows[0].azimuth {
        return Ok(a);
    }
    let rig = scene.rig();
    let rc = rig.clamp_rotation();
    let oc = rig.clamp.translation.vector;
    let mut best: Option<(Real, Real)> = None; // (|e_xy|, α)
    for r in rows {
        let Some(p) = r.end else { continue };
        let h = crate::helix::Helix::new(r.kto[0], r.kto[1], r.kto[2])?;
        let e = h.position(1.0);
        let m = e.x.hypot(e.y);
        if best.is_none_or(|b| m > b.0) {
            let local = rc.transpose() * (p - oc) / rig.rod.length;
            let a = local.y.atan2(local.x) - e.y.atan2(e.x);
            best = Some((m, a.sin().atan2(a.cos())));
        }
    }
    Ok(match best {
        // Round-off around 0 is 0 (no "−0.000" in titles).
        Some((m, a)) if m > MIN_END_OFFSET => {
            if a.abs() < ZERO_AZIMUTH {
                0.0
            } else {
                a
            }
        }
        _ => fallback,
    })
}

/// Check that every row belongs to `scene`'s rig at azimuth `azimuth`: the row's rod end (if
/// given) within [`END_TOLERANCE`] of the helix end, and the arm's tool (FK) within
/// [`END_TOLERANCE`] of the rod end. The error names the file, line and distance.
pub fn check_rows(scene: &super::Scene, rows: &[Row], azimuth: Real, path: &Path) -> Result<()> {
    for r in rows {
        let nodes = scene.rod_nodes(r.kto, azimuth, 1)?;
        let end = nodes[1];
        if let Some(p) = r.end {
            let d = (p - end).norm();
            if d > END_TOLERANCE {
                return Err(bad_line(
                    path,
                    r.line,
                    "x,y,z",
                    format!(
                        "the rod end ({:.4}, {:.4}, {:.4}) is {d:.4} m from the end of the helix \
                         (κ, τ, ω) = ({}, {}, {}) on rig {} at azimuth {azimuth:.4} rad: the \
                         trajectory was planned for another rig or clamp",
                        p.x,
                        p.y,
                        p.z,
                        r.kto[0],
                        r.kto[1],
                        r.kto[2],
                        scene.rig().name
                    ),
                ));
            }
        }
        let tool = scene
            .model()
            .link_frames(&r.q)
            .map_err(|e| bad_line(path, r.line, "q", e.to_string()))?[scene.model().tip_index()]
        .mul(&crate::robot::Frame::from_iso(&scene.rig().tool))
        .pos;
        let d = (tool - end).norm();
        if d > END_TOLERANCE {
            return Err(bad_line(
                path,
                r.line,
                "q",
                format!(
                    "the arm's tool (forward kinematics of {}) is {d:.4} m from the rod end on rig \
                     {}: the trajectory does not hold this rig's rod",
                    scene.model().name(),
                    scene.rig().name
                ),
            ));
        }
    }
    Ok(())
}
