//! Physical rod parameters for the dynamics, with the seed paper's two rods as presets.
//!
//! | preset | L | radius h | E | ν | ρ | source |
//! |---|---|---|---|---|---|---|
//! | [`PhysicalRod::paper_sim`] | 1 m | 0.781 mm | 1.12 GPa | 0.33 | 1180 kg/m³ | the default of the paper's disturbance study (§III.D) |
//! | [`PhysicalRod::nitinol`] | 0.5 m | 0.79375 mm (2r = 1.5875 mm) | 67.5 GPa | 0.33 | 6450 kg/m³ | the paper's experimental rod (§IV) |
//!
//! # Derived quantities (solid circular section)
//! - area `A = πh²`, bending stiffness `k_b = EI = Eπh⁴/4`, twisting stiffness
//!   `k_t = GJ = k_b/(1+ν)`, stretching stiffness `k_s = EA`;
//! - the time unit `T₀ = √(ρA L⁴/k_b) = (2L²/h)·√(ρ/E)`: the dynamics in nondimensional form
//!   (lengths in L, energies in `k_b/L`, time in `T₀`) depend only on `h/L`, ν, `L/L_gb` and the
//!   nondimensional speed; E and ρ enter through `T₀` (and `L_gb`) alone;
//! - the gravito-bending length `L_gb = (h²E/(8ρg))^{1/3}` as the paper writes it (§III.D, after
//!   Jawed et al. 2014), with `h` the rod **radius**. Nondimensionally the weight per unit length
//!   is `ρAgL³/k_b = ½(L/L_gb)³`.
//!
//! The paper quotes `L_gb/L = 1.3816` for its nitinol rod; the formula with the radius gives
//! 0.876 (with g = 9.81 m/s²). The quoted value is reproduced (to 0.7 %) only with the diameter
//! in place of `h`, so the paper appears to have used the diameter there;
//! [`PhysicalRod::gravito_bending_length`] follows the formula as written.
//!
//! ```
//! use helixreach::rod::dynamics::presets::PhysicalRod;
//! let p = PhysicalRod::paper_sim();
//! let lgb = p.gravito_bending_length(9.81).unwrap();
//! assert!((lgb - 0.1948).abs() < 1e-3, "{lgb}");
//! // The nitinol rod with the diameter in place of h gives the paper's 1.38.
//! let n = PhysicalRod::nitinol();
//! let with_diameter = PhysicalRod { radius: 2.0 * n.radius, ..n };
//! let r = with_diameter.gravito_bending_length(9.81).unwrap() / n.length;
//! assert!((r - 1.3816).abs() < 0.015, "{r}");
//! ```

use crate::error::{fmt_num, require_positive, Error, Result};
use crate::math::Real;
use crate::rod::params::twist_ratio;
use crate::rod::Material;

/// Standard gravity (m/s²).
pub const STANDARD_GRAVITY: Real = 9.81;

/// Physical parameters of a solid circular elastic rod (SI units).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PhysicalRod {
    /// Length L (m).
    pub length: Real,
    /// Cross-section radius h (m).
    pub radius: Real,
    /// Young's modulus E (Pa).
    pub youngs_modulus: Real,
    /// Poisson's ratio ν ∈ (−1, 0.5].
    pub nu: Real,
    /// Density ρ (kg/m³).
    pub density: Real,
}

/// The named presets, for the CLI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Preset {
    /// [`PhysicalRod::paper_sim`].
    #[default]
    PaperSim,
    /// [`PhysicalRod::nitinol`].
    Nitinol,
}

impl Preset {
    /// The rod of this preset.
    pub fn rod(self) -> PhysicalRod {
        match self {
            Preset::PaperSim => PhysicalRod::paper_sim(),
            Preset::Nitinol => PhysicalRod::nitinol(),
        }
    }

    /// Parse `paper-sim` or `nitinol`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "paper-sim" => Ok(Preset::PaperSim),
            "nitinol" => Ok(Preset::Nitinol),
            _ => Err(Error::invalid(
                "preset",
                name,
                "expected `paper-sim` or `nitinol`",
            )),
        }
    }

    /// The CLI name.
    pub fn name(self) -> &'static str {
        match self {
            Preset::PaperSim => "paper-sim",
            Preset::Nitinol => "nitinol",
        }
    }
}

impl PhysicalRod {
    /// The default rod of the paper's simulations (§III.D): E = 1.12 GPa, ν = 0.33,
    /// ρ = 1180 kg/m³, L = 1 m, h = 0.781 mm.
    pub fn paper_sim() -> Self {
        PhysicalRod {
            length: 1.0,
            radius: 0.781e-3, // m (a material property, not a tolerance)
            youngs_modulus: 1.12e9,
            nu: 0.33,
            density: 1180.0,
        }
    }

    /// The paper's nitinol rod (§IV): L = 0.5 m, 2r = 1.5875 mm, E = 67.5 GPa, ν = 0.33,
    /// ρ = 6450 kg/m³.
    pub fn nitinol() -> Self {
        PhysicalRod {
            length: 0.5,
            radius: 0.5 * 1.5875e-3, // m (a material property, not a tolerance)
            youngs_modulus: 67.5e9,
            nu: 0.33,
            density: 6450.0,
        }
    }

    /// Check every field (finite, > 0; ν in (−1, 0.5]; radius < length).
    pub fn validate(&self) -> Result<()> {
        require_positive("length", self.length)?;
        require_positive("radius", self.radius)?;
        require_positive("youngs_modulus", self.youngs_modulus)?;
        require_positive("density", self.density)?;
        twist_ratio(self.nu)?;
        if self.radius >= self.length {
            return Err(Error::invalid(
                "radius",
                self.radius,
                format!("must be smaller than the length {} m", self.length),
            ));
        }
        // Each field in range can still give derived quantities out of range (E = 1e308 makes
        // k_b overflow, and the time unit 0): refused here, naming the fields they come from.
        for (what, v) in [
            (
                "the bending stiffness k_b = E·πh⁴/4 (N·m²)",
                self.bending_stiffness(),
            ),
            ("the mass per length ρπh² (kg/m)", self.linear_density()),
            ("the time unit √(ρA·L⁴/k_b) (s)", self.time_unit()),
        ] {
            if !(v.is_finite() && v > Real::MIN_POSITIVE.sqrt() && v < Real::MAX.sqrt()) {
                return Err(Error::invalid(
                    "rod",
                    format!(
                        "length = {}, radius = {}, youngs_modulus = {}, density = {}",
                        fmt_num(self.length),
                        fmt_num(self.radius),
                        fmt_num(self.youngs_modulus),
                        fmt_num(self.density)
                    ),
                    format!(
                        "{what} = {} is out of the computable range (between \
                         1e-154 and 1e154)",
                        fmt_num(v)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The twist ratio `c = k_t/k_b = 1/(1+ν)` (ν as validated by [`PhysicalRod::validate`] or
    /// the rig loader; [`crate::math::twist_ratio`] checks it).
    pub fn twist_ratio(&self) -> Real {
        crate::math::twist_ratio_unchecked(self.nu)
    }

    /// Cross-section area `A = πh²` (m²).
    pub fn area(&self) -> Real {
        std::f64::consts::PI * self.radius * self.radius
    }

    /// Bending stiffness `k_b = Eπh⁴/4` (N·m²).
    pub fn bending_stiffness(&self) -> Real {
        self.youngs_modulus * std::f64::consts::PI * self.radius.powi(4) / 4.0
    }

    /// Mass per unit length `ρA` (kg/m).
    pub fn linear_density(&self) -> Real {
        self.density * self.area()
    }

    /// The time unit `T₀ = √(ρA L⁴/k_b)` (s).
    pub fn time_unit(&self) -> Real {
        (self.linear_density() * self.length.powi(4) / self.bending_stiffness()).sqrt()
    }

    /// Slenderness `h/L`.
    pub fn slenderness(&self) -> Real {
        self.radius / self.length
    }

    /// The nondimensional stiffnesses (lengths in L, energies in `k_b/L`): `k_b = 1`,
    /// `k_t = 1/(1+ν)`, `k_s = EA·L²/k_b = 4(L/h)²`.
    pub fn nondimensional_material(&self) -> Result<Material> {
        self.validate()?;
        let s = self.slenderness();
        Material::nondimensional(self.nu, 4.0 / (s * s))
    }

    /// The gravito-bending length `L_gb = (h²E/(8ρg))^{1/3}` (m) for gravity `g` (m/s², > 0).
    pub fn gravito_bending_length(&self, g: Real) -> Result<Real> {
        self.validate()?;
        require_positive("gravity", g)?;
        Ok((self.radius * self.radius * self.youngs_modulus / (8.0 * self.density * g)).cbrt())
    }

    /// The gravity magnitude (m/s²) at which `L_gb/L` equals `ratio` (> 0): the knob the
    /// disturbance study turns to vary `L_gb/L` with the rod unchanged.
    pub fn gravity_for_ratio(&self, ratio: Real) -> Result<Real> {
        self.validate()?;
        require_positive("lgb_ratio", ratio)?;
        let lgb = ratio * self.length;
        Ok(self.radius * self.radius * self.youngs_modulus / (8.0 * self.density * lgb.powi(3)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fields each in range whose derived quantities are not: refused naming the fields.
    #[test]
    fn derived_quantities_out_of_range_are_refused() {
        let mut p = PhysicalRod::paper_sim();
        p.youngs_modulus = 1e308;
        assert!(!p.bending_stiffness().is_finite());
        let e = p.validate().unwrap_err().to_string();
        assert!(
            e.contains("youngs_modulus = 1e308") && e.contains("bending stiffness"),
            "{e}"
        );
        let mut p = PhysicalRod::paper_sim();
        p.density = 1e-300;
        let e = p.validate().unwrap_err().to_string();
        assert!(
            e.contains("density = 1e-300") && e.contains("mass per length"),
            "{e}"
        );
        assert!(PhysicalRod::paper_sim().validate().is_ok());
        assert!(PhysicalRod::nitinol().validate().is_ok());
    }

    #[test]
    fn time_unit_and_stiffness_of_the_paper_rod() {
        let p = PhysicalRod::paper_sim();
        // k_b = 1.12e9·π·(0.781e-3)⁴/4.
        let kb = 1.12e9 * std::f64::consts::PI * 0.781e-3f64.powi(4) / 4.0;
        assert!((p.bending_stiffness() / kb - 1.0).abs() < 1e-14);
        // T₀ = 2L²/h·√(ρ/E).
        let t0 = 2.0 / 0.781e-3 * (1180.0f64 / 1.12e9).sqrt();
        assert!((p.time_unit() / t0 - 1.0).abs() < 1e-12);
        let g = p.gravity_for_ratio(0.6).unwrap();
        assert!((p.gravito_bending_length(g).unwrap() - 0.6).abs() < 1e-12);
    }

    #[test]
    fn bad_parameters_are_named() {
        let mut p = PhysicalRod::paper_sim();
        p.density = Real::NAN;
        let e = p.validate().unwrap_err().to_string();
        assert!(e.contains("density"), "{e}");
        assert!(Preset::parse("steel").is_err());
    }
}
