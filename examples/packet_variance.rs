//! A scene's wave packets: the slope variance their model leaves to the BRDF where nothing
//! resolves it (`Packet::slope_variance`, summed over the packets reaching a point) against their
//! f64 surface's own (the mean square of its slope, every packet summed), over squares of `SIDE`
//! m tiling the packets' box (at most about 400 of them, evenly strided). A ratio above 1: the
//! surface is rougher than the BRDF is told. docs/bench/packets.md quotes it.
//! `cargo run --release --example packet_variance -- scenes/wake_mast.toml 16`
use glam::DVec2;
use ocean::model::packets::sources::Sources;
use ocean::model::packets::Packet;
use ocean::model::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().ok_or("usage: packet_variance SCENE.toml [SIDE]")?;
    let side: f64 = match args.next() {
        Some(s) => s.parse().map_err(|_| format!("SIDE: {s} is not a length in metres"))?,
        None => 16.0,
    };
    if !(side > 0.0 && side.is_finite()) {
        return Err(format!("SIDE: {side} m, must be positive").into());
    }
    let scene = Scene::load(std::path::Path::new(&path))?;
    let field = Sources::of_scene(&scene)?.field(scene.render.time_s);
    if field.packets.is_empty() {
        return Err(format!("{path}: no wave packets at {} s", scene.render.time_s).into());
    }
    let (lo, hi) =
        field.packets.iter().fold((DVec2::MAX, DVec2::MIN), |(lo, hi), p| (lo.min(p.centre), hi.max(p.centre)));
    let shortest = field.packets.iter().map(Packet::wavelength).fold(f64::INFINITY, f64::min);
    // Eight samples a wavelength of the shortest: its slope's mean square to well under 1%.
    let per_side = (8.0 * side / shortest).ceil() as usize;
    let (columns, rows) = (((hi.x - lo.x) / side).ceil() as usize, ((hi.y - lo.y) / side).ceil() as usize);
    let stride = ((columns * rows) as f64 / 400.0).sqrt().ceil().max(1.0) as usize;
    println!(
        "{} packets, the shortest {shortest:.2} m; squares of {side} m, every {stride} of them",
        field.packets.len()
    );
    let mut ratios = Vec::new();
    let (mut surface_sum, mut model_sum) = (0.0, 0.0);
    for column in (0..columns).step_by(stride) {
        for row in (0..rows).step_by(stride) {
            let corner = lo + DVec2::new(column as f64, row as f64) * side;
            let (surface, model) = field.slope_variance_over(corner, side, per_side);
            // Squares the wake barely reaches would only add noise to the ratios.
            if model > 1e-4 {
                ratios.push(surface / model);
                surface_sum += surface;
                model_sum += model;
            }
        }
    }
    if ratios.is_empty() {
        return Err("no square holds enough of the packets' variance".into());
    }
    ratios.sort_by(f64::total_cmp);
    let quartile = |q: f64| ratios[((ratios.len() - 1) as f64 * q).round() as usize];
    println!(
        "{} squares: slope variance, surface {:.5}, model {:.5}, ratio {:.2}; per square, quartiles {:.2} {:.2} {:.2}",
        ratios.len(),
        surface_sum / ratios.len() as f64,
        model_sum / ratios.len() as f64,
        surface_sum / model_sum,
        quartile(0.25),
        quartile(0.5),
        quartile(0.75)
    );
    Ok(())
}
