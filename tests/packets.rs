//! Local waves on the GPU: a moving hull's wake seen from straight above stays inside the Kelvin
//! wedge behind it and its transverse waves keep pace with it; a splash's rings reach the picture
//! without a validation error, and every bad local-wave key is refused with one line.

mod common;

use common::{assert_clean, gpu, render};
use glam::DVec2;
use ocean::model::scene::Scene;
use ocean::model::waves::G;
use ocean::render::renderer::RenderedFrame;
use std::f64::consts::TAU;

const HULL_M: f64 = 10.0;

/// A 10 m hull at hull Froude number 0.3 (or standing still) on a glassy sea, seen from 400 m
/// straight above, the camera 150 m behind it.
fn wake_scene(moving: bool) -> Scene {
    let boat = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/models/boat.gltf");
    let speed = if moving { 0.3 * (G * HULL_M).sqrt() } else { 0.0 };
    let text = format!(
        r#"
        [camera]
        height_m = 400.0
        pitch_deg = -90.0
        fov_y_deg = 60.0
        x_m = -150.0
        [sun]
        elevation_deg = 35.0
        azimuth_deg = 90.0
        [wind]
        speed_mps = 0.5
        [waves]
        lambda_max_m = "peak"
        [[object]]
        file = "{boat}"
        velocity_mps = [{speed}, 0.0]
        hull_length_m = {HULL_M}
        wake_amplitude_m = 0.3
        "#
    );
    Scene::parse(&text, "wake").unwrap()
}

/// Each pixel's luminance change from `still` to `moving`, with where its ray meets the sea
/// relative to the hull (x along the track, y across).
fn change_around_hull(moving: &RenderedFrame, still: &RenderedFrame, scene: &Scene) -> Vec<(DVec2, f64)> {
    let camera = &moving.frame.camera;
    let hull = DVec2::new(-scene.camera.x_m, -scene.camera.y_m);
    let (w, h) = (moving.width, moving.height);
    let lum = |p: &[f32; 4]| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64;
    let mut out = Vec::new();
    for py in 0..h {
        for px in 0..w {
            let ndc = [(px as f64 + 0.5) / w as f64 * 2.0 - 1.0, (py as f64 + 0.5) / h as f64 * 2.0 - 1.0];
            let Some(hit) = camera.sea_hit(camera.ray(ndc)) else { continue };
            let i = (py * w + px) as usize;
            out.push((hit.point.truncate() - hull, lum(&moving.hdr[i]) - lum(&still.hdr[i])));
        }
    }
    out
}

/// The wake's change to the picture lies behind the hull inside arcsin(1/3) = 19.47 deg of its
/// track: the outer edge, where the rms change per half degree falls to a quarter of its largest,
/// within 1 deg of it 20 to 35 hull lengths behind (there the cusp's own width, r^(1/3)
/// k^(-2/3), is a degree); nothing ahead of the hull and little beyond the wedge. Its transverse waves along the track are 2 pi U^2 / g long, within 5%.
#[test]
fn a_wake_seen_from_above_keeps_to_the_kelvin_wedge() {
    let gpu = gpu();
    let (moving_scene, still_scene) = (wake_scene(true), wake_scene(false));
    let (report, moving) = render(&gpu, &moving_scene, 512, 512);
    assert_clean(&report, "wake");
    let packets = report.packets.expect("the moving hull has a wake");
    assert!(packets.alive > 500 && packets.dropped_energy_share == 0.0, "{packets:?}");
    let (_, still) = render(&gpu, &still_scene, 512, 512);
    let change = change_around_hull(&moving, &still, &moving_scene);

    // The rms change per half degree from the track, 20 to 35 hull lengths behind.
    let (bins, per_degree) = (80, 2.0);
    let mut sum = vec![(0.0, 0usize); bins];
    for (r, d) in &change {
        let (behind, across) = (-r.x, r.y.abs());
        let distance = r.length();
        if behind > 0.0 && (20.0 * HULL_M..35.0 * HULL_M).contains(&distance) {
            let angle = across.atan2(behind).to_degrees();
            if let Some(bin) = sum.get_mut((angle * per_degree) as usize) {
                bin.0 += d * d;
                bin.1 += 1;
            }
        }
    }
    let rms: Vec<f64> = sum.iter().map(|&(s, n)| if n > 0 { (s / n as f64).sqrt() } else { 0.0 }).collect();
    let peak = rms.iter().copied().fold(0.0, f64::max);
    let edge = (rms.iter().rposition(|&v| v >= 0.25 * peak).unwrap() as f64 + 0.5) / per_degree;
    let kelvin = (1.0f64 / 3.0).asin().to_degrees();
    assert!(peak > 0.0 && (edge - kelvin).abs() <= 1.0, "edge {edge} deg: {rms:?}");
    assert!(rms[(24.0 * per_degree) as usize..].iter().all(|&v| v < 0.1 * peak), "beyond the wedge: {rms:?}");
    // Ahead of the hull, past its own waves' reach, the sea is unchanged.
    let ahead = change.iter().filter(|(r, _)| r.x > 3.0 * HULL_M).map(|(_, d)| d.abs()).fold(0.0, f64::max);
    let behind = change.iter().map(|(_, d)| d.abs()).fold(0.0, f64::max);
    assert!(ahead < 0.02 * behind, "ahead {ahead}, behind {behind}");

    // Along the track, 3 to 12 hull lengths behind: the wavelength of the largest Fourier
    // amplitude of the change.
    let u = 0.3 * (G * HULL_M).sqrt();
    let expected = TAU * u * u / G;
    let track: Vec<(f64, f64)> = change
        .iter()
        .filter(|(r, _)| r.y.abs() < 1.0 && (-12.0 * HULL_M..-3.0 * HULL_M).contains(&r.x))
        .map(|(r, d)| (r.x, *d))
        .collect();
    assert!(track.len() > 100, "{}", track.len());
    let power = |lambda: f64| {
        let k = TAU / lambda;
        let (c, s) = track.iter().fold((0.0, 0.0), |(c, s), &(x, d)| (c + d * (k * x).cos(), s + d * (k * x).sin()));
        c * c + s * s
    };
    let measured = (0..=300)
        .map(|i| expected * (0.6 + 0.8 * i as f64 / 300.0))
        .max_by(|a, b| power(*a).total_cmp(&power(*b)))
        .unwrap();
    assert!((measured / expected - 1.0).abs() <= 0.05, "{measured} m against 2 pi U^2 / g = {expected} m");
    eprintln!("wake: edge {edge:.2} deg (Kelvin {kelvin:.2}); transverse {measured:.2} m (2 pi U^2 / g {expected:.2})");
}

/// Each bad local-wave key is refused with one line that names it and what it allows.
#[test]
fn bad_local_wave_keys_are_refused_with_one_line() {
    let object = |keys: &str| format!("[[object]]\nfile = \"boat.gltf\"\nhull_length_m = 10.0\n{keys}\n");
    let splash = |keys: &str| format!("[[splash]]\n{keys}\n");
    let cases = [
        (object("velocity_mps = [nan, 0.0]"), "velocity_mps.x = NaN"),
        (object("velocity_mps = [3.0, inf]"), "velocity_mps.y = inf"),
        (object("velocity_mps = [130.0, 0.0]"), "outside the model's band"),
        (object("wake_amplitude_m = -1.0"), "wake_amplitude_m = -1 is out of range [0, 100]"),
        (object("start_s = nan"), "start_s = NaN"),
        (splash("position_m = [nan, 0.0]\ntime_s = 1.0\nradius_m = 1.0"), "splash 1: position_m.x = NaN"),
        (splash("position_m = [0.0, 0.0]\ntime_s = 1.0\nradius_m = -1.0"), "splash 1: radius_m = -1"),
        (splash("position_m = [0.0, 0.0]\ntime_s = -2.0\nradius_m = 1.0"), "splash 1: time_s = -2"),
        (splash("position_m = [0.0, 0.0]\ntime_s = 1.0\nradius_m = 100.0"), "outside the model's band"),
        (splash("position_m = [0.0, 0.0]\ntime_s = 1.0\nradius_m = 1e-4"), "outside the model's band"),
        (
            "[[wake]]\nposition_m = [0.0, 0.0]\nvelocity_mps = [0.0, 0.0]\nhull_length_m = 5.0\n".to_owned(),
            "wake 1: velocity_mps = [0, 0]: a wake needs a moving hull",
        ),
        (
            "[[wake]]\nposition_m = [0.0, 0.0]\nvelocity_mps = [3.0, 0.0]\nhull_length_m = 0.0\n".to_owned(),
            "wake 1: hull_length_m = 0 is out of range (0, 10000]",
        ),
        ("[packets]\nmax_alive = 200000\n".to_owned(), "packets.max_alive = 200000 is out of range [1, 131072]"),
        ("[packets]\nmax_alive = 0\n".to_owned(), "packets.max_alive = 0"),
    ];
    for (text, expected) in cases {
        let message = Scene::parse(&text, "bad.toml").unwrap_err().to_string();
        assert!(message.contains(expected), "{text}: {message}");
        assert!(!message.contains('\n'), "{message}");
    }
    let hull = Scene::parse(&object("hull_length_m = -2.0").replace("hull_length_m = 10.0\n", ""), "bad.toml");
    assert!(hull.unwrap_err().to_string().contains("hull_length_m = -2 is out of range (0, 10000]"));
}

/// A still floating hull with a draft, rocked by a splash in a light air, radiates a pulse of
/// rings (its model's draft, taken by resolve_hulls); the same hull fixed, or moving, radiates none.
#[test]
fn a_buoy_rocked_by_a_splash_radiates_rings_and_a_fixed_one_none() {
    let buoy = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/models/buoy.gltf");
    let scene = |keys: &str| {
        let text = format!(
            "[wind]\nspeed_mps = 0.5\n[[splash]]\nposition_m = [18.0, 5.0]\ntime_s = 0.0\nradius_m = 2.0\n\
             [[object]]\nfile = \"{buoy}\"\nposition_m = [30.0, 5.0, 0.0]\nscale = 3.0\n{keys}\n"
        );
        let mut scene = Scene::parse(&text, "buoy.toml").unwrap();
        scene.resolve_hulls().unwrap();
        ocean::model::packets::sources::Sources::of_scene(&scene).unwrap()
    };
    let floating = scene("motion = \"floating\"");
    assert_eq!(floating.hulls.len(), 1);
    let hull = &floating.hulls[0];
    // The model is 1 m across with 0.6 m below its waterline, scaled 3 times.
    assert!((hull.plane.draft_m - 1.8).abs() < 1e-6 && (hull.plane.length_m - 3.0).abs() < 1e-6, "{:?}", hull.plane);
    // Once the splash's rings have crossed it, the hull's own circle it: packets centred around
    // it whose carriers point away from it.
    let rings = |t: f64| {
        let field = floating.field(t);
        let splash = scene("motion = \"fixed\"").field(t);
        field.packets.len() - splash.packets.len()
    };
    assert_eq!(rings(0.5), 0, "nothing before the splash's rings arrive");
    let t = (4..40).map(|i| i as f64 * 0.5).find(|&t| rings(t) > 0).expect("the rocked buoy radiates");
    for p in floating.field(t).packets.iter().skip(scene("motion = \"fixed\"").field(t).packets.len()) {
        let out = (p.centre - hull.centre).normalize();
        assert!(out.dot(p.direction) > 0.999, "{p:?}");
    }
    assert!(scene("motion = \"fixed\"").hulls.is_empty());
    let moving = scene("motion = \"floating\"\nvelocity_mps = [2.0, 0.0]");
    assert!(moving.hulls.is_empty() && moving.wakes.len() == 1);
}

/// The GPU's binning (tiles' counts, scan, tiles' writes) leaves exactly the lists the CPU's grid makes
/// for the same packets: every cell's start and every packet index, in packet order.
#[test]
fn the_gpu_bins_the_packets_as_the_cpu_grid_does() {
    use ocean::model::packets::grid::{PacketGrid, PERSPECTIVE_CELLS_PER_SIDE};
    use ocean::render::packets::ENTRIES_PER_PACKET;
    use ocean::render::renderer::{Options, Renderer};
    let gpu = gpu();
    let scene =
        Scene::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/wake_mast.toml"))).unwrap();
    let mut renderer = Renderer::new(&gpu, &scene, 96, 64, Options::default()).unwrap();
    renderer.render(&scene).unwrap();
    let (starts, lists) = renderer.read_packet_lists().unwrap().expect("the scene has local waves");
    let field = renderer.packet_field().unwrap();
    let map = renderer.packet_cell_map().expect("binned in the view's cells");
    let max_entries = ENTRIES_PER_PACKET * scene.packets.max_alive as usize;
    let grid = PacketGrid::new(&field.packets, max_entries, map, PERSPECTIVE_CELLS_PER_SIDE);
    let (cpu_starts, cpu_lists) = grid.lists();
    assert!(cpu_lists.len() > 10_000, "{} entries", cpu_lists.len());
    assert_eq!(starts, cpu_starts, "the cells' starts");
    assert!(lists == cpu_lists, "the lists differ at {:?}", lists.iter().zip(&cpu_lists).position(|(a, b)| a != b));
    assert_eq!(gpu.validation_counts().error_total(), 0);
}
