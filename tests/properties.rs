//! Property tests (proptest) of the invariants the module docs claim, each against an
//! independent reference: helix frames are rotations and the material frame differs from the
//! transported one by the twist ω/c about the tangent; directions are unit vectors with the sign
//! pattern of their input; the parallel transport is the rotation `exp(θ k̂)` about `a × b`; the
//! segment distance equals a dense brute-force minimum; the collision walk's boolean check and
//! clearance agree; and (feature `interop`) the compiled FK equals k's.

use helixreach::directions::Direction;
use helixreach::helix::Helix;
use helixreach::math::{parallel_transport, so3_exp, tol, twist_ratio, Mat3, Real, Vec3};
use helixreach::robot::collision::segment_distance_squared;
use helixreach::robot::{CollisionModel, RobotModel};
use proptest::prelude::*;

fn orthonormal_error(r: &Mat3) -> Real {
    (r.transpose() * r - Mat3::identity()).norm()
}

fn unit() -> impl Strategy<Value = Vec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
        .prop_filter("not near zero", |(x, y, z)| x * x + y * y + z * z > 1e-4)
        .prop_map(|(x, y, z)| Vec3::new(x, y, z).normalize())
}

fn point() -> impl Strategy<Value = Vec3> {
    (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn helix_frames_are_rotations_and_material_is_transported_turned_by_the_twist(
        kappa in 0.0..40.0f64, tau in -40.0..40.0f64, omega in -40.0..40.0f64,
        s in 0.0..1.0f64, nu in -0.5..0.5f64,
    ) {
        let h = Helix::new(kappa, tau, omega).unwrap();
        let c = twist_ratio(nu).unwrap();
        for f in [h.frenet_frame(s), h.transported_frame(s), h.material_frame(s, c)] {
            // Relative to the total turning (frames are exp of s·|w|).
            let scale = 1.0 + s * (kappa.hypot(tau) + (omega / c).abs());
            prop_assert!(orthonormal_error(&f) <= 50.0 * tol::FRAME_ORTHONORMAL * scale);
            prop_assert!((f.determinant() - 1.0).abs() <= 50.0 * tol::FRAME_ORTHONORMAL * scale);
        }
        // Material = transported turned by (ω/c)·s about the common tangent d3.
        let (q, m) = (h.transported_frame(s), h.material_frame(s, c));
        prop_assert!((q.column(2) - m.column(2)).norm() < 1e-12);
        let turned = q * so3_exp(&(Vec3::z() * (omega / c) * s));
        let scale = 1.0 + s * (kappa.hypot(tau) + (omega / c).abs());
        prop_assert!((turned - m).norm() <= 1e-12 * scale, "{:e}", (turned - m).norm());
    }

    #[test]
    fn directions_are_unit_with_the_input_signs(
        k in 0.0..1e6f64, t in -1e6..1e6f64, w in -1e6..1e6f64, e in -300i32..300,
    ) {
        let f = 10f64.powi(e);
        let (k, t, w) = (k * f, t * f, w * f);
        prop_assume!(k > 0.0 || t != 0.0 || w != 0.0);
        let d = Direction::new(k, t, w).unwrap();
        prop_assert!((d.kappa.powi(2) + d.tau.powi(2) + d.omega.powi(2) - 1.0).abs() < 4.0 * Real::EPSILON);
        prop_assert!(d.kappa >= 0.0);
        if t != 0.0 {
            prop_assert_eq!(d.tau.signum(), t.signum());
        }
        if w != 0.0 {
            prop_assert_eq!(d.omega.signum(), w.signum());
        }
        // Scaling the input does not move the direction.
        let d2 = Direction::new(3.0 * k, 3.0 * t, 3.0 * w);
        if let Ok(d2) = d2 {
            prop_assert!((d2.kappa - d.kappa).abs() + (d2.tau - d.tau).abs() + (d2.omega - d.omega).abs() < 1e-15);
        }
    }

    #[test]
    fn parallel_transport_is_the_rotation_about_a_cross_b(a in unit(), b in unit(), d in point()) {
        let k = a.cross(&b);
        let s = k.norm();
        prop_assume!(s > 1e-6 || a.dot(&b) > 0.0);
        // Independent reference: the rotation matrix exp(θ k̂), θ = atan2(|a×b|, a·b).
        let r = if s > 0.0 { so3_exp(&(k / s * s.atan2(a.dot(&b)))) } else { Mat3::identity() };
        let p = parallel_transport(&d, &a, &b, &Vec3::x());
        prop_assert!((p - r * d).norm() <= 1e-12 * (1.0 + d.norm()), "{:e}", (p - r * d).norm());
        prop_assert!((parallel_transport(&a, &a, &b, &Vec3::x()) - b).norm() < 1e-12);
        prop_assert!((p.norm() - d.norm()).abs() < 1e-12);
    }

    #[test]
    fn segment_distance_equals_a_dense_brute_force_minimum(
        p1 in point(), q1 in point(), p2 in point(), q2 in point(),
    ) {
        let d = segment_distance_squared(&p1, &q1, &p2, &q2).sqrt();
        // Dense reference: the minimum over a 400×400 grid of parameter pairs is an upper
        // bound that is at most one grid step (times the segment lengths) above the truth.
        let n = 400;
        let mut best = Real::MAX;
        for i in 0..=n {
            let x = p1 + (q1 - p1) * (i as Real / n as Real);
            for j in 0..=n {
                let y = p2 + (q2 - p2) * (j as Real / n as Real);
                best = best.min((x - y).norm());
            }
        }
        let slack = ((q1 - p1).norm() + (q2 - p2).norm()) / n as Real;
        prop_assert!(d <= best + 1e-12, "closed form {d} above the grid minimum {best}");
        prop_assert!(d >= best - slack - 1e-12, "closed form {d} far below the grid minimum {best}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// The one pair walk serves both queries: a configuration is collision-free exactly when
    /// its clearance is positive, and a reported contact pair has distance 0.
    #[test]
    fn collision_check_and_clearance_agree(seed in any::<u64>()) {
        use rand::SeedableRng;
        let m = RobotModel::load("sawyer", None).unwrap();
        let cm = CollisionModel::for_model(&m).unwrap();
        let mut ws = cm.workspace();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..20 {
            let q = m.random_config(&mut rng);
            let q = &q[..m.dof()];
            let hit = cm.check(q, &mut ws, None);
            let near = cm.clearance(q, &mut ws, None).unwrap();
            match hit {
                Some(c) => prop_assert_eq!(near.distance, 0.0, "hit {:?} but clearance {:?}", c, near),
                None => prop_assert!(near.distance > 0.0, "no hit but clearance {:?}", near),
            }
        }
    }
}

#[cfg(feature = "interop")]
proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// The compiled chain equals k's FK (an independent implementation) at any in-limit
    /// configuration of every built-in robot.
    #[test]
    fn compiled_fk_equals_the_k_chain(seed in any::<u64>(), which in 0usize..3) {
        use rand::SeedableRng;
        let name = ["sawyer", "panda", "iiwa14"][which];
        let m = RobotModel::load(name, None).unwrap();
        let k = helixreach::robot::k_bridge::KRobot::new(&m).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let q = m.random_config(&mut rng);
        let q = &q[..m.dof()];
        let (a, b) = (m.chain().tool_pose(q), k.tool_pose(q));
        prop_assert!((a.pos - b.pos).norm() <= 1e-12 && (a.rot - b.rot).abs().max() <= 1e-12);
    }
}
