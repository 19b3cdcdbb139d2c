//! Stage 5: one planned trajectory with the joint limits.

use super::{paper_directions, write, Settings};
use crate::boundary::continuum;
use crate::error::{Error, Result};
use crate::math::tol;
use crate::planning::planner::{Planner, RayPlan, ReachClass};
use crate::planning::rig::{Rig, RollMode};
use crate::records::{JointLimit, TrajectoryRow};
use serde::Serialize;
use std::path::Path;

/// Outcome of [`trajectory`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlannedTrajectory {
    /// The paper's name of the direction planned.
    pub direction: String,
    /// Roll mode (`fixed`).
    pub roll_mode: String,
    /// Reach class of the plan.
    pub class: String,
    /// Continuum s* of the direction.
    pub s_star: f64,
    /// Farthest s planned.
    pub s_reached: f64,
    /// Waypoints of the trajectory.
    pub waypoints: usize,
    /// Largest joint step between waypoints (rad).
    pub max_joint_step_rad: f64,
    /// Path cost Σ‖Δθ‖.
    pub path_cost: f64,
    /// Duration of the time-parametrized trajectory (s).
    pub duration_s: f64,
    /// The waypoints (as in `trajectory.csv`).
    #[serde(skip)]
    pub rows: Vec<TrajectoryRow>,
    /// Joint limits (and the motor's, when finite), as in `joint_limits.csv`.
    #[serde(skip)]
    pub limits: Vec<JointLimit>,
    /// Figure subtitle.
    #[serde(skip)]
    pub subtitle: String,
}

/// Stage 5: plan the first paper direction that is testable in roll mode `fixed` (else the one
/// reaching farthest relative to its end) → `trajectory.csv`, `trajectory.json`,
/// `joint_limits.csv`. Fails when every paper direction is blocked.
pub fn trajectory(st: &Settings, out: &Path) -> Result<PlannedTrajectory> {
    let rig = Rig::load(&st.rig)?;
    let planner = Planner::new(rig.clone())?;
    let mut best: Option<(String, RayPlan)> = None;
    for (name, d) in paper_directions() {
        let s = continuum::critical_s(&d, tol::S_STAR_REL)?.s_star;
        let p = planner.plan_best(&d, s, &[0.0], RollMode::Fixed, true)?;
        let better = best
            .as_ref()
            .is_none_or(|(_, b)| p.s_reached / p.s_end > b.s_reached / b.s_end);
        if better {
            best = Some((name.to_string(), p));
        }
        if best
            .as_ref()
            .is_some_and(|b| b.1.class == ReachClass::Testable)
        {
            break;
        }
    }
    let Some((name, plan)) = best else {
        return Err(Error::invalid(
            "paper directions",
            "[]",
            "no paper direction could be planned",
        ));
    };
    if plan.s_reached <= 0.0 {
        return Err(Error::invalid(
            "rig",
            &st.rig,
            format!("every paper direction is blocked in roll mode fixed ({name})"),
        ));
    }
    let traj = planner.trajectory(&plan)?;
    write(
        out,
        "trajectory.csv",
        &crate::records::trajectory::trajectory_csv(&traj)?,
    )?;
    write(
        out,
        "trajectory.json",
        &crate::records::trajectory::trajectory_json(&traj)?,
    )?;
    let meta = crate::records::trajectory::trajectory_meta_json(&traj)?;
    write(out, "trajectory.csv.meta.json", &meta)?;
    write(out, "trajectory.json.meta.json", &meta)?;
    let mut limits: Vec<JointLimit> = planner
        .model()
        .joints()
        .iter()
        .map(|j| JointLimit {
            name: j.name.clone(),
            lower: j.lower,
            upper: j.upper,
        })
        .collect();
    if rig.motor.range.0.is_finite() && rig.motor.range.1.is_finite() {
        limits.push(JointLimit {
            name: "motor".into(),
            lower: rig.motor.range.0,
            upper: rig.motor.range.1,
        });
    }
    write(
        out,
        "joint_limits.csv",
        &crate::records::csv_out::to_csv(&limits)?,
    )?;
    let rows: Vec<TrajectoryRow> = traj
        .points
        .iter()
        .map(|p| TrajectoryRow {
            t: p.t,
            s: p.s,
            q: p.q.clone(),
            motor: p.motor,
        })
        .collect();
    Ok(PlannedTrajectory {
        direction: name.clone(),
        roll_mode: "fixed".into(),
        class: plan.class.as_str().to_string(),
        s_star: plan.s_star,
        s_reached: plan.s_reached,
        waypoints: rows.len(),
        max_joint_step_rad: plan.max_joint_step,
        path_cost: plan.path_cost,
        duration_s: traj.duration(),
        rows,
        limits,
        subtitle: format!("{name}, roll mode fixed"),
    })
}
