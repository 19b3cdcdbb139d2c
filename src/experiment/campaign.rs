//! The whole campaign into a folder ([`run_campaign`]; the domain is
//! [`crate::planning::campaign`], the files the records of `records::campaign`): the ray sweep (`rays.csv`, resumable through
//! [`crate::sweep::driver`], the run files written atomically as each ray is planned), then the
//! order, the moves, the sessions and the outputs.
//!
//! # Outputs in the campaign folder
//! | file | holds |
//! |---|---|
//! | `rays.csv` (+ `.meta.json` settings record) | every planned ray: class, cause, duration, start and end joints ([`RayRunRecord`]) |
//! | `runs/<name>.csv` (+ `.meta.json`) | a run's trajectory, as `helixreach plan` writes it |
//! | `runs/<name>.json` (+ `.meta.json`) | the arm's ROS 2 `trajectory_msgs/msg/JointTrajectory` |
//! | `transitions/<order>.csv` | the move into run `order` (`t`, the joints by URDF name, `motor`), when the robot moves |
//! | `campaign.csv` | the runs in execution order, then the rays that are not testable ([`CampaignRecord`]) |
//! | `campaign.json` | the totals ([`CampaignSummary`]) |
//! | `timeline.png` | the sessions (`plot::campaign_timeline`; with the `plots` feature) |
//!
//! `<name>` is `d<i>` (i the 0-based index of the direction in the input set, three digits at
//! least), `p<k>_d<i>` for placement k of a layout. Resuming (`resume`) continues `rays.csv`
//! (its checkpoint) when its settings record matches, and recomputes the rest (order, moves,
//! sessions: the session length and handling times may change between resumes); `force`
//! replaces a finished campaign. Files in `runs/` and `transitions/` that the new run list does
//! not name are removed once it is written.

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::io::Output;
use crate::math::Real;
use crate::par::Par;
use crate::planning::campaign::{
    move_time, order_tour, plan_run, plan_transition, schedule, Handling, TimelineBar, Transition,
    TransitionKind,
};
use crate::planning::planner::{Planner, ReachClass};
use crate::planning::rig::RollMode;
use crate::records::campaign::{
    joints_text, parse_joints, ray_run_columns, transition_csv, CampaignRecord, RayRunRecord,
    RAY_RUN_KEY_COLUMNS,
};
use crate::records::csv_out::{to_csv, CsvRecord};
use crate::records::fmt_real;
use crate::records::trajectory::{
    message_json, trajectory_meta_json, Channels, JointTrajectoryMsg,
};
use crate::sweep::driver::{self, SweepOptions};
use crate::sweep::reach::{s_star_of, BoundaryTable, ReachOptions};
use std::path::{Path, PathBuf};

/// A ray to plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Ray {
    /// Placement (1-based).
    pub placement: usize,
    /// The direction.
    pub dir: Direction,
    /// Azimuths to try (the best is kept).
    pub azimuths: Vec<Real>,
    /// The stem of its run files (module docs).
    pub name: String,
}

/// A ray listed without planning (a layout direction no placement tests).
#[derive(Debug, Clone, PartialEq)]
pub struct Unplanned {
    /// The direction.
    pub dir: Direction,
    /// Its class.
    pub class: String,
    /// The farthest s known.
    pub s_reached: Option<Real>,
    /// Why it is not planned.
    pub cause: String,
}

/// What a campaign plans.
#[derive(Debug)]
pub struct CampaignInput {
    /// One planner per placement (placement k is `planners[k − 1]`).
    pub planners: Vec<Planner>,
    /// The rays to plan, in input order.
    pub rays: Vec<Ray>,
    /// Rays listed without planning.
    pub unplanned: Vec<Unplanned>,
    /// Roll mode.
    pub roll: RollMode,
    /// s* per direction (default: the continuum test).
    pub boundary: Option<BoundaryTable>,
    /// Where the azimuths come from, for the settings record (`rig` or a layout's digest).
    pub azimuth_source: String,
}

/// How a campaign runs.
#[derive(Debug, Clone)]
pub struct CampaignOptions {
    /// The campaign folder.
    pub out: PathBuf,
    /// Continue a campaign in `out`.
    pub resume: bool,
    /// Replace a campaign in `out`.
    pub force: bool,
    /// Between checkpoints of `rays.csv`.
    pub checkpoint_interval: std::time::Duration,
    /// Progress on stderr.
    pub progress: bool,
    /// Session length (s).
    pub session_s: Real,
    /// Handling times.
    pub handling: Handling,
    /// The parallelism of the ray sweep and of the moves.
    pub par: Par,
}

/// One session of [`CampaignSummary`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SessionSummary {
    /// Session (1-based).
    pub session: usize,
    /// Runs in it.
    pub runs: usize,
    /// Its length (s): runs, moves and handling.
    pub duration_s: Real,
}

/// The totals of a campaign (`campaign.json`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CampaignSummary {
    /// Rays considered (planned and listed).
    pub rays: usize,
    /// Testable rays: the runs.
    pub runs: usize,
    /// Rays that are not testable.
    pub not_testable: usize,
    /// Placements (clamp positions).
    pub placements: usize,
    /// Σ run durations (s).
    pub run_s: Real,
    /// Σ robot motion time of the moves between runs (s).
    pub transition_s: Real,
    /// Σ stated handling times (s).
    pub handling_s: Real,
    /// Total robot time (s): runs + moves + handling.
    pub total_s: Real,
    /// The same in hours.
    pub total_h: Real,
    /// Moves by kind.
    pub transitions: std::collections::BTreeMap<String, usize>,
    /// Handling time per unclamp move and per clamp move (s).
    pub unclamp_s: Real,
    /// Handling time per clamp move (s).
    pub clamp_move_s: Real,
    /// Σ of the move time bound over consecutive runs in input order and in the chosen order
    /// (s; what the ordering minimizes, [`move_time`]).
    pub order_bound_input_s: Real,
    /// See `order_bound_input_s`.
    pub order_bound_chosen_s: Real,
    /// Session length (s).
    pub session_s: Real,
    /// The sessions.
    pub sessions: Vec<SessionSummary>,
    /// Rays computed in this run and taken from an earlier one (`--resume`).
    pub computed: usize,
    /// See `computed`.
    pub resumed: usize,
}

const RUNS_DIR: &str = "runs";
const TRANSITIONS_DIR: &str = "transitions";

/// The settings record of `rays.csv`: per placement what `helixreach reach` records (rig
/// digest, robot files, roll, azimuths, margins, boundary source), and the azimuth source.
fn settings(input: &CampaignInput, base: SweepOptions) -> SweepOptions {
    let mut out = base;
    for (k, p) in input.planners.iter().enumerate() {
        let one = crate::sweep::reach::settings(
            p,
            input.boundary.as_ref(),
            &ReachOptions {
                roll: input.roll,
                azimuths: p.rig().azimuths.clone(),
            },
            &SweepOptions::new(&out.out, &["x"], 1),
        );
        for (name, value) in one.settings {
            let name = if k == 0 {
                name
            } else {
                format!("{name}_placement_{}", k + 1)
            };
            out = out.setting(&name, value);
        }
    }
    out.sweep("campaign")
        .setting("placements", input.planners.len())
        .setting("azimuth_source", &input.azimuth_source)
}

/// Plan one ray, write its run files when testable, and give its `rays.csv` row.
fn plan_one(input: &CampaignInput, ray: &Ray, folder: &Path) -> Result<RayRunRecord> {
    let planner = &input.planners[ray.placement - 1];
    let s_star = s_star_of(&ray.dir, input.boundary.as_ref())?;
    let plan = plan_run(planner, &ray.dir, s_star, &ray.azimuths, input.roll)?;
    let mut rec = RayRunRecord {
        placement: ray.placement,
        dir_kappa: ray.dir.kappa,
        dir_tau: ray.dir.tau,
        dir_omega: ray.dir.omega,
        class: plan.class.as_str().to_string(),
        cause: plan.cause.map_or(String::new(), |c| c.as_str().to_string()),
        s_star,
        s_reached: plan.s_reached,
        azimuth: plan.azimuth,
        duration_s: None,
        motor_start: None,
        q_start: String::new(),
        q_end: String::new(),
        file: String::new(),
    };
    if plan.class == ReachClass::Testable {
        let traj = planner.trajectory(&plan)?;
        let (Some(first), Some(last)) = (traj.points.first(), traj.points.last()) else {
            return Err(Error::invalid("trajectory", &ray.name, "no points"));
        };
        let rel = format!("{RUNS_DIR}/{}.csv", ray.name);
        let meta = trajectory_meta_json(&traj)?;
        let csv = crate::records::trajectory::trajectory_csv(&traj)?;
        let msg = message_json(&JointTrajectoryMsg::new(&traj, Channels::Arm)?)?;
        // Written again identically when a killed run is resumed: replacing is allowed.
        Output::new(folder.join(&rel))
            .force(true)
            .write_with_sidecar(csv.as_bytes(), meta.as_bytes())?;
        Output::new(folder.join(format!("{RUNS_DIR}/{}.json", ray.name)))
            .force(true)
            .write_with_sidecar(msg.as_bytes(), meta.as_bytes())?;
        rec.duration_s = Some(traj.duration());
        rec.motor_start = Some(first.motor);
        rec.q_start = joints_text(&first.q);
        rec.q_end = joints_text(&last.q);
        rec.file = rel;
    }
    Ok(rec)
}

/// A `rays.csv` row read back.
struct Planned {
    placement: usize,
    dir: Direction,
    class: String,
    cause: String,
    s_star: Real,
    s_reached: Real,
    azimuth: Real,
    run: Option<RunEnds>,
    file: String,
}

struct RunEnds {
    duration: Real,
    motor: Real,
    q_start: Vec<Real>,
    q_end: Vec<Real>,
}

fn read_rays(path: &Path) -> Result<Vec<Planned>> {
    let mut t = crate::io::CsvInput::open(path)?;
    let mut col = std::collections::HashMap::new();
    for name in RayRunRecord::HEADER {
        col.insert(*name, t.column(name, "")?);
    }
    let mut out = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| crate::io::bad_line(path, line, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, line);
        let text = |name: &str| rec.get(col[name]).unwrap_or("").to_string();
        let num = |name: &str| crate::io::parse_field(path, line, &rec, col[name], name);
        let bad = |name: &str, e: Error| crate::io::bad_line(path, line, name, e.to_string());
        let dir = Direction::new(num("dir_kappa")?, num("dir_tau")?, num("dir_omega")?)
            .map_err(|e| bad("direction", e))?;
        let placement = text("placement")
            .parse::<usize>()
            .map_err(|_| crate::io::bad_line(path, line, "placement", "not a count".into()))?;
        let run = if text("file").is_empty() {
            None
        } else {
            Some(RunEnds {
                duration: num("duration_s")?,
                motor: num("motor_start")?,
                q_start: parse_joints(&text("q_start"), "q_start")
                    .map_err(|e| bad("q_start", e))?,
                q_end: parse_joints(&text("q_end"), "q_end").map_err(|e| bad("q_end", e))?,
            })
        };
        out.push(Planned {
            placement,
            dir,
            class: text("class"),
            cause: text("cause"),
            s_star: num("s_star")?,
            s_reached: num("s_reached")?,
            azimuth: num("azimuth")?,
            run,
            file: text("file"),
        });
    }
    Ok(out)
}

/// Remove the files of `runs/` and `transitions/` that `rows` does not name (with their
/// sidecars): left by an earlier campaign in the folder (`force`, or a resume with another
/// session split). Only names this module writes (`.csv`, `.json`, `.meta.json`) are removed.
fn remove_stale(folder: &Path, rows: &[CampaignRecord]) -> Result<()> {
    let mut keep = std::collections::HashSet::new();
    for r in rows {
        for f in [&r.file, &r.ros2_file, &r.transition_file] {
            if !f.is_empty() {
                keep.insert(f.clone());
                keep.insert(format!("{f}.meta.json"));
            }
        }
    }
    for sub in [RUNS_DIR, TRANSITIONS_DIR] {
        let dir = folder.join(sub);
        let entries = std::fs::read_dir(&dir).map_err(|source| Error::Io {
            path: dir.clone(),
            source,
        })?;
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let ours = name.ends_with(".csv") || name.ends_with(".json");
            if ours && e.path().is_file() && !keep.contains(&format!("{sub}/{name}")) {
                std::fs::remove_file(e.path()).map_err(|source| Error::Io {
                    path: e.path(),
                    source,
                })?;
            }
        }
    }
    Ok(())
}

/// Run the campaign (module docs). Errors: the sweep's (an existing campaign without
/// `resume`/`force`, settings that differ on resume, a planner failure), and the writes.
pub fn run_campaign(input: &CampaignInput, opts: &CampaignOptions) -> Result<CampaignSummary> {
    let folder = &opts.out;
    let io_err = |path: &Path, source: std::io::Error| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    for sub in [RUNS_DIR, TRANSITIONS_DIR] {
        let d = folder.join(sub);
        std::fs::create_dir_all(&d).map_err(|e| io_err(&d, e))?;
    }
    let rays_csv = folder.join("rays.csv");
    let mut sweep = SweepOptions::new(&rays_csv, RayRunRecord::HEADER, RAY_RUN_KEY_COLUMNS);
    for c in ray_run_columns() {
        sweep = sweep.column(c);
    }
    sweep.resume = opts.resume;
    sweep.force = opts.force;
    sweep.checkpoint_interval = opts.checkpoint_interval;
    sweep.progress = opts.progress;
    sweep.par = opts.par;
    let sweep = settings(input, sweep);
    let done = driver::run(
        &input.rays,
        |r| {
            vec![
                r.placement.to_string(),
                fmt_real(r.dir.kappa),
                fmt_real(r.dir.tau),
                fmt_real(r.dir.omega),
            ]
        },
        |r| plan_one(input, r, folder),
        &sweep,
    )?;
    let planned = read_rays(&rays_csv)?;
    let limits: Vec<_> = input
        .planners
        .iter()
        .map(crate::planning::trajectory::timing_limits)
        .collect::<Result<_>>()?;

    // Order: placements in order, inside each a tour.
    let mut order: Vec<usize> = Vec::new();
    let (mut bound_input, mut bound_chosen) = (0.0, 0.0);
    for p in 1..=input.planners.len() {
        let idx: Vec<usize> = (0..planned.len())
            .filter(|&i| planned[i].placement == p && planned[i].run.is_some())
            .collect();
        let lim = &limits[p - 1];
        let cost = |a: usize, b: usize| {
            let (x, y) = (
                planned[idx[a]].run.as_ref().map(|r| (&r.q_end, r.motor)),
                planned[idx[b]].run.as_ref().map(|r| (&r.q_start, r.motor)),
            );
            match (x, y) {
                (Some((qa, ma)), Some((qb, mb))) => move_time(qa, ma, qb, mb, lim),
                _ => Real::INFINITY,
            }
        };
        let tour = order_tour(idx.len(), cost);
        let sum = |p: &[usize]| p.windows(2).map(|w| cost(w[0], w[1])).sum::<Real>();
        bound_input += sum(&(0..idx.len()).collect::<Vec<_>>());
        bound_chosen += sum(&tour);
        order.extend(tour.into_iter().map(|k| idx[k]));
    }

    // The moves, in parallel over the runs (each depends on its predecessor's end only).
    let transitions: Vec<Transition> = opts
        .par
        .map_range(order.len(), |k| {
            let cur = &planned[order[k]];
            let to = cur.run.as_ref().map(|r| (&r.q_start[..], r.motor));
            if k == 0 {
                return Ok(Transition {
                    kind: TransitionKind::Start,
                    motion_s: 0.0,
                    handling_s: 0.0,
                    points: Vec::new(),
                    cause: None,
                });
            }
            let prev = &planned[order[k - 1]];
            let from = prev.run.as_ref().map(|r| (&r.q_end[..], r.motor));
            let (Some(from), Some(to)) = (from, to) else {
                return Err(Error::invalid("campaign order", k, "a run without joints"));
            };
            plan_transition(
                &input.planners[cur.placement - 1],
                from,
                to,
                prev.placement != cur.placement,
                &opts.handling,
            )
        })?
        .into_iter()
        .collect::<Result<_>>()?;

    let blocks: Vec<(Real, Real)> = order
        .iter()
        .zip(&transitions)
        .map(|(&i, t)| {
            (
                t.motion_s + t.handling_s,
                planned[i].run.as_ref().map_or(0.0, |r| r.duration),
            )
        })
        .collect();
    let (slots, lengths) = schedule(&blocks, opts.session_s);

    // campaign.csv
    let clamp = |p: usize| input.planners[p - 1].rig().clamp.translation.vector;
    let mut rows: Vec<CampaignRecord> = Vec::new();
    let mut kinds = std::collections::BTreeMap::new();
    let mut bars = Vec::new();
    let joint_names: Vec<String> = input.planners[0]
        .model()
        .joints()
        .iter()
        .map(|j| j.name.clone())
        .collect();
    for (k, (&i, t)) in order.iter().zip(&transitions).enumerate() {
        let p = &planned[i];
        let c = clamp(p.placement);
        let run = p.run.as_ref();
        *kinds.entry(t.kind.as_str().to_string()).or_insert(0) += 1;
        let tfile = if t.points.len() > 1 {
            let rel = format!("{TRANSITIONS_DIR}/{:03}.csv", k + 1);
            Output::new(folder.join(&rel))
                .force(true)
                .write(transition_csv(t, &joint_names).as_bytes())?;
            rel
        } else {
            String::new()
        };
        let slot = slots[k];
        let pre = t.motion_s + t.handling_s;
        if pre > 0.0 {
            bars.push(TimelineBar {
                session: slot.session,
                start_s: slot.start_s - pre,
                end_s: slot.start_s,
                placement: None,
            });
        }
        let dur = run.map_or(0.0, |r| r.duration);
        bars.push(TimelineBar {
            session: slot.session,
            start_s: slot.start_s,
            end_s: slot.start_s + dur,
            placement: Some(p.placement),
        });
        rows.push(CampaignRecord {
            order: Some(k + 1),
            placement: Some(p.placement),
            clamp_x: Some(c.x),
            clamp_y: Some(c.y),
            clamp_z: Some(c.z),
            dir_kappa: p.dir.kappa,
            dir_tau: p.dir.tau,
            dir_omega: p.dir.omega,
            s_star: p.s_star,
            s_reached: Some(p.s_reached),
            class: p.class.clone(),
            cause: t
                .cause
                .map_or(String::new(), |c| format!("move blocked: {}", c.as_str())),
            azimuth: Some(p.azimuth),
            duration_s: Some(dur),
            transition: t.kind.as_str().to_string(),
            transition_s: Some(t.motion_s),
            handling_s: Some(t.handling_s),
            session: Some(slot.session),
            start_s: Some(slot.start_s),
            file: p.file.clone(),
            ros2_file: p.file.replace(".csv", ".json"),
            transition_file: tfile,
        });
    }
    let empty = |dir: Direction,
                 placement: Option<usize>,
                 class: String,
                 cause: String,
                 s_star: Real,
                 s_reached: Option<Real>,
                 azimuth: Option<Real>| {
        let c = placement.map(clamp);
        CampaignRecord {
            order: None,
            placement,
            clamp_x: c.map(|c| c.x),
            clamp_y: c.map(|c| c.y),
            clamp_z: c.map(|c| c.z),
            dir_kappa: dir.kappa,
            dir_tau: dir.tau,
            dir_omega: dir.omega,
            s_star,
            s_reached,
            class,
            cause,
            azimuth,
            duration_s: None,
            transition: String::new(),
            transition_s: None,
            handling_s: None,
            session: None,
            start_s: None,
            file: String::new(),
            ros2_file: String::new(),
            transition_file: String::new(),
        }
    };
    for p in planned.iter().filter(|p| p.run.is_none()) {
        rows.push(empty(
            p.dir,
            Some(p.placement),
            p.class.clone(),
            p.cause.clone(),
            p.s_star,
            Some(p.s_reached),
            Some(p.azimuth),
        ));
    }
    for u in &input.unplanned {
        let s_star = s_star_of(&u.dir, input.boundary.as_ref())?;
        rows.push(empty(
            u.dir,
            None,
            u.class.clone(),
            u.cause.clone(),
            s_star,
            u.s_reached,
            None,
        ));
    }
    let out = |name: &str| Output::new(folder.join(name)).force(true);
    out("campaign.csv").write(to_csv(&rows)?.as_bytes())?;
    remove_stale(folder, &rows)?;

    let run_s: Real = blocks.iter().map(|b| b.1).sum();
    let transition_s: Real = transitions.iter().map(|t| t.motion_s).sum();
    let handling_s: Real = transitions.iter().map(|t| t.handling_s).sum();
    let total_s = run_s + transition_s + handling_s;
    let summary = CampaignSummary {
        rays: planned.len() + input.unplanned.len(),
        runs: order.len(),
        not_testable: planned.len() - order.len() + input.unplanned.len(),
        placements: input.planners.len(),
        run_s,
        transition_s,
        handling_s,
        total_s,
        total_h: total_s / 3600.0,
        transitions: kinds,
        unclamp_s: opts.handling.unclamp_s,
        clamp_move_s: opts.handling.clamp_move_s,
        order_bound_input_s: bound_input,
        order_bound_chosen_s: bound_chosen,
        session_s: opts.session_s,
        sessions: lengths
            .iter()
            .enumerate()
            .map(|(k, &d)| SessionSummary {
                session: k + 1,
                runs: slots.iter().filter(|s| s.session == k + 1).count(),
                duration_s: d,
            })
            .collect(),
        computed: done.computed,
        resumed: done.resumed,
    };
    let json = serde_json::to_string_pretty(&summary)
        .map_err(|e| Error::invalid("campaign.json", "", e.to_string()))?;
    out("campaign.json").write(json.as_bytes())?;
    #[cfg(not(feature = "plots"))]
    let _ = &bars;
    #[cfg(feature = "plots")]
    if !bars.is_empty() {
        let png = folder.join("timeline.png");
        if png.exists() {
            std::fs::remove_file(&png).map_err(|e| io_err(&png, e))?;
        }
        crate::plot::campaign_timeline::render(&bars, opts.session_s, &png)?;
    }
    Ok(summary)
}
