//! Stage 6 (feature `plots`): the figures of a study, PNG and SVG, from its typed outcomes, and
//! `speed_error.csv`; with a planned trajectory also the render strip of robot, rod and scene
//! ([`crate::plot::render::render_trajectory`]: `render_strip.png`/`.svg`, `render_frames.csv`).
//!
//! The bifurcation map (`bifurcation_map.png`/`.svg`) needs no earlier stage: the
//! type of every direction of a quarter-sphere lattice is computed here
//! ([`crate::bifurcation::survey`]: [`BIFURCATION_QUICK`] in quick mode, [`BIFURCATION_FULL`]
//! otherwise), written to `bifurcation.csv` (the columns of `helixreach bifurcation`), and drawn
//! with the seed's 42 labelled directions marked.

use super::{paper_directions, write, Log, StudyReport};
use crate::directions::Direction;
use crate::error::Result;
use crate::planning::rig::Rig;
use crate::plot;
use serde::Serialize;
use std::path::Path;

/// The demo's bifurcation map in quick mode: (quarter-sphere directions, DER edges, static
/// return point).
pub const BIFURCATION_QUICK: (usize, usize, bool) = (24, 24, false);
/// The same in full mode.
pub const BIFURCATION_FULL: (usize, usize, bool) = (150, 50, true);

/// Draws one figure (PNG and SVG) by a renderer writing to a path.
type DrawFigure<'a> = dyn FnMut(&str, &dyn Fn(&Path) -> Result<()>) -> Result<()> + 'a;

/// Classify the quarter-sphere lattice of the demo's mode, write `bifurcation.csv`, and draw
/// the map with the seed's labels (see the module docs).
fn bifurcation_map(
    par: crate::par::Par,
    quick: bool,
    out: &Path,
    figure: &mut DrawFigure<'_>,
    log: &Log,
) -> Result<()> {
    use crate::bifurcation::{survey, BifurcationParams};
    let (n_dirs, n_edges, with_return) = if quick {
        BIFURCATION_QUICK
    } else {
        BIFURCATION_FULL
    };
    let dirs = crate::directions::fibonacci(n_dirs, true)?;
    let mut p = BifurcationParams::planning();
    p.der.n_edges = n_edges;
    p.statics_return = with_return;
    let t = std::time::Instant::now();
    let results = survey::survey(par, &dirs, &p)?;
    let resolution = format!("n={n_edges}");
    let records: Vec<crate::records::bifurcation::BifurcationRecord> = dirs
        .iter()
        .zip(&results)
        .map(|(d, b)| crate::records::bifurcation::BifurcationRecord::new(d, b, &resolution))
        .collect();
    let csv = crate::records::csv_out::to_csv(&records)?;
    write(out, "bifurcation.csv", &csv)?;
    let count = |k: &str| results.iter().filter(|b| b.kind.name() == k).count();
    log.say(
        "figures",
        format!(
            "bifurcation types of {n_dirs} quarter-sphere directions (DER n = {n_edges}): {} \
             subcritical, {} supercritical, {} degenerate in {:.1} s",
            count("subcritical"),
            count("supercritical"),
            count("degenerate"),
            t.elapsed().as_secs_f64()
        ),
    );
    let rows: Vec<_> = dirs
        .iter()
        .zip(&results)
        .map(|(d, b)| plot::bifurcation_map::BifurcationRow::from_result(*d, b))
        .collect();
    let labelled: Vec<_> = survey::seed_labels()?
        .iter()
        .map(plot::bifurcation_map::BifurcationRow::from_label)
        .collect();
    figure("bifurcation_map", &|p| {
        plot::bifurcation_map::render(&rows, &labelled, p)
    })
}

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
        // The robot, rod and scene along the same trajectory: the strip of
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
    bifurcation_map(
        report.settings.par()?,
        report.settings.mode == "quick",
        out,
        &mut figure,
        log,
    )?;
    let rows = report.speed_rows();
    if !rows.is_empty() {
        write(
            out,
            "speed_error.csv",
            &crate::records::csv_out::to_csv(&rows)?,
        )?;
        figure("speed_error", &|p| plot::speed_error::render(&rows, p))?;
    }
    files.extend(render_files);
    Ok(Figures { files })
}
