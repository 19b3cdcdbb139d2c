//! Tests of `helixreach::helix` against independent references:
//! - an RK4 integration of the Frenet–Serret equations, of parallel transport
//!   (d_i' = κB × d_i) and of the material frame (m_i' = (κB + (ω/c)T) × m_i), written here in
//!   plain arrays, at > 1,300 seeded random helices (κ log-uniform in [1e-12, 60],
//!   τ ∈ [−60, 60], tiny λ, λ within 1e-9 of 2π and 4π, κ = 0, τ = 0);
//! - near λ → 0: the Taylor series of exp(ŵ) and of its integral, summed from matrix powers;
//! - near λ = 2πk: a double-double evaluation of λ − 2πk, so exp(ŵ) = exp((λ−2πk)·ŵ/λ);
//! - analytic limits (planar arc, straight twisted rod), the mirror symmetry, orthonormality;
//! - the discrete transport's observed order of convergence;
//! - the error metric, bad input, and the CLI.

use helixreach::helix::discrete::{self, DiscreteHelix};
use helixreach::helix::error_metric::{paper_error, safe_error, RADIUS_FLOOR};
use helixreach::helix::{twist_ratio, Helix};
use helixreach::math::{rot_z, Mat3, Vec3};
use helixreach::Error;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------------
// Reference 1: RK4 on the Frenet–Serret, Bishop and material-frame equations.

type V3 = [f64; 3];

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// State: N, B, T, r, d1, d2, m1, m2 (8 vectors, clamp frame).
type State = [V3; 8];

fn rhs(k: f64, t: f64, phi: f64, y: &State) -> State {
    let [n, b, tt, _r, d1, d2, m1, m2] = *y;
    let mut out = [[0.0; 3]; 8];
    for j in 0..3 {
        out[0][j] = -k * tt[j] + t * b[j]; // N' = −κT + τB
        out[1][j] = -t * n[j]; //            B' = −τN
        out[2][j] = k * n[j]; //             T' = κN
        out[3][j] = tt[j]; //                r' = T
    }
    // Parallel transport: angular velocity κB (= T × T'), no spin about T.
    let kb = [k * b[0], k * b[1], k * b[2]];
    out[4] = cross(kb, d1);
    out[5] = cross(kb, d2);
    // Material frame: angular velocity κB + φT (uniform twist rate φ = ω/c about the tangent).
    let om = [
        kb[0] + phi * tt[0],
        kb[1] + phi * tt[1],
        kb[2] + phi * tt[2],
    ];
    out[6] = cross(om, m1);
    out[7] = cross(om, m2);
    out
}

fn axpy(y: &State, h: f64, k: &State) -> State {
    let mut o = *y;
    for i in 0..8 {
        for j in 0..3 {
            o[i][j] += h * k[i][j];
        }
    }
    o
}

/// An upper bound Ω of the rotation rates in the system: the Frenet frame turns at λ, the
/// material frame at |κB + φT| ≤ κ + |φ| about an axis that itself turns at λ.
fn rate(k: f64, t: f64, phi: f64) -> f64 {
    ((k * k + t * t).sqrt() + phi.abs()).max(1.0)
}

/// Integrate from s = 0 to each of `checkpoints` (increasing, in (0, 1]) with classical RK4
/// at a step h with h·Ω ≤ 1/200 (Ω from [`rate`]). Global error ≈ Ω(hΩ)⁴/120 ≤ 5e-12·Ω.
fn rk4(k: f64, t: f64, phi: f64, checkpoints: &[f64]) -> Vec<State> {
    let omega_max = rate(k, t, phi);
    let e = |i: usize| {
        let mut v = [0.0; 3];
        v[i] = 1.0;
        v
    };
    let mut y: State = [e(0), e(1), e(2), [0.0; 3], e(0), e(1), e(0), e(1)];
    let mut s0 = 0.0;
    let mut out = Vec::new();
    for &s1 in checkpoints {
        let n = ((s1 - s0) * omega_max * 200.0).ceil().max(8.0) as usize;
        let h = (s1 - s0) / n as f64;
        for _ in 0..n {
            let k1 = rhs(k, t, phi, &y);
            let k2 = rhs(k, t, phi, &axpy(&y, 0.5 * h, &k1));
            let k3 = rhs(k, t, phi, &axpy(&y, 0.5 * h, &k2));
            let k4 = rhs(k, t, phi, &axpy(&y, h, &k3));
            for i in 0..8 {
                for j in 0..3 {
                    y[i][j] += h / 6.0 * (k1[i][j] + 2.0 * k2[i][j] + 2.0 * k3[i][j] + k4[i][j]);
                }
            }
        }
        out.push(y);
        s0 = s1;
    }
    out
}

fn frame(c0: V3, c1: V3, c2: V3) -> Mat3 {
    Mat3::from_columns(&[Vec3::from(c0), Vec3::from(c1), Vec3::from(c2)])
}

fn max_abs(m: &Mat3) -> f64 {
    m.iter().fold(0.0, |a, x| a.max(x.abs()))
}

fn orthonormality(m: &Mat3) -> f64 {
    max_abs(&(m.transpose() * m - Mat3::identity()))
}

// ---------------------------------------------------------------------------------------------
// Sample sets.

#[derive(Debug, Clone, Copy)]
struct Case {
    kappa: f64,
    tau: f64,
    omega: f64,
    nu: f64,
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    (lo.ln() + rng.random::<f64>() * (hi.ln() - lo.ln())).exp()
}

fn near_2pi_k(rng: &mut ChaCha8Rng, k: f64) -> (f64, f64) {
    let lam = 2.0 * PI * k + rng.random_range(-1e-9..1e-9);
    let psi = rng.random_range(0.0..PI);
    (lam * psi.sin(), lam * psi.cos())
}

fn cases() -> Vec<Case> {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let mut out = Vec::new();
    let mut push = |rng: &mut ChaCha8Rng, kappa: f64, tau: f64| {
        out.push(Case {
            kappa,
            tau,
            omega: rng.random_range(-20.0..20.0),
            nu: rng.random_range(-0.99..0.5),
        })
    };
    for _ in 0..1000 {
        let k = log_uniform(&mut rng, 1e-12, 60.0);
        let t = rng.random_range(-60.0..60.0);
        push(&mut rng, k, t);
    }
    for _ in 0..100 {
        // tiny λ: both κ and |τ| in [1e-12, 1e-3]
        let k = log_uniform(&mut rng, 1e-12, 1e-3);
        let t = log_uniform(&mut rng, 1e-12, 1e-3) * if rng.random() { 1.0 } else { -1.0 };
        push(&mut rng, k, t);
    }
    for kk in [1.0, 2.0] {
        for _ in 0..100 {
            let (k, t) = near_2pi_k(&mut rng, kk);
            push(&mut rng, k, t);
        }
    }
    for _ in 0..20 {
        let t = rng.random_range(-60.0..60.0);
        push(&mut rng, 0.0, t); // straight twisted rod
        let k = rng.random_range(0.0..60.0);
        push(&mut rng, k, 0.0); // planar arc
    }
    push(&mut rng, 0.0, 0.0);
    out
}

// ---------------------------------------------------------------------------------------------

#[test]
fn closed_form_matches_rk4_integration() {
    let checkpoints = [0.25, 0.5, 0.75, 1.0];
    let mut worst = (0.0f64, 0.0f64, 0.0f64); // (position, frames, orthonormality)
    let cases = cases();
    assert!(cases.len() >= 1000);
    for cs in &cases {
        let h = Helix::new(cs.kappa, cs.tau, cs.omega).unwrap();
        let c = twist_ratio(cs.nu).unwrap();
        let phi = cs.omega / c;
        let rk = rk4(cs.kappa, cs.tau, phi, &checkpoints);
        let rate = rate(cs.kappa, cs.tau, phi);
        // RK4 truncation (≤ 5e-12·Ω) plus roundoff over ≤ 200·Ω steps.
        let tol = 2e-11 * rate;
        for (y, &s) in rk.iter().zip(&checkpoints) {
            let [n, b, t, r, d1, d2, m1, m2] = *y;
            let ep = (h.position(s) - Vec3::from(r)).amax();
            let ef = max_abs(&(h.frenet_frame(s) - frame(n, b, t)));
            let eq = max_abs(&(h.transported_frame(s) - frame(d1, d2, t)));
            let em = max_abs(&(h.material_frame(s, c) - frame(m1, m2, t)));
            let e = ef.max(eq).max(em);
            assert!(
                ep < tol && e < tol,
                "{cs:?} s={s}: position {ep:e}, frames {e:e}"
            );
            worst.0 = worst.0.max(ep / rate);
            worst.1 = worst.1.max(e / rate);
            for m in [
                h.frenet_frame(s),
                h.transported_frame(s),
                h.material_frame(s, c),
            ] {
                worst.2 = worst.2.max(orthonormality(&m));
            }
        }
        // The end pose is the s = 1 evaluation, scaled by L.
        let len = 0.51;
        let p = h.end_pose(len, cs.nu).unwrap();
        let [_, _, t, r, d1, d2, m1, m2] = rk[3];
        assert!((p.position / len - Vec3::from(r)).amax() < tol);
        assert!(max_abs(&(p.transported - frame(d1, d2, t))) < tol);
        assert!(max_abs(&(p.material - frame(m1, m2, t))) < tol);
        assert_eq!(p.motor_angle, phi);
        worst.2 = worst.2.max(orthonormality(&p.material));
        worst.2 = worst.2.max(orthonormality(&p.transported));
        assert!(p.material.determinant() > 0.0);
    }
    println!(
        "{} helices: max |closed − RK4|/Ω: position {:.2e}, frames {:.2e}; max |RᵀR − I| {:.2e}",
        cases.len(),
        worst.0,
        worst.1,
        worst.2
    );
    assert!(worst.2 <= 1e-14, "orthonormality {:e}", worst.2);
}

#[test]
fn frames_are_orthonormal_at_random_arc_lengths() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut worst = 0.0f64;
    for cs in cases() {
        let h = Helix::new(cs.kappa, cs.tau, cs.omega).unwrap();
        let c = twist_ratio(cs.nu).unwrap();
        for _ in 0..4 {
            let s = rng.random_range(0.0..1.0);
            for m in [
                h.frenet_frame(s),
                h.transported_frame(s),
                h.material_frame(s, c),
            ] {
                worst = worst.max(orthonormality(&m));
                assert!((m.determinant() - 1.0).abs() < 1e-14);
            }
        }
    }
    assert!(
        worst <= helixreach::math::tol::FRAME_ORTHONORMAL,
        "{worst:e}"
    );
}

// ---------------------------------------------------------------------------------------------
// Reference 2: Taylor series of exp(ŵ) and ∫₀¹exp(uŵ)du·e₃ from matrix powers (tiny λ).

fn hat(w: &Vec3) -> Mat3 {
    Mat3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

fn series_pose(k: f64, t: f64, terms: usize) -> (Mat3, Vec3) {
    let what = hat(&Vec3::new(0.0, k, t));
    let mut f = Mat3::identity();
    let mut r = Vec3::zeros();
    let mut p = Mat3::identity(); // ŵ^j / j!
    for j in 0..terms {
        if j > 0 {
            p = p * what / j as f64;
            f += p;
        }
        r += p.column(2) / (j + 1) as f64; // ŵ^j e3 / (j+1)!
    }
    (f, r)
}

/// max over entries of |x − ref| / |ref| (entries with ref = 0 must match exactly).
fn rel_err_mat(x: &Mat3, r: &Mat3) -> f64 {
    x.iter().zip(r.iter()).fold(0.0, |a, (x, r)| {
        a.max(if *r == 0.0 {
            if *x == 0.0 {
                0.0
            } else {
                f64::INFINITY
            }
        } else {
            ((x - r) / r).abs()
        })
    })
}

fn rel_err_vec(x: &Vec3, r: &Vec3) -> f64 {
    x.iter()
        .zip(r.iter())
        .fold(0.0, |a, (x, r)| a.max(((x - r) / r).abs()))
}

#[test]
fn tiny_and_moderate_lambda_are_componentwise_accurate() {
    // λ ≤ 1: the series terms shrink at least like 1/j!, no cancellation among the leading
    // terms of any entry, so the series is a componentwise-accurate reference.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut worst = 0.0f64;
    for i in 0..400 {
        let lam = if i < 200 {
            log_uniform(&mut rng, 1e-12, 1e-3)
        } else {
            log_uniform(&mut rng, 1e-3, 1.0)
        };
        let psi = rng.random_range(0.02..PI - 0.02); // both κ and τ non-negligible
        let (k, t) = (lam * psi.sin(), lam * psi.cos());
        let h = Helix::new(k, t, 0.0).unwrap();
        let (f_ref, r_ref) = series_pose(k, t, 30);
        let (f, r) = h.frenet_and_position(1.0);
        let e = rel_err_mat(&f, &f_ref).max(rel_err_vec(&r, &r_ref));
        worst = worst.max(e);
        assert!(
            e < 4e-15,
            "κ={k:e} τ={t:e} λ={lam:e}: componentwise rel err {e:e}"
        );
        // frenet_frame / position agree with the fused evaluation bit for bit.
        assert_eq!(h.frenet_frame(1.0), f);
        assert_eq!(h.position(1.0), r);
    }
    println!("λ ∈ [1e-12, 1]: worst componentwise relative error vs Taylor series {worst:.2e}");
}

// ---------------------------------------------------------------------------------------------
// Reference 3: double-double λ − 2πk.

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// λ − 2πk to ~1e-30 absolute, from κ, τ (exact f64 inputs).
fn lambda_minus_2pik(k: f64, t: f64, kk: f64) -> f64 {
    let (a, ae) = two_prod(k, k);
    let (b, be) = two_prod(t, t);
    let (s, se) = two_sum(a, b);
    let s_lo = se + ae + be;
    let x = s.sqrt();
    let (x2, x2e) = two_prod(x, x);
    // λ ≈ x + (S − x²)/(2x)
    let corr = ((s - x2) - x2e + s_lo) / (2.0 * x);
    const TWO_PI_HI: f64 = std::f64::consts::TAU;
    const TWO_PI_LO: f64 = 2.449_293_598_294_706_4e-16;
    // x − 2πk·hi is exact (Sterbenz) for k ∈ {1, 2}; kk·hi is exact (power of two).
    (x - kk * TWO_PI_HI) + (corr - kk * TWO_PI_LO)
}

#[test]
fn near_multiples_of_2pi_match_double_double_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let mut worst = 0.0f64;
    for kk in [1.0, 2.0] {
        for _ in 0..200 {
            let (k, t) = near_2pi_k(&mut rng, kk);
            let h = Helix::new(k, t, 0.0).unwrap();
            let d = lambda_minus_2pik(k, t, kk);
            assert!(d.abs() < 1.1e-9);
            let lam = 2.0 * PI * kk + d; // only used as a divisor/axis norm
            let u = Vec3::new(0.0, k, t) / lam;
            let uh = hat(&u);
            // exp(λû) = exp(δû): sin δ, 1 − cos δ by series (δ < 1.1e-9).
            let (sd, omc) = (d - d * d * d / 6.0, 0.5 * d * d);
            let f_ref = Mat3::identity() + sd * uh + omc * (uh * uh);
            // r(1) = e3 + (1−cos λ)/λ²·ŵe3 + (λ − sin λ)/λ³·ŵ²e3 with cos λ = cos δ, sin λ = sin δ.
            let w = Vec3::new(0.0, k, t);
            let we3 = w.cross(&Vec3::z());
            let r_ref = Vec3::z()
                + omc / (lam * lam) * we3
                + (lam - sd) / (lam * lam * lam) * w.cross(&we3);
            let (f, r) = h.frenet_and_position(1.0);
            let e = max_abs(&(f - f_ref)).max((r - r_ref).amax());
            worst = worst.max(e);
            // One ulp of λ (≈ 8.9e-16 at 2π, 1.8e-15 at 4π) feeds sin λ; allow ~2 ulps.
            assert!(e < 2.0 * kk * 1.8e-15, "k={kk} δ={d:e}: {e:e}");
        }
    }
    println!("λ within 1e-9 of 2π, 4π: worst |closed − double-double reference| {worst:.2e}");
}

// ---------------------------------------------------------------------------------------------
// Analytic limits and symmetry.

#[test]
fn planar_arc_and_straight_twisted_rod_limits() {
    for &k in &[1e-9, 0.3, 1.0, PI, 10.0, 60.0] {
        // τ = 0: a circular arc in the x–z plane; the frames turn about y = B.
        let h = Helix::new(k, 0.0, 0.0).unwrap();
        let r = h.position(1.0);
        let exp_r = Vec3::new(2.0 * (0.5 * k).sin().powi(2) / k, 0.0, k.sin() / k);
        assert!(
            (r - exp_r).amax() < 4e-16 * (1.0 + 1.0 / k),
            "{k}: {r:?} vs {exp_r:?}"
        );
        let (c, s) = (k.cos(), k.sin());
        let ry = Mat3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c);
        assert!(max_abs(&(h.frenet_frame(1.0) - ry)) < 1e-15);
        assert!(max_abs(&(h.transported_frame(1.0) - ry)) < 1e-15);
    }
    for &t in &[-60.0, -1.0, 1e-9, 5.0] {
        // κ = 0: straight rod along z; the Frenet frame spins at τ, the Bishop frame does not.
        let h = Helix::new(0.0, t, 2.0).unwrap();
        assert_eq!(h.position(0.7), Vec3::new(0.0, 0.0, 0.7));
        assert!(max_abs(&(h.frenet_frame(1.0) - rot_z(t))) < 1e-15);
        assert!(max_abs(&(h.transported_frame(1.0) - Mat3::identity())) < 1e-15);
        let p = h.end_pose(2.0, 0.5).unwrap();
        assert!((p.motor_angle - 3.0).abs() < 1e-15);
        assert!(max_abs(&(p.material - rot_z(3.0))) < 1e-15);
        assert_eq!(p.position, Vec3::new(0.0, 0.0, 2.0));
    }
}

#[test]
fn mirror_symmetry_is_a_reflection_of_the_pose() {
    // The reflection P: y → −y of the clamp frame maps the curve r to P r. Its tangent and
    // normal are P T, P N (κ is unchanged), its binormal (P T) × (P N) = det(P)·P(T × N) = −P B,
    // so its torsion is −τ and its Frenet frame is P F P (P on the right flips the B column).
    // Parallel transport commutes with P, and [P d1, −P d2, P d3] = P Q P is the proper frame
    // (identity at s = 0). P Rz(a) P = Rz(−a), so the material twist flips: ω → −ω.
    let p = Mat3::from_diagonal(&Vec3::new(1.0, -1.0, 1.0));
    let mut rng = ChaCha8Rng::seed_from_u64(17);
    for cs in cases().iter().step_by(3) {
        let h = Helix::new(cs.kappa, cs.tau, cs.omega).unwrap();
        let m = Helix::new(cs.kappa, -cs.tau, -cs.omega).unwrap();
        assert_eq!(m, h.mirror());
        let s = rng.random_range(0.0..1.0);
        let c = twist_ratio(cs.nu).unwrap();
        let tol = 4e-16;
        assert!((m.position(s) - p * h.position(s)).amax() <= tol * 4.0);
        assert!(max_abs(&(m.frenet_frame(s) - p * h.frenet_frame(s) * p)) <= tol);
        assert!(max_abs(&(m.transported_frame(s) - p * h.transported_frame(s) * p)) <= tol);
        assert!(max_abs(&(m.material_frame(s, c) - p * h.material_frame(s, c) * p)) <= tol);
        let (a, b) = (
            h.end_pose(1.0, cs.nu).unwrap(),
            m.end_pose(1.0, cs.nu).unwrap(),
        );
        assert_eq!(b.motor_angle, -a.motor_angle);
        assert!((b.position - p * a.position).amax() <= tol * 4.0);
        assert!(max_abs(&(b.material - p * a.material * p)) <= tol);
    }
}

#[test]
fn position_derivative_is_the_tangent() {
    // A second, local check independent of RK: central differences of r(s) give T(s).
    let h = Helix::new(7.0, -3.0, 0.0).unwrap();
    for i in 0..=10 {
        let s = i as f64 / 10.0;
        let d = 1e-5;
        let fd = (h.position(s + d) - h.position(s - d)) / (2.0 * d);
        assert!((fd - h.frenet_frame(s).column(2)).norm() < 1e-8);
    }
}

// ---------------------------------------------------------------------------------------------
// Discrete helix.

fn discrete_error(h: &Helix, n: usize) -> (f64, f64) {
    let d = DiscreteHelix::new(h, n).unwrap();
    let mut mid = 0.0f64;
    for (i, f) in d.frames.iter().enumerate() {
        let s = (i as f64 + 0.5) / n as f64;
        mid = mid.max(max_abs(&(f - h.transported_frame(s))));
        assert!(orthonormality(f) < 1e-14);
    }
    let end = max_abs(&(d.end_frame(h) - h.transported_frame(1.0)));
    (mid, end)
}

#[test]
fn discrete_transport_converges_with_order_two() {
    for &(k, t) in &[(5.0, 3.0), (2.0, -7.0), (20.0, 15.0), (1e-3, 40.0)] {
        let h = Helix::new(k, t, 0.0).unwrap();
        let ns = [50, 100, 200, 400, 800];
        let errs: Vec<(f64, f64)> = ns.iter().map(|&n| discrete_error(&h, n)).collect();
        let mut orders = Vec::new();
        for i in 1..ns.len() {
            let p_mid = (errs[i - 1].0 / errs[i].0).log2();
            let p_end = (errs[i - 1].1 / errs[i].1).log2();
            orders.push((p_mid, p_end));
        }
        println!(
            "κ={k} τ={t}: n={ns:?} max|frame_i − Q(s_mid)| = {:?}; |end − Q(1)| = {:?}; observed orders (mid, end) = {orders:.3?}",
            errs.iter().map(|e| format!("{:.2e}", e.0)).collect::<Vec<_>>(),
            errs.iter().map(|e| format!("{:.2e}", e.1)).collect::<Vec<_>>(),
        );
        let (p_mid, p_end) = *orders.last().unwrap();
        assert!(p_mid > 1.9 && p_mid < 2.1, "mid order {p_mid}");
        assert!(p_end > 1.9 && p_end < 2.1, "end order {p_end}");
        assert!(errs[4].0 < 1e-3 * h.lambda().max(1.0).powi(2));
    }
}

#[test]
fn discrete_transport_handles_parallel_tangents() {
    // κ = 0 and κ = 1e-12: consecutive tangents are (nearly) parallel. The paper's
    // b = t_{i−1}×t_i/|t_{i−1}×t_i| is 0/0 there; ours must stay exact.
    let a = Vec3::z();
    let naive_b = a.cross(&a) / a.cross(&a).norm();
    assert!(
        naive_b.x.is_nan(),
        "the paper's form is undefined for parallel tangents"
    );
    for &k in &[0.0, 1e-12, 1e-8] {
        let h = Helix::new(k, 30.0, 0.0).unwrap();
        let d = DiscreteHelix::new(&h, 1000).unwrap();
        for (i, f) in d.frames.iter().enumerate() {
            let s = (i as f64 + 0.5) / 1000.0;
            assert!(f.iter().all(|x| x.is_finite()));
            assert!(
                max_abs(&(f - h.transported_frame(s))) < 1e-10,
                "κ={k} edge {i}"
            );
        }
    }
    // Coarse discretizations of tight helices (turns of up to ~180° per edge) stay proper frames.
    for n in 1..12 {
        for &(k, t) in &[(60.0, 0.0), (60.0, 5.0), (3.0 * PI, 0.0)] {
            let d = DiscreteHelix::new(&Helix::new(k, t, 0.0).unwrap(), n).unwrap();
            for f in &d.frames {
                assert!(f.iter().all(|x| x.is_finite()) && orthonormality(f) < 1e-14);
                assert!((f.determinant() - 1.0).abs() < 1e-14);
            }
        }
    }
    // Exactly antiparallel tangents (a cusp): still a proper frame carried onto −z.
    let f = discrete::transport_frame(&Mat3::identity(), &-Vec3::z());
    assert!(orthonormality(&f) < 1e-15 && (f.determinant() - 1.0).abs() < 1e-15);
    assert_eq!(f.column(2).into_owned(), -Vec3::z());
    // Nearly antiparallel: the minimal rotation about a × b (here x): d1 = x stays x.
    let b = Vec3::new(0.0, 1e-9, -1.0).normalize();
    let f = discrete::transport_frame(&Mat3::identity(), &b);
    assert!((f.column(0) - Vec3::x()).amax() < 1e-15, "{f}");
    // Generic turn: the transported vector keeps its angle to the rotation axis a × b.
    let a = Vec3::new(0.3, -0.2, 0.9).normalize();
    let b = Vec3::new(-0.5, 0.4, 0.2).normalize();
    let axis = a.cross(&b).normalize();
    let d = Vec3::new(1.0, 2.0, 3.0);
    let rd = discrete::transport_vector(&d, &a, &b, &Vec3::x());
    assert!((rd.dot(&axis) - d.dot(&axis)).abs() < 1e-14);
    assert!((rd.norm() - d.norm()).abs() < 1e-14);
    assert!((discrete::transport_vector(&a, &a, &b, &Vec3::x()) - b).amax() < 1e-15);
}

/// The seed paper's discrete parallel transport (its eq. for m1^int), valid only for
/// non-parallel consecutive tangents.
fn paper_transport(m1: &Vec3, t0: &Vec3, t1: &Vec3) -> Vec3 {
    let b = t0.cross(t1) / t0.cross(t1).norm();
    let m = m1.dot(&t0.cross(&b)) * t1.cross(&b) + m1.dot(&b) * b;
    m / m.norm()
}

#[test]
fn discrete_transport_equals_the_papers_formula_where_it_is_defined() {
    for &(k, t, n) in &[(5.0, 3.0, 50), (20.0, -15.0, 64), (0.3, 2.0, 10)] {
        let h = Helix::new(k, t, 0.0).unwrap();
        let d = DiscreteHelix::new(&h, n).unwrap();
        let mut m1: Vec3 = d.frames[0].column(0).into_owned();
        for i in 1..n {
            m1 = paper_transport(&m1, &d.tangents[i - 1], &d.tangents[i]);
            let ours = d.frames[i];
            assert!((ours.column(0) - m1).amax() < 1e-13, "κ={k} τ={t} edge {i}");
            let m2 = d.tangents[i].cross(&m1);
            assert!((ours.column(1) - m2).amax() < 1e-13);
        }
    }
}

#[test]
fn nodes_and_tangents() {
    let h = Helix::new(3.0, 2.0, 0.0).unwrap();
    let q = discrete::nodes(&h, 64);
    assert_eq!(q.len(), 65);
    assert_eq!(q[0], Vec3::zeros());
    for (i, p) in q.iter().enumerate() {
        assert_eq!(*p, h.position(i as f64 / 64.0));
    }
    let t = discrete::edge_tangents(&q).unwrap();
    assert_eq!(t.len(), 64);
    for (i, ti) in t.iter().enumerate() {
        let tm = h
            .frenet_frame((i as f64 + 0.5) / 64.0)
            .column(2)
            .into_owned();
        // chord/|chord| = T + h²κτ/24·B + O(h⁴) at the midpoint, h = 1/64
        assert!((ti - tm).norm() < 6.0 / 24.0 / 64.0f64.powi(2) * 1.05);
    }
    let dup = vec![Vec3::zeros(), Vec3::zeros()];
    assert!(discrete::edge_tangents(&dup).is_err());
    assert!(DiscreteHelix::new(&h, 0).is_err());
}

// ---------------------------------------------------------------------------------------------
// Error metric.

#[test]
fn error_metric_zero_on_helix_positive_otherwise_finite_at_zero_curvature() {
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    for &(k, t) in &[
        (3.0, 4.0),
        (10.0, -2.0),
        (1e-12, 5.0),
        (0.0, 5.0),
        (0.0, 0.0),
        (1e-300, 0.0),
    ] {
        let h = Helix::new(k, t, 0.0).unwrap();
        let q = discrete::nodes(&h, 50);
        assert_eq!(safe_error(&q, &q, &h, 1.0, RADIUS_FLOOR).unwrap(), 0.0);
        let bumped: Vec<Vec3> = q
            .iter()
            .map(|p| p + Vec3::new(rng.random(), rng.random(), rng.random()) * 1e-6)
            .collect();
        let e = safe_error(&bumped, &q, &h, 1.0, RADIUS_FLOOR).unwrap();
        assert!(e > 0.0 && e.is_finite(), "κ={k} τ={t}: {e}");
        // Moving one node changes e by exactly |Δ|/(n+1)/ρ with ρ = clamp(R, ρ_min, 1)·L.
        let mut one = q.clone();
        one[7].x += 2e-3;
        let r: f64 = k / (k * k + t * t);
        let r = r.clamp(RADIUS_FLOOR, 1.0);
        let r = if r.is_nan() { 1.0 } else { r }; // κ = τ = 0: straight, R = ∞ → L
        let e1 = safe_error(&one, &q, &h, 2.0, RADIUS_FLOOR).unwrap();
        assert!(
            (e1 - 2e-3 / 51.0 / (2.0 * r)).abs() < 1e-12 * e1,
            "κ={k} τ={t}: {e1}"
        );
        if k > 0.0 && r > RADIUS_FLOOR && r < 1.0 {
            // Inside the clamp the safe form is the paper's e.
            let ep = paper_error(&one, &q, &h, 2.0).unwrap();
            assert!((ep - e1).abs() < 1e-14 * ep);
        }
    }
    let h0 = Helix::new(0.0, 1.0, 0.0).unwrap();
    let q = discrete::nodes(&h0, 4);
    assert!(paper_error(&q, &q, &h0, 1.0).is_err());
    assert!(safe_error(&q, &q[..3], &h0, 1.0, RADIUS_FLOOR).is_err());
    let mut nan = q.clone();
    nan[2].y = f64::NAN;
    assert!(safe_error(&nan, &q, &h0, 1.0, RADIUS_FLOOR).is_err());
    assert!(safe_error(&q, &q, &h0, 1.0, 0.0).is_err());
}

#[test]
fn error_metric_detects_a_non_helical_rod() {
    // Nodes of a different helix (a rod that snapped to another shape) give e ≫ 0.
    let h = Helix::new(6.0, 6.0, 0.0).unwrap();
    let other = Helix::new(6.0, -6.0, 0.0).unwrap();
    let (q, qh) = (discrete::nodes(&other, 100), discrete::nodes(&h, 100));
    let e = paper_error(&q, &qh, &h, 1.0).unwrap();
    assert!(e > 0.5, "{e}");
}

// ---------------------------------------------------------------------------------------------
// Bad input.

fn field_of(e: Error) -> String {
    match e {
        Error::InvalidParameter { field, .. } => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
}

#[test]
fn bad_input_gives_typed_errors_naming_the_field() {
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 2e6] {
        assert_eq!(field_of(Helix::new(bad, 1.0, 1.0).unwrap_err()), "kappa");
        assert_eq!(field_of(Helix::new(1.0, bad, 1.0).unwrap_err()), "tau");
        assert_eq!(field_of(Helix::new(1.0, 1.0, bad).unwrap_err()), "omega");
    }
    assert_eq!(
        field_of(Helix::new(-1e-300, 1.0, 1.0).unwrap_err()),
        "kappa"
    );
    assert!(Helix::new(-0.0, 1.0, 1.0).is_ok());
    let h = Helix::new(1.0, 2.0, 3.0).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(field_of(h.end_pose(bad, 0.3).unwrap_err()), "length");
    }
    for bad in [-1.0, -1.5, 0.5000001, 1.0, f64::NAN, f64::INFINITY] {
        let e = h.end_pose(1.0, bad).unwrap_err();
        let msg = e.to_string();
        assert_eq!(field_of(e), "nu");
        assert!(msg.contains("nu"), "{msg}");
    }
    assert!(h.end_pose(1.0, 0.5).is_ok());
    assert!(h.end_pose(1.0, -0.999).is_ok());
    // The validated and unchecked paths agree bit for bit.
    let c = twist_ratio(0.3).unwrap();
    assert_eq!(h.end_pose(0.7, 0.3).unwrap(), h.end_pose_unchecked(0.7, c));
    // Rays: s must be finite and >= 0.
    let d = helixreach::directions::Direction::new(0.6, 0.0, 0.8).unwrap();
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(field_of(Helix::on_ray(&d, bad).unwrap_err()), "s");
    }
    assert_eq!(field_of(Helix::on_ray(&d, 1e7).unwrap_err()), "kappa");
    let msg = Helix::new(-2.0, 0.0, 0.0).unwrap_err().to_string();
    assert!(msg.contains("kappa") && msg.contains("-2"), "{msg}");
}

// ---------------------------------------------------------------------------------------------
// CLI.

fn cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_prints_the_end_pose_as_json() {
    let out = cli(&[
        "helix", "--kappa", "3.1", "--tau", "-2", "--omega", "1.5", "--nu", "0.25", "--length",
        "0.51",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let p = Helix::new(3.1, -2.0, 1.5)
        .unwrap()
        .end_pose(0.51, 0.25)
        .unwrap();
    // serde_json prints shortest round-trip digits, but its default parser may be 1 ulp off:
    // compare to 2 ulps (the CSV test checks exact round trips with Rust's parser).
    let close = |a: f64, b: f64| (a - b).abs() <= 2.0 * f64::EPSILON * b.abs();
    let pos: Vec<f64> = serde_json::from_value(v["position"].clone()).unwrap();
    for i in 0..3 {
        assert!(close(pos[i], p.position[i]), "{pos:?}");
    }
    // Default: the frames as unit quaternions (scalar first, qw ≥ 0): rebuilt as matrices they
    // equal the library's frames.
    for (key, m) in [
        ("material_wxyz", &p.material),
        ("transported_wxyz", &p.transported),
    ] {
        let q: [f64; 4] = serde_json::from_value(v[key].clone()).unwrap();
        assert!(q[0] >= 0.0 && (q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-14);
        let r = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[0], q[1], q[2], q[3],
        ))
        .to_rotation_matrix();
        assert!((r.matrix() - m).amax() < 1e-14, "{key}");
    }
    assert!(v.get("material_rows").is_none());
    // --matrix: the rows themselves.
    let out = cli(&[
        "helix", "--kappa", "3.1", "--tau", "-2", "--omega", "1.5", "--nu", "0.25", "--length",
        "0.51", "--matrix",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows: [[f64; 3]; 3] = serde_json::from_value(v["material_rows"].clone()).unwrap();
    let rows_t: [[f64; 3]; 3] = serde_json::from_value(v["transported_rows"].clone()).unwrap();
    for i in 0..3 {
        for j in 0..3 {
            assert!(close(rows[i][j], p.material[(i, j)]));
            assert!(close(rows_t[i][j], p.transported[(i, j)]));
        }
    }
    assert!((v["motor_angle"].as_f64().unwrap() - 1.5 * 1.25).abs() < 1e-15);
    assert_eq!(v["inputs"]["tau"].as_f64().unwrap(), -2.0);

    // A closed case: a half circle (κ = π, τ = 0) ends at (2/π, 0, 0)·L, tangent −z.
    let out = cli(&[
        "helix",
        "--kappa",
        &PI.to_string(),
        "--tau",
        "0",
        "--omega",
        "0",
        "--matrix",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pos: Vec<f64> = serde_json::from_value(v["position"].clone()).unwrap();
    assert!((pos[0] - 2.0 / PI).abs() < 1e-15 && pos[1] == 0.0 && pos[2].abs() < 1e-15);
    assert!((v["material_rows"][2][2].as_f64().unwrap() + 1.0).abs() < 1e-15);
    assert_eq!(v["motor_angle"].as_f64().unwrap(), 0.0);
}

#[test]
fn cli_points_csv_roundtrips_with_17_digits_and_names_bad_lines() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("pts.csv");
    std::fs::write(&path, "kappa,tau,omega\n1,2,3\n0,0,0\n7.5,-1e-9,-4\n").unwrap();
    let out = cli(&["helix", "--points", path.to_str().unwrap(), "--nu", "0.3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "kappa,tau,omega,x,y,z,qw,qx,qy,qz,motor_angle"
    );
    let inputs = [(1.0, 2.0, 3.0), (0.0, 0.0, 0.0), (7.5, -1e-9, -4.0)];
    let mant_17 = |x: &str| {
        // d.dddddddddddddddde±x: 17 significant digits
        let mant = x.trim_start_matches('-').split('e').next().unwrap();
        assert_eq!(mant.len(), 18, "{x}");
    };
    for (line, &(k, t, w)) in lines.by_ref().zip(&inputs) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 11);
        f.iter().for_each(|x| mant_17(x));
        let v: Vec<f64> = f.iter().map(|x| x.parse().unwrap()).collect();
        let p = Helix::new(k, t, w).unwrap().end_pose(1.0, 0.3).unwrap();
        assert_eq!(&v[..3], &[k, t, w]);
        assert_eq!(&v[3..6], p.position.as_slice());
        assert!(v[6] >= 0.0);
        let r = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            v[6], v[7], v[8], v[9],
        ))
        .to_rotation_matrix();
        assert!((r.matrix() - p.material).amax() < 1e-14);
        assert_eq!(v[10], p.motor_angle);
    }
    assert!(lines.next().is_none());
    // --matrix: the material frame row-major, exactly.
    let out = cli(&[
        "helix",
        "--points",
        path.to_str().unwrap(),
        "--nu",
        "0.3",
        "--matrix",
    ]);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "kappa,tau,omega,x,y,z,r00,r01,r02,r10,r11,r12,r20,r21,r22,motor_angle"
    );
    for (line, &(k, t, w)) in lines.by_ref().zip(&inputs) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 16);
        f.iter().for_each(|x| mant_17(x));
        let v: Vec<f64> = f.iter().map(|x| x.parse().unwrap()).collect();
        let p = Helix::new(k, t, w).unwrap().end_pose(1.0, 0.3).unwrap();
        assert_eq!(&v[3..6], p.position.as_slice());
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(v[6 + 3 * i + j], p.material[(i, j)]);
            }
        }
        assert_eq!(v[15], p.motor_angle);
    }
    assert!(lines.next().is_none());

    // A bad value: the error names the file, the line and the field; exit code 2.
    std::fs::write(&path, "kappa,tau,omega\n1,2,3\n1,abc,3\n").unwrap();
    let out = cli(&["helix", "--points", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("pts.csv:3") && err.contains("tau"), "{err}");
    std::fs::write(&path, "kappa,tau,omega\n-1,2,3\n").unwrap();
    let err = String::from_utf8_lossy(&cli(&["helix", "--points", path.to_str().unwrap()]).stderr)
        .into_owned();
    assert!(err.contains("pts.csv:2") && err.contains("kappa"), "{err}");
    std::fs::write(&path, "kappa,omega\n1,3\n").unwrap();
    let err = String::from_utf8_lossy(&cli(&["helix", "--points", path.to_str().unwrap()]).stderr)
        .into_owned();
    assert!(err.contains("tau"), "{err}");
    // Bad scalar flags.
    let out = cli(&[
        "helix", "--kappa", "1", "--tau", "0", "--omega", "0", "--nu", "0.7",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nu"));
    let out = cli(&[
        "helix", "--kappa", "1", "--tau", "0", "--omega", "0", "--length", "-1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("length"));
    let out = cli(&["helix", "--kappa", "nan", "--tau", "0", "--omega", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("kappa"));
}

// ---------------------------------------------------------------------------------------------
// Direction sets: reading errors name the line.

#[test]
fn direction_csv_errors_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("d.csv");
    std::fs::write(&path, "dir_kappa,dir_tau,dir_omega\n1,0,0\n0,0,0\n").unwrap();
    let e = helixreach::directions::read_csv(&path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("d.csv:3"), "{e}");
    std::fs::write(&path, "dir_kappa,dir_tau,dir_omega\n3,4,0\n").unwrap();
    let d = helixreach::directions::read_csv(&path).unwrap();
    assert!((d[0].kappa - 0.6).abs() < 1e-16 && (d[0].tau - 0.8).abs() < 1e-16);
}
