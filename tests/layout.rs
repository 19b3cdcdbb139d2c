//! Rig layout: set cover against exhaustive enumeration, the reach bound against FK,
//! rig files round-tripped, the layout's coverage recounted by the reach sweep from the written
//! rig files, no-feasible-clamp reports, resume rules and bad input.

use helixreach::directions::Direction;
use helixreach::layout::candidates::{grid, Candidate, Region};
use helixreach::layout::precheck::ReachBound;
use helixreach::layout::set_cover::{brute_force, exact, greedy, BitSet};
use helixreach::layout::{run, LayoutOptions, Reference, RunControl};
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::Rig;
use helixreach::robot::RobotModel;
use helixreach::sweep::driver::SweepOptions;
use helixreach::sweep::reach::{self, ReachOptions, REACH_HEADER};
use proptest::prelude::*;
use rand::SeedableRng;
use std::path::Path;

fn sets_of(n: usize, lists: &[Vec<usize>]) -> Vec<BitSet> {
    lists.iter().map(|l| BitSet::from_indices(n, l)).collect()
}

// ---------------------------------------------------------------------------------------------
// Set cover.

#[test]
fn greedy_equals_brute_force_on_a_small_instance() {
    // Nested-ish sets where greedy's first pick is part of the optimum.
    let sets = sets_of(
        10,
        &[
            vec![0, 1, 2, 3, 4],
            vec![4, 5, 6],
            vec![6, 7, 8, 9],
            vec![0, 9],
            vec![2, 3],
        ],
    );
    for k in 1..=4 {
        let b = brute_force(&sets, k);
        assert_eq!(greedy(&sets, k).covered, b.covered, "k = {k}");
        let e = exact(&sets, k, 1_000_000);
        assert!(e.proven);
        assert_eq!(e.covered, b.covered, "k = {k}");
    }
    assert_eq!(brute_force(&sets, 2).covered, 9);
    assert_eq!(brute_force(&sets, 3).covered, 10);
}

#[test]
fn exact_beats_greedy_where_greedy_is_suboptimal() {
    // Greedy takes the big middle set, then can only add 2; the two halves cover all 8.
    let sets = sets_of(
        8,
        &[vec![1, 2, 3, 4, 5, 6], vec![0, 1, 2, 3], vec![4, 5, 6, 7]],
    );
    assert_eq!(greedy(&sets, 2).covered, 7);
    let e = exact(&sets, 2, 1_000);
    assert_eq!(
        (e.covered, e.chosen.clone(), e.proven),
        (8, vec![1, 2], true)
    );
    assert_eq!(brute_force(&sets, 2).covered, 8);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]
    #[test]
    fn greedy_le_exact_eq_exhaustive(
        n in 1usize..24,
        raw in prop::collection::vec(prop::collection::vec(0usize..24, 0..10), 1..9),
        k in 1usize..5,
    ) {
        let sets = sets_of(n, &raw);
        let b = brute_force(&sets, k);
        let e = exact(&sets, k, 10_000_000);
        let g = greedy(&sets, k);
        prop_assert!(e.proven);
        prop_assert_eq!(e.covered, b.covered);
        prop_assert!(g.covered <= b.covered);
        // The classic guarantee: greedy ≥ (1 − 1/e)·OPT.
        prop_assert!(g.covered as f64 >= (1.0 - (-1.0f64).exp()) * b.covered as f64 - 1e-9);
        // What `exact` reports is what its choice covers.
        let mut u = BitSet::new(n);
        for &i in &e.chosen { u.union_with(&sets[i]); }
        prop_assert_eq!(u.count(), e.covered);
        prop_assert!(e.chosen.len() <= k);
    }
}

// ---------------------------------------------------------------------------------------------
// Reach bound: every configuration's rod end lies inside it (FK), and it is not vacuous.

#[test]
fn reach_bound_contains_every_fk_and_is_tight() {
    for name in ["sawyer-seed", "panda-bench"] {
        let rig = Rig::load(name).unwrap();
        let model = RobotModel::load(&rig.robot.source(), Some(&rig.robot.tip_link)).unwrap();
        let planner = Planner::new(rig.clone()).unwrap();
        let b = ReachBound::of(&model, &rig);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut far: f64 = 0.0;
        for _ in 0..20_000 {
            let q = model.random_config(&mut rng);
            let p = planner.tool_pose(&q[..model.dof()]).translation.vector;
            let d = (p - b.centre).norm();
            assert!(
                d <= b.radius,
                "{name}: FK at {d} m outside the bound {} m",
                b.radius
            );
            far = far.max(d);
        }
        // Sampling finds configurations close to the bound (the bound is not loose).
        assert!(
            far > 0.85 * b.radius,
            "{name}: farthest {far} vs bound {}",
            b.radius
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Rig files.

#[test]
fn rig_toml_round_trip_of_a_tilted_placement() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let c = Candidate {
        origin: [0.8, -0.2, -0.1],
        tilt: 20f64.to_radians(),
        heading: 1.0,
    };
    let placed = c.place(&rig);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("p.toml");
    std::fs::write(&path, placed.to_toml().unwrap()).unwrap();
    let back = Rig::load(path.to_str().unwrap()).unwrap();
    assert!((back.clamp.translation.vector - placed.clamp.translation.vector).norm() < 1e-15);
    assert!((back.clamp_rotation() - placed.clamp_rotation()).norm() < 1e-12);
    assert!((back.tool.to_homogeneous() - placed.tool.to_homogeneous()).norm() < 1e-12);
    assert_eq!(back.planner, placed.planner);
    assert_eq!(back.obstacles, placed.obstacles);
    assert_eq!(back.rod, placed.rod);
    assert_eq!(back.azimuths, placed.azimuths);
    assert_eq!(back.roll, placed.roll);
    assert_eq!(back.motor.range, placed.motor.range);
    // The tilted clamp axis is what the candidate says.
    let d3 = back.clamp_rotation().column(2).into_owned();
    assert!((d3.z - 20f64.to_radians().cos()).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// The whole workflow on the seed rig, recounted independently.

fn seed_dirs() -> Vec<Direction> {
    // Three quarter-sphere directions testable on the seed rig's own clamp (`helixreach reach
    // --fibonacci 40 --quarter`), two of the seed's own (trajectories.csv).
    [
        (0.10165493399648305, 0.3375, -0.9358205086415721),
        (0.7777424488887131, 0.5125, -0.3639511412217134),
        (0.7612838590874295, 0.6375, -0.11849318922600945),
        (0.974555, 0.224148, 0.0),
        (0.845150, 0.416101, 0.335533),
    ]
    .iter()
    .map(|&(k, t, w)| Direction::new(k, t, w).unwrap())
    .collect()
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn layout_coverage_equals_reach_at_the_written_rigs() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let dirs = seed_dirs();
    let mut opts = LayoutOptions::around(&rig);
    opts.region = "0.8:0.85,-0.15:-0.15,-0.144:-0.144".parse().unwrap();
    opts.spacing = 0.05;
    opts.placements = 2;
    opts.references = vec![Reference {
        origin: [0.85, -0.1, -0.144],
        own: vec![0, 2],
    }];
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("lay");
    let control = RunControl::default();
    let rep = run(&rig, &dirs, None, &opts, &control, &out)
        .unwrap()
        .expect("not sharded");
    assert_eq!(rep.n_grid, 2);
    assert_eq!(rep.candidates.len(), 3);
    assert!(!rep.placements.is_empty());
    for f in [
        "rays.csv",
        "candidates.csv",
        "placements.csv",
        "assignment.csv",
        "coverage.csv",
        "reference.csv",
        "heatmap.png",
        "directions.png",
        "coverage.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    // Independent recount: every placement's rig file, loaded back, through the reach sweep.
    let mut union = BitSet::new(dirs.len());
    for p in &rep.placements {
        let placed = Rig::load(out.join(&p.rig_file).to_str().unwrap()).unwrap();
        let planner = Planner::new(placed.clone()).unwrap();
        let ro = ReachOptions {
            roll: placed.roll,
            azimuths: placed.azimuths.clone(),
        };
        let csv = tmp.path().join(format!("reach-{}.csv", p.candidate));
        reach::run(
            &planner,
            &dirs,
            None,
            &ro,
            &SweepOptions::new(&csv, REACH_HEADER, 3),
        )
        .unwrap();
        let text = read(&csv);
        let testable: Vec<usize> = text
            .lines()
            .skip(1)
            .enumerate()
            .filter(|(_, l)| l.split(',').nth(5) == Some("testable"))
            .map(|(i, _)| i)
            .collect();
        assert_eq!(
            testable.len(),
            p.covered,
            "placement {:?}: reach says {testable:?}",
            p.pose
        );
        assert_eq!(testable.len(), rep.covered[p.candidate]);
        for &i in &testable {
            union.insert(i);
        }
    }
    assert_eq!(union.count(), rep.placements.last().unwrap().cumulative);
    // The assignment gives each covered direction a placement that tests it.
    let assign = read(&out.join("assignment.csv"));
    let assigned = assign
        .lines()
        .skip(1)
        .filter(|l| l.split(',').nth(5) == Some("testable"))
        .count();
    assert_eq!(assigned, union.count());
    assert!(assign.starts_with("dir_kappa,dir_tau,dir_omega,placement,azimuth,class,s_reached\n"));
    // The seed rig's own clamp tests some of these directions.
    assert!(rep.covered[1] >= 1, "seed clamp covers {:?}", rep.covered);

    // Resume: everything is taken from rays.csv, the outputs are the same.
    let before = read(&out.join("placements.csv"));
    let control = RunControl {
        resume: true,
        ..RunControl::default()
    };
    run(&rig, &dirs, None, &opts, &control, &out).unwrap();
    assert_eq!(read(&out.join("placements.csv")), before);
    // Without --resume an existing run is not replaced.
    let e = run(&rig, &dirs, None, &opts, &RunControl::default(), &out).unwrap_err();
    assert!(e.to_string().contains("refusing to overwrite"), "{e}");
    // A resume with other settings is refused.
    let mut other = opts.clone();
    other.region = "0.8:0.85,-0.2:-0.2,-0.144:-0.144".parse().unwrap();
    let e = run(&rig, &dirs, None, &other, &control, &out).unwrap_err();
    assert!(e.to_string().contains("other settings"), "{e}");
}

#[test]
fn a_region_out_of_reach_is_reported_not_an_error() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let dirs = seed_dirs();
    let mut opts = LayoutOptions::around(&rig);
    opts.region = "3:3.1,0:0.1,0:0".parse().unwrap();
    opts.spacing = 0.1;
    let tmp = tempfile::tempdir().unwrap();
    let rep = run(&rig, &dirs, None, &opts, &RunControl::default(), tmp.path())
        .unwrap()
        .unwrap();
    assert_eq!(rep.candidates.len(), 4);
    assert!(rep.covered.iter().all(|&c| c == 0));
    assert!(rep.placements.is_empty());
    assert_eq!(
        rep.decided,
        vec![("reach_bound".to_string(), 4 * dirs.len())]
    );
    assert!((rep.cheap_fraction() - 1.0).abs() < 1e-15);
    let assign = read(&tmp.path().join("assignment.csv"));
    assert_eq!(assign.lines().count(), 1 + dirs.len());
    assert!(
        assign
            .lines()
            .skip(1)
            .all(|l| l.contains(",,,unreachable,")),
        "{assign}"
    );
    assert!(tmp.path().join("heatmap.png").is_file());
}

/// The placement kind the sweep reports (what decides a placement's rays) agrees with the
/// reach bound and the planner asked directly, and with the rows it writes.
#[test]
fn placement_kind_agrees_with_the_planner_and_the_rows() {
    use helixreach::layout::evaluate::{PlacementKind, Sweep};
    let rig = Rig::load("sawyer-seed").unwrap();
    let dirs = vec![seed_dirs()[0]];
    let at = |x: f64, y: f64, z: f64| Candidate {
        origin: [x, y, z],
        tilt: 0.0,
        heading: 0.0,
    };
    let o = rig.clamp.translation.vector;
    // Far away; a corner of the seed grid whose straight rod has no valid configuration
    // (seen in full layout runs); the rig's own clamp.
    let cands = vec![at(3.0, 0.0, 0.0), at(0.9, -0.35, -0.145), at(o.x, o.y, o.z)];
    let sweep = Sweep::new(
        helixreach::par::Par::all(),
        &rig,
        &cands,
        &dirs,
        None,
        rig.roll,
        rig.azimuths.clone(),
    )
    .unwrap();
    let kinds: Vec<PlacementKind> = (0..3).map(|c| sweep.placement_kind(c).unwrap()).collect();
    assert_eq!(
        kinds,
        vec![
            PlacementKind::OutOfReach,
            PlacementKind::NoStart,
            PlacementKind::Ready
        ]
    );
    assert!(sweep.bound().straight_out_of_reach(&cands[0].place(&rig)));
    let err = Planner::new(cands[1].place(&rig)).unwrap_err().to_string();
    assert!(err.contains("unreachable clamp"), "{err}");
    assert!(Planner::new(cands[2].place(&rig)).is_ok());
    // Rows of the placements decided once: their decided_by says so.
    assert_eq!(sweep.row(&(0, 0)).unwrap().decided_by, "reach_bound");
    assert_eq!(sweep.row(&(1, 0)).unwrap().decided_by, "clamp");
}

#[test]
fn bad_input_is_a_clear_error() {
    let rig = Rig::load("sawyer-seed").unwrap();
    let dirs = seed_dirs();
    let tmp = tempfile::tempdir().unwrap();
    let base = LayoutOptions::around(&rig);
    let err = |o: &LayoutOptions| {
        run(&rig, &dirs, None, o, &RunControl::default(), tmp.path())
            .unwrap_err()
            .to_string()
    };
    let mut o = base.clone();
    o.placements = 0;
    assert!(err(&o).contains("placements"));
    let mut o = base.clone();
    o.spacing = 0.0;
    assert!(err(&o).contains("spacing"));
    let mut o = base.clone();
    o.spacing = -0.1;
    assert!(err(&o).contains("spacing"));
    let mut o = base.clone();
    o.spacing = f64::NAN;
    assert!(err(&o).contains("spacing"));
    let mut o = base.clone();
    o.margin = Some(f64::NAN);
    assert!(err(&o).contains("margin"));
    let mut o = base.clone();
    o.tilts_deg = vec![f64::NAN];
    assert!(err(&o).contains("tilts"));
    let e = run(&rig, &[], None, &base, &RunControl::default(), tmp.path()).unwrap_err();
    assert!(e.to_string().contains("directions"), "{e}");
    for bad in ["0.9:0.8,0:0,0:0", "0:nan,0:0,0:0", "0:1,0:1", "0:1,a:b,0:0"] {
        let e = bad.parse::<Region>().unwrap_err().to_string();
        assert!(e.contains("region") && e.contains(bad), "{e}");
    }
    assert!(grid(&"0:1,0:1,0:1".parse().unwrap(), 1e-3, &[0.0], 1)
        .unwrap_err()
        .to_string()
        .contains("at most"));
    // Nothing was written for rejected input.
    assert!(!tmp.path().join("rays.csv").exists());
    // The CLI says the same, with exit code 2.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_helixreach"))
        .args(["layout", "--fibonacci", "4", "--spacing", "0", "--out"])
        .arg(tmp.path().join("cli"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("spacing"));
}

#[test]
fn end_pose_check_rules_out_only_untestable_rays() {
    // Candidate (0.80, −0.30) at the seed clamp's height: the five `seed_dirs` and three
    // low-τ quarter-sphere directions (`--fibonacci 2000 --quarter`, items 1, 2, 3) whose end
    // pose the sampled pointwise test finds without a valid configuration there.
    let rig = Rig::load("sawyer-seed").unwrap();
    let mut dirs = seed_dirs();
    for (k, t, w) in [
        (0.9320321616790715, 0.00075, 0.362374788162528),
        (0.6754897665345254, 0.00125, -0.7373683020086585),
        (0.4424703040121164, 0.00175, 0.8967814491655284),
    ] {
        dirs.push(Direction::new(k, t, w).unwrap());
    }
    let mut opts = LayoutOptions::around(&rig);
    opts.region = "0.8:0.8,-0.3:-0.3,-0.145:-0.145".parse().unwrap();
    opts.placements = 1;
    let tmp = tempfile::tempdir().unwrap();
    let rays = |check: bool| {
        let mut o = opts.clone();
        o.end_pose_check = check;
        let out = tmp.path().join(format!("check-{check}"));
        let rep = run(&rig, &dirs, None, &o, &RunControl::default(), &out)
            .unwrap()
            .unwrap();
        let text = read(&out.join("rays.csv"));
        let rows: Vec<(String, String)> = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                (f[4].to_string(), f[9].to_string())
            })
            .collect();
        (rep, rows)
    };
    let (with, rows_with) = rays(true);
    let (without, rows_without) = rays(false);
    assert_eq!(rows_with.len(), dirs.len());
    // The check decided the three low-τ rays, and the full planner, run on them, agrees that
    // they are not testable; every other ray is planned, with the same answer.
    let decided: Vec<usize> = (0..dirs.len())
        .filter(|&i| rows_with[i].1 == "end_pose")
        .collect();
    assert_eq!(decided, vec![5, 6, 7], "{rows_with:?}");
    for i in 0..dirs.len() {
        if decided.contains(&i) {
            assert_eq!(rows_with[i].0, "unreachable");
            assert_ne!(rows_without[i].0, "testable", "ray {i}: {rows_without:?}");
        } else {
            assert_eq!(rows_with[i], rows_without[i], "ray {i}");
        }
    }
    assert_eq!(with.covered, without.covered);
    assert!(with.covered[0] >= 1, "{:?}", with.covered);
    assert!(with.decided.contains(&("end_pose".to_string(), 3)));
    assert!(!without.decided.iter().any(|(k, _)| k == "end_pose"));
    // The planner's own test directly: valid at the end of every ray it plans testable.
    let placed = rig.with_clamp_origin([0.8, -0.3, -0.145]).unwrap();
    let planner = Planner::new(placed).unwrap();
    for (i, d) in dirs.iter().enumerate() {
        if rows_without[i].0 == "testable" {
            let s_star = helixreach::sweep::reach::s_star_of(d, None).unwrap();
            assert_eq!(planner.end_pose_valid(d, s_star, 0.0).unwrap(), Some(true));
        }
    }
}

/// `layout --search exact` decides every ray by the search: the written placement rig says so,
/// and its coverage equals an independent `reach` by the search at that rig; a bad `--search`
/// value is an error naming the flag (exit 2) and writes nothing.
#[test]
fn layout_search_flag_decides_by_the_search() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("lay");
    let dirs_csv = tmp.path().join("dirs.csv");
    let dirs = seed_dirs();
    let mut text = String::from("dir_kappa,dir_tau,dir_omega\n");
    for d in &dirs {
        text.push_str(&format!("{:?},{:?},{:?}\n", d.kappa, d.tau, d.omega));
    }
    std::fs::write(&dirs_csv, text).unwrap();
    let cli = |search: &str, out: &Path| {
        std::process::Command::new(env!("CARGO_BIN_EXE_helixreach"))
            .args(["--quiet", "layout", "--directions"])
            .arg(&dirs_csv)
            .args([
                "--region",
                "0.85:0.85,-0.1:-0.1,-0.144:-0.144",
                "--placements",
                "1",
                "--search",
                search,
                "--out",
            ])
            .arg(out)
            .output()
            .unwrap()
    };
    let o = cli("exact", &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let placements = read(&out.join("placements.csv"));
    let row = placements.lines().nth(1).expect("one placement");
    let head: Vec<&str> = placements.lines().next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let fields: Vec<&str> = row.split(',').collect();
    let covered: usize = fields[col("covered")].parse().unwrap();
    let placed = Rig::load(out.join(fields[col("rig_file")]).to_str().unwrap()).unwrap();
    assert_eq!(
        placed.planner.search,
        helixreach::planning::rig::SearchMethod::Exact
    );
    let planner = Planner::new(placed.clone()).unwrap();
    let testable = dirs
        .iter()
        .filter(|d| {
            let s = helixreach::boundary::continuum::critical_s(d, 1e-10)
                .unwrap()
                .s_star;
            planner
                .plan_best(d, s, &placed.azimuths, placed.roll, false)
                .unwrap()
                .class
                == helixreach::planning::planner::ReachClass::Testable
        })
        .count();
    assert_eq!(covered, testable);
    let bad = tmp.path().join("bad");
    let o = cli("fast", &bad);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--search"));
    assert!(!bad.exists());
}
