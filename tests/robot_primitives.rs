//! The primitive layer of mesh collision (`helixreach::robot::collision::fit`) on the vendored
//! arms (UR3/5/10, Panda, xArm7, Kinova Jaco2): every fitted capsule contains its mesh, the
//! stated gap agrees with a brute-force estimate, the primitive models never report free where
//! the hulls touch, padding grows the capsules by exactly its amount, and a rig's
//! `collision_model` is validated.

mod common;

use common::robots::{self, ARMS};
use helixreach::math::{Real, Vec3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

// ---------------------------------------------------------------------------------------------
// An independent point-to-hull distance: the hull's triangles, a point-triangle closest point
// (Ericson, Real-Time Collision Detection §5.1.5), inside by the side of every face plane.

/// The closest point of triangle `abc` to `p`.
fn closest_on_triangle(p: &Vec3, a: &Vec3, b: &Vec3, c: &Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// A convex hull as triangles, with a point inside (the vertex centroid).
struct HullTris {
    tris: Vec<[Vec3; 3]>,
    inner: Vec3,
}

impl HullTris {
    fn new(h: &parry3d_f64::shape::ConvexPolyhedron) -> HullTris {
        let (v, idx) = h.to_trimesh();
        let v: Vec<Vec3> = v.iter().map(|p| p.coords).collect();
        let inner = v.iter().sum::<Vec3>() / v.len() as Real;
        let tris = idx
            .iter()
            .map(|t| [v[t[0] as usize], v[t[1] as usize], v[t[2] as usize]])
            .collect();
        HullTris { tris, inner }
    }

    /// Distance from `p` to the solid hull (0 inside).
    fn distance(&self, p: &Vec3) -> Real {
        let inside = self.tris.iter().all(|[a, b, c]| {
            let n = (b - a).cross(&(c - a));
            // Same side of the face's plane as the interior point (or on it).
            n.dot(&(p - a)) * n.dot(&(self.inner - a)) >= 0.0
        });
        if inside {
            return 0.0;
        }
        self.tris
            .iter()
            .map(|[a, b, c]| (p - closest_on_triangle(p, a, b, c)).norm())
            .fold(Real::MAX, Real::min)
    }
}

/// A uniformly random point of the surface of the capsule (`a`, `b`, `r`).
fn capsule_surface_point(rng: &mut ChaCha8Rng, a: &Vec3, b: &Vec3, r: Real) -> Vec3 {
    let d = b - a;
    let len = d.norm();
    let unit = || {
        // Uniform on the sphere (normalised Gaussian via Box–Muller).
        let g = |rng: &mut ChaCha8Rng| {
            let (u1, u2): (Real, Real) = (rng.random_range(1e-300..1.0), rng.random());
            (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
        };
        move |rng: &mut ChaCha8Rng| Vec3::new(g(rng), g(rng), g(rng)).normalize()
    };
    let sphere_area = 4.0 * std::f64::consts::PI * r * r;
    let side_area = std::f64::consts::TAU * r * len;
    let n = unit()(rng);
    if len == 0.0 || rng.random::<Real>() * (sphere_area + side_area) < sphere_area {
        // On the caps: a point of a sphere, on its outer half.
        let dir = if len > 0.0 { d / len } else { Vec3::z() };
        let end = if n.dot(&dir) >= 0.0 { b } else { a };
        end + n * r
    } else {
        let dir = d / len;
        let radial = (n - dir * n.dot(&dir)).normalize();
        a + d * rng.random::<Real>() + radial * r
    }
}

/// Every vertex of every mesh of every vendored arm lies inside the mesh's fitted capsule (so
/// the convex hull does: a capsule is convex); the stated gap is ≥ 0 and agrees with a brute
/// force over 20,000 random points of the capsule's surface and an independent point–hull
/// distance: the brute force never exceeds `gap + gap_resolution` (the gap is an upper bound
/// up to its resolution) and falls short of `gap` by at most 0.5 mm (the points are a few
/// millimetres apart on these capsules, and the distance to the hull varies slowly near its
/// maximum, which lies on a cap; seen: at most 0.07 mm short).
#[test]
fn every_mesh_vertex_is_inside_its_capsule_and_the_gap_matches_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut n_meshes = 0;
    for arm in &ARMS {
        let m = robots::load(arm);
        let mut seen = std::collections::HashSet::new();
        for l in m.links() {
            for g in &l.meshes {
                if !seen.insert(g.mesh.file.clone()) {
                    continue;
                }
                n_meshes += 1;
                let mesh = &g.mesh;
                let c = mesh.capsule;
                let what = format!("{} {}", arm.name, mesh.file.display());
                assert!(c.radius.is_finite() && c.radius > 0.0, "{what}: {c:?}");
                // Containment: every mesh vertex and every hull vertex.
                let worst = mesh
                    .vertices
                    .iter()
                    .chain(&mesh.hull_points)
                    .map(|p| {
                        // Distance to the segment, by sampling-free closed form written here.
                        let d = c.b - c.a;
                        let t = if d.norm_squared() > 0.0 {
                            ((p - c.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
                        } else {
                            0.0
                        };
                        (p - (c.a + d * t)).norm() - c.radius
                    })
                    .fold(Real::MIN, Real::max);
                assert!(worst <= 1e-9, "{what}: a vertex {worst:e} m outside");
                // The gap.
                assert!(c.gap >= 0.0 && c.gap_resolution >= 0.0, "{what}: {c:?}");
                let hull = HullTris::new(mesh.hull_polyhedron());
                let brute = (0..20_000)
                    .map(|_| hull.distance(&capsule_surface_point(&mut rng, &c.a, &c.b, c.radius)))
                    .fold(0.0, Real::max);
                eprintln!(
                    "{what}: radius {:.4} half-length {:.4} gap {:.5} ± {:.1e}, brute force {brute:.5}",
                    c.radius,
                    c.half_length(),
                    c.gap,
                    c.gap_resolution
                );
                assert!(
                    brute <= c.gap + c.gap_resolution + 1e-9,
                    "{what}: brute force {brute} above the stated gap {} + {}",
                    c.gap,
                    c.gap_resolution
                );
                assert!(
                    brute >= c.gap - 0.5e-3,
                    "{what}: brute force {brute} far below the stated gap {}",
                    c.gap
                );
            }
        }
    }
    assert!(n_meshes >= 30, "{n_meshes} meshes");
}

// ---------------------------------------------------------------------------------------------
// The three collision models on random configurations.

use helixreach::robot::collision::{CollisionKind, CollisionSettings, RodGeometry};
use helixreach::robot::{CollisionModel, DisabledPairs, RobotModel};

fn model(m: &RobotModel, kind: CollisionKind, padding: Real) -> CollisionModel {
    CollisionModel::with_settings(
        m,
        &DisabledPairs::default(),
        &[],
        &CollisionSettings {
            padding,
            link_padding: Vec::new(),
            kind,
        },
    )
    .unwrap()
}

/// On 500 seeded random configurations per arm (padding 0 and 1 cm): every self-contact link
/// pair of the hull model is one of the primitives model (the capsules contain the hulls), and
/// `primitives_then_hull` reports exactly the hull model's pairs and first hit; a random rod
/// near the arm likewise. The hull model's answer is checked against parry alone too.
#[test]
fn primitives_never_miss_a_hull_contact_and_the_broad_phase_changes_nothing() {
    for arm in &ARMS {
        let m = robots::load(arm);
        for pad in [0.0, 0.01] {
            let hull = model(&m, CollisionKind::Hull, pad);
            let prim = model(&m, CollisionKind::Primitives, pad);
            let both = model(&m, CollisionKind::PrimitivesThenHull, pad);
            let (mut wh, mut wp, mut wb) = (hull.workspace(), prim.workspace(), both.workspace());
            let mut rng = ChaCha8Rng::seed_from_u64(17);
            let (mut hull_hits, mut prim_extra, mut rod_hits) = (0usize, 0usize, 0usize);
            for _ in 0..500 {
                let q = m.random_config(&mut rng);
                let q = &q[..m.dof()];
                hull.update(q, &mut wh);
                prim.update(q, &mut wp);
                both.update(q, &mut wb);
                let h = hull.self_collisions(&wh);
                let p = prim.self_collisions(&wp);
                let b = both.self_collisions(&wb);
                let mut reference = hull.self_collision_parry(&wh);
                reference.dedup();
                assert_eq!(h, reference, "{}: hull model vs parry at {q:?}", arm.name);
                for pair in &h {
                    assert!(
                        p.contains(pair),
                        "{} pad {pad}: hulls of {} and {} touch at {q:?}, primitives say free",
                        arm.name,
                        m.links()[pair.0].name,
                        m.links()[pair.1].name
                    );
                }
                assert_eq!(
                    b, h,
                    "{} pad {pad}: primitives_then_hull at {q:?}",
                    arm.name
                );
                assert_eq!(
                    both.self_collision(&wb),
                    hull.self_collision(&wh),
                    "{} pad {pad}: first hit at {q:?}",
                    arm.name
                );
                hull_hits += h.len();
                prim_extra += p.len() - h.len();
                // A rod from near a random link to the tool, bulging sideways.
                let frames = hull.link_frames(&wh).to_vec();
                let link = rng.random_range(0..frames.len());
                let jitter = |rng: &mut ChaCha8Rng, s: Real| {
                    Vec3::new(
                        rng.random_range(-s..s),
                        rng.random_range(-s..s),
                        rng.random_range(-s..s),
                    )
                };
                let start = frames[link].pos + jitter(&mut rng, 0.2);
                let end = m.tool_pose(q).unwrap().pos;
                let bulge = jitter(&mut rng, 0.3);
                let nodes: Vec<Vec3> = (0..=16)
                    .map(|i| {
                        let t = i as Real / 16.0;
                        start + (end - start) * t + bulge * (4.0 * t * (1.0 - t))
                    })
                    .collect();
                let rod = RodGeometry {
                    nodes: &nodes,
                    radius: 0.004,
                    ignore_near_clamp: 0.0,
                    ignore_near_tool: 0.05,
                    against_scene: false,
                };
                let rh = hull.rod_collision(&wh, &rod);
                assert_eq!(
                    both.rod_collision(&wb, &rod),
                    rh,
                    "{} pad {pad}: rod at {q:?}",
                    arm.name
                );
                if rh.is_some() {
                    rod_hits += 1;
                    assert!(prim.rod_collision(&wp, &rod).is_some(), "{}: rod", arm.name);
                }
            }
            eprintln!(
                "{} pad {pad}: {hull_hits} hull contact pairs, {prim_extra} extra primitive pairs, {rod_hits} rod hits in 500 configurations",
                arm.name
            );
            assert!(
                hull_hits > 0 && rod_hits > 0,
                "{}: nothing touched",
                arm.name
            );
        }
    }
}

/// Padding grows every fitted capsule's radius by exactly the link's padding (global and per
/// link) and nothing else; and under `primitives` with padding p on every link, a
/// configuration is in self-contact exactly when the unpadded capsules are within 2p (the
/// unpadded model's clearance as the reference), on random Panda configurations.
#[test]
fn padding_grows_each_capsule_by_exactly_its_padding() {
    let arm = ARMS.iter().find(|a| a.name == "panda").unwrap();
    let m = robots::load(arm);
    let plain = model(&m, CollisionKind::Primitives, 0.0);
    let p = 0.015;
    let padded = model(&m, CollisionKind::Primitives, p);
    let hand = m.link_index("panda_hand").unwrap();
    let per_link = CollisionModel::with_settings(
        &m,
        &DisabledPairs::default(),
        &[],
        &CollisionSettings {
            padding: p,
            link_padding: vec![("panda_hand".into(), 0.04)],
            kind: CollisionKind::PrimitivesThenHull,
        },
    )
    .unwrap();
    let (c0, c1, c2) = (
        plain.mesh_capsules(),
        padded.mesh_capsules(),
        per_link.mesh_capsules(),
    );
    assert!(!c0.is_empty() && c0.len() == c1.len() && c0.len() == c2.len());
    for ((a, b), c) in c0.iter().zip(c1).zip(c2) {
        assert_eq!((a.link, a.a, a.b), (b.link, b.a, b.b));
        assert_eq!(b.radius, a.radius + p);
        let want = if a.link == hand { 0.04 } else { p };
        assert_eq!(c.radius, a.radius + want, "{}", m.links()[a.link].name);
    }
    assert!(c0.iter().any(|c| c.link == hand));
    // Behaviour: contact ⇔ unpadded capsules within 2p.
    let (mut w0, mut w1) = (plain.workspace(), padded.workspace());
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (mut checked, mut only_padded) = (0, 0);
    for _ in 0..500 {
        let q = m.random_config(&mut rng);
        let q = &q[..m.dof()];
        plain.update(q, &mut w0);
        padded.update(q, &mut w1);
        let d = plain.self_clearance(&w0).unwrap().distance;
        if (d - 2.0 * p).abs() > 1e-9 {
            checked += 1;
            let hit = padded.self_collision(&w1).is_some();
            assert_eq!(hit, d <= 2.0 * p, "distance {d} at {q:?}");
            only_padded += usize::from(hit && plain.self_collision(&w0).is_none());
        }
    }
    assert!(checked > 450 && only_padded > 0, "{checked} {only_padded}");
}

// ---------------------------------------------------------------------------------------------
// The rig's `collision_model`.

use helixreach::planning::rig::{Rig, EMBEDDED_RIGS};

/// A rig for the vendored Panda with `extra` lines in `[robot]`, written in `dir`.
fn panda_rig(dir: &std::path::Path, extra: &str) -> std::path::PathBuf {
    let seed = EMBEDDED_RIGS
        .iter()
        .find(|(n, _)| *n == "sawyer-seed")
        .unwrap()
        .1;
    let arm = ARMS.iter().find(|a| a.name == "panda").unwrap();
    let robot = format!(
        "[robot]\nurdf = {:?}\ntip_link = \"panda_hand_tcp\"\npackage_paths = [{:?}]\n{extra}\n\n",
        robots::urdf(arm).display().to_string(),
        robots::package_dir().display().to_string()
    );
    let start = seed.find("[robot]").unwrap();
    let end = start + seed[start..].find("[tool]").unwrap();
    let text = format!("{}{robot}{}", &seed[..start], &seed[end..]);
    let p = dir.join("panda-rig.toml");
    std::fs::write(&p, text).unwrap();
    p
}

/// `collision_model` selects the model (the default is `primitives_then_hull`), the collision
/// summary names it, and a value that is not a model is refused naming the file, the field and
/// the value.
#[test]
fn the_rig_chooses_the_collision_model_and_refuses_an_unknown_one() {
    let dir = tempfile::tempdir().unwrap();
    for (extra, kind) in [
        ("", CollisionKind::PrimitivesThenHull),
        ("collision_model = \"hull\"", CollisionKind::Hull),
        (
            "collision_model = \"primitives\"",
            CollisionKind::Primitives,
        ),
        (
            "collision_model = \"primitives_then_hull\"",
            CollisionKind::PrimitivesThenHull,
        ),
    ] {
        let p = panda_rig(dir.path(), extra);
        let rig = Rig::load(p.to_str().unwrap()).unwrap();
        assert_eq!(rig.robot.collision.kind, kind, "{extra}");
        let src = p.display().to_string();
        let m = rig.robot.load_model(&src).unwrap();
        let cm = rig.robot.collision_model(&m, &[], &src).unwrap();
        assert_eq!(cm.kind(), kind);
        let s = cm.summary();
        assert!(
            s.contains(&format!("collision_model {}", kind.name())),
            "{s}"
        );
    }
    for bad in ["\"capsules\"", "\"Hull\"", "\"\""] {
        let p = panda_rig(dir.path(), &format!("collision_model = {bad}"));
        let e = Rig::load(p.to_str().unwrap()).unwrap_err().to_string();
        assert!(
            e.contains("panda-rig.toml")
                && e.contains("robot.collision_model")
                && e.contains(bad)
                && e.contains("primitives_then_hull"),
            "{e}"
        );
    }
    // Not a string.
    let p = panda_rig(dir.path(), "collision_model = 3");
    let e = Rig::load(p.to_str().unwrap()).unwrap_err().to_string();
    assert!(e.contains("collision_model"), "{e}");
}
