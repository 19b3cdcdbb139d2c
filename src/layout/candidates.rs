//! Candidate clamp poses: a grid over a box of the bench in the robot base frame, optionally
//! with tilted clamp axes.
//!
//! # Grid
//! A [`Region`] `x0:x1,y0:y1,z0:z1` (metres, base frame) is sampled at `spacing` along each axis:
//! `x0, x0 + h, …` up to `x1` (inclusive within 1e-9 m), the same for y and z; a degenerate
//! range `a:a` gives one value. The count is bounded by [`MAX_CANDIDATES`].
//!
//! # Tilt
//! The rig's clamp frame `R_c = [d1 d2 d3]` (the rod tangent d3 usually points up) is tilted by
//! angle θ toward the horizontal heading h (angle from +x_base about +z_base):
//! `R = Rot(a, θ)·R_c` with the horizontal axis `a = (−sin h, cos h, 0)`, so that a vertical d3
//! leans toward `(cos h, sin h, 0)`. θ = 0 is the rig's own orientation (one candidate per
//! position, whatever the headings); every θ > 0 adds `headings` evenly spaced headings.
//!
//! ```
//! use helixreach::layout::candidates::{grid, Region};
//! let r: Region = "0.7:0.9,-0.2:0,-0.144:-0.144".parse().unwrap();
//! let c = grid(&r, 0.1, &[0.0], 4).unwrap();
//! assert_eq!(c.len(), 3 * 3);
//! assert!((c[0].origin[0] - 0.7).abs() < 1e-12 && (c[8].origin[1] - 0.0).abs() < 1e-12);
//! ```

use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3, DEG};
use crate::planning::rig::{iso_from, Rig};
use std::str::FromStr;

/// Largest number of candidate poses a grid may have.
pub const MAX_CANDIDATES: usize = 100_000;

/// Largest tilt of the clamp axis (rad): 90° lays the rod flat.
pub const MAX_TILT: Real = 90.0 * DEG;

/// A box of the bench in the base frame (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    /// `[lo, hi]` per axis x, y, z.
    pub bounds: [[Real; 2]; 3],
}

impl Region {
    /// A checked region: finite bounds with `lo ≤ hi` on every axis.
    pub fn new(bounds: [[Real; 2]; 3]) -> Result<Region> {
        for (axis, [lo, hi]) in ["x", "y", "z"].iter().zip(bounds) {
            if !(lo.is_finite() && hi.is_finite()) {
                return Err(Error::invalid(
                    "region",
                    format!("{axis} = {lo}:{hi}"),
                    "bounds must be finite numbers (metres)",
                ));
            }
            if lo > hi {
                return Err(Error::invalid(
                    "region",
                    format!("{axis} = {lo}:{hi}"),
                    "empty region: the lower bound exceeds the upper",
                ));
            }
        }
        Ok(Region { bounds })
    }

    /// The default region: `±half` in x and y around `origin`, at its height.
    pub fn around(origin: &Vec3, half: Real) -> Region {
        Region {
            bounds: [
                [origin.x - half, origin.x + half],
                [origin.y - half, origin.y + half],
                [origin.z, origin.z],
            ],
        }
    }
}

impl FromStr for Region {
    type Err = Error;
    /// Parse `x0:x1,y0:y1,z0:z1`.
    fn from_str(s: &str) -> Result<Region> {
        let bad = |why: &str| Error::invalid("region", s, why.to_string());
        let parts: Vec<&str> = s.split(',').collect();
        if parts.len() != 3 {
            return Err(bad("must be x0:x1,y0:y1,z0:z1 (metres, base frame)"));
        }
        let mut b = [[0.0; 2]; 3];
        for (k, p) in parts.iter().enumerate() {
            let (lo, hi) = p
                .split_once(':')
                .ok_or_else(|| bad("each axis must be lo:hi (use a:a for one value)"))?;
            for (j, t) in [lo, hi].iter().enumerate() {
                b[k][j] = t
                    .trim()
                    .parse::<Real>()
                    .map_err(|_| bad(&format!("`{t}` is not a number")))?;
            }
        }
        Region::new(b).map_err(|e| bad(&e.to_string()))
    }
}

/// One candidate clamp pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Clamp origin (m, base frame).
    pub origin: [Real; 3],
    /// Tilt of the clamp axis from the rig's (rad).
    pub tilt: Real,
    /// Heading of the tilt about +z (rad; 0 when `tilt = 0`).
    pub heading: Real,
}

impl Candidate {
    /// The clamp rotation `Rot(a, θ)·R_c` (see the module docs).
    pub fn rotation(&self, rig_rotation: &Mat3) -> Mat3 {
        if self.tilt == 0.0 {
            return *rig_rotation;
        }
        let axis =
            nalgebra::Unit::new_normalize(Vec3::new(-self.heading.sin(), self.heading.cos(), 0.0));
        nalgebra::Rotation3::from_axis_angle(&axis, self.tilt).into_inner() * rig_rotation
    }

    /// The rig with its clamp moved to this candidate (everything else unchanged; the scene
    /// stays where it is in the base frame).
    pub fn place(&self, rig: &Rig) -> Rig {
        let mut r = rig.clone();
        let rot = self.rotation(&rig.clamp_rotation());
        r.clamp = iso_from(&rot, &Vec3::from(self.origin));
        r
    }

    /// The rod tangent d3 at the clamp (base frame).
    pub fn d3(&self, rig_rotation: &Mat3) -> Vec3 {
        self.rotation(rig_rotation).column(2).into_owned()
    }
}

/// A region whose width is a whole number of spacings up to round-off (in spacings) gets its last
/// grid line.
const GRID_SLACK: Real = 1e-9;

/// Number of grid values on `[lo, hi]` at spacing `h`, as a real (it may be astronomically large
/// or infinite for absurd input: counted before anything is allocated).
fn axis_count(lo: Real, hi: Real, h: Real) -> Real {
    ((hi - lo) / h + GRID_SLACK).floor() + 1.0
}

/// The grid values of an axis whose [`axis_count`] is `n`.
fn axis_values(lo: Real, h: Real, n: usize) -> Vec<Real> {
    (0..n).map(|i| lo + i as Real * h).collect()
}

/// The candidates of a grid over `region` at `spacing` (m) for every tilt of `tilts_deg`
/// (degrees, 0 = the rig's orientation) and `headings` headings per non-zero tilt. Order:
/// tilt-major, then heading, then z, y, x (x fastest). Errors: spacing not finite and > 0, a
/// tilt outside [0°, 90°] or NaN, `headings = 0` with a non-zero tilt, or more than
/// [`MAX_CANDIDATES`] poses.
pub fn grid(
    region: &Region,
    spacing: Real,
    tilts_deg: &[Real],
    headings: usize,
) -> Result<Vec<Candidate>> {
    if !(spacing.is_finite() && spacing > 0.0) {
        return Err(Error::invalid(
            "spacing",
            spacing,
            "must be finite and > 0 (metres)",
        ));
    }
    if tilts_deg.is_empty() {
        return Err(Error::invalid(
            "tilts",
            "[]",
            "give at least one tilt (0 = upright)",
        ));
    }
    for &t in tilts_deg {
        if !(t.is_finite() && (0.0..=MAX_TILT / DEG).contains(&t)) {
            return Err(Error::invalid(
                "tilts",
                t,
                "each tilt must lie in [0, 90] degrees",
            ));
        }
        if t > 0.0 && headings == 0 {
            return Err(Error::invalid(
                "headings",
                0,
                "a non-zero tilt needs at least one heading",
            ));
        }
    }
    if headings > MAX_CANDIDATES {
        return Err(Error::invalid(
            "headings",
            headings,
            format!("must be <= {MAX_CANDIDATES} (helixreach::layout::candidates::MAX_CANDIDATES)"),
        ));
    }
    // Count in reals first (a 1e300-wide region or a 1e-300 spacing), allocate after the bound.
    let [bx, by, bz] = region.bounds;
    let counts = [
        axis_count(bx[0], bx[1], spacing),
        axis_count(by[0], by[1], spacing),
        axis_count(bz[0], bz[1], spacing),
    ];
    let per_tilt: Real = tilts_deg
        .iter()
        .map(|&t| if t == 0.0 { 1.0 } else { headings as Real })
        .sum();
    let total = counts.iter().product::<Real>() * per_tilt;
    if total.is_nan() || total > MAX_CANDIDATES as Real {
        return Err(Error::invalid(
            "spacing",
            spacing,
            format!(
                "the grid would have {} candidate poses (at most {MAX_CANDIDATES}): use a \
                 larger spacing or a smaller region",
                crate::error::fmt_num(total)
            ),
        ));
    }
    let (xs, ys, zs) = (
        axis_values(bx[0], spacing, counts[0] as usize),
        axis_values(by[0], spacing, counts[1] as usize),
        axis_values(bz[0], spacing, counts[2] as usize),
    );
    let total = xs.len() * ys.len() * zs.len() * per_tilt as usize;
    let mut out = Vec::with_capacity(total as usize);
    for &t in tilts_deg {
        let hs: Vec<Real> = if t == 0.0 {
            vec![0.0]
        } else {
            (0..headings)
                .map(|i| 2.0 * std::f64::consts::PI * i as Real / headings as Real)
                .collect()
        };
        for &h in &hs {
            for &z in &zs {
                for &y in &ys {
                    for &x in &xs {
                        out.push(Candidate {
                            origin: [x, y, z],
                            tilt: t * DEG,
                            heading: h,
                        });
                    }
                }
            }
        }
    }
    Ok(out)
}

/// Parse a comma-separated list of tilts in degrees (`0,15,30`).
pub fn parse_tilts(s: &str) -> Result<Vec<Real>> {
    s.split(',')
        .map(|t| {
            t.trim()
                .parse::<Real>()
                .map_err(|_| Error::invalid("tilts", s, format!("`{t}` is not a number (degrees)")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilt_leans_toward_heading() {
        let c = Candidate {
            origin: [0.0; 3],
            tilt: 30.0 * DEG,
            heading: 0.5 * std::f64::consts::PI,
        };
        let d3 = c.d3(&Mat3::identity());
        // Leans toward +y by 30°.
        assert!(
            (d3 - Vec3::new(0.0, 0.5, 3f64.sqrt() / 2.0)).norm() < 1e-12,
            "{d3}"
        );
        let r = c.rotation(&Mat3::identity());
        assert!((r.transpose() * r - Mat3::identity()).norm() < 1e-12);
    }

    #[test]
    fn bad_grids_are_errors() {
        let r: Region = "0:1,0:1,0:0".parse().unwrap();
        assert!(grid(&r, 0.0, &[0.0], 4).is_err());
        assert!(grid(&r, Real::NAN, &[0.0], 4).is_err());
        assert!(grid(&r, 1e-4, &[0.0], 4).is_err());
        assert!(grid(&r, 0.5, &[Real::NAN], 4).is_err());
        assert!(grid(&r, 0.5, &[10.0], 0).is_err());
        assert!("1:0,0:1,0:0".parse::<Region>().is_err());
        assert!("0:1,0:1".parse::<Region>().is_err());
        assert!("0:nan,0:1,0:0".parse::<Region>().is_err());
        assert_eq!(grid(&r, 0.5, &[0.0, 10.0], 4).unwrap().len(), 9 * 5);
    }
}
