//! The trajectory to render: the CSV that `helixreach plan` writes, checked against the rig, and
//! the choice of frames.
//!
//! # Columns
//! The robot's joints by their URDF names (any order), or `q0..q{n−1}` (the earlier header:
//! exactly the robot's count), and `s`, `kappa`, `tau`, `omega` are required; `t`, `motor`, `x,y,z` (the rod end in the base frame), `azimuth` and `phase`
//! (`load`, `reconfigure`, `hold`, `unload`) are used when present. Every value used must be
//! finite; an error names the file, the line and the field.
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
//! rows, or, without the column, of rows at constant s whose joints move). s* is given, or the
//! continuum boundary along the trajectory's direction. `--frames N` instead takes N rows evenly
//! spaced in time (in row order without `t`).

use crate::error::{Error, Result};
use crate::io::{bad_line, parse_field, CsvInput};
use crate::math::{Real, Vec3};
use crate::plot::style::guard;
use crate::records::trajectory::{joint_columns, MOTOR_COLUMN};
use std::path::Path;

/// Largest distance (m) between a row's rod end and the helix end on the rig, and between the
/// arm's tool and the rod end.
pub const END_TOLERANCE: Real = 1e-3;
/// Most rows read from a trajectory file.
pub const MAX_ROWS: usize = 1_000_000;
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

/// Read a trajectory CSV for a robot with `joint_names` (see the module docs).
pub fn read_trajectory(path: &Path, joint_names: &[String], robot: &str) -> Result<Vec<Row>> {
    let mut csv = CsvInput::open(path)?;
    let dof = joint_names.len();
    let header: Vec<String> = csv
        .reader
        .headers()
        .map_or_else(|_| Vec::new(), |h| h.iter().map(str::to_string).collect());
    let iq = match joint_columns(&header, joint_names) {
        Some((iq, _)) if iq.len() == dof => iq,
        Some((iq, _)) => {
            return Err(csv.file_error(format!(
                "has {} joint columns (q0..q{}) but robot {robot} has {dof} joints ({}): the \
                 trajectory is for another robot",
                iq.len(),
                iq.len().saturating_sub(1),
                joint_names.join(",")
            )))
        }
        None => {
            return Err(csv.file_error(format!(
                "names neither the {dof} joints of robot {robot} ({}) nor q0..q{}: the \
                 trajectory is for another robot (header: {})",
                joint_names.join(","),
                dof.saturating_sub(1),
                header.join(",")
            )))
        }
    };
    let qnames: Vec<&str> = iq.iter().map(|&c| header[c].as_str()).collect();
    let hint = "a trajectory CSV as `helixreach plan` writes";
    let is = csv.column("s", hint)?;
    let ik = [
        csv.column("kappa", hint)?,
        csv.column("tau", hint)?,
        csv.column("omega", hint)?,
    ];
    let opt = |n: &str| csv.column(n, "").ok();
    let it = opt("t");
    let im = opt(MOTOR_COLUMN);
    let ia = opt("azimuth");
    let iph = opt("phase");
    let ixyz = match (opt("x"), opt("y"), opt("z")) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        _ => None,
    };
    let mut rows = Vec::new();
    let mut rec = csv::StringRecord::new();
    loop {
        let more = csv
            .reader
            .read_record(&mut rec)
            .map_err(|e| csv.file_error(e.to_string()))?;
        if !more {
            break;
        }
        let line = rec.position().map_or(rows.len() + 2, |p| p.line() as usize);
        if rows.len() >= MAX_ROWS {
            return Err(csv.file_error(format!("more than {MAX_ROWS} rows")));
        }
        let num = |col: usize, name: &str| -> Result<Real> {
            let v = parse_field(path, line, &rec, col, name)?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad_line(path, line, name, format!("`{v}` must be finite")))
            }
        };
        let q = iq
            .iter()
            .enumerate()
            .map(|(j, &c)| num(c, qnames[j]))
            .collect::<Result<Vec<_>>>()?;
        let t = match it {
            Some(c) => num(c, "t")?,
            None => rows.len() as Real,
        };
        let s = num(is, "s")?;
        if s < 0.0 {
            return Err(bad_line(path, line, "s", format!("`{s}` must be >= 0")));
        }
        let kto = [
            num(ik[0], "kappa")?,
            num(ik[1], "tau")?,
            num(ik[2], "omega")?,
        ];
        if kto[0] < 0.0 {
            return Err(bad_line(
                path,
                line,
                "kappa",
                format!("`{}` must be >= 0", kto[0]),
            ));
        }
        let end = match ixyz {
            Some([x, y, z]) => Some(Vec3::new(num(x, "x")?, num(y, "y")?, num(z, "z")?)),
            None => None,
        };
        let phase = match iph {
            Some(c) => {
                let text = rec.get(c).unwrap_or("");
                Some(Phase::parse(text).ok_or_else(|| {
                    bad_line(
                        path,
                        line,
                        "phase",
                        format!("`{text}`: expected load, reconfigure, hold or unload"),
                    )
                })?)
            }
            None => None,
        };
        rows.push(Row {
            line,
            t,
            q,
            motor: match im {
                Some(c) => num(c, MOTOR_COLUMN)?,
                None => Real::NAN,
            },
            s,
            kto,
            end,
            azimuth: match ia {
                Some(c) => Some(num(c, "azimuth")?),
                None => None,
            },
            phase,
        });
    }
    if rows.is_empty() {
        return Err(csv.file_error("no data rows after the header".into()));
    }
    Ok(rows)
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

/// Choose the frames of a strip (see the module docs). Errors on `Even(0)`, on more than
/// [`MAX_STRIP_FRAMES`] frames, and when s* cannot be found.
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
            let mut i = 0;
            while i < rows.len() {
                if reconfiguring(rows, i) {
                    let start = i;
                    while i + 1 < rows.len() && reconfiguring(rows, i + 1) {
                        i += 1;
                    }
                    out.push(FrameChoice {
                        row: (start + i) / 2,
                        label: "reconfigure".into(),
                    });
                }
                i += 1;
            }
            out.push(FrameChoice {
                row: rows.len() - 1,
                label: "end".into(),
            });
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
            if out.len() > MAX_STRIP_FRAMES {
                return Err(Error::invalid(
                    "frames",
                    out.len(),
                    format!(
                        "the default selection (with every reconfiguration) exceeds \
                         {MAX_STRIP_FRAMES} frames; choose --frames N"
                    ),
                ));
            }
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
