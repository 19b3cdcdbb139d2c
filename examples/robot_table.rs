//! The table of docs/ROBOTS.md: for each vendored arm (`tests/data/robots/`), its links, its
//! collision elements (URDF primitives and meshes), the meshes' triangles, the convex hulls
//! and fitted capsules, the largest capsule gap (with the link it belongs to and the gap's
//! resolution), and for the self pairs checked (every pair not joined by a joint, and those
//! left by the arm's vendored MoveIt SRDF where it has one) how many configurations are in
//! self-contact under the `hull` and the `primitives` models (10,000 seeded random in-limit
//! configurations; the capsules never miss a hull contact, see tests/robot_primitives.rs).
//! Timings are not here: `cargo bench --bench self_collision`.
//!
//! Run: `cargo run --release --example robot_table`

#[path = "../tests/common/robots.rs"]
mod robots;

use helixreach::math::Real;
use helixreach::robot::collision::{CollisionKind, CollisionSettings};
use helixreach::robot::{CollisionModel, DisabledPairs};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The vendored SRDF of an arm (under `example-robot-data/robots/`), if it has one.
fn srdf_of(arm: &str) -> Option<&'static str> {
    match arm {
        "ur5" => Some("ur_description/srdf/ur5.srdf"),
        "panda" => Some("panda_description/srdf/panda.srdf"),
        "xarm7" => Some("xarm_description/srdf/xarm7.srdf"),
        "kinova" => Some("kinova_description/srdf/kinova.srdf"),
        "baxter_right" => Some("baxter_description/srdf/baxter_manipulation.srdf"),
        _ => None,
    }
}

fn main() {
    const N: usize = 10_000;
    println!(
        "| arm | dof | links | URDF primitives | meshes | triangles | hulls (vertices) | capsules | largest capsule gap (m) | all pairs: count, in contact hulls / capsules | SRDF pairs: count, in contact hulls / capsules |"
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
        let contact = |disabled: &DisabledPairs| -> String {
            let model = |kind| {
                CollisionModel::with_settings(
                    &m,
                    disabled,
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
            format!(
                "{}, {:.1} % / {:.1} %",
                hull.n_self_pairs(),
                pct(in_hull),
                pct(in_prim)
            )
        };
        let all = contact(&DisabledPairs::for_model(&m).unwrap());
        let srdf = srdf_of(arm.name)
            .map(|rel| {
                let p = robots::package_dir()
                    .join("example-robot-data/robots")
                    .join(rel);
                let d = DisabledPairs::for_model(&m)
                    .unwrap()
                    .merged(&DisabledPairs::from_srdf_file(&p).unwrap());
                format!("{} ({rel})", contact(&d))
            })
            .unwrap_or_else(|| "no SRDF".into());
        println!(
            "| {} | {} | {} | {prims} | {meshes} | {triangles} | {meshes} ({hull_vertices}) | {meshes} | {gap:.4} ({gap_link}; ± {res:.0e}) | {all} | {srdf} |",
            arm.name,
            m.dof(),
            links.len(),
        );
    }
}
