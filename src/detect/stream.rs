//! The detector fed live, one sample at a time, while the robot runs.
//!
//! [`StreamingDetector::push`] takes one sample (joints, marker in the camera frame) and says
//! "snap" ([`StreamEvent::Snap`]) as soon as the jump test ([`super::jump`]) is sure, then
//! "return" on unloading. It runs the batch steps causally with the **clamp given** (a lab knows
//! where its clamp is; [`super::clamp`] needs the whole run):
//!
//! 1. each sample is projected on arrival ([`super::projection`], continuing from the previous
//!    sample exactly as the batch does);
//! 2. sample i is flagged when sample i + [`OUTLIER_HALF_WINDOW`] has arrived (the spike test's
//!    window);
//! 3. the extrinsics are fitted once, when the first flagged sample has s above
//!    `fit_fraction × s*` — on the same samples the batch uses ([`super::fit_end`]);
//! 4. from then on every flagged sample's e goes to the same [`Scanner`] as the batch's.
//!
//! So on the same samples it finds the **same s_snap and s_return as [`super::Detector::detect`]**
//! (tests/detect.rs checks it), reported at most [`OUTLIER_HALF_WINDOW`] raw samples plus
//! [`super::jump::JumpOptions::latency`] usable samples after the last helical sample.
//! The batch's run-level checks (load-then-unload shape, direction residual) need the whole run
//! and are not made here. Memory: a few numbers per sample (the scan keeps every usable sample).

use super::extrinsics::{fit_extrinsics, ExtrinsicsFit};
use super::jump::Scanner;
use super::observations::{flag_at, SampleFlag, OUTLIER_HALF_WINDOW};
use super::projection::PoseCurve;
use super::{deviation, Detector};
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{Real, Vec3};
use crate::planning::pose_projection::Tracker;

/// What a pushed sample completed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StreamEvent {
    /// The snap: s of the last helical sample, its index, and the index of the sample whose
    /// arrival decided it.
    Snap {
        /// s of the last helical sample.
        s: Real,
        /// Its sample index (0-based, in push order).
        index: usize,
        /// The sample that decided it.
        decided_at: usize,
    },
    /// The return on unloading.
    Return {
        /// s where e came back.
        s: Real,
        /// Its sample index.
        index: usize,
        /// The sample that decided it.
        decided_at: usize,
    },
}

/// A streaming detector for one run (module docs).
#[derive(Debug)]
pub struct StreamingDetector<'a> {
    det: &'a Detector,
    curve: PoseCurve,
    fit_limit: Real,
    tracker: Tracker,
    s: Vec<Real>,
    off_path: Vec<bool>,
    present: Vec<Option<Vec3>>,
    flags: Vec<SampleFlag>,
    buf: [Vec<Real>; 3],
    extrinsics: Option<ExtrinsicsFit>,
    fed: usize,
    scanner: Scanner,
    arrived: usize,
    events: Vec<StreamEvent>,
}

impl<'a> StreamingDetector<'a> {
    /// A detector for the ray `dir` with the clamp at `clamp` (m, base frame).
    pub fn new(det: &'a Detector, dir: &Direction, clamp: [Real; 3]) -> Result<Self> {
        if !clamp.iter().all(|x| x.is_finite()) {
            return Err(Error::invalid(
                "clamp",
                format!("{clamp:?}"),
                "must be finite",
            ));
        }
        let s_pred = crate::boundary::continuum::critical_s(dir, 1e-8)
            .map(|c| c.s_star)
            .unwrap_or(Real::NAN);
        if !s_pred.is_finite() {
            return Err(Error::invalid(
                "direction",
                format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
                "no finite continuum s*: the extrinsics fit limit is undefined",
            ));
        }
        Ok(StreamingDetector {
            det,
            curve: det.curve(dir, Vec3::from(clamp)),
            fit_limit: det.options.fit_fraction * s_pred,
            tracker: Tracker::new(),
            s: Vec::new(),
            off_path: Vec::new(),
            present: Vec::new(),
            flags: Vec::new(),
            buf: Default::default(),
            extrinsics: None,
            fed: 0,
            scanner: Scanner::new(det.options.jump.clone()),
            arrived: 0,
            events: Vec::new(),
        })
    }

    /// The extrinsics, once fitted.
    pub fn extrinsics(&self) -> Option<&ExtrinsicsFit> {
        self.extrinsics.as_ref()
    }

    /// Every event so far.
    pub fn events(&self) -> &[StreamEvent] {
        &self.events
    }

    /// Feed one sample: the robot's joints and the marker in the camera frame (non-finite or
    /// all zero: no marker). Returns the events this sample completed.
    pub fn push(&mut self, joints: &[Real], marker: [Real; 3]) -> Result<Vec<StreamEvent>> {
        let o = &self.det.options;
        if joints.len() != self.det.model.dof() {
            return Err(Error::invalid(
                "joints",
                joints.len(),
                format!("the robot has {} joints", self.det.model.dof()),
            ));
        }
        let joints_ok = joints.iter().all(|x| x.is_finite());
        let (s, off) = if joints_ok {
            let (rot, pos) = self.det.tool_pose(joints);
            let p = self.tracker.project(&self.curve, &rot, &pos)?;
            (
                p.s,
                !(p.position_error <= o.max_position_error
                    && p.rotation_error <= o.max_rotation_error),
            )
        } else {
            (Real::NAN, false)
        };
        let m = (joints_ok && marker.iter().all(|x| x.is_finite()) && marker != [0.0; 3])
            .then(|| Vec3::from(marker));
        self.s.push(s);
        self.off_path.push(off);
        self.present.push(m);
        self.arrived += 1;
        let before = self.events.len();
        while self.flags.len() + OUTLIER_HALF_WINDOW < self.arrived {
            self.finalize_next()?;
        }
        Ok(self.events[before..].to_vec())
    }

    /// The run has ended: flag and scan the last samples (and fit the extrinsics if the run never
    /// passed the fit limit). Returns the events completed.
    pub fn finish(&mut self) -> Result<Vec<StreamEvent>> {
        let before = self.events.len();
        while self.flags.len() < self.arrived {
            self.finalize_next()?;
        }
        if self.extrinsics.is_none() {
            self.fit(self.arrived)?;
        }
        Ok(self.events[before..].to_vec())
    }

    fn finalize_next(&mut self) -> Result<()> {
        let i = self.flags.len();
        let mut f = flag_at(&self.present, i, &mut self.buf);
        if f == SampleFlag::Ok && self.off_path[i] {
            f = SampleFlag::OffPath;
        }
        self.flags.push(f);
        if self.extrinsics.is_none() && self.s[i] > self.fit_limit {
            self.fit(i)?;
        } else if self.extrinsics.is_some() {
            self.feed(i)?;
        }
        Ok(())
    }

    /// Fit on samples `..end`, then scan them and every flagged sample after.
    fn fit(&mut self, end: usize) -> Result<()> {
        let fit: Vec<(Real, Vec3)> = (0..end)
            .filter(|&i| self.flags[i] == SampleFlag::Ok)
            .map(|i| (self.s[i], self.present[i].unwrap_or_default()))
            .collect();
        self.extrinsics = Some(fit_extrinsics(&self.curve, &fit)?);
        for i in self.fed..self.flags.len() {
            self.feed(i)?;
        }
        Ok(())
    }

    fn feed(&mut self, i: usize) -> Result<()> {
        let ext = self.extrinsics.as_ref().expect("fitted before feeding");
        let e = match (self.flags[i], self.present[i]) {
            (SampleFlag::Ok, Some(m)) => {
                deviation::marker_error(&self.curve, &ext.camera_to_base, ext.sigma, self.s[i], &m)?
                    .e
            }
            _ => Real::NAN,
        };
        self.fed = i + 1;
        let had = (self.scanner.jump.is_some(), self.scanner.ret.is_some());
        self.scanner.push(i, self.s[i], e);
        let at = self.arrived - 1;
        if let (false, Some(j)) = (had.0, self.scanner.jump) {
            if j.after - j.before > super::observations::LOST_GAP {
                // The jump happened while the marker was lost: no s is claimed (as the batch).
                return Ok(());
            }
            self.events.push(StreamEvent::Snap {
                s: self.s[j.before],
                index: j.before,
                decided_at: at,
            });
        }
        if let (false, Some((r, _))) = (had.1, self.scanner.ret) {
            self.events.push(StreamEvent::Return {
                s: self.s[r],
                index: r,
                decided_at: at,
            });
        }
        Ok(())
    }
}
