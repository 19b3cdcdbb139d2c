//! Every file format of helixreach: the records (rows) the commands write and read, and their
//! readers and writers.
//!
//! # Layering
//! `records` sits at the edge. It depends on the domain types it converts (directions,
//! `boundary`, `planning`, `compare`, `detect`, `rod`, …); the domain modules — `planning`,
//! `compare`, `boundary`, `helix`, `robot`, `rod`, `bifurcation`, `directions` — import no
//! file format and nothing of `records` (they take and return values). Reading and writing
//! files is done here and by the orchestration that runs a command into a folder, which calls
//! these records: the sweep driver ([`crate::sweep`]), the study and the campaign
//! ([`crate::experiment`]), the layout's sweep and reports ([`crate::layout`]), the batch
//! detection of recorded runs ([`crate::detect`]), the figures and the command-line program.
//! `records` imports none of those (only tests compare with them): a cycle through `records`
//! is a bug.
//!
//! # The figures' readers
//! Each reader looks columns up by header name, so extra columns are ignored and column order is
//! free; only the columns a figure needs are required. Errors name the file, the 1-based line and
//! the column ([`Error::BadLine`]), or the missing column together with the header that was found
//! ([`Error::File`]). Numbers must be finite, except `s_star`, which may be `inf` (stable up to
//! the search limit).
//!
//! | reader | CSV written by | required columns |
//! |---|---|---|
//! | [`read_boundary`] | `helixreach boundary` | `dir_kappa,dir_tau,dir_omega,s_star` (`method,resolution` optional) |
//! | [`read_reach`] | `helixreach reach` | `dir_kappa,dir_tau,dir_omega,s_star,s_reached,class,cause` (`roll_mode` optional) |
//! | [`read_series`] | `helixreach simulate` | `s,error` (`t` optional) |
//! | [`read_speed_error`] | benches / `demo` | `method,resolution,time_per_direction_s,max_rel_err,median_rel_err` |
//! | [`read_trajectory`] | `helixreach plan` ([`trajectory`]) | `s`, the joints before `motor` (or `q0..qN`, consecutive from `q0`) |
//! | [`read_joint_limits`] | user / `demo` | `joint,lower,upper` |

pub mod bifurcation;
pub mod boundary;
pub mod campaign;
pub mod centerline;
pub mod check;
pub mod clamp_runs;
pub mod columns;
pub mod compare;
pub mod csv_out;
pub mod detect;
pub mod disturbances;
pub mod helix_points;
pub mod ik;
pub mod layout;
pub mod reach;
pub mod render;
pub mod ros2_bag;
pub mod series;
pub mod trajectory;

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use csv_out::CsvRecord;
use std::path::{Path, PathBuf};

/// One direction of a boundary CSV: where the ray S̄ leaves the stable set.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryRow {
    /// The unit direction S̄.
    pub dir: Direction,
    /// Critical distance s* along S̄; `f64::INFINITY` when stable up to the search limit.
    pub s_star: Real,
    /// Boundary method (`continuum`, `der`, …); empty when the column is absent.
    pub method: String,
    /// Method resolution (tolerance, n); empty when the column is absent.
    pub resolution: String,
}

/// Format a real for CSV: the shortest text that reads back to the same `f64` (`inf`, `-inf`,
/// `NaN` for the non-finite values). Every CSV writer uses it.
///
/// ```
/// use helixreach::records::fmt_real;
/// assert_eq!(fmt_real(0.1), "0.1");
/// assert_eq!(fmt_real(f64::INFINITY), "inf");
/// let x = 1.0 / 3.0;
/// assert_eq!(fmt_real(x).parse::<f64>().unwrap(), x);
/// ```
pub fn fmt_real(x: Real) -> String {
    format!("{x}")
}

/// Columns of a boundary CSV ([`boundary::BoundaryRecord`]).
pub const BOUNDARY_HEADER: &[&str] = boundary::BoundaryRecord::HEADER;

/// Columns of a reachability CSV ([`reach::ReachRecord`]).
pub const REACH_HEADER: &[&str] = reach::ReachRecord::HEADER;

/// The key columns of a row keyed by direction: `dir_kappa,dir_tau,dir_omega`, the unit S̄ by
/// [`fmt_real`]. Records hold it as a nested field; the csv writer puts its columns in place
/// (it cannot serialize `#[serde(flatten)]`, a map, but writes a nested struct's fields).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DirColumns {
    /// κ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_kappa: Real,
    /// τ̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_tau: Real,
    /// ω̂ of the direction.
    #[serde(serialize_with = "csv_out::real")]
    pub dir_omega: Real,
}

impl CsvRecord for DirColumns {
    const HEADER: &'static [&'static str] = &["dir_kappa", "dir_tau", "dir_omega"];
}

impl From<&Direction> for DirColumns {
    fn from(d: &Direction) -> Self {
        DirColumns {
            dir_kappa: d.kappa,
            dir_tau: d.tau,
            dir_omega: d.omega,
        }
    }
}

/// The key columns of a direction ([`DirColumns`]) as text.
pub fn dir_key(d: &Direction) -> Vec<String> {
    vec![fmt_real(d.kappa), fmt_real(d.tau), fmt_real(d.omega)]
}

pub use crate::planning::cause::BlockCause;
pub use crate::planning::planner::ReachClass;

/// Parse a record enum ([`ReachClass`], [`BlockCause`]) from its CSV spelling, by serde.
fn parse_name<T: serde::de::DeserializeOwned>(s: &str) -> std::result::Result<T, String> {
    use serde::de::IntoDeserializer;
    T::deserialize(s.into_deserializer())
        .map_err(|e: serde::de::value::Error| format!("`{s}`: {e}"))
}

/// A blocking cause from its CSV spelling; an empty field or `none` means not blocked (`reach`
/// writes none for testable rays).
fn parse_cause(s: &str) -> std::result::Result<Option<BlockCause>, String> {
    match s {
        "" | "none" => Ok(None),
        _ => parse_name(s).map(Some),
    }
}

/// One direction of a reachability CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct ReachRow {
    /// The unit direction S̄.
    pub dir: Direction,
    /// Critical distance s* (may be ∞).
    pub s_star: Real,
    /// Farthest s the planner reached along the ray.
    pub s_reached: Real,
    /// Classification.
    pub class: ReachClass,
    /// Blocking cause (`None` for testable rays).
    pub cause: Option<BlockCause>,
    /// Roll mode (`fixed`, `motor`, …); empty when the column is absent.
    pub roll_mode: String,
}

/// One sample of a DER dynamics series: the helix error at distance s along the ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeriesRow {
    /// Time (s); NaN when the column is absent.
    pub t: Real,
    /// Distance along the ray, ‖S‖ = s.
    pub s: Real,
    /// Helix error e.
    pub error: Real,
}

/// One labelled DER dynamics series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// The samples, in file order.
    pub rows: Vec<SeriesRow>,
    /// Detected instability distance s_dyn, drawn as a marker when known.
    pub s_detected: Option<Real>,
    /// A reference instability distance (e.g. the continuum s*), drawn as a dotted line.
    pub s_reference: Option<Real>,
}

/// One row of the speed-versus-error table of boundary methods (`speed_error.csv`,
/// `helixreach boundary --speed-report`), written by [`csv_out::to_csv`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SpeedErrorRow {
    /// Method name (`continuum`, `der`, `dynamics`).
    pub method: String,
    /// Resolution (tolerance, n, dt …) as text.
    pub resolution: String,
    /// Time per direction (s): one thread's CPU time where the writer measured it so.
    #[serde(serialize_with = "csv_out::real")]
    pub time_per_direction_s: Real,
    /// Maximum relative error of s* versus the reference.
    #[serde(serialize_with = "csv_out::real")]
    pub max_rel_err: Real,
    /// Median relative error of s* versus the reference.
    #[serde(serialize_with = "csv_out::real")]
    pub median_rel_err: Real,
}

impl csv_out::CsvRecord for SpeedErrorRow {
    const HEADER: &'static [&'static str] = &[
        "method",
        "resolution",
        "time_per_direction_s",
        "max_rel_err",
        "median_rel_err",
    ];
}

/// One waypoint of a planned trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryRow {
    /// Time from start (s); NaN when absent.
    pub t: Real,
    /// Distance along the ray.
    pub s: Real,
    /// Joint angles q0..q(n−1) (rad).
    pub q: Vec<Real>,
    /// Motor angle (rad); NaN when the file has no motor column.
    pub motor: Real,
}

/// Limits of one joint (rad): a row of a joint-limits CSV (`joint,lower,upper`, the demo's
/// `joint_limits.csv`), read by [`read_joint_limits`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct JointLimit {
    /// Joint name.
    #[serde(rename = "joint")]
    pub name: String,
    /// Lower limit (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub lower: Real,
    /// Upper limit (rad).
    #[serde(serialize_with = "csv_out::real")]
    pub upper: Real,
}

impl CsvRecord for JointLimit {
    const HEADER: &'static [&'static str] = &["joint", "lower", "upper"];
}

/// A CSV file held in memory with header lookup and line-numbered parsing.
struct Table {
    path: PathBuf,
    headers: Vec<String>,
    rows: Vec<csv::StringRecord>,
}

impl Table {
    fn read(path: &Path) -> Result<Table> {
        let file_err = |reason: String| Error::File {
            path: path.to_path_buf(),
            reason,
        };
        if !path.exists() {
            return Err(file_err("file not found".into()));
        }
        let mut rdr = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .comment(Some(b'#'))
            .from_path(path)
            .map_err(|e| file_err(e.to_string()))?;
        let headers: Vec<String> = rdr
            .headers()
            .map_err(|e| file_err(e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let mut rows = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            rows.push(rec.map_err(|e| Error::BadLine {
                path: path.to_path_buf(),
                line: k + 2,
                field: "record".into(),
                reason: e.to_string(),
            })?);
        }
        if rows.is_empty() {
            return Err(file_err("no data rows after the header".into()));
        }
        Ok(Table {
            path: path.to_path_buf(),
            headers,
            rows,
        })
    }

    fn has(&self, name: &str) -> bool {
        self.headers.iter().any(|h| h == name)
    }

    fn col(&self, name: &str) -> Result<usize> {
        self.headers
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| Error::File {
                path: self.path.clone(),
                reason: format!(
                    "missing column `{name}` (header: {})",
                    self.headers.join(",")
                ),
            })
    }

    fn line(&self, row: usize) -> usize {
        self.rows[row]
            .position()
            .map(|p| p.line() as usize)
            .unwrap_or(row + 2)
    }

    fn bad(&self, row: usize, field: &str, reason: String) -> Error {
        Error::BadLine {
            path: self.path.clone(),
            line: self.line(row),
            field: field.into(),
            reason,
        }
    }

    fn text(&self, row: usize, col: usize) -> &str {
        self.rows[row].get(col).unwrap_or("")
    }

    /// A finite number (or +∞ when `allow_inf`).
    fn real(&self, row: usize, col: usize, name: &str, allow_inf: bool) -> Result<Real> {
        let s = self.text(row, col);
        let v: Real = s
            .parse()
            .map_err(|_| self.bad(row, name, format!("`{s}` is not a number")))?;
        if v.is_finite() || (allow_inf && v == Real::INFINITY) {
            Ok(v)
        } else {
            Err(self.bad(
                row,
                name,
                format!(
                    "`{s}` is not finite{}",
                    if allow_inf { " (or +inf)" } else { "" }
                ),
            ))
        }
    }

    fn direction(&self, row: usize, cols: [usize; 3]) -> Result<Direction> {
        let k = self.real(row, cols[0], "dir_kappa", false)?;
        let t = self.real(row, cols[1], "dir_tau", false)?;
        let w = self.real(row, cols[2], "dir_omega", false)?;
        Direction::new(k, t, w).map_err(|e| self.bad(row, "direction", e.to_string()))
    }

    fn dir_cols(&self) -> Result<[usize; 3]> {
        Ok([
            self.col("dir_kappa")?,
            self.col("dir_tau")?,
            self.col("dir_omega")?,
        ])
    }
}

/// Read a boundary CSV (`helixreach boundary`).
pub fn read_boundary(path: &Path) -> Result<Vec<BoundaryRow>> {
    let t = Table::read(path)?;
    let dc = t.dir_cols()?;
    let is = t.col("s_star")?;
    // Rows of directions the method refused (non-empty `refused`) have no boundary point.
    let irf = t.has("refused").then(|| t.col("refused")).transpose()?;
    let im = t.has("method").then(|| t.col("method")).transpose()?;
    let ir = t
        .has("resolution")
        .then(|| t.col("resolution"))
        .transpose()?;
    (0..t.rows.len())
        .filter(|&r| irf.is_none_or(|c| t.text(r, c).is_empty()))
        .map(|r| {
            let s_star = t.real(r, is, "s_star", true)?;
            if s_star < 0.0 {
                return Err(t.bad(r, "s_star", format!("{s_star} is negative")));
            }
            Ok(BoundaryRow {
                dir: t.direction(r, dc)?,
                s_star,
                method: im.map(|c| t.text(r, c).to_string()).unwrap_or_default(),
                resolution: ir.map(|c| t.text(r, c).to_string()).unwrap_or_default(),
            })
        })
        .collect()
}

/// Read a reachability CSV (`helixreach reach`).
pub fn read_reach(path: &Path) -> Result<Vec<ReachRow>> {
    let t = Table::read(path)?;
    let dc = t.dir_cols()?;
    let (is, ir, icl, ica) = (
        t.col("s_star")?,
        t.col("s_reached")?,
        t.col("class")?,
        t.col("cause")?,
    );
    let im = t.has("roll_mode").then(|| t.col("roll_mode")).transpose()?;
    (0..t.rows.len())
        .map(|r| {
            let s_reached = t.real(r, ir, "s_reached", true)?;
            if s_reached < 0.0 {
                return Err(t.bad(r, "s_reached", format!("{s_reached} is negative")));
            }
            Ok(ReachRow {
                dir: t.direction(r, dc)?,
                s_star: t.real(r, is, "s_star", true)?,
                s_reached,
                class: parse_name(t.text(r, icl)).map_err(|e| t.bad(r, "class", e))?,
                cause: parse_cause(t.text(r, ica)).map_err(|e| t.bad(r, "cause", e))?,
                roll_mode: im.map(|c| t.text(r, c).to_string()).unwrap_or_default(),
            })
        })
        .collect()
}

/// Read a DER dynamics series CSV (`helixreach simulate`); the label is the file stem.
pub fn read_series(path: &Path) -> Result<Series> {
    let t = Table::read(path)?;
    let (is, ie) = (t.col("s")?, t.col("error")?);
    let it = t.has("t").then(|| t.col("t")).transpose()?;
    let rows = (0..t.rows.len())
        .map(|r| {
            Ok(SeriesRow {
                t: match it {
                    Some(c) => t.real(r, c, "t", false)?,
                    None => Real::NAN,
                },
                s: t.real(r, is, "s", false)?,
                error: t.real(r, ie, "error", false)?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Series {
        label: path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        rows,
        s_detected: None,
        s_reference: None,
    })
}

/// Read the speed-versus-error table of boundary methods.
pub fn read_speed_error(path: &Path) -> Result<Vec<SpeedErrorRow>> {
    let t = Table::read(path)?;
    let (im, ir, it, ix, id) = (
        t.col("method")?,
        t.col("resolution")?,
        t.col("time_per_direction_s")?,
        t.col("max_rel_err")?,
        t.col("median_rel_err")?,
    );
    (0..t.rows.len())
        .map(|r| {
            let row = SpeedErrorRow {
                method: t.text(r, im).to_string(),
                resolution: t.text(r, ir).to_string(),
                time_per_direction_s: t.real(r, it, "time_per_direction_s", false)?,
                max_rel_err: t.real(r, ix, "max_rel_err", false)?,
                median_rel_err: t.real(r, id, "median_rel_err", false)?,
            };
            if row.time_per_direction_s <= 0.0 {
                return Err(t.bad(
                    r,
                    "time_per_direction_s",
                    format!("{} must be > 0 (log axis)", row.time_per_direction_s),
                ));
            }
            for (name, v) in [
                ("max_rel_err", row.max_rel_err),
                ("median_rel_err", row.median_rel_err),
            ] {
                if v < 0.0 {
                    return Err(t.bad(r, name, format!("{v} is negative")));
                }
            }
            Ok(row)
        })
        .collect()
}

/// Read a trajectory CSV (`helixreach plan`) without knowing the robot, by the one trajectory
/// reader ([`trajectory::read_trajectory_file`]): the joint columns are `q0, q1, …` (the
/// index header) up to the first missing index, otherwise the columns before `motor` but `t`
/// (the joint names of [`trajectory::trajectory_header`], in file order); `s` required.
pub fn read_trajectory(path: &Path) -> Result<Vec<TrajectoryRow>> {
    let t = trajectory::read_trajectory_file(path, &[], "")?;
    let s = t.s.as_ref().ok_or_else(|| {
        t.file_error(format!(
            "missing column `s` (joint columns: {})",
            t.joint_names.join(",")
        ))
    })?;
    Ok((0..t.rows())
        .map(|i| TrajectoryRow {
            t: t.t.as_ref().map_or(Real::NAN, |v| v[i]),
            s: s[i],
            q: t.row(i).to_vec(),
            motor: t.motor.as_ref().map_or(Real::NAN, |v| v[i]),
        })
        .collect())
}

/// Read joint limits from a CSV with columns `joint,lower,upper` (rad), one row per joint in
/// chain order; a row named `motor` gives the motor's limits.
pub fn read_joint_limits(path: &Path) -> Result<Vec<JointLimit>> {
    let t = Table::read(path)?;
    let (ij, il, iu) = (t.col("joint")?, t.col("lower")?, t.col("upper")?);
    (0..t.rows.len())
        .map(|r| {
            let lim = JointLimit {
                name: t.text(r, ij).to_string(),
                lower: t.real(r, il, "lower", false)?,
                upper: t.real(r, iu, "upper", false)?,
            };
            if lim.lower >= lim.upper {
                return Err(t.bad(
                    r,
                    "upper",
                    format!("lower {} must be < upper {}", lim.lower, lim.upper),
                ));
            }
            Ok(lim)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn boundary_accepts_inf_and_reorders_columns() {
        let d = tempfile::tempdir().unwrap();
        let p = write(
            d.path(),
            "b.csv",
            "s_star,dir_omega,dir_tau,dir_kappa,extra\n6.283,0,0,1,x\ninf,0,1,0,y\n",
        );
        let b = read_boundary(&p).unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(b[0].dir.kappa, 1.0);
        assert!(b[1].s_star.is_infinite());
        assert_eq!(b[0].method, "");
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let d = tempfile::tempdir().unwrap();
        let p = write(d.path(), "b.csv", "dir_kappa,dir_tau,dir_omega\n1,0,0\n");
        let e = read_boundary(&p).unwrap_err().to_string();
        assert!(
            e.contains("b.csv") && e.contains("missing column `s_star`"),
            "{e}"
        );
        let p = write(
            d.path(),
            "r.csv",
            "dir_kappa,dir_tau,dir_omega,s_star,s_reached,class,cause\n\
             1,0,0,6.28,7,testable,none\n1,0,0,6.28,0,blocked,teleport\n",
        );
        let e = read_reach(&p).unwrap_err().to_string();
        assert!(
            e.contains("r.csv:3") && e.contains("cause") && e.contains("teleport"),
            "{e}"
        );
        let p = write(d.path(), "s.csv", "t,s,error\n0,0,0\n0.1,NaN,0\n");
        let e = read_series(&p).unwrap_err().to_string();
        assert!(e.contains("s.csv:3: s:"), "{e}");
        let e = read_series(&d.path().join("nope.csv"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("nope.csv") && e.contains("not found"), "{e}");
        let p = write(d.path(), "empty.csv", "t,s,error\n");
        assert!(read_series(&p)
            .unwrap_err()
            .to_string()
            .contains("no data rows"));
    }

    #[test]
    fn trajectory_finds_joint_columns() {
        let d = tempfile::tempdir().unwrap();
        let p = write(
            d.path(),
            "t.csv",
            "t,q0,q1,q2,motor,s\n0,0.1,0.2,0.3,0,0\n1,0.2,0.3,0.4,0.5,0.1\n",
        );
        let t = read_trajectory(&p).unwrap();
        assert_eq!(t[1].q, vec![0.2, 0.3, 0.4]);
        assert_eq!(t[1].motor, 0.5);
        // The joint names of `plan`'s header: the columns before `motor`.
        let p = write(
            d.path(),
            "n.csv",
            "t,right_j0,right_j1,right_j2,motor,s\n0,0.1,0.2,0.3,0,0\n1,0.2,0.3,0.4,0.5,0.1\n",
        );
        let n = read_trajectory(&p).unwrap();
        assert_eq!(n, t);
        let p = write(d.path(), "none.csv", "t,a,s\n0,0.1,0\n");
        let e = read_trajectory(&p).unwrap_err().to_string();
        assert!(
            e.contains("none.csv") && e.contains("no joint columns"),
            "{e}"
        );
        let p = write(d.path(), "l.csv", "joint,lower,upper\nj0,1,-1\n");
        let e = read_joint_limits(&p).unwrap_err().to_string();
        assert!(e.contains("l.csv:2") && e.contains("upper"), "{e}");
    }
}
