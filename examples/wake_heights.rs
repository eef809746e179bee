//! The heights of a scene's first moving object's wake (f64, model::packets): the largest over
//! the rays within 20 degrees of its track at 3 to 48 m behind it, for choosing a wake's
//! amplitude scale. `cargo run --release --example wake_heights -- scenes/objects/wake_sunset.toml`
use glam::DVec2;
use ocean::model::packets::sources::Sources;
use ocean::model::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args().nth(1).ok_or("usage: wake_heights SCENE.toml")?;
    let scene = Scene::load(std::path::Path::new(&path))?;
    let field = Sources::of_scene(&scene)?.field(scene.render.time_s);
    let object = scene
        .objects
        .iter()
        .find(|o| o.velocity_mps != [0.0, 0.0])
        .ok_or_else(|| format!("{path}: no moving object"))?;
    let at = DVec2::new(object.position_m[0], object.position_m[1]);
    let track = DVec2::from(object.velocity_mps).normalize();
    println!("{} packets; hull {:.1} m", field.packets.len(), object.hull_length_m.unwrap_or(0.0));
    for r in [3.0, 6.0, 12.0, 24.0, 48.0] {
        let highest = (0..400)
            .map(|i| (-20.0 + 40.0 * i as f64 / 400.0f64).to_radians())
            .map(|a| field.height(at - track.rotate(DVec2::from_angle(a)) * r).abs())
            .fold(0.0, f64::max);
        println!("{r:5.1} m behind: highest crest {highest:.3} m");
    }
    Ok(())
}
