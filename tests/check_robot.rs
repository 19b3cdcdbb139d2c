//! `helixreach check --robot URDF`: limits and self-collision of a joint trajectory without a
//! rig, on the vendored UR5 (all of whose links are meshes). The self-colliding configuration
//! is found by brute force and its colliding link pairs taken from parry's exact
//! mesh-versus-mesh test (not from the hull model the check uses): the per-row CSV must say
//! `self_collision` 1 and list exactly those pairs, 0 and nothing on a free configuration, and
//! the command exits non-zero (the collision bit) when any row fails.

mod common;

use common::robots::{self, ARMS};
use helixreach::math::Real;
use helixreach::planning::rig::RobotSpec;
use helixreach::robot::{CollisionModel, RobotModel};
use parry3d_f64::query;
use parry3d_f64::shape::TriMesh;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

fn helixreach(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .expect("run helixreach")
}

fn ur5() -> &'static robots::Arm {
    ARMS.iter().find(|a| a.name == "ur5").unwrap()
}

/// The UR5 as `check --robot` loads it (no padding, its own never-colliding list).
fn spec() -> RobotSpec {
    RobotSpec {
        urdf: robots::urdf(ur5()).display().to_string(),
        dir: ".".into(),
        tip_link: ur5().tip.into(),
        package_paths: vec![robots::package_dir()],
        no_collision: Vec::new(),
        collision: Default::default(),
        srdf: None,
    }
}

/// Link pairs whose exact meshes intersect at `q`, among the pairs `cm` checks (names, the
/// earlier link first); `None` when a checked pair has a link without a mesh that `cm` reports.
fn mesh_pairs(
    m: &RobotModel,
    cm: &CollisionModel,
    tm: &[Vec<(helixreach::robot::Frame, TriMesh)>],
    q: &[Real],
) -> BTreeSet<String> {
    let mut ws = cm.workspace();
    cm.update(q, &mut ws);
    let frames = cm.link_frames(&ws).to_vec();
    let mut out = BTreeSet::new();
    for (a, b) in cm.self_pair_links() {
        let (a, b) = (a.min(b), a.max(b));
        let touch = tm[a].iter().any(|(oa, ta)| {
            tm[b].iter().any(|(ob, tb)| {
                let pa = frames[a].mul(oa).to_iso();
                let pb = frames[b].mul(ob).to_iso();
                query::intersection_test(&pa, ta, &pb, tb).unwrap()
            })
        });
        if touch {
            out.insert(format!("{}|{}", m.links()[a].name, m.links()[b].name));
        }
    }
    out
}

/// Link pairs the hull model finds colliding at `q` (names, the earlier link first).
fn hull_pairs(m: &RobotModel, cm: &CollisionModel, q: &[Real]) -> BTreeSet<String> {
    let mut ws = cm.workspace();
    cm.update(q, &mut ws);
    cm.self_collisions(&ws)
        .into_iter()
        .map(|(a, b)| format!("{}|{}", m.links()[a.min(b)].name, m.links()[a.max(b)].name))
        .collect()
}

fn write_rows(path: &Path, rows: &[&[Real]]) {
    let text: String = rows
        .iter()
        .map(|q| {
            q.iter()
                .map(|x| format!("{x:?}"))
                .collect::<Vec<_>>()
                .join(" ")
                + "\n"
        })
        .collect();
    std::fs::write(path, text).unwrap();
}

fn check(traj: &Path, out: &Path) -> Output {
    let urdf = robots::urdf(ur5());
    let pkg = robots::package_dir();
    helixreach(&[
        "check",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        ur5().tip,
        "--package-path",
        pkg.to_str().unwrap(),
        "--trajectory",
        traj.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

fn rows_of(csv: &Path) -> Vec<(u8, BTreeSet<String>)> {
    let mut rd = csv::Reader::from_path(csv).unwrap();
    let h = rd.headers().unwrap().clone();
    let col = |n: &str| h.iter().position(|c| c == n).unwrap();
    let (c1, c2) = (col("self_collision"), col("self_pairs"));
    rd.records()
        .map(|r| {
            let r = r.unwrap();
            let pairs = r[c2]
                .split(';')
                .filter(|s| !s.is_empty())
                .map(str::to_string)
                .collect();
            (r[c1].parse().unwrap(), pairs)
        })
        .collect()
}

#[test]
fn check_robot_reports_self_collision_rows_and_their_mesh_pairs() {
    let m = {
        let s = spec();
        s.load_model("test").unwrap()
    };
    let cm = spec().collision_model(&m, &[], "test").unwrap();
    let tm: Vec<Vec<_>> = m
        .links()
        .iter()
        .map(|l| {
            l.meshes
                .iter()
                .map(|g| (g.origin, g.mesh.trimesh().unwrap()))
                .collect()
        })
        .collect();
    // Brute force: the first random configuration whose hull pairs are exactly its mesh pairs
    // (non-empty), and the first free one.
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut hit, mut free) = (None, None);
    for _ in 0..20_000 {
        let q = m.random_config(&mut rng)[..m.dof()].to_vec();
        let hull = hull_pairs(&m, &cm, &q);
        if hull.is_empty() {
            // Hull ⊇ mesh: the meshes are free too (checked).
            assert!(mesh_pairs(&m, &cm, &tm, &q).is_empty());
            free.get_or_insert(q);
        } else if hit.is_none() {
            let mesh = mesh_pairs(&m, &cm, &tm, &q);
            if mesh == hull {
                hit = Some((q, mesh));
            }
        }
        if hit.is_some() && free.is_some() {
            break;
        }
    }
    let (q_hit, pairs) = hit.expect("no self-colliding UR5 configuration found");
    let q_free = free.expect("no free UR5 configuration found");
    eprintln!("colliding at {q_hit:?}: {pairs:?}");

    let dir = tempfile::tempdir().unwrap();
    // Free rows only: pass, exit 0, every row 0 with no pairs.
    let t_free = dir.path().join("free.txt");
    let o_free = dir.path().join("free.csv");
    write_rows(&t_free, &[&q_free, &q_free]);
    let o = check(&t_free, &o_free);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let rows = rows_of(&o_free);
    assert_eq!(rows.len(), 2);
    assert!(
        rows.iter().all(|(c, p)| *c == 0 && p.is_empty()),
        "{rows:?}"
    );

    // A colliding row between free ones: that row says 1 and exactly the mesh pairs; exit
    // 64 + the finding bits, the collision bit (2) among them.
    let t = dir.path().join("t.txt");
    let out = dir.path().join("rows.csv");
    write_rows(&t, &[&q_free, &q_hit, &q_free]);
    let o = check(&t, &out);
    let code = o.status.code().unwrap();
    assert!(
        code >= 64 && (code - 64) & 2 != 0,
        "exit {code}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let rows = rows_of(&out);
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[0], (0, BTreeSet::new()));
    assert_eq!(rows[1], (1, pairs));
    assert_eq!(rows[2], (0, BTreeSet::new()));
    let summary: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(summary["self_collisions"], 1, "{summary}");
}

#[test]
fn check_robot_refuses_a_rig_only_option_and_a_wrong_joint_count() {
    let dir = tempfile::tempdir().unwrap();
    let t = dir.path().join("t.txt");
    std::fs::write(&t, "0 0 0 0 0\n").unwrap();
    let out = dir.path().join("rows.csv");
    let o = check(&t, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("t.txt") && err.contains('5') && err.contains('6'),
        "{err}"
    );
    assert!(!out.exists());
    let urdf = robots::urdf(ur5());
    let o = helixreach(&[
        "check",
        "--robot",
        urdf.to_str().unwrap(),
        "--trajectory",
        t.to_str().unwrap(),
        "--direction",
        "1,1,1",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--direction"), "{err}");
}
