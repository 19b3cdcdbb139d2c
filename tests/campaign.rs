//! `helixreach campaign` as a lab runs it: every run passes `check`, the run list agrees with
//! the run files, sessions respect their length, rays that are not testable are listed with a
//! cause and no files, and bad input is an error naming file, line and value with nothing
//! written.

use helixreach::planning::check::{CheckOptions, Checker};
use helixreach::planning::rig::Rig;
use helixreach::records::trajectory::read_joint_file;
use std::path::Path;
use std::process::{Command, Output};

fn helixreach(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(args)
        .output()
        .expect("run helixreach")
}

/// On the seed rig: stops at s ≈ 2.13 of its target (no IK), as in `tests/plan_cli.rs`.
const PARTIAL_RAY: &str = "0.9294,0.075,0.3614";
/// Three rays of the 6-direction quarter lattice, testable on the seed rig.
const TESTABLE: [&str; 3] = [
    "0.6589052093531741,0.7500000000000001,-0.05782668144766698",
    "0.35938947172314983,0.5833333333333334,0.7283964784626416",
    "0.00000000000000006101935726003574,0.08333333333333333,-0.9965217285917832",
];

type Row = std::collections::HashMap<String, String>;

fn read_csv(path: &Path) -> Vec<Row> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect()
        })
        .collect()
}

fn num(r: &Row, k: &str) -> f64 {
    r[k].parse().unwrap_or_else(|_| panic!("{k} = `{}`", r[k]))
}

/// The last `t` of a trajectory CSV (its first column), read as text.
fn last_t(path: &Path) -> f64 {
    let text = std::fs::read_to_string(path).unwrap();
    let last = text.lines().rfind(|l| !l.is_empty()).unwrap();
    last.split(',').next().unwrap().parse().unwrap()
}

fn directions_file(dir: &Path, rows: &[&str]) -> std::path::PathBuf {
    let p = dir.join("dirs.csv");
    let mut s = String::from("dir_kappa,dir_tau,dir_omega\n");
    for r in rows {
        s.push_str(r);
        s.push('\n');
    }
    std::fs::write(&p, s).unwrap();
    p
}

/// The ladder's paths of these three rays start from start configurations that need both kinds
/// of move between runs (so both are checked); the search's need only unclamped moves.
#[test]
fn a_campaign_on_the_seed_rig_passes_check_and_its_run_list_adds_up() {
    campaign_passes_check("ladder");
}

/// The same campaign decided by the search (the rig's default): its runs (one of them with a
/// reconfiguration at a held pose) pass the same checks.
#[test]
fn a_campaign_decided_by_the_search_passes_check() {
    campaign_passes_check("exact");
}

fn campaign_passes_check(search: &str) {
    let tmp = tempfile::tempdir().unwrap();
    let mut rows = vec![PARTIAL_RAY];
    rows.extend(TESTABLE);
    let dirs = directions_file(tmp.path(), &rows);
    let out = tmp.path().join("camp");
    let session_h = 0.25;
    let o = helixreach(&[
        "--quiet",
        "campaign",
        "--rig",
        "sawyer-seed",
        "--search",
        search,
        "--directions",
        dirs.to_str().unwrap(),
        "--session-hours",
        &session_h.to_string(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let list = read_csv(&out.join("campaign.csv"));
    assert_eq!(list.len(), 4);
    let rig = Rig::load("sawyer-seed").unwrap();
    let checker = Checker::new(rig.clone()).unwrap();
    let planner = helixreach::planning::planner::Planner::new(rig.clone()).unwrap();
    let names = checker.joint_names();
    let straight = rig.straight_tool_pose();
    let runs: Vec<&Row> = list.iter().filter(|r| !r["order"].is_empty()).collect();
    assert_eq!(runs.len(), 3, "{list:?}");
    let mut prev_end: Option<Vec<f64>> = None;
    let mut session_len = std::collections::BTreeMap::<usize, (f64, usize)>::new();
    let mut clock = 0.0;
    let mut session = 0;
    let mut kinds = std::collections::BTreeSet::new();
    for (k, r) in runs.iter().enumerate() {
        assert_eq!(num(r, "order") as usize, k + 1);
        assert_eq!(r["class"], "testable");
        // The run passes check: limits, collisions (rod too), steps, speeds, pose at its s.
        let file = read_joint_file(&out.join(&r["file"]), &names).unwrap();
        let d = helixreach::directions::Direction::new(
            num(r, "dir_kappa"),
            num(r, "dir_tau"),
            num(r, "dir_omega"),
        )
        .unwrap();
        let opt = CheckOptions {
            direction: Some(d),
            azimuth: num(r, "azimuth"),
            ..CheckOptions::default()
        };
        let rep = checker.check(&file, &opt).unwrap();
        assert_eq!(rep.finding_mask(), 0, "{}: {:?}", r["file"], rep.findings());
        assert!(rep.timed && rep.pose_at_file_s);
        // Its duration is its file's last t; its ROS 2 message exists.
        let dur = num(r, "duration_s");
        assert_eq!(dur, last_t(&out.join(&r["file"])), "{}", r["file"]);
        assert!(out.join(&r["ros2_file"]).is_file());
        // The move into it: from the last run's last row to this run's first row, checked
        // (self, scene, limits, speeds); a reconfiguration holds the straight rod's end pose.
        let first = file.row(0).to_vec();
        let kind = r["transition"].as_str();
        kinds.insert(kind.to_string());
        match kind {
            "start" => assert_eq!(k, 0),
            "none" => assert_eq!(prev_end.as_deref(), Some(&first[..])),
            "reconfigure_at_straight" | "unclamp_move" => {
                let mv = read_joint_file(&out.join(&r["transition_file"]), &names).unwrap();
                let rep = checker.check(&mv, &CheckOptions::default()).unwrap();
                assert_eq!(rep.finding_mask(), 0, "{kind}: {:?}", rep.findings());
                let close =
                    |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9);
                assert!(
                    close(mv.row(0), prev_end.as_deref().unwrap()),
                    "{kind} start"
                );
                assert!(close(mv.row(mv.rows() - 1), &first), "{kind} end");
                assert!(
                    (last_t(&out.join(&r["transition_file"])) - num(r, "transition_s")).abs()
                        < 1e-9
                );
                if kind == "reconfigure_at_straight" {
                    assert_eq!(num(r, "handling_s"), 0.0);
                    for i in 0..mv.rows() {
                        let p = planner.tool_pose(mv.row(i));
                        let dp = (p.translation.vector - straight.translation.vector).norm();
                        let dr = (p.rotation.inverse() * straight.rotation).angle();
                        assert!(dp < 1e-5 && dr < 1e-5, "row {i}: {dp} m, {dr} rad");
                    }
                } else {
                    assert!(num(r, "handling_s") > 0.0);
                }
            }
            other => panic!("unexpected move `{other}`"),
        }
        prev_end = Some(file.row(file.rows() - 1).to_vec());
        // Sessions, recomputed from the list: a run starts after its move; a new session
        // starts with the move.
        let pre = num(r, "transition_s") + num(r, "handling_s");
        let s = num(r, "session") as usize;
        if s != session {
            assert_eq!(s, session + 1);
            session = s;
            clock = 0.0;
        }
        clock += pre;
        assert!((num(r, "start_s") - clock).abs() < 1e-6, "{r:?}");
        clock += dur;
        let e = session_len.entry(s).or_insert((0.0, 0));
        *e = (clock, e.1 + 1);
    }
    // By the ladder these three rays need both kinds of move (so both are checked above).
    if search == "ladder" {
        assert!(
            kinds.contains("reconfigure_at_straight") && kinds.contains("unclamp_move"),
            "{kinds:?}"
        );
    }
    for (s, (len, n)) in &session_len {
        assert!(
            *len <= session_h * 3600.0 + 1e-6 || *n == 1,
            "session {s}: {len} s, {n} runs"
        );
    }
    // The total is the sum of the list.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("campaign.json")).unwrap()).unwrap();
    let total: f64 = session_len.values().map(|v| v.0).sum();
    assert!((summary["total_s"].as_f64().unwrap() - total).abs() < 1e-6);
    assert_eq!(
        summary["sessions"].as_array().unwrap().len(),
        session_len.len()
    );
    assert!(session_len.len() >= 2, "{session_len:?}");
    assert!(out.join("timeline.png").is_file());
    // The partial ray: listed with its cause, no files.
    let bad: Vec<&Row> = list.iter().filter(|r| r["order"].is_empty()).collect();
    assert_eq!(bad.len(), 1);
    assert_eq!(
        (bad[0]["class"].as_str(), bad[0]["cause"].as_str()),
        ("partial", "no_ik")
    );
    assert!(bad[0]["file"].is_empty() && bad[0]["session"].is_empty());
    let files: Vec<String> = std::fs::read_dir(out.join("runs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!files.iter().any(|f| f.starts_with("d000")), "{files:?}");
    assert_eq!(files.len(), 3 * 4, "{files:?}");

    // A finished campaign is refused; --resume plans nothing again and writes the same list.
    let args = [
        "--quiet",
        "campaign",
        "--search",
        search,
        "--directions",
        dirs.to_str().unwrap(),
        "--session-hours",
        "0.25",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = helixreach(&args);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--resume"));
    let before = std::fs::read(out.join("campaign.csv")).unwrap();
    // A file an earlier campaign left in runs/ is removed; the run files stay.
    std::fs::write(out.join("runs/d999.csv"), "t\n0\n").unwrap();
    let mut resumed = args.to_vec();
    resumed.push("--resume");
    let o = helixreach(&resumed);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read(out.join("campaign.csv")).unwrap(), before);
    assert!(!out.join("runs/d999.csv").exists());
    assert_eq!(std::fs::read_dir(out.join("runs")).unwrap().count(), 3 * 4);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("campaign.json")).unwrap()).unwrap();
    assert_eq!(
        (summary["computed"].as_u64(), summary["resumed"].as_u64()),
        (Some(0), Some(4))
    );
}

#[test]
fn no_testable_ray_exits_3_and_lists_the_cause() {
    let tmp = tempfile::tempdir().unwrap();
    let dirs = directions_file(tmp.path(), &[PARTIAL_RAY]);
    let out = tmp.path().join("camp");
    let o = helixreach(&[
        "--quiet",
        "campaign",
        "--directions",
        dirs.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        o.status.code(),
        Some(3),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let list = read_csv(&out.join("campaign.csv"));
    assert_eq!(list.len(), 1);
    assert_eq!(list[0]["cause"], "no_ik");
}

#[test]
fn a_bad_direction_row_names_file_line_and_value_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let dirs = directions_file(tmp.path(), &[TESTABLE[0], "0.5,zero,0.5", TESTABLE[1]]);
    let out = tmp.path().join("camp");
    let o = helixreach(&[
        "campaign",
        "--directions",
        dirs.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!("{}:3", dirs.display())) && err.contains("zero"),
        "{err}"
    );
    assert!(!out.exists());
}

/// A layout folder by hand: placement 1 the seed rig, placement 2 its clamp 5 cm along y.
fn layout(dir: &Path, second_rig: bool) {
    let rig = Rig::load("sawyer-seed").unwrap();
    std::fs::write(dir.join("placement_1.toml"), rig.to_toml().unwrap()).unwrap();
    let o = rig.clamp.translation.vector;
    if second_rig {
        let moved = rig.with_clamp_origin([o.x, o.y + 0.05, o.z]).unwrap();
        std::fs::write(dir.join("placement_2.toml"), moved.to_toml().unwrap()).unwrap();
    }
    std::fs::write(
        dir.join("placements.csv"),
        "placement,candidate,x,y,z,tilt_deg,heading_deg,covered,new,cumulative,\
         cumulative_fraction,rig_file\n\
         1,0,0.85,-0.15,-0.144,0,0,2,2,2,0.5,placement_1.toml\n\
         2,1,0.85,-0.1,-0.144,0,0,1,1,3,0.75,placement_2.toml\n",
    )
    .unwrap();
    let mut a = String::from("dir_kappa,dir_tau,dir_omega,placement,azimuth,class,s_reached\n");
    a.push_str(&format!("{},2,0,testable,8\n", TESTABLE[0]));
    a.push_str(&format!("{},1,0,testable,15\n", TESTABLE[1]));
    a.push_str(&format!("{},1,0,testable,9\n", TESTABLE[2]));
    a.push_str(&format!("{PARTIAL_RAY},,,partial,2.1\n"));
    std::fs::write(dir.join("assignment.csv"), a).unwrap();
}

#[test]
fn a_layout_campaign_groups_runs_by_placement() {
    let tmp = tempfile::tempdir().unwrap();
    let lay = tmp.path().join("lay");
    std::fs::create_dir(&lay).unwrap();
    layout(&lay, true);
    let out = tmp.path().join("camp");
    let o = helixreach(&[
        "--quiet",
        "campaign",
        "--layout",
        lay.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let list = read_csv(&out.join("campaign.csv"));
    let placements: Vec<&str> = list.iter().map(|r| r["placement"].as_str()).collect();
    let moves: Vec<&str> = list.iter().map(|r| r["transition"].as_str()).collect();
    assert_eq!(placements, ["1", "1", "2", ""], "{list:?}");
    assert_eq!(moves[2], "clamp_move", "{moves:?}");
    assert_eq!(num(&list[2], "handling_s"), 900.0);
    assert!((num(&list[2], "clamp_y") + 0.1).abs() < 1e-12);
    assert_eq!(list[3]["cause"], "no_placement_tests_it");
    // Placement 2's run passes check on placement 2's rig.
    let rig2 = Rig::load(lay.join("placement_2.toml").to_str().unwrap()).unwrap();
    let checker = Checker::new(rig2).unwrap();
    let r = &list[2];
    let file = read_joint_file(&out.join(&r["file"]), &checker.joint_names()).unwrap();
    let opt = CheckOptions {
        direction: Some(
            helixreach::directions::Direction::new(
                num(r, "dir_kappa"),
                num(r, "dir_tau"),
                num(r, "dir_omega"),
            )
            .unwrap(),
        ),
        azimuth: num(r, "azimuth"),
        ..CheckOptions::default()
    };
    assert_eq!(checker.check(&file, &opt).unwrap().finding_mask(), 0);
}

#[test]
fn a_layout_with_a_missing_rig_file_is_an_error_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let lay = tmp.path().join("lay");
    std::fs::create_dir(&lay).unwrap();
    layout(&lay, false);
    let out = tmp.path().join("camp");
    let o = helixreach(&[
        "campaign",
        "--layout",
        lay.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!("{}:3", lay.join("placements.csv").display()))
            && err.contains("rig_file")
            && err.contains("placement_2.toml"),
        "{err}"
    );
    assert!(!out.exists());
}

/// The campaign folder is the same for one and two threads: the run list, the totals and every
/// run and move file.
#[test]
fn the_same_campaign_for_one_and_two_threads() {
    let tmp = tempfile::tempdir().unwrap();
    let dirs = directions_file(tmp.path(), &TESTABLE);
    let mut folders = Vec::new();
    for n in ["1", "2"] {
        let out = tmp.path().join(format!("camp{n}"));
        let o = helixreach(&[
            "--quiet",
            "--threads",
            n,
            "campaign",
            "--directions",
            dirs.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        folders.push(out);
    }
    let list = read_csv(&folders[0].join("campaign.csv"));
    let mut files = vec!["campaign.csv".to_string(), "rays.csv".to_string()];
    for r in &list {
        for k in ["file", "ros2_file", "transition_file"] {
            if !r[k].is_empty() {
                files.push(r[k].clone());
            }
        }
    }
    assert!(files.len() >= 8, "{files:?}");
    for f in &files {
        assert_eq!(
            std::fs::read(folders[0].join(f)).unwrap(),
            std::fs::read(folders[1].join(f)).unwrap(),
            "{f}"
        );
    }
    let json = |d: &Path| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join("campaign.json")).unwrap()).unwrap()
    };
    assert_eq!(json(&folders[0])["total_s"], json(&folders[1])["total_s"]);
}
