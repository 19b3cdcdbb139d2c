//! Inverse kinematics: every solution found for a tool pose (or a tool position + axis with the
//! roll about the axis free), inside the joint limits, polished to `tol::IK_POSITION` /
//! `tol::IK_ANGLE`.
//!
//! # Method: box-constrained Levenberg–Marquardt
//! With the pose error `e(q) = [p* − p(q); log(R*·R(q)ᵀ)]` (root frame, m and rad) and the
//! geometric Jacobian `J` ([`crate::robot::kinematics`]), one iteration solves
//!
//! `(J_A J_Aᵀ + λ I₆) y = e,  Δq = J_Aᵀ y`
//!
//! (damped least squares, i.e. the minimum-norm LM step of the redundant arm), where `J_A` is `J`
//! with the columns of the *inactive* joints zeroed: a locked joint (the redundancy parameter),
//! and every joint that sits on a limit while the step would push it outward (active set,
//! recomputed until the step is feasible). The new point is projected onto the box of joint
//! limits, so the limits hold at every iterate — no clamping afterwards. The step is accepted
//! only if it lowers `‖e‖`; then `λ` shrinks (toward Gauss–Newton, quadratic convergence to
//! `1e-10`), otherwise `λ` grows and the step is retried (adaptive damping: robust at
//! singularities, where `J Jᵀ` loses rank and `λ I` keeps the system definite).
//! A run that has not halved its error within 10 iterations is abandoned (stalled, typically
//! against a limit) and the next seed is tried. Optionally ([`IkParams::limit_weighting`]) the
//! columns of `J` are weighted against joint limits (weighted least norm after Chan & Dubey).
//!
//! With the roll free ([`IkTarget::Axis`]), the orientation residual is the rotation vector
//! `φ` that turns the current tool axis `z` onto `z*`, and the angular rows of `J` are projected
//! onto the plane ⊥ `z` (`(I − z zᵀ) J_ω`), since a rotation about `z` does not move `z`.
//!
//! # Redundancy and all solutions
//! The 7-DOF arm has a continuum of solutions per pose. The redundancy parameter is one locked
//! joint ([`IkParams::redundancy_joint`], the Sawyer seed used `j0`) sampled at
//! [`IkParams::samples`] evenly spaced values across its range; for each value the solver runs
//! from the caller's seeds and then from [`IkParams::restarts`] random seeds (a ChaCha8 stream
//! fixed by [`IkParams::rng_seed`]: deterministic), and keeps the distinct converged solutions
//! (max-norm distance > [`IkParams::dedup_tolerance`]).
//! [`IkSolver::track`] is the planner's fast path: one LM run from the previous waypoint's
//! solution, which converges to the nearby solution (minimum-norm steps).
//!
//! Iterations use fixed-size nalgebra matrices on the stack: no allocation per iteration.

use super::kinematics::{Frame, Jacobian, MAX_DOF};
use super::model::RobotModel;
use crate::error::{Error, Result};
use crate::math::{rotation_sin_cos, tol, Mat3, Real, Vec3};
use nalgebra::Vector6;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Iterations over which a run must halve its error (else it is abandoned as stalled).
const STALL_WINDOW: usize = 10;
/// [`log_rot`]: below this angle (rad) the rotation vector is the skew part itself
/// (`θ/sin θ = 1` to machine precision).
const LOG_SMALL_ANGLE: Real = 1e-8;
/// sin(`LOG_SMALL_ANGLE`) (= the angle to round-off).
const LOG_SMALL_SIN: Real = LOG_SMALL_ANGLE;
/// [`log_rot`]: within this of π (rad) the axis comes from the symmetric part (nalgebra), where
/// `θ/sin θ` loses accuracy.
const LOG_NEAR_PI: Real = 1e-4;
/// Levenberg–Marquardt damping at the start of a solve (dimensionless, on JᵀJ's scale): the
/// default of [`IkParams::initial_damping`].
pub const LM_LAMBDA_START: Real = 1e-3;
/// Initial damping of solvers that only track ([`IkParams::tracking`]): every run starts
/// within one small step of its solution, where the undamped (Gauss–Newton) step converges
/// quadratically; a rejected step raises it ×8.
pub const TRACK_DAMPING: Real = 1e-7;
/// Least Levenberg–Marquardt damping after successful steps.
const LM_LAMBDA_MIN: Real = 1e-14;
/// Limit weighting: the distance (rad) to a joint limit is at least this (the weight stays
/// finite at the limit).
const LIMIT_GAP_FLOOR: Real = 1e-9;

/// What the tool must reach.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum IkTarget {
    /// A full tool pose (root frame).
    Pose(Frame),
    /// A tool position and tool z axis (unit, root frame); the roll about the axis is free.
    Axis {
        /// Tool origin (m).
        position: Vec3,
        /// Unit tool z axis.
        axis: Vec3,
    },
}

impl IkTarget {
    /// A full-pose target, validated (finite, proper rotation).
    pub fn pose(pose: Frame) -> Result<IkTarget> {
        for (i, v) in pose.pos.iter().enumerate() {
            crate::error::require_finite(&format!("target.position[{i}]"), *v)?;
        }
        let r = &pose.rot;
        if !r.iter().all(|x| x.is_finite())
            || (r.transpose() * r - Mat3::identity()).norm() > crate::math::tol::INPUT_ROTATION
            || r.determinant() < 0.0
        {
            return Err(Error::invalid(
                "target.rotation",
                format!("{r:?}"),
                "must be a finite proper rotation matrix",
            ));
        }
        Ok(IkTarget::Pose(pose))
    }

    /// A position + axis target (roll free), validated; the axis is normalized.
    pub fn axis(position: Vec3, axis: Vec3) -> Result<IkTarget> {
        for (i, v) in position.iter().chain(axis.iter()).enumerate() {
            crate::error::require_finite(&format!("target[{i}]"), *v)?;
        }
        let n = axis.norm();
        if n < crate::math::tol::ZERO_VECTOR {
            return Err(Error::invalid("target.axis", n, "must be non-zero"));
        }
        Ok(IkTarget::Axis {
            position,
            axis: axis / n,
        })
    }

    /// The number of task coordinates the target fixes: 6 for a pose, 5 for a position + axis
    /// (the roll is free). An arm with more joints than this has self-motion at the target (a
    /// 7-DOF arm at a pose: one dimension; a 6-DOF arm at a free-roll target: one); an arm
    /// with no more has isolated solutions (IK branches), and locking a joint leaves it fewer
    /// joints than the target needs.
    ///
    /// ```
    /// use helixreach::robot::{Frame, IkTarget};
    /// let t = IkTarget::pose(Frame::identity()).unwrap();
    /// assert_eq!((t.dimension(), t.free_roll().dimension()), (6, 5));
    /// ```
    pub fn dimension(&self) -> usize {
        match self {
            IkTarget::Pose(_) => 6,
            IkTarget::Axis { .. } => 5,
        }
    }

    /// The same target with the roll freed (pose → its position and tool z axis).
    pub fn free_roll(&self) -> IkTarget {
        match *self {
            IkTarget::Pose(f) => IkTarget::Axis {
                position: f.pos,
                axis: f.rot.column(2).into_owned(),
            },
            a => a,
        }
    }

    /// Position and orientation errors of a tool pose (m, rad).
    pub fn errors(&self, tool: &Frame) -> (Real, Real) {
        let (p, s, c) = self.error_parts(tool);
        (p.norm(), s.atan2(c))
    }

    /// Position error (target − tool) and the sine and cosine of the orientation error angle
    /// (the tool-axis angle when the roll is free).
    #[inline]
    fn error_parts(&self, tool: &Frame) -> (Vec3, Real, Real) {
        match self {
            IkTarget::Pose(t) => {
                let (s, c) = rotation_sin_cos(&(t.rot * tool.rot.transpose()));
                (t.pos - tool.pos, s, c)
            }
            IkTarget::Axis { position, axis } => {
                let z = tool.rot.column(2);
                (position - tool.pos, z.cross(axis).norm(), z.dot(axis))
            }
        }
    }

    /// Whether a tool pose is within `tp` (m) and `ta` (rad, below π/2) of the target, given
    /// as `tp2` = tp² and `tan_ta` = tan(ta): the test of [`IkTarget::errors`] without the
    /// arctangent (an angle θ = atan2(s, c) is at most `ta` exactly when c > 0 and
    /// s ≤ tan(ta)·c).
    #[inline]
    fn within(&self, tool: &Frame, tp2: Real, tan_ta: Real) -> bool {
        let (p, s, c) = self.error_parts(tool);
        p.norm_squared() <= tp2 && c > 0.0 && s <= tan_ta * c
    }

    /// Residual `e` (6) and, in axis mode, the projection of the angular rows of `jac`.
    #[inline]
    fn residual(&self, tool: &Frame, jac: Option<&mut Jacobian>) -> Vector6<Real> {
        let (p, w) = match self {
            IkTarget::Pose(t) => (t.pos - tool.pos, log_rot(&(t.rot * tool.rot.transpose()))),
            IkTarget::Axis { position, axis } => {
                let z: Vec3 = tool.rot.column(2).into_owned();
                if let Some(j) = jac {
                    // (I − z zᵀ) J_ω
                    for c in 0..MAX_DOF {
                        let wc: Vec3 = j.fixed_view::<3, 1>(3, c).into_owned();
                        let proj = wc - z * z.dot(&wc);
                        j.fixed_view_mut::<3, 1>(3, c).copy_from(&proj);
                    }
                }
                let c = z.cross(axis);
                let s = c.norm();
                let ang = s.atan2(z.dot(axis));
                let w = if s > tol::TINY {
                    c * (ang / s)
                } else if ang > 1.0 {
                    // Antiparallel: turn about any axis ⊥ z.
                    let any = if z.x.abs() < 0.9 {
                        Vec3::x()
                    } else {
                        Vec3::y()
                    };
                    z.cross(&any).normalize() * ang
                } else {
                    Vec3::zeros()
                };
                (position - tool.pos, w)
            }
        };
        Vector6::new(p.x, p.y, p.z, w.x, w.y, w.z)
    }
}

/// The solution y of `(J·W·Jᵀ + λ·I)·y = e` with `W = diag(w)`, `w ≥ 0` (6×6, symmetric
/// positive definite for λ > 0) by Cholesky factorization; `None` when a pivot is not
/// positive (λ ≤ 0 on a singular `J·W^½`, or a non-finite entry). Only the lower triangle of
/// `J·W·Jᵀ` is formed; the factorization and the two triangular solves are written out for the
/// fixed size (fully unrolled): nalgebra's generic product and factorization of the same
/// matrix cost about a sixth of a track's instructions, these about a third of that.
#[inline]
fn damped_normal_solve(
    j: &Jacobian,
    w: &[Real; MAX_DOF],
    lambda: Real,
    e: &Vector6<Real>,
) -> Option<Vector6<Real>> {
    // Constant loop bounds (the triangles by `if`): the compiler unrolls every loop.
    let mut a = [[0.0; 6]; 6];
    for k in 0..MAX_DOF {
        let wk = w[k];
        for r in 0..6 {
            let jr = j[(r, k)] * wk;
            for c in 0..6 {
                if c <= r {
                    a[r][c] += jr * j[(c, k)];
                }
            }
        }
    }
    let mut l = [[0.0; 6]; 6];
    for c in 0..6 {
        let mut d = a[c][c] + lambda;
        for k in 0..6 {
            if k < c {
                d -= l[c][k] * l[c][k];
            }
        }
        if d.is_nan() || d <= 0.0 {
            return None;
        }
        let dc = d.sqrt();
        l[c][c] = dc;
        let inv = 1.0 / dc;
        for r in 0..6 {
            if r > c {
                let mut v = a[r][c];
                for k in 0..6 {
                    if k < c {
                        v -= l[r][k] * l[c][k];
                    }
                }
                l[r][c] = v * inv;
            }
        }
    }
    let mut y = [0.0; 6];
    for r in 0..6 {
        let mut v = e[r];
        for k in 0..6 {
            if k < r {
                v -= l[r][k] * y[k];
            }
        }
        y[r] = v / l[r][r];
    }
    for r in (0..6).rev() {
        let mut v = y[r];
        for k in 0..6 {
            if k > r {
                v -= l[k][r] * y[k];
            }
        }
        y[r] = v / l[r][r];
    }
    Some(Vector6::from(y))
}

/// Rotation vector of `r` (log map), robust near 0 and π.
#[inline]
fn log_rot(r: &Mat3) -> Vec3 {
    let w = 0.5
        * Vec3::new(
            r[(2, 1)] - r[(1, 2)],
            r[(0, 2)] - r[(2, 0)],
            r[(1, 0)] - r[(0, 1)],
        );
    let s = w.norm();
    let c = 0.5 * (r.trace() - 1.0);
    // θ = atan2(s, c) < LOG_SMALL_ANGLE exactly when c > 0 and s < sin(LOG_SMALL_ANGLE): the
    // common case of a converging solve, without the arctangent.
    if c > 0.0 && s < LOG_SMALL_SIN {
        return w;
    }
    let th = s.atan2(c);
    if th < LOG_SMALL_ANGLE {
        w
    } else if th < std::f64::consts::PI - LOG_NEAR_PI {
        w * (th / s)
    } else {
        nalgebra::Rotation3::from_matrix_unchecked(*r).scaled_axis()
    }
}

/// Settings of the IK solver (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct IkParams {
    /// Position tolerance (m).
    pub position_tolerance: Real,
    /// Orientation tolerance (rad).
    pub angle_tolerance: Real,
    /// LM iterations per run (accepted or rejected steps).
    pub max_iterations: usize,
    /// Random restarts per redundancy sample (after the caller's seeds).
    pub restarts: usize,
    /// The joint locked as the redundancy parameter in [`IkSolver::solve_all`] (`None`: all
    /// joints free).
    pub redundancy_joint: Option<usize>,
    /// Number of values of the redundancy joint, evenly spaced over the span reached by the
    /// free solutions (≥ 1 when a joint is locked).
    pub samples: usize,
    /// Explicit values of the redundancy joint (rad); when non-empty they replace `samples`.
    pub lock_values: Vec<Real>,
    /// Free solutions (nearest first) used as seeds for each locked value.
    pub lock_seeds: usize,
    /// Seed of the random restarts.
    pub rng_seed: u64,
    /// Weight the step against joint limits (weighted least norm): joints near a limit move
    /// less. Off by default: it halves the convergence rate from random seeds; useful in
    /// [`IkSolver::track`] to keep a tracked path away from limits.
    pub limit_weighting: bool,
    /// Two solutions closer than this in every joint are the same (rad).
    pub dedup_tolerance: Real,
    /// Levenberg–Marquardt damping λ of the first step (on JJᵀ's scale, m² and rad²). The
    /// default [`LM_LAMBDA_START`] is robust from random seeds; a tracker whose seeds lie
    /// within a small step of the solution converges quadratically (Gauss–Newton) from a much
    /// smaller value, in fewer iterations. λ rises ×8 on every rejected step either way.
    pub initial_damping: Real,
}

impl Default for IkParams {
    /// `1e-10` m / rad, 100 iterations, 50 restarts, `j0` locked at 8 samples.
    ///
    /// ```
    /// let p = helixreach::robot::ik::IkParams::default();
    /// assert_eq!(p.position_tolerance, helixreach::math::tol::IK_POSITION);
    /// ```
    fn default() -> Self {
        IkParams {
            position_tolerance: tol::IK_POSITION,
            angle_tolerance: tol::IK_ANGLE,
            max_iterations: 100,
            restarts: 50,
            redundancy_joint: Some(0),
            samples: 8,
            lock_values: Vec::new(),
            lock_seeds: 4,
            rng_seed: 0,
            limit_weighting: false,
            // The default of the named, documented field: not a tolerance literal.
            dedup_tolerance: 1e-3,
            initial_damping: LM_LAMBDA_START,
        }
    }
}

impl IkParams {
    /// The same settings for a solver used only by [`IkSolver::track`] from nearby seeds (a
    /// waypoint or self-motion step away): `initial_damping` = [`TRACK_DAMPING`].
    ///
    /// ```
    /// use helixreach::robot::ik::{IkParams, TRACK_DAMPING};
    /// assert_eq!(IkParams::default().tracking().initial_damping, TRACK_DAMPING);
    /// ```
    pub fn tracking(self) -> Self {
        IkParams {
            initial_damping: TRACK_DAMPING,
            ..self
        }
    }

    /// The defaults without a redundancy joint: every joint free, a plain pose solve or track
    /// from a seed (how the seed-run witness corrects recorded rows onto our pose).
    pub fn without_redundancy() -> Self {
        IkParams {
            redundancy_joint: None,
            ..IkParams::default()
        }
    }
}

/// One IK solution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IkSolution {
    q: [Real; MAX_DOF],
    dof: usize,
    /// Position error by FK (m).
    pub position_error: Real,
    /// Orientation error by FK (rad; the tool-axis angle when the roll is free).
    pub rotation_error: Real,
    /// LM iterations used.
    pub iterations: usize,
}

impl IkSolution {
    /// The joint values.
    pub fn joints(&self) -> &[Real] {
        &self.q[..self.dof]
    }
}

/// The solver: a model and its settings.
#[derive(Clone, Debug)]
pub struct IkSolver<'a> {
    model: &'a RobotModel,
    params: IkParams,
    lower: [Real; MAX_DOF],
    upper: [Real; MAX_DOF],
}

impl<'a> IkSolver<'a> {
    /// A solver for `model`; checks the parameters.
    pub fn new(model: &'a RobotModel, params: IkParams) -> Result<IkSolver<'a>> {
        crate::error::require_positive("ik.position_tolerance", params.position_tolerance)?;
        crate::error::require_positive("ik.angle_tolerance", params.angle_tolerance)?;
        crate::error::require_positive("ik.initial_damping", params.initial_damping)?;
        // Every count bounded (crate::limits): a typo is an error, not an hour-long solve.
        use crate::limits::{check_size, MAX_IK_ITERATIONS, MAX_IK_RESTARTS, MAX_IK_SAMPLES};
        check_size("ik.samples", params.samples, MAX_IK_SAMPLES)?;
        check_size("ik.restarts", params.restarts, MAX_IK_RESTARTS)?;
        check_size(
            "ik.max_iterations",
            params.max_iterations,
            MAX_IK_ITERATIONS,
        )?;
        check_size("ik.lock_values", params.lock_values.len(), MAX_IK_SAMPLES)?;
        check_size("ik.lock_seeds", params.lock_seeds, MAX_IK_SAMPLES)?;
        if let Some(j) = params.redundancy_joint {
            if j >= model.dof() {
                return Err(Error::invalid(
                    "ik.redundancy_joint",
                    j,
                    format!("the chain has {} joints", model.dof()),
                ));
            }
            if params.samples == 0 {
                return Err(Error::invalid("ik.samples", 0, "must be ≥ 1"));
            }
        }
        Ok(IkSolver {
            model,
            lower: model.lower(),
            upper: model.upper(),
            params,
        })
    }

    /// The settings.
    pub fn params(&self) -> &IkParams {
        &self.params
    }

    /// One LM run from `seed` (the planner's "track" mode): the joint `lock.0`, if given, is held
    /// at `lock.1`. `None` if it does not converge within the iterations.
    pub fn track(
        &self,
        target: &IkTarget,
        seed: &[Real],
        lock: Option<(usize, Real)>,
    ) -> Option<IkSolution> {
        self.track_into(target, seed, lock, None)
    }

    /// [`IkSolver::track`], also writing the geometric Jacobian at the solution into `jac`
    /// (the one the run evaluated there: [`crate::robot::kinematics::Chain::jacobian`] of the
    /// returned joints, bit for bit, for an [`IkTarget::Pose`]; for an [`IkTarget::Axis`] its
    /// angular rows are projected off the tool axis). `jac` is left unspecified on `None`.
    pub fn track_with_jacobian(
        &self,
        target: &IkTarget,
        seed: &[Real],
        lock: Option<(usize, Real)>,
        jac: &mut Jacobian,
    ) -> Option<IkSolution> {
        self.track_into(target, seed, lock, Some(jac))
    }

    fn track_into(
        &self,
        target: &IkTarget,
        seed: &[Real],
        lock: Option<(usize, Real)>,
        jac_out: Option<&mut Jacobian>,
    ) -> Option<IkSolution> {
        let n = self.model.dof();
        if seed.len() != n {
            return None;
        }
        let mut q = [0.0; MAX_DOF];
        for i in 0..n {
            q[i] = seed[i].clamp(self.lower[i], self.upper[i]);
        }
        if let Some((j, v)) = lock {
            if j >= n || !(self.lower[j]..=self.upper[j]).contains(&v) {
                return None;
            }
            q[j] = v;
        }
        self.lm(target, q, lock.map(|l| l.0), jac_out)
    }

    /// The first solution found: from `seed` (if any), then from random restarts, all joints
    /// free.
    pub fn solve(&self, target: &IkTarget, seed: Option<&[Real]>) -> Option<IkSolution> {
        if let Some(s) = seed {
            if let Some(sol) = self.track(target, s, None) {
                return Some(sol);
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.params.rng_seed);
        for _ in 0..self.params.restarts {
            let q = self.random(&mut rng);
            if let Some(sol) = self.lm(target, q, None, None) {
                return Some(sol);
            }
        }
        None
    }

    /// Every distinct solution found (see the module docs), deterministic order: first the
    /// solutions with the redundancy joint locked at each sampled value, then the free ones.
    /// An arm without self-motion at the target (no more joints than
    /// [`IkTarget::dimension`]: a 6-DOF arm at a pose) has isolated solutions, one per IK
    /// branch (and per 2π turn of a joint whose range allows it): only the free runs are made.
    pub fn solve_all(&self, target: &IkTarget, seeds: &[&[Real]]) -> Vec<IkSolution> {
        let tol = self.params.dedup_tolerance;
        let push = |sol: IkSolution, out: &mut Vec<IkSolution>| {
            let dup = out.iter().any(|o| {
                o.joints()
                    .iter()
                    .zip(sol.joints())
                    .all(|(a, b)| (a - b).abs() <= tol)
            });
            if !dup {
                out.push(sol);
            }
        };
        // Phase 1: free runs from the caller's seeds and random restarts.
        let mut free: Vec<IkSolution> = Vec::new();
        for s in seeds {
            if let Some(sol) = self.track(target, s, None) {
                push(sol, &mut free);
            }
        }
        let mut rng = ChaCha8Rng::seed_from_u64(self.params.rng_seed);
        for _ in 0..self.params.restarts {
            let q = self.random(&mut rng);
            if let Some(sol) = self.lm(target, q, None, None) {
                push(sol, &mut free);
            }
        }
        let Some(j) = self.params.redundancy_joint else {
            return free;
        };
        // No self-motion (e.g. a 6-DOF arm at a pose): the solutions are isolated branches,
        // all of them found by the free runs; a locked joint would leave too few joints.
        if self.model.dof() <= target.dimension() {
            return free;
        }
        // Phase 2: lock joint j at values spread over the span the free solutions reached (or
        // the caller's values), seeded from the nearest free solutions.
        let values: Vec<Real> = if !self.params.lock_values.is_empty() {
            self.params.lock_values.clone()
        } else if free.is_empty() {
            Vec::new()
        } else {
            let lo = free.iter().map(|s| s.q[j]).fold(Real::INFINITY, Real::min);
            let hi = free
                .iter()
                .map(|s| s.q[j])
                .fold(Real::NEG_INFINITY, Real::max);
            let n = self.params.samples.max(1);
            (0..n)
                .map(|k| lo + (k as Real + 0.5) * (hi - lo) / n as Real)
                .collect()
        };
        let mut out: Vec<IkSolution> = Vec::new();
        let mut order: Vec<usize> = (0..free.len()).collect();
        for v in values {
            if !(self.lower[j]..=self.upper[j]).contains(&v) {
                continue;
            }
            order.sort_by(|&a, &b| {
                (free[a].q[j] - v)
                    .abs()
                    .total_cmp(&(free[b].q[j] - v).abs())
            });
            for &f in order.iter().take(self.params.lock_seeds) {
                if let Some(sol) = self.track(target, free[f].joints(), Some((j, v))) {
                    push(sol, &mut out);
                }
            }
        }
        for f in free {
            push(f, &mut out);
        }
        out
    }

    fn random(&self, rng: &mut ChaCha8Rng) -> [Real; MAX_DOF] {
        let mut q = [0.0; MAX_DOF];
        for i in 0..self.model.dof() {
            q[i] = rng.random_range(self.lower[i]..=self.upper[i]);
        }
        q
    }

    /// The trial configuration of one LM iteration from `q` (inside the limits) with Jacobian
    /// `jac` and residual `e` (as [`IkTarget::residual`] leaves them) at damping `lambda`: the
    /// damped, limit-weighted least-norm step over the joints that are free (not `locked`) and
    /// not pushed outward through a limit, clamped into the limits.
    fn trial(
        &self,
        q: &[Real; MAX_DOF],
        jac: &Jacobian,
        e: &Vector6<Real>,
        lambda: Real,
        locked: Option<usize>,
    ) -> [Real; MAX_DOF] {
        let n = self.model.dof();
        // Active set: free joints that are not pushed outward through a limit.
        let mut active = [false; MAX_DOF];
        for i in 0..n {
            active[i] = Some(i) != locked;
        }
        // Joint-limit weighting (weighted least norm, Chan & Dubey 1995): a joint moving
        // toward a limit gets weight w = 1 + |∂H/∂q|, H = Σ r²/(4 (u − q)(q − l)); its
        // column is scaled by 1/√w, so the redundant arm moves the other joints instead.
        let mut scale = [1.0; MAX_DOF];
        for i in 0..n * usize::from(self.params.limit_weighting) {
            let (l, u) = (self.lower[i], self.upper[i]);
            let (a, b) = (
                (u - q[i]).max(LIMIT_GAP_FLOOR),
                (q[i] - l).max(LIMIT_GAP_FLOOR),
            );
            let r = u - l;
            let g = r * r * (2.0 * q[i] - u - l) / (4.0 * a * a * b * b);
            scale[i] = 1.0 / (1.0 + g.abs()).sqrt();
        }
        let mut dq = [0.0; MAX_DOF];
        for _pass in 0..=n {
            // Columns scaled by `scale`, inactive ones removed: J·W·Jᵀ with W = diag(scale²),
            // and the step W·Jᵀ·y.
            let mut w = [0.0; MAX_DOF];
            for i in 0..MAX_DOF {
                if active[i] {
                    w[i] = scale[i] * scale[i];
                }
            }
            let Some(y) = damped_normal_solve(jac, &w, lambda, e) else {
                break;
            };
            let mut step = jac.transpose() * y;
            for i in 0..MAX_DOF {
                step[i] *= w[i];
            }
            let mut changed = false;
            for i in 0..n {
                dq[i] = step[i];
                if active[i] {
                    let at_lo = q[i] <= self.lower[i] && step[i] < 0.0;
                    let at_hi = q[i] >= self.upper[i] && step[i] > 0.0;
                    if at_lo || at_hi {
                        active[i] = false;
                        changed = true;
                    }
                }
            }
            if !changed {
                break;
            }
        }
        let mut qn = *q;
        for i in 0..n {
            if active[i] {
                qn[i] = (q[i] + dq[i]).clamp(self.lower[i], self.upper[i]);
            }
        }
        qn
    }

    /// The first trial of a track ([`IkSolver::track`]) from `q` toward `target`, no joint
    /// locked: one damped Gauss–Newton step at the initial damping, limit-weighted and clamped
    /// like every LM iteration. A track from `q` continues from this point, so it converges
    /// within about the residual left here (second order in the step) of it: a predictor of
    /// where the track ends that costs one Jacobian and one 6×6 solve instead of the track's
    /// several. `None` when `q` has not the arm's joint count.
    pub fn predict(&self, target: &IkTarget, q: &[Real]) -> Option<[Real; MAX_DOF]> {
        let n = self.model.dof();
        if q.len() != n {
            return None;
        }
        let mut x = [0.0; MAX_DOF];
        for i in 0..n {
            x[i] = q[i].clamp(self.lower[i], self.upper[i]);
        }
        let mut jac = Jacobian::zeros();
        let tool = self.model.chain().jacobian(&x[..n], &mut jac);
        let e = target.residual(&tool, Some(&mut jac));
        Some(self.trial(&x, &jac, &e, self.params.initial_damping, None))
    }

    /// Box-constrained LM from `q` (inside the limits); on success the Jacobian at the
    /// solution is copied into `jac_out`, if given.
    fn lm(
        &self,
        target: &IkTarget,
        mut q: [Real; MAX_DOF],
        locked: Option<usize>,
        jac_out: Option<&mut Jacobian>,
    ) -> Option<IkSolution> {
        let n = self.model.dof();
        let chain = self.model.chain();
        let (tp, ta) = (self.params.position_tolerance, self.params.angle_tolerance);
        let (tp2, tan_ta) = (tp * tp, ta.min(1.5).tan());
        let (mut jac, mut jac_n) = (Jacobian::zeros(), Jacobian::zeros());
        let mut tool = chain.jacobian(&q[..n], &mut jac);
        let mut e = target.residual(&tool, Some(&mut jac));
        let mut err2 = e.norm_squared();
        let mut lambda: Real = self.params.initial_damping;
        let mut checkpoint = err2;
        for it in 0..self.params.max_iterations {
            // Stall test: a run that has not halved its error in the last `STALL_WINDOW`
            // iterations is in a local minimum (typically against a limit): restart instead.
            if it > 0 && it % STALL_WINDOW == 0 {
                if err2 > 0.25 * checkpoint {
                    return None;
                }
                checkpoint = err2;
            }
            if target.within(&tool, tp2, tan_ta) {
                if let Some(out) = jac_out {
                    *out = jac;
                }
                let (pe, ae) = target.errors(&tool);
                return Some(IkSolution {
                    q,
                    dof: n,
                    position_error: pe,
                    rotation_error: ae,
                    iterations: it,
                });
            }
            let qn = self.trial(&q, &jac, &e, lambda, locked);
            // The trial's Jacobian with its pose (one FK pass): most trials are accepted.
            let tool_n = chain.jacobian(&qn[..n], &mut jac_n);
            let en = target.residual(&tool_n, None);
            let err2n = en.norm_squared();
            if err2n < err2 {
                q = qn;
                tool = tool_n;
                jac = jac_n;
                e = target.residual(&tool, Some(&mut jac));
                err2 = e.norm_squared();
                lambda = (lambda * 0.2).max(LM_LAMBDA_MIN);
            } else {
                lambda *= 8.0;
                if lambda > 1e6 {
                    return None;
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix6;

    /// The convergence test without the arctangent agrees with the errors' test: poses
    /// around a target at distances and angles spread across the tolerances (pose and axis
    /// targets).
    #[test]
    fn within_agrees_with_errors() {
        let mut rng = ChaCha8Rng::seed_from_u64(8);
        let (mut inside, mut outside) = (0, 0);
        for k in 0..20_000 {
            let axis = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
            let t = Frame::new(
                nalgebra::Rotation3::from_scaled_axis(axis * rng.random_range(0.0..3.0))
                    .into_inner(),
                Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0)),
            );
            let (tp, ta) = (
                (10.0 as Real).powf(rng.random_range(-10.0..-2.0)),
                (10.0 as Real).powf(rng.random_range(-10.0..-1.0)),
            );
            let dir = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
            let rax = Vec3::from_fn(|_, _| rng.random_range(-1.0..1.0)).normalize();
            let tool = Frame::new(
                nalgebra::Rotation3::from_scaled_axis(rax * ta * rng.random_range(0.0..2.0))
                    .into_inner()
                    * t.rot,
                t.pos + dir * tp * rng.random_range(0.0..2.0),
            );
            let target = if k % 2 == 0 {
                IkTarget::Pose(t)
            } else {
                IkTarget::Pose(t).free_roll()
            };
            let (pe, ae) = target.errors(&tool);
            let want = pe <= tp && ae <= ta;
            // Away from the boundary by more than round-off: the same answer.
            if (pe - tp).abs() > 1e-9 * tp && (ae - ta).abs() > 1e-9 * ta {
                assert_eq!(target.within(&tool, tp * tp, ta.tan()), want, "{k}");
                if want {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
        }
        assert!(inside > 2_000 && outside > 2_000, "{inside} {outside}");
    }

    /// The damped normal-equation solve agrees with nalgebra's Cholesky solve of the same
    /// matrix (random 6×7 Jacobians, rank-deficient ones, λ from 1e-12 to 1), its residual is at
    /// round-off, and a non-positive pivot (λ = 0 on a rank-deficient `J`) is `None`.
    #[test]
    fn damped_normal_solve_agrees_with_nalgebra() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        for k in 0..2_000 {
            let mut j = Jacobian::from_fn(|_, _| rng.random_range(-1.0..1.0));
            if k % 4 == 0 {
                // Rank 5: the last row a combination of the others.
                let row = j.row(0) * 0.3 - j.row(2) * 1.7;
                j.set_row(5, &row);
            }
            let e = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let lambda = (10.0 as Real).powf(rng.random_range(-12.0..0.0));
            let a: Matrix6<Real> = j * j.transpose() + Matrix6::identity() * lambda;
            let want = a.cholesky().expect("SPD").solve(&e);
            let got = damped_normal_solve(&j, &[1.0; MAX_DOF], lambda, &e).expect("SPD");
            let scale = want.norm().max(1.0);
            let cond = 1.0 / lambda.min(1.0);
            assert!(
                (got - want).norm() <= 1e-12 * scale * cond,
                "{k}: {got} vs {want}"
            );
            assert!((a * got - e).norm() <= 1e-10 * scale * a.norm(), "{k}");
            if k % 4 == 0 {
                assert!(
                    damped_normal_solve(&j, &[1.0; MAX_DOF], 0.0, &e).is_none() || {
                        // Round-off may leave a tiny positive pivot: then the solve is huge.
                        let y = damped_normal_solve(&j, &[1.0; MAX_DOF], 0.0, &e).unwrap();
                        y.norm() > 1e6
                    }
                );
            }
        }
        let zero = Jacobian::zeros();
        assert!(damped_normal_solve(&zero, &[1.0; MAX_DOF], 0.0, &Vector6::zeros()).is_none());
    }

    /// With weights, the solve is that of the columns scaled by their square roots (zero
    /// weights remove a column), against nalgebra's Cholesky solve of `J·W·Jᵀ + λ·I`.
    #[test]
    fn weighted_normal_solve_agrees_with_scaled_columns() {
        let mut rng = ChaCha8Rng::seed_from_u64(22);
        for k in 0..2_000 {
            let j = Jacobian::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let mut w: [Real; MAX_DOF] = [0.0; MAX_DOF];
            for (i, wi) in w.iter_mut().enumerate() {
                // Every weight in (0, 1], one or two joints removed on some draws.
                *wi = if (k + i) % 5 == 0 && k % 3 == 0 {
                    0.0
                } else {
                    rng.random_range(0.01..=1.0)
                };
            }
            let mut js = j;
            for i in 0..MAX_DOF {
                js.column_mut(i).scale_mut(w[i].sqrt());
            }
            let e = Vector6::from_fn(|_, _| rng.random_range(-1.0..1.0));
            let lambda = (10.0 as Real).powf(rng.random_range(-8.0..0.0));
            let a: Matrix6<Real> = js * js.transpose() + Matrix6::identity() * lambda;
            let want = a.cholesky().expect("SPD").solve(&e);
            let got = damped_normal_solve(&j, &w, lambda, &e).expect("SPD");
            let scale = want.norm().max(1.0);
            assert!(
                (got - want).norm() <= 1e-11 * scale / lambda.min(1.0),
                "{k}: {got} vs {want}"
            );
        }
    }

    /// Every count of [`IkParams`] is checked against [`crate::limits`] by [`IkSolver::new`]:
    /// one past the limit is an error naming the field, the value and the limit; the limit
    /// itself is accepted.
    #[test]
    fn ik_size_parameters_are_bounded_by_the_limits() {
        use crate::limits::{MAX_IK_ITERATIONS, MAX_IK_RESTARTS, MAX_IK_SAMPLES};
        let model = RobotModel::load("sawyer", None).unwrap();
        type Set = fn(&mut IkParams, usize);
        let cases: [(&str, usize, Set); 5] = [
            ("ik.samples", MAX_IK_SAMPLES, |p, n| p.samples = n),
            ("ik.restarts", MAX_IK_RESTARTS, |p, n| p.restarts = n),
            ("ik.max_iterations", MAX_IK_ITERATIONS, |p, n| {
                p.max_iterations = n
            }),
            ("ik.lock_values", MAX_IK_SAMPLES, |p, n| {
                p.lock_values = vec![0.0; n]
            }),
            ("ik.lock_seeds", MAX_IK_SAMPLES, |p, n| p.lock_seeds = n),
        ];
        for (field, max, set) in cases {
            let mut p = IkParams::default();
            set(&mut p, max);
            assert!(IkSolver::new(&model, p.clone()).is_ok(), "{field} = {max}");
            set(&mut p, max + 1);
            let e = IkSolver::new(&model, p).unwrap_err().to_string();
            assert!(
                e.contains(field)
                    && e.contains(&(max + 1).to_string())
                    && e.contains(&max.to_string()),
                "{e}"
            );
        }
    }

    /// `initial_damping` must be positive (the error names the field). Tracks of small pose
    /// steps (5 mm, 2°, like the search's slices) from a converged configuration reach the
    /// target within the tolerances with either damping, the undamped start in fewer LM
    /// iterations, and, for joint steps within the search's bound (0.05 rad), land within the
    /// step's square of each other (the same point of the self-motion curve to first order).
    #[test]
    fn undamped_tracks_converge_in_fewer_iterations() {
        let model = RobotModel::load("sawyer", None).unwrap();
        for bad in [0.0, -1.0, Real::NAN] {
            let p = IkParams {
                initial_damping: bad,
                ..IkParams::default()
            };
            let Err(e) = IkSolver::new(&model, p) else {
                panic!("initial_damping {bad} accepted");
            };
            let e = e.to_string();
            assert!(e.contains("ik.initial_damping"), "{e}");
        }
        let damped = IkSolver::new(&model, IkParams::default()).unwrap();
        let undamped = IkSolver::new(&model, IkParams::default().tracking()).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (mut it_d, mut it_u, mut n) = (0usize, 0usize, 0usize);
        for _ in 0..300 {
            let q0 = damped.random(&mut rng);
            let tip = model.chain().tool_pose(&q0[..7]);
            let axis = Vec3::new(rng.random(), rng.random(), rng.random()).normalize();
            let rot = nalgebra::Rotation3::from_axis_angle(
                &nalgebra::Unit::new_normalize(axis),
                2.0_f64.to_radians(),
            );
            let moved = Frame {
                rot: rot.into_inner() * tip.rot,
                pos: tip.pos + 0.005 * axis,
            };
            let target = IkTarget::Pose(moved);
            let (Some(a), Some(b)) = (
                damped.track(&target, &q0[..7], None),
                undamped.track(&target, &q0[..7], None),
            ) else {
                continue;
            };
            for sol in [&a, &b] {
                assert!(sol.position_error <= tol::IK_POSITION);
                assert!(sol.rotation_error <= tol::IK_ANGLE);
            }
            let gap = (0..7)
                .map(|j| (a.joints()[j] - b.joints()[j]).abs())
                .fold(0.0, Real::max);
            let step = (0..7)
                .map(|j| (a.joints()[j] - q0[j]).abs())
                .fold(0.0, Real::max);
            // Within the search's joint-step bound (a larger step is no edge of it).
            if step <= 0.05 {
                assert!(gap <= step * step + 1e-9, "gap {gap} for a step {step}");
            }
            it_d += a.iterations;
            it_u += b.iterations;
            n += 1;
        }
        assert!(n >= 250, "only {n} of 300 tracks converged");
        assert!(it_u < it_d, "undamped {it_u} vs damped {it_d} iterations");
    }
}
