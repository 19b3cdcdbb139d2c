//! The seed's error e of one tracked marker: its deviation from the predicted helix, normalised
//! by the helix radius.
//!
//! For a sample at distance s along S̄ (helix (κ, τ) = s·(κ̂, τ̂)), with the marker `o` in the
//! camera frame, the fitted extrinsics `(R, t)` and the predicted marker point `m(s)` at arc
//! length σ ([`super::extrinsics`]):
//!
//! e = |R·o + t − m(s)| / ρ(s),   ρ = L·clamp(κ/(κ² + τ²), ρ_min, 1)
//!
//! — the paper's e ([`crate::helix::error_metric`]) applied to the one node the camera sees,
//! with its safe radius ([`normalizing_radius`], ρ_min = [`RADIUS_FLOOR`]): near the straight
//! rod the helix radius exceeds L and the normaliser stays L.

use super::extrinsics::Rigid;
use super::projection::PoseCurve;
use crate::error::Result;
use crate::helix::error_metric::{normalizing_radius, RADIUS_FLOOR};
use crate::math::{Real, Vec3};

/// The marker in the base frame, its predicted place and e.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarkerError {
    /// `R·o + t` (m).
    pub marker: Vec3,
    /// `m(s)` (m).
    pub predicted: Vec3,
    /// e.
    pub e: Real,
}

/// e of a marker `camera` (camera frame) at distance `s`, marker arc length `sigma`.
pub fn marker_error(
    curve: &PoseCurve,
    camera_to_base: &Rigid,
    sigma: Real,
    s: Real,
    camera: &Vec3,
) -> Result<MarkerError> {
    let h = curve.helix(s)?;
    let predicted = curve.point(s, sigma)?;
    let marker = camera_to_base.apply(camera);
    let rho = normalizing_radius(&h, RADIUS_FLOOR) * curve.length;
    Ok(MarkerError {
        marker,
        predicted,
        e: (marker - predicted).norm() / rho,
    })
}
