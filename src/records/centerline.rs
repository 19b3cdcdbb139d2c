//! The simulated rod's centerline (`helixreach simulate --centerline`): one row per node of every
//! kept configuration, in the rig's base frame (m), with the material frame of the edge that
//! starts at the node, columns [`CenterlineRecord::HEADER`]:
//!
//! - `sample, t, s`: the recorded sample of the series (`--out`) this configuration belongs to
//!   (0-based row index among the series' samples), its time (s) and ray distance;
//! - `node, arc`: node index i (0 … n) and its arc length (m) from the clamp, `(i − ½)·L/(n − 1)`
//!   (the straddling clamps put nodes 0 and n half an edge outside `[0, L]`);
//! - `x, y, z`: the node position;
//! - `m1x … tz`: the material frame `[m¹ m² t]` of edge i (from node i to node i + 1) as three
//!   unit vectors; empty on the last node (no edge starts there).
//!
//! See [`crate::rod::dynamics::centerline`] for the frames and the placement.

use super::csv_out::{self, CsvRecord};
use crate::error::Result;
use crate::math::{Mat3, Real};
use crate::rod::clamp::ClampPlacement;
use crate::rod::dynamics::centerline::{Centerline, Placement};

/// One node of one kept configuration.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CenterlineRecord {
    /// Row index of the sample in the series.
    pub sample: usize,
    /// Time (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Distance along the ray.
    #[serde(serialize_with = "csv_out::real")]
    pub s: Real,
    /// Node index.
    pub node: usize,
    /// Arc length of the node from the clamp (m).
    #[serde(serialize_with = "csv_out::real")]
    pub arc: Real,
    /// Position (base frame, m).
    #[serde(serialize_with = "csv_out::real")]
    pub x: Real,
    #[serde(serialize_with = "csv_out::real")]
    /// A component (see the field above).
    pub y: Real,
    #[serde(serialize_with = "csv_out::real")]
    /// A component (see the field above).
    pub z: Real,
    /// Material frame of the edge starting at this node (base frame), NaN (empty) on the last
    /// node: `m¹`, `m²`, `t`.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub m1x: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub m1y: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub m1z: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub m2x: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub m2y: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub m2z: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub tx: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub ty: Real,
    #[serde(serialize_with = "csv_out::real_or_empty")]
    /// A component (see the field above).
    pub tz: Real,
}

impl CsvRecord for CenterlineRecord {
    const HEADER: &'static [&'static str] = &[
        "sample", "t", "s", "node", "arc", "x", "y", "z", "m1x", "m1y", "m1z", "m2x", "m2y", "m2z",
        "tx", "ty", "tz",
    ];
}

/// The rows of every kept configuration, placed by `placement` (straddling clamps, as the
/// dynamics uses).
pub fn centerline_records(lines: &[Centerline], placement: &Placement) -> Vec<CenterlineRecord> {
    let mut out = Vec::new();
    for c in lines {
        let n = c.frames.len();
        for (i, x) in c.nodes.iter().enumerate() {
            let p = placement.point(x);
            let m = if i < n {
                placement.frame(&c.frames[i])
            } else {
                Mat3::from_element(Real::NAN)
            };
            out.push(CenterlineRecord {
                sample: c.sample,
                t: c.t,
                s: c.s,
                node: i,
                arc: ClampPlacement::Straddle.node_arclength(n, i, placement.length),
                x: p.x,
                y: p.y,
                z: p.z,
                m1x: m[(0, 0)],
                m1y: m[(1, 0)],
                m1z: m[(2, 0)],
                m2x: m[(0, 1)],
                m2y: m[(1, 1)],
                m2z: m[(2, 1)],
                tx: m[(0, 2)],
                ty: m[(1, 2)],
                tz: m[(2, 2)],
            });
        }
    }
    out
}

/// The centerline CSV text.
pub fn centerline_csv(lines: &[Centerline], placement: &Placement) -> Result<String> {
    csv_out::to_csv(&centerline_records(lines, placement))
}
