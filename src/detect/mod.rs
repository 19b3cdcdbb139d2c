//! Detect the snap from a recorded run: the seed's perception step, from raw observations
//! (measured joints and a tracked marker) to the measured boundary point.
//!
//! # Steps (one module each)
//! 1. [`observations`]: read and validate the samples ([`crate::records::detect`] reads the
//!    file); flag dropped markers and spikes.
//! 2. [`projection`]: FK of each sample's joints, projected onto the ray's pose curve → s;
//!    loading and unloading told apart at the largest s; a run that is not load-then-unload is
//!    refused.
//! 3. [`clamp`]: the clamp origin fitted from the joints when not given.
//! 4. [`extrinsics`]: camera → base transform and the marker's arc length, fitted on early
//!    loading (Kabsch over a 1-D search in arc length), with the residual.
//! 5. [`deviation`]: the seed's error e per sample.
//! 6. [`jump`]: the snap (where e jumps on loading), the return (where it drops back on
//!    unloading), or "no snap seen" with the reason.
//! 7. [`stream`]: the same as a streaming detector fed one sample at a time.
//!
//! [`Detector::detect`] runs 1–6 on one recorded run.
//!
//! # What is refused, what is flagged
//! Refused with an error naming the file, line and value: a malformed or empty file
//! ([`crate::records::detect`]), a run that is not load-then-unload ([`projection::split_phases`]),
//! a direction that does not match the run (the median pose residual of the samples exceeds
//! [`DetectOptions::max_median_position_error`] or [`DetectOptions::max_median_rotation_error`]).
//! Flagged per sample and counted: dropped markers, spikes, samples off the pose curve (a
//! disturbed path). The outcome's reason says when the track was lost where the jump would be,
//! when the run stopped before the predicted boundary, or when the path was disturbed there.
//!
//! ```no_run
//! use helixreach::detect::{DetectOptions, Detector};
//! use helixreach::directions::Direction;
//! use helixreach::planning::rig::Rig;
//! let det = Detector::new(Rig::load("sawyer-seed")?, DetectOptions::default())?;
//! let obs = det.read("test_c1_0.75_c2_0.txt".as_ref())?;
//! let d = det.detect(&obs, &Direction::new(0.8, 0.6, 0.0)?, Some([0.85, -0.15, -0.144]))?;
//! println!("{:?} at s = {:?}", d.outcome.reason, d.outcome.s_snap);
//! # Ok::<(), helixreach::Error>(())
//! ```

pub mod clamp;
pub mod deviation;
pub mod extrinsics;
pub mod jump;
pub mod observations;
pub mod projection;
pub mod stream;

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{Mat3, Real, Vec3};
use crate::planning::rig::Rig;
use crate::records::detect::{
    read_observations, DetectRunRecord, DetectSampleRecord, ObservationFile,
};
use crate::robot::{Frame, RobotModel};
use extrinsics::ExtrinsicsFit;
use jump::{JumpOptions, Outcome};
use observations::SampleFlag;
use std::path::Path;

/// Settings of a detection.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectOptions {
    /// Helix azimuth α of the run (rad).
    pub azimuth: Real,
    /// Largest s searched by the projection.
    pub s_max: Real,
    /// The extrinsics are fitted on the samples before s first exceeds this fraction of the
    /// continuum s* ([`fit_end`]).
    pub fit_fraction: Real,
    /// A sample whose tool is farther than this from the pose curve is off the path (m).
    pub max_position_error: Real,
    /// … or turned more than this (rad).
    pub max_rotation_error: Real,
    /// The run does not follow this direction when the median position residual exceeds this (m)
    pub max_median_position_error: Real,
    /// … or the median rotation residual exceeds this (rad).
    pub max_median_rotation_error: Real,
    /// The jump test.
    pub jump: JumpOptions,
}

impl Default for DetectOptions {
    fn default() -> Self {
        DetectOptions {
            azimuth: 0.0,
            s_max: 15.0,
            fit_fraction: 0.6,
            max_position_error: 0.015,
            max_rotation_error: 0.05,
            max_median_position_error: 0.008,
            max_median_rotation_error: 0.03,
            jump: JumpOptions::default(),
        }
    }
}

/// One sample of a detection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampleResult {
    /// 1-based line in the file.
    pub line: usize,
    /// Loading (true) or unloading.
    pub loading: bool,
    /// The projection.
    pub projected: crate::planning::pose_projection::Projected,
    /// The marker error (None when the marker is unusable).
    pub marker: Option<deviation::MarkerError>,
    /// The flag.
    pub flag: SampleFlag,
    /// Used in the extrinsics fit.
    pub in_fit: bool,
}

/// The result of [`Detector::detect`].
#[derive(Debug, Clone)]
pub struct Detection {
    /// The file.
    pub path: std::path::PathBuf,
    /// The direction.
    pub dir: Direction,
    /// The clamp origin used (m).
    pub clamp: Vec3,
    /// The clamp fit (None when the clamp was given).
    pub clamp_fit: Option<clamp::ClampFit>,
    /// The extrinsics fit.
    pub extrinsics: ExtrinsicsFit,
    /// Index of the reversal sample.
    pub reversal: usize,
    /// Largest s.
    pub s_reversal: Real,
    /// The continuum boundary s* of the direction.
    pub s_predicted: Real,
    /// Median tool position / rotation residual (m, rad).
    pub median_pose_error: (Real, Real),
    /// Per sample.
    pub samples: Vec<SampleResult>,
    /// Samples flagged (not ok).
    pub flagged: usize,
    /// The verdict.
    pub outcome: Outcome,
    /// The streaming detector's latency with these settings (usable samples after the last
    /// helical one, plus the spike test's look-ahead in raw samples).
    pub latency: usize,
}

/// Detects snaps on one rig.
#[derive(Debug, Clone)]
pub struct Detector {
    rig: Rig,
    model: RobotModel,
    tool: Frame,
    /// The settings.
    pub options: DetectOptions,
}

fn median(mut v: Vec<Real>) -> Real {
    if v.is_empty() {
        return Real::NAN;
    }
    v.sort_by(Real::total_cmp);
    v[v.len() / 2]
}

impl Detector {
    /// Load the rig's robot.
    pub fn new(rig: Rig, options: DetectOptions) -> Result<Detector> {
        let model = RobotModel::load(&rig.robot.source(), Some(&rig.robot.tip_link))?;
        let tool = Frame::from_iso(&rig.tool);
        Ok(Detector {
            rig,
            model,
            tool,
            options,
        })
    }

    /// The rig.
    pub fn rig(&self) -> &Rig {
        &self.rig
    }

    /// Read an observation file for this rig's robot.
    pub fn read(&self, path: &Path) -> Result<ObservationFile> {
        read_observations(path, self.model.dof())
    }

    /// The tool pose (rotation, position) of joints `q` (base frame).
    pub fn tool_pose(&self, q: &[Real]) -> (Mat3, Vec3) {
        let f = self.model.chain().tool_pose(q).mul(&self.tool);
        (f.rot, f.pos)
    }

    /// The pose curve of `dir` with the clamp at `origin`.
    pub fn curve(&self, dir: &Direction, origin: Vec3) -> projection::PoseCurve {
        projection::PoseCurve::new(
            &self.rig,
            dir,
            origin,
            self.options.azimuth,
            self.options.s_max,
        )
    }

    /// Detect on one run (module docs). `clamp`: the clamp origin (m), fitted when `None`.
    pub fn detect(
        &self,
        obs: &ObservationFile,
        dir: &Direction,
        clamp: Option<[Real; 3]>,
    ) -> Result<Detection> {
        let o = &self.options;
        if obs.dof != self.model.dof() {
            return Err(Error::File {
                path: obs.path.clone(),
                reason: format!(
                    "{} joints per sample, the robot has {}",
                    obs.dof,
                    self.model.dof()
                ),
            });
        }
        let n = obs.len();
        let poses: Vec<Option<(Mat3, Vec3)>> = (0..n)
            .map(|i| observations::joints_ok(obs, i).then(|| self.tool_pose(obs.joints(i))))
            .collect();
        let (origin, clamp_fit) = match clamp {
            Some(c) => {
                if !c.iter().all(|x| x.is_finite()) {
                    return Err(Error::invalid("clamp", format!("{c:?}"), "must be finite"));
                }
                (Vec3::new(c[0], c[1], c[2]), None)
            }
            None => {
                let f = clamp::fit_clamp(&self.curve(dir, Vec3::zeros()), &poses)
                    .map_err(|e| in_file(&obs.path, e))?;
                (f.origin, Some(f))
            }
        };
        let curve = self.curve(dir, origin);
        let proj = projection::project_all(&curve, &poses)?;
        let med = (
            median(
                proj.iter()
                    .map(|p| p.position_error)
                    .filter(|x| x.is_finite())
                    .collect(),
            ),
            median(
                proj.iter()
                    .map(|p| p.rotation_error)
                    .filter(|x| x.is_finite())
                    .collect(),
            ),
        );
        if !(med.0 <= o.max_median_position_error && med.1 <= o.max_median_rotation_error) {
            return Err(Error::File {
                path: obs.path.clone(),
                reason: format!(
                    "the run does not follow direction ({:.6}, {:.6}, {:.6}) from clamp ({:.4}, {:.4}, {:.4}): median tool residual {:.1} mm / {:.1} mrad (limits {:.1} mm / {:.1} mrad)",
                    dir.kappa, dir.tau, dir.omega, origin.x, origin.y, origin.z,
                    med.0 * 1e3, med.1 * 1e3,
                    o.max_median_position_error * 1e3, o.max_median_rotation_error * 1e3
                ),
            });
        }
        let s: Vec<Real> = proj.iter().map(|p| p.s).collect();
        let rev = projection::split_phases(&s, &obs.lines, &obs.path)?;
        let s_rev = s[rev];
        let mut flags = observations::flag_samples(obs);
        for (f, p) in flags.iter_mut().zip(&proj) {
            if *f == SampleFlag::Ok
                && !(p.position_error <= o.max_position_error
                    && p.rotation_error <= o.max_rotation_error)
            {
                *f = SampleFlag::OffPath;
            }
        }
        let s_predicted = crate::boundary::continuum::critical_s(dir, 1e-8)
            .map(|c| c.s_star)
            .unwrap_or(Real::NAN);
        let fit_end = fit_end(&s, o.fit_fraction, s_predicted, s_rev);
        let fit_idx: Vec<usize> = (0..=fit_end)
            .filter(|&i| flags[i] == SampleFlag::Ok)
            .collect();
        let fit_samples: Vec<(Real, Vec3)> = fit_idx
            .iter()
            .map(|&i| (s[i], observations::marker(obs, i).unwrap_or_default()))
            .collect();
        let ext =
            extrinsics::fit_extrinsics(&curve, &fit_samples).map_err(|e| in_file(&obs.path, e))?;
        let mut in_fit = vec![false; n];
        for &i in &fit_idx {
            in_fit[i] = true;
        }
        let mut samples = Vec::with_capacity(n);
        for i in 0..n {
            let marker = match (flags[i], observations::marker(obs, i)) {
                (SampleFlag::Ok, Some(m)) => Some(deviation::marker_error(
                    &curve,
                    &ext.camera_to_base,
                    ext.sigma,
                    s[i],
                    &m,
                )?),
                _ => None,
            };
            samples.push(SampleResult {
                line: obs.lines[i],
                loading: i <= rev,
                projected: proj[i],
                marker,
                flag: flags[i],
                in_fit: in_fit[i],
            });
        }
        let e: Vec<Real> = samples
            .iter()
            .map(|x| x.marker.map_or(Real::NAN, |m| m.e))
            .collect();
        let outcome = jump::detect(&s, &e, &flags, rev, s_predicted, fit_end, &o.jump);
        let flagged = flags.iter().filter(|f| **f != SampleFlag::Ok).count();
        Ok(Detection {
            path: obs.path.clone(),
            dir: *dir,
            clamp: origin,
            clamp_fit,
            extrinsics: ext,
            reversal: rev,
            s_reversal: s_rev,
            s_predicted,
            median_pose_error: med,
            samples,
            flagged,
            outcome,
            latency: o.jump.latency() + observations::OUTLIER_HALF_WINDOW,
        })
    }
}

/// The last sample of the extrinsics fit: the one before the first sample whose s exceeds
/// `fraction` × s* (`s_predicted`; the reversal s when s* is not finite), or the last sample.
pub fn fit_end(s: &[Real], fraction: Real, s_predicted: Real, s_reversal: Real) -> usize {
    let limit = fraction
        * if s_predicted.is_finite() {
            s_predicted
        } else {
            s_reversal
        };
    s.iter()
        .position(|x| *x > limit)
        .map_or(s.len() - 1, |i| i.saturating_sub(1))
}

fn in_file(path: &Path, e: Error) -> Error {
    Error::File {
        path: path.to_path_buf(),
        reason: e.to_string(),
    }
}

impl Detection {
    /// The per-sample rows (`detect --out`).
    pub fn sample_records(&self) -> Vec<DetectSampleRecord> {
        let nan = Real::NAN;
        self.samples
            .iter()
            .map(|x| {
                let (m, p, e) = x.marker.map_or(([nan; 3], [nan; 3], nan), |m| {
                    (
                        [m.marker.x, m.marker.y, m.marker.z],
                        [m.predicted.x, m.predicted.y, m.predicted.z],
                        m.e,
                    )
                });
                DetectSampleRecord {
                    line: x.line,
                    phase: if x.loading { "loading" } else { "unloading" },
                    s: x.projected.s,
                    pose_position_error: x.projected.position_error,
                    pose_rotation_error: x.projected.rotation_error,
                    marker_x: m[0],
                    marker_y: m[1],
                    marker_z: m[2],
                    predicted_x: p[0],
                    predicted_y: p[1],
                    predicted_z: p[2],
                    e,
                    flag: x.flag.as_str(),
                    in_fit: x.in_fit,
                }
            })
            .collect()
    }
}

/// The batch row of one run (`helixreach detect --runs`): a run the detector refuses (a bad file,
/// a direction that does not match) gets reason `rejected`, no s, and the error in the notes.
pub fn run_record(det: &Detector, run: &crate::records::detect::DetectRun) -> DetectRunRecord {
    let r = det
        .read(&run.path)
        .and_then(|obs| Ok((det.detect(&obs, &run.dir, run.clamp)?, obs.len())));
    let c = run.clamp.unwrap_or([Real::NAN; 3]);
    match r {
        Ok((d, n)) => DetectRunRecord {
            observations: run.observations.clone(),
            dir: (&run.dir).into(),
            s_measured: d.outcome.s_snap,
            s_return: d.outcome.s_return,
            confidence: d.outcome.confidence.as_str(),
            reason: d.outcome.reason.as_str(),
            s_reversal: d.s_reversal,
            s_predicted: d.s_predicted,
            marker_arc: d.extrinsics.sigma,
            fit_rms: d.extrinsics.rms,
            clamp_x: d.clamp.x,
            clamp_y: d.clamp.y,
            clamp_z: d.clamp.z,
            samples: n,
            flagged: d.flagged,
            notes: d.outcome.notes.join("; "),
        },
        Err(e) => DetectRunRecord {
            observations: run.observations.clone(),
            dir: (&run.dir).into(),
            s_measured: None,
            s_return: None,
            confidence: "none",
            reason: "rejected",
            s_reversal: Real::NAN,
            s_predicted: Real::NAN,
            marker_arc: Real::NAN,
            fit_rms: Real::NAN,
            clamp_x: c[0],
            clamp_y: c[1],
            clamp_z: c[2],
            samples: 0,
            flagged: 0,
            notes: e.to_string(),
        },
    }
}

impl Detection {
    /// The JSON summary (`helixreach detect` on one run).
    pub fn summary_json(&self) -> serde_json::Value {
        let o = &self.outcome;
        let x = &self.extrinsics;
        let r = x.camera_to_base.rotation;
        let t = x.camera_to_base.translation;
        serde_json::json!({
            "observations": self.path.display().to_string(),
            "direction": [self.dir.kappa, self.dir.tau, self.dir.omega],
            "samples": self.samples.len(),
            "flagged": self.flagged,
            "clamp": {
                "origin": [self.clamp.x, self.clamp.y, self.clamp.z],
                "fitted": self.clamp_fit.is_some(),
                "fit_rms": self.clamp_fit.map(|c| c.rms),
            },
            "pose_residual_median": {"position": self.median_pose_error.0, "rotation": self.median_pose_error.1},
            "extrinsics": {
                "camera_to_base_rotation": [[r[(0,0)], r[(0,1)], r[(0,2)]], [r[(1,0)], r[(1,1)], r[(1,2)]], [r[(2,0)], r[(2,1)], r[(2,2)]]],
                "camera_to_base_translation": [t.x, t.y, t.z],
                "marker_arc": x.sigma,
                "fit_rms": x.rms,
                "fit_rms_at_arc_offset_0_05": x.rms_at_sigma_offset,
                "fit_samples": x.used,
                "fit_trimmed": x.trimmed,
            },
            "s_reversal": self.s_reversal,
            "s_predicted": self.s_predicted,
            "s_snap": o.s_snap,
            "s_return": o.s_return,
            "levels": o.levels.map(|(a, b)| [a, b]),
            "reason": o.reason.as_str(),
            "confidence": o.confidence.as_str(),
            "notes": o.notes,
            "latency_samples": self.latency,
        })
    }
}
