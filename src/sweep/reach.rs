//! The reachability sweep ([architecture §6](crate::architecture)): every direction of a set is planned on a rig
//! ([`crate::planning::planner::Planner::plan_best`]) and classified as `testable`, `partial` or
//! `blocked`, with the blocking cause. Built on the generic [`crate::sweep::driver`]: parallel
//! over directions only, rows in input order (bitwise identical for any thread count),
//! checkpointed, resumable, shardable, atomic output.
//!
//! Columns: [`REACH_HEADER`] (`reconfigurations`: self-motion reconfigurations at a held pose on
//! the path, see [`crate::planning::planner`]; `backoffs`: drives back along the ray below s* on
//! the path, see [`crate::planning::search`]; `bifurcation`: the bifurcation type the margin
//! past s* was chosen for, `any` when the rig's margin does not depend on it — otherwise the
//! type of [`crate::bifurcation::planning_type`], see
//! [`crate::planning::rig::PlannerSettings::margin_for`]). An unreachable direction is a `blocked` row with its cause, never an
//! error; only a failure of the boundary computation or of the planner's input aborts the sweep.
//!
//! The boundary s* of each direction comes from the continuum conjugate-point test
//! ([`crate::boundary::continuum::critical_s`]) or from a boundary CSV written by
//! `helixreach boundary` ([`BoundaryTable`]).

use crate::directions::Direction;
use crate::error::{Error, Result};
use crate::math::{same_azimuth, tol, Real};
use crate::planning::planner::{AzimuthTargets, Planner, RayPlan};
use crate::planning::rig::RollMode;
use crate::sweep::driver::{self, Row, SweepOptions, SweepSummary};
use crate::sweep::record::fnv1a_hex;
use std::collections::HashMap;
use std::path::Path;

pub use crate::records::REACH_HEADER;

/// s* per direction read from a boundary CSV (`dir_kappa,dir_tau,dir_omega,s_star`, `inf`
/// allowed), or from several boundary CSVs computed with gravity, one per azimuth
/// ([`BoundaryTable::read_per_azimuth`]: gravity makes s* depend on the ray's azimuth).
/// Directions are matched after normalization, to 1e-9.
#[derive(Debug, Clone, Default)]
pub struct BoundaryTable {
    parts: Vec<Part>,
}

/// One boundary CSV of a [`BoundaryTable`].
#[derive(Debug, Clone, Default)]
struct Part {
    map: HashMap<[i64; 3], Real>,
    path: std::path::PathBuf,
    gravity: Option<(Real, Real)>,
}

fn key_of(d: &Direction) -> [i64; 3] {
    let q = |x: Real| (x * 1e9).round() as i64;
    [q(d.kappa), q(d.tau), q(d.omega)]
}

impl BoundaryTable {
    /// Read a boundary CSV. Errors name the file, line and column.
    pub fn read(path: &Path) -> Result<BoundaryTable> {
        Ok(BoundaryTable {
            parts: vec![Part::read(path)?],
        })
    }

    /// Read one boundary CSV ([`BoundaryTable::read`]), or several computed with gravity at
    /// distinct azimuths (`helixreach boundary --method der --gravity --azimuth A`, one file
    /// per azimuth, the same g): a ray planned at azimuth A is then planned to the s* of the
    /// file of A ([`s_star_at`]). Several files without gravity, with different g or with the
    /// same azimuth twice are refused, naming the files.
    pub fn read_per_azimuth(paths: &[std::path::PathBuf]) -> Result<BoundaryTable> {
        crate::limits::check_size("boundary files", paths.len(), crate::limits::MAX_AZIMUTHS)?;
        if paths.len() <= 1 {
            return match paths.first() {
                Some(p) => Self::read(p),
                None => Err(Error::invalid("boundary", "[]", "need at least one file")),
            };
        }
        let mut parts: Vec<Part> = Vec::with_capacity(paths.len());
        for p in paths {
            let part = Part::read(p)?;
            let Some((g, a)) = part.gravity else {
                return Err(Error::File {
                    path: p.clone(),
                    reason: "several --boundary files are one per azimuth, each computed with \
                             gravity (`helixreach boundary --method der --gravity --azimuth A`); \
                             this one has no gravity (a gravity-free s* holds for every \
                             azimuth: give it alone)"
                        .into(),
                });
            };
            for q in &parts {
                let (g0, a0) = q.gravity.expect("every part has gravity");
                if (g - g0).abs() > 1e-12 * g0.abs().max(1.0) {
                    return Err(Error::File {
                        path: p.clone(),
                        reason: format!(
                            "computed with g = {g} m/s², {} with g = {g0}: the boundaries per \
                             azimuth must share the gravity",
                            q.path.display()
                        ),
                    });
                }
                if same_azimuth(a, a0) {
                    return Err(Error::File {
                        path: p.clone(),
                        reason: format!(
                            "computed at azimuth {a} rad, as {} is: one boundary per azimuth",
                            q.path.display()
                        ),
                    });
                }
            }
            parts.push(part);
        }
        Ok(BoundaryTable { parts })
    }

    /// `(g, azimuth)` when the table was computed with gravity (`boundary --method der
    /// --gravity`, recorded in its sidecar), of each of its files; empty for a gravity-free
    /// boundary.
    pub fn gravity(&self) -> Vec<(Real, Real)> {
        self.parts.iter().filter_map(|p| p.gravity).collect()
    }

    /// True when the table holds one boundary per azimuth (several files).
    pub fn per_azimuth(&self) -> bool {
        self.parts.len() > 1
    }

    /// s* of `dir`, if listed (a table of one file; `None` for a table per azimuth, see
    /// [`BoundaryTable::get_at`]).
    pub fn get(&self, dir: &Direction) -> Option<Real> {
        match self.parts.as_slice() {
            [p] => p.get(dir),
            _ => None,
        }
    }

    /// s* of `dir` at azimuth `azimuth`, if listed: a table of one file serves every azimuth
    /// (the planning commands refuse, before planning, an azimuth other than that of a
    /// boundary with gravity); a table per azimuth answers from the file of `azimuth`.
    pub fn get_at(&self, dir: &Direction, azimuth: Real) -> Option<Real> {
        match self.parts.as_slice() {
            [p] => p.get(dir),
            parts => parts
                .iter()
                .find(|p| p.gravity.is_some_and(|(_, a)| same_azimuth(a, azimuth)))
                .and_then(|p| p.get(dir)),
        }
    }

    /// The file the table was read from (its first, for a table per azimuth).
    pub fn path(&self) -> &Path {
        self.parts.first().map_or(Path::new(""), |p| &p.path)
    }

    /// The files the table was read from, for messages (`a.csv, b.csv`).
    pub fn paths_display(&self) -> String {
        let names: Vec<String> = self
            .parts
            .iter()
            .map(|p| p.path.display().to_string())
            .collect();
        names.join(", ")
    }

    /// Refuse, before any work, a direction set that is not all in the table (a boundary
    /// computed on other directions): the error names the file, how many directions are missing
    /// and the first one. Boundary values are never interpolated between directions.
    pub fn check_covers(&self, dirs: &[Direction]) -> Result<()> {
        self.parts.iter().try_for_each(|p| p.check_covers(dirs))
    }

    /// Number of directions listed (of the first file).
    pub fn len(&self) -> usize {
        self.parts.first().map_or(0, |p| p.map.len())
    }

    /// A digest of the table's contents (sorted entries), for the settings record; for a table
    /// per azimuth, of every file's azimuth and digest.
    pub fn digest(&self) -> String {
        match self.parts.as_slice() {
            [p] => p.digest(),
            parts => {
                let each: Vec<String> = parts
                    .iter()
                    .map(|p| {
                        format!(
                            "{}:{}",
                            fmt_real(p.gravity.map_or(Real::NAN, |(_, a)| a)),
                            p.digest()
                        )
                    })
                    .collect();
                fnv1a_hex(each.join("\n").as_bytes())
            }
        }
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Part {
    fn read(path: &Path) -> Result<Part> {
        let mut table = crate::io::CsvInput::open(path)?;
        let col = |name: &str| table.column(name, "");
        let cols = [
            col("dir_kappa")?,
            col("dir_tau")?,
            col("dir_omega")?,
            col("s_star")?,
        ];
        let refused_col = table.column("refused", "").ok();
        let mut map = HashMap::new();
        let mut lines: HashMap<[i64; 3], usize> = HashMap::new();
        for (k, rec) in table.reader.records().enumerate() {
            let line = k + 2;
            let bad = |field: &str, reason: String| crate::io::bad_line(path, line, field, reason);
            let rec = rec.map_err(|e| bad("record", e.to_string()))?;
            let line = crate::io::line_of(&rec, line);
            let bad = |field: &str, reason: String| crate::io::bad_line(path, line, field, reason);
            if let Some(why) = refused_col
                .and_then(|c| rec.get(c))
                .filter(|w| !w.is_empty())
            {
                return Err(bad(
                    "refused",
                    format!("the boundary method gave no s* for this direction: {why}"),
                ));
            }
            let mut v = [0.0; 4];
            for (i, (&c, name)) in cols
                .iter()
                .zip(["dir_kappa", "dir_tau", "dir_omega", "s_star"])
                .enumerate()
            {
                v[i] = crate::io::parse_field(path, line, &rec, c, name)?;
            }
            let d =
                Direction::new(v[0], v[1], v[2]).map_err(|e| bad("direction", e.to_string()))?;
            if v[3].is_nan() || v[3] <= 0.0 {
                return Err(bad("s_star", format!("{} must be > 0 (or inf)", v[3])));
            }
            if let Some(first) = lines.insert(key_of(&d), line) {
                return Err(bad(
                    "direction",
                    format!(
                        "({}, {}, {}) is the direction of line {first} (to 1e-9 after \
                         normalizing): each direction may appear once",
                        v[0], v[1], v[2]
                    ),
                ));
            }
            map.insert(key_of(&d), v[3]);
        }
        Ok(Part {
            map,
            path: path.to_path_buf(),
            gravity: sidecar_gravity(path)?,
        })
    }

    fn get(&self, dir: &Direction) -> Option<Real> {
        self.map.get(&key_of(dir)).copied()
    }

    fn check_covers(&self, dirs: &[Direction]) -> Result<()> {
        let missing: Vec<&Direction> = dirs.iter().filter(|d| self.get(d).is_none()).collect();
        let Some(first) = missing.first() else {
            return Ok(());
        };
        Err(Error::File {
            path: self.path.clone(),
            reason: format!(
                "lists {} of the {} directions to run ({} missing, first ({}, {}, {})): \
                 compute the boundary on the same direction set (same --directions or \
                 --fibonacci/--quarter), or leave --boundary out (the continuum s* is then \
                 computed per direction)",
                dirs.len() - missing.len(),
                dirs.len(),
                missing.len(),
                first.kappa,
                first.tau,
                first.omega
            ),
        })
    }

    fn digest(&self) -> String {
        let mut entries: Vec<String> = self
            .map
            .iter()
            .map(|(k, v)| format!("{},{},{},{}", k[0], k[1], k[2], fmt_real(*v)))
            .collect();
        entries.sort();
        fnv1a_hex(entries.join("\n").as_bytes())
    }
}

/// The `(gravity, azimuth)` settings of the boundary CSV `path`'s sidecar, when it has them.
fn sidecar_gravity(path: &Path) -> Result<Option<(Real, Real)>> {
    let Some(record) = crate::sweep::record::SettingsRecord::read(path)? else {
        return Ok(None);
    };
    let Some(g) = record.settings.get("gravity") else {
        return Ok(None);
    };
    let sidecar = crate::io::sidecar_path(path);
    let num = |name: &str, text: Option<&String>| -> Result<Real> {
        let text = text.ok_or_else(|| {
            Error::invalid(
                format!("{}: settings.{name}", sidecar.display()),
                "missing",
                "a boundary with gravity records its azimuth",
            )
        })?;
        text.parse::<Real>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                Error::invalid(
                    format!("{}: settings.{name}", sidecar.display()),
                    text,
                    "not a finite number",
                )
            })
    };
    Ok(Some((
        num("gravity", Some(g))?,
        num("azimuth", record.settings.get("azimuth"))?,
    )))
}

/// s* of `dir`: from `table` when given (a missing direction is an error naming it), else the
/// continuum conjugate-point test at relative tolerance [`tol::S_STAR_REL`].
pub fn s_star_of(dir: &Direction, table: Option<&BoundaryTable>) -> Result<Real> {
    if let Some(t) = table.filter(|t| t.per_azimuth()) {
        return Err(Error::invalid(
            "boundary",
            t.paths_display(),
            "one boundary per azimuth is used by `reach` (each azimuth planned to its own s*); \
             this command plans with one s* per direction: give one boundary file",
        ));
    }
    match table {
        Some(t) => t.get(dir).ok_or_else(|| {
            Error::invalid(
                "boundary",
                format!("({}, {}, {})", dir.kappa, dir.tau, dir.omega),
                format!("direction not listed in {}", t.path().display()),
            )
        }),
        None => Ok(crate::boundary::continuum::critical_s(dir, tol::S_STAR_REL)?.s_star),
    }
}

/// `(azimuth, s*)` of `dir` at each of `azimuths` from a table per azimuth
/// ([`BoundaryTable::get_at`]); an azimuth or direction the table lacks is an error naming
/// the files.
pub fn s_star_at(
    dir: &Direction,
    table: &BoundaryTable,
    azimuths: &[Real],
) -> Result<Vec<(Real, Real)>> {
    azimuths
        .iter()
        .map(|&a| {
            table.get_at(dir, a).map(|s| (a, s)).ok_or_else(|| {
                Error::invalid(
                    "boundary",
                    format!("({}, {}, {}) at azimuth {a}", dir.kappa, dir.tau, dir.omega),
                    format!("not listed in {}", table.paths_display()),
                )
            })
        })
        .collect()
}

pub use crate::records::fmt_real;

/// The CSV row of a plan (a [`crate::records::reach::ReachRecord`], columns [`REACH_HEADER`]).
pub fn reach_row(p: &RayPlan) -> Result<Row> {
    crate::records::csv_out::fields(&crate::records::reach::ReachRecord::from(p))
}

/// What the sweep plans per direction.
#[derive(Debug, Clone)]
pub struct ReachOptions {
    /// Roll mode.
    pub roll: RollMode,
    /// Azimuths tried per ray (the best is kept).
    pub azimuths: Vec<Real>,
}

/// Plan one direction: its record (the sweep driver writes its fields).
pub fn reach_one(
    planner: &Planner,
    dir: &Direction,
    table: Option<&BoundaryTable>,
    opts: &ReachOptions,
) -> Result<crate::records::reach::ReachRecord> {
    let kind = if planner.rig().planner.type_dependent() {
        Some(crate::bifurcation::planning_type(dir)?)
    } else {
        None
    };
    let plan = match table.filter(|t| t.per_azimuth()) {
        Some(t) => {
            let targets = s_star_at(dir, t, &opts.azimuths)?;
            planner.plan_best_typed_at(
                dir,
                &AzimuthTargets::Each(&targets),
                kind,
                opts.roll,
                false,
            )?
        }
        None => {
            let s_star = s_star_of(dir, table)?;
            planner.plan_best_typed(dir, s_star, kind, &opts.azimuths, opts.roll, false)?
        }
    };
    Ok(crate::records::reach::ReachRecord::from(&plan))
}

/// The settings a reach sweep records (see [`crate::sweep::record`]): a digest of the rig
/// (every field but its name, description and file location), the name and content digest of
/// every file the robot was loaded from ([`RobotModel::sources`](crate::robot::RobotModel::sources):
/// URDF, never-colliding pair list, …), the roll mode, the azimuths, the planner margin, and
/// where s* comes from (a `--boundary` table by the digest of its contents).
pub fn settings(
    planner: &Planner,
    table: Option<&BoundaryTable>,
    opts: &ReachOptions,
    sweep: &SweepOptions,
) -> SweepOptions {
    let mut rig = planner.rig().clone();
    rig.name.clear();
    rig.description.clear();
    rig.source.clear();
    rig.robot.dir = std::path::PathBuf::new();
    let azimuths: Vec<String> = opts.azimuths.iter().map(|&a| fmt_real(a)).collect();
    sweep
        .clone()
        .sweep("reach")
        .setting("rig", planner.rig().name.as_str())
        .setting("rig_digest", fnv1a_hex(format!("{rig:?}").as_bytes()))
        .setting(
            "robot_files",
            crate::sources::sources_setting(planner.model().sources()),
        )
        .setting("roll_mode", opts.roll.as_str())
        .setting("azimuths", azimuths.join(" "))
        .setting("margin", fmt_real(planner.rig().planner.margin))
        .setting(
            "margin_supercritical",
            planner
                .rig()
                .planner
                .margin_supercritical
                .map_or("margin".to_string(), fmt_real),
        )
        .setting(
            "boundary",
            match table {
                Some(t) => format!("table {}", t.digest()),
                None => format!("continuum tol={:e}", tol::S_STAR_REL),
            },
        )
}

/// Run the sweep over `dirs` with the driver's options (output, resume, force, shard,
/// progress); the settings of [`settings`] are recorded in the output. A `table` that lacks
/// any of the directions the run computes (all of `dirs`, or the shard's block) is refused
/// before any work ([`BoundaryTable::check_covers`]).
pub fn run(
    planner: &Planner,
    dirs: &[Direction],
    table: Option<&BoundaryTable>,
    opts: &ReachOptions,
    sweep: &SweepOptions,
) -> Result<SweepSummary> {
    if let Some(t) = table {
        // The directions this run computes (a shard's block only: a table made per shard fits).
        let mine = sweep.shard.map_or(0..dirs.len(), |s| s.range(dirs.len()));
        t.check_covers(&dirs[mine])?;
    }
    let sweep = &settings(planner, table, opts, sweep);
    driver::run(
        dirs,
        |d| vec![fmt_real(d.kappa), fmt_real(d.tau), fmt_real(d.omega)],
        |d| reach_one(planner, d, table, opts),
        sweep,
    )
}
