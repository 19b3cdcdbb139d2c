//! Validation of the raw samples: which samples carry a usable marker.
//!
//! A sample is
//! - [`SampleFlag::Dropped`] when its marker is missing (a non-finite coordinate, or exactly
//!   `(0, 0, 0)`, what depth cameras write for "no depth") or its joints are;
//! - [`SampleFlag::Outlier`] when its marker lies farther than [`OUTLIER_DISTANCE`] from the
//!   componentwise median of the usable markers within ±[`OUTLIER_HALF_WINDOW`] samples (a
//!   spike: a wrong blob, a reflection). A lasting change of the marker's place (the snap
//!   itself) moves the median with it and is not flagged, except the few samples of the fast
//!   transition;
//! - [`SampleFlag::OffPath`] (set later, [`super`]) when the tool is far from the ray's pose curve.
//!
//! A stretch of consecutive unusable samples longer than [`LOST_GAP`] samples is a lost track;
//! it is reported, and a jump inside it is not claimed ([`super::jump`]).

use crate::math::{Real, Vec3};
use crate::records::detect::ObservationFile;

/// Half-width (samples) of the outlier test's median window.
pub const OUTLIER_HALF_WINDOW: usize = 4;
/// Distance (m) from the local median beyond which a marker is an outlier.
pub const OUTLIER_DISTANCE: Real = 0.01;
/// More consecutive unusable samples than this is a lost track.
pub const LOST_GAP: usize = 20;

/// Why a sample is not used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleFlag {
    /// Usable.
    Ok,
    /// No marker (or no joints).
    Dropped,
    /// A marker spike.
    Outlier,
    /// The tool is off the ray's pose curve.
    OffPath,
}

impl SampleFlag {
    /// The CSV spelling.
    pub fn as_str(&self) -> &'static str {
        match self {
            SampleFlag::Ok => "ok",
            SampleFlag::Dropped => "dropped",
            SampleFlag::Outlier => "outlier",
            SampleFlag::OffPath => "off_path",
        }
    }
}

/// Whether the joints of sample `i` are all finite.
pub fn joints_ok(f: &ObservationFile, i: usize) -> bool {
    f.joints(i).iter().all(|x| x.is_finite())
}

/// The marker of sample `i` when present.
pub fn marker(f: &ObservationFile, i: usize) -> Option<Vec3> {
    let m = f.marker[i];
    let present = m.iter().all(|x| x.is_finite()) && m != [0.0, 0.0, 0.0];
    present.then(|| Vec3::new(m[0], m[1], m[2]))
}

/// The marker of sample `i` when it and the joints are present.
pub fn present(f: &ObservationFile, i: usize) -> Option<Vec3> {
    if joints_ok(f, i) {
        marker(f, i)
    } else {
        None
    }
}

/// The flag of every sample (dropped and outliers; module docs).
pub fn flag_samples(f: &ObservationFile) -> Vec<SampleFlag> {
    let present: Vec<Option<Vec3>> = (0..f.len()).map(|i| present(f, i)).collect();
    let mut buf: [Vec<Real>; 3] = Default::default();
    (0..f.len())
        .map(|i| flag_at(&present, i, &mut buf))
        .collect()
}

/// The flag of sample `i` from the present markers around it (`present[i + OUTLIER_HALF_WINDOW]`
/// must exist unless the run ends before); `buf` is scratch.
pub fn flag_at(present: &[Option<Vec3>], i: usize, buf: &mut [Vec<Real>; 3]) -> SampleFlag {
    let Some(m) = present[i] else {
        return SampleFlag::Dropped;
    };
    let lo = i.saturating_sub(OUTLIER_HALF_WINDOW);
    let hi = (i + OUTLIER_HALF_WINDOW + 1).min(present.len());
    for b in buf.iter_mut() {
        b.clear();
    }
    for p in present[lo..hi].iter().flatten() {
        for k in 0..3 {
            buf[k].push(p[k]);
        }
    }
    if buf[0].len() < 3 {
        return SampleFlag::Ok;
    }
    let mut med = Vec3::zeros();
    for k in 0..3 {
        buf[k].sort_by(Real::total_cmp);
        med[k] = buf[k][buf[k].len() / 2];
    }
    if (m - med).norm() > OUTLIER_DISTANCE {
        SampleFlag::Outlier
    } else {
        SampleFlag::Ok
    }
}

/// The longest stretch of consecutive unusable samples within `range`, as (first index, length).
pub fn longest_gap(flags: &[SampleFlag], range: std::ops::Range<usize>) -> (usize, usize) {
    let (mut best, mut start, mut run) = ((range.start, 0), range.start, 0);
    for i in range {
        if flags[i] == SampleFlag::Ok {
            run = 0;
        } else {
            if run == 0 {
                start = i;
            }
            run += 1;
            if run > best.1 {
                best = (start, run);
            }
        }
    }
    best
}
