//! `helixreach simulate`: DER dynamics along one ray (thin glue over
//! [`helixreach::rod::dynamics::simulate_ray`]). Writes the series `t,s,kappa,tau,omega,error,
//! energy` to `--out` (atomically) and prints the detection as JSON on stdout.
//!
//! `--unload` runs the seed's protocol: load, hold `--hold` seconds at the turn (`--s-turn`, or
//! where the loading run would stop: the confirmed jump plus 5 %), unload to s = 0 at the same
//! speed. The series then has a last column `phase` (`load`, `hold`, `unload`) and the JSON
//! reports `s_turn` and `s_return` (where unloading rejoined the helix; see
//! `helixreach::rod::dynamics::ray`).
//!
//! The rod is the rig's with `--rig` (its clamp pose places the centerline and orients
//! gravity), a preset with `--preset`, or `paper-sim` (module `rod_args`). `--centerline FILE`
//! writes the node positions and material frames of every K-th sample
//! (`helixreach::records::centerline`).

use anyhow::Context;
use helixreach::directions::Direction;
use helixreach::math::{Real, Vec3};
use helixreach::rod::dynamics::centerline::Placement;
use helixreach::rod::dynamics::presets::{Preset, STANDARD_GRAVITY};
use helixreach::rod::dynamics::{simulate_ray, SimParams, Simulation, Unload};
use helixreach::Error;
use std::io::Write;
use std::path::PathBuf;

/// Arguments of `helixreach simulate`.
#[derive(Debug, clap::Args)]
#[command(after_help = examples!(
    "$ helixreach simulate --direction 1,0,0 --n-edges 12 --s-max 7 --out series.csv",
    "> helixreach simulate --direction 0.6,0.8,0 --gravity --unload --out series.csv"
))]
pub struct Args {
    /// Search direction κ̂,τ̂,ω̂ (normalized; κ̂ ≥ 0), e.g. `1,1,1`.
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        required = true
    )]
    direction: Vec<Real>,
    /// Ray speed v = ds/dt (1/s): s(t) = v·t, with s the nondimensional distance along the ray
    /// (not the end speed; the mean end speed is reported).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    speed: Real,
    /// Number of edges n (≥ 4).
    #[arg(long, default_value_t = 40)]
    n_edges: usize,
    /// Time step Δt (s).
    // A time step (the default of `SimParams::dt`), not a tolerance.
    #[arg(long, default_value_t = 2e-3, allow_negative_numbers = true)]
    dt: Real,
    /// Gravity g = 9.81 m/s² along −z of the rig's base frame (with `--rig`: the rig's clamp
    /// orientation decides how it loads the rod), or of the clamp frame without `--rig` (the
    /// rod points up, as in the seed rig).
    #[arg(long)]
    gravity: bool,
    /// Gravity vector gx,gy,gz (m/s², base frame of the rig; the clamp frame without `--rig`),
    /// instead of --gravity.
    #[arg(
        long,
        allow_negative_numbers = true,
        value_delimiter = ',',
        conflicts_with = "gravity"
    )]
    gravity_vector: Option<Vec<Real>>,
    /// Jitter magnitude d/L of the imposed end (fraction of the rod length).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    jitter: Real,
    /// Jitter knot period (s; at least 2·dt).
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    jitter_period: Real,
    /// Jitter seed.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Mass-proportional viscous damping ζ (1/s). `--unload` needs it > 0 (e.g. 2): undamped,
    /// the ringing after the snap hides the return.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    damping: Real,
    /// The rod (`--rig`, `--preset`, field overrides; default `paper-sim`).
    #[command(flatten)]
    rod: super::rod_args::RodArgs,
    /// Helix azimuth α (rad, as every command's `--azimuth`) about the clamp tangent: the helix
    /// first curls toward cos α·d1 + sin α·d2 of the clamp frame (with gravity, α changes the
    /// run). Default 0.
    #[arg(long, allow_negative_numbers = true)]
    azimuth: Option<Real>,
    // `--azimuth-deg`: the earlier spelling in degrees, kept hidden.
    #[arg(
        long,
        hide = true,
        conflicts_with = "azimuth",
        allow_negative_numbers = true
    )]
    azimuth_deg: Option<Real>,
    /// Write the centerline (node positions and material frames, base frame of the rig — the
    /// clamp frame without `--rig`) of every K-th recorded sample to this CSV.
    #[arg(long)]
    centerline: Option<PathBuf>,
    /// With --centerline: keep every K-th recorded sample (K ≥ 1).
    #[arg(long, default_value_t = 10, requires = "centerline")]
    centerline_stride: usize,
    /// Largest s simulated.
    #[arg(long, default_value_t = 40.0, allow_negative_numbers = true)]
    s_max: Real,
    /// Sample spacing in s.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true)]
    record_ds: Real,
    /// Load, hold and unload (the seed's protocol).
    #[arg(long)]
    unload: bool,
    /// With --unload: where loading turns (default: the confirmed jump plus 5 %).
    #[arg(long, requires = "unload", allow_negative_numbers = true)]
    s_turn: Option<Real>,
    /// With --unload: hold time at the turn (s).
    #[arg(
        long,
        requires = "unload",
        default_value_t = 1.0,
        allow_negative_numbers = true
    )]
    hold: Real,
    /// Output CSV (t,s,kappa,tau,omega,error,energy[,phase]), written atomically (`-`:
    /// standard output, before the JSON summary).
    #[arg(long)]
    out: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    force: bool,
}

/// Run `helixreach simulate`.
pub fn run(args: Args) -> anyhow::Result<()> {
    use helixreach::limits::{check_size, MAX_N_EDGES};
    // The output is checked before the simulation: a refused path fails at once.
    let out = helixreach::io::Output::new(&args.out).force(args.force);
    out.check()?;
    check_size("--n-edges", args.n_edges, MAX_N_EDGES)?;
    let [k, t, w] = <[Real; 3]>::try_from(args.direction.as_slice())
        .map_err(|_| Error::invalid("direction", format!("{:?}", args.direction), "give K,T,W"))?;
    let dir = Direction::new(k, t, w)?;
    let resolved = args.rod.resolve(Preset::PaperSim)?;
    let rod = resolved.rod;
    let azimuth = match (args.azimuth, args.azimuth_deg) {
        (Some(a), _) => a,
        (None, Some(d)) => d.to_radians(),
        (None, None) => 0.0,
    };
    let placement = match &resolved.rig {
        Some(rig) => Placement::new(
            rig.clamp.translation.vector,
            rig.clamp_rotation(),
            azimuth,
            rod.length,
        )?,
        None => Placement::new(
            Vec3::zeros(),
            helixreach::math::Mat3::identity(),
            azimuth,
            rod.length,
        )?,
    };
    if args.centerline_stride == 0 {
        return Err(Error::invalid("--centerline-stride", 0, "must be >= 1").into());
    }
    let centerline_out = args.centerline.as_ref().map(|c| {
        helixreach::io::Output::new(c)
            .force(args.force)
            .input(&args.out)
    });
    if let Some(c) = &centerline_out {
        c.check()?;
    }
    let gravity_base = match (&args.gravity_vector, args.gravity) {
        (Some(g), _) => {
            let [x, y, z] = <[Real; 3]>::try_from(g.as_slice())
                .map_err(|_| Error::invalid("gravity_vector", format!("{g:?}"), "give GX,GY,GZ"))?;
            Vec3::new(x, y, z)
        }
        (None, true) => Vec3::new(0.0, 0.0, -STANDARD_GRAVITY),
        (None, false) => Vec3::zeros(),
    };
    let gravity = placement.to_helix_frame(&gravity_base);
    let p = SimParams {
        rod,
        n_edges: args.n_edges,
        dt: args.dt,
        speed: args.speed,
        gravity,
        damping: args.damping,
        jitter: args.jitter,
        jitter_period: args.jitter_period,
        seed: args.seed,
        s_max: args.s_max,
        record_ds: args.record_ds,
        unload: args.unload.then_some(Unload {
            s_turn: args.s_turn,
            hold: args.hold,
        }),
        centerline_stride: if args.centerline.is_some() {
            args.centerline_stride
        } else {
            0
        },
        ..SimParams::default()
    };
    p.validate()?;
    let bar = progress_bar(args.s_max);
    let started = std::time::Instant::now();
    let sim = simulate_ray(&dir, &p, &mut |s| {
        bar.set_position((s * 100.0) as u64);
        bar.set_message(format!("{s:.2}"));
    })?;
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    out.write(helixreach::records::series::series_csv(&sim)?.as_bytes())?;
    if let Some(c) = &centerline_out {
        let text = helixreach::records::centerline::centerline_csv(&sim.centerlines, &placement)?;
        c.write(text.as_bytes())?;
    }
    let json = summary_json(&dir, &p, &sim, wall, &resolved.source, &gravity_base);
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    serde_json::to_writer_pretty(&mut out, &json)?;
    writeln!(out)?;
    out.flush().context("writing to stdout")?;
    Ok(())
}

/// A progress bar over s ∈ [0, s_max] on stderr (hidden when stderr is not a terminal).
pub fn progress_bar(s_max: Real) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new((s_max * 100.0) as u64);
    bar.set_draw_target(if super::global().quiet {
        indicatif::ProgressDrawTarget::hidden()
    } else {
        indicatif::ProgressDrawTarget::stderr()
    });
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} s = {msg} ({elapsed})")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

fn summary_json(
    dir: &Direction,
    p: &SimParams,
    sim: &Simulation,
    wall: Real,
    rod_source: &str,
    gravity_base: &Vec3,
) -> serde_json::Value {
    let finite = |x: Real| if x.is_finite() { Some(x) } else { None };
    let lgb = p
        .rod
        .gravito_bending_length(STANDARD_GRAVITY)
        .ok()
        .map(|l| l / p.rod.length);
    serde_json::json!({
        "direction": [dir.kappa, dir.tau, dir.omega],
        "s_dyn": finite(sim.s_dyn()),
        "s_turn": sim.s_turn,
        "s_return": sim.s_return,
        "hysteresis": sim.s_return.map(|r| sim.s_dyn() - r).and_then(finite),
        "detection": sim.detection,
        "speed_convention": "ray speed ds/dt (1/s)",
        "speed": p.speed,
        "mean_end_speed_m_per_s": sim.mean_end_speed,
        "rod_source": rod_source,
        "rod": p.rod,
        "lgb_over_l_at_9.81": lgb,
        "gravity_base_frame": [gravity_base.x, gravity_base.y, gravity_base.z],
        "gravity_clamp_frame": [p.gravity.x, p.gravity.y, p.gravity.z],
        "jitter": p.jitter,
        "n_edges": p.n_edges,
        "dt": p.dt,
        "time_unit_s": sim.time_unit,
        "steps": sim.steps,
        "newton_iterations": sim.newton_iterations,
        "substeps": sim.substeps,
        "stopped_on_failure": sim.stopped_on_failure,
        "samples": sim.samples.len(),
        "wall_time_s": wall,
    })
}
