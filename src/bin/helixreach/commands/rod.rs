//! `helixreach rod`: the rod of a rig (or a preset, with field overrides) and whether gravity
//! matters for it — the gravito-bending length ratio `L_gb/L = (h²E/(8ρg))^{1/3}/L`, the seed
//! paper's criterion (negligible above 0.6) and helixreach's measured one
//! ([`helixreach::rod::gravity`] says how each was obtained). With `--rig`, also how the rig's
//! clamp orients gravity against the rod (the cosine between the clamp tangent d3 and the
//! base frame's up, +z), and what `reach`, `plan`, `layout` and `campaign` do with this rod
//! (`planning`: [`helixreach::rod::gravity::planning_gravity`] at the rig's margin). JSON on
//! stdout.

use helixreach::math::Real;
use helixreach::rod::dynamics::presets::{Preset, STANDARD_GRAVITY};
use helixreach::rod::gravity::assess;
use std::io::Write;

/// Arguments of `helixreach rod`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach rod",
    "$ helixreach rod --preset nitinol"
))]
pub struct Args {
    /// The rod (`--rig`, `--preset`, field overrides; default the embedded `sawyer-seed` rig).
    #[command(flatten)]
    rod: super::rod_args::RodArgs,
    /// Gravity g (m/s², > 0).
    #[arg(long, default_value_t = STANDARD_GRAVITY, allow_negative_numbers = true)]
    g: Real,
}

/// Run `helixreach rod`.
pub fn run(args: Args) -> anyhow::Result<()> {
    let mut rod_args = args.rod.clone();
    if rod_args.rig.is_none() && rod_args.preset.is_none() {
        rod_args.rig = Some("sawyer-seed".into());
    }
    let resolved = rod_args.resolve(Preset::PaperSim)?;
    let a = assess(&resolved.rod, args.g)?;
    let meaning = if a.negligible {
        format!(
            "L_gb/L = {:.3} >= {}: gravity is negligible for this rod; the gravity-free boundary \
             applies",
            a.lgb_over_l, a.measured_threshold
        )
    } else if a.lgb_over_l >= a.seed_threshold {
        format!(
            "L_gb/L = {:.3}: above the seed paper's 0.6 but below the measured {}: gravity may \
             move s* by more than 1 % on this rig",
            a.lgb_over_l, a.measured_threshold
        )
    } else {
        format!(
            "L_gb/L = {:.3} < {}: gravity is not negligible; the gravity-free boundary does not \
             describe this rod",
            a.lgb_over_l, a.seed_threshold
        )
    };
    let clamp = resolved.rig.as_ref().map(|rig| {
        let d3 = rig.clamp_rotation().column(2).into_owned();
        serde_json::json!({
            "clamp_tangent_d3_base": [d3.x, d3.y, d3.z],
            "cos_tangent_to_up": d3.z,
            "orientation": if d3.z > 0.99 {
                "rod up (gravity compresses it along its tangent)"
            } else if d3.z < -0.99 {
                "rod down (gravity stretches it)"
            } else if d3.z.abs() < 0.01 {
                "rod horizontal (gravity bends it)"
            } else {
                "rod inclined"
            },
        })
    });
    // What reach, plan, layout and campaign do with this rig's rod (rod::gravity::planning_gravity).
    let planning = resolved.rig.as_ref().map(|rig| {
        let p = &rig.planner;
        let margin = p.margin.min(p.margin_supercritical.unwrap_or(p.margin));
        match helixreach::rod::gravity::planning_gravity(
            &resolved.rod,
            &resolved.source,
            margin,
            &[],
            &rig.azimuths,
        ) {
            Ok(v) => serde_json::json!({ "verdict": v, "meaning": v.to_string() }),
            Err(e) => serde_json::json!({ "verdict": "refused", "meaning": e.to_string() }),
        }
    });
    let json = serde_json::json!({
        "rod_source": resolved.source,
        "rod": resolved.rod,
        "assessment": a,
        "meaning": meaning,
        "criteria": {
            "seed": "the seed paper's Fig. 5(c): DER dynamics along [1,1,1]/sqrt(3), paper-sim rod, L_gb/L in 0.2..1.4, read by eye (no tolerance stated)",
            "measured": "DER dynamics along [1,1,1]/sqrt(3), paper-sim rod, rod up, n = 30, ray speed 0.01/s: the L_gb/L at which s_dyn moves by 1 % from the gravity-free run, interpolated between 3 (-0.65 %) and 2 (-1.02 %) (docs/RESULTS.md)",
            "static": "DER statics with the weight, n = 40, the seed's three directions, rod up and horizontal: gravity moves s* by 1 % at L_gb/L = 1.1 at most; below, the shift is estimated as 1 % x (1.1 / (L_gb/L))^2 (Koiter's two-thirds law), trusted down to 0.6 (docs/RESULTS.md)",
        },
        "planning": planning,
        "clamp": clamp,
    });
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    serde_json::to_writer_pretty(&mut out, &json)?;
    writeln!(out)?;
    Ok(())
}
