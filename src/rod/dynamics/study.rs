//! The seed paper's disturbance study (its Fig. 5): the instability point along
//! S̄ = [1, 1, 1]/√3 as one factor varies at a time around the `paper-sim` rod.
//!
//! | factor | values (the others at the base) | knob |
//! |---|---|---|
//! | [`Factor::Nu`] | ν ∈ {0, 0.1, 0.2, 0.33, 0.4, 0.5} | Poisson's ratio (c = 1/(1+ν)) |
//! | [`Factor::YoungsModulus`] | E × {¼, ½, 1, 2, 4} | Young's modulus |
//! | [`Factor::GravityLength`] | L_gb/L ∈ {0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.4} and ∞ (no gravity) | gravity `(0, 0, −g)` with g chosen so that `(h²E/(8ρg))^{1/3}` = L_gb (the rod itself unchanged) |
//! | [`Factor::Speed`] | v ∈ {½, 1, 2, 4, 8, 16} × the base ray speed | ray speed ds/dt |
//! | [`Factor::Jitter`] | d/L ∈ {0, 0.005, 0.01, 0.02, 0.04, 0.08} | jitter magnitude |
//!
//! Every run is an independent [`simulate_ray`]; runs are spread over rayon threads and
//! returned in the table's order (deterministic: a run depends only on its parameters and its
//! seed).

use super::ray::{simulate_ray, SimParams, Simulation};
use crate::directions::Direction;
use crate::error::Result;
use crate::math::{Real, Vec3};

/// A factor of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factor {
    /// Poisson's ratio ν.
    Nu,
    /// Young's modulus E (as a multiple of the base).
    YoungsModulus,
    /// The gravito-bending length ratio L_gb/L (∞ = no gravity).
    GravityLength,
    /// The ray speed (as a multiple of the base).
    Speed,
    /// The jitter magnitude d/L.
    Jitter,
}

impl Factor {
    /// All factors, in the paper's order (Fig. 5 a–e).
    pub const ALL: [Factor; 5] = [
        Factor::Nu,
        Factor::YoungsModulus,
        Factor::GravityLength,
        Factor::Speed,
        Factor::Jitter,
    ];

    /// File-name stem and column name.
    pub fn name(self) -> &'static str {
        match self {
            Factor::Nu => "nu",
            Factor::YoungsModulus => "youngs_modulus",
            Factor::GravityLength => "lgb_over_l",
            Factor::Speed => "speed",
            Factor::Jitter => "jitter",
        }
    }

    /// The values studied (in the unit of the CSV column: ν; E in Pa; L_gb/L; v in 1/s; d/L).
    pub fn values(self, base: &SimParams) -> Vec<Real> {
        match self {
            Factor::Nu => vec![0.0, 0.1, 0.2, 0.33, 0.4, 0.5],
            Factor::YoungsModulus => [0.25, 0.5, 1.0, 2.0, 4.0]
                .iter()
                .map(|f| f * base.rod.youngs_modulus)
                .collect(),
            Factor::GravityLength => {
                vec![0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0, 1.4, Real::INFINITY]
            }
            Factor::Speed => [0.5, 1.0, 2.0, 4.0, 8.0, 16.0]
                .iter()
                .map(|f| f * base.speed)
                .collect(),
            Factor::Jitter => vec![0.0, 0.005, 0.01, 0.02, 0.04, 0.08],
        }
    }

    /// The run parameters for `value` of this factor around `base`.
    pub fn apply(self, base: &SimParams, value: Real) -> Result<SimParams> {
        let mut p = *base;
        match self {
            Factor::Nu => p.rod.nu = value,
            Factor::YoungsModulus => p.rod.youngs_modulus = value,
            Factor::GravityLength => {
                p.gravity = if value.is_finite() {
                    Vec3::new(0.0, 0.0, -base.rod.gravity_for_ratio(value)?)
                } else {
                    Vec3::zeros()
                };
            }
            Factor::Speed => {
                // Keep the number of steps per unit s: Δt ∝ 1/v.
                p.dt = base.dt * base.speed / value;
                p.speed = value;
            }
            Factor::Jitter => {
                p.jitter = value;
                p.dt = p.dt.min(0.25 * p.jitter_period);
            }
        }
        p.validate()?;
        Ok(p)
    }
}

/// One run of the study.
#[derive(Debug, Clone)]
pub struct Run {
    /// The factor varied.
    pub factor: Factor,
    /// Its value.
    pub value: Real,
    /// The simulation, or why it failed (a failed run does not stop the study).
    pub sim: std::result::Result<Simulation, String>,
}

/// The study direction S̄ = [1, 1, 1]/√3.
pub fn study_direction() -> Direction {
    Direction::new(1.0, 1.0, 1.0).expect("constant direction")
}

/// Run the study for `factors` around `base` (every value of every factor), in parallel over
/// runs on `par`, results in table order. `done()` is called after each run (from worker
/// threads).
pub fn run_study(
    base: &SimParams,
    factors: &[Factor],
    par: crate::par::Par,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<Run>> {
    let dir = study_direction();
    let jobs: Vec<(Factor, Real, SimParams)> = factors
        .iter()
        .flat_map(|&f| f.values(base).into_iter().map(move |v| (f, v)))
        .map(|(f, v)| Ok((f, v, f.apply(base, v)?)))
        .collect::<Result<_>>()?;
    par.map(&jobs, |(factor, value, p)| {
        let sim = simulate_ray(&dir, p, &mut |_| {});
        done();
        Run {
            factor: *factor,
            value: *value,
            sim: sim.map_err(|e| e.to_string()),
        }
    })
}
