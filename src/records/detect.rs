//! The formats of `helixreach detect`: the raw observation file of one run (read), the run list
//! of a batch (read), the per-sample table (`--out` of one run) and the batch's measured file
//! (written).
//!
//! # Observation file ([`read_observations`])
//! One sample per line, in time order, numbers separated by spaces (or commas): the robot's
//! `dof` measured joint angles (rad, the robot's joint order), then the marker's position
//! `x y z` (m) in the camera frame, then optionally one or two image coordinates (pixels; the
//! seed writes the marker's image row twice). So a line has `dof + 3`, `dof + 4` or `dof + 5`
//! fields, the same number on every line. Blank lines and `#` comments are skipped.
//! A field that is not a number is an error naming the file, the 1-based line, the column and
//! the text; `nan` (and a non-finite value) is accepted and marks the sample as dropped —
//! [`crate::detect::observations`] flags it. At most [`MAX_SAMPLES`] samples.
//!
//! # Run list of a batch ([`read_detect_runs`])
//! CSV with columns `observations` (a path, relative to the run list's folder),
//! `dir_kappa,dir_tau,dir_omega`, and optionally `clamp_x,clamp_y,clamp_z` (m, base frame;
//! empty or absent: fitted from the joints). Other columns are ignored.
//!
//! # Outputs
//! - [`DetectSampleRecord`]: one row per sample (`detect --out` of one run);
//! - [`DetectRunRecord`]: one row per run (`detect --runs … --out`), whose columns
//!   `dir_kappa,dir_tau,dir_omega,s_measured` are what `compare --measured` reads (an empty
//!   `s_measured` where no snap was seen; the other columns are kept beside them).

use super::csv_out::{self, CsvRecord};
use super::DirColumns;
use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::Real;
use std::path::{Path, PathBuf};

/// Largest number of samples of one observation file.
pub const MAX_SAMPLES: usize = 2_000_000;

/// Largest number of runs of one run list.
pub const MAX_RUNS: usize = 100_000;

/// The raw samples of one observation file, validated for shape only.
#[derive(Debug, Clone, PartialEq)]
pub struct ObservationFile {
    /// The file (for messages).
    pub path: PathBuf,
    /// Joints per sample.
    pub dof: usize,
    /// Joint angles, `dof` per sample (rad); non-finite where the sample is dropped.
    pub joints: Vec<Real>,
    /// Marker position in the camera frame (m); non-finite where dropped.
    pub marker: Vec<[Real; 3]>,
    /// The first image coordinate (pixels), when the file has one.
    pub image: Vec<Option<Real>>,
    /// 1-based line of each sample.
    pub lines: Vec<usize>,
}

impl ObservationFile {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// No samples (never true for a file [`read_observations`] accepted).
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The joints of sample `i`.
    pub fn joints(&self, i: usize) -> &[Real] {
        &self.joints[i * self.dof..(i + 1) * self.dof]
    }
}

/// Read an observation file (module docs) for a robot with `dof` joints.
pub fn read_observations(path: &Path, dof: usize) -> Result<ObservationFile> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_observations(&text, path, dof)
}

/// [`read_observations`] on text already read; `path` names it in errors.
///
/// ```
/// use helixreach::records::detect::parse_observations;
/// let p = std::path::Path::new("run.txt");
/// let f = parse_observations("0 0 0 1 2 3 12.5\n0 0 0 nan nan nan 0\n", p, 3).unwrap();
/// assert_eq!((f.len(), f.marker[0], f.image[0]), (2, [1.0, 2.0, 3.0], Some(12.5)));
/// assert!(f.marker[1][0].is_nan());
/// let e = parse_observations("0 0 0 1 2\n", p, 3).unwrap_err().to_string();
/// assert!(e.contains("run.txt:1") && e.contains("5 fields"), "{e}");
/// let e = parse_observations("0 0 0 1 2 x\n", p, 3).unwrap_err().to_string();
/// assert!(e.contains("run.txt:1") && e.contains("marker_z") && e.contains("`x`"), "{e}");
/// ```
pub fn parse_observations(text: &str, path: &Path, dof: usize) -> Result<ObservationFile> {
    let bad = |line: usize, field: &str, reason: String| Error::BadLine {
        path: path.to_path_buf(),
        line,
        field: field.to_string(),
        reason,
    };
    let mut out = ObservationFile {
        path: path.to_path_buf(),
        dof,
        joints: Vec::new(),
        marker: Vec::new(),
        image: Vec::new(),
        lines: Vec::new(),
    };
    let mut n_fields = None;
    let mut fields: Vec<&str> = Vec::with_capacity(dof + 5);
    for (i, l) in text.lines().enumerate() {
        let line = i + 1;
        let l = l.trim();
        if l.is_empty() || l.starts_with('#') {
            continue;
        }
        if out.lines.len() >= MAX_SAMPLES {
            return Err(bad(
                line,
                "samples",
                format!("more than {MAX_SAMPLES} samples"),
            ));
        }
        fields.clear();
        fields.extend(
            l.split(|c: char| c == ',' || c.is_whitespace())
                .filter(|f| !f.is_empty()),
        );
        let n = fields.len();
        if !(dof + 3..=dof + 5).contains(&n) {
            return Err(bad(
                line,
                "columns",
                format!(
                    "{n} fields, expected {} to {} ({dof} joints, marker x y z, up to two image coordinates)",
                    dof + 3,
                    dof + 5
                ),
            ));
        }
        match n_fields {
            None => n_fields = Some(n),
            Some(m) if m != n => {
                return Err(bad(
                    line,
                    "columns",
                    format!("{n} fields, the earlier lines have {m}"),
                ))
            }
            _ => {}
        }
        let num = |k: usize| -> Result<Real> {
            let f = fields[k];
            f.parse::<Real>().map_err(|_| {
                let name = if k < dof {
                    format!("joint {k}")
                } else if k < dof + 3 {
                    ["marker_x", "marker_y", "marker_z"][k - dof].to_string()
                } else {
                    format!("image {}", k - dof - 3)
                };
                bad(line, &name, format!("`{f}` is not a number"))
            })
        };
        for k in 0..dof {
            let v = num(k)?;
            out.joints.push(v);
        }
        let m = [num(dof)?, num(dof + 1)?, num(dof + 2)?];
        let img = if n > dof + 3 {
            Some(num(dof + 3)?)
        } else {
            None
        };
        out.marker.push(m);
        out.image.push(img);
        out.lines.push(line);
    }
    if out.lines.is_empty() {
        return Err(Error::File {
            path: path.to_path_buf(),
            reason: "empty file: no observation samples".into(),
        });
    }
    Ok(out)
}

/// One run of a batch.
#[derive(Debug, Clone, PartialEq)]
pub struct DetectRun {
    /// 1-based line in the run list.
    pub line: usize,
    /// The observation file as written in the run list.
    pub observations: String,
    /// The file resolved against the run list's folder.
    pub path: PathBuf,
    /// The ray's direction.
    pub dir: Direction,
    /// The clamp position (m), when given.
    pub clamp: Option<[Real; 3]>,
}

/// Read a run list (module docs).
pub fn read_detect_runs(path: &Path) -> Result<Vec<DetectRun>> {
    let mut t = crate::io::CsvInput::open(path)?;
    let hint = "header must contain observations,dir_kappa,dir_tau,dir_omega (clamp_x,clamp_y,clamp_z optional)";
    let obs_col = t.column("observations", hint)?;
    let dcols = [
        t.column("dir_kappa", hint)?,
        t.column("dir_tau", hint)?,
        t.column("dir_omega", hint)?,
    ];
    let ccols: Vec<Option<usize>> = ["clamp_x", "clamp_y", "clamp_z"]
        .iter()
        .map(|n| t.column(n, "").ok())
        .collect();
    let base = path.parent().unwrap_or(Path::new("."));
    let mut runs = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let rec = rec.map_err(|e| crate::io::bad_line(path, k + 2, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, k + 2);
        if runs.len() >= MAX_RUNS {
            return Err(crate::io::bad_line(
                path,
                line,
                "runs",
                format!("more than {MAX_RUNS} runs"),
            ));
        }
        let obs = rec.get(obs_col).unwrap_or("").to_string();
        if obs.is_empty() {
            return Err(crate::io::bad_line(
                path,
                line,
                "observations",
                "empty path".into(),
            ));
        }
        let mut d = [0.0; 3];
        for (v, (&c, name)) in
            d.iter_mut()
                .zip(dcols.iter().zip(["dir_kappa", "dir_tau", "dir_omega"]))
        {
            *v = crate::io::parse_field(path, line, &rec, c, name)?;
        }
        let dir = Direction::new(d[0], d[1], d[2])
            .map_err(|e| crate::io::bad_line(path, line, "direction", e.to_string()))?;
        let given: Vec<&str> = ccols
            .iter()
            .map(|c| c.and_then(|c| rec.get(c)).unwrap_or(""))
            .collect();
        let clamp = if given.iter().all(|g| g.is_empty()) {
            None
        } else {
            let mut c = [0.0; 3];
            for (j, name) in ["clamp_x", "clamp_y", "clamp_z"].iter().enumerate() {
                let col = ccols[j].ok_or_else(|| {
                    crate::io::bad_line(path, line, name, "column missing".into())
                })?;
                let v = crate::io::parse_field(path, line, &rec, col, name)?;
                if !v.is_finite() {
                    return Err(crate::io::bad_line(
                        path,
                        line,
                        name,
                        format!("{v} is not finite"),
                    ));
                }
                c[j] = v;
            }
            Some(c)
        };
        runs.push(DetectRun {
            line,
            path: base.join(&obs),
            observations: obs,
            dir,
            clamp,
        });
    }
    Ok(runs)
}

/// One sample of a run (`detect --out`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DetectSampleRecord {
    /// 1-based line of the observation file.
    pub line: usize,
    /// `loading` or `unloading`.
    pub phase: &'static str,
    /// Distance along the ray, by projection of the measured tool pose (empty when dropped).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s: Real,
    /// Distance of the tool position from the pose curve at `s` (m).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub pose_position_error: Real,
    /// Angle between the tool rotation and the pose curve's at `s` (rad).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub pose_rotation_error: Real,
    /// The marker in the base frame through the fitted extrinsics (m).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub marker_x: Real,
    /// See `marker_x`.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub marker_y: Real,
    /// See `marker_x`.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub marker_z: Real,
    /// The predicted marker position on the helix at `s` (m, base frame).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub predicted_x: Real,
    /// See `predicted_x`.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub predicted_y: Real,
    /// See `predicted_x`.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub predicted_z: Real,
    /// The seed's error e (deviation over the helix radius).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub e: Real,
    /// `ok`, or why the sample is not used (`dropped`, `outlier`, `off_path`).
    pub flag: &'static str,
    /// The sample was used to fit the extrinsics.
    pub in_fit: bool,
}

impl CsvRecord for DetectSampleRecord {
    const HEADER: &'static [&'static str] = &[
        "line",
        "phase",
        "s",
        "pose_position_error",
        "pose_rotation_error",
        "marker_x",
        "marker_y",
        "marker_z",
        "predicted_x",
        "predicted_y",
        "predicted_z",
        "e",
        "flag",
        "in_fit",
    ];
}

/// One run of a batch (`detect --runs … --out`). The first column is the key of the run.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DetectRunRecord {
    /// The observation file as written in the run list.
    pub observations: String,
    /// The direction.
    pub dir: DirColumns,
    /// Where e jumped on loading (empty: no snap seen).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_measured: Option<Real>,
    /// Where e came back on unloading (empty: not seen).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_return: Option<Real>,
    /// `high`, `low` or `none`.
    pub confidence: &'static str,
    /// Why (the outcome's name: `snap`, `gradual`, `noise`, `tracking_lost`, …).
    pub reason: &'static str,
    /// Largest s of the run.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s_reversal: Real,
    /// The continuum s* of the direction.
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub s_predicted: Real,
    /// Fitted marker arc length (fraction of the rod from the clamp).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub marker_arc: Real,
    /// RMS residual of the extrinsics fit (m).
    #[serde(serialize_with = "csv_out::real_or_empty")]
    pub fit_rms: Real,
    /// The clamp used (m).
    #[serde(serialize_with = "csv_out::real")]
    pub clamp_x: Real,
    /// See `clamp_x`.
    #[serde(serialize_with = "csv_out::real")]
    pub clamp_y: Real,
    /// See `clamp_x`.
    #[serde(serialize_with = "csv_out::real")]
    pub clamp_z: Real,
    /// Samples in the file.
    pub samples: usize,
    /// Samples not used (dropped marker, outlier, off the pose curve).
    pub flagged: usize,
    /// Notes (`;`-separated): flags that do not change the outcome.
    pub notes: String,
}

impl CsvRecord for DetectRunRecord {
    const HEADER: &'static [&'static str] = &[
        "observations",
        "dir_kappa",
        "dir_tau",
        "dir_omega",
        "s_measured",
        "s_return",
        "confidence",
        "reason",
        "s_reversal",
        "s_predicted",
        "marker_arc",
        "fit_rms",
        "clamp_x",
        "clamp_y",
        "clamp_z",
        "samples",
        "flagged",
        "notes",
    ];
}

/// One sample of a per-sample CSV, as the detection figure draws it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplePoint {
    /// Loading (true) or unloading.
    pub loading: bool,
    /// Distance along the ray.
    pub s: Real,
    /// The error e.
    pub e: Real,
}

/// Read the per-sample CSV of `helixreach detect --out` (columns `phase,s,e`; rows with an
/// empty `e`, the unused samples, are skipped). Errors name the file, line and field.
pub fn read_detect_samples(path: &Path) -> Result<Vec<SamplePoint>> {
    let mut t = crate::io::CsvInput::open(path)?;
    let hint = "header must contain phase,s,e (helixreach detect --out)";
    let (cp, cs, ce) = (
        t.column("phase", hint)?,
        t.column("s", hint)?,
        t.column("e", hint)?,
    );
    let mut out = Vec::new();
    for (k, rec) in t.reader.records().enumerate() {
        let rec = rec.map_err(|e| crate::io::bad_line(path, k + 2, "record", e.to_string()))?;
        let line = crate::io::line_of(&rec, k + 2);
        if out.len() >= MAX_SAMPLES {
            return Err(crate::io::bad_line(
                path,
                line,
                "samples",
                format!("more than {MAX_SAMPLES}"),
            ));
        }
        if rec.get(ce).unwrap_or("").is_empty() {
            continue;
        }
        let loading = match rec.get(cp).unwrap_or("") {
            "loading" => true,
            "unloading" => false,
            other => {
                return Err(crate::io::bad_line(
                    path,
                    line,
                    "phase",
                    format!("`{other}`: expected loading or unloading"),
                ))
            }
        };
        let s = crate::io::parse_field(path, line, &rec, cs, "s")?;
        let e = crate::io::parse_field(path, line, &rec, ce, "e")?;
        if !(s.is_finite() && e.is_finite()) {
            return Err(crate::io::bad_line(
                path,
                line,
                "s,e",
                format!("({s}, {e}) not finite"),
            ));
        }
        out.push(SamplePoint { loading, s, e });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn headers_match_fields() {
        let s = DetectSampleRecord {
            line: 1,
            phase: "loading",
            s: 0.0,
            pose_position_error: 0.0,
            pose_rotation_error: 0.0,
            marker_x: 0.0,
            marker_y: 0.0,
            marker_z: 0.0,
            predicted_x: 0.0,
            predicted_y: 0.0,
            predicted_z: 0.0,
            e: 0.0,
            flag: "ok",
            in_fit: true,
        };
        assert_eq!(
            csv_out::field_names(&s).unwrap(),
            DetectSampleRecord::HEADER
        );
        let r = DetectRunRecord {
            observations: "a".into(),
            dir: DirColumns {
                dir_kappa: 1.0,
                dir_tau: 0.0,
                dir_omega: 0.0,
            },
            s_measured: None,
            s_return: None,
            confidence: "none",
            reason: "gradual",
            s_reversal: 0.0,
            s_predicted: 0.0,
            marker_arc: 0.0,
            fit_rms: 0.0,
            clamp_x: 0.0,
            clamp_y: 0.0,
            clamp_z: 0.0,
            samples: 0,
            flagged: 0,
            notes: String::new(),
        };
        assert_eq!(csv_out::field_names(&r).unwrap(), DetectRunRecord::HEADER);
    }
}
