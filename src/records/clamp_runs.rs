//! Tables of directions with a clamp position: the seed's run index (`trajectories.csv`:
//! `file,…,dir_kappa,dir_tau,dir_omega,clamp_x,clamp_y,clamp_z,…`), read by
//! [`read_seed_runs`], and the reference positions of
//! `helixreach layout --reference` ([`crate::layout::read_references`]). Columns are found by
//! name (others are ignored); errors name the file, the 1-based line and the field.

use crate::directions::Direction;
use crate::error::Result;
use crate::math::Real;
use crate::planning::witness::SeedRun;
use std::path::Path;

/// The columns read, in the order of [`ClampedDirection`]'s numbers.
pub const COLUMNS: [&str; 6] = [
    "dir_kappa",
    "dir_tau",
    "dir_omega",
    "clamp_x",
    "clamp_y",
    "clamp_z",
];

/// The run-file column of the seed's index.
pub const FILE_COLUMN: &str = "file";

/// One row: a direction and where the clamp stood.
#[derive(Debug, Clone, PartialEq)]
pub struct ClampedDirection {
    /// 1-based line in the file (for errors of later checks).
    pub line: usize,
    /// The direction (normalized).
    pub dir: Direction,
    /// The clamp position (m, robot base frame).
    pub clamp: [Real; 3],
    /// The run file, when the table has the [`FILE_COLUMN`] (then never empty).
    pub file: Option<String>,
}

/// Read a table of [`COLUMNS`]; with `with_file` also the [`FILE_COLUMN`], required and
/// non-empty on every row.
pub fn read_clamped_directions(path: &Path, with_file: bool) -> Result<Vec<ClampedDirection>> {
    let mut table = crate::io::CsvInput::open(path)?;
    let hint = format!(
        "header must contain {}{}",
        if with_file { "file," } else { "" },
        COLUMNS.join(",")
    );
    let mut cols = [0usize; 6];
    for (k, n) in COLUMNS.iter().enumerate() {
        cols[k] = table.column(n, &hint)?;
    }
    let file_col = if with_file {
        Some(table.column(FILE_COLUMN, &hint)?)
    } else {
        None
    };
    let mut rows = Vec::new();
    for (k, rec) in table.reader.records().enumerate() {
        let line = k + 2;
        let bad = |field: &str, reason: String| crate::io::bad_line(path, line, field, reason);
        let rec = rec.map_err(|e| bad("record", e.to_string()))?;
        let mut v = [0.0; 6];
        for i in 0..6 {
            v[i] = crate::io::parse_field(path, line, &rec, cols[i], COLUMNS[i])?;
        }
        let file = match file_col {
            Some(c) => {
                let f = rec.get(c).unwrap_or("").trim();
                if f.is_empty() {
                    return Err(bad(FILE_COLUMN, "empty".into()));
                }
                Some(f.to_string())
            }
            None => None,
        };
        rows.push(ClampedDirection {
            line,
            dir: Direction::new(v[0], v[1], v[2]).map_err(|e| bad("direction", e.to_string()))?,
            clamp: [v[3], v[4], v[5]],
            file,
        });
    }
    Ok(rows)
}

/// Read the seed's run index (`trajectories.csv`: columns `file`, `dir_kappa`, `dir_tau`,
/// `dir_omega`, `clamp_x`, `clamp_y`, `clamp_z`); errors name the file, line and field.
pub fn read_seed_runs(index: &Path) -> Result<Vec<SeedRun>> {
    Ok(read_clamped_directions(index, true)?
        .into_iter()
        .map(|r| SeedRun {
            file: r.file.unwrap_or_default(),
            dir: r.dir,
            clamp: r.clamp,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns by name in any order; the file column required only when asked; errors name the
    /// file, line and field.
    #[test]
    fn reads_by_name_and_names_bad_fields() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("runs.csv");
        std::fs::write(
            &p,
            "clamp_z,dir_omega,file,dir_tau,dir_kappa,clamp_y,clamp_x,extra\n\
             -0.1,0,a.txt,0.8,0.6,-0.15,0.75,x\n",
        )
        .unwrap();
        let r = read_clamped_directions(&p, true).unwrap();
        assert_eq!(r[0].clamp, [0.75, -0.15, -0.1]);
        assert_eq!((r[0].dir.kappa, r[0].dir.tau), (0.6, 0.8));
        assert_eq!(r[0].file.as_deref(), Some("a.txt"));
        assert_eq!(r[0].line, 2);
        assert_eq!(read_clamped_directions(&p, false).unwrap()[0].file, None);
        std::fs::write(
            &p,
            "file,dir_kappa,dir_tau,dir_omega,clamp_x,clamp_y,clamp_z\n\
             a.txt,1,0,0,0.7,0,0\n ,1,0,0,0.7,0,0\n",
        )
        .unwrap();
        let e = read_clamped_directions(&p, true).unwrap_err().to_string();
        assert!(e.contains("runs.csv:3") && e.contains("file"), "{e}");
        assert_eq!(read_clamped_directions(&p, false).unwrap().len(), 2);
        std::fs::write(
            &p,
            "dir_kappa,dir_tau,dir_omega,clamp_x,clamp_y\n1,0,0,0.7,0\n",
        )
        .unwrap();
        let e = read_clamped_directions(&p, false).unwrap_err().to_string();
        assert!(e.contains("clamp_z"), "{e}");
    }
}
