//! Stability boundary (continuum), the sweep driver and the `boundary` / `merge`
//! commands.
//!
//! The continuum boundary is checked against
//! - analytic limits: the κ axis (2π, the arc closes into a circle), the straight twisted rod
//!   (Greenhill: ω* = 2x₁, tan x₁ = x₁, derived below), the κ → 0⁺ limit on the τ axis (Euler
//!   column 2π) and the documented κ = 0 plane;
//! - an independent direct RK4 integration, in the material frame, of the nonlinear equilibrium
//!   ODE together with its variational equations (themselves checked by finite differences of the
//!   nonlinear ODE), on the *unscaled* helix where needed;
//! - invariants: c-independence, mirror symmetry, star-convexity, step refinement.

use helixreach::boundary::continuum::{critical_s, critical_s_with, is_stable, ContinuumParams};
use helixreach::directions::{fibonacci, Direction};
use helixreach::records::columns::{Column, Kind};
use helixreach::sweep::driver::{self, Shard, SweepOptions};
use nalgebra::{Matrix3, Matrix6, SMatrix, Vector3};
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering};

type M36 = SMatrix<f64, 3, 6>;

fn hat(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// First root of tan x = x on (π, 3π/2), by Newton on f(x) = sin x − x cos x (f' = x sin x).
fn greenhill_x1() -> f64 {
    let mut x: f64 = 4.5;
    for _ in 0..50 {
        x -= (x.sin() - x * x.cos()) / (x * x.sin());
    }
    x
}

fn random_dirs(n: usize, seed: u64, kmin: f64) -> Vec<Direction> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut out = vec![];
    while out.len() < n {
        let v: [f64; 3] = [
            rng.random_range(0.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ];
        let d = Direction::new(v[0], v[1], v[2]).unwrap();
        if d.kappa >= kmin {
            out.push(d);
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Independent reference: the Kirchhoff rod ODE in the *material* frame (no rotating frame, no
// constant-coefficient assumption, no scaling), integrated with classical RK4.
// ---------------------------------------------------------------------------------------------

/// Rod state: nonlinear (R, r, m, n) and the variations (α, β, δm, δn), each 3×6 (one column per
/// component of the base wrench).
#[derive(Clone, Copy)]
struct State {
    rot: Matrix3<f64>,
    r: Vector3<f64>,
    m: Vector3<f64>,
    n: Vector3<f64>,
    al: M36,
    be: M36,
    dm: M36,
    dn: M36,
}

impl State {
    fn axpy(&self, h: f64, d: &State) -> State {
        State {
            rot: self.rot + d.rot * h,
            r: self.r + d.r * h,
            m: self.m + d.m * h,
            n: self.n + d.n * h,
            al: self.al + d.al * h,
            be: self.be + d.be * h,
            dm: self.dm + d.dm * h,
            dn: self.dn + d.dn * h,
        }
    }
    fn j(&self) -> Matrix6<f64> {
        let mut j = Matrix6::zeros();
        j.fixed_view_mut::<3, 6>(0, 0).copy_from(&self.al);
        j.fixed_view_mut::<3, 6>(3, 0).copy_from(&self.be);
        j
    }
}

/// R' = R[u]×, r' = R e3, m' = −u×m − e3×n, n' = −u×n, u = K⁻¹m, and the linearization with
/// body-frame pose perturbations R(I+[α]×), r + Rβ.
fn rhs(s: &State, c: f64) -> State {
    let kinv = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.0 / c));
    let e3 = Vector3::z();
    let u = kinv * s.m;
    let uh = hat(&u);
    let e3h = hat(&e3);
    let du = kinv * s.dm;
    State {
        rot: s.rot * uh,
        r: s.rot * e3,
        m: -u.cross(&s.m) - e3.cross(&s.n),
        n: -u.cross(&s.n),
        al: -uh * s.al + du,
        be: -e3h * s.al - uh * s.be,
        dm: hat(&s.m) * du - uh * s.dm - e3h * s.dn,
        dn: hat(&s.n) * du - uh * s.dn,
    }
}

fn rk4(s: &State, h: f64, c: f64) -> State {
    let k1 = rhs(s, c);
    let k2 = rhs(&s.axpy(0.5 * h, &k1), c);
    let k3 = rhs(&s.axpy(0.5 * h, &k2), c);
    let k4 = rhs(&s.axpy(h, &k3), c);
    let mut out = *s;
    for (k, w) in [(k1, 1.0), (k2, 2.0), (k3, 2.0), (k4, 1.0)] {
        out = out.axpy(h * w / 6.0, &k);
    }
    out
}

/// The helix (κ, τ, ω) at t = 0: material frame = Frenet frame, m = κB + ωT, n = (ω−τ)(κB + τT).
fn helix_start(k: f64, t: f64, w: f64) -> State {
    let mut dm = M36::zeros();
    let mut dn = M36::zeros();
    for i in 0..3 {
        dm[(i, i)] = 1.0;
        dn[(i, 3 + i)] = 1.0;
    }
    State {
        rot: Matrix3::identity(),
        r: Vector3::zeros(),
        m: Vector3::new(0.0, k, w),
        n: Vector3::new(0.0, k, t) * (w - t),
        al: M36::zeros(),
        be: M36::zeros(),
        dm,
        dn,
    }
}

/// First zero of det J(t) on (t_quiet, t_max] of the helix (κ, τ, ω), by RK4 with step h and
/// bisection inside the bracketing step (each trial point one RK4 step from the bracket start).
/// Signs before `t_quiet` are not compared: near t = 0, det J ~ t^p with a large p and its sign is
/// rounding noise (no conjugate point can be there: the short rod is far from buckling).
fn rk_first_conjugate(
    k: f64,
    t: f64,
    w: f64,
    c: f64,
    h: f64,
    t_quiet: f64,
    t_max: f64,
) -> Option<f64> {
    let mut s = helix_start(k, t, w);
    let mut prev = f64::NAN;
    let mut time = 0.0;
    while time < t_max {
        let next = rk4(&s, h, c);
        let d = next.j().determinant();
        if time > t_quiet && d.signum() != prev.signum() {
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let dm = rk4(&s, mid, c).j().determinant();
                if dm.signum() == prev.signum() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return Some(time + 0.5 * (lo + hi));
        }
        prev = d;
        s = next;
        time += h;
    }
    None
}

#[test]
fn variational_equations_match_finite_differences_of_the_nonlinear_ode() {
    // J(t) from the variational equations vs central differences of the end pose with respect to
    // the base wrench, both integrated with RK4 in the material frame.
    let (k, t, w, c) = (0.8, -0.5, 0.6, 1.0 / 1.33);
    let (h, steps) = (1e-3, 3000);
    let base = helix_start(k, t, w);
    let mut s = base;
    for _ in 0..steps {
        s = rk4(&s, h, c);
    }
    let eps = 1e-6;
    for col in 0..6 {
        let mut ends = vec![];
        for sign in [1.0, -1.0] {
            let mut p = base;
            if col < 3 {
                p.m[col] += sign * eps;
            } else {
                p.n[col - 3] += sign * eps;
            }
            for _ in 0..steps {
                p = rk4(&p, h, c);
            }
            ends.push(p);
        }
        let dr = s.rot.transpose() * (ends[0].rot - ends[1].rot) / (2.0 * eps);
        let alpha = Vector3::new(dr[(2, 1)], dr[(0, 2)], dr[(1, 0)]);
        let beta = s.rot.transpose() * (ends[0].r - ends[1].r) / (2.0 * eps);
        for i in 0..3 {
            assert!((alpha[i] - s.al[(i, col)]).abs() < 1e-7, "α{i} col {col}");
            assert!((beta[i] - s.be[(i, col)]).abs() < 1e-7, "β{i} col {col}");
        }
    }
    // The nonlinear solution from that base wrench is the helix: its end position matches the
    // closed form r(1) = (κ(1−cos λ)/λ², κτ(λ−sin λ)/λ³, 1 − κ²(λ−sin λ)/λ³), λ = √(κ²+τ²),
    // integrated to t = 3: rescale the helix by 3 (κ, τ → 3κ, 3τ on a unit length) ×3.
    let (ks, ts) = (3.0 * k, 3.0 * t);
    let l = (ks * ks + ts * ts).sqrt();
    let want = Vector3::new(
        ks * (1.0 - l.cos()) / (l * l),
        ks * ts * (l - l.sin()) / l.powi(3),
        1.0 - ks * ks * (l - l.sin()) / l.powi(3),
    ) * 3.0;
    assert!((s.r - want).norm() < 1e-9, "{} vs {}", s.r, want);
}

#[test]
fn matches_direct_rk_integration_on_random_directions() {
    let dirs = random_dirs(30, 7, 0.15);
    let mut checked = 0;
    for (i, d) in dirs.iter().enumerate() {
        let nu = [-0.25, 0.33, 0.5][i % 3];
        let p = ContinuumParams {
            nu,
            ..ContinuumParams::default()
        };
        let s = critical_s_with(d, &p).unwrap().s_star;
        assert!(s.is_finite(), "{d:?}");
        if s > 40.0 {
            continue;
        }
        let rk = rk_first_conjugate(
            d.kappa,
            d.tau,
            d.omega,
            1.0 / (1.0 + nu),
            0.01,
            1.0,
            s + 1.0,
        )
        .unwrap_or_else(|| panic!("RK finds no conjugate point for {d:?} (s* = {s})"));
        assert!(((rk - s) / s).abs() < 1e-7, "{d:?}: continuum {s}, RK {rk}");
        checked += 1;
    }
    assert!(checked >= 24, "only {checked} directions checked");
}

#[test]
fn kappa_axis_is_two_pi() {
    let r = critical_s(&Direction::new(1.0, 0.0, 0.0).unwrap(), 1e-12).unwrap();
    assert!((r.s_star - 2.0 * PI).abs() < 1e-10 * 2.0 * PI, "{r:?}");
    assert!(r.est_error <= 1e-11 * r.s_star);
}

/// Greenhill's clamped twisted rod. For a straight rod along e3 with twisting moment M (bending
/// stiffness 1, no axial force) and a small transverse deflection w = x + iy, the transverse
/// moment balance m_⊥' + (r' × n)_⊥ = 0 with m_⊥ = (−y'', x'') + M(x', y') reads, in complex form,
/// w''' − iM w'' + (n₁ + i n₂) = 0, so w''' ∝ e^{iMt} and w = a + bt + ct² + d·e^{iMt}. Clamping
/// both ends (w = w' = 0 at t = 0 and 1) has a non-trivial solution iff
/// (2 + iM) = e^{iM}(2 − iM), i.e. M = 2·arg(2 + iM) + 2πk: with x = M/2, tan x = x. The first
/// root x₁ ≈ 4.4934 gives M* = 2x₁ ≈ 8.9868 (Greenhill 1883; e.g. Timoshenko & Gere, Theory of
/// Elastic Stability, §2.21, where the clamped shaft has ML/EI = 8.99).
#[test]
fn omega_axis_is_greenhill() {
    let x1 = greenhill_x1();
    assert!((x1.tan() - x1).abs() < 1e-9 && x1 > PI && x1 < 1.5 * PI);
    let want = 2.0 * x1;
    assert!((want - 8.9868).abs() < 1e-4);
    // Exactly on the axis (κ = 0: the documented straight-rod case) and approaching it through
    // helices, where the scan must resolve the near-double root (the buckling mode of the straight
    // rod has two polarizations, so det J touches zero there).
    for sign in [1.0, -1.0] {
        let on = critical_s(&Direction::new(0.0, 0.0, sign).unwrap(), 1e-12).unwrap();
        assert!((on.s_star - want).abs() < 1e-12, "{on:?}");
        for (k, tol) in [(1e-2, 2e-3), (1e-3, 2e-5), (1e-5, 1e-8)] {
            let d = Direction::new(k, 0.0, sign).unwrap();
            let s = critical_s(&d, 1e-12).unwrap().s_star;
            assert!((s - want).abs() < tol * want, "κ̂ = {k}: {s} vs {want}");
        }
    }
    assert!(is_stable(0.0, 0.0, want * (1.0 - 1e-6)).unwrap());
    assert!(!is_stable(0.0, 0.0, want * (1.0 + 1e-6)).unwrap());
}

/// On the τ axis: κ → 0⁺ keeps the helix's axial compression τ², an Euler column clamped at both
/// ends, first (symmetric) mode at τ² = 4π²: s* → 2π. Exactly on the axis the rod is straight and
/// untwisted (documented κ = 0 plane): s* = ∞.
#[test]
fn tau_axis_limit_and_kappa_zero_plane() {
    for sign in [1.0, -1.0] {
        for (k, tol) in [(1e-3, 1e-4), (1e-5, 1e-7)] {
            let d = Direction::new(k, sign, 0.0).unwrap();
            let s = critical_s(&d, 1e-12).unwrap().s_star;
            assert!((s - 2.0 * PI).abs() < tol * 2.0 * PI, "κ̂ = {k}: {s}");
        }
        let on = critical_s(&Direction::new(0.0, sign, 0.0).unwrap(), 1e-10).unwrap();
        assert!(on.s_star.is_infinite() && on.est_error == 0.0);
    }
    assert!(is_stable(0.0, 1e6, 0.0).unwrap());
    // Elsewhere on κ = 0: the tension-free twisted rod, s* = 2x₁/|ω̂|; beyond s_max: ∞.
    let x1 = greenhill_x1();
    for &(t, w) in &[(1.0, 1.0), (-2.0, 0.5), (0.3, -1.0)] {
        let d = Direction::new(0.0, t, w).unwrap();
        let s = critical_s(&d, 1e-10).unwrap().s_star;
        assert!((s - 2.0 * x1 / d.omega.abs()).abs() < 1e-12 * s);
    }
    let d = Direction::new(0.0, 1.0, 1e-3).unwrap();
    assert!(critical_s(&d, 1e-10).unwrap().s_star.is_infinite());
}

/// The κ → 0⁺ limit of the helix (κ, τ̂, ω̂): a straight rod clamped at both ends under the
/// helix's axial compression `P = −(ω̂ − τ̂)τ̂ s²` and twisting moment `M = ω̂ s` (bending
/// stiffness 1), computed independently of the Jacobi equation. The complex deflection
/// `w = x + iy` satisfies `w'''' − iM w''' + P w'' = 0`, with characteristic roots `0, 0, ik₁, ik₂`,
/// `k² − Mk − P = 0` ⇒ `k₁ = τ̂s`, `k₂ = (ω̂ − τ̂)s` (real: the discriminant is `(ω̂ − 2τ̂)²s²`).
/// With `w = A + Bt + Ce^{ik₁t} + De^{ik₂t}` and `w = w' = 0` at both ends the determinant is
/// `Δ = (e₁ − 1 − ik₁)·ik₂(e₂ − 1) − (e₂ − 1 − ik₂)·ik₁(e₁ − 1)`, `e_j = e^{ik_j}`, and
/// `Δ·e^{−i(k₁+k₂)/2}` is purely imaginary. Its first sign change past s = 1 (scan 0.01, then
/// bisection) is the limit s*. Needs `k₁ ≠ k₂`, `k₁, k₂ ≠ 0`.
fn straight_rod_limit(tau: f64, omega: f64) -> f64 {
    let g = |s: f64| {
        let (k1, k2) = (tau * s, (omega - tau) * s);
        // complex numbers as (re, im)
        let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
        let ex = |x: f64| (x.cos(), x.sin());
        let (e1, e2) = (ex(k1), ex(k2));
        let a1 = (e1.0 - 1.0, e1.1 - k1);
        let a2 = (e2.0 - 1.0, e2.1 - k2);
        let t1 = mul(mul(a1, (0.0, k2)), (e2.0 - 1.0, e2.1));
        let t2 = mul(mul(a2, (0.0, k1)), (e1.0 - 1.0, e1.1));
        let d = (t1.0 - t2.0, t1.1 - t2.1);
        let p = mul(d, ex(-0.5 * (k1 + k2)));
        assert!(
            p.0.abs() <= 1e-9 * (1.0 + p.1.abs()),
            "not imaginary: {p:?}"
        );
        p.1
    };
    let h = 0.01;
    let mut s = 1.0;
    let mut prev = g(s);
    loop {
        let v = g(s + h);
        if v.signum() != prev.signum() {
            let (mut lo, mut hi) = (s, s + h);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if g(mid).signum() == prev.signum() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return 0.5 * (lo + hi);
        }
        prev = v;
        s += h;
        assert!(s < 100.0, "no root for ({tau}, {omega})");
    }
}

/// Tiny κ̂, where `det J = O(κ²)` underflows (evaluated literally, `1e-160,1,0` gives s* = 1.3 with
/// est_error 1e-15; the limit is 2π). Every representable κ̂ > 0 — the decades
/// 10⁻¹ … 10⁻³⁰⁰, the smallest normal and subnormals down to the smallest f64 — gives a result
/// right to its `est_error` (plus the O(κ̂²) distance to the limit): against direct RK integration
/// where κ̂ is large enough for it (κ̂ ≥ 1e-3), against the independent straight-rod limit
/// ([`straight_rod_limit`], Greenhill on the ω axis) for κ̂ ≤ 1e-6, and mirror-symmetric.
#[test]
fn tiny_kappa_continuum_is_right_for_every_representable_kappa() {
    let x1 = greenhill_x1();
    // (τ̂, ω̂, limit s* as κ̂ → 0⁺)
    let mut cases = vec![(0.0, 1.0, 2.0 * x1)];
    for (t, w) in [(1.0f64, 0.0f64), (0.6, 0.8), (0.6, -0.8), (0.3, 0.9)] {
        let n: f64 = (t * t + w * w).sqrt();
        let (t, w) = (t / n, w / n);
        cases.push((t, w, straight_rod_limit(t, w)));
    }
    assert!((cases[1].2 - 2.0 * PI).abs() < 1e-12, "{}", cases[1].2);
    let mut kappas: Vec<f64> = (1..=300).map(|k| 10f64.powi(-k)).collect();
    kappas.extend([
        f64::MIN_POSITIVE,
        1e-310,
        1e-320,
        f64::from_bits(1), // 4.9e-324, the smallest positive f64
    ]);
    for &(t, w, limit) in &cases {
        for &k in &kappas {
            let mut results = vec![];
            for sign in [1.0, -1.0] {
                let d = Direction::new(k, sign * t, sign * w).unwrap();
                let r = critical_s(&d, 1e-12).unwrap();
                assert!(
                    r.s_star.is_finite() && r.est_error <= 1e-11 * r.s_star,
                    "κ̂ = {k:e}, {d:?}: {r:?}"
                );
                if k <= 1e-6 {
                    let bound = r.est_error + 1e-10 * limit;
                    assert!(
                        (r.s_star - limit).abs() <= bound,
                        "κ̂ = {k:e}, {d:?}: s* = {} (est_error {:e}), limit {limit}",
                        r.s_star,
                        r.est_error
                    );
                } else if k >= 1e-3 && sign > 0.0 {
                    let rk = rk_first_conjugate(
                        d.kappa,
                        d.tau,
                        d.omega,
                        1.0 / 1.33,
                        0.01,
                        1.0,
                        r.s_star + 1.0,
                    )
                    .unwrap();
                    assert!(
                        ((rk - r.s_star) / rk).abs() < 1e-7,
                        "κ̂ = {k:e}, {d:?}: {} vs RK {rk}",
                        r.s_star
                    );
                }
                results.push(r.s_star);
            }
            assert!(
                (results[0] - results[1]).abs() <= 1e-11 * results[0],
                "mirror, κ̂ = {k:e}: {results:?}"
            );
        }
    }
}

#[test]
fn independent_of_c() {
    for d in random_dirs(20, 11, 0.0) {
        let s: Vec<f64> = [-0.25, 0.33, 0.5]
            .iter()
            .map(|&nu| {
                let p = ContinuumParams {
                    nu,
                    ..ContinuumParams::default()
                };
                critical_s_with(&d, &p).unwrap().s_star
            })
            .collect();
        for x in &s[1..] {
            assert!(
                (x - s[0]).abs() <= 1e-8 * s[0] || (x.is_infinite() && s[0].is_infinite()),
                "{d:?}: {s:?}"
            );
        }
    }
}

#[test]
fn mirror_symmetry() {
    for d in random_dirs(25, 12, 0.0) {
        let m = Direction::new(d.kappa, -d.tau, -d.omega).unwrap();
        let a = critical_s(&d, 1e-11).unwrap().s_star;
        let b = critical_s(&m, 1e-11).unwrap().s_star;
        assert!((a - b).abs() <= 1e-9 * a, "{d:?}: {a} vs {b}");
    }
}

/// Star-convexity, checked on the *unscaled* helix s·S̄ over the rod [0, 1] with the independent
/// RK integrator: a conjugate point on (0, 1] exists exactly for s beyond s*, so each sampled ray
/// crosses the boundary once, where the continuum test says.
#[test]
fn single_crossing_along_rays() {
    let c = 1.0 / 1.33;
    for d in random_dirs(6, 13, 0.2) {
        let s_star = critical_s(&d, 1e-10).unwrap().s_star;
        let mut crossings = 0;
        let mut prev_stable = true;
        for i in 1..=12 {
            let s = s_star * (0.1 * i as f64 + 0.02);
            let [k, t, w] = d.at(s);
            let h = 0.2 / s.max(1.0);
            let unstable = rk_first_conjugate(k, t, w, c, h, 1.0 / s, 1.0).is_some();
            let stable = !unstable;
            assert_eq!(stable, is_stable(k, t, w).unwrap(), "{d:?} at s = {s}");
            assert_eq!(stable, s < s_star, "{d:?} at s = {s} (s* = {s_star})");
            if stable != prev_stable {
                crossings += 1;
            }
            prev_stable = stable;
        }
        assert_eq!(crossings, 1, "{d:?}");
    }
}

/// The scan's step resolves every root: a 16× finer step gives the same s* on a lattice that
/// includes near-κ = 0 directions (near-double roots).
#[test]
fn step_refinement_changes_nothing() {
    let mut dirs = fibonacci(150, false).unwrap();
    dirs.extend(
        random_dirs(10, 14, 0.0)
            .iter()
            .map(|d| Direction::new(1e-4, d.tau, d.omega).unwrap()),
    );
    for d in dirs {
        let a = critical_s(&d, 1e-11).unwrap().s_star;
        let fine = ContinuumParams {
            step: helixreach::boundary::continuum::DEFAULT_STEP / 16.0,
            tol_rel: 1e-11,
            ..ContinuumParams::default()
        };
        let b = critical_s_with(&d, &fine).unwrap().s_star;
        assert!(
            (a - b).abs() <= 1e-9 * a || (a.is_infinite() && b.is_infinite()),
            "{d:?}: {a} vs {b}"
        );
    }
}

#[test]
fn tolerance_is_honoured() {
    for d in random_dirs(10, 15, 0.05) {
        let r = critical_s(&d, 1e-13).unwrap().s_star;
        for tol in [1e-4, 1e-6, 1e-8] {
            let c = critical_s(&d, tol).unwrap();
            assert!(((c.s_star - r) / r).abs() <= tol, "{d:?} tol {tol}");
            assert!(c.est_error <= tol * c.s_star);
        }
    }
}

#[test]
fn bad_input_is_a_clear_error() {
    let cases = [
        (
            Direction {
                kappa: f64::NAN,
                tau: 0.0,
                omega: 1.0,
            },
            "dir_kappa",
        ),
        (
            Direction {
                kappa: 0.0,
                tau: 0.0,
                omega: 0.0,
            },
            "direction",
        ),
        (
            Direction {
                kappa: -0.6,
                tau: 0.8,
                omega: 0.0,
            },
            "dir_kappa",
        ),
    ];
    for (d, field) in cases {
        let e = critical_s(&d, 1e-8).unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
    let d = Direction::new(1.0, 0.0, 0.0).unwrap();
    for tol in [0.0, -1e-8, f64::NAN, 1.0] {
        let e = critical_s(&d, tol).unwrap_err().to_string();
        assert!(e.contains("tol"), "{e}");
    }
    let p = ContinuumParams {
        nu: 0.7,
        ..ContinuumParams::default()
    };
    assert!(critical_s_with(&d, &p)
        .unwrap_err()
        .to_string()
        .contains("nu"));
    assert!(is_stable(-1.0, 0.0, 0.0)
        .unwrap_err()
        .to_string()
        .contains("kappa"));
    assert!(is_stable(1.0, f64::NAN, 0.0)
        .unwrap_err()
        .to_string()
        .contains("tau"));
    assert!(Direction::new(0.0, 0.0, 0.0).is_err());
}

// ---------------------------------------------------------------------------------------------
// Sweep driver
// ---------------------------------------------------------------------------------------------

/// The columns of the synthetic sweeps: an item and a value.
const XV: [Column; 2] = [
    Column::new("x", "", Kind::Count, "the item"),
    Column::new("v", "", Kind::Finite, "a value computed from it"),
];

fn xv(out: &std::path::Path) -> SweepOptions {
    SweepOptions::new(out, &["x", "v"], 1)
        .column(XV[0])
        .column(XV[1])
}

fn square_row(x: &u64) -> helixreach::Result<Vec<String>> {
    // A deterministic but non-trivial float computation per item.
    let mut v = *x as f64;
    for _ in 0..100 {
        v = (v * 1.000_001).sin() + v.sqrt();
    }
    Ok(vec![x.to_string(), format!("{v}")])
}

#[test]
fn driver_is_deterministic_across_thread_counts() {
    let dir = tempfile::tempdir().unwrap();
    let items: Vec<u64> = (0..500).collect();
    let mut outs = vec![];
    for threads in [1, 2, 3] {
        let out = dir.path().join(format!("t{threads}.csv"));
        let mut opts = xv(&out);
        opts.batch = 7;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| driver::run(&items, |x| vec![x.to_string()], square_row, &opts))
            .unwrap();
        outs.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(outs[0], outs[1]);
    assert_eq!(outs[0], outs[2]);
}

#[test]
fn driver_resumes_without_recomputing_and_checkpoints_on_failure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let items: Vec<u64> = (0..40).collect();
    let full = dir.path().join("full.csv");
    driver::run(&items, |x| vec![x.to_string()], square_row, &xv(&full)).unwrap();

    // A run that fails at item 25, checkpointing every batch: the rows before it survive.
    let mut opts = xv(&out);
    opts.batch = 5;
    opts.checkpoint_interval = std::time::Duration::ZERO;
    let e = driver::run(
        &items,
        |x| vec![x.to_string()],
        |x| {
            if *x == 25 {
                Err(helixreach::Error::invalid("x", x, "boom"))
            } else {
                square_row(x)
            }
        },
        &opts,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("item 25") && e.contains("boom"), "{e}");
    // (Checkpoints go beside the output; header + rows.)
    let partial = std::fs::read_to_string(driver::partial_path(&out)).unwrap();
    assert_eq!(partial.lines().count(), 1 + 25 + 4, "{partial}");

    // Resume: only the missing 11 items are computed, and the result equals the full run.
    let count = AtomicUsize::new(0);
    opts.resume = true;
    let summary = driver::run(
        &items,
        |x| vec![x.to_string()],
        |x| {
            count.fetch_add(1, Ordering::Relaxed);
            square_row(x)
        },
        &opts,
    )
    .unwrap();
    assert_eq!(count.load(Ordering::Relaxed), 11);
    assert_eq!((summary.resumed, summary.computed), (29, 11));
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&full).unwrap());

    // A different header refuses to resume; a wrong key is an error naming the row.
    let mut other = SweepOptions::new(&out, &["x", "w"], 1)
        .column(XV[0])
        .column(Column::new("w", "", Kind::Finite, "a value"));
    other.resume = true;
    let e = driver::run(&items, |x| vec![x.to_string()], square_row, &other).unwrap_err();
    assert!(e.to_string().contains("header"), "{e}");
    let e = driver::run(
        &items,
        |x| vec![(x + 1).to_string()],
        square_row,
        &xv(&dir.path().join("k.csv")),
    )
    .unwrap_err();
    assert!(e.to_string().contains("key"), "{e}");
}

#[test]
fn driver_shards_concatenate_to_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let items: Vec<u64> = (0..23).collect();
    let full = dir.path().join("full.csv");
    driver::run(&items, |x| vec![x.to_string()], square_row, &xv(&full)).unwrap();
    let mut body = String::new();
    for i in 0..3 {
        let p = dir.path().join(format!("s{i}.csv"));
        let mut o = xv(&p);
        o.shard = Some(Shard::new(i, 3).unwrap());
        driver::run(&items, |x| vec![x.to_string()], square_row, &o).unwrap();
        let t = std::fs::read_to_string(&p).unwrap();
        // Skip the header.
        body.extend(t.lines().skip(1).map(|l| format!("{l}\n")));
    }
    let full = std::fs::read_to_string(&full).unwrap();
    assert_eq!(format!("x,v\n{body}"), full);
}

// ---------------------------------------------------------------------------------------------
// CLI
// ---------------------------------------------------------------------------------------------

fn cli(args: &[&str], threads: usize) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .env("RAYON_NUM_THREADS", threads.to_string())
        .output()
        .unwrap()
}

#[test]
fn cli_boundary_resume_shards_merge_and_threads() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let base = [
        "boundary",
        "--method",
        "continuum",
        "--fibonacci",
        "60",
        "--tol",
        "1e-9",
    ];
    let run = |extra: &[&str], threads: usize| {
        let mut a: Vec<&str> = base.to_vec();
        a.extend_from_slice(extra);
        let o = cli(&a, threads);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let (one, two) = (p("one.csv"), p("two.csv"));
    run(&["--out", &one], 1);
    run(&["--out", &two], 2);
    let a = std::fs::read_to_string(&one).unwrap();
    assert_eq!(a, std::fs::read_to_string(&two).unwrap());
    let lines: Vec<&str> = a.lines().collect();
    let meta = std::fs::read_to_string(format!("{one}.meta.json")).unwrap();
    assert!(meta.contains("\"sweep\": \"boundary\""), "{meta}");
    assert_eq!(
        lines[0],
        "dir_kappa,dir_tau,dir_omega,s_star,kappa,tau,omega,method,resolution,est_error,refused"
    );
    assert_eq!(lines.len(), 61);
    // Rows are in Fibonacci order and agree with the library.
    let dirs = fibonacci(60, false).unwrap();
    for (l, d) in lines[1..].iter().zip(&dirs) {
        let f: Vec<&str> = l.split(',').collect();
        assert_eq!(f[0].parse::<f64>().unwrap(), d.kappa);
        let s: f64 = f[3].parse().unwrap();
        assert_eq!(s, critical_s(d, 1e-9).unwrap().s_star);
        assert!((f[4].parse::<f64>().unwrap() - s * d.kappa).abs() <= 1e-15 * s);
        assert_eq!((f[7], f[8]), ("continuum", "tol=1e-9"));
    }

    // Resume from a checkpoint of the first 19 rows (the record beside it names those bytes)
    // reproduces the full output.
    let res = p("res.csv");
    let cut = lines[..20].join("\n") + "\n";
    std::fs::write(format!("{res}.partial"), &cut).unwrap();
    let mut meta: serde_json::Value = serde_json::from_str(&meta).unwrap();
    meta["csv"] = serde_json::json!({
        "rows": 19,
        "bytes": cut.len(),
        "fnv1a": helixreach::sweep::record::fnv1a_hex(cut.as_bytes()),
    });
    std::fs::write(format!("{res}.partial.meta.json"), meta.to_string()).unwrap();
    run(&["--out", &res, "--resume"], 2);
    assert_eq!(std::fs::read_to_string(&res).unwrap(), a);

    // Shards merged in order reproduce the full output.
    let shards: Vec<String> = (0..3).map(|i| p(&format!("s{i}.csv"))).collect();
    for (i, s) in shards.iter().enumerate() {
        run(&["--out", s, "--shard", &format!("{i}/3")], 1);
    }
    let merged = p("merged.csv");
    let mut args = vec!["merge", "--out", &merged];
    args.extend(shards.iter().map(String::as_str));
    let o = cli(&args, 1);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read_to_string(&merged).unwrap(), a);
    // Overlapping shards are refused.
    let o = cli(
        &["merge", "--force", "--out", &merged, &shards[0], &shards[0]],
        1,
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("expected 1/3"));
}

#[test]
fn cli_bad_input_names_the_problem() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("d.csv");
    std::fs::write(&d, "dir_kappa,dir_tau,dir_omega\n1,0,0\nNaN,1,0\n").unwrap();
    let out = dir.path().join("o.csv");
    let (d, out) = (d.to_str().unwrap(), out.to_str().unwrap());
    let o = cli(&["boundary", "--directions", d, "--out", out], 1);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("d.csv:3") && e.contains("dir_kappa"), "{e}");
    let bad: [(&[&str], &str); 3] = [
        (&["--tol", "0"], "tol"),
        (&["--tol=-1e-8"], "tol"),
        (&["--nu", "0.9"], "nu"),
    ];
    for (extra, field) in bad {
        let mut a = vec!["boundary", "--fibonacci", "4", "--out", out];
        a.extend_from_slice(extra);
        let o = cli(&a, 1);
        assert_eq!(o.status.code(), Some(2));
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(e.contains(field), "{e}");
    }
    let o = cli(
        &[
            "boundary",
            "--fibonacci",
            "4",
            "--shard",
            "4/4",
            "--out",
            out,
        ],
        1,
    );
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("shard"));
}

/// The DER-statics boundary (n = 100) agrees with the continuum within 0.1 % on a
/// handful of generic directions (the convergence study itself lives with the DER tests).
#[test]
fn der_n100_agrees_with_continuum() {
    use helixreach::boundary::der;
    let p = der::DerBoundaryParams {
        n_edges: 100,
        tol_rel: 1e-8,
        ..Default::default()
    };
    for v in [
        [0.594, 0.698, 0.4],
        [1.0, 1.0, -1.0],
        [0.1, -0.3, 0.9],
        [0.8, -0.5, 0.6],
    ] {
        let d = Direction::new(v[0], v[1], v[2]).unwrap();
        let c = critical_s(&d, 1e-10).unwrap().s_star;
        let r = der::critical_s(&d, &p).unwrap().s_star;
        assert!(((r - c) / c).abs() < 1e-3, "{d:?}: DER {r}, continuum {c}");
    }
}
