//! The heights of a scene's first moving object's wake (f64, model::packets): the largest over
//! the rays within 20 degrees of its track at 3 to 48 m behind it, for choosing a wake's
//! amplitude scale. `cargo run --release --example wake_heights -- scenes/objects/wake_sunset.toml`
use glam::DVec2;
use ocean::model::packets::sources::Sources;
use ocean::model::scene::Scene;
fn main() {
    let scene = Scene::load(std::path::Path::new(&std::env::args().nth(1).unwrap())).unwrap();
    let s = Sources::of_scene(&scene).unwrap();
    let f = s.field(scene.render.time_s);
    let o = &scene.objects[0];
    let p = DVec2::new(o.position_m[0], o.position_m[1]);
    let v = DVec2::from(o.velocity_mps).normalize();
    println!("packets {} hull {:?}", f.packets.len(), o.hull_length_m);
    for r in [3.0, 6.0, 12.0, 24.0, 48.0] {
        let mut m: f64 = 0.0;
        for i in 0..400 {
            let a = (i as f64 / 400.0 * 40.0 - 20.0).to_radians();
            let d = -v.rotate(DVec2::from_angle(a));
            m = m.max(f.height(p + d * r).abs());
        }
        println!("r {r} max height {m:.4}");
    }
}
