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
//! Channels: the arm's joints and the motor. Segment k (point k → k+1, steps `d_k`) is
//! traversed at constant speed in `Δt_k = 1/r_k`. Its least duration keeps the speed limits:
//!
//! `Δt_k ≥ max( max_c |d_kc| / v_c ,  |Δp| / v_end ,  Δθ_end·L / v_end ,  |Δs| / v_s )`
//!
//! (`v_c` the joint limits scaled by the rig's `velocity_scale`, and the motor's; `v_end` the
//! quasi-static rod-end speed, `Δp`, `Δθ_end` the rod end's translation and rotation, L the rod
//! length; `v_s` the rod's quasi-static ray speed `max_ray_speed`); a segment into the `hold`
//! sample lasts at least `hold_time`. Accelerations are finite differences: at point k between
//! segments k−1 and k, `a_kc = (d_kc·r_k − d_(k−1)c·r_(k−1)) / ((Δt_(k−1) + Δt_k)/2)`, with the
//! robot at rest (a zero-length segment of zero velocity) before the first point, after the last
//! and on both sides of a segment that does not move (the hold): `|a_kc| ≤ A_c` (the rig's joint
//! and motor acceleration limits times `acceleration_scale`).
//!
//! The rates of each run of moving segments (rest to rest) come from a time-optimal path
//! parametrization on the run's points (the discretization of TOPP-RA, Pham & Pham 2018): σ is
//! the arc length in the acceleration-scaled norm `|d ⊘ A|`, `x_i = σ̇²` at point i, σ̈ constant
//! on each segment (`x_(i+1) = x_i + 2·σ̈_i·ℓ_i`), and at every point `|q'_c·σ̈_i + q''_c·x_i| ≤
//! A_c` with q', q'' the path's finite-difference derivatives, `x_i` at most the square of the
//! slower neighbouring segment's speed bound, `x = 0` at both ends. These constraints are linear
//! in (x, σ̈): a backward pass finds each point's controllable set `[0, K_i]` (bisection to
//! 2⁻⁸⁰ of the bound), a forward pass takes the largest σ̈ staying controllable; a segment's rate
//! is `(√x_i + √x_(i+1)) / (2·ℓ_i)`. The run's rates are then scaled down by the square root of
//! the largest ratio of a written finite-difference acceleration to its limit, when that ratio
//! exceeds 1 (a factor 1 − O(step) on a smooth path), so that the file keeps every limit exactly.
//!
//! Why not the largest rate per segment given its neighbour: the averaged finite difference
//! lets a very short fast segment sit beside a very long slow one, so such rates alternate —
//! files that keep the limits, with durations no interpolating controller follows smoothly. The
//! path parametrization gives a smooth profile that tends to the continuous optimum as the steps
//! shrink (rest to rest on a line: the bang-bang time 2·√(D/A) within 3 % on 240 uneven steps, a
//! unit test). Applying the speed bound at the points (the slower neighbour's) costs a segment
//! beside a slower one a little of its own bound (1.6 % of the least duration of the seed rig's
//! run along (1, 1, 1)). Limits are used times (1 − 10⁻⁶) so that the written file's own finite
//! differences stay within them. Cost: O(n · channels · 80) per trajectory, no allocation per
//! segment.
//!
//! Each point stores the velocity of the quadratic through it and its neighbours (the
//! segment velocities weighted by the opposite segment's duration; zero at a stop) and the
//! acceleration above: positions, velocities and accelerations at every point, consistent with
//! the finite differences of the times and positions.
//!
//! # Outputs (written by `records::trajectory`; this module imports no file format)
//! - CSV: `t,<joint names>,motor,s,kappa,tau,omega,x,y,z,qw,qx,qy,qz,phase`, then the
//!   velocities `v_<joint>..,v_motor` and accelerations `a_<joint>..,a_motor` (the URDF joint
//!   names, as in the JSON; readers also take the index header `q0..`); the pose is the tool frame in the robot
//!   base frame, the quaternion scalar first; `phase` is one of `load`, `reconfigure`, `hold`,
//!   `unload`.
//! - JSON / YAML: the arm's ROS 2 `trajectory_msgs/msg/JointTrajectory` (the motor on its own).
//! - Every output `F` has the sidecar `F.meta.json`: the [`RayOutcome`] and the phases.

use crate::error::{Error, Result};
use crate::math::{rotation_angle, Iso3, Real};
use crate::planning::cause::BlockCause;
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
    /// Joint velocities then the motor's (rad/s), filled by [`time_parametrize`].
    pub velocity: Vec<Real>,
    /// Joint accelerations then the motor's (rad/s²), filled by [`time_parametrize`].
    pub acceleration: Vec<Real>,
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
        velocity: Vec::new(),
        acceleration: Vec::new(),
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
    let model = planner.model();
    time_parametrize(&mut points, &timing_limits(planner)?)?;
    Ok(Trajectory {
        joint_names: model.joints().iter().map(|j| j.name.clone()).collect(),
        motor_name: "rod_motor".into(),
        frame_id: model.root_link().to_string(),
        points,
        outcome: RayOutcome::of(plan),
    })
}

/// The timing limits of a planner's rig: the robot's joint speed limits times the rig's
/// `velocity_scale`, its acceleration limits times `acceleration_scale`, the motor's, the
/// rod-end and ray speeds, the rod length and the hold time.
pub fn timing_limits(planner: &Planner) -> Result<TimingLimits> {
    let rig = planner.rig();
    let model = planner.model();
    let scale = rig.planner.velocity_scale;
    let a_scale = rig.planner.acceleration_scale;
    Ok(TimingLimits {
        joint_velocity: model.joints().iter().map(|j| j.velocity * scale).collect(),
        joint_acceleration: rig
            .joint_acceleration_limits(model.dof())?
            .iter()
            .map(|a| a * a_scale)
            .collect(),
        motor_velocity: rig.motor.max_velocity * scale,
        motor_acceleration: rig.motor.max_acceleration * a_scale,
        ray_speed: rig.planner.max_ray_speed,
        end_speed: rig.planner.end_speed,
        rod_length: rig.rod.length,
        hold_time: rig.planner.hold_time,
    })
}

/// Limits of [`time_parametrize`].
#[derive(Debug, Clone, PartialEq)]
pub struct TimingLimits {
    /// Joint speed limits (rad/s), one per joint.
    pub joint_velocity: Vec<Real>,
    /// Joint acceleration limits (rad/s²), one per joint.
    pub joint_acceleration: Vec<Real>,
    /// Motor speed limit (rad/s).
    pub motor_velocity: Real,
    /// Motor acceleration limit (rad/s²).
    pub motor_acceleration: Real,
    /// Quasi-static rod-end speed (m/s).
    pub end_speed: Real,
    /// Quasi-static ray speed |ds/dt| (1/s; ∞ = none).
    pub ray_speed: Real,
    /// Rod length (m), converting end rotation to a speed.
    pub rod_length: Real,
    /// Least duration of the segment into a `hold` sample (s).
    pub hold_time: Real,
}

/// Duration of a segment that does not move (two equal samples outside a hold), so that times
/// strictly increase (s).
pub const DWELL: Real = 1e-3;

/// The limits are used times this factor, so that the finite differences of the written file
/// (times summed and printed) stay within them.
const SAFETY: Real = 1.0 - 1e-6;

/// One segment of the path for the timing.
struct Segment {
    /// Channel steps (joints, then the motor).
    d: Vec<Real>,
    /// Whether any channel moves.
    moving: bool,
    /// Least duration (velocity limits, end and ray speed, hold).
    dt_min: Real,
}

/// The rates (1/duration) of one run of consecutive moving segments `segs`, from rest to rest,
/// written to `rate`; `kmax` and `x` are scratch buffers (module docs, "Timing").
fn run_rates(
    segs: &[Segment],
    acc: &[Real],
    rate: &mut [Real],
    kmax: &mut Vec<Real>,
    x: &mut Vec<Real>,
) -> Result<()> {
    let n = segs.len();
    let channels = acc.len();
    // Segment lengths in the acceleration-scaled norm |d ⊘ A|: the path parameter σ.
    let len = |k: usize| -> Real {
        segs[k]
            .d
            .iter()
            .zip(acc)
            .map(|(d, a)| (d / a) * (d / a))
            .sum::<Real>()
            .sqrt()
    };
    // q' and q'' = dq/dσ, d²q/dσ² at grid point i (σ at the segments' ends), one-sided at the
    // run's ends.
    let dq = |i: usize, c: usize| -> (Real, Real) {
        if i == 0 {
            (segs[0].d[c] / len(0), 0.0)
        } else if i == n {
            (segs[n - 1].d[c] / len(n - 1), 0.0)
        } else {
            let (l1, l2) = (len(i - 1), len(i));
            let (a, b) = (segs[i - 1].d[c] / l1, segs[i].d[c] / l2);
            (0.5 * (a + b), (b - a) / (0.5 * (l1 + l2)))
        }
    };
    // Largest σ̇² at point i: the neighbouring segments' speed bounds, and |q''·x| ≤ A where
    // q' = 0 (σ̈ cannot then help).
    let cap = |i: usize| -> Real {
        if i == 0 || i == n {
            return 0.0;
        }
        let r = (len(i - 1) / segs[i - 1].dt_min).min(len(i) / segs[i].dt_min);
        let mut c_max = r * r;
        for c in 0..channels {
            let (d1, d2) = dq(i, c);
            if d1 == 0.0 && d2 != 0.0 {
                c_max = c_max.min(acc[c] / d2.abs());
            }
        }
        c_max
    };
    // The σ̈ interval at point i and σ̇² = xi: |q'·σ̈ + q''·σ̇²| ≤ A per channel.
    let u_bounds = |i: usize, xi: Real| -> (Real, Real) {
        let (mut lo, mut hi) = (Real::NEG_INFINITY, Real::INFINITY);
        for c in 0..channels {
            let (d1, d2) = dq(i, c);
            if d1 != 0.0 {
                let (p, q) = ((-acc[c] - d2 * xi) / d1, (acc[c] - d2 * xi) / d1);
                lo = lo.max(p.min(q));
                hi = hi.min(p.max(q));
            }
        }
        (lo, hi)
    };
    // x_(i+1) = x_i + 2·σ̈_i·ℓ_i must lie in [0, next].
    let feasible = |i: usize, xi: Real, next: Real| -> bool {
        let (lo, hi) = u_bounds(i, xi);
        let l = 2.0 * len(i);
        lo.max(-xi / l) <= hi.min((next - xi) / l)
    };
    // Backward pass: the controllable sets [0, K_i] (convex, holding 0: a bisection).
    kmax.clear();
    kmax.resize(n + 1, 0.0);
    for i in (0..n).rev() {
        let (c_max, next) = (cap(i), kmax[i + 1]);
        kmax[i] = if feasible(i, c_max, next) {
            c_max
        } else {
            let (mut lo, mut hi) = (0.0, c_max);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if feasible(i, mid, next) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            lo
        };
    }
    // Forward pass: the largest σ̈ that stays controllable.
    x.clear();
    x.push(0.0);
    for i in 0..n {
        let xi = x[i];
        let (_, hi) = u_bounds(i, xi);
        let l = 2.0 * len(i);
        let u = hi.min((kmax[i + 1] - xi) / l);
        x.push((xi + l * u).clamp(0.0, kmax[i + 1]));
    }
    for i in 0..n {
        let w = x[i].sqrt() + x[i + 1].sqrt();
        rate[i] = if w > 0.0 {
            0.5 * w / len(i)
        } else {
            // Rest at both ends of the segment (a run of one segment): from rest to rest in one
            // step, 2·|d|·r² ≤ A.
            segs[i]
                .d
                .iter()
                .zip(acc)
                .filter(|(d, _)| **d != 0.0)
                .map(|(d, a)| (0.5 * a / d.abs()).sqrt())
                .fold(1.0 / segs[i].dt_min, Real::min)
        };
        if !(rate[i].is_finite() && rate[i] > 0.0) {
            return Err(Error::invalid(
                "trajectory segment",
                i,
                "no finite positive speed",
            ));
        }
    }
    // The written accelerations are the finite differences of the segment velocities: scale
    // the run's rates so that they keep the limits exactly (a factor 1 − O(step) where the
    // path is smooth).
    let mut worst: Real = 0.0;
    for i in 0..=n {
        let before = (i > 0).then(|| (&segs[i - 1].d, rate[i - 1]));
        let after = (i < n).then(|| (&segs[i].d, rate[i]));
        let half =
            0.5 * (before.map_or(0.0, |(_, r)| 1.0 / r) + after.map_or(0.0, |(_, r)| 1.0 / r));
        for c in 0..channels {
            let vi = before.map_or(0.0, |(d, r)| d[c] * r);
            let vo = after.map_or(0.0, |(d, r)| d[c] * r);
            worst = worst.max(((vo - vi) / half).abs() / acc[c]);
        }
    }
    if worst > 1.0 {
        let f = 1.0 / worst.sqrt();
        for r in rate.iter_mut() {
            *r *= f;
        }
    }
    Ok(())
}

/// Fill the times, velocities and accelerations of `points` (the first at t = 0) within
/// `limits`; see the module docs.
///
/// ```
/// use helixreach::planning::trajectory::{time_parametrize, Phase, TimingLimits, TrajectoryPoint};
/// use helixreach::math::Iso3;
/// let p = |q: f64, m: f64, phase| TrajectoryPoint { t: 0.0, q: vec![q], motor: m, s: 0.0,
///     kto: [0.0; 3], pose: Iso3::identity(), phase, velocity: vec![], acceleration: vec![] };
/// let mut pts = vec![p(0.0, 0.0, Phase::Load), p(0.5, 0.0, Phase::Load),
///     p(0.5, 0.0, Phase::Hold)];
/// let lim = TimingLimits { joint_velocity: vec![1.0], joint_acceleration: vec![1.0],
///     motor_velocity: 4.0, motor_acceleration: 1.0, end_speed: 1.0, ray_speed: f64::INFINITY,
///     rod_length: 1.0, hold_time: 3.0 };
/// time_parametrize(&mut pts, &lim).unwrap();
/// // From rest to rest over 0.5 rad: 2·v/Δt ≤ 1 with v = 0.5/Δt, so Δt = 1 s.
/// assert!((pts[1].t - 1.0).abs() < 1e-5);
/// assert!((pts[2].t - pts[1].t - 3.0).abs() < 1e-12);
/// assert_eq!(pts[1].velocity, vec![0.0, 0.0]);
/// ```
pub fn time_parametrize(points: &mut [TrajectoryPoint], limits: &TimingLimits) -> Result<()> {
    let dof = limits.joint_velocity.len();
    if limits.joint_acceleration.len() != dof {
        return Err(Error::invalid(
            "joint acceleration limits",
            limits.joint_acceleration.len(),
            format!("need one per joint ({dof})"),
        ));
    }
    for (name, list) in [
        ("joint velocity limit", &limits.joint_velocity),
        ("joint acceleration limit", &limits.joint_acceleration),
    ] {
        for (j, v) in list.iter().enumerate() {
            if !(v.is_finite() && *v > 0.0) {
                return Err(Error::invalid(
                    format!("{name} [{j}]"),
                    v,
                    "must be finite and > 0",
                ));
            }
        }
    }
    for (name, v) in [
        ("motor velocity limit", limits.motor_velocity),
        ("motor acceleration limit", limits.motor_acceleration),
        ("end speed", limits.end_speed),
        ("rod length", limits.rod_length),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::invalid(name, v, "must be finite and > 0"));
        }
    }
    if limits.ray_speed.is_nan() || limits.ray_speed <= 0.0 {
        return Err(Error::invalid("ray speed", limits.ray_speed, "must be > 0"));
    }
    if !(limits.hold_time.is_finite() && limits.hold_time >= 0.0) {
        return Err(Error::invalid(
            "hold time",
            limits.hold_time,
            "must be finite and >= 0",
        ));
    }
    let vel: Vec<Real> = limits
        .joint_velocity
        .iter()
        .chain([&limits.motor_velocity])
        .map(|v| v * SAFETY)
        .collect();
    let acc: Vec<Real> = limits
        .joint_acceleration
        .iter()
        .chain([&limits.motor_acceleration])
        .map(|a| a * SAFETY)
        .collect();
    let n = points.len();
    let mut segs: Vec<Segment> = Vec::with_capacity(n.saturating_sub(1));
    for k in 1..n {
        let (a, b) = (&points[k - 1], &points[k]);
        if a.q.len() != dof || b.q.len() != dof {
            return Err(Error::invalid(
                "trajectory joints",
                b.q.len(),
                format!("every point needs {dof} joints"),
            ));
        }
        let mut d: Vec<Real> = (0..dof).map(|j| b.q[j] - a.q[j]).collect();
        d.push(b.motor - a.motor);
        let mut dt: Real = 0.0;
        for (c, dc) in d.iter().enumerate() {
            dt = dt.max(dc.abs() / vel[c]);
        }
        let dp = (b.pose.translation.vector - a.pose.translation.vector).norm();
        let dr = rotation_angle(
            &(a.pose.rotation.inverse() * b.pose.rotation)
                .to_rotation_matrix()
                .into_inner(),
        );
        dt = dt.max(dp / limits.end_speed);
        dt = dt.max(dr * limits.rod_length / limits.end_speed);
        dt = dt.max((b.s - a.s).abs() / limits.ray_speed);
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
        let moving = d.iter().any(|x| *x != 0.0);
        segs.push(Segment {
            d,
            moving,
            dt_min: if moving { dt } else { dt.max(DWELL) },
        });
    }
    // Rates: non-moving segments at their least duration; each run of moving segments from
    // rest to rest (module docs).
    let m = segs.len();
    let mut rate: Vec<Real> = segs.iter().map(|g| 1.0 / g.dt_min).collect();
    let (mut kmax, mut x) = (Vec::with_capacity(m + 1), Vec::with_capacity(m + 1));
    let mut k = 0;
    while k < m {
        if !segs[k].moving {
            k += 1;
            continue;
        }
        let end = (k..m).find(|&j| !segs[j].moving).unwrap_or(m);
        run_rates(&segs[k..end], &acc, &mut rate[k..end], &mut kmax, &mut x)?;
        k = end;
    }
    // Times, then each point's velocity and acceleration from its two segments (a stop, with
    // velocity 0, next to a dwell or at either end).
    if let Some(first) = points.first_mut() {
        first.t = 0.0;
    }
    for k in 0..m {
        let t0 = points[k].t;
        points[k + 1].t = t0 + 1.0 / rate[k];
    }
    let seg_v = |k: usize, c: usize| -> (Real, Real) {
        if segs[k].moving {
            (segs[k].d[c] * rate[k], 1.0 / rate[k])
        } else {
            (0.0, 0.0)
        }
    };
    for (i, p) in points.iter_mut().enumerate() {
        let channels = dof + 1;
        p.velocity = vec![0.0; channels];
        p.acceleration = vec![0.0; channels];
        let before = (i > 0).then(|| i - 1);
        let after = (i < m).then_some(i);
        for c in 0..channels {
            let (vi, ti) = before.map_or((0.0, 0.0), |k| seg_v(k, c));
            let (vo, to) = after.map_or((0.0, 0.0), |k| seg_v(k, c));
            let stop = ti == 0.0 || to == 0.0;
            p.velocity[c] = if stop {
                0.0
            } else {
                (vi * to + vo * ti) / (ti + to)
            };
            let half = 0.5 * (ti + to);
            p.acceleration[c] = if half > 0.0 { (vo - vi) / half } else { 0.0 };
        }
    }
    Ok(())
}

impl Trajectory {
    /// Total duration (s).
    pub fn duration(&self) -> Real {
        self.points.last().map_or(0.0, |p| p.t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Quat, Vec3};

    fn pt(q: [Real; 2], m: Real, x: Real, a: Real, phase: Phase) -> TrajectoryPoint {
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
            phase,
            velocity: Vec::new(),
            acceleration: Vec::new(),
        }
    }

    fn limits() -> TimingLimits {
        TimingLimits {
            joint_velocity: vec![1.0, 2.0],
            joint_acceleration: vec![0.5, 3.0],
            motor_velocity: 3.0,
            motor_acceleration: 2.0,
            end_speed: 0.01,
            ray_speed: 0.05,
            rod_length: 0.5,
            hold_time: 2.0,
        }
    }

    /// Finite differences of the times and positions: every segment speed and every point's
    /// acceleration (rest before the first and after the last point) within the limits, the
    /// ray speed too; the stored velocities and accelerations equal the differences.
    #[test]
    fn finite_differences_keep_every_limit() {
        let lim = limits();
        // A curved joint path with a corner, a motor spin, a hold and the way back.
        let mut pts = Vec::new();
        for k in 0..=40 {
            let u = k as Real / 40.0;
            let q = [0.8 * u, if u < 0.5 { 0.0 } else { 0.6 * (u - 0.5) }];
            pts.push(pt(q, 2.0 * u * u, 0.002 * u, 0.0, Phase::Load));
        }
        let last = pts.last().unwrap().clone();
        pts.push(TrajectoryPoint {
            phase: Phase::Hold,
            ..last
        });
        for k in (0..40).rev() {
            let mut p = pts[k].clone();
            p.phase = Phase::Unload;
            pts.push(p);
        }
        time_parametrize(&mut pts, &lim).unwrap();
        let vmax = [1.0, 2.0, 3.0];
        let amax = [0.5, 3.0, 2.0];
        let x = |p: &TrajectoryPoint, c: usize| if c < 2 { p.q[c] } else { p.motor };
        let n = pts.len();
        let seg =
            |k: usize, c: usize| (x(&pts[k + 1], c) - x(&pts[k], c)) / (pts[k + 1].t - pts[k].t);
        let mut tight_v: Real = 0.0;
        let mut tight_a: Real = 0.0;
        for k in 0..n - 1 {
            let dt = pts[k + 1].t - pts[k].t;
            assert!(dt > 0.0, "times strictly increase at {k}");
            assert!((pts[k + 1].s - pts[k].s).abs() / dt <= lim.ray_speed * (1.0 + 1e-9));
            for c in 0..3 {
                let r = seg(k, c).abs() / vmax[c];
                assert!(r <= 1.0 + 1e-9, "segment {k} channel {c}: {r}");
                tight_v = tight_v.max(r);
            }
        }
        assert!(
            (pts[41].t - pts[40].t - 2.0).abs() < 1e-12,
            "the hold lasts hold_time"
        );
        for i in 0..n {
            for c in 0..3 {
                let (vi, ti) = if i > 0 {
                    (seg(i - 1, c), pts[i].t - pts[i - 1].t)
                } else {
                    (0.0, 0.0)
                };
                let (vo, to) = if i + 1 < n {
                    (seg(i, c), pts[i + 1].t - pts[i].t)
                } else {
                    (0.0, 0.0)
                };
                // A dwell (the hold) counts as a stop.
                let (vi, ti) =
                    if i > 0 && pts[i].q == pts[i - 1].q && pts[i].motor == pts[i - 1].motor {
                        (0.0, 0.0)
                    } else {
                        (vi, ti)
                    };
                let (vo, to) =
                    if i + 1 < n && pts[i].q == pts[i + 1].q && pts[i].motor == pts[i + 1].motor {
                        (0.0, 0.0)
                    } else {
                        (vo, to)
                    };
                let a = (vo - vi) / (0.5 * (ti + to));
                let r = a.abs() / amax[c];
                assert!(r <= 1.0 + 1e-9, "point {i} channel {c}: {r}");
                tight_a = tight_a.max(r);
                assert!(
                    (pts[i].acceleration[c] - a).abs() <= 1e-9 * amax[c],
                    "{i} {c}"
                );
                let v = if ti == 0.0 || to == 0.0 {
                    0.0
                } else {
                    (vi * to + vo * ti) / (ti + to)
                };
                assert!((pts[i].velocity[c] - v).abs() <= 1e-9 * vmax[c], "{i} {c}");
            }
        }
        // Some limit is reached (the timing is not merely slow).
        assert!(tight_a > 0.99 || tight_v > 0.99, "{tight_v} {tight_a}");
    }

    /// Rest to rest over one joint step of length L at acceleration A: Δt = √(2L/A) for one
    /// segment (2·v/Δt = A with v = L/Δt).
    #[test]
    fn one_step_from_rest_to_rest() {
        let mut lim = limits();
        lim.end_speed = 1e9;
        lim.ray_speed = Real::INFINITY;
        let mut pts = vec![
            pt([0.0, 0.0], 0.0, 0.0, 0.0, Phase::Load),
            pt([0.2, 0.0], 0.0, 0.0, 0.0, Phase::Load),
        ];
        time_parametrize(&mut pts, &lim).unwrap();
        let want = (2.0 * 0.2 / 0.5 as Real).sqrt();
        assert!(
            (pts[1].t - want).abs() < 1e-5 * want,
            "{} vs {want}",
            pts[1].t
        );
    }

    /// Rest to rest over a straight joint path of length D cut into many segments of uneven
    /// length, the acceleration limit A binding (the speed limit is never reached): the
    /// continuous time-optimal motion is bang-bang, T = 2·√(D/A). The discrete rates converge
    /// to it, and neighbouring segments of similar length take similar times (no alternation
    /// of short and long segments).
    #[test]
    fn many_segments_approach_the_bang_bang_time() {
        let mut lim = limits();
        lim.end_speed = 1e9;
        lim.ray_speed = Real::INFINITY;
        for pattern in [[1.0, 1.0, 1.0], [1.0, 3.0, 2.0], [1.0, 0.2, 5.0]] {
            let steps: Vec<Real> = (0..240).map(|k| pattern[k % 3]).collect();
            let total: Real = steps.iter().sum();
            let d = 1.0;
            let mut q = 0.0;
            let mut pts = vec![pt([0.0, 0.0], 0.0, 0.0, 0.0, Phase::Load)];
            for st in &steps {
                q += d * st / total;
                pts.push(pt([q, 0.0], 0.0, 0.0, 0.0, Phase::Load));
            }
            time_parametrize(&mut pts, &lim).unwrap();
            let want = 2.0 * (d / 0.5 as Real).sqrt();
            let got = pts.last().unwrap().t;
            assert!(
                (got - want).abs() < 0.03 * want,
                "pattern {pattern:?}: {got} s vs bang-bang {want} s"
            );
            // Away from the ends, the speed of neighbouring segments differs by little.
            for k in 20..pts.len() - 21 {
                let v = |k: usize| (pts[k + 1].q[0] - pts[k].q[0]) / (pts[k + 1].t - pts[k].t);
                let (a, b) = (v(k), v(k + 1));
                assert!(
                    (a - b).abs() <= 0.1 * a.max(b),
                    "pattern {pattern:?}, segments {k}, {}: speeds {a} and {b}",
                    k + 1
                );
            }
        }
    }

    #[test]
    fn bad_limits_are_errors() {
        let mut pts = vec![pt([0.0, 0.0], 0.0, 0.0, 0.0, Phase::Load)];
        let mut lim = limits();
        lim.joint_velocity[1] = 0.0;
        assert!(time_parametrize(&mut pts, &lim).is_err());
        let mut lim = limits();
        lim.joint_acceleration.pop();
        assert!(time_parametrize(&mut pts, &lim).is_err());
    }
}
