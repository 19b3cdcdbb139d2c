//! The output files of a layout run (all written atomically into the output directory; the CSV
//! rows are the records of [`crate::records::layout`]):
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
use crate::error::Result;
use crate::io::write_atomic;
use crate::math::{Real, DEG};
use crate::planning::rig::Rig;
#[cfg(feature = "plots")]
use crate::plot::{layout_coverage, layout_directions, layout_heatmap};
use crate::records::csv_out::to_csv;
use crate::records::layout::{
    AssignmentRecord, CandidateRecord, CoverageRecord, PlacementRecord, ReferenceRecord,
};
use std::path::Path;

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
    let frac = |n: usize| n as Real / nd.max(1) as Real;
    let rc = rig.clamp_rotation();

    let write = |name: &str, text: String| write_atomic(&dir.join(name), text.as_bytes());

    // candidates.csv
    let rows: Vec<CandidateRecord> = report
        .candidates
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let d3 = c.d3(&rc);
            CandidateRecord {
                candidate: i,
                x: c.origin[0],
                y: c.origin[1],
                z: c.origin[2],
                tilt_deg: c.tilt / DEG,
                heading_deg: c.heading / DEG,
                d3_x: d3.x,
                d3_y: d3.y,
                d3_z: d3.z,
                kind: if i < report.n_grid {
                    "grid"
                } else {
                    "reference"
                },
                covered: report.covered[i],
                fraction: frac(report.covered[i]),
            }
        })
        .collect();
    write("candidates.csv", to_csv(&rows)?)?;

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
        rows.push(PlacementRecord {
            placement: rank + 1,
            candidate: p.candidate,
            x: p.pose.origin[0],
            y: p.pose.origin[1],
            z: p.pose.origin[2],
            tilt_deg: p.pose.tilt / DEG,
            heading_deg: p.pose.heading / DEG,
            covered: p.covered,
            new: p.new,
            cumulative: p.cumulative,
            cumulative_fraction: frac(p.cumulative),
            rig_file: p.rig_file.display().to_string(),
        });
    }
    write("placements.csv", to_csv(&rows)?)?;

    // assignment.csv
    let rows: Vec<AssignmentRecord> = report
        .assignment
        .iter()
        .enumerate()
        .map(|(d, a)| {
            let dirv = &dirs[d];
            let (placement, azimuth, class, s_reached) = match a {
                Some((rank, r)) => (
                    Some(rank + 1),
                    Some(r.azimuth),
                    r.class.clone(),
                    Some(r.s_reached),
                ),
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
                    (
                        None,
                        None,
                        best.map_or("unreachable".into(), |b| b.class.clone()),
                        best.map(|b| b.s_reached).filter(|s| s.is_finite()),
                    )
                }
            };
            AssignmentRecord {
                dir_kappa: dirv.kappa,
                dir_tau: dirv.tau,
                dir_omega: dirv.omega,
                placement,
                azimuth,
                class,
                s_reached,
            }
        })
        .collect();
    write("assignment.csv", to_csv(&rows)?)?;

    // coverage.csv
    let rows: Vec<CoverageRecord> = report
        .by_k
        .iter()
        .map(|c| CoverageRecord {
            k: c.k,
            greedy: c.greedy.covered,
            exact: c.exact.covered,
            exact_proven: c.exact.proven,
            exact_nodes: c.exact.nodes,
            total: nd,
        })
        .collect();
    write("coverage.csv", to_csv(&rows)?)?;

    // reference.csv
    if let Some(r) = &report.reference {
        let mut rows = vec![
            ReferenceRecord {
                set: "reference_own_position",
                placements: r.positions,
                covered: r.own,
                total: r.own_total,
            },
            ReferenceRecord {
                set: "reference_union",
                placements: r.positions,
                covered: r.union,
                total: nd,
            },
        ];
        rows.extend(report.by_k.iter().map(|c| ReferenceRecord {
            set: "layout_best",
            placements: c.k,
            covered: c.exact.covered.max(c.greedy.covered),
            total: nd,
        }));
        write("reference.csv", to_csv(&rows)?)?;
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
