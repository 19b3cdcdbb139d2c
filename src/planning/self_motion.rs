//! Self-motion of a 7-DOF arm at a held tool pose: walking the 1-D manifold
//! `M(T) = { q : FK(q) = T }` and resampling a walk so that the executed (joint-linear) motion
//! keeps the rod end where it is.
//!
//! # The manifold and its tangent
//! For a 7-joint arm with a full 6-D pose imposed, `M(T)` is a union of closed curves (away from
//! singularities). Its tangent at `q` spans the null space of the 6×7 geometric Jacobian `J(q)`;
//! with `J₋ᵢ` the 6×6 matrix without column i, the cofactor vector
//!
//! `nᵢ = (−1)ⁱ · det(J₋ᵢ)`
//!
//! satisfies `J·n = 0` (Cramer: each row of `J` dotted with `n` is the determinant of a 7×7 matrix
//! with a repeated row), and is non-zero exactly where `J` has full rank ([`null_direction`]).
//!
//! # Walking (exploration)
//! Predictor–corrector continuation: from `q` the predictor `q + h·n̂` (`n̂` scaled to max-norm
//! 1, oriented like the previous step) is projected back onto `M(T)` by one minimum-norm
//! Levenberg–Marquardt run ([`IkSolver::track`], to `1e-10` m / rad). A step is accepted when the
//! corrected point moved forward (`Δq·n̂ > 0`), by at most the joint-step bound (max-norm) and at
//! least a quarter of `h`; otherwise `h` is halved, down to `min_step` (then the walk ends: a
//! joint limit, a singularity or a fold). The accepted step must also pass the caller's validity
//! test (limits, collisions along the joint-linear segment); the first invalid step ends the walk
//! in that direction — the walk covers the **connected valid component** of the start point at
//! resolution `max_step` (the rig's `planner.self_motion_step`). A walk that returns next to its
//! start has gone round a closed component and stops.
//!
//! # Executing (resampling)
//! A robot controller interpolates linearly in joint space between samples; the chord between two
//! manifold points leaves the manifold by O(h²). [`refine`] bisects each walk step (new points
//! projected onto `M(T)`) until the tool pose at t = ¼, ½, ¾ of every chord is within
//! [`HOLD_TOLERANCE`] (1e-6 m and 1e-6 rad) of `T`; samples themselves are within `1e-10`.

use crate::math::{rotation_angle, Real};
use crate::robot::{Chain, Frame, IkSolver, IkTarget, Jacobian, MAX_DOF};
use nalgebra::Matrix6;

/// Largest rod-end pose error (m and rad) anywhere on an executed reconfiguration.
pub const HOLD_TOLERANCE: Real = 1e-6;

/// Bisection depth of [`refine`] per walk step (2¹² pieces at most).
const MAX_REFINE_DEPTH: u32 = 12;

/// [`null_direction`] calls `J` singular when its largest 6×6 minor is at most this (the minors
/// are in m³: three position rows in m, three angular rows dimensionless).
const SINGULAR_MINOR: Real = 1e-12;

/// A joint vector.
pub type Q = [Real; MAX_DOF];

/// The tangent of the self-motion manifold at a configuration with Jacobian `jac`, scaled to
/// max-norm 1, or `None` for an arm that is not 7-DOF or a (numerically) singular `J`.
///
/// ```
/// use helixreach::robot::{RobotModel, Jacobian};
/// use helixreach::planning::self_motion::null_direction;
/// let m = RobotModel::load("sawyer", None).unwrap();
/// let q = [0.3, -0.8, 0.2, 1.4, -0.3, 0.9, 0.1];
/// let mut j = Jacobian::zeros();
/// m.chain().jacobian(&q, &mut j);
/// let n = null_direction(&j, 7).unwrap();
/// assert!((j * nalgebra::SVector::<f64, 7>::from(n)).norm() < 1e-12);
/// ```
pub fn null_direction(jac: &Jacobian, dof: usize) -> Option<Q> {
    if dof != 7 || MAX_DOF != 7 {
        return None;
    }
    let mut n = [0.0; MAX_DOF];
    let mut m = Matrix6::<Real>::zeros();
    for (i, ni) in n.iter_mut().enumerate() {
        let mut c = 0;
        for k in 0..7 {
            if k != i {
                m.set_column(c, &jac.column(k));
                c += 1;
            }
        }
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        *ni = sign * m.determinant();
    }
    let scale = n.iter().fold(0.0, |a: Real, x| a.max(x.abs()));
    if !(scale.is_finite() && scale > SINGULAR_MINOR) {
        return None;
    }
    for x in n.iter_mut() {
        *x /= scale;
    }
    Some(n)
}

/// Settings of [`walk`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSettings {
    /// Largest predictor step (max-norm, rad): the sampling resolution of the walk.
    pub max_step: Real,
    /// Smallest predictor step before the walk gives up (rad).
    pub min_step: Real,
    /// Largest joint step between consecutive samples (max-norm, rad).
    pub joint_step_bound: Real,
    /// Most samples of one walk.
    pub max_samples: usize,
}

/// The held pose: the arm's chain, an IK solver (track mode) and the full-pose target of the
/// tip link.
#[derive(Debug)]
pub struct Held<'a> {
    /// The arm's kinematic chain.
    pub chain: &'a Chain,
    /// The solver used to project onto the manifold.
    pub solver: &'a IkSolver<'a>,
    /// The tip-link pose held (root frame).
    pub tip: Frame,
    /// Number of joints.
    pub dof: usize,
}

impl Held<'_> {
    fn project(&self, seed: &Q) -> Option<Q> {
        let sol = self
            .solver
            .track(&IkTarget::Pose(self.tip), &seed[..self.dof], None)?;
        let mut q = [0.0; MAX_DOF];
        q[..self.dof].copy_from_slice(sol.joints());
        Some(q)
    }

    /// Position and rotation error of the tip at `q` against the held pose.
    pub fn pose_error(&self, q: &[Real]) -> (Real, Real) {
        let f = self.chain.tool_pose(&q[..self.dof]);
        (
            (f.pos - self.tip.pos).norm(),
            rotation_angle(&(self.tip.rot * f.rot.transpose())),
        )
    }
}

fn max_abs_diff(a: &Q, b: &Q, dof: usize) -> Real {
    (0..dof).map(|j| (a[j] - b[j]).abs()).fold(0.0, Real::max)
}

/// Walk the self-motion manifold of `held` from `q0` in direction `sign` (±1 along the cofactor
/// tangent), see the module docs. `valid(a, b)` accepts the step a → b (configuration b and the
/// joint-linear segment); `visit(b)` is called on every accepted sample and stops the walk by
/// returning `true`. Returns the accepted samples (without `q0`) and whether `visit` stopped it.
pub fn walk<V, S>(
    held: &Held<'_>,
    q0: &Q,
    sign: Real,
    s: &WalkSettings,
    mut valid: V,
    mut visit: S,
) -> (Vec<Q>, bool)
where
    V: FnMut(&Q, &Q) -> bool,
    S: FnMut(&Q) -> bool,
{
    let dof = held.dof;
    let mut out: Vec<Q> = Vec::new();
    let mut jac = Jacobian::zeros();
    let mut cur = *q0;
    let mut prev_dir: Option<Q> = None;
    let mut h = s.max_step;
    while out.len() < s.max_samples {
        held.chain.jacobian(&cur[..dof], &mut jac);
        let Some(mut n) = null_direction(&jac, dof) else {
            break;
        };
        let flip = match &prev_dir {
            None => sign < 0.0,
            Some(p) => (0..dof).map(|j| p[j] * n[j]).sum::<Real>() < 0.0,
        };
        if flip {
            for x in n.iter_mut() {
                *x = -*x;
            }
        }
        let mut accepted = None;
        while h >= s.min_step {
            let mut pred = cur;
            for j in 0..dof {
                pred[j] += h * n[j];
            }
            if let Some(q) = held.project(&pred) {
                let step = max_abs_diff(&q, &cur, dof);
                let along: Real = (0..dof).map(|j| (q[j] - cur[j]) * n[j]).sum();
                if along > 0.0 && step <= s.joint_step_bound && step >= 0.25 * h {
                    accepted = Some(q);
                    break;
                }
            }
            h *= 0.5;
        }
        let Some(q) = accepted else {
            break;
        };
        if !valid(&cur, &q) {
            break;
        }
        out.push(q);
        if visit(&q) {
            return (out, true);
        }
        // Round a closed component: back next to the start.
        if out.len() > 4 && max_abs_diff(&q, q0, dof) < s.max_step {
            break;
        }
        prev_dir = Some(n);
        cur = q;
        h = (2.0 * h).min(s.max_step);
    }
    (out, false)
}

/// Resample the joint path `path` (consecutive points on the held manifold) so that the tool pose
/// on every joint-linear chord stays within [`HOLD_TOLERANCE`] of the held pose (checked at
/// t = ¼, ½, ¾; see the module docs). Returns the new samples after `path[0]` (the last is
/// `path[last]`), or `None` when a chord cannot be brought within the tolerance.
pub fn refine(held: &Held<'_>, path: &[Q]) -> Option<Vec<Q>> {
    let dof = held.dof;
    let chord_ok = |a: &Q, b: &Q| {
        [0.25, 0.5, 0.75].iter().all(|&t| {
            let mut q = *a;
            for j in 0..dof {
                q[j] = a[j] + t * (b[j] - a[j]);
            }
            let (dp, dr) = held.pose_error(&q);
            dp <= HOLD_TOLERANCE && dr <= HOLD_TOLERANCE
        })
    };
    let mut out = Vec::new();
    for w in path.windows(2) {
        // Depth-first bisection with an explicit stack (right halves pushed first).
        let mut stack: Vec<(Q, Q, u32)> = vec![(w[0], w[1], 0)];
        while let Some((a, b, depth)) = stack.pop() {
            if chord_ok(&a, &b) {
                out.push(b);
                continue;
            }
            if depth >= MAX_REFINE_DEPTH {
                return None;
            }
            let mut mid = a;
            for j in 0..dof {
                mid[j] = 0.5 * (a[j] + b[j]);
            }
            let m = held.project(&mid)?;
            // The projection must land between a and b (not on another branch).
            let span = max_abs_diff(&a, &b, dof);
            if max_abs_diff(&m, &a, dof) > span || max_abs_diff(&m, &b, dof) > span {
                return None;
            }
            stack.push((m, b, depth + 1));
            stack.push((a, m, depth + 1));
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::{IkParams, RobotModel};

    /// Walk the Sawyer's self-motion at a held pose: every sample holds the pose to 1e-9, steps
    /// stay under the bound, the refined chords hold it to `HOLD_TOLERANCE` (checked here at
    /// 16 interior points, finer than `refine` checks), and a walk unhindered by validity goes
    /// round a closed curve.
    #[test]
    fn walk_stays_on_the_manifold_and_refines_within_tolerance() {
        let m = RobotModel::load("sawyer", None).unwrap();
        let q0: Q = [0.3, -0.8, 0.2, 1.4, -0.3, 0.9, 0.1];
        let tip = m.chain().tool_pose(&q0);
        let solver = IkSolver::new(&m, IkParams::default()).unwrap();
        let held = Held {
            chain: m.chain(),
            solver: &solver,
            tip,
            dof: 7,
        };
        let s = WalkSettings {
            max_step: 0.02,
            min_step: 1e-4,
            joint_step_bound: 0.05,
            max_samples: 400,
        };
        let (lo, hi) = (m.lower(), m.upper());
        let inside = |q: &Q| (0..7).all(|j| q[j] >= lo[j] && q[j] <= hi[j]);
        let (pts, stopped) = walk(&held, &q0, 1.0, &s, |_, b| inside(b), |_| false);
        assert!(!stopped);
        assert!(pts.len() > 20, "walk of {} samples", pts.len());
        let mut prev = q0;
        for q in &pts {
            let (dp, dr) = held.pose_error(q);
            assert!(dp < 1e-9 && dr < 1e-9, "{dp:e} {dr:e}");
            assert!(max_abs_diff(q, &prev, 7) <= 0.05 + 1e-15);
            prev = *q;
        }
        // The walk moved j0 (the self-motion of this arm is not a fixed point).
        let span = pts
            .iter()
            .map(|q| (q[0] - q0[0]).abs())
            .fold(0.0, Real::max);
        assert!(span > 0.1, "j0 span {span}");
        let mut path = vec![q0];
        path.extend(pts.iter().take(20));
        let fine = refine(&held, &path).unwrap();
        assert!(fine.len() > 20);
        let mut a = q0;
        for b in &fine {
            for i in 1..16 {
                let t = i as Real / 16.0;
                let q: Vec<Real> = (0..7).map(|j| a[j] + t * (b[j] - a[j])).collect();
                let (dp, dr) = held.pose_error(&q);
                assert!(
                    dp <= HOLD_TOLERANCE && dr <= HOLD_TOLERANCE,
                    "{dp:e} {dr:e}"
                );
            }
            a = *b;
        }
        assert_eq!(fine.last(), path.last());
    }
}
