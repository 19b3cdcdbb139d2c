//! Draw the default rig at one configuration with the library API (the call a rig-layout tool
//! uses to show a placement): `cargo run --example render_scene -- OUT.png [--labels]`.

use helixreach::planning::rig::Rig;
use helixreach::plot::render::{render_scene, Configuration, RenderOptions, Scene};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let out = args.next().unwrap_or_else(|| "render_scene.png".into());
    let labels = args.any(|a| a == "--labels");
    let rig = Rig::load("sawyer-seed")?;
    let scene = Scene::new(&rig)?;
    // A configuration the seed's Sawyer executed, holding the helix (κ, τ, ω) = (2, 3, 0).
    let q = vec![-0.857, -0.873, -1.819, -0.034, 1.860, 2.434, -2.200];
    let mut snap = scene.snapshot(&Configuration {
        q,
        kto: [2.0, 3.0, 0.0],
        azimuth: 0.0,
    })?;
    snap.title = vec!["seed configuration, helix (2, 3, 0)".into()];
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
