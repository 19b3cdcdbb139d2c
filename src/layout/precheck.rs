//! Cheap checks that rule out rays before the full planner runs.
//!
//! A check here may only say "not testable" when **no** feasible motion can exist, never when the
//! planner could find one. The geometric bounds below are proofs. One numerical IK miss at a
//! waypoint is *not* such a proof (a local solver can miss a solution), so it is never used
//! alone; the end-pose check is the planner's own sampled pointwise test, with its guarantee:
//!
//! # Reach bound
//! Let `p₀` be the origin of the first actuated joint's frame (fixed in the base frame: only fixed
//! links precede it) and `oᵢ` the constant offsets (`origin.pos`) of the link steps after it on
//! the path to the tip link. The tip position is `p₀ + Σ Rᵢ·oᵢ` with rotations `Rᵢ`, so for every
//! configuration `|p_tip − p₀| ≤ Σ |oᵢ| =: R` (triangle inequality). The rod-end tool frame is
//! the tip times the rig's fixed `tool` transform `t`, so `|p_tool − p₀| ≤ R + |t|`. A ray one of
//! whose pose-path waypoints has its rod end farther than `R + |t|` (plus 1 µm) from `p₀` cannot
//! be driven past that waypoint by any configuration: it is not testable.
//!
//! For a whole placement: every rod end lies within `L` (the rod length) of the clamp, so when the
//! straight rod's end is already out of reach, no ray starts ([`ReachBound::straight_out_of_reach`]).
//!
//! # No boundary
//! A ray whose boundary s* is infinite (stable up to the sweep's s_max) is never `testable` by
//! the planner's definition (nothing to see snap); it is decided without planning.
//!
//! # End pose (roll mode `fixed`, 7 joints)
//! A testable plan ends with a ladder node at the last waypoint s_end = s*·(1 + margin): a
//! configuration holding that waypoint's rod-end pose, inside the joint and motor limits, free
//! of self, scene and rod collision. [`end_pose_blocked`] runs the planner's pointwise test
//! ([`Planner::end_pose_valid`], the test of the pointwise gate: tracks from the straight rod's
//! start configurations, 60 random restarts, then the redundancy joint locked on a 0.05 rad grid
//! over its whole range) at that waypoint for every azimuth; when it finds no valid
//! configuration for any azimuth, the ray is not testable. Guarantee (the gate's): exact
//! provided the sampled test finds a valid configuration whenever one exists; a valid piece of
//! the self-motion set narrower than the grid could be missed. Such a ray is written
//! `unreachable` with cause and `decided_by` `end_pose` (its s_reached is not computed). It
//! costs one pointwise test per azimuth (most of the time of a ray whose end pose is valid: the
//! first seed's track) and saves the base plan and the dense levels of a ray that stops before
//! its end. Roll mode `motor` is not checked (its valid set at a pose is 2-dimensional).
//! Switched off by `LayoutOptions::end_pose_check` (`--no-end-pose-check`), for comparisons.

use crate::directions::Direction;
use crate::error::Result;
use crate::math::{Real, Vec3};
use crate::planning::planner::Planner;
use crate::planning::pose_path::{pose_path, Ray, Spacing};
use crate::planning::rig::Rig;
use crate::robot::kinematics::LinkMotion;
use crate::robot::RobotModel;

/// Slack added to the reach radius (m), far above rounding of the sums.
pub const REACH_SLACK: Real = 1e-6;

/// The reach ball of a robot + tool (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReachBound {
    /// Centre `p₀` (base frame).
    pub centre: Vec3,
    /// Radius `R + |t|` plus [`REACH_SLACK`] (m).
    pub radius: Real,
}

impl ReachBound {
    /// The bound of `model` (its tip link) and the rig's tool transform.
    pub fn of(model: &RobotModel, rig: &Rig) -> ReachBound {
        let links = model.chain().links();
        // Path from the tip up to the root.
        let mut path = Vec::new();
        let mut i = Some(model.tip_index());
        while let Some(k) = i {
            path.push(k);
            i = links[k].parent;
        }
        path.reverse();
        let first = path
            .iter()
            .position(|&k| !matches!(links[k].motion, LinkMotion::Fixed));
        // A prismatic joint (a rail) adds its largest travel to the reach.
        let travel = |k: usize| match links[k].motion {
            LinkMotion::Prismatic { dof, .. } => {
                let j = &model.joints()[dof];
                j.lower.abs().max(j.upper.abs())
            }
            _ => 0.0,
        };
        // Position of every link frame origin before (and at) the first actuated joint is fixed.
        let mut centre = Vec3::zeros();
        let mut rot = crate::math::Mat3::identity();
        let mut radius = 0.0;
        for (n, &k) in path.iter().enumerate() {
            let o = &links[k].origin;
            match first {
                Some(f) if n > f => radius += o.pos.norm() + travel(k),
                Some(f) if n == f => {
                    centre += rot * o.pos;
                    rot *= o.rot;
                    radius += travel(k);
                }
                _ => {
                    centre += rot * o.pos;
                    rot *= o.rot;
                }
            }
        }
        ReachBound {
            centre,
            radius: radius + rig.tool.translation.vector.norm() + REACH_SLACK,
        }
    }

    /// Whether a rod-end position is provably out of reach.
    pub fn out_of_reach(&self, p: &Vec3) -> bool {
        (p - self.centre).norm() > self.radius
    }

    /// Whether the straight rod of `rig` ends out of reach (then no ray of the placement starts).
    pub fn straight_out_of_reach(&self, rig: &Rig) -> bool {
        self.out_of_reach(&rig.straight_tool_pose().translation.vector)
    }

    /// Whether every azimuth of the ray `dir` to `s_end` on `rig` has a waypoint (of the
    /// planner's own pose path) out of reach: then the ray is not testable.
    pub fn ray_out_of_reach(
        &self,
        rig: &Rig,
        dir: &Direction,
        s_end: Real,
        azimuths: &[Real],
    ) -> Result<bool> {
        let sp = Spacing::of(rig);
        for &a in azimuths {
            let ray = Ray {
                dir: [dir.kappa, dir.tau, dir.omega],
                azimuth: a,
            };
            let wps = pose_path(rig, &ray, s_end, &sp)?;
            if !wps
                .iter()
                .any(|w| self.out_of_reach(&w.tool.translation.vector))
            {
                return Ok(false);
            }
        }
        Ok(!azimuths.is_empty())
    }
}

/// Whether the end-pose check (module docs, "End pose") rules the ray out: for every azimuth the
/// planner's pointwise test finds no valid configuration at the ray's last waypoint. `false`
/// when the test does not apply at some azimuth (not 7 joints, s* infinite, no start
/// configuration) or there are no azimuths.
pub fn end_pose_blocked(
    planner: &Planner,
    dir: &Direction,
    s_star: Real,
    azimuths: &[Real],
) -> Result<bool> {
    for &a in azimuths {
        if planner.end_pose_valid(dir, s_star, a)? != Some(false) {
            return Ok(false);
        }
    }
    Ok(!azimuths.is_empty())
}
