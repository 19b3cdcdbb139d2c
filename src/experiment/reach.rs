//! Stage 3: reachability of the experiment's quarter-sphere (and of the ω = 0 fan, for the
//! section figure) in both roll modes, on the sweep driver.

use super::{omega0_fan, write, Log, Settings};
use crate::directions::{fibonacci, Direction};
use crate::error::Result;
use crate::planning::planner::Planner;
use crate::planning::rig::{Rig, RollMode};
use crate::records::{self, ReachClass, ReachRow};
use crate::sweep::driver::SweepOptions;
use crate::sweep::reach::{self as sweep_reach, ReachOptions, REACH_HEADER};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::Instant;

/// Class counts of one roll mode over the quarter-sphere.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RollSummary {
    /// Directions planned.
    pub directions: usize,
    /// Testable directions.
    pub testable: usize,
    /// Partial directions.
    pub partial: usize,
    /// Blocked directions.
    pub blocked: usize,
    /// Directions whose search hit its node bound (`planner.max_search_nodes`): neither proven
    /// testable nor proven partial.
    pub undecided: usize,
    /// `testable / directions`.
    pub fraction_testable: f64,
    /// `partial / directions`.
    pub fraction_partial: f64,
    /// `blocked / directions`.
    pub fraction_blocked: f64,
    /// `undecided / directions`.
    pub fraction_undecided: f64,
    /// Directions per blocking cause (partial and blocked rays).
    pub causes: BTreeMap<String, usize>,
    /// Azimuths tried per ray.
    pub azimuths: Vec<f64>,
    /// Wall time of the quarter-sphere sweep (0 for rows resumed from an earlier run).
    pub wall_seconds: f64,
}

/// Outcome of [`reach_survey`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReachSurvey {
    /// Roll mode `fixed` (the paper's scheme).
    pub roll_fixed: RollSummary,
    /// Roll mode `motor`.
    pub roll_motor: RollSummary,
    /// Quarter-sphere rows of both modes (as in `reach.csv`: `fixed` first).
    #[serde(skip)]
    pub rows: Vec<ReachRow>,
    /// ω = 0 fan rows of both modes (as in `reach_omega0.csv`).
    #[serde(skip)]
    pub fan: Vec<ReachRow>,
}

impl RollSummary {
    /// The class and cause counts of `rows` (one roll mode), tried at `azimuths`, swept in
    /// `wall` seconds.
    pub fn of(rows: &[ReachRow], azimuths: &[f64], wall: f64) -> RollSummary {
        let count = |c: ReachClass| rows.iter().filter(|r| r.class == c).count();
        let mut causes: BTreeMap<String, usize> = BTreeMap::new();
        for cause in rows.iter().filter_map(|r| r.cause) {
            *causes.entry(cause.as_str().to_string()).or_default() += 1;
        }
        let n = rows.len() as f64;
        let (t, p, b, u) = (
            count(ReachClass::Testable),
            count(ReachClass::Partial),
            count(ReachClass::Blocked),
            count(ReachClass::Undecided),
        );
        RollSummary {
            directions: rows.len(),
            testable: t,
            partial: p,
            blocked: b,
            undecided: u,
            fraction_testable: t as f64 / n,
            fraction_partial: p as f64 / n,
            fraction_blocked: b as f64 / n,
            fraction_undecided: u as f64 / n,
            causes,
            azimuths: azimuths.to_vec(),
            wall_seconds: wall,
        }
    }
}

/// One driver sweep of `dirs` into `out/name` (checkpointed, resumable), read back as rows.
fn sweep(
    planner: &Planner,
    dirs: &[Direction],
    opts: &ReachOptions,
    path: &Path,
    resume: bool,
    log: &Log,
) -> Result<(Vec<ReachRow>, String)> {
    let mut so = SweepOptions::new(path, REACH_HEADER, 3);
    // A rerun of the study replaces its earlier sweeps (only once each is complete), unless it
    // resumes them; resume refuses rows made with other settings (the driver's record).
    so.resume = resume;
    so.force = !resume;
    so.progress = log.shows();
    sweep_reach::run(planner, dirs, None, opts, &so)?;
    let text = std::fs::read_to_string(path).map_err(|source| crate::Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    Ok((records::read_reach(path)?, text))
}

/// Stage 3: plan every quarter-sphere direction (boundary from the continuum test) in roll
/// modes `fixed` and `motor`, azimuth 0, and the ω = 0 fan likewise. Each (set, mode) is one
/// sweep-driver run into `reach_{fixed,motor}.csv` / `reach_omega0_{fixed,motor}.csv`
/// (checkpointed; `resume` keeps finished rows); their concatenations are `reach.csv` and
/// `reach_omega0.csv`. A planner error fails the stage (naming the direction).
pub fn reach_survey(st: &Settings, out: &Path, resume: bool, log: &Log) -> Result<ReachSurvey> {
    let rig = Rig::load(&st.rig)?;
    let planner = Planner::new(rig)?;
    let quarter = fibonacci(st.reach_directions, true)?;
    let fan: Vec<Direction> = omega0_fan(st.reach_fan_directions);
    let mut csv = REACH_HEADER.join(",") + "\n";
    let mut fan_csv = csv.clone();
    let mut rows = Vec::new();
    let mut fan_rows = Vec::new();
    let mut summaries = Vec::new();
    for (label, roll) in [("fixed", RollMode::Fixed), ("motor", RollMode::Motor)] {
        let opts = ReachOptions {
            roll,
            azimuths: vec![0.0],
        };
        let t = Instant::now();
        let (r, text) = sweep(
            &planner,
            &quarter,
            &opts,
            &out.join(format!("reach_{label}.csv")),
            resume,
            log,
        )?;
        let wall = t.elapsed().as_secs_f64();
        let (f, ftext) = sweep(
            &planner,
            &fan,
            &opts,
            &out.join(format!("reach_omega0_{label}.csv")),
            resume,
            log,
        )?;
        let s = RollSummary::of(&r, &opts.azimuths, wall);
        log.say(
            "reachability",
            format!(
                "roll {label}: {:.1} % testable, {:.1} % partial, {:.1} % blocked, {:.1} % undecided \
                 ({} directions, {wall:.1} s)",
                100.0 * s.fraction_testable,
                100.0 * s.fraction_partial,
                100.0 * s.fraction_blocked,
                100.0 * s.fraction_undecided,
                s.directions
            ),
        );
        // Concatenate the rows (without the repeated header).
        let body = |t: &str| -> String { t.lines().skip(1).map(|l| format!("{l}\n")).collect() };
        csv.push_str(&body(&text));
        fan_csv.push_str(&body(&ftext));
        rows.extend(r);
        fan_rows.extend(f);
        summaries.push(s);
    }
    write(out, "reach.csv", &csv)?;
    write(out, "reach_omega0.csv", &fan_csv)?;
    let roll_motor = summaries.pop().expect("two roll modes");
    let roll_fixed = summaries.pop().expect("two roll modes");
    Ok(ReachSurvey {
        roll_fixed,
        roll_motor,
        rows,
        fan: fan_rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planning::cause::BlockCause;

    /// Every direction is counted in exactly one class: the four counts sum to the directions
    /// and the four fractions to 1, with rays of every class (undecided included) and causes
    /// counted for the partial and blocked rays only.
    #[test]
    fn summary_counts_every_class() {
        let dir = Direction::new(1.0, 0.0, 0.0).unwrap();
        let row = |class, cause| ReachRow {
            dir,
            s_star: 8.0,
            s_reached: 4.0,
            class,
            cause,
            roll_mode: "motor".into(),
        };
        let mut rows = vec![row(ReachClass::Testable, None); 5];
        rows.extend(vec![
            row(ReachClass::Partial, Some(BlockCause::JointLimit));
            3
        ]);
        rows.push(row(ReachClass::Blocked, Some(BlockCause::NoIk)));
        rows.extend(vec![row(ReachClass::Undecided, None); 2]);
        let s = RollSummary::of(&rows, &[0.0], 1.0);
        assert_eq!(
            (s.testable, s.partial, s.blocked, s.undecided),
            (5, 3, 1, 2)
        );
        assert_eq!(s.directions, 11);
        let f =
            s.fraction_testable + s.fraction_partial + s.fraction_blocked + s.fraction_undecided;
        assert!((f - 1.0).abs() < 1e-15, "{f}");
        assert_eq!(s.causes.values().sum::<usize>(), 4);
    }
}
