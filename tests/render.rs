//! `render`: the drawn geometry agrees with an independent FK (k), the image is painted where the
//! geometry projects, clearance pairs are drawn with the collision model's distances, the GIF
//! decodes to the stated frames and size, and bad input fails naming the file, line and field.

use helixreach::directions::Direction;
use helixreach::math::Vec3;
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::plot::render::input::{
    read_trajectory, select_frames, Phase, Row, MAX_STRIP_FRAMES,
};
use helixreach::plot::render::{
    render_gif, render_rgb, render_scene, render_trajectory, Arrangement, ClearanceKind,
    Configuration, FrameSelection, Layout, Part, RenderOptions, Scene, Snapshot, Solid,
    TrajectoryRender, View,
};
use helixreach::robot::collision::{ObstaclePose, SceneObstacle};
use helixreach::robot::k_bridge::KRobot;
use helixreach::robot::Shape;
use rand::SeedableRng;

mod common;
use common::png::Png;

const BIN: &str = env!("CARGO_BIN_EXE_helixreach");
/// A configuration the seed's Sawyer executed (the module docs of `robot`).
const SEED_Q: [f64; 7] = [-0.857, -0.873, -1.819, -0.034, 1.860, 2.434, -2.200];

fn scene() -> Scene {
    Scene::new(&Rig::load("sawyer-seed").unwrap()).unwrap()
}

fn snap(scene: &Scene, q: &[f64], kto: [f64; 3]) -> Snapshot {
    scene
        .snapshot(&Configuration {
            q: q.to_vec(),
            kto,
            azimuth: 0.0,
        })
        .unwrap()
}

/// Screen coordinates written out per view, independent of `View::project`.
fn screen(v: View, p: &Vec3) -> [f64; 2] {
    match v {
        View::Front => [p.x, p.z],
        View::Side => [p.y, p.z],
        View::Top => [p.x, p.y],
        View::Iso => [
            (p.x + p.y) / 2f64.sqrt(),
            (-p.x + p.y + 2.0 * p.z) / 6f64.sqrt(),
        ],
    }
}

fn configs() -> Vec<Vec<f64>> {
    let m = scene();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(14);
    let mut out = vec![vec![0.0; 7], SEED_Q.to_vec()];
    for _ in 0..3 {
        out.push(m.model().random_config(&mut rng)[..7].to_vec());
    }
    out
}

#[test]
fn projected_capsules_agree_with_k_forward_kinematics() {
    let sc = scene();
    let k = KRobot::new(sc.model()).unwrap();
    let mut checked = 0;
    for q in configs() {
        let s = snap(&sc, &q, [0.0; 3]);
        let frames = k.link_frames(&q);
        for (i, link) in sc.model().links().iter().enumerate() {
            let drawn: Vec<&Solid> = s
                .bodies
                .iter()
                .filter(|b| b.part == Part::Link(i))
                .map(|b| &b.solid)
                .collect();
            assert_eq!(drawn.len(), link.collision.len(), "{}", link.name);
            for (c, solid) in link.collision.iter().zip(drawn) {
                let Shape::Capsule { half_length, .. } = c.shape else {
                    continue;
                };
                let pose = frames[i].mul(&c.origin);
                let ra = pose.transform_point(&Vec3::new(0.0, 0.0, -half_length));
                let rb = pose.transform_point(&Vec3::new(0.0, 0.0, half_length));
                let Solid::Capsule { a, b, .. } = solid else {
                    panic!("{}: a capsule drawn as {solid:?}", link.name);
                };
                for v in View::ALL {
                    for (got, want) in [(a, ra), (b, rb)] {
                        let (g, w) = (v.project(got), screen(v, &want));
                        assert!(
                            (g[0] - w[0]).abs() < 1e-9 && (g[1] - w[1]).abs() < 1e-9,
                            "{} {v:?}: drawn {g:?}, k FK {w:?}",
                            link.name
                        );
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 5 * 8, "only {checked} capsules checked");
}

#[test]
fn image_is_painted_where_fk_projects_the_links_and_the_rod() {
    let sc = scene();
    let k = KRobot::new(sc.model()).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let q = SEED_Q.to_vec();
    let s = snap(&sc, &q, [0.0; 3]);
    let opts = RenderOptions {
        views: View::ALL.to_vec(),
        ..Default::default()
    };
    let out = dir.path().join("scene.png");
    render_scene(&sc, &s, &opts, &out).unwrap();
    let png = Png::read(&out);
    let layout = Layout::new(std::slice::from_ref(&s), &opts, Arrangement::Row).unwrap();
    assert_eq!((png.width, png.height), layout.size());
    // Joint origins of the moving links (by k's FK) lie on their links: painted, not white.
    let frames = k.link_frames(&q);
    for name in ["right_l2", "right_l4", "right_hand"] {
        let i = sc.model().link_index(name).unwrap();
        for v in 0..4 {
            let px = layout.pixel(0, v, &frames[i].pos);
            let c = png.at(px);
            assert!(c != [255, 255, 255], "{name} view {v}: white at {px:?}");
        }
    }
    // The straight rod's midpoint (exact: clamp + L/2 · d3) in the side view, where the
    // arm is behind it: rod colour (vermillion, possibly lightened by depth).
    let rig = sc.rig();
    let mid = rig.clamp.translation.vector + 0.5 * rig.rod.length * rig.clamp_rotation().column(2);
    let c = png.at(layout.pixel(0, 1, &mid));
    assert!(
        c[0] > 180 && c[1] < 160 && c[2] < 120,
        "rod midpoint not rod-coloured: {c:?}"
    );
    // A point far above the robot, inside the top-left of the front panel, is background.
    let (ox, oy) = layout.panel_origin(0, 0);
    assert_eq!(png.at((ox + 64, oy + 30)), [255, 255, 255]);
}

#[test]
fn clearance_points_realize_the_collision_model_distances() {
    let sc = scene();
    let mut n = 0;
    for (j, q) in configs().iter().enumerate() {
        let kto = [3.0 * j as f64, 4.0, 1.0];
        let s = snap(&sc, q, kto);
        for c in &s.clearances {
            let d = (c.point_a - c.point_b).norm();
            if c.kind == ClearanceKind::Scene {
                // Box–box scene pairs: parry's exact closest points can be closer than the
                // collision model's distance (seed rig, lowered table: pedestal_feet – table
                // 0.1978 m by closest points and by hand, 0.2093 m by the model — reported).
                assert!(
                    d <= c.distance + 1e-6,
                    "{} – {}: {d} > {}",
                    c.a,
                    c.b,
                    c.distance
                );
            } else if c.distance > 0.0 {
                assert!(
                    (d - c.distance).abs() < 1e-6,
                    "{:?} {} – {}: points {d} apart, model says {}",
                    c.kind,
                    c.a,
                    c.b,
                    c.distance
                );
                n += 1;
            }
        }
        assert!(s.clearance(ClearanceKind::SelfCollision).is_some());
        assert!(s.clearance(ClearanceKind::Scene).is_some());
        assert!(s.clearance(ClearanceKind::RodArm).is_some());
    }
    assert!(n >= 5, "{n}");
}

#[test]
fn a_known_collision_draws_the_contact_pair() {
    let mut rig = Rig::load("sawyer-seed").unwrap();
    let clean = Scene::new(&rig).unwrap();
    let q = SEED_Q.to_vec();
    // A small probe ball on the axis of the forearm capsule collides with the forearm only.
    let l4 = clean.model().link_index("right_l4").unwrap();
    let s0 = snap(&clean, &q, [0.0; 3]);
    let axis_mid = s0
        .bodies
        .iter()
        .find(|b| b.part == Part::Link(l4))
        .map(|b| b.solid.center())
        .unwrap();
    rig.obstacles.push(SceneObstacle {
        name: "probe".into(),
        shape: Shape::Sphere { radius: 0.01 },
        pose: ObstaclePose {
            xyz: [axis_mid.x, axis_mid.y, axis_mid.z],
            rpy: [0.0; 3],
        },
    });
    let sc = Scene::new(&rig).unwrap();
    let s = snap(&sc, &q, [0.0; 3]);
    let c = s.clearance(ClearanceKind::Scene).unwrap().clone();
    assert_eq!(c.distance, 0.0);
    assert_eq!((c.a.as_str(), c.b.as_str()), ("right_l4", "probe"));

    let dir = tempfile::tempdir().unwrap();
    let opts = RenderOptions {
        views: vec![View::Front, View::Top],
        ..Default::default()
    };
    let svg = dir.path().join("hit.svg");
    render_scene(&sc, &s, &opts, &svg).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("scene COLLISION: right_l4 – probe"),
        "the footer must name the pair"
    );
    let png = dir.path().join("hit.png");
    render_scene(&sc, &s, &opts, &png).unwrap();
    let img = Png::read(&png);
    let layout = Layout::new(std::slice::from_ref(&s), &opts, Arrangement::Row).unwrap();
    for v in 0..2 {
        // The dot at the contact point is the scene-pair green (0x00, 0x9E, 0x73).
        let p = img.at(layout.pixel(0, v, &c.point_a));
        assert!(
            p[1] > 120 && p[0] < 60 && p[2] > 80 && p[2] < 150,
            "view {v}: contact dot not green: {p:?}"
        );
    }
    // Without the probe there is no scene collision at this configuration.
    assert!(s0.clearance(ClearanceKind::Scene).unwrap().distance > 0.0);
}

#[test]
fn gif_decodes_to_the_stated_frames_and_size() {
    let sc = scene();
    let n = 7;
    let snaps: Vec<Snapshot> = (0..n)
        .map(|k| {
            let f = k as f64 / (n - 1) as f64;
            let q: Vec<f64> = SEED_Q.iter().map(|x| x * (1.0 - 0.3 * f)).collect();
            snap(&sc, &q, [2.0 * f, 3.0 * f, 0.0])
        })
        .collect();
    let opts = RenderOptions {
        views: vec![View::Front, View::Iso],
        panel: (260, 240),
        ..Default::default()
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.gif");
    render_gif(
        helixreach::par::Par::all(),
        &sc,
        &snaps,
        &opts,
        120,
        &out,
        false,
    )
    .unwrap();
    let (w, h) = Layout::new(&snaps, &opts, Arrangement::Row).unwrap().size();
    let mut dec = gif::DecodeOptions::new();
    dec.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = dec.read_info(std::fs::File::open(&out).unwrap()).unwrap();
    assert_eq!((dec.width() as u32, dec.height() as u32), (w, h));
    let layout = Layout::new(&snaps, &opts, Arrangement::Row).unwrap();
    let mut frames = 0;
    let mut first: Option<Vec<u8>> = None;
    let mut differ = false;
    while let Some(f) = dec.read_next_frame().unwrap() {
        assert_eq!((f.width as u32, f.height as u32), (w, h));
        assert_eq!(f.delay, 12);
        match &first {
            None => first = Some(f.buffer.to_vec()),
            Some(b) => differ |= b[..] != f.buffer[..],
        }
        // The decoded frame is the drawn frame: every flat colour exact, only rare glyph-edge
        // greys moved to a palette neighbour.
        let rgb = render_rgb(&sc, &snaps[frames], &layout, &opts).unwrap();
        let exact = rgb
            .chunks_exact(3)
            .zip(f.buffer.chunks_exact(4))
            .filter(|(a, b)| a[..] == b[..3])
            .count();
        let frac = exact as f64 / (w * h) as f64;
        assert!(
            frac > 0.98,
            "frame {frames}: only {frac} of the pixels exact"
        );
        frames += 1;
    }
    assert_eq!(frames, n);
    assert!(differ, "the arm moves: frames must differ");
    assert!(render_gif(
        helixreach::par::Par::all(),
        &sc,
        &[],
        &opts,
        100,
        &out,
        false
    )
    .is_err());
}

fn plan_csv(rig: &Rig, azimuth: f64) -> String {
    let planner = Planner::new(rig.clone()).unwrap();
    let dir = Direction::new(0.3, 0.9, 0.3).unwrap();
    let s_star = helixreach::sweep::reach::s_star_of(&dir, None).unwrap();
    let plan = planner
        .plan_ray(&dir, s_star, azimuth, RollMode::Fixed, true)
        .unwrap();
    assert!(plan.s_reached > 0.5 * s_star, "the test ray must get far");
    helixreach::records::trajectory::trajectory_csv(&planner.trajectory(&plan).unwrap()).unwrap()
}

#[test]
fn planned_trajectory_renders_with_its_azimuth_and_wrong_rig_is_refused() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let dir = tempfile::tempdir().unwrap();
    let traj = dir.path().join("traj.csv");
    std::fs::write(&traj, plan_csv(&rig, 0.4)).unwrap();
    let opts = TrajectoryRender {
        strip: RenderOptions {
            views: vec![View::Front, View::Iso],
            ..Default::default()
        },
        ..Default::default()
    };
    let sum = render_trajectory(&rig, &traj, &opts, dir.path()).unwrap();
    assert!((sum.azimuth - 0.4).abs() < 1e-6, "azimuth {}", sum.azimuth);
    assert!(sum.frames.len() >= 5, "{:?}", sum.frames);
    assert!(sum.frames[0].label.contains("s = 0"));
    assert!(sum.frames.last().unwrap().label.contains("end"));
    let png = Png::read(&sum.strip_png);
    assert!(png.width >= 5 * 400);
    let csv = std::fs::read_to_string(&sum.frames_csv).unwrap();
    assert_eq!(csv.lines().count(), sum.frames.len() + 1);
    assert!(csv.starts_with("frame,row,line,t,s,phase,label,self_m"));
    // Rod–arm clearance is what the planner kept above its inflation.
    let m = sum.min_clearance[2].unwrap();
    assert!(m >= rig.planner.rod_clearance - 1e-9, "rod-arm {m}");

    // The same file on a rig whose clamp moved 5 cm: refused, naming the line.
    let mut moved = rig.clone();
    moved.clamp.translation.vector.x += 0.05;
    let e = render_trajectory(&moved, &traj, &opts, dir.path())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("traj.csv:2:") && e.contains("another rig"),
        "{e}"
    );
}

fn rows_of(s: &[(f64, Option<Phase>)]) -> Vec<Row> {
    s.iter()
        .enumerate()
        .map(|(i, &(s, phase))| Row {
            line: i + 2,
            t: i as f64,
            q: vec![
                if phase == Some(Phase::Reconfigure) {
                    i as f64
                } else {
                    0.0
                };
                7
            ],
            motor: 0.0,
            s,
            kto: [s, 0.0, 0.0],
            end: None,
            azimuth: None,
            phase,
        })
        .collect()
}

#[test]
fn default_frames_are_the_s_star_fractions_the_end_and_each_reconfiguration() {
    use Phase::*;
    let rows = rows_of(&[
        (0.0, Some(Load)),
        (0.3, Some(Load)),
        (0.5, Some(Load)),
        (0.5, Some(Reconfigure)),
        (0.5, Some(Reconfigure)),
        (0.5, Some(Reconfigure)),
        (0.8, Some(Load)),
        (1.0, Some(Load)),
        (1.1, Some(Hold)),
        (0.6, Some(Unload)),
        (0.0, Some(Unload)),
    ]);
    let f = select_frames(&rows, FrameSelection::Default { s_star: Some(1.0) }).unwrap();
    let got: Vec<(usize, &str)> = f.iter().map(|c| (c.row, c.label.as_str())).collect();
    assert_eq!(
        got,
        vec![
            (0, "s = 0"),
            (1, "s = ¼ s*"),
            (2, "s = ½ s*"),
            (4, "reconfigure"),
            (6, "s = ¾ s*"),
            (7, "s = s*"),
            (10, "end"),
        ]
    );
    // Without the phase column a reconfiguration is a run at constant s with moving joints.
    let mut bare = rows.clone();
    for r in &mut bare {
        r.phase = None;
    }
    let g = select_frames(&bare, FrameSelection::Default { s_star: Some(1.0) }).unwrap();
    assert!(
        g.iter().any(|c| c.label == "reconfigure" && c.row == 4),
        "{g:?}"
    );
    // N even frames; 0 and too many are refused.
    assert_eq!(
        select_frames(&rows, FrameSelection::Even(3)).unwrap().len(),
        3
    );
    let e = select_frames(&rows, FrameSelection::Even(0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("frames = 0"), "{e}");
    assert!(select_frames(&rows, FrameSelection::Even(33)).is_err());
}

/// A path with more reconfigurations than the strip has room for (a search path that backs off
/// and reconfigures often) keeps every s* fraction and the end and shows an even subset of the
/// reconfigurations, first and last included, each labelled with its rank.
#[test]
fn default_frames_subsample_many_reconfigurations() {
    use Phase::*;
    let n = 40;
    let mut spec = vec![(0.0, Some(Load))];
    for k in 0..n {
        let s = 0.02 * (k + 1) as f64;
        spec.push((s, Some(Load)));
        spec.push((s, Some(Reconfigure)));
    }
    spec.push((1.0, Some(Load)));
    spec.push((1.1, Some(Hold)));
    let rows = rows_of(&spec);
    let f = select_frames(&rows, FrameSelection::Default { s_star: Some(1.0) }).unwrap();
    assert!(f.len() <= MAX_STRIP_FRAMES, "{}", f.len());
    for name in ["s = 0", "s = ¼ s*", "s = ½ s*", "s = ¾ s*", "s = s*", "end"] {
        assert!(f.iter().any(|c| c.label.contains(name)), "{name}: {f:?}");
    }
    // Reconfiguration k (1-based) is row 2k: every shown one is a reconfiguration row, labelled
    // with its own rank; the first and the last are shown.
    let shown: Vec<usize> = f
        .iter()
        .filter_map(|c| {
            let rest = c.label.split("reconfigure ").nth(1)?;
            let k: usize = rest.split(" of ").next()?.parse().ok()?;
            assert!(rest.ends_with(&format!(" of {n}")), "{c:?}");
            assert_eq!(c.row, 2 * k, "{c:?}");
            Some(k)
        })
        .collect();
    assert_eq!(shown.first(), Some(&1), "{f:?}");
    assert_eq!(shown.last(), Some(&n), "{f:?}");
    assert!(shown.windows(2).all(|w| w[0] < w[1]));
    assert!(shown.len() >= MAX_STRIP_FRAMES - 6, "{}", shown.len());
}

#[test]
fn bad_trajectories_fail_naming_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let names: Vec<String> = (0..7).map(|j| format!("j{j}")).collect();
    let head7 = "t,q0,q1,q2,q3,q4,q5,q6,motor,s,kappa,tau,omega";
    // Another robot: six joints.
    let p = dir.path().join("six.csv");
    std::fs::write(
        &p,
        "t,q0,q1,q2,q3,q4,q5,motor,s,kappa,tau,omega\n0,0,0,0,0,0,0,0,0,0,0,0\n",
    )
    .unwrap();
    let e = read_trajectory(&p, &names, "sawyer")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("six.csv") && e.contains("6 joint columns") && e.contains("7 joints"),
        "{e}"
    );
    // Another robot's joint names: refused, not read by position.
    let p = dir.path().join("panda.csv");
    let panda: Vec<String> = (1..=7).map(|j| format!("panda_joint{j}")).collect();
    std::fs::write(
        &p,
        format!(
            "t,{},motor,s,kappa,tau,omega\n0,0,0,0,0,0,0,0,0,0,0,0,0\n",
            panda.join(",")
        ),
    )
    .unwrap();
    let e = read_trajectory(&p, &names, "sawyer")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("panda.csv") && e.contains("j0,j1") && e.contains("panda_joint1"),
        "{e}"
    );
    // The robot's joint names, in any order: read by name.
    let p = dir.path().join("named.csv");
    std::fs::write(
        &p,
        "t,j6,j5,j4,j3,j2,j1,j0,motor,s,kappa,tau,omega\n0,6,5,4,3,2,1,0,0,0,0,0,0\n",
    )
    .unwrap();
    let rows = read_trajectory(&p, &names, "sawyer").unwrap();
    assert_eq!(rows[0].q, [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    // A NaN joint on the second data row (line 3).
    let p = dir.path().join("nan.csv");
    std::fs::write(
        &p,
        format!("{head7}\n0,0,0,0,0,0,0,0,0,0,0,0,0\n1,0,0,NaN,0,0,0,0,0,0.1,0.1,0,0\n"),
    )
    .unwrap();
    let e = read_trajectory(&p, &names, "sawyer")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("nan.csv:3") && e.contains("q2") && e.contains("NaN"),
        "{e}"
    );
    // An unknown phase.
    let p = dir.path().join("phase.csv");
    std::fs::write(
        &p,
        format!("{head7},phase\n0,0,0,0,0,0,0,0,0,0,0,0,0,spin\n"),
    )
    .unwrap();
    let e = read_trajectory(&p, &names, "sawyer")
        .unwrap_err()
        .to_string();
    assert!(e.contains("phase.csv:2") && e.contains("spin"), "{e}");
    // Empty file.
    let p = dir.path().join("empty.csv");
    std::fs::write(&p, format!("{head7}\n")).unwrap();
    let e = read_trajectory(&p, &names, "sawyer")
        .unwrap_err()
        .to_string();
    assert!(e.contains("empty.csv") && e.contains("no data rows"), "{e}");

    // Through the CLI: --frames 0 and a bad view are refused with exit code 2.
    let rig = Rig::load("sawyer-seed").unwrap();
    let traj = dir.path().join("traj.csv");
    std::fs::write(&traj, plan_csv(&rig, 0.0)).unwrap();
    for (extra, want) in [
        (vec!["--frames", "0"], "frames = 0"),
        (vec!["--views", "front,back"], "back"),
        (vec!["--gif", "--gif-frames", "0"], "gif frames = 0"),
    ] {
        let out = std::process::Command::new(BIN)
            .args(["render", "--rig", "sawyer-seed", "--trajectory"])
            .arg(&traj)
            .arg("--out")
            .arg(dir.path().join("o"))
            .args(&extra)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(want), "{extra:?}: {err}");
    }
}

#[test]
fn rod_follows_the_rig_clamp_and_azimuth() {
    // The drawn rod starts at the clamp, is tangent to d3 there, and ends where the planner's
    // pose map puts the rod end (PoseMap: an independent composition of the same frames).
    let rig = Rig::load("sawyer-seed").unwrap();
    let sc = Scene::new(&rig).unwrap();
    let kto = [3.0, 2.0, 1.0];
    for az in [0.0, 0.7, -2.0] {
        let rod = sc.rod_nodes(kto, az, 200).unwrap();
        let oc = rig.clamp.translation.vector;
        assert!((rod[0] - oc).norm() < 1e-15);
        let t0 = (rod[1] - rod[0]).normalize();
        assert!((t0 - rig.clamp_rotation().column(2)).norm() < 1e-2);
        let (tool, _) = helixreach::planning::pose_path::PoseMap::new(&rig, az)
            .end(kto)
            .unwrap();
        assert!((rod[200] - tool.translation.vector).norm() < 1e-12);
        let len: f64 = rod.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!((len - rig.rod.length).abs() < 1e-4, "length {len}");
    }
}
