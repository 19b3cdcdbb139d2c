//! The table of docs/ROBOTS.md: for each vendored arm (`tests/data/robots/`), its links, its
//! collision elements (URDF primitives and meshes), the meshes' triangles, the convex hulls
//! and fitted capsules, the largest capsule gap (with the link it belongs to and the gap's
//! resolution), the self pairs checked, and how often the `primitives` model reports a
//! self-contact that the hulls do not have (10,000 seeded random in-limit configurations;
//! the hulls' contacts are always reported, see tests/robot_primitives.rs). Timings are not
//! here: `cargo bench --bench self_collision`.
//!
//! Run: `cargo run --release --example robot_table`

#[path = "../tests/common/robots.rs"]
mod robots;

use helixreach::math::Real;
use helixreach::robot::collision::{CollisionKind, CollisionSettings};
use helixreach::robot::{CollisionModel, DisabledPairs};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn main() {
    const N: usize = 10_000;
    println!(
        "| arm | dof | links | URDF primitives | meshes | triangles | hulls (vertices) | capsules | largest capsule gap (m) | self pairs | configurations in contact: hulls / capsules |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for arm in &robots::ARMS {
        let m = robots::load(arm);
        let links = m.links();
        let prims: usize = links.iter().map(|l| l.collision.len()).sum();
        let meshes: usize = links.iter().map(|l| l.meshes.len()).sum();
        let triangles: usize = links
            .iter()
            .flat_map(|l| &l.meshes)
            .map(|g| g.mesh.triangles.len())
            .sum();
        let hull_vertices: usize = links
            .iter()
            .flat_map(|l| &l.meshes)
            .map(|g| g.mesh.hull_points.len())
            .sum();
        let (gap, res, gap_link) = links
            .iter()
            .flat_map(|l| l.meshes.iter().map(move |g| (g.mesh.capsule, &l.name)))
            .max_by(|a, b| a.0.gap.total_cmp(&b.0.gap))
            .map(|(c, l)| (c.gap, c.gap_resolution, l.clone()))
            .unwrap_or((0.0, 0.0, String::new()));
        let model = |kind| {
            CollisionModel::with_settings(
                &m,
                &DisabledPairs::for_model(&m).unwrap(),
                &[],
                &CollisionSettings {
                    kind,
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let (hull, prim) = (model(CollisionKind::Hull), model(CollisionKind::Primitives));
        assert_eq!(prim.mesh_capsules().len(), meshes);
        let (mut wh, mut wp) = (hull.workspace(), prim.workspace());
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let (mut in_hull, mut in_prim) = (0usize, 0usize);
        for _ in 0..N {
            let q = m.random_config(&mut rng);
            let q = &q[..m.dof()];
            let h = hull.check(q, &mut wh, None).is_some();
            let p = prim.check(q, &mut wp, None).is_some();
            assert!(p || !h, "{}: the capsules missed a hull contact", arm.name);
            in_hull += usize::from(h);
            in_prim += usize::from(p);
        }
        let pct = |k: usize| 100.0 * k as Real / N as Real;
        println!(
            "| {} | {} | {} | {prims} | {meshes} | {triangles} | {meshes} ({hull_vertices}) | {meshes} | {gap:.4} ({gap_link}; ± {res:.0e}) | {} | {:.1} % / {:.1} % |",
            arm.name,
            m.dof(),
            links.len(),
            hull.n_self_pairs(),
            pct(in_hull),
            pct(in_prim),
        );
    }
}
