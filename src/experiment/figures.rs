//! Stage 6 (feature `plots`): the figures of a study, PNG and SVG, from its typed outcomes, and
//! `speed_error.csv`; with a planned trajectory also the render strip of robot, rod and scene
//! ([`crate::plot::render::render_trajectory`]: `render_strip.png`/`.svg`, `render_frames.csv`).

use super::{paper_directions, write, Log, StudyReport};
use crate::directions::Direction;
use crate::error::Result;
use crate::planning::rig::Rig;
use crate::plot;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Outcome of [`figures`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figures {
    /// Files written (PNG and SVG twins), relative to the output directory.
    pub files: Vec<String>,
}

/// Draw every figure whose stage finished; a figure that cannot be drawn fails the stage.
pub fn figures(report: &StudyReport, out: &Path, log: &Log) -> Result<Figures> {
    let mut files = Vec::new();
    let mut render_files = Vec::new();
    let mut figure = |stem: &str, f: &dyn Fn(&Path) -> Result<()>| -> Result<()> {
        for ext in ["png", "svg"] {
            let name = format!("{stem}.{ext}");
            f(&out.join(&name))?;
            files.push(name);
        }
        log.say("figures", format!("{stem} drawn"));
        Ok(())
    };
    if let Some(c) = &report.continuum {
        figure("boundary3d", &|p| plot::boundary3d::render(&c.rows, p))?;
        let reach_fan = report
            .reach
            .as_ref()
            .map(|r| r.fan.clone())
            .unwrap_or_default();
        figure("section", &|p| plot::section::render(&c.fan, &reach_fan, p))?;
    }
    if let Some(r) = &report.reach {
        let marked: Vec<Direction> = paper_directions().iter().map(|d| d.1).collect();
        figure("directions", &|p| {
            plot::direction_map::render(&r.rows, &marked, "paper's directions", p)
        })?;
    }
    if let Some(d) = report.dynamics.as_ref().filter(|d| !d.series.is_empty()) {
        figure("error_vs_s", &|p| plot::error_vs_s::render(&d.series, p))?;
    }
    if let Some(t) = &report.trajectory {
        let opts = plot::trajectory::TrajectoryOptions {
            limits: t.limits.clone(),
            s_star: Some(t.s_star),
            subtitle: t.subtitle.clone(),
        };
        figure("trajectory", &|p| {
            plot::trajectory::render(&t.rows, &opts, p)
        })?;
        // The robot, rod and scene along the same trajectory (issue 14): the strip of
        // snapshots at s = 0, ¼, ½, ¾ of s*, s*, the end and every reconfiguration.
        let rig = Rig::load(&report.settings.rig)?;
        let strip = plot::render::render_trajectory(
            &rig,
            &out.join("trajectory.csv"),
            &plot::render::TrajectoryRender::default(),
            out,
        )?;
        for p in [&strip.strip_png, &strip.strip_svg] {
            let name = p.file_name().unwrap_or_default().to_string_lossy();
            render_files.push(name.into_owned());
        }
        log.say("figures", "render_strip drawn");
    }
    let rows = report.speed_rows();
    if !rows.is_empty() {
        let mut csv =
            String::from("method,resolution,time_per_direction_s,max_rel_err,median_rel_err\n");
        for r in &rows {
            let _ = writeln!(
                csv,
                "{},{},{},{},{}",
                r.method, r.resolution, r.time_per_direction_s, r.max_rel_err, r.median_rel_err
            );
        }
        write(out, "speed_error.csv", &csv)?;
        figure("speed_error", &|p| plot::speed_error::render(&rows, p))?;
    }
    files.extend(render_files);
    Ok(Figures { files })
}
