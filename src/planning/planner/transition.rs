//! Moves between two runs at the straight rod (s = 0), for a campaign
//! ([`crate::planning::campaign`]): a self-motion reconfiguration with the rod held, or a free
//! joint-linear move with the rod end released.
//!
//! - [`Planner::straight_reconfiguration`]: both configurations must hold the same tool pose
//!   (to [`self_motion::HOLD_TOLERANCE`]); the self-motion manifold of that pose is walked
//!   ([`self_motion::walk`], resolution `planner.self_motion_step`) from `from` in both
//!   directions until a sample comes within half a joint step (`planner.max_joint_step`,
//!   max-norm) of `to`; the walk plus `to` is resampled ([`self_motion::refine`]: the rod end
//!   within 1e-6 m / rad on every joint-linear chord) and every sample and chord is checked
//!   exactly as a ladder edge at s = 0 is: joint limits, self, scene and rod collision against
//!   the straight rod, segments every `segment_check_step`, steps within `max_joint_step`.
//!   `None` when `to` is not on the connected valid component of `from` (at the walk's
//!   resolution) or the poses differ. Cost: one walk, at most 2 × 2,000 samples.
//! - [`Planner::free_move`]: the joint-linear segment `from → to` (end points included) checked
//!   for joint limits, self and scene collision, and — with `rod` — the straight rod without
//!   the `rod_end_exclusion` metres the motor holds (the rod released by the motor stays
//!   straight in its clamp).

use super::{node, Planner, MAX_WALK_SAMPLES};
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::cause::BlockCause;
use crate::planning::self_motion::{self, Held, Q};
use crate::robot::IkSolver;

impl Planner {
    fn padded(&self, what: &str, q: &[Real]) -> Result<Q> {
        if q.len() != self.dof || q.iter().any(|x| !x.is_finite()) {
            return Err(Error::invalid(
                what,
                format!("{q:?}"),
                format!("needs {} finite joint values", self.dof),
            ));
        }
        Ok(super::pad(q))
    }

    fn within_limits(&self, q: &[Real]) -> bool {
        let (lo, hi) = (self.model.lower(), self.model.upper());
        q.iter().enumerate().all(|(j, &x)| x >= lo[j] && x <= hi[j])
    }

    /// The self-motion path from `from` to `to` at the straight rod with the rod held (module
    /// docs): the joint samples after `from`, the last one `to`; `None` when there is none.
    /// Errors: a configuration of the wrong length or not finite.
    pub fn straight_reconfiguration(
        &self,
        from: &[Real],
        to: &[Real],
        motor: Real,
    ) -> Result<Option<Vec<Vec<Real>>>> {
        let (a, b) = (
            self.padded("reconfiguration start", from)?,
            self.padded("reconfiguration end", to)?,
        );
        let dof = self.dof;
        if dof != 7 {
            return Ok(None);
        }
        let solver = IkSolver::new(&self.model, self.ik.clone())?;
        let held = Held {
            chain: self.model.chain(),
            solver: &solver,
            tip: self.model.chain().tool_pose(&a[..dof]),
            dof,
        };
        let (dp, dr) = held.pose_error(&b[..dof]);
        if dp > self_motion::HOLD_TOLERANCE || dr > self_motion::HOLD_TOLERANCE {
            return Ok(None);
        }
        let mut sc = self.new_scratch();
        self.rod_nodes([0.0; 3], 0.0, &mut sc.rod)?;
        let mut settings = self.walk_settings();
        settings.max_samples = MAX_WALK_SAMPLES;
        let half = 0.5 * self.rig.planner.max_joint_step;
        let near = |q: &Q| (0..dof).all(|j| (q[j] - b[j]).abs() <= half);
        if near(&a) {
            return Ok(self.checked_path(&held, &[a, b], motor).ok());
        }
        for sign in [1.0, -1.0] {
            let (samples, hit) = self_motion::walk(
                &held,
                &a,
                sign,
                &settings,
                |p, q| {
                    self.check_config(&q[..dof], &mut sc).is_ok()
                        && self
                            .check_segment(&node(*p, motor), &node(*q, motor), &mut sc)
                            .is_ok()
                },
                near,
            );
            if !hit {
                continue;
            }
            let mut coarse = vec![a];
            coarse.extend(samples);
            coarse.push(b);
            if let Ok(path) = self.checked_path(&held, &coarse, motor) {
                return Ok(Some(path));
            }
        }
        Ok(None)
    }

    /// `coarse` resampled on the held manifold and checked (module docs); `Err` when a sample or
    /// chord fails.
    fn checked_path(
        &self,
        held: &Held<'_>,
        coarse: &[Q],
        motor: Real,
    ) -> std::result::Result<Vec<Vec<Real>>, BlockCause> {
        let dof = self.dof;
        let fine = self_motion::refine(held, coarse).ok_or(BlockCause::NoIk)?;
        let mut sc = self.new_scratch();
        self.rod_nodes([0.0; 3], 0.0, &mut sc.rod)
            .map_err(|_| BlockCause::NoIk)?;
        let mut prev = coarse[0];
        for q in &fine {
            let (p, n) = (node(prev, motor), node(*q, motor));
            if !self.within_limits(&q[..dof]) {
                return Err(BlockCause::JointLimit);
            }
            if self.edge_cost(&p, &n).is_none() {
                return Err(BlockCause::Discontinuity);
            }
            self.check_config(&q[..dof], &mut sc)?;
            self.check_segment(&p, &n, &mut sc)?;
            prev = *q;
        }
        Ok(fine.iter().map(|q| q[..dof].to_vec()).collect())
    }

    /// Check the free joint-linear move `from → to` (module docs): `Ok(Ok(()))` when clear,
    /// `Ok(Err(cause))` with the first cause met. Errors: a configuration of the wrong length.
    pub fn free_move(
        &self,
        from: &[Real],
        to: &[Real],
        rod: bool,
    ) -> Result<std::result::Result<(), BlockCause>> {
        let (a, b) = (
            self.padded("move start", from)?,
            self.padded("move end", to)?,
        );
        let dof = self.dof;
        for q in [&a, &b] {
            if !self.within_limits(&q[..dof]) {
                return Ok(Err(BlockCause::JointLimit));
            }
        }
        let mut sc = self.new_scratch();
        if rod {
            self.rod_nodes([0.0; 3], 0.0, &mut sc.rod)?;
            for q in [&a, &b] {
                if let Err(c) = self.check_config(&q[..dof], &mut sc) {
                    return Ok(Err(c));
                }
            }
            return Ok(self.check_segment(&node(a, 0.0), &node(b, 0.0), &mut sc));
        }
        // Without the rod: every sample against self and scene only.
        let mut dmax: Real = 0.0;
        for j in 0..dof {
            dmax = dmax.max((b[j] - a[j]).abs());
        }
        let n = (dmax / self.rig.planner.segment_check_step).ceil().max(1.0) as usize;
        let mut qi = [0.0; crate::robot::MAX_DOF];
        for k in 0..=n {
            let t = k as Real / n as Real;
            for j in 0..dof {
                qi[j] = a[j] + t * (b[j] - a[j]);
            }
            if let Some(c) = self.collision.check(&qi[..dof], &mut sc.ws, None) {
                return Ok(Err(super::cause_of(&c)));
            }
        }
        Ok(Ok(()))
    }
}
