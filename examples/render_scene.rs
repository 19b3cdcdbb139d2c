//! Draw the default rig at one configuration with the library API (the call a rig-layout tool
//! uses to show a placement): plan one ray, pose the arm at the middle of its trajectory, draw
//! it. `cargo run --example render_scene -- OUT.png [--labels]`.

use helixreach::directions::Direction;
use helixreach::planning::planner::Planner;
use helixreach::planning::rig::{Rig, RollMode};
use helixreach::plot::render::{render_scene, Configuration, RenderOptions, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "render_scene.png".into());
    let labels = args.any(|a| a == "--labels");
    let rig = Rig::load("sawyer-seed")?;
    let planner = Planner::new(rig.clone())?;
    let dir = Direction::new(0.3, 0.9, 0.3)?;
    let s_star = helixreach::sweep::reach::s_star_of(&dir, None)?;
    let plan = planner.plan_ray(&dir, s_star, 0.0, RollMode::Fixed, true)?;
    let traj = planner.trajectory(&plan)?;
    let p = &traj.points[traj.points.len() / 2];
    let scene = Scene::new(&rig)?;
    let mut snap = scene.snapshot(&Configuration {
        q: p.q.clone(),
        kto: p.kto,
        azimuth: plan.azimuth,
    })?;
    snap.title = vec![format!(
        "direction (0.3, 0.9, 0.3), s = {:.3} (s* = {:.3}), t = {:.1} s",
        p.s, s_star, p.t
    )];
    let opts = RenderOptions {
        labels,
        title: format!("rig {}", rig.name),
        ..RenderOptions::default()
    };
    render_scene(&scene, &snap, &opts, std::path::Path::new(&out))?;
    for c in &snap.clearances {
        println!("{} {:.4} m: {} – {}", c.kind.as_str(), c.distance, c.a, c.b);
    }
    Ok(())
}
