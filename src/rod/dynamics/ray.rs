//! The paper's manipulation in silico: the rod's held end driven along a ray
//! `(κ, τ, ω) = s(t)·S̄` at finite speed, integrated by [`Stepper`], with the helix error e
//! recorded against s and the instability detected by [`detect`].
//!
//! # Speed convention
//! `speed` is the **ray speed** `v = ds/dt` (nondimensional s per second): `s(t) = v·t`. The
//! held end then moves at `L·|d r_end/ds|·v` m/s, which varies along the ray (the mean end
//! speed over a run is reported in [`Simulation::mean_end_speed`]). The ray speed is the
//! natural parameter of the study because the instability point is a value of s.
//!
//! # Set-up
//! - The rod (n edges, straddling clamps [`ClampPlacement::Straddle`] as in
//!   [`crate::boundary::der`], so s_dyn → the DER statics s* at the same n as v → 0) starts
//!   straight along the clamp frame's z axis, untwisted, at rest; the first edge is clamped at
//!   the origin with the identity frame.
//! - With gravity, the initial state is first relaxed to the static equilibrium under its
//!   weight ([`Stepper::relax`]).
//! - At time t the end clamp is the helix end pose at s(t) ([`crate::helix::Helix::end_pose`]:
//!   position and material frame, motor angle ω/c included), shifted by the jitter
//!   ([`Jitter`], position only, magnitude `jitter·L`).
//! - Samples are recorded every `record_ds` in s: `(t, s, κ, τ, ω, e, E_el)` with e the safe
//!   helix error ([`crate::helix::error_metric::safe_error`], radius floor
//!   [`RADIUS_FLOOR`]) of the nodes against the helix at the same arc lengths (nodes 0 and n of
//!   the straddling clamps sit half an edge outside the rod and are compared with the helix
//!   continued there).
//! - The run stops at `s_max`, or once e has stayed above the detection threshold and s has
//!   advanced by `post_jump·s` past the first crossing (enough samples to confirm the jump).
//!
//! # Unloading (the seed's protocol: load, hold, unload)
//! With [`SimParams::unload`] the run does not stop there: the end turns at `s_turn` (given, or
//! where the loading run would have stopped: the confirmed jump plus `post_jump`, or `s_max`),
//! is held for `hold` seconds, and then driven back along the same ray at the same ray speed
//! down to s = 0. Every sample carries its [`Phase`]; loading samples are recorded every
//! `record_ds` in s as before, hold and unloading samples every `record_ds/speed` seconds.
//! The instability is detected on the loading samples only. The **return** `s_return` is read
//! from the unloading samples: with ẽ the running median of e (the detection's window) and T the
//! loading detection's threshold (or `detect.jump` without a detection), the last unloading
//! sample with ẽ ≥ T and the next one bracket the return, and `s_return` is the log-linear
//! crossing of T between them. No unloading sample above T: `s_return` is `None` (the rod never
//! left the helix, or came back during the hold); above T to the end: `s_return = 0`.
//!
//! Unloading requires damping ([`SimParams::damping`] > 0, else [`SimParams::validate`] refuses
//! the run): without it the post-snap rod rings (implicit Euler barely damps the slow modes),
//! leaves the static far branch before its fold and keeps its helix error above T until the
//! ringing has decayed, so the crossing above would time the decay (3.69 against the static
//! return 5.94 along (1, 1, 1) at n = 16), not the return. With ζ = 2/s the run follows the
//! static far branch and returns just below its end (`tests/bifurcation.rs`,
//! `damped_dynamic_unloading_follows_the_static_far_branch_and_returns_at_its_end`).

use super::centerline::Centerline;
use super::detect::{detect, DetectParams, Detection};
use super::jitter::Jitter;
use super::presets::PhysicalRod;
use super::stepper::{EndClamp, Stepper, StepperParams};
use crate::directions::Direction;
use crate::error::{require_finite, require_positive, Error, Result};
use crate::helix::error_metric::{safe_error, RADIUS_FLOOR};
use crate::helix::Helix;
use crate::math::{Real, Vec3};
use crate::rod::clamp::{clamp_nodes, ClampPlacement, End};
use crate::rod::params::twist_ratio;
use crate::rod::{Rod, RodState};

/// A time step lands on a recording (or turning) time when it is within this fraction of `dt`
/// of it: `s = v·t` accumulates rounding, and a step 1e-16 short must not skip a sample.
const RECORD_SLACK: Real = 1e-9;
/// The same in s (nondimensional): a step within this of a recording or turning point reaches it.
const RECORD_SLACK_S: Real = 1e-12;
/// Round-off allowed between the clamp's nodes and the straight rod's first nodes (both built
/// from the same `ē` in nondimensional units of order 1): a debug invariant.
const CLAMP_NODE_ROUNDOFF: Real = 1e-14;

/// Parameters of one simulated ray (SI units unless stated).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimParams {
    /// The physical rod.
    pub rod: PhysicalRod,
    /// Number of edges n (≥ 4).
    pub n_edges: usize,
    /// Time step Δt (s, > 0).
    pub dt: Real,
    /// Ray speed v = ds/dt (1/s, > 0; see the module docs).
    pub speed: Real,
    /// Gravity vector in the clamp frame (m/s²); zero for none. The seed rig holds the rod
    /// pointing up, i.e. gravity `(0, 0, −g)`.
    pub gravity: Vec3,
    /// Mass-proportional viscous damping ζ (1/s, ≥ 0).
    pub damping: Real,
    /// Jitter magnitude d/L (≥ 0).
    pub jitter: Real,
    /// Jitter knot period (s, > 0; at least 2Δt so the steps resolve the path).
    pub jitter_period: Real,
    /// Jitter seed.
    pub seed: u64,
    /// Largest s simulated.
    pub s_max: Real,
    /// Sample spacing in s.
    pub record_ds: Real,
    /// After e first exceeds the threshold, continue for this fraction of s (≥ 0).
    pub post_jump: Real,
    /// The detection rule.
    pub detect: DetectParams,
    /// Newton controls.
    pub stepper: StepperParams,
    /// Load, hold and unload (see the module docs); `None`: loading only.
    pub unload: Option<Unload>,
    /// Keep the configuration of every `k`-th recorded sample (the first one included) as a
    /// [`Centerline`] in [`Simulation::centerlines`]; 0: none.
    pub centerline_stride: usize,
}

/// The unloading protocol of [`SimParams::unload`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unload {
    /// Where loading turns; `None`: where a loading-only run would stop.
    pub s_turn: Option<Real>,
    /// Hold time at `s_turn` (s, ≥ 0).
    pub hold: Real,
}

impl Default for Unload {
    /// Turn where the loading run stops, hold 1 s.
    fn default() -> Self {
        Unload {
            s_turn: None,
            hold: 1.0,
        }
    }
}

/// Which part of the load–hold–unload protocol a sample belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    /// s increasing.
    Load,
    /// s held at the turn.
    Hold,
    /// s decreasing.
    Unload,
}

impl Phase {
    /// `load`, `hold` or `unload`.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Load => "load",
            Phase::Hold => "hold",
            Phase::Unload => "unload",
        }
    }
}

impl Default for SimParams {
    /// The paper-sim rod, n = 40, Δt = 2 ms, v = 0.1/s, no gravity, no damping, no jitter
    /// (period 0.1 s, seed 0), s_max = 40, samples every 0.01, 5 % past the jump.
    fn default() -> Self {
        SimParams {
            rod: PhysicalRod::paper_sim(),
            n_edges: 40,
            dt: 2e-3, // s (the time step, not a tolerance)
            speed: 0.1,
            gravity: Vec3::zeros(),
            damping: 0.0,
            jitter: 0.0,
            jitter_period: 0.1,
            seed: 0,
            s_max: 40.0,
            record_ds: 0.01,
            post_jump: 0.05,
            detect: DetectParams::default(),
            stepper: StepperParams::default(),
            unload: None,
            centerline_stride: 0,
        }
    }
}

impl SimParams {
    /// Check every field (errors name the field and value).
    pub fn validate(&self) -> Result<()> {
        self.rod.validate()?;
        if self.n_edges < 4 {
            return Err(Error::invalid(
                "n_edges",
                self.n_edges,
                "the dynamics needs at least 4 edges",
            ));
        }
        require_positive("dt", self.dt)?;
        require_positive("speed", self.speed)?;
        for (f, v) in [
            ("gravity_x", self.gravity.x),
            ("gravity_y", self.gravity.y),
            ("gravity_z", self.gravity.z),
        ] {
            require_finite(f, v)?;
        }
        for (f, v) in [
            ("damping", self.damping),
            ("jitter", self.jitter),
            ("post_jump", self.post_jump),
        ] {
            require_finite(f, v)?;
            if v < 0.0 {
                return Err(Error::invalid(f, v, "must be >= 0"));
            }
        }
        if self.jitter >= 0.5 {
            return Err(Error::invalid(
                "jitter",
                self.jitter,
                "must be < 0.5 (a fraction of the rod length)",
            ));
        }
        require_positive("jitter_period", self.jitter_period)?;
        if self.jitter > 0.0 && self.dt > 0.5 * self.jitter_period {
            return Err(Error::invalid(
                "dt",
                self.dt,
                format!(
                    "must be <= half the jitter period ({} s) to resolve the jitter path",
                    self.jitter_period
                ),
            ));
        }
        require_positive("s_max", self.s_max)?;
        if self.s_max > crate::limits::MAX_S {
            return Err(Error::invalid(
                "s_max",
                self.s_max,
                format!(
                    "must be <= {:e} (helixreach::limits::MAX_S)",
                    crate::limits::MAX_S
                ),
            ));
        }
        require_positive("record_ds", self.record_ds)?;
        self.detect.validate()?;
        if let Some(u) = self.unload {
            require_finite("hold", u.hold)?;
            if u.hold < 0.0 || u.hold > 1e4 {
                return Err(Error::invalid("hold", u.hold, "must lie in [0, 1e4] s"));
            }
            if let Some(st) = u.s_turn {
                require_positive("s_turn", st)?;
                if st > self.s_max {
                    return Err(Error::invalid(
                        "s_turn",
                        st,
                        format!("must be <= s_max = {}", self.s_max),
                    ));
                }
            }
        }
        // One time step advances s by speed·dt: more than s_max in one step is no simulation
        // (and would evaluate helices far past s_max).
        let ds = self.speed * self.dt;
        if ds > self.s_max {
            return Err(Error::invalid(
                "speed",
                self.speed,
                format!(
                    "one time step (dt = {} s) would advance s by speed·dt = {}, more than \
                     s_max = {}: lower the speed or dt",
                    crate::error::fmt_num(self.dt),
                    crate::error::fmt_num(ds),
                    crate::error::fmt_num(self.s_max)
                ),
            ));
        }
        // Loading to s_max, and with unloading back to 0 plus the hold: an upper bound on the
        // steps of the run.
        let load = self.s_max / (self.speed * self.dt);
        let steps = match &self.unload {
            Some(u) => 2.0 * load + u.hold / self.dt,
            None => load,
        };
        let max = crate::limits::MAX_SIM_STEPS;
        if steps > max as Real {
            return Err(Error::invalid(
                "dt",
                self.dt,
                format!(
                    "the run would take up to {steps:.3e} time steps (s_max/(speed·dt), doubled \
                     and plus hold/dt when unloading); at most {max} (raise dt or speed)"
                ),
            ));
        }
        if self.unload.is_some() && self.damping == 0.0 {
            return Err(Error::invalid(
                "damping",
                self.damping,
                "unloading needs damping > 0 (e.g. 2 /s): undamped, the post-snap rod rings, \
                 leaves the far branch early and its helix error stays above the threshold \
                 until the ringing has decayed, so the return read from it would measure that \
                 decay, not the return (module docs, \"Unloading\")",
            ));
        }
        Ok(())
    }
}

/// One recorded sample.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Sample {
    /// Time (s).
    pub t: Real,
    /// Distance along the ray.
    pub s: Real,
    /// κ = s·κ̂.
    pub kappa: Real,
    /// τ = s·τ̂.
    pub tau: Real,
    /// ω = s·ω̂.
    pub omega: Real,
    /// Helix error e (safe form).
    pub error: Real,
    /// Elastic energy (J).
    pub energy: Real,
    /// Load, hold or unload.
    pub phase: Phase,
}

/// The result of [`simulate_ray`].
#[derive(Debug, Clone)]
pub struct Simulation {
    /// The recorded series.
    pub samples: Vec<Sample>,
    /// The detected instability, if any.
    pub detection: Option<Detection>,
    /// Steps taken.
    pub steps: usize,
    /// Newton iterations summed over all steps.
    pub newton_iterations: usize,
    /// Sub-steps taken (> steps when steps had to be split).
    pub substeps: usize,
    /// Mean speed of the held end (m/s) over the run.
    pub mean_end_speed: Real,
    /// The time unit T₀ (s) of the nondimensional equations.
    pub time_unit: Real,
    /// Whether the run ended early because a step failed after the jump.
    pub stopped_on_failure: bool,
    /// With unloading: where loading turned.
    pub s_turn: Option<Real>,
    /// With unloading: where the rod returned to the helix (see the module docs).
    pub s_return: Option<Real>,
    /// The kept configurations ([`SimParams::centerline_stride`]), in sample order.
    pub centerlines: Vec<Centerline>,
}

impl Simulation {
    /// The detected `s_dyn`, or ∞ when no instability was seen up to `s_max`.
    pub fn s_dyn(&self) -> Real {
        self.detection.map_or(Real::INFINITY, |d| d.s_dyn)
    }
}

/// Simulate the ray `dir` (see the module docs). `progress(s)` is called after every recorded
/// sample.
pub fn simulate_ray(
    dir: &Direction,
    p: &SimParams,
    progress: &mut dyn FnMut(Real),
) -> Result<Simulation> {
    p.validate()?;
    let dir = Direction::new(dir.kappa, dir.tau, dir.omega)?;
    let phys = p.rod;
    let n = p.n_edges;
    let c = twist_ratio(phys.nu)?;
    let t0 = phys.time_unit();
    let len = phys.length;
    let placement = ClampPlacement::Straddle;
    let h = placement.edge_length(n, 1.0);
    let rod = Rod::uniform(n, h, phys.nondimensional_material()?)?;
    // Straight initial rod along z.
    let nodes: Vec<Vec3> = (0..=n)
        .map(|i| Vec3::new(0.0, 0.0, placement.node_arclength(n, i, 1.0)))
        .collect();
    let [a, b] = clamp_nodes(placement, End::Start, &Vec3::zeros(), &Vec3::z(), h);
    debug_assert!(
        (a - nodes[0]).norm() < CLAMP_NODE_ROUNDOFF && (b - nodes[1]).norm() < CLAMP_NODE_ROUNDOFF
    );
    let state = RodState::from_nodes(&nodes, &vec![0.0; n], &Vec3::x())
        .ok_or_else(|| Error::invalid("n_edges", n, "degenerate initial rod"))?;
    // Nondimensional weight per length: ρA g L³/k_b.
    let gscale = phys.linear_density() * len.powi(3) / phys.bending_stiffness();
    let gravity = p.gravity * gscale;
    let twist_inertia = 0.5 * phys.slenderness().powi(2);
    let mut st = Stepper::new(
        rod,
        placement,
        state,
        twist_inertia,
        gravity,
        p.damping * t0,
        p.stepper,
    )?;
    if gravity.norm() > 0.0 {
        st.relax()?;
    }
    let dt = p.dt / t0;
    let mut jitter = Jitter::new(p.jitter, p.jitter_period, p.seed);
    let mut helix_nodes = vec![Vec3::zeros(); n + 1];
    let mut rod_nodes = vec![Vec3::zeros(); n + 1];
    let arcs: Vec<Real> = (0..=n)
        .map(|i| placement.node_arclength(n, i, 1.0))
        .collect();
    let mut samples = Vec::new();
    let mut centerlines = Vec::new();
    let mut recorded_count = 0usize;
    let stride = p.centerline_stride;
    let ekb = phys.bending_stiffness() / len;
    let mut record = |st: &Stepper, t: Real, s: Real, phase: Phase| -> Result<Sample> {
        if stride > 0 && recorded_count % stride == 0 {
            let state = st.state();
            centerlines.push(Centerline {
                sample: recorded_count,
                t,
                s,
                nodes: (0..=n).map(|i| state.node(i)).collect(),
                frames: (0..n).map(|j| state.material_frame(j)).collect(),
            });
        }
        recorded_count += 1;
        let [k, ta, w] = dir.at(s);
        let hx = Helix::new(k, ta, w)?;
        for i in 0..=n {
            helix_nodes[i] = hx.position(arcs[i]);
            rod_nodes[i] = st.state().node(i);
        }
        let e = safe_error(&rod_nodes, &helix_nodes, &hx, 1.0, RADIUS_FLOOR)?;
        Ok(Sample {
            t,
            s,
            kappa: k,
            tau: ta,
            omega: w,
            error: e,
            energy: st.elastic_energy() * ekb,
            phase,
        })
    };
    samples.push(record(&st, 0.0, 0.0, Phase::Load)?);
    progress(0.0);
    let mut next_record = p.record_ds;
    let mut first_cross: Option<Real> = None;
    let (mut steps, mut newton, mut substeps) = (0usize, 0usize, 0usize);
    let mut stopped_on_failure = false;
    let mut path_len = 0.0;
    let mut last_end = Helix::new(0.0, 0.0, 0.0)?
        .end_pose_unchecked(1.0, c)
        .position;
    let mut k: u64 = 0;
    // The schedule s(t): loading at the ray speed until the turn (t_turn, s_turn), then the
    // hold, then unloading at the same speed.
    let hold = p.unload.map_or(0.0, |u| u.hold);
    let mut turn: Option<(Real, Real)> = None;
    let sched = move |t: Real, turn: Option<(Real, Real)>| -> (Real, Phase) {
        match turn {
            None => (p.speed * t, Phase::Load),
            Some((tt, st)) if t <= tt + hold => (st, Phase::Hold),
            Some((tt, st)) => ((st - p.speed * (t - tt - hold)).max(0.0), Phase::Unload),
        }
    };
    let record_dt = p.record_ds / p.speed;
    let mut next_record_t = 0.0;
    loop {
        let t_k = k as Real * p.dt;
        let t_next = (k + 1) as Real * p.dt;
        let (s_next, phase) = sched(t_next, turn);
        // The end pose as a function of the fraction of the step. The (smooth) jitter is
        // evaluated at both ends of the step and interpolated linearly for sub-steps.
        let (j0, j1) = (jitter.at(t_k), jitter.at(t_next));
        let tr = turn;
        let end = |lam: Real| -> EndClamp {
            let (s, _) = sched(t_k + lam * p.dt, tr);
            let [k, ta, w] = dir.at(s);
            // Helix::new cannot fail for finite, bounded parameters (validated s_max).
            let hx = Helix::new(k, ta, w).expect("validated helix parameters");
            let pose = hx.end_pose_unchecked(1.0, c);
            EndClamp {
                position: pose.position + j0 + (j1 - j0) * lam,
                frame: pose.material,
            }
        };
        match st.step(dt, Some(&end)) {
            Ok(r) => {
                newton += r.newton_iterations;
                substeps += r.substeps;
            }
            Err(e) => {
                if first_cross.is_some() {
                    stopped_on_failure = true;
                    break;
                }
                return Err(e);
            }
        }
        steps += 1;
        k += 1;
        let endp = end(1.0).position;
        path_len += (endp - last_end).norm();
        last_end = endp;
        if phase != Phase::Load {
            if t_next + RECORD_SLACK * p.dt >= next_record_t {
                samples.push(record(&st, t_next, s_next, phase)?);
                progress(s_next);
                next_record_t += record_dt;
            }
            if phase == Phase::Unload && s_next <= 0.0 {
                break;
            }
            continue;
        }
        let recorded = s_next + RECORD_SLACK_S >= next_record;
        if recorded {
            let smp = record(&st, t_next, s_next, phase)?;
            samples.push(smp);
            progress(s_next);
            next_record += p.record_ds;
            if first_cross.is_none() && smp.error >= p.detect.jump {
                first_cross = Some(s_next);
            }
        }
        // Where a loading-only run stops; with unloading, where it turns.
        let mut stop = s_next >= p.s_max;
        if let Some(sc) = first_cross {
            // Stop once the detector confirms a jump with enough samples after it; re-arm if it
            // does not (a transient excursion, or noise).
            if recorded && s_next >= sc * (1.0 + p.post_jump) && samples.len() % 10 == 0 {
                let (ss, ee): (Vec<Real>, Vec<Real>) =
                    samples.iter().map(|x| (x.s, x.error)).unzip();
                match detect(&ss, &ee, &p.detect)? {
                    Some(d)
                        if samples.len() - d.jump_index > p.detect.persist + p.detect.window =>
                    {
                        stop = true;
                    }
                    Some(_) => {}
                    None => first_cross = None,
                }
            }
        }
        match p.unload {
            None if stop => break,
            None => {}
            Some(u) => {
                let turn_now = match u.s_turn {
                    Some(st) => s_next + RECORD_SLACK_S >= st,
                    None => stop,
                };
                if turn_now {
                    turn = Some((t_next, s_next));
                    next_record_t = t_next + record_dt;
                }
            }
        }
    }
    let loading: Vec<&Sample> = samples.iter().filter(|x| x.phase == Phase::Load).collect();
    let s_series: Vec<Real> = loading.iter().map(|x| x.s).collect();
    let e_series: Vec<Real> = loading.iter().map(|x| x.error).collect();
    let detection = detect(&s_series, &e_series, &p.detect)?;
    let s_return = if p.unload.is_some() {
        let level = detection.map_or(p.detect.jump, |d| d.threshold);
        return_point(&samples, level, p.detect.window)
    } else {
        None
    };
    let total_t = steps as Real * p.dt;
    Ok(Simulation {
        samples,
        detection,
        steps,
        newton_iterations: newton,
        substeps,
        s_turn: turn.map(|t| t.1),
        s_return,
        mean_end_speed: if total_t > 0.0 {
            path_len * len / total_t
        } else {
            0.0
        },
        time_unit: t0,
        stopped_on_failure,
        centerlines,
    })
}

/// The return on unloading (see the module docs): the log-linear crossing of `level` by the
/// running median of e after the last unloading sample at or above it.
pub fn return_point(samples: &[Sample], level: Real, window: usize) -> Option<Real> {
    let un: Vec<&Sample> = samples
        .iter()
        .filter(|x| x.phase == Phase::Unload)
        .collect();
    let e: Vec<Real> = un.iter().map(|x| x.error).collect();
    let m = super::detect::running_median(&e, window);
    let last = m.iter().rposition(|&v| v >= level)?;
    if last + 1 >= m.len() {
        return Some(0.0);
    }
    let (s0, s1) = (un[last].s, un[last + 1].s);
    let (a, b) = (
        m[last].max(crate::math::tol::TINY).ln(),
        m[last + 1].max(crate::math::tol::TINY).ln(),
    );
    let f = if a > b {
        ((a - level.ln()) / (a - b)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Some(s0 + f * (s1 - s0))
}
