//! Implicit Euler time stepping of a clamped discrete elastic rod (the seed paper's EOM, §II.B).
//!
//! # Equations (nondimensional: lengths in L, energies in `k_b/L`, time in `T₀`)
//! With the lumped (diagonal) mass matrix `M`, the elastic energy `E` of [`crate::rod::energy`],
//! a constant external force `F` (gravity) and mass-proportional viscous damping `ζ·M·q̇`, one
//! step from `(q_k, q̇_k)` solves for `q_{k+1}` on the free DOFs
//!
//! `r(q) = M/Δt²·(q − q_k − Δt·q̇_k) + ζ·M/Δt·(q − q_k) + ∇E(q) − F = 0`,
//!
//! then sets `q̇_{k+1} = (q_{k+1} − q_k)/Δt` (every DOF, clamped ones included). Newton's method
//! solves `r = 0` with the Jacobian `J = (1/Δt² + ζ/Δt)·M + ∇²E`, banded with half-bandwidth 10,
//! factored by [`crate::rod::BandedLdlt`] on the contiguous free range
//! [`Rod::free_range_clamped`]. The Newton start is the explicit predictor `q_k + Δt·q̇_k`;
//! a step that increases `‖r‖∞` is halved (backtracking); convergence is `‖Δq‖∞ ≤ step_tol`
//! or a residual at the round-off floor. A step whose Newton iteration fails is retried as two
//! half steps (recursively, [`StepperParams::max_subdivisions`] levels).
//!
//! # Lumped masses
//! Node `i` carries `m_i = ρA·l_i` and edge `j` the twist inertia `I_j = ½ρAh²·ē_j` (the polar
//! moment of inertia of its section, `ρ·πh⁴/2`, times its length); nondimensionally
//! `m_i = l_i` and `I_j = ½(h/L)²·ē_j`. Here `l_i` is the Voronoi length of node `i` (the end
//! nodes get half an edge). Only free DOFs enter the equations.
//!
//! # Boundary conditions
//! The first clamped edge (nodes 0, 1, θ₀) stays where the initial state put it; the last one
//! is re-imposed at the new time by [`clamp::impose`] from an [`EndClamp`] supplied by the
//! caller as a function of the fraction of the step (so sub-steps get the pose at their time).
//! The twist angle of the clamped edge is chosen continuously (within π of its last value).
//!
//! # Reference frames
//! After every change of positions the reference frames are time-parallel transported
//! ([`RodState::update_reference`]), so the energy's gradient and Hessian are exact at every
//! Newton iterate (see [`crate::rod::state`]); θ is measured relative to these frames and its
//! velocity is the difference quotient of θ, as in DER.
//!
//! # Energy
//! For an elastic energy that is convex near the trajectory (a perturbed stable equilibrium),
//! implicit Euler dissipates: `E(q_{k+1}) + K_{k+1} ≤ E(q_k) + K_k − ½‖q̇_{k+1} − q̇_k‖²_M`
//! (K the kinetic energy), the numerical damping that tests/dynamics.rs checks.
//!
//! # Allocation
//! [`Stepper::new`] sizes every buffer; [`Stepper::step`] allocates nothing.

use crate::error::{require_finite, require_positive, Error, Result};
use crate::math::{Mat3, Real, Vec3};
use crate::rod::clamp::{self, ClampPlacement, End};
use crate::rod::energy;
use crate::rod::{Rod, RodState, Workspace};

/// A Newton step is halved when it multiplies the residual `‖r‖∞` by more than this. Not 1:
/// with a stiff stretching term the first step from a straight rod raises the (badly scaled)
/// residual by orders of magnitude through the axial strain it induces, and the next step
/// removes it; halving there stalls.
pub const BACKTRACK_GROWTH: Real = 1e4;

/// Proximal time step of [`Stepper::relax`] (nondimensional time).
pub const RELAX_STEP: Real = 0.1;
/// Maximum proximal steps of [`Stepper::relax`].
pub const RELAX_MAX_STEPS: usize = 2000;
/// Default Newton step tolerance of an implicit step ([`StepperParams::step_tol`]): the max-norm
/// of the update, nondimensional (positions in units of L, angles in radians).
pub const DEFAULT_STEP_TOL: Real = 1e-10;

/// The pose imposed on the last clamped edge: the rod's end point and material frame
/// `[m¹ m² t]` (columns), nondimensional (L = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndClamp {
    /// End point (the clamp point at arc length L).
    pub position: Vec3,
    /// Material frame; its third column is the end tangent.
    pub frame: Mat3,
}

/// Controls of [`Stepper`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepperParams {
    /// Maximum Newton iterations per step.
    pub max_iters: usize,
    /// Convergence on the Newton step `‖Δq‖∞` (units of L and rad).
    pub step_tol: Real,
    /// Times a failed step is split in two before giving up.
    pub max_subdivisions: usize,
}

impl Default for StepperParams {
    /// `max_iters = 25`, `step_tol = 1e-10`, `max_subdivisions = 6`.
    fn default() -> Self {
        StepperParams {
            max_iters: 25,
            step_tol: DEFAULT_STEP_TOL,
            max_subdivisions: 6,
        }
    }
}

/// Work done by one call of [`Stepper::step`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct StepReport {
    /// Newton iterations (assemblies) summed over sub-steps.
    pub newton_iterations: usize,
    /// Sub-steps taken (1 unless a step had to be split).
    pub substeps: usize,
}

/// An implicit Euler integrator for one clamped rod (see the module docs).
#[derive(Debug, Clone)]
pub struct Stepper {
    rod: Rod,
    placement: ClampPlacement,
    state: RodState,
    /// Velocity `q̇` (length 4n+3).
    vel: Vec<Real>,
    mass: Vec<Real>,
    force: Vec<Real>,
    damping: Real,
    params: StepperParams,
    ws: Workspace,
    /// State at the start of the step (restored when a step fails).
    start: RodState,
    start_vel: Vec<Real>,
    /// State at the start of the current sub-step (`q_k`).
    sub_start: RodState,
    sub_vel: Vec<Real>,
    /// Newton base iterate (backtracking).
    base: RodState,
    /// Inertial target `q_k + Δt·q̇_k` on every DOF.
    target: Vec<Real>,
    time: Real,
}

impl Stepper {
    /// A stepper for `rod` (nondimensional stiffnesses, L = 1) starting at rest in `state`,
    /// whose two end edges are the clamped ones (placement `placement`).
    ///
    /// - `twist_inertia_ratio`: `½(h/L)²`, the twist inertia per unit mass and length;
    /// - `gravity`: the nondimensional weight per unit length `ρA·g·L³/k_b` as a vector (zero
    ///   for none);
    /// - `damping`: ζ ≥ 0 in inverse time units (`ζ·M·q̇` opposes the motion).
    ///
    /// Errors on n < 4, non-finite or negative inputs.
    pub fn new(
        rod: Rod,
        placement: ClampPlacement,
        state: RodState,
        twist_inertia_ratio: Real,
        gravity: Vec3,
        damping: Real,
        params: StepperParams,
    ) -> Result<Self> {
        let n = rod.n_edges();
        if n < 4 {
            return Err(Error::invalid(
                "n_edges",
                n,
                "the dynamics needs at least 4 edges",
            ));
        }
        if state.n_edges() != n {
            return Err(Error::invalid(
                "state",
                state.n_edges(),
                format!("state has a different number of edges than the rod ({n})"),
            ));
        }
        if let Some(k) = state.q.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("q[{k}]"),
                state.q[k],
                "must be finite",
            ));
        }
        require_positive("twist_inertia_ratio", twist_inertia_ratio)?;
        for (f, v) in [
            ("gravity_x", gravity.x),
            ("gravity_y", gravity.y),
            ("gravity_z", gravity.z),
        ] {
            require_finite(f, v)?;
        }
        require_finite("damping", damping)?;
        if damping < 0.0 {
            return Err(Error::invalid("damping", damping, "must be >= 0"));
        }
        require_positive("step_tol", params.step_tol)?;
        let nd = rod.n_dofs();
        let mut mass = vec![0.0; nd];
        let mut force = vec![0.0; nd];
        for i in 0..=n {
            let l = 0.5
                * (if i > 0 { rod.rest_length(i - 1) } else { 0.0 }
                    + if i < n { rod.rest_length(i) } else { 0.0 });
            for a in 0..3 {
                mass[4 * i + a] = l;
                force[4 * i + a] = l * gravity[a];
            }
        }
        for j in 0..n {
            mass[4 * j + 3] = twist_inertia_ratio * rod.rest_length(j);
        }
        let ws = Workspace::new(&rod);
        Ok(Stepper {
            placement,
            vel: vec![0.0; nd],
            mass,
            force,
            damping,
            params,
            ws,
            start: state.clone(),
            start_vel: vec![0.0; nd],
            sub_start: state.clone(),
            sub_vel: vec![0.0; nd],
            base: state.clone(),
            target: vec![0.0; nd],
            state,
            rod,
            time: 0.0,
        })
    }

    /// The rod model.
    pub fn rod(&self) -> &Rod {
        &self.rod
    }

    /// The current configuration.
    pub fn state(&self) -> &RodState {
        &self.state
    }

    /// The current velocity `q̇` (every DOF).
    pub fn velocity(&self) -> &[Real] {
        &self.vel
    }

    /// Mutable access to the velocity (to perturb a state in tests and studies).
    pub fn velocity_mut(&mut self) -> &mut [Real] {
        &mut self.vel
    }

    /// The lumped mass of every DOF.
    pub fn masses(&self) -> &[Real] {
        &self.mass
    }

    /// Elapsed (nondimensional) time.
    pub fn time(&self) -> Real {
        self.time
    }

    /// Elastic energy `E(q)`.
    pub fn elastic_energy(&self) -> Real {
        energy::energy(&self.rod, &self.state)
    }

    /// Kinetic energy `½ q̇ᵀ M q̇` of the free DOFs.
    pub fn kinetic_energy(&self) -> Real {
        let f = self.rod.free_range_clamped();
        0.5 * f
            .map(|k| self.mass[k] * self.vel[k] * self.vel[k])
            .sum::<Real>()
    }

    /// Potential of the external force on the free DOFs, `−Fᵀq` (gravity).
    pub fn external_potential(&self) -> Real {
        let f = self.rod.free_range_clamped();
        -f.map(|k| self.force[k] * self.state.q[k]).sum::<Real>()
    }

    /// Total mechanical energy: elastic + kinetic + external potential.
    pub fn total_energy(&self) -> Real {
        self.elastic_energy() + self.kinetic_energy() + self.external_potential()
    }

    /// Replace the configuration (velocity set to zero); the clamped DOFs are taken as given.
    pub fn set_state(&mut self, state: &RodState) -> Result<()> {
        if state.n_edges() != self.rod.n_edges() {
            return Err(Error::invalid(
                "state",
                state.n_edges(),
                "different number of edges",
            ));
        }
        self.state.copy_from(state);
        self.vel.iter_mut().for_each(|v| *v = 0.0);
        Ok(())
    }

    /// Static equilibrium under the external force with the clamps as they are. Velocity is
    /// reset to zero. Returns the number of negative eigenvalues of the free Hessian there
    /// (0 ⇔ stable).
    ///
    /// A sequence of proximal steps (implicit Euler from rest with the time step
    /// [`RELAX_STEP`]: each minimizes `E − Fᵀq + ½‖q − q_k‖²_M/τ²`, so it converges from any
    /// start towards a local minimum) until the change is below `step_tol`, then a plain Newton
    /// polish (kept only if it converges).
    pub fn relax(&mut self) -> Result<usize> {
        let a = 1.0 / (RELAX_STEP * RELAX_STEP);
        for _ in 0..RELAX_MAX_STEPS {
            self.sub_start.copy_from(&self.state);
            self.target.copy_from_slice(&self.state.q);
            self.newton(a, 0.0)?;
            let change = self
                .state
                .q
                .iter()
                .zip(&self.sub_start.q)
                .fold(0.0, |m: Real, (x, y)| m.max((x - y).abs()));
            if change <= self.params.step_tol {
                break;
            }
        }
        self.sub_start.copy_from(&self.state);
        self.target.copy_from_slice(&self.state.q);
        if self.newton(0.0, 0.0).is_err() {
            self.state.copy_from(&self.sub_start);
        }
        self.vel.iter_mut().for_each(|v| *v = 0.0);
        energy::hessian(&self.rod, &self.state, &mut self.ws.hess);
        let free = self.rod.free_range_clamped();
        match self.ws.ldlt.factor(&self.ws.hess, free) {
            Ok(()) => Ok(self.ws.ldlt.inertia().1),
            Err(_) => Ok(1),
        }
    }

    /// Advance by `dt` (> 0, nondimensional). `end(λ)` gives the pose of the last clamped edge
    /// at the fraction λ ∈ (0, 1] of the step (λ = 1: the end of the step); `None` holds it.
    pub fn step(&mut self, dt: Real, end: Option<&dyn Fn(Real) -> EndClamp>) -> Result<StepReport> {
        require_positive("dt", dt)?;
        self.start.copy_from(&self.state);
        self.start_vel.copy_from_slice(&self.vel);
        let mut report = StepReport::default();
        match self.step_recursive(dt, 0.0, 1.0, end, 0, &mut report) {
            Ok(()) => {
                self.time += dt;
                Ok(report)
            }
            Err(e) => {
                self.state.copy_from(&self.start);
                self.vel.copy_from_slice(&self.start_vel);
                Err(e)
            }
        }
    }

    fn step_recursive(
        &mut self,
        dt: Real,
        lam0: Real,
        lam1: Real,
        end: Option<&dyn Fn(Real) -> EndClamp>,
        depth: usize,
        report: &mut StepReport,
    ) -> Result<()> {
        let h = dt * (lam1 - lam0);
        match self.single_step(h, end.map(|f| f(lam1)), report) {
            Ok(()) => {
                report.substeps += 1;
                Ok(())
            }
            Err(_) if depth < self.params.max_subdivisions => {
                let mid = 0.5 * (lam0 + lam1);
                self.step_recursive(dt, lam0, mid, end, depth + 1, report)?;
                self.step_recursive(dt, mid, lam1, end, depth + 1, report)
            }
            Err(e) => Err(e),
        }
    }

    /// One implicit Euler step of length `h`; on failure the state and velocity are restored.
    fn single_step(
        &mut self,
        h: Real,
        end: Option<EndClamp>,
        report: &mut StepReport,
    ) -> Result<()> {
        let free = self.rod.free_range_clamped();
        let n = self.rod.n_edges();
        self.sub_start.copy_from(&self.state);
        self.sub_vel.copy_from_slice(&self.vel);
        // Inertial target q_k + h·q̇_k, and the predictor on the free DOFs.
        for k in 0..self.target.len() {
            self.target[k] = self.state.q[k] + h * self.vel[k];
        }
        for k in free {
            self.state.q[k] = self.target[k];
        }
        let ok = match end {
            Some(ec) => clamp::impose(
                &mut self.state,
                self.placement,
                End::End,
                &ec.position,
                &ec.frame,
                self.rod.rest_length(n - 1),
            ),
            None => self.state.update_reference(),
        };
        let result = if ok {
            self.newton(1.0 / (h * h), self.damping / h)
        } else {
            Err(degenerate())
        };
        match result {
            Ok(iters) => {
                report.newton_iterations += iters;
                for k in 0..self.vel.len() {
                    self.vel[k] = (self.state.q[k] - self.sub_start.q[k]) / h;
                }
                Ok(())
            }
            Err(e) => {
                report.newton_iterations += self.params.max_iters;
                self.state.copy_from(&self.sub_start);
                self.vel.copy_from_slice(&self.sub_vel);
                Err(e)
            }
        }
    }

    /// Newton on `r(q) = a·M(q − target) + b·M(q − q_k) + ∇E − F` over the free DOFs, where
    /// `q_k` is `self.sub_start` (used only when `b > 0`). Returns the iterations.
    fn newton(&mut self, a: Real, b: Real) -> Result<usize> {
        let free = self.rod.free_range_clamped();
        let m = free.len();
        let lo = free.start;
        let p = self.params;
        let mut base_res = Real::INFINITY;
        let mut alpha = 1.0;
        let mut have_base = false;
        let c = a + b;
        for it in 0..p.max_iters {
            energy::energy_gradient_hessian(
                &self.rod,
                &self.state,
                &mut self.ws.grad,
                &mut self.ws.hess,
            );
            let mut res: Real = 0.0;
            let mut scale: Real = 0.0;
            for k in free.clone() {
                let mut r = self.ws.grad[k] - self.force[k];
                if a != 0.0 {
                    r += self.mass[k] * a * (self.state.q[k] - self.target[k]);
                }
                if b != 0.0 {
                    r += self.mass[k] * b * (self.state.q[k] - self.sub_start.q[k]);
                }
                self.ws.grad[k] = r;
                res = res.max(r.abs());
                let d = self.ws.hess.get(k, k) + c * self.mass[k];
                scale = scale.max(d.abs());
            }
            if !res.is_finite() {
                return Err(Error::NotConverged {
                    what: "implicit Euler Newton (non-finite residual)".into(),
                    iterations: it,
                    residual: res,
                });
            }
            if have_base && res >= BACKTRACK_GROWTH * base_res && alpha > 1.0 / 64.0 {
                // The last step made things worse: halve it from the base.
                alpha *= 0.5;
                self.state.copy_from(&self.base);
                for k in 0..m {
                    self.state.q[lo + k] += alpha * self.ws.step[k];
                }
                if !self.state.update_reference() {
                    return Err(degenerate());
                }
                continue;
            }
            base_res = res;
            alpha = 1.0;
            // Round-off floor of the residual: ε·(largest diagonal)·(1 + |q|).
            let qmax = self.state.q.iter().fold(1.0, |m: Real, v| m.max(v.abs()));
            if res <= 64.0 * Real::EPSILON * scale * qmax {
                return Ok(it);
            }
            if c != 0.0 {
                for k in free.clone() {
                    self.ws.hess.add(k, k, c * self.mass[k]);
                }
            }
            self.ws
                .ldlt
                .factor(&self.ws.hess, free.clone())
                .map_err(|e| Error::NotConverged {
                    what: format!("implicit Euler Newton ({e})"),
                    iterations: it,
                    residual: res,
                })?;
            for k in 0..m {
                self.ws.step[k] = -self.ws.grad[lo + k];
            }
            self.ws.ldlt.solve_in_place(&mut self.ws.step[..m]);
            let step = self.ws.step[..m]
                .iter()
                .fold(0.0, |s: Real, v| s.max(v.abs()));
            self.base.copy_from(&self.state);
            have_base = true;
            for k in 0..m {
                self.state.q[lo + k] += self.ws.step[k];
            }
            if !self.state.update_reference() {
                return Err(degenerate());
            }
            if step <= p.step_tol {
                return Ok(it + 1);
            }
        }
        Err(Error::NotConverged {
            what: "implicit Euler Newton".into(),
            iterations: p.max_iters,
            residual: base_res,
        })
    }
}

fn degenerate() -> Error {
    Error::NotConverged {
        what: "implicit Euler step (an edge collapsed)".into(),
        iterations: 0,
        residual: Real::NAN,
    }
}
