//! Time parametrization of a planned joint + motor path and its writers (CSV and a JSON shaped like
//! ROS `trajectory_msgs/JointTrajectory`).
//!
//! # Phases (the seed's protocol)
//! A trajectory loads the rod from the straight rod to `s_end` (phase `load`), holds it there
//! (`hold`: one repeated sample, lasting the rig's `hold_time`), and unloads it back to the
//! straight rod along the same joint path reversed (`unload`). Self-motion reconfigurations at a
//! held pose (`reconfigure`, [`crate::planning::self_motion`]) keep s and the rod-end pose
//! constant; on unloading they are run backwards and stay `reconfigure`.
//!
//! # Timing
//! Segment k (waypoint k → k+1) lasts the shortest time that keeps every limit:
//!
//! `Δt_k = max( max_j |Δq_j| / v_j ,  |Δm| / v_m ,  |Δp| / v_end ,  Δθ_end·L / v_end )`
//!
//! with `v_j` the joint speed limits (already scaled by the rig's `velocity_scale`), `v_m` the
//! motor limit, `v_end` the quasi-static rod-end speed, `Δp` and `Δθ_end` the rod end's translation
//! and rotation (the rotation converted to a speed through the rod length L). Within a segment the
//! motion is linear in joint space at constant speed, so every limit holds on the whole segment.
//! A segment that ends in the `hold` sample lasts at least `hold_time`.
//! The velocity stored at a waypoint is the mean of its two adjacent segment velocities (zero at
//! both ends): a convex combination of in-limit values, hence in limit too.
//!
//! # Outputs (written by [`crate::records::trajectory`])
//! - CSV: `t,q0..q{n-1},motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase`; the pose is the tool
//!   frame in the robot base frame, the quaternion scalar first; `phase` is one of `load`,
//!   `reconfigure`, `hold`, `unload`.
//! - JSON: `{"header":{"frame_id":…},"joint_names":[…, motor],"points":[{"positions":[…],
//!   "velocities":[…],"time_from_start":{"secs":…,"nsecs":…},"phase":…}]}`; the motor is the
//!   last joint.

use crate::error::{Error, Result};
use crate::math::{rotation_angle, Iso3, Real};
use crate::planning::ladder::BlockCause;
use crate::planning::planner::{PlannedPoint, Planner, RayPlan, ReachClass};

/// The phase of a trajectory sample (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Phase {
    /// Driving the rod from the straight rod toward `s_end`.
    #[default]
    Load,
    /// Self-motion at a held rod-end pose (s constant).
    Reconfigure,
    /// Holding the rod at the end of loading.
    Hold,
    /// Driving the rod back to the straight rod along the loading path.
    Unload,
    /// Driving back along the ray below s* during loading (to reconfigure and drive on).
    Backoff,
}

impl Phase {
    /// The CSV name (`load`, `reconfigure`, `hold`, `unload`, `backoff`).
    pub fn as_str(&self) -> &'static str {
        match self {
            Phase::Load => "load",
            Phase::Reconfigure => "reconfigure",
            Phase::Hold => "hold",
            Phase::Unload => "unload",
            Phase::Backoff => "backoff",
        }
    }

    /// Parse the CSV name.
    pub fn parse(s: &str) -> Option<Phase> {
        [
            Phase::Load,
            Phase::Reconfigure,
            Phase::Hold,
            Phase::Unload,
            Phase::Backoff,
        ]
        .into_iter()
        .find(|p| p.as_str() == s)
    }
}

impl std::fmt::Display for Phase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One sample of a trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryPoint {
    /// Time from start (s).
    pub t: Real,
    /// Joint positions (rad).
    pub q: Vec<Real>,
    /// Motor angle (rad).
    pub motor: Real,
    /// Distance along the ray (nondimensional).
    pub s: Real,
    /// Helix parameters (κ, τ, ω) = s·S̄.
    pub kto: [Real; 3],
    /// Tool pose (rod end) in the robot base frame.
    pub pose: Iso3,
    /// Phase of the protocol.
    pub phase: Phase,
}

/// What a trajectory was planned for and how far it goes: written with every trajectory output
/// (the CSV's and the JSON's `F.meta.json` sidecar), so a partial run never looks like a complete
/// experiment.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RayOutcome {
    /// The ray's direction (κ̂, τ̂, ω̂).
    pub direction: [Real; 3],
    /// Helix azimuth α (rad).
    pub azimuth: Real,
    /// Boundary s* of the ray (`null` in JSON when the rod is stable along the whole ray).
    pub s_star: Real,
    /// The s the experiment must reach: s*·(1 + margin).
    pub s_target: Real,
    /// The farthest s the trajectory reaches (= `s_target` when `class` is `testable`).
    pub s_reached: Real,
    /// `testable` (reaches `s_target`), `partial` (stops before it), `blocked` (cannot leave
    /// the straight rod).
    pub class: ReachClass,
    /// Why the path stops before `s_target` (`null` when testable).
    pub cause: Option<BlockCause>,
}

impl RayOutcome {
    /// The outcome of a plan.
    pub fn of(plan: &RayPlan) -> RayOutcome {
        RayOutcome {
            direction: [plan.dir.kappa, plan.dir.tau, plan.dir.omega],
            azimuth: plan.azimuth,
            s_star: plan.s_star,
            s_target: plan.s_end,
            s_reached: plan.s_reached,
            class: plan.class,
            cause: plan.cause,
        }
    }
}

/// A time-parametrized joint + motor trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Arm joint names, in the order of [`TrajectoryPoint::q`].
    pub joint_names: Vec<String>,
    /// Name of the motor joint (last in the JSON).
    pub motor_name: String,
    /// The robot base frame name.
    pub frame_id: String,
    /// Samples, in time order.
    pub points: Vec<TrajectoryPoint>,
    /// The ray and how far the trajectory drives it.
    pub outcome: RayOutcome,
}

/// The time-parametrized trajectory of a plan with a path (the seed's protocol): load along the
/// path (with its `reconfigure` pieces) to the farthest s reached, hold for the rig's
/// `hold_time`, and unload back to the straight rod along the same joint path reversed. Timing
/// by [`time_parametrize`] with the robot's joint speed limits scaled by the rig's
/// `velocity_scale`. A partial plan gives the trajectory as far as it goes, its
/// [`RayOutcome`] saying so.
pub fn of_plan(planner: &Planner, plan: &RayPlan) -> Result<Trajectory> {
    let path = plan
        .path
        .as_ref()
        .ok_or_else(|| Error::invalid("plan", "no path", "plan with want_path = true"))?;
    let point = |p: &PlannedPoint, phase: Phase| TrajectoryPoint {
        t: 0.0,
        q: p.q.clone(),
        motor: p.motor,
        s: p.waypoint.s,
        kto: p.waypoint.kto,
        pose: planner.tool_pose(&p.q),
        phase,
    };
    let mut points: Vec<TrajectoryPoint> = path.iter().map(|p| point(p, p.phase)).collect();
    if let Some(last) = path.last() {
        points.push(point(last, Phase::Hold));
        // Unloading: point k is reached by running the loading step k → k+1 backwards,
        // a reconfiguration when that step was one.
        for k in (0..path.len().saturating_sub(1)).rev() {
            let phase = if path[k + 1].phase == Phase::Reconfigure {
                Phase::Reconfigure
            } else {
                Phase::Unload
            };
            points.push(point(&path[k], phase));
        }
    }
    let rig = planner.rig();
    let model = planner.model();
    let scale = rig.planner.velocity_scale;
    let limits = TimingLimits {
        joint_velocity: model.joints().iter().map(|j| j.velocity * scale).collect(),
        motor_velocity: rig.motor.max_velocity * scale,
        end_speed: rig.planner.end_speed,
        rod_length: rig.rod.length,
        hold_time: rig.planner.hold_time,
    };
    time_parametrize(&mut points, &limits)?;
    Ok(Trajectory {
        joint_names: model.joints().iter().map(|j| j.name.clone()).collect(),
        motor_name: "rod_motor".into(),
        frame_id: model.root_link().to_string(),
        points,
        outcome: RayOutcome::of(plan),
    })
}

/// Limits of [`time_parametrize`].
#[derive(Debug, Clone, PartialEq)]
pub struct TimingLimits {
    /// Joint speed limits (rad/s), one per joint.
    pub joint_velocity: Vec<Real>,
    /// Motor speed limit (rad/s).
    pub motor_velocity: Real,
    /// Quasi-static rod-end speed (m/s).
    pub end_speed: Real,
    /// Rod length (m), converting end rotation to a speed.
    pub rod_length: Real,
    /// Least duration of the segment into a `hold` sample (s).
    pub hold_time: Real,
}

/// Fill the times of `points` (the first at t = 0) within `limits`; see the module docs.
///
/// ```
/// use helixreach::planning::trajectory::{time_parametrize, Phase, TimingLimits, TrajectoryPoint};
/// use helixreach::math::Iso3;
/// let p = |q: f64, m: f64, phase| TrajectoryPoint { t: 0.0, q: vec![q], motor: m, s: 0.0,
///     kto: [0.0; 3], pose: Iso3::identity(), phase };
/// let mut pts = vec![p(0.0, 0.0, Phase::Load), p(0.5, 0.0, Phase::Load),
///     p(0.5, 2.0, Phase::Load), p(0.5, 2.0, Phase::Hold)];
/// let lim = TimingLimits { joint_velocity: vec![1.0], motor_velocity: 4.0, end_speed: 1.0,
///     rod_length: 1.0, hold_time: 3.0 };
/// time_parametrize(&mut pts, &lim).unwrap();
/// assert_eq!([pts[1].t, pts[2].t, pts[3].t], [0.5, 1.0, 4.0]);
/// ```
pub fn time_parametrize(points: &mut [TrajectoryPoint], limits: &TimingLimits) -> Result<()> {
    for (j, v) in limits.joint_velocity.iter().enumerate() {
        if !(v.is_finite() && *v > 0.0) {
            return Err(Error::invalid(
                format!("joint velocity limit [{j}]"),
                v,
                "must be finite and > 0",
            ));
        }
    }
    for (name, v) in [
        ("motor velocity limit", limits.motor_velocity),
        ("end speed", limits.end_speed),
        ("rod length", limits.rod_length),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(name, v, "must be finite and > 0"));
        }
    }
    if !(limits.hold_time.is_finite() && limits.hold_time >= 0.0) {
        return Err(Error::invalid(
            "hold time",
            limits.hold_time,
            "must be finite and >= 0",
        ));
    }
    if let Some(first) = points.first_mut() {
        first.t = 0.0;
    }
    for k in 1..points.len() {
        let (a, b) = (&points[k - 1], &points[k]);
        if a.q.len() != limits.joint_velocity.len() || b.q.len() != a.q.len() {
            return Err(Error::invalid(
                "trajectory joints",
                b.q.len(),
                format!("every point needs {} joints", limits.joint_velocity.len()),
            ));
        }
        let mut dt: Real = 0.0;
        for j in 0..a.q.len() {
            dt = dt.max((b.q[j] - a.q[j]).abs() / limits.joint_velocity[j]);
        }
        dt = dt.max((b.motor - a.motor).abs() / limits.motor_velocity);
        let dp = (b.pose.translation.vector - a.pose.translation.vector).norm();
        let dr = rotation_angle(
            &(a.pose.rotation.inverse() * b.pose.rotation)
                .to_rotation_matrix()
                .into_inner(),
        );
        dt = dt.max(dp / limits.end_speed);
        dt = dt.max(dr * limits.rod_length / limits.end_speed);
        if b.phase == Phase::Hold && a.phase != Phase::Hold {
            dt = dt.max(limits.hold_time);
        }
        if !dt.is_finite() {
            return Err(Error::invalid(
                "trajectory segment",
                k,
                "non-finite duration",
            ));
        }
        let t0 = points[k - 1].t;
        points[k].t = t0 + dt;
    }
    Ok(())
}

impl Trajectory {
    /// Joint + motor velocities at each point: the mean of the adjacent segment velocities,
    /// zero at both ends. Row k has `q.len() + 1` entries (the motor last).
    pub fn velocities(&self) -> Vec<Vec<Real>> {
        let n = self.points.len();
        let dof = self.points.first().map_or(0, |p| p.q.len());
        let seg = |k: usize| -> Vec<Real> {
            // Velocity of segment k → k+1 (zero for a zero-length segment).
            let (a, b) = (&self.points[k], &self.points[k + 1]);
            let dt = b.t - a.t;
            let mut v: Vec<Real> = (0..dof)
                .map(|j| {
                    if dt > 0.0 {
                        (b.q[j] - a.q[j]) / dt
                    } else {
                        0.0
                    }
                })
                .collect();
            v.push(if dt > 0.0 {
                (b.motor - a.motor) / dt
            } else {
                0.0
            });
            v
        };
        (0..n)
            .map(|k| {
                if k == 0 || k + 1 == n {
                    vec![0.0; dof + 1]
                } else {
                    let (u, w) = (seg(k - 1), seg(k));
                    u.iter().zip(&w).map(|(a, b)| 0.5 * (a + b)).collect()
                }
            })
            .collect()
    }

    /// The CSV text (header + one row per point), full precision:
    /// [`crate::records::trajectory::trajectory_csv`].
    pub fn to_csv(&self) -> Result<String> {
        crate::records::trajectory::trajectory_csv(self)
    }

    /// The JSON text shaped like ROS `trajectory_msgs/JointTrajectory` (motor as the last joint):
    /// [`crate::records::trajectory::trajectory_json`].
    pub fn to_json(&self) -> Result<String> {
        crate::records::trajectory::trajectory_json(self)
    }

    /// Total duration (s).
    pub fn duration(&self) -> Real {
        self.points.last().map_or(0.0, |p| p.t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Quat, Vec3};

    fn pt(q: [Real; 2], m: Real, x: Real, a: Real) -> TrajectoryPoint {
        TrajectoryPoint {
            t: 0.0,
            q: q.to_vec(),
            motor: m,
            s: x,
            kto: [x, 0.0, 0.0],
            pose: Iso3::from_parts(
                Vec3::new(x, 0.0, 0.0).into(),
                Quat::from_axis_angle(&Vec3::z_axis(), a),
            ),
            phase: Phase::Load,
        }
    }

    #[test]
    fn every_limit_holds_and_one_is_tight_per_segment() {
        let lim = TimingLimits {
            joint_velocity: vec![1.0, 2.0],
            motor_velocity: 3.0,
            end_speed: 0.01,
            rod_length: 0.5,
            hold_time: 0.0,
        };
        let mut pts = vec![
            pt([0.0, 0.0], 0.0, 0.0, 0.0),
            pt([0.3, 0.0], 0.0, 0.0, 0.0),  // joint 0 limits: 0.3 s
            pt([0.3, 1.0], 0.0, 0.0, 0.0),  // joint 1: 0.5 s
            pt([0.3, 1.0], 3.0, 0.0, 0.0),  // motor: 1 s
            pt([0.3, 1.0], 3.0, 0.02, 0.0), // translation: 2 s
            pt([0.3, 1.0], 3.0, 0.02, 0.1), // rotation: 0.1·0.5/0.01 = 5 s
        ];
        time_parametrize(&mut pts, &lim).unwrap();
        let dts: Vec<f64> = pts.windows(2).map(|w| w[1].t - w[0].t).collect();
        for (got, want) in dts.iter().zip([0.3, 0.5, 1.0, 2.0, 5.0]) {
            assert!((got - want).abs() < 1e-12, "{dts:?}");
        }
        let traj = Trajectory {
            joint_names: vec!["a".into(), "b".into()],
            motor_name: "rod_motor".into(),
            frame_id: "base".into(),
            points: pts,
            outcome: RayOutcome {
                direction: [1.0, 0.0, 0.0],
                azimuth: 0.0,
                s_star: 1.0,
                s_target: 1.1,
                s_reached: 1.1,
                class: ReachClass::Testable,
                cause: None,
            },
        };
        for v in traj.velocities() {
            assert!(
                v[0].abs() <= 1.0 + 1e-12 && v[1].abs() <= 2.0 + 1e-12 && v[2].abs() <= 3.0 + 1e-12
            );
        }
        let csv = traj.to_csv().unwrap();
        assert!(csv.starts_with("t,q0,q1,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase\n"));
        assert!(csv.lines().nth(1).unwrap().ends_with(",load"));
        assert_eq!(csv.lines().count(), 7);
        let json: serde_json::Value = serde_json::from_str(&traj.to_json().unwrap()).unwrap();
        assert_eq!(json["joint_names"][2], "rod_motor");
        assert_eq!(json["points"][5]["time_from_start"]["secs"], 8);
        assert!(
            (json["points"][5]["time_from_start"]["nsecs"]
                .as_i64()
                .unwrap()
                - 800_000_000)
                .abs()
                <= 1
        );
        assert_eq!(json["points"][3]["positions"][2], 3.0);
    }

    #[test]
    fn bad_limits_are_errors() {
        let mut pts = vec![pt([0.0, 0.0], 0.0, 0.0, 0.0)];
        let lim = TimingLimits {
            joint_velocity: vec![1.0, 0.0],
            motor_velocity: 3.0,
            end_speed: 0.01,
            rod_length: 0.5,
            hold_time: 1.0,
        };
        assert!(time_parametrize(&mut pts, &lim).is_err());
    }
}
