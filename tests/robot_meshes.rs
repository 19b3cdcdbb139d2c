//! The real robot descriptions of `tests/data/robots` (UR3/5/10, Panda, xArm7, Kinova Jaco2):
//! every collision mesh loads, FK agrees with k on every link, and the convex-hull collision
//! model never reports free where the exact meshes touch (parry's mesh-versus-mesh test).

mod common;

use common::robots::{self, ARMS};
use helixreach::math::Real;
use helixreach::robot::collision::CollisionModel;
use helixreach::robot::k_bridge::KRobot;
use helixreach::robot::{DisabledPairs, Frame, RobotModel};
use parry3d_f64::query;
use parry3d_f64::shape::TriMesh;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Every arm loads with every collision element of its URDF (none dropped), each mesh with
/// triangles and a hull.
#[test]
fn every_arm_loads_with_all_its_collision_meshes() {
    for arm in &ARMS {
        let m = robots::load(arm);
        assert_eq!(m.dof(), arm.dof, "{}", arm.name);
        let n: usize = m
            .links()
            .iter()
            .map(|l| l.collision.len() + l.meshes.len())
            .sum();
        assert_eq!(n, arm.elements, "{}: collision elements", arm.name);
        // The URDF's own count of <collision> elements (independent of the loader).
        let text = std::fs::read_to_string(robots::urdf(arm)).unwrap();
        assert_eq!(text.matches("<collision").count(), n, "{}", arm.name);
        for l in m.links() {
            for g in &l.meshes {
                assert!(!g.mesh.triangles.is_empty() && g.mesh.hull_points.len() >= 4);
            }
        }
        assert!(m.ignored_geometry().is_empty());
        // The URDF, its (absent) pair list and each mesh file are the model's sources.
        let meshes: std::collections::HashSet<_> = m
            .links()
            .iter()
            .flat_map(|l| l.meshes.iter().map(|g| g.mesh.file.clone()))
            .collect();
        assert_eq!(m.sources().len(), 2 + meshes.len(), "{}", arm.name);
    }
}

/// FK of every link agrees with k (an independent implementation) to 1e-12 on 1,000 random
/// in-limit configurations per arm (mimic and prismatic gripper joints frozen in both).
#[test]
fn fk_of_every_link_agrees_with_k() {
    for arm in &ARMS {
        let m = robots::load(arm);
        let k = KRobot::new(&m).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut buf = vec![Frame::identity(); m.chain().n_links()];
        let mut worst: Real = 0.0;
        for _ in 0..1000 {
            let q = m.random_config(&mut rng);
            let q = &q[..m.dof()];
            m.chain().link_frames(q, &mut buf);
            let kf = k.link_frames(q);
            for (a, b) in buf.iter().zip(&kf) {
                worst = worst
                    .max((a.pos - b.pos).norm())
                    .max((a.rot - b.rot).abs().max());
            }
            let t = m.chain().tool_pose(q);
            let kt = k.tool_pose(q);
            worst = worst
                .max((t.pos - kt.pos).norm())
                .max((t.rot - kt.rot).abs().max());
        }
        assert!(worst <= 1e-12, "{}: FK vs k differs by {worst:e}", arm.name);
    }
}

/// The meshes of a link, posed: one parry triangle mesh per mesh element.
fn trimeshes(m: &RobotModel) -> Vec<Vec<(Frame, TriMesh)>> {
    m.links()
        .iter()
        .map(|l| {
            l.meshes
                .iter()
                .map(|g| (g.origin, g.mesh.trimesh().unwrap()))
                .collect()
        })
        .collect()
}

/// On random configurations of each arm, the hull model's self-collision agrees with parry's
/// exact mesh-versus-mesh test on every checked link pair: a mesh contact is never reported
/// free (hull ⊇ mesh); the hull's extra contacts are counted.
#[test]
fn hull_self_collision_never_misses_a_mesh_contact() {
    const N: usize = 2000;
    for arm in &ARMS {
        let m = robots::load(arm);
        let cm = CollisionModel::new(&m, &DisabledPairs::default(), &[]).unwrap();
        let mut ws = cm.workspace();
        let tm = trimeshes(&m);
        let mut pairs = cm.self_pair_links();
        pairs
            .iter_mut()
            .for_each(|p| *p = (p.0.min(p.1), p.0.max(p.1)));
        pairs.sort_unstable();
        pairs.dedup();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut mesh_hits, mut hull_extra) = (0usize, 0usize);
        // Configurations where the hulls of two links touch while their meshes are ≥ 3 cm apart.
        let mut far_extra = 0usize;
        for _ in 0..N {
            let mut far = false;
            let q = m.random_config(&mut rng);
            cm.update(&q[..m.dof()], &mut ws);
            let frames = cm.link_frames(&ws).to_vec();
            let mut hull: Vec<(usize, usize)> = cm
                .self_collisions(&ws)
                .into_iter()
                .map(|(a, b)| (a.min(b), a.max(b)))
                .collect();
            hull.sort_unstable();
            for &(a, b) in &pairs {
                let mut touch = false;
                'outer: for (oa, ta) in &tm[a] {
                    for (ob, tb) in &tm[b] {
                        let pa = frames[a].mul(oa).to_iso();
                        let pb = frames[b].mul(ob).to_iso();
                        if query::intersection_test(&pa, ta, &pb, tb).unwrap() {
                            touch = true;
                            break 'outer;
                        }
                    }
                }
                let h = hull.binary_search(&(a, b)).is_ok();
                assert!(
                    h || !touch,
                    "{}: meshes of {} and {} touch at q = {:?}, hull model says free",
                    arm.name,
                    m.links()[a].name,
                    m.links()[b].name,
                    &q[..m.dof()]
                );
                mesh_hits += usize::from(touch);
                hull_extra += usize::from(h && !touch);
                // Only links whose geometry is all meshes: a primitive (a UR's `ee_link` box) is
                // checked exactly, not as a hull.
                let all_mesh = |l: usize| m.links()[l].collision.is_empty();
                if h && !touch && !far && all_mesh(a) && all_mesh(b) {
                    // Far: every mesh pair is more than 3 cm apart (parry's closest points
                    // with a 3 cm cut-off: `Disjoint` beyond it).
                    far = tm[a].iter().all(|(oa, ta)| {
                        tm[b].iter().all(|(ob, tb)| {
                            let pa = frames[a].mul(oa).to_iso();
                            let pb = frames[b].mul(ob).to_iso();
                            matches!(
                                query::closest_points(&pa, ta, &pb, tb, 0.03).unwrap(),
                                query::ClosestPoints::Disjoint
                            )
                        })
                    });
                }
            }
            far_extra += usize::from(far);
        }
        // A hull is the mesh's convex closure: it adds contacts only in concave parts. Links
        // whose meshes are 3 cm apart should rarely touch as hulls.
        assert!(
            far_extra * 100 <= N,
            "{}: hull contacts with the meshes ≥ 3 cm apart on {far_extra} of {N} configurations (> 1 %)",
            arm.name
        );
        eprintln!(
            "{}: {} link pairs, {N} configurations: {mesh_hits} mesh contacts, {hull_extra} contacts of the model the meshes lack (primitives included), \
             {far_extra} configurations with a hull contact of meshes ≥ 3 cm apart",
            arm.name,
            pairs.len()
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Small hand-made robots: formats, scale, bad inputs.

use helixreach::robot::mesh::MeshSearch;
use helixreach::robot::LoadOptions;
use std::path::{Path, PathBuf};

/// A unit cube `[-0.5, 0.5]³` as triangles.
fn cube_triangles() -> Vec<[[f32; 3]; 3]> {
    let v = |i: u32| -> [f32; 3] {
        [
            if i & 1 == 0 { -0.5 } else { 0.5 },
            if i & 2 == 0 { -0.5 } else { 0.5 },
            if i & 4 == 0 { -0.5 } else { 0.5 },
        ]
    };
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut t = Vec::new();
    for q in quads {
        t.push([v(q[0]), v(q[1]), v(q[2])]);
        t.push([v(q[0]), v(q[2]), v(q[3])]);
    }
    t
}

fn write_binary_stl(path: &Path, tris: &[[[f32; 3]; 3]]) {
    let mut b = vec![0u8; 80];
    b.extend((tris.len() as u32).to_le_bytes());
    for t in tris {
        b.extend([0u8; 12]);
        for v in t {
            for x in v {
                b.extend(x.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    std::fs::write(path, b).unwrap();
}

fn write_ascii_stl(path: &Path, tris: &[[[f32; 3]; 3]]) {
    let mut s = String::from("solid cube\n");
    for t in tris {
        s.push_str(" facet normal 0 0 0\n  outer loop\n");
        for v in t {
            s.push_str(&format!("   vertex {} {} {}\n", v[0], v[1], v[2]));
        }
        s.push_str("  endloop\n endfacet\n");
    }
    s.push_str("endsolid cube\n");
    std::fs::write(path, s).unwrap();
}

fn write_obj(path: &Path, tris: &[[[f32; 3]; 3]]) {
    let mut s = String::new();
    for t in tris {
        for v in t {
            s.push_str(&format!("v {} {} {}\n", v[0], v[1], v[2]));
        }
    }
    for k in 0..tris.len() {
        s.push_str(&format!("f {} {} {}\n", 3 * k + 1, 3 * k + 2, 3 * k + 3));
    }
    std::fs::write(path, s).unwrap();
}

/// A two-joint arm: `base` (box), `l1` (the mesh `l1_geometry`), `l2` (box), tool `tip`.
fn arm_urdf(l1_geometry: &str, extra: &str) -> String {
    format!(
        r#"<robot name="two">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="l1"><collision><origin xyz="0 0 0.25"/><geometry>{l1_geometry}</geometry></collision></link>
  <link name="l2"><collision><geometry><box size="0.1 0.1 0.3"/></geometry></collision></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="jt" type="fixed"><parent link="l2"/><child link="tip"/><origin xyz="0 0 0.3"/></joint>
  {extra}
</robot>"#
    )
}

fn load_in(dir: &Path, urdf: &str, opts: &LoadOptions) -> helixreach::Result<RobotModel> {
    let p = dir.join("robot.urdf");
    std::fs::write(&p, urdf).unwrap();
    RobotModel::from_urdf_file_with(&p, Some("tip"), opts)
}

fn no_env() -> LoadOptions {
    LoadOptions {
        search: MeshSearch {
            package_paths: Vec::new(),
            ros_package_path: false,
        },
        no_collision: Vec::new(),
    }
}

/// STL (binary and ASCII) and OBJ load, `scale` applies per axis, and the hull of a scaled
/// cube is that box: its vertices are the 8 corners.
#[test]
fn stl_binary_ascii_and_obj_load_with_scale() {
    let dir = tempfile::tempdir().unwrap();
    let tris = cube_triangles();
    write_binary_stl(&dir.path().join("c.stl"), &tris);
    write_ascii_stl(&dir.path().join("a.stl"), &tris);
    write_obj(&dir.path().join("c.obj"), &tris);
    for (file, rel) in [("c.stl", true), ("a.stl", false), ("c.obj", true)] {
        let name = if rel {
            file.to_string()
        } else {
            format!("file://{}", dir.path().join(file).display())
        };
        let g = format!(r#"<mesh filename="{name}" scale="0.1 0.2 0.4"/>"#);
        let m = load_in(dir.path(), &arm_urdf(&g, ""), &no_env()).unwrap();
        let l1 = &m.links()[m.link_index("l1").unwrap()];
        assert_eq!(l1.meshes.len(), 1, "{file}");
        let h = &l1.meshes[0].mesh.hull_points;
        assert_eq!(h.len(), 8, "{file}: hull of a box has 8 vertices");
        for p in h {
            assert!(
                (p.x.abs() - 0.05).abs() < 1e-7
                    && (p.y.abs() - 0.1).abs() < 1e-7
                    && (p.z.abs() - 0.2).abs() < 1e-7,
                "{file}: {p:?}"
            );
        }
        assert_eq!(l1.meshes[0].mesh.triangles.len(), 12);
        let want = dir.path().join(file).display().to_string();
        assert!(m.sources().iter().any(|s| s.path() == want), "{file}");
    }
}

fn err_of(dir: &Path, urdf: &str, opts: &LoadOptions) -> String {
    load_in(dir, urdf, opts).unwrap_err().to_string()
}

/// Each bad collision element is an error naming the file, the link and the element.
#[test]
fn bad_mesh_elements_are_errors_naming_file_link_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Missing file: every path searched is named.
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="missing.stl"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("robot.urdf")
            && e.contains("link l1 collision[0]")
            && e.contains(&d.join("missing.stl").display().to_string()),
        "{e}"
    );
    // Empty and unreadable meshes.
    std::fs::write(d.join("empty.stl"), "solid e\nendsolid e\n").unwrap();
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="empty.stl"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("empty.stl") && e.contains("link l1 collision[0]"),
        "{e}"
    );
    std::fs::write(d.join("junk.obj"), "this is not a mesh\n").unwrap();
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="junk.obj"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("junk.obj") && e.contains("link l1 collision[0]"),
        "{e}"
    );
    // A NaN vertex.
    let mut tris = cube_triangles();
    tris[3][1][2] = f32::NAN;
    write_binary_stl(&d.join("nan.stl"), &tris);
    let e = err_of(d, &arm_urdf(r#"<mesh filename="nan.stl"/>"#, ""), &no_env());
    assert!(
        e.contains("nan.stl") && e.contains("link l1 collision[0]") && e.contains("not finite"),
        "{e}"
    );
    // An unsupported format.
    std::fs::write(d.join("m.ply"), "ply\n").unwrap();
    let e = err_of(d, &arm_urdf(r#"<mesh filename="m.ply"/>"#, ""), &no_env());
    assert!(
        e.contains("m.ply") && e.contains("unsupported mesh format"),
        "{e}"
    );
    // A flat mesh (no volume).
    let flat: Vec<[[f32; 3]; 3]> = vec![[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]];
    write_binary_stl(&d.join("flat.stl"), &flat);
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="flat.stl"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("flat.stl") && e.contains("no convex hull"),
        "{e}"
    );
    // A bad scale.
    write_binary_stl(&d.join("c.stl"), &cube_triangles());
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="c.stl" scale="1 0 1"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("link l1 collision[0]") && e.contains("scale"),
        "{e}"
    );
}

/// `package://` resolves through the package directories in order, then `ROS_PACKAGE_PATH`;
/// one that resolves nowhere is an error listing every path searched.
#[test]
fn package_urls_resolve_through_package_paths_or_name_every_path_searched() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let pkg = d.join("share/my_robot_description/meshes");
    std::fs::create_dir_all(&pkg).unwrap();
    write_binary_stl(&pkg.join("l1.stl"), &cube_triangles());
    let g = r#"<mesh filename="package://my_robot_description/meshes/l1.stl"/>"#;
    let urdf = arm_urdf(g, "");
    // Nowhere to look.
    let e = err_of(d, &urdf, &no_env());
    assert!(e.contains("no package directory given"), "{e}");
    // Two wrong directories: both candidate paths named.
    let opts = |dirs: Vec<PathBuf>| LoadOptions {
        search: MeshSearch {
            package_paths: dirs,
            ros_package_path: false,
        },
        no_collision: Vec::new(),
    };
    let e = err_of(d, &urdf, &opts(vec![d.join("a"), d.join("b")]));
    for x in ["a", "b"] {
        let c = d.join(x).join("my_robot_description/meshes/l1.stl");
        assert!(e.contains(&c.display().to_string()), "{e}");
    }
    assert!(e.contains("link l1 collision[0]"), "{e}");
    // The parent of the package, or the package directory itself.
    let m = load_in(d, &urdf, &opts(vec![d.join("a"), d.join("share")])).unwrap();
    assert_eq!(m.links()[1].meshes[0].mesh.file, pkg.join("l1.stl"));
    let m = load_in(d, &urdf, &opts(vec![d.join("share/my_robot_description")])).unwrap();
    assert_eq!(m.links()[1].meshes[0].mesh.file, pkg.join("l1.stl"));
}

/// A mesh over the size limit (a 2-million-triangle binary STL, 100 MB) is a clear error
/// before it is read; so is a small file declaring 2 million triangles.
#[test]
fn a_two_million_triangle_mesh_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let n: u32 = 2_000_000;
    let mut head = vec![0u8; 80];
    head.extend(n.to_le_bytes());
    std::fs::write(d.join("huge.stl"), &head).unwrap();
    // A sparse file of the full size: no 100 MB written.
    let f = std::fs::OpenOptions::new()
        .write(true)
        .open(d.join("huge.stl"))
        .unwrap();
    f.set_len(84 + 50 * n as u64).unwrap();
    drop(f);
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="huge.stl"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("huge.stl") && e.contains("MAX_MESH_FILE_BYTES"),
        "{e}"
    );
    // Small file, huge declared count.
    let mut b = vec![0u8; 80];
    b.extend(n.to_le_bytes());
    b.extend(vec![0u8; 50 * 12]);
    std::fs::write(d.join("liar.stl"), b).unwrap();
    let e = err_of(
        d,
        &arm_urdf(r#"<mesh filename="liar.stl"/>"#, ""),
        &no_env(),
    );
    assert!(
        e.contains("liar.stl") && e.contains("MAX_MESH_TRIANGLES"),
        "{e}"
    );
}

/// A link on the arm without collision geometry is an error unless listed in `no_collision`;
/// a URDF with no collision geometry at all never loads as a robot with nothing to check.
#[test]
fn a_link_without_collision_geometry_is_an_error_unless_listed() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let urdf = arm_urdf("", "").replace(
        r#"<link name="l1"><collision><origin xyz="0 0 0.25"/><geometry></geometry></collision></link>"#,
        r#"<link name="l1"/>"#,
    );
    assert!(urdf.contains(r#"<link name="l1"/>"#));
    let e = err_of(d, &urdf, &no_env());
    assert!(
        e.contains("link l1") && e.contains("no collision geometry") && e.contains("no_collision"),
        "{e}"
    );
    let mut opts = no_env();
    opts.no_collision = vec!["l1".into()];
    let m = load_in(d, &urdf, &opts).unwrap();
    assert_eq!(m.ignored_geometry().len(), 1);
    // Naming a link that has geometry, or no link, is an error too.
    opts.no_collision = vec!["l2".into()];
    assert!(err_of(d, &urdf, &opts).contains("l2"));
    opts.no_collision = vec!["nope".into()];
    assert!(err_of(d, &urdf, &opts).contains("nope"));
    // No collision geometry anywhere.
    let bare = r#"<robot name="bare">
  <link name="base"/><link name="l1"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>"#;
    let e = RobotModel::from_urdf_str(bare, "bare.urdf", Some("l1"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bare.urdf") && e.contains("no collision geometry"),
        "{e}"
    );
}

const BOX: &str = r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;

/// A mimic cycle is an error naming the joints; a mimic of a mimic off the arm follows its
/// source; a mimic on the arm is an error.
#[test]
fn mimic_joints_follow_their_source_and_a_cycle_is_an_error() {
    let robot = |mimics: &str| {
        format!(
            r#"<robot name="m">
  <link name="base">{BOX}</link><link name="l1">{BOX}</link>
  <link name="fa">{BOX}</link><link name="fb">{BOX}</link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="ja" type="revolute"><parent link="l1"/><child link="fa"/><origin xyz="0.3 0 0"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/>{}</joint>
  <joint name="jb" type="prismatic"><parent link="l1"/><child link="fb"/><origin xyz="0 0.3 0"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>{}</joint>
</robot>"#,
            mimics.split('|').next().unwrap(),
            mimics.split('|').nth(1).unwrap()
        )
    };
    let cyc = robot(r#"<mimic joint="jb"/>|<mimic joint="ja"/>"#);
    let e = RobotModel::from_urdf_str(&cyc, "cyc.urdf", Some("l1"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mimic cycle") && e.contains("ja") && e.contains("jb"),
        "{e}"
    );
    // ja follows j1 (2·q + 0.1); jb follows ja (0.5·v(ja) − 0.2) through the chain of mimics.
    let ok = robot(
        r#"<mimic joint="j1" multiplier="2" offset="0.1"/>|<mimic joint="ja" multiplier="0.5" offset="-0.2"/>"#,
    );
    let m = RobotModel::from_urdf_str(&ok, "ok.urdf", Some("l1")).unwrap();
    assert_eq!(m.dof(), 1);
    for q in [-1.0, 0.0, 0.7] {
        let f = m.link_frames(&[q]).unwrap();
        let fa = &f[m.link_index("fa").unwrap()];
        let fb = &f[m.link_index("fb").unwrap()];
        let va: Real = 2.0 * q + 0.1;
        let vb = 0.5 * va - 0.2;
        // fa: rotated by q about z, then by va about z: total q + va.
        let ang = fa.rot[(1, 0)].atan2(fa.rot[(0, 0)]);
        assert!((ang - (q + va)).abs() < 1e-12, "{ang} vs {}", q + va);
        // fb: at Rz(q)·(vb, 0.3, 0).
        let (s, c) = q.sin_cos();
        let want = helixreach::math::Vec3::new(c * vb - s * 0.3, s * vb + c * 0.3, 0.0);
        assert!((fb.pos - want).norm() < 1e-12, "{:?} vs {want:?}", fb.pos);
    }
    // A mimic on the path to the tool.
    let e = RobotModel::from_urdf_str(&ok, "ok.urdf", Some("fa"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint ja mimic") && e.contains("path"), "{e}");
}

/// A prismatic rail under a revolute joint: FK, Jacobian (finite differences) and limits in
/// metres.
#[test]
fn a_prismatic_rail_moves_the_arm() {
    let urdf = format!(
        r#"<robot name="rail">
  <link name="base">{BOX}</link><link name="cart">{BOX}</link><link name="l1">{BOX}</link><link name="tip"/>
  <joint name="rail" type="prismatic"><parent link="base"/><child link="cart"/><axis xyz="0 1 0"/><limit lower="-0.5" upper="1.5" effort="1" velocity="0.3"/></joint>
  <joint name="j1" type="continuous"><parent link="cart"/><child link="l1"/><origin xyz="0 0 0.2"/><axis xyz="0 0 1"/></joint>
  <joint name="jt" type="fixed"><parent link="l1"/><child link="tip"/><origin xyz="0.4 0 0"/></joint>
</robot>"#
    );
    let m = RobotModel::from_urdf_str(&urdf, "rail.urdf", Some("tip")).unwrap();
    assert_eq!(m.dof(), 2);
    assert_eq!((m.joints()[0].lower, m.joints()[0].upper), (-0.5, 1.5));
    for (y, a) in [(0.0, 0.0), (1.2, 0.5), (-0.3, -2.0)] {
        let p = m.tool_pose(&[y, a]).unwrap().pos;
        let want = helixreach::math::Vec3::new(0.4 * a.cos(), y + 0.4 * a.sin(), 0.2);
        assert!((p - want).norm() < 1e-14, "{p:?} vs {want:?}");
        let (_, j) = m.jacobian(&[y, a]).unwrap();
        let h = 1e-6;
        for k in 0..2 {
            let mut qp = [y, a];
            let mut qm = [y, a];
            qp[k] += h;
            qm[k] -= h;
            let d = (m.tool_pose(&qp).unwrap().pos - m.tool_pose(&qm).unwrap().pos) / (2.0 * h);
            for r in 0..3 {
                assert!((j[(r, k)] - d[r]).abs() < 1e-8, "J[{r},{k}]");
            }
        }
        // The rail's angular column is zero.
        assert!(j.fixed_view::<3, 1>(3, 0).norm() == 0.0);
    }
}

/// Padding: with padding p on every link, a self pair is in contact exactly when the unpadded
/// bodies are within 2p (parry's distance as the reference), on random UR5 configurations.
#[test]
fn padding_grows_every_body_by_its_amount() {
    use helixreach::robot::collision::CollisionSettings;
    let arm = ARMS.iter().find(|a| a.name == "ur5").unwrap();
    let m = robots::load(arm);
    let p = 0.02;
    let plain = CollisionModel::new(&m, &DisabledPairs::default(), &[]).unwrap();
    let padded = CollisionModel::with_settings(
        &m,
        &DisabledPairs::default(),
        &[],
        &CollisionSettings {
            padding: p,
            link_padding: Vec::new(),
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        padded.summary().contains("padding 0.02 m"),
        "{}",
        padded.summary()
    );
    let (mut w1, mut w2) = (plain.workspace(), padded.workspace());
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut only_padded, mut checked) = (0, 0);
    for _ in 0..300 {
        let q = m.random_config(&mut rng);
        let q = &q[..m.dof()];
        plain.update(q, &mut w1);
        padded.update(q, &mut w2);
        let d = plain.self_clearance(&w1).map(|c| c.distance).unwrap();
        let hit = padded.self_collision(&w2).is_some();
        // Away from the threshold, the padded check is the distance test.
        if (d - 2.0 * p).abs() > 1e-6 {
            checked += 1;
            assert_eq!(hit, d <= 2.0 * p, "distance {d} at {q:?}");
            only_padded += usize::from(hit && plain.self_collision(&w1).is_none());
        }
    }
    assert!(checked > 250 && only_padded > 0, "{checked} {only_padded}");
}

/// The never-colliding pair sampler (`robot --write-disabled`) on a mesh robot: a pair it lists
/// as `never` is free, by parry's exact mesh-versus-mesh test, on 2,000 other random
/// configurations; adjacent links are not listed (they are skipped anyway).
#[test]
fn disabled_pair_sampling_works_on_mesh_robots() {
    let arm = ARMS.iter().find(|a| a.name == "panda").unwrap();
    let m = robots::load(arm);
    let d = DisabledPairs::compute(&m, 10_000, 1).unwrap();
    let idx = |n: &str| m.links().iter().position(|l| l.name == n).unwrap();
    let never: Vec<(usize, usize)> = d
        .disabled
        .iter()
        .filter(|p| p.reason == "never")
        .map(|p| (idx(&p.a), idx(&p.b)))
        .collect();
    assert!(!never.is_empty());
    let cm = CollisionModel::new(&m, &DisabledPairs::default(), &[]).unwrap();
    let candidates = cm.self_pair_links();
    for &(a, b) in &never {
        assert!(
            candidates.contains(&(a, b)) || candidates.contains(&(b, a)),
            "{} | {}: listed but not a candidate pair",
            m.links()[a].name,
            m.links()[b].name
        );
    }
    let mut ws = cm.workspace();
    let tm = trimeshes(&m);
    let mut rng = ChaCha8Rng::seed_from_u64(99);
    for _ in 0..2000 {
        let q = m.random_config(&mut rng);
        cm.update(&q[..m.dof()], &mut ws);
        let frames = cm.link_frames(&ws).to_vec();
        for &(a, b) in &never {
            for (oa, ta) in &tm[a] {
                for (ob, tb) in &tm[b] {
                    let pa = frames[a].mul(oa).to_iso();
                    let pb = frames[b].mul(ob).to_iso();
                    assert!(
                        !query::intersection_test(&pa, ta, &pb, tb).unwrap(),
                        "{} | {} listed as never colliding, meshes touch at q = {:?}",
                        m.links()[a].name,
                        m.links()[b].name,
                        &q[..m.dof()]
                    );
                }
            }
        }
    }
}

/// A `robot --write-disabled` file names the command that regenerates it with every load option
/// it was made with (tool link, package path, samples, seed): run as written (with `--force`),
/// that line reproduces the file byte for byte.
#[test]
fn a_disabled_pairs_file_names_the_command_that_regenerates_it() {
    let arm = ARMS.iter().find(|a| a.name == "panda").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("panda.pairs.toml");
    let bin = env!("CARGO_BIN_EXE_helixreach");
    let urdf = robots::urdf(arm);
    let pkg = robots::package_dir();
    let run = |args: &[&str]| {
        let o = std::process::Command::new(bin).args(args).output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    run(&[
        "--quiet",
        "robot",
        "--robot",
        urdf.to_str().unwrap(),
        "--tip",
        arm.tip,
        "--package-path",
        pkg.to_str().unwrap(),
        "--samples",
        "10000",
        "--seed",
        "7",
        "--write-disabled",
        out.to_str().unwrap(),
    ]);
    let first = std::fs::read_to_string(&out).unwrap();
    let line = first
        .lines()
        .find_map(|l| l.strip_prefix("# Regenerate: "))
        .expect("a Regenerate line");
    for needle in [
        format!("--tip {}", arm.tip),
        format!("--package-path {}", pkg.display()),
        "--samples 10000".into(),
        "--seed 7".into(),
    ] {
        assert!(line.contains(&needle), "{needle} missing from: {line}");
    }
    let words: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(words[0], "helixreach");
    let mut again: Vec<&str> = vec!["--quiet"];
    again.extend(&words[1..]);
    again.push("--force");
    run(&again);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), first);
}
