//! The records of a test campaign (`helixreach campaign --out DIR`,
//! [`crate::experiment::campaign`]): the ray sweep `rays.csv` ([`RayRunRecord`], what the sweep
//! driver checkpoints and `--resume` reads back) and the run list `campaign.csv`
//! ([`CampaignRecord`], the runs in execution order, then the rays that are not testable); a
//! move between runs ([`transition_csv`]); the layout folder a campaign reads ([`read_layout`]).
//!
//! Positions are metres in the robot base frame, times seconds, angles radians; numbers by
//! [`fmt_real`]; a value that does not apply is an empty field.

use super::csv_out::{self, CsvRecord};
use super::fmt_real;
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use crate::planning::campaign::{Assigned, LayoutInput, Transition};
use crate::records::columns::{Column, Kind};
use std::path::Path;

/// One planned ray of `rays.csv`. The key is the first four columns.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RayRunRecord {
    /// Placement (1-based; 1 for a single rig).
    pub placement: usize,
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// `testable`, `partial`, `blocked` or `undecided`.
    pub class: String,
    /// Blocking cause; empty for testable rays.
    pub cause: String,
    /// The boundary s* (`inf`: none).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// Farthest s reached.
    #[serde(serialize_with = "csv_out::real")]
    pub s_reached: Real,
    /// Azimuth of the plan (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub azimuth: Real,
    /// Duration of the run (s, the last `t` of its CSV); empty when not testable.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub duration_s: Option<Real>,
    /// Motor angle at the start (rad); empty when not testable.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub motor_start: Option<Real>,
    /// Joints at the start (s = 0), space-separated (rad); empty when not testable.
    pub q_start: String,
    /// Joints at the end (s = 0 again), space-separated (rad); empty when not testable.
    pub q_end: String,
    /// The run's trajectory CSV, relative to the campaign folder; empty when not testable.
    pub file: String,
}

impl CsvRecord for RayRunRecord {
    const HEADER: &'static [&'static str] = &[
        "placement",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "class",
        "cause",
        "s_star",
        "s_reached",
        "azimuth",
        "duration_s",
        "motor_start",
        "q_start",
        "q_end",
        "file",
    ];
}

/// Number of key columns of [`RayRunRecord`] (`placement,dir_kappa,dir_tau,dir_omega`).
pub const RAY_RUN_KEY_COLUMNS: usize = 4;

/// The columns of [`RayRunRecord`] that the shared column table does not define, with their
/// units and rules (for the sweep driver).
pub fn ray_run_columns() -> Vec<Column> {
    vec![
        Column::new("placement", "", Kind::Count, "placement (1-based)"),
        Column::new("class", "", Kind::Text, "reachability class"),
        Column::new(
            "cause",
            "",
            Kind::Text,
            "blocking cause; empty when testable",
        ),
        Column::new(
            "duration_s",
            "s",
            Kind::FiniteOrEmpty,
            "duration of the run (last t of its CSV)",
        ),
        Column::new(
            "motor_start",
            "rad",
            Kind::FiniteOrEmpty,
            "motor angle at the start",
        ),
        Column::new("q_start", "rad", Kind::Text, "joints at the start"),
        Column::new("q_end", "rad", Kind::Text, "joints at the end"),
        Column::new("file", "", Kind::Text, "the run's trajectory CSV"),
    ]
}

/// One ray of `campaign.csv`: a run (in execution order) or a ray that is not testable (order,
/// session and times empty, `cause` says why).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CampaignRecord {
    /// Execution order (1-based); empty for a ray that is not testable.
    pub order: Option<usize>,
    /// Placement (1-based; 1 for a single rig); empty when no placement of a layout tests it.
    pub placement: Option<usize>,
    /// Clamp origin x (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_x: Option<Real>,
    /// Clamp origin y (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_y: Option<Real>,
    /// Clamp origin z (m).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub clamp_z: Option<Real>,
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
    /// The boundary s* (`inf`: none).
    #[serde(serialize_with = "csv_out::real")]
    pub s_star: Real,
    /// Farthest s reached (the target s*·(1 + margin) for a run).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_reached: Option<Real>,
    /// `testable`, `partial`, `blocked`, `undecided` (or the layout's class).
    pub class: String,
    /// Why the ray is not testable; empty for a run.
    pub cause: String,
    /// Azimuth of the plan (rad); empty when not planned.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub azimuth: Option<Real>,
    /// Duration of the run (s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub duration_s: Option<Real>,
    /// The move into this run: `start`, `none`, `reconfigure_at_straight`, `unclamp_move`,
    /// `clamp_move` or `blocked`.
    pub transition: String,
    /// Robot motion time of that move (s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub transition_s: Option<Real>,
    /// Stated handling time of that move (unclamping, moving the clamp; s).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub handling_s: Option<Real>,
    /// Session (1-based).
    pub session: Option<usize>,
    /// Start of the run from the start of its session (s; after its transition).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub start_s: Option<Real>,
    /// The run's trajectory CSV (relative to the campaign folder).
    pub file: String,
    /// The run's ROS 2 `JointTrajectory` JSON.
    pub ros2_file: String,
    /// The move's joint trajectory CSV (`t,q…,motor`), when it moves.
    pub transition_file: String,
}

impl CsvRecord for CampaignRecord {
    const HEADER: &'static [&'static str] = &[
        "order",
        "placement",
        "clamp_x",
        "clamp_y",
        "clamp_z",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_star",
        "s_reached",
        "class",
        "cause",
        "azimuth",
        "duration_s",
        "transition",
        "transition_s",
        "handling_s",
        "session",
        "start_s",
        "file",
        "ros2_file",
        "transition_file",
    ];
}

/// The move `t` as a joint CSV `t,<joint names>,motor` (what `helixreach check` reads, timed).
pub fn transition_csv(t: &Transition, joint_names: &[String]) -> String {
    let mut s = String::from("t");
    for name in joint_names {
        s.push(',');
        s.push_str(name);
    }
    s.push_str(",motor\n");
    for (t, q, m) in &t.points {
        s.push_str(&fmt_real(*t));
        for x in q {
            s.push(',');
            s.push_str(&fmt_real(*x));
        }
        s.push(',');
        s.push_str(&fmt_real(*m));
        s.push('\n');
    }
    s
}

/// Joints as the space-separated text of `rays.csv`.
pub fn joints_text(q: &[Real]) -> String {
    q.iter().map(|x| fmt_real(*x)).collect::<Vec<_>>().join(" ")
}

/// Joints from the space-separated text of `rays.csv` (`what` names the field in errors).
pub fn parse_joints(text: &str, what: &str) -> Result<Vec<Real>> {
    text.split_whitespace()
        .map(|x| match x.parse::<Real>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(Error::invalid(what, x, "not a finite number")),
        })
        .collect()
}

/// Read `DIR/placements.csv` and `DIR/assignment.csv` (the layout input of [`crate::planning::campaign`]). Errors name the file, the
/// line, the field and the value: a rig file that does not exist, a placement number out of
/// order, an assignment to a placement not listed, a bad number or direction.
pub fn read_layout(dir: &Path) -> Result<LayoutInput> {
    let pf = dir.join("placements.csv");
    if !pf.is_file() {
        return Err(Error::File {
            path: pf,
            reason: "does not exist: not a `helixreach layout` folder".into(),
        });
    }
    let mut t = crate::io::CsvInput::open(&pf)?;
    let (ip, ir) = (t.column("placement", "")?, t.column("rig_file", "")?);
    let mut rig_files = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| crate::io::bad_line(&pf, line, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, line);
        let p = rec.get(ip).unwrap_or("");
        if p.parse::<usize>().ok() != Some(rig_files.len() + 1) {
            return Err(crate::io::bad_line(
                &pf,
                line,
                "placement",
                format!(
                    "`{p}`: expected {} (placements numbered 1, 2, … in order)",
                    rig_files.len() + 1
                ),
            ));
        }
        let name = rec.get(ir).unwrap_or("");
        let path = dir.join(name);
        if name.is_empty() || !path.is_file() {
            return Err(crate::io::bad_line(
                &pf,
                line,
                "rig_file",
                format!("`{name}`: {} does not exist", path.display()),
            ));
        }
        rig_files.push(path);
    }
    if rig_files.is_empty() {
        return Err(t.file_error("no placements".into()));
    }
    let af = dir.join("assignment.csv");
    let mut t = crate::io::CsvInput::open(&af)?;
    let hint = "an assignment.csv of helixreach layout";
    let cols = [
        t.column("dir_kappa", hint)?,
        t.column("dir_tau", hint)?,
        t.column("dir_omega", hint)?,
    ];
    let (ip, ia, ic, is) = (
        t.column("placement", hint)?,
        t.column("azimuth", hint)?,
        t.column("class", hint)?,
        t.column("s_reached", hint)?,
    );
    let mut assigned = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let line = k + 2;
        let rec = rec.map_err(|e| crate::io::bad_line(&af, line, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, line);
        let mut v = [0.0; 3];
        for (x, (&c, name)) in
            v.iter_mut()
                .zip(cols.iter().zip(["dir_kappa", "dir_tau", "dir_omega"]))
        {
            *x = crate::io::parse_field(&af, line, &rec, c, name)?;
        }
        let dir = Direction::new(v[0], v[1], v[2])
            .map_err(|e| crate::io::bad_line(&af, line, "direction", e.to_string()))?;
        let opt_num = |c: usize, name: &str| -> Result<Option<Real>> {
            match rec.get(c).unwrap_or("") {
                "" => Ok(None),
                _ => {
                    let x = crate::io::parse_field(&af, line, &rec, c, name)?;
                    if x.is_finite() {
                        Ok(Some(x))
                    } else {
                        Err(crate::io::bad_line(
                            &af,
                            line,
                            name,
                            format!("`{x}` is not finite"),
                        ))
                    }
                }
            }
        };
        let placement = match rec.get(ip).unwrap_or("") {
            "" => None,
            p => match p.parse::<usize>() {
                Ok(n) if (1..=rig_files.len()).contains(&n) => Some(n),
                _ => {
                    return Err(crate::io::bad_line(
                        &af,
                        line,
                        "placement",
                        format!(
                            "`{p}`: not a placement of {} (1..={})",
                            pf.display(),
                            rig_files.len()
                        ),
                    ))
                }
            },
        };
        assigned.push(Assigned {
            dir,
            placement,
            azimuth: opt_num(ia, "azimuth")?,
            class: rec.get(ic).unwrap_or("").to_string(),
            s_reached: opt_num(is, "s_reached")?,
        });
    }
    if assigned.is_empty() {
        return Err(t.file_error("no directions".into()));
    }
    Ok(LayoutInput {
        rig_files,
        assigned,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use csv_out::{fields, header_matches};

    #[test]
    fn headers_name_the_fields_in_order() {
        let ray = RayRunRecord {
            placement: 1,
            dir_kappa: 0.6,
            dir_tau: 0.8,
            dir_omega: 0.0,
            class: "testable".into(),
            cause: String::new(),
            s_star: 5.0,
            s_reached: 5.5,
            azimuth: 0.0,
            duration_s: Some(12.5),
            motor_start: Some(0.0),
            q_start: "0 1".into(),
            q_end: "0 1".into(),
            file: "runs/d000.csv".into(),
        };
        header_matches(&ray);
        assert_eq!(fields(&ray).unwrap()[9], "12.5");
        let row = CampaignRecord {
            order: None,
            placement: Some(1),
            clamp_x: Some(0.8),
            clamp_y: Some(0.0),
            clamp_z: Some(0.1),
            dir_kappa: 1.0,
            dir_tau: 0.0,
            dir_omega: 0.0,
            s_star: Real::INFINITY,
            s_reached: Some(0.0),
            class: "blocked".into(),
            cause: "no_ik".into(),
            azimuth: None,
            duration_s: None,
            transition: String::new(),
            transition_s: None,
            handling_s: None,
            session: None,
            start_s: None,
            file: String::new(),
            ros2_file: String::new(),
            transition_file: String::new(),
        };
        header_matches(&row);
        let f = fields(&row).unwrap();
        assert_eq!(
            (f[0].as_str(), f[8].as_str(), f[13].as_str()),
            ("", "inf", "")
        );
    }
}
