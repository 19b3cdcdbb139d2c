//! The search of the valid set on arms other than the seed's, against a second method, on the
//! rigs `rig init` writes: Baxter's right arm (7-DOF, a collision model of 39 primitives with
//! tight clearances, with its SRDF), the Panda (7-DOF, mesh hulls), the UR5 and the Jaco2
//! (6-DOF). The
//! ladder drives each ray to its `s_reached` by a path whose every point and step it checks
//! (limits, collisions, the joint-step bound), so the search — whose partial answer says no
//! path leaves its reachable piece — must reach every whole slice the ladder reaches, and be
//! testable where the ladder is.

mod common;

use common::robots::{self, ARMS};
use helixreach::directions::fibonacci;
use helixreach::planning::planner::{Planner, ReachClass};
use helixreach::planning::pose_path::{pose_path, Ray, Spacing};
use helixreach::planning::rig::{Rig, RollMode, SearchMethod};
use helixreach::planning::rig_init::{rig_init, RigInitOptions};

/// The rig `helixreach rig init` writes for the vendored arm `name` (Baxter with
/// `--srdf baxter_manipulation.srdf`: without it no clamp is found; the Jaco2 (`kinova`) with
/// `--srdf kinova.srdf --rod-length 0.3`: at the default length no clamp candidate holds the
/// straight rod without collision), at the command's defaults otherwise.
fn rig_of(name: &str, dir: &std::path::Path) -> Rig {
    let arm = ARMS.iter().find(|a| a.name == name).unwrap();
    let urdf = robots::urdf(arm);
    let srdf = match name {
        "baxter_right" => Some("srdf/baxter_manipulation.srdf"),
        "kinova" => Some("srdf/kinova.srdf"),
        _ => None,
    }
    .map(|f| urdf.parent().unwrap().parent().unwrap().join(f));
    let opts = RigInitOptions {
        robot: urdf.to_str().unwrap().to_string(),
        tip_link: arm.tip.to_string(),
        package_paths: vec![robots::package_dir()],
        no_collision: Vec::new(),
        srdf,
        name: name.to_string(),
        tool_offset: 0.1,
        padding: 0.005,
        rod_length: (name == "kinova").then_some(0.3),
        par: helixreach::par::Par::from_option(None).unwrap(),
    };
    rig_init(&opts, dir).unwrap().rig
}

/// The search against the ladder on `n` quarter-sphere rays of the rig of arm `name` (roll
/// `fixed`, margin 0.1, the rig's defaults otherwise): asserts that the search is testable
/// wherever the ladder is, and returns the number of rays the ladder leaves partial and those
/// (direction index, search slice, ladder slice) where the search's farthest slice is before
/// the last slice at or below the ladder's `s_reached` (the ladder refines between slices, so
/// its s may lie inside the next interval).
fn behind_the_ladder(name: &str, n: usize) -> (usize, Vec<(usize, usize, usize)>) {
    let dir = tempfile::tempdir().unwrap();
    let rig = rig_of(name, dir.path());
    let mut exact_rig = rig.clone();
    exact_rig.planner.search = SearchMethod::Exact;
    let mut ladder_rig = rig.clone();
    ladder_rig.planner.search = SearchMethod::Ladder;
    let (exact, ladder) = (
        Planner::new(exact_rig).unwrap(),
        Planner::new(ladder_rig).unwrap(),
    );
    let margin = rig.planner.margin;
    let mut behind = Vec::new();
    let mut partial = 0;
    for (k, d) in fibonacci(n, true).unwrap().iter().enumerate() {
        let s_star = helixreach::sweep::reach::s_star_of(d, None).unwrap();
        let e = exact
            .plan_ray(d, s_star, 0.0, RollMode::Fixed, false)
            .unwrap();
        let l = ladder
            .plan_ray(d, s_star, 0.0, RollMode::Fixed, false)
            .unwrap();
        if l.class == ReachClass::Testable {
            assert_eq!(
                e.class,
                ReachClass::Testable,
                "{name}, direction {k}: {d:?}"
            );
            continue;
        }
        partial += 1;
        let ray = Ray {
            dir: [d.kappa, d.tau, d.omega],
            azimuth: 0.0,
        };
        let wps = pose_path(&rig, &ray, s_star * (1.0 + margin), &Spacing::of(&rig)).unwrap();
        let slice_at = |s: f64| wps.iter().rposition(|w| w.s <= s + 1e-12).unwrap();
        let (se, sl) = (slice_at(e.s_reached), slice_at(l.s_reached));
        if se < sl {
            behind.push((k, se, sl));
        }
    }
    (partial, behind)
}

/// Baxter's right arm, 100 rays: the search is never behind the ladder. A load track that
/// lands in collision is continued along the landing slice's self-motion to the nearest valid
/// configuration within the joint-step bound (`search::linking`, "Landing"): without that, the
/// search stops 1–4 slices before the ladder on 13 of these rays (direction 65: slice 28,
/// the ladder 32, which it reaches by tracks with the redundancy joint locked next to the
/// minimum-norm one); with landings sampled every half of the bound instead of every quarter,
/// on 1 (direction 66: 29, the ladder 31).
#[test]
fn the_search_reaches_every_slice_the_ladder_reaches_on_baxter() {
    let (partial, behind) = behind_the_ladder("baxter_right", 100);
    assert!(partial >= 50, "{partial} rays the ladder leaves partial");
    assert!(
        behind.is_empty(),
        "rays (direction, search slice, ladder slice) where the search stops before the ladder: \
         {behind:?}"
    );
}

/// The same on the Panda (7-DOF, mesh hulls), the UR5 and the Jaco2 (6-DOF: finitely many
/// configurations per slice, no landings; the Jaco2 with mesh hulls and continuous joints), 50 rays
/// each.
#[test]
fn the_search_reaches_every_slice_the_ladder_reaches_on_panda_ur5_and_jaco2() {
    for name in ["panda", "ur5", "kinova"] {
        let (partial, behind) = behind_the_ladder(name, 50);
        assert!(
            partial >= 20,
            "{name}: {partial} rays the ladder leaves partial"
        );
        assert!(behind.is_empty(), "{name}: {behind:?}");
    }
}
