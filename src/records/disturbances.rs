//! The disturbance study (`helixreach disturbances --out DIR`, [`crate::rod::dynamics::study`]):
//! per factor `DIR/<factor>.csv`, one [`DisturbanceSampleRecord`] per recorded sample of every
//! value's run (the run's detected point repeated on each of its rows, empty when none), and
//! `DIR/summary.csv`, one [`DisturbanceSummaryRecord`] per run (`shift_rel` relative to the
//! study's base run, empty when either has no detected point).

use super::csv_out::{self, CsvRecord};
use crate::math::Real;
use crate::rod::dynamics::detect::Detection;
use crate::rod::dynamics::study::Run;
use crate::rod::dynamics::Sample;

/// One sample of one run of the study.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DisturbanceSampleRecord {
    /// The factor's value of the run (unit of [`crate::rod::dynamics::study::Factor::values`]).
    #[serde(serialize_with = "csv_out::real")]
    pub value: Real,
    /// Time (s).
    #[serde(serialize_with = "csv_out::real")]
    pub t: Real,
    /// Distance along the ray.
    #[serde(serialize_with = "csv_out::real")]
    pub s: Real,
    /// Helix error e.
    #[serde(serialize_with = "csv_out::real")]
    pub error: Real,
    /// Elastic energy (J).
    #[serde(serialize_with = "csv_out::real")]
    pub energy: Real,
    /// The run's detected onset s_dyn; empty when none.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_dyn: Option<Real>,
    /// The run's threshold crossing s_cross; empty when none.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_cross: Option<Real>,
}

impl CsvRecord for DisturbanceSampleRecord {
    const HEADER: &'static [&'static str] =
        &["value", "t", "s", "error", "energy", "s_dyn", "s_cross"];
}

impl DisturbanceSampleRecord {
    /// Sample `x` of a run with factor value `value` and detected point `detection`.
    pub fn new(value: Real, x: &Sample, detection: Option<&Detection>) -> Self {
        DisturbanceSampleRecord {
            value,
            t: x.t,
            s: x.s,
            error: x.error,
            energy: x.energy,
            s_dyn: detection.map(|d| d.s_dyn),
            s_cross: detection.map(|d| d.s_cross),
        }
    }
}

/// One run of the study: its detected point and its shift against the base run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct DisturbanceSummaryRecord {
    /// The factor's name ([`crate::rod::dynamics::study::Factor::name`]).
    pub factor: &'static str,
    /// The factor's value.
    #[serde(serialize_with = "csv_out::real")]
    pub value: Real,
    /// Detected onset s_dyn; empty when none (or the run failed).
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_dyn: Option<Real>,
    /// Threshold crossing s_cross; empty when none.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub s_cross: Option<Real>,
    /// `s_dyn / s_dyn(base) − 1`; empty without both points.
    #[serde(serialize_with = "csv_out::opt_real")]
    pub shift_rel: Option<Real>,
}

impl CsvRecord for DisturbanceSummaryRecord {
    const HEADER: &'static [&'static str] = &["factor", "value", "s_dyn", "s_cross", "shift_rel"];
}

impl DisturbanceSummaryRecord {
    /// The summary of `run` against the base run's `s_dyn` (`None`, or not finite: no shift).
    pub fn new(run: &Run, base_s_dyn: Option<Real>) -> Self {
        let d = detection(run);
        DisturbanceSummaryRecord {
            factor: run.factor.name(),
            value: run.value,
            s_dyn: d.map(|d| d.s_dyn),
            s_cross: d.map(|d| d.s_cross),
            shift_rel: match (base_s_dyn, d) {
                (Some(b), Some(d)) if b.is_finite() => Some(d.s_dyn / b - 1.0),
                _ => None,
            },
        }
    }
}

/// The detected point of `run` (`None` when it failed or saw no instability).
pub fn detection(run: &Run) -> Option<&Detection> {
    run.sim.as_ref().ok().and_then(|s| s.detection.as_ref())
}

/// The sample rows of `runs` (those of one factor, in order): every sample of every successful
/// run.
pub fn sample_records<'a>(runs: impl IntoIterator<Item = &'a Run>) -> Vec<DisturbanceSampleRecord> {
    runs.into_iter()
        .filter_map(|r| r.sim.as_ref().ok().map(|sim| (r, sim)))
        .flat_map(|(r, sim)| {
            sim.samples
                .iter()
                .map(move |x| DisturbanceSampleRecord::new(r.value, x, sim.detection.as_ref()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv_out::{field_names, fields, to_csv};

    fn sample() -> DisturbanceSampleRecord {
        DisturbanceSampleRecord {
            value: Real::INFINITY,
            t: 0.2,
            s: 0.1 + 0.2,
            error: 1.675e-4,
            energy: 2.1e-28,
            s_dyn: None,
            s_cross: Some(10.796386132343333),
        }
    }

    /// Headers name the serde fields in order; numbers are `{}` of f64 (as the command wrote
    /// them by hand before the record layer), `None` an empty field.
    #[test]
    fn headers_and_numbers_match_the_hand_written_format() {
        let r = sample();
        assert_eq!(field_names(&r).unwrap(), DisturbanceSampleRecord::HEADER);
        let by_hand = format!(
            "value,t,s,error,energy,s_dyn,s_cross\n{},{},{},{},{},,{}\n",
            r.value,
            r.t,
            r.s,
            r.error,
            r.energy,
            r.s_cross.unwrap()
        );
        assert_eq!(to_csv(&[r]).unwrap(), by_hand);
        let m = DisturbanceSummaryRecord {
            factor: "lgb_over_l",
            value: 0.3,
            s_dyn: Some(10.71),
            s_cross: None,
            shift_rel: Some(10.71 / 10.78 - 1.0),
        };
        assert_eq!(field_names(&m).unwrap(), DisturbanceSummaryRecord::HEADER);
        let f = fields(&m).unwrap();
        assert_eq!(f[..4], ["lgb_over_l", "0.3", "10.71", ""]);
        assert_eq!(f[4].parse::<Real>().unwrap(), 10.71 / 10.78 - 1.0);
    }
}
