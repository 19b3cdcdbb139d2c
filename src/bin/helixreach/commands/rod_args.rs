//! The rod of the commands that simulate (`simulate`, `boundary --method der`, `bifurcation`):
//! `--rig R` takes the rig's `[rod]` (length, radius or diameter, E, ν, ρ; validated by the rig
//! loader, errors name the rig file and the field), `--preset NAME` one of the seed paper's two
//! rods (`paper-sim`, `nitinol`); `--length`, `--radius`, `--youngs-modulus`, `--nu`,
//! `--density` override single fields of either. Without `--rig` and `--preset` the command's
//! default preset is used. The embedded rig `sawyer-seed` holds the seed's nitinol rod as the
//! experiment used it (L = 0.51 m; the `nitinol` preset is the paper's rounded L = 0.5 m).

use helixreach::math::Real;
use helixreach::planning::rig::Rig;
use helixreach::rod::dynamics::presets::{PhysicalRod, Preset};

/// The rod flags (flattened into each command's `Args`).
#[derive(Debug, Clone, clap::Args)]
pub struct RodArgs {
    /// The rod of this rig (a rig file or an embedded rig name): its `[rod]` table.
    #[arg(long, conflicts_with = "preset")]
    pub rig: Option<String>,
    /// Rod preset: `paper-sim` (L = 1 m, h = 0.781 mm, E = 1.12 GPa, ν = 0.33, ρ = 1180 kg/m³)
    /// or `nitinol` (L = 0.5 m, 2h = 1.5875 mm, E = 67.5 GPa, ν = 0.33, ρ = 6450 kg/m³).
    #[arg(long)]
    pub preset: Option<String>,
    /// Override the rod length L (m).
    #[arg(long, allow_negative_numbers = true)]
    pub length: Option<Real>,
    /// Override the rod radius h (m).
    #[arg(long, allow_negative_numbers = true)]
    pub radius: Option<Real>,
    /// Override Young's modulus E (Pa).
    #[arg(long, allow_negative_numbers = true)]
    pub youngs_modulus: Option<Real>,
    /// Override Poisson's ratio ν ∈ (−1, 0.5] (c = 1/(1+ν)).
    #[arg(long, allow_negative_numbers = true)]
    pub nu: Option<Real>,
    /// Override the density ρ (kg/m³).
    #[arg(long, allow_negative_numbers = true)]
    pub density: Option<Real>,
}

/// The rod a command uses, and where it came from.
#[derive(Debug, Clone)]
pub struct ResolvedRod {
    /// The validated rod.
    pub rod: PhysicalRod,
    /// The rig, when `--rig` was given.
    pub rig: Option<Rig>,
    /// `rig NAME`, `preset NAME` or `default preset NAME`, plus ` with overrides` when a field
    /// flag was given.
    pub source: String,
    /// Whether anything but the default preset was asked for (a rig, a preset or a field flag).
    pub explicit: bool,
}

impl RodArgs {
    /// Resolve the rod (`default` when neither `--rig` nor `--preset` is given). Errors name
    /// the rig file and field, or the flag.
    pub fn resolve(&self, default: Preset) -> anyhow::Result<ResolvedRod> {
        let (mut rod, rig, mut source) = match (&self.rig, &self.preset) {
            (Some(r), _) => {
                let rig = Rig::load(r)?;
                (rig.rod, Some(rig), format!("rig {r}"))
            }
            (None, Some(p)) => (Preset::parse(p)?.rod(), None, format!("preset {p}")),
            (None, None) => (
                default.rod(),
                None,
                format!("default preset {}", default.name()),
            ),
        };
        let overrides = [
            self.length,
            self.radius,
            self.youngs_modulus,
            self.nu,
            self.density,
        ];
        let overridden = overrides.iter().any(Option::is_some);
        if let Some(v) = self.length {
            rod.length = v;
        }
        if let Some(v) = self.radius {
            rod.radius = v;
        }
        if let Some(v) = self.youngs_modulus {
            rod.youngs_modulus = v;
        }
        if let Some(v) = self.nu {
            rod.nu = v;
        }
        if let Some(v) = self.density {
            rod.density = v;
        }
        if overridden {
            source.push_str(" with overrides");
            rod.validate().map_err(|e| {
                anyhow::anyhow!(
                    "the rod of {source} (--length/--radius/--youngs-modulus/--nu/--density): {e}"
                )
            })?;
        }
        Ok(ResolvedRod {
            rod,
            rig,
            source,
            explicit: self.rig.is_some() || self.preset.is_some() || overridden,
        })
    }
}
