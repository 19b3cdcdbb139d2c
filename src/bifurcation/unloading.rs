//! Hysteresis from DER statics: where the post-snap equilibrium rejoins the helix on unloading.
//!
//! Past s* on a subcritical ray the helix is unstable and no equilibrium is nearby: the rod
//! snaps to a far equilibrium. [`static_return`] finds it and follows it back down in s:
//!
//! 1. at `s_a = s*·(1 + OVERSHOOT)` the helix equilibrium (or the sampled helix, if Newton
//!    has no helical equilibrium there) is pushed along the critical mode φ so that its largest
//!    node moves `KICK·L`, and relaxed to a local minimum by damped implicit-Euler dynamics
//!    with the ends held ([`crate::rod::dynamics::Stepper`]), polished by Newton once the
//!    motion has died out and accepted when stable;
//! 2. natural continuation down in s: the far state is moved by the change of the sampled
//!    helix from s to `s − Δs` (the predictor), the end clamp is set to the helix end pose at
//!    `s − Δs` ([`crate::rod::clamp::impose`], twist continuous) and Newton re-converges (if
//!    Newton fails, the end is moved from s to `s − Δs` by damped dynamics instead, which
//!    follows the far branch while it exists and falls back to the helix where it ends); a step is
//!    accepted when the equilibrium is stable (LDLᵀ inertia 0) and still away from the helix
//!    (largest node distance to the sampled helix > `AWAY·L`); accepted steps grow by 1.5,
//!    rejected ones halve;
//! 3. the far branch ends at a fold (Newton fails), a loss of stability, or a merge with the
//!    helix; `s_return` is the last accepted s once Δs < `tol_rel·s*` (the true end lies in
//!    `[s_return − Δs, s_return]`).
//!
//! **Self-contact.** The DER energy has no contact term. Every state of the relaxation and of
//! the damped end moves, and every accepted equilibrium, is checked by a
//! [`ContactMonitor`]: when two edges come closer than the rod's
//! diameter or pass through each other, the real rod would touch itself there and the DER
//! branch says nothing about it. The result then carries [`StaticReturn::self_contact`] and no
//! `s_return` (NaN). A continuation step whose Newton jump crosses edges (not a motion: a
//! jump to another branch) is rejected like a failed step. A passage the per-step check
//! samples too coarsely is caught by its consequence: the linking number
//! ([`super::contact::linking_number`]) of the relaxed state differs from the helix's, or jumps
//! between neighbouring equilibria of the branch, by more than [`LINKING_JUMP`]
//! ([`StaticReturn::linking_change`], `s_return` NaN). A branch followed down to
//! `s ≤ 10⁻³·s*` (the floor) is reported with `s_return` at the floor: it cannot exist for a
//! real rod (near s = 0 the ends are a straight rod's, and a far state there needs a changed
//! linking number) — the caller must not report it as a return point.
//!
//! Statics gives the quasi-static limit (speed → 0) of the dynamic unloading. A *damped*
//! dynamic run follows this far branch (its elastic energy agrees with the branch's within
//! 0.3 % at n = 16, tests/bifurcation.rs) and falls to the helix after its end, delayed by the
//! slow passage through the fold: the dynamic return lies below the static one by a gap
//! ∝ v^(2/3) that vanishes as v → 0. An *undamped* run rings after the snap: the vibration
//! throws it off the far branch before the fold (above the static return), and its helix error
//! stays above the detection threshold until the ringing has decayed, far below it.

use super::contact::{linking_number, ContactMonitor, SelfContact};
use super::reduction::CriticalMode;
use crate::boundary::der::DerRay;
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::helix::Helix;
use crate::math::{Real, Vec3};
use crate::rod::clamp::{self, ClampPlacement, End};
use crate::rod::dynamics::{Stepper, StepperParams};
use crate::rod::statics::{self, NewtonParams};
use crate::rod::{RodState, Workspace};

/// The far equilibrium is sought this fraction past s*.
pub const OVERSHOOT: Real = 0.02;
/// Kick along the critical mode (largest node displacement, units of L).
pub const KICK: Real = 0.05;
/// A state whose nodes are all within this distance (units of L) of the helix counts as the helix.
pub const AWAY: Real = 0.01;
/// A change of the linking number larger than this (turns) between the helix and the relaxed
/// post-snap state, or between neighbouring equilibria of the far branch, is a passage of the
/// rod through itself or over an end (a passage changes it by ±2; a continuation step by
/// much less than 1).
pub const LINKING_JUMP: Real = 1.0;

/// Twist inertia per unit mass during the relaxation (only the path to rest depends on it).
const RELAX_TWIST_INERTIA: Real = 0.01;
/// Damping ζ of the relaxation (nondimensional time units).
const RELAX_DAMPING: Real = 10.0;
/// Time step of the relaxation (nondimensional): small enough that `M/Δt²` dominates the
/// negative curvature of the unstable helix, so every implicit step is well posed.
const RELAX_DT: Real = 0.01;
/// Largest number of relaxation steps.
const RELAX_STEPS: usize = 20_000;
/// Kinetic energy below which a Newton polish is tried.
const RELAX_KINETIC: Real = 1e-6;

/// The result of [`static_return`].
#[derive(Debug, Clone, PartialEq)]
pub struct StaticReturn {
    /// Last s at which the far equilibrium was found stable and away from the helix.
    pub s_return: Real,
    /// Bracket width below `s_return` within which the far branch ends.
    pub uncertainty: Real,
    /// Largest node distance from the helix at `s_a` (the snap's size, units of L).
    pub snap_size: Real,
    /// Newton solves spent.
    pub solves: usize,
    /// The followed far branch, one point per accepted step, s decreasing (the relaxed
    /// post-snap state first).
    pub branch: Vec<BranchPoint>,
    /// Where the rod touched or passed through itself (then `s_return` is NaN): the s of the
    /// motion or equilibrium, and the edges.
    pub self_contact: Option<(Real, SelfContact)>,
    /// The far branch was followed down to the floor `10⁻³·s*` (`s_return` is the floor).
    pub at_floor: bool,
    /// Where the linking number of the rod jumped (then `s_return` is NaN): the s and the
    /// jump (±2 for one passage through itself or over an end; [`linking_number`]).
    pub linking_change: Option<(Real, Real)>,
}

/// One accepted equilibrium of the far branch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchPoint {
    /// Distance along the ray.
    pub s: Real,
    /// Elastic energy (units of k_b/L).
    pub energy: Real,
    /// Largest node distance from the sampled helix (units of L).
    pub distance: Real,
}

/// Largest node distance between `st` and the sampled helix at `s` (`ray`'s discretization).
fn distance_to_helix(ray: &mut DerRay, st: &RodState, s: Real) -> Result<Real> {
    let h = ray.initial_state(s)?;
    let n = st.n_edges();
    Ok((0..=n)
        .map(|i| (st.node(i) - h.node(i)).norm())
        .fold(0.0, Real::max))
}

/// Move the end clamp of `st` to the helix end pose at `s`.
fn move_end(
    st: &mut RodState,
    dir: &Direction,
    s: Real,
    c: Real,
    placement: ClampPlacement,
) -> Result<bool> {
    let [k, t, w] = dir.at(s);
    let hx = Helix::new(k, t, w)?;
    let frame = hx.material_frame(1.0, c);
    let n = st.n_edges();
    let h = placement.edge_length(n, 1.0);
    Ok(clamp::impose(
        st,
        placement,
        End::End,
        &hx.position(1.0),
        &frame,
        h,
    ))
}

/// Follow the post-snap equilibrium of `ray` back down from past `s_star` (see the module
/// docs). `mode` is the critical mode at s*, `c` the twist ratio, `stretch` the stretching
/// stiffness of the boundary's rod, `tol_rel` the relative resolution of `s_return`,
/// `diameter` the rod's diameter (units of L) for the self-contact check.
#[allow(clippy::too_many_arguments)]
pub fn static_return(
    ray: &mut DerRay,
    dir: &Direction,
    s_star: Real,
    mode: &CriticalMode,
    c: Real,
    placement: ClampPlacement,
    stretch: Real,
    tol_rel: Real,
    diameter: Real,
) -> Result<StaticReturn> {
    let s_a = s_star * (1.0 + OVERSHOOT);
    let start = match ray.evaluate(s_a) {
        Ok(_) => ray.state().cloned(),
        Err(Error::NotConverged { .. }) => None,
        Err(e) => return Err(e),
    };
    let mut st = match start {
        Some(s) => s,
        None => ray.initial_state(s_a)?,
    };
    // The ray's rod at the boundary's stretching stiffness (a failed cold start of
    // `DerRay::evaluate` leaves it at a continuation value).
    let mut rod = ray.rod().clone();
    rod.material.stretch = stretch;
    let mut monitor = ContactMonitor::new(rod.n_edges(), diameter);
    let contact = |s: Real, c: SelfContact, branch: Vec<BranchPoint>, solves| StaticReturn {
        s_return: Real::NAN,
        uncertainty: Real::NAN,
        snap_size: Real::NAN,
        solves,
        branch,
        self_contact: Some((s, c)),
        at_floor: false,
        linking_change: None,
    };
    let relinked = |s: Real, d: Real, branch: Vec<BranchPoint>, solves| StaticReturn {
        s_return: Real::NAN,
        uncertainty: Real::NAN,
        snap_size: Real::NAN,
        solves,
        branch,
        self_contact: None,
        at_floor: false,
        linking_change: Some((s, d)),
    };
    if let Some(c) = monitor.observe(&st) {
        return Ok(contact(s_a, c, Vec::new(), 0));
    }
    let helix_energy = crate::rod::energy::energy(&rod, &st);
    let helix_lk = linking_number(&st);
    let x = KICK / mode.max_node.max(crate::math::tol::TINY);
    for (q, p) in st.q.iter_mut().zip(&mode.phi) {
        *q += x * p;
    }
    if !st.update_reference() {
        return Err(Error::invalid("kick", x, "degenerate kicked rod"));
    }
    // Relax: damped implicit-Euler dynamics with the ends held, then a Newton polish once the
    // motion has died out (a Newton solve from the kicked state could land on any equilibrium,
    // the unstable helix included; the damped motion descends the energy).
    let mut stepper = Stepper::new(
        rod.clone(),
        placement,
        st,
        RELAX_TWIST_INERTIA,
        Vec3::zeros(),
        RELAX_DAMPING,
        StepperParams::default(),
    )?;
    let free = rod.free_range_clamped();
    let mut ws = Workspace::new(&rod);
    let newton = NewtonParams::default();
    let mut relaxed = None;
    let mut polish = stepper.state().clone();
    for k in 1..=RELAX_STEPS {
        stepper.step(RELAX_DT, None)?;
        if let Some(c) = monitor.observe(stepper.state()) {
            return Ok(contact(s_a, c, Vec::new(), 0));
        }
        if k % 50 == 0 && stepper.kinetic_energy() < RELAX_KINETIC {
            polish.copy_from(stepper.state());
            if let Ok(eq) = statics::solve(&rod, &mut polish, free.clone(), &mut ws, &newton) {
                if eq.negative == 0 {
                    relaxed = Some(polish.clone());
                    break;
                }
            }
        }
    }
    let Some(mut st) = relaxed else {
        return Err(Error::NotConverged {
            what: format!("relaxation to the post-snap equilibrium at s = {s_a}"),
            iterations: RELAX_STEPS,
            residual: stepper.kinetic_energy(),
        });
    };
    // A passage through itself or over an end that the per-step check sampled too coarsely.
    let mut lk = linking_number(&st);
    if (lk - helix_lk).abs() > LINKING_JUMP {
        return Ok(relinked(s_a, lk - helix_lk, Vec::new(), 0));
    }
    let snap_size = distance_to_helix(ray, &st, s_a)?;
    if snap_size <= AWAY {
        // A *stable* state on the centerline of the *unstable* helix differs from it in twist by
        // whole turns: the DER rod changed its linking number (through itself or an end) in a
        // way the contact monitor did not see.
        let e = crate::rod::energy::energy(&rod, &st);
        return Err(Error::NotConverged {
            what: format!(
                "post-snap equilibrium at s = {s_a:.4}: relaxed to a stable state only {snap_size:.1e} from the \
                 unstable helix's centerline with elastic energy {e:.4} against the helix's {helix_energy:.4} \
                 (its twist differs by whole turns: the contact-free DER rod changed its linking number)"
            ),
            iterations: 0,
            residual: snap_size,
        });
    }
    let mut branch = vec![BranchPoint {
        s: s_a,
        energy: crate::rod::energy::energy(&rod, &st),
        distance: snap_size,
    }];
    let mut s = s_a;
    let mut ds = 0.02 * s_star;
    let mut trial = st.clone();
    let mut solves = 0;
    let s_floor = S_FLOOR_REL * s_star;
    while ds >= tol_rel * s_star {
        let s_new = s - ds;
        if s_new <= s_floor {
            // The far branch survives down to the straight rod: report the floor.
            return Ok(StaticReturn {
                s_return: s_floor,
                uncertainty: s_floor,
                snap_size,
                solves,
                branch,
                self_contact: None,
                at_floor: true,
                linking_change: None,
            });
        }
        // Predictor: the far state moved by the change of the sampled helix from s to s_new
        // (smooth along the rod, consistent with the moved end clamp), then the clamp.
        trial.copy_from(&st);
        let (h_old, h_new) = (ray.initial_state(s)?, ray.initial_state(s_new)?);
        for k in free.clone() {
            trial.q[k] += h_new.q[k] - h_old.q[k];
        }
        let ok = trial.update_reference()
            && move_end(&mut trial, dir, s_new, c, placement)?
            && match statics::solve(&rod, &mut trial, free.clone(), &mut ws, &newton) {
                Ok(eq) => {
                    solves += 1;
                    // A Newton jump that crosses edges left the branch (rejected); an
                    // equilibrium in contact ends the branch's meaning.
                    monitor.reset();
                    monitor.observe(&st);
                    match monitor.observe(&trial) {
                        Some(c) if !c.crossed => return Ok(contact(s_new, c, branch, solves)),
                        Some(_) => false,
                        None => eq.negative == 0 && distance_to_helix(ray, &trial, s_new)? > AWAY,
                    }
                }
                Err(Error::NotConverged { .. }) => {
                    solves += 1;
                    // Newton's basin is small for the stiff, fine rod: move the end from s to
                    // s_new quasi-statically by damped dynamics instead, settle and polish.
                    let moved = (s, s_new);
                    match settle_moved(
                        &mut stepper,
                        &st,
                        dir,
                        moved,
                        c,
                        &rod,
                        &mut ws,
                        &mut monitor,
                    )? {
                        Settled::At(x) => {
                            trial.copy_from(&x);
                            distance_to_helix(ray, &trial, s_new)? > AWAY
                        }
                        Settled::Contact(c) => return Ok(contact(s_new, c, branch, solves)),
                        Settled::No => false,
                    }
                }
                Err(e) => return Err(e),
            };
        if ok {
            let lk_new = linking_number(&trial);
            if (lk_new - lk).abs() > LINKING_JUMP {
                return Ok(relinked(s_new, lk_new - lk, branch, solves));
            }
            lk = lk_new;
            st.copy_from(&trial);
            s = s_new;
            branch.push(BranchPoint {
                s,
                energy: crate::rod::energy::energy(&rod, &st),
                distance: distance_to_helix(ray, &st, s)?,
            });
            ds = (1.5 * ds).min(0.05 * s_star);
        } else {
            ds *= 0.5;
        }
    }
    Ok(StaticReturn {
        s_return: s,
        uncertainty: 2.0 * ds,
        snap_size,
        solves,
        branch,
        self_contact: None,
        at_floor: false,
        linking_change: None,
    })
}

/// The outcome of [`settle_moved`].
enum Settled {
    /// A stable equilibrium.
    At(RodState),
    /// The motion touched or crossed the rod itself.
    Contact(SelfContact),
    /// No stable equilibrium reached (a failed step, or still moving).
    No,
}

/// The unloading continuation stops at `s = S_FLOOR_REL·s*` (the straight rod, practically):
/// a far branch that survives down to it returns there, flagged `at_floor`.
const S_FLOOR_REL: Real = 1e-3;

/// Steps over which the end is moved in [`settle_moved`].
const MOVE_STEPS: usize = 20;

/// From the equilibrium `st` at `s0`, move the end clamp to the helix end pose at `s1` over
/// [`MOVE_STEPS`] damped implicit-Euler steps, let the motion die out and polish by Newton;
/// every state of the motion is checked for self-contact by `monitor`.
#[allow(clippy::too_many_arguments)]
fn settle_moved(
    stepper: &mut Stepper,
    st: &RodState,
    dir: &Direction,
    (s0, s1): (Real, Real),
    c: Real,
    rod: &crate::rod::Rod,
    ws: &mut Workspace,
    monitor: &mut ContactMonitor,
) -> Result<Settled> {
    stepper.set_state(st)?;
    monitor.reset();
    monitor.observe(st);
    let pose = |s: Real| -> Result<crate::rod::dynamics::EndClamp> {
        let [k, t, w] = dir.at(s);
        let hx = Helix::new(k, t, w)?;
        Ok(crate::rod::dynamics::EndClamp {
            position: hx.position(1.0),
            frame: hx.material_frame(1.0, c),
        })
    };
    // Validate the path once (Helix::new fails only on non-finite input).
    pose(s0)?;
    pose(s1)?;
    for j in 0..MOVE_STEPS {
        let a = j as Real / MOVE_STEPS as Real;
        let end = |lam: Real| {
            let s = s0 + (s1 - s0) * (a + lam / MOVE_STEPS as Real);
            pose(s).expect("validated end poses")
        };
        if stepper.step(RELAX_DT, Some(&end)).is_err() {
            return Ok(Settled::No);
        }
        if let Some(c) = monitor.observe(stepper.state()) {
            return Ok(Settled::Contact(c));
        }
    }
    let free = rod.free_range_clamped();
    let newton = NewtonParams::default();
    let mut polish = stepper.state().clone();
    for k in 1..=RELAX_STEPS / 4 {
        if stepper.step(RELAX_DT, None).is_err() {
            return Ok(Settled::No);
        }
        if let Some(c) = monitor.observe(stepper.state()) {
            return Ok(Settled::Contact(c));
        }
        if k % 50 == 0 && stepper.kinetic_energy() < RELAX_KINETIC {
            polish.copy_from(stepper.state());
            if let Ok(eq) = statics::solve(rod, &mut polish, free.clone(), ws, &newton) {
                if eq.negative == 0 {
                    return Ok(Settled::At(polish));
                }
            }
        }
    }
    Ok(Settled::No)
}
