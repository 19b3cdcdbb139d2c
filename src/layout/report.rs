//! The output files of a layout run (all written atomically into the output directory):
//!
//! | file | columns / content |
//! |---|---|
//! | `candidates.csv` | `candidate,x,y,z,tilt_deg,heading_deg,d3_x,d3_y,d3_z,kind,covered,fraction` (kind `grid` or `reference`) |
//! | `placements.csv` | `placement,candidate,x,y,z,tilt_deg,heading_deg,covered,new,cumulative,cumulative_fraction,rig_file` |
//! | `assignment.csv` | `dir_kappa,dir_tau,dir_omega,placement,azimuth,class,s_reached` (placement 1-based; empty when no placement tests the direction, then class/s_reached are the best over the placements) |
//! | `coverage.csv` | `k,greedy,exact,exact_proven,exact_nodes,total` |
//! | `reference.csv` | `set,placements,covered,total` (only with reference positions) |
//! | `placement_<i>.toml` | the rig with the clamp at placement i |
//! | `heatmap.png`, `directions.png`, `coverage.png` | figures ([`crate::plot::layout_heatmap`], [`crate::plot::layout_directions`], [`crate::plot::layout_coverage`]) |

use super::evaluate::RayResult;
use super::precheck::ReachBound;
use super::LayoutReport;
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::io::write_atomic;
use crate::math::{Real, DEG};
use crate::planning::rig::Rig;
#[cfg(feature = "plots")]
use crate::plot::{layout_coverage, layout_directions, layout_heatmap};
use crate::sweep::reach::fmt_real;
use std::path::Path;

fn csv_bytes(header: &[&str], rows: &[Vec<String>]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let ser = |e: csv::Error| Error::invalid("row", "", e.to_string());
    w.write_record(header).map_err(ser)?;
    for r in rows {
        w.write_record(r).map_err(ser)?;
    }
    w.into_inner()
        .map_err(|e| Error::invalid("row", "", e.to_string()))
}

fn class_rank(c: &str) -> u8 {
    match c {
        "testable" => 4,
        "partial" => 3,
        "blocked" => 2,
        "unreachable" => 1,
        _ => 0,
    }
}

/// Write every output of `report` into `dir` (see the module docs).
pub fn write_all(
    rig: &Rig,
    dirs: &[Direction],
    report: &LayoutReport,
    rays: &[RayResult],
    bound: &ReachBound,
    dir: &Path,
) -> Result<()> {
    let nd = report.n_dirs;
    let frac = |n: usize| fmt_real(n as Real / nd.max(1) as Real);
    let rc = rig.clamp_rotation();

    // candidates.csv
    let rows: Vec<Vec<String>> = report
        .candidates
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let d3 = c.d3(&rc);
            vec![
                i.to_string(),
                fmt_real(c.origin[0]),
                fmt_real(c.origin[1]),
                fmt_real(c.origin[2]),
                fmt_real(c.tilt / DEG),
                fmt_real(c.heading / DEG),
                fmt_real(d3.x),
                fmt_real(d3.y),
                fmt_real(d3.z),
                if i < report.n_grid {
                    "grid"
                } else {
                    "reference"
                }
                .to_string(),
                report.covered[i].to_string(),
                frac(report.covered[i]),
            ]
        })
        .collect();
    write_atomic(
        &dir.join("candidates.csv"),
        &csv_bytes(
            &[
                "candidate",
                "x",
                "y",
                "z",
                "tilt_deg",
                "heading_deg",
                "d3_x",
                "d3_y",
                "d3_z",
                "kind",
                "covered",
                "fraction",
            ],
            &rows,
        )?,
    )?;

    // placement rigs + placements.csv
    let mut rows = Vec::new();
    for (rank, p) in report.placements.iter().enumerate() {
        let mut placed = p.pose.place(rig);
        placed.name = format!("{}-placement-{}", rig.name, rank + 1);
        placed.description = format!(
            "{} — clamp moved by `helixreach layout` (placement {} of {}: {} of {} directions)",
            rig.description,
            rank + 1,
            report.placements.len(),
            p.covered,
            nd
        );
        write_atomic(&dir.join(&p.rig_file), placed.to_toml()?.as_bytes())?;
        rows.push(vec![
            (rank + 1).to_string(),
            p.candidate.to_string(),
            fmt_real(p.pose.origin[0]),
            fmt_real(p.pose.origin[1]),
            fmt_real(p.pose.origin[2]),
            fmt_real(p.pose.tilt / DEG),
            fmt_real(p.pose.heading / DEG),
            p.covered.to_string(),
            p.new.to_string(),
            p.cumulative.to_string(),
            frac(p.cumulative),
            p.rig_file.display().to_string(),
        ]);
    }
    write_atomic(
        &dir.join("placements.csv"),
        &csv_bytes(
            &[
                "placement",
                "candidate",
                "x",
                "y",
                "z",
                "tilt_deg",
                "heading_deg",
                "covered",
                "new",
                "cumulative",
                "cumulative_fraction",
                "rig_file",
            ],
            &rows,
        )?,
    )?;

    // assignment.csv
    let mut rows = Vec::new();
    for (d, a) in report.assignment.iter().enumerate() {
        let dirv = &dirs[d];
        let mut row = vec![
            fmt_real(dirv.kappa),
            fmt_real(dirv.tau),
            fmt_real(dirv.omega),
        ];
        match a {
            Some((rank, r)) => row.extend([
                (rank + 1).to_string(),
                fmt_real(r.azimuth),
                r.class.clone(),
                fmt_real(r.s_reached),
            ]),
            None => {
                // The best answer any placement gave (class, then s reached).
                let best = report
                    .placements
                    .iter()
                    .map(|p| &rays[p.candidate * nd + d])
                    .max_by(|a, b| {
                        class_rank(&a.class).cmp(&class_rank(&b.class)).then(
                            a.s_reached
                                .partial_cmp(&b.s_reached)
                                .unwrap_or(std::cmp::Ordering::Equal),
                        )
                    });
                row.extend([
                    String::new(),
                    String::new(),
                    best.map_or("unreachable".into(), |b| b.class.clone()),
                    best.filter(|b| b.s_reached.is_finite())
                        .map_or(String::new(), |b| fmt_real(b.s_reached)),
                ]);
            }
        }
        rows.push(row);
    }
    write_atomic(
        &dir.join("assignment.csv"),
        &csv_bytes(
            &[
                "dir_kappa",
                "dir_tau",
                "dir_omega",
                "placement",
                "azimuth",
                "class",
                "s_reached",
            ],
            &rows,
        )?,
    )?;

    // coverage.csv
    let rows: Vec<Vec<String>> = report
        .by_k
        .iter()
        .map(|c| {
            vec![
                c.k.to_string(),
                c.greedy.covered.to_string(),
                c.exact.covered.to_string(),
                c.exact.proven.to_string(),
                c.exact.nodes.to_string(),
                nd.to_string(),
            ]
        })
        .collect();
    write_atomic(
        &dir.join("coverage.csv"),
        &csv_bytes(
            &[
                "k",
                "greedy",
                "exact",
                "exact_proven",
                "exact_nodes",
                "total",
            ],
            &rows,
        )?,
    )?;

    // reference.csv
    if let Some(r) = &report.reference {
        let mut rows = vec![
            vec![
                "reference_own_position".to_string(),
                r.positions.to_string(),
                r.own.to_string(),
                r.own_total.to_string(),
            ],
            vec![
                "reference_union".to_string(),
                r.positions.to_string(),
                r.union.to_string(),
                nd.to_string(),
            ],
        ];
        for c in &report.by_k {
            rows.push(vec![
                "layout_best".to_string(),
                c.k.to_string(),
                c.exact.covered.max(c.greedy.covered).to_string(),
                nd.to_string(),
            ]);
        }
        write_atomic(
            &dir.join("reference.csv"),
            &csv_bytes(&["set", "placements", "covered", "total"], &rows)?,
        )?;
    }

    // Figures (feature `plots`; the core build writes the CSVs only).
    #[cfg(not(feature = "plots"))]
    let _ = bound;
    #[cfg(feature = "plots")]
    {
        let cells: Vec<layout_heatmap::Cell> = report.candidates[..report.n_grid]
            .iter()
            .zip(&report.covered)
            .map(|(c, &n)| layout_heatmap::Cell {
                x: c.origin[0],
                y: c.origin[1],
                fraction: n as Real / nd.max(1) as Real,
            })
            .collect();
        let chosen: Vec<(Real, Real)> = report
            .placements
            .iter()
            .map(|p| (p.pose.origin[0], p.pose.origin[1]))
            .collect();
        let refs: Vec<(Real, Real)> = report.candidates[report.n_grid..]
            .iter()
            .map(|c| (c.origin[0], c.origin[1]))
            .collect();
        let z = rig.clamp.translation.vector.z;
        let dz = z - bound.centre.z;
        let reach_r = (bound.radius * bound.radius - dz * dz).max(0.0).sqrt();
        layout_heatmap::render(
            &layout_heatmap::Heatmap {
                cells,
                chosen,
                references: refs,
                base: (bound.centre.x, bound.centre.y),
                reach_radius: reach_r,
                total: nd,
            },
            &dir.join("heatmap.png"),
        )?;
        let points: Vec<(Direction, Option<usize>)> = dirs
            .iter()
            .zip(&report.assignment)
            .map(|(d, a)| (*d, a.as_ref().map(|(rank, _)| *rank)))
            .collect();
        layout_directions::render(
            &points,
            report.placements.len(),
            &dir.join("directions.png"),
        )?;
        let curve: Vec<layout_coverage::Point> = report
            .by_k
            .iter()
            .map(|c| layout_coverage::Point {
                k: c.k,
                greedy: c.greedy.covered,
                exact: c.exact.covered,
                proven: c.exact.proven,
            })
            .collect();
        layout_coverage::render(
            &curve,
            nd,
            report.reference.as_ref().map(|r| r.union),
            &dir.join("coverage.png"),
        )?;
    }
    Ok(())
}
