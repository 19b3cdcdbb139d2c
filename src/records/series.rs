//! The DER dynamics series (`helixreach simulate --out`, the demo's `series_N.csv`): one row per
//! recorded sample, columns [`SeriesRecord::HEADER`]; with unloading ([`Simulation::s_turn`]
//! set) a last column `phase` (`load`, `hold`, `unload`), columns [`PhasedSeriesRecord::HEADER`].
//! Read back (the figure's columns `t,s,error`) by [`read_series`](super::read_series).

use super::csv_out::{self, CsvRecord};
use crate::error::Result;
use crate::math::Real;
use crate::rod::dynamics::{Sample, Simulation};

/// One sample of a series.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SeriesRecord {
    /// Time (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Distance along the ray.
    #[serde(serialize_with = "csv_out::real")]
    pub s: Real,
    /// κ = s·κ̂.
    #[serde(serialize_with = "csv_out::real")]
    pub kappa: Real,
    /// τ = s·τ̂.
    #[serde(serialize_with = "csv_out::real")]
    pub tau: Real,
    /// ω = s·ω̂.
    #[serde(serialize_with = "csv_out::real")]
    pub omega: Real,
    /// Helix error e.
    #[serde(serialize_with = "csv_out::real")]
    pub error: Real,
    /// Elastic energy (J).
    #[serde(serialize_with = "csv_out::real")]
    pub energy: Real,
}

impl CsvRecord for SeriesRecord {
    const HEADER: &'static [&'static str] = &["t", "s", "kappa", "tau", "omega", "error", "energy"];
}

impl From<&Sample> for SeriesRecord {
    fn from(x: &Sample) -> Self {
        SeriesRecord {
            t: x.t,
            s: x.s,
            kappa: x.kappa,
            tau: x.tau,
            omega: x.omega,
            error: x.error,
            energy: x.energy,
        }
    }
}

/// One sample of a series with unloading: [`SeriesRecord`] and its phase. The csv writer puts a
/// nested struct's fields in place (it cannot serialize `#[serde(flatten)]`, a map), so the
/// row is the sample's seven columns and then `phase`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct PhasedSeriesRecord {
    /// The sample's columns.
    pub sample: SeriesRecord,
    /// `load`, `hold` or `unload`.
    pub phase: &'static str,
}

impl CsvRecord for PhasedSeriesRecord {
    const HEADER: &'static [&'static str] = &[
        "t", "s", "kappa", "tau", "omega", "error", "energy", "phase",
    ];
}

impl From<&Sample> for PhasedSeriesRecord {
    fn from(x: &Sample) -> Self {
        PhasedSeriesRecord {
            sample: x.into(),
            phase: x.phase.name(),
        }
    }
}

/// The series of `sim` as CSV text: [`PhasedSeriesRecord`]s when it unloads, else
/// [`SeriesRecord`]s.
pub fn series_csv(sim: &Simulation) -> Result<String> {
    if sim.s_turn.is_some() {
        let rows: Vec<PhasedSeriesRecord> = sim.samples.iter().map(Into::into).collect();
        csv_out::to_csv(&rows)
    } else {
        let rows: Vec<SeriesRecord> = sim.samples.iter().map(Into::into).collect();
        csv_out::to_csv(&rows)
    }
}
