//! The GPU's shading against the f64 CPU reference (src/measure/reference.rs) on chosen pixels, one BRDF
//! term at a time through the shader's specialization constants.

mod common;

use common::{gpu, render_terms_by};
use glam::DVec2;
use ocean::measure::bench::error_vs_time::{sea_pixels_by_band, BANDS_M};
use ocean::measure::reference::ReferenceScene;
use ocean::model::packets::sources::Sources;
use ocean::model::packets::PacketField;
use ocean::model::scene::{LongestWave, Scene};
use ocean::model::sky::SkyModel;
use ocean::model::waves::{generate, WaveSet};
use ocean::output::{luminance, luminance_rgb};
use ocean::render::footprint::Footprint;
use ocean::render::frame::CameraFrame;
use ocean::render::passes::ocean::{Method, Terms};

const W: u32 = 160;
const H: u32 = 120;

/// Looking down from 30 m at short waves, the sun ahead and high: glitter in view, and no train
/// long enough for the grid, so the visible point is the ray's hit on the rest plane.
fn scene() -> Scene {
    let mut s = Scene::default();
    // The f64 reference evaluates Preetham's sky, and the comparison is of linear radiance.
    s.sky.model = ocean::model::scene::SkyKind::Preetham;
    s.camera.height_m = 30.0;
    s.camera.pitch_deg = -40.0;
    s.camera.fov_y_deg = 40.0;
    s.sun.elevation_deg = 35.0;
    s.wind.speed_mps = 8.0;
    s.waves.count = 40;
    s.waves.lambda_max_m = LongestWave::Metres(4.0);
    s.render.time_s = 12.5;
    s
}

fn relative_error(gpu: f64, cpu: f64, floor: f64) -> f64 {
    (gpu - cpu).abs() / cpu.abs().max(floor)
}

#[test]
fn gpu_shading_matches_the_f64_reference() {
    check_against_reference(Method::Paper, scene(), Tolerance::STEEP);
}

/// A splash's rings in view: each packet in the normal at its weight and the rest of its slope
/// variance in the BRDF, as the f64 footprint adds it (glsl/packets.glsl against
/// render::footprint), by the paper's method and by the full one.
#[test]
fn a_splash_s_shading_matches_the_f64_reference() {
    let mut s = scene();
    let text = "[[splash]]\nposition_m = [34.0, 0.0]\ntime_s = 9.0\nradius_m = 0.25\n";
    s.splashes = Scene::parse(text, "splash").unwrap().splashes;
    check_against_reference(Method::Paper, s.clone(), Tolerance::STEEP);
    check_against_reference(Method::Full, s, Tolerance { sky: 0.10, sky_mean: 0.025, sea_full: 0.05 });
}

/// The full method's sky against the same quadrature with each facet weighted by its projected
/// area and the reflections below the horizon meeting the sea: one shifted textureGrad lookup
/// against the integral it stands for.
#[test]
fn full_method_shading_matches_the_f64_reference() {
    // Measured: sky 6.0% at worst and 1.2% on average (one lookup per pixel: 16% and 4.3%).
    check_against_reference(Method::Full, scene(), Tolerance { sky: 0.10, sky_mean: 0.025, sea_full: 0.05 });
}

/// The same at grazing view on a rough sea, where a good part of every footprint reflects below
/// the horizon: the map's region beyond it (the sea met again) and the entering share in the
/// refracted term.
#[test]
fn full_method_shading_matches_the_f64_reference_at_grazing_view() {
    let mut s = scene();
    s.camera.pitch_deg = -3.0;
    s.wind.speed_mps = 15.0;
    s.sun.elevation_deg = 10.0; // its glitter in view
                                // Measured: sky 7.8% at worst and 2.8% on average, sea 0.8% (one lookup per pixel: 23%, 8.9%
                                // and 2.6%; the paper's own lookup against its own integral in this view: 20% and 8.2%).
    check_against_reference(Method::Full, s, Tolerance { sky: 0.12, sky_mean: 0.045, sea_full: 0.03 });
}

/// What the f64 reference borrows: the scene's waves, camera and sky.
struct Setup {
    waves: WaveSet,
    camera: CameraFrame,
    sky: SkyModel,
    /// The scene's wave packets at its time, in the eye's frame.
    packets: Option<PacketField>,
}

impl Setup {
    fn new(scene: &Scene) -> Setup {
        let waves = generate(scene);
        let camera = CameraFrame::new(scene, &waves, W, H);
        let sky = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
        let sources = Sources::of_scene(scene).unwrap();
        let eye = DVec2::new(scene.camera.x_m, scene.camera.y_m);
        let packets = (!sources.is_empty()).then(|| sources.field(scene.render.time_s).relative_to(eye));
        Setup { waves, camera, sky, packets }
    }

    fn reference(&self, scene: &Scene, full: bool) -> ReferenceScene<'_> {
        let footprint = Footprint {
            camera: &self.camera,
            waves: &self.waves,
            time_s: scene.render.time_s,
            width: W,
            height: H,
            packets: self.packets.as_ref(),
        };
        ReferenceScene { footprint, sky: &self.sky, full }
    }
}

/// The reference's precondition: nothing is displaced anywhere on screen (every train unresolved
/// per grid cell), so the visible point is the ray's hit on the rest plane.
fn assert_nothing_displaced(reference: &ReferenceScene, scene: &Scene) {
    for py in (0..H).step_by(4) {
        for px in (0..W).step_by(4) {
            if let Some(wavelength) = reference.displaced_train(scene.render.grid_cell_px, px as f64, py as f64) {
                panic!("train {wavelength} m resolved by the grid at ({px}, {py})");
            }
        }
    }
}

/// The full method's sky lookup against the integral it stands for, band by band from the eye, as
/// docs/results.md's figures look: 10 m up, 10 degrees down, the sun 20 degrees up ahead. One
/// isotropic lookup per pixel blurred the sky over azimuths no slope reaches and fell 4.6, 5.5,
/// 7.8, 9.1, 9.7% below the f64 quadrature from 10 to 500 m; the pair of lookups along the
/// footprint's longer axis (glsl/brdf.glsl) is within 0.6, 0.7, 0.5, 1.5, 2.4% of it (measured
/// on the calm figure scene; in this view, whose waves are shortened so that the grid displaces
/// none, 0.1-1.9% against the one lookup's 4.3% at 10-20 m).
#[test]
fn full_sky_lookup_keeps_its_integral_in_every_distance_band() {
    let mut s = scene();
    s.camera.height_m = 10.0;
    s.camera.pitch_deg = -10.0;
    s.camera.fov_y_deg = 50.0;
    s.sun.elevation_deg = 20.0;
    s.wind.speed_mps = 4.0;
    let setup = Setup::new(&s);
    let reference = setup.reference(&s, true);
    let camera = &setup.camera;
    assert_nothing_displaced(&reference, &s);
    let gpu = gpu();
    let frame = render_terms_by(&gpu, &s, W, H, Terms { sun: false, sky: true, sea: false }, Method::Full);
    let counts = gpu.validation_counts();
    assert_eq!(counts.error_total(), 0, "{counts:?}");
    let mut compared = 0;
    for (b, pixels) in sea_pixels_by_band(camera, W, H).iter().enumerate() {
        if pixels.len() < 100 || BANDS_M[b] >= 1000.0 {
            continue; // too few pixels, or the horizon's rows, which the reference does not split
        }
        let (mut gpu_sum, mut cpu_sum) = (0.0, 0.0);
        for &i in pixels.iter().step_by(2) {
            let (px, py) = ((i as u32 % W) as f64, (i as u32 / W) as f64);
            let Some(cpu) = reference.shade(px, py) else { continue };
            let g = frame.hdr[i];
            gpu_sum += luminance(g);
            cpu_sum += luminance_rgb(cpu.sky);
        }
        let error = gpu_sum / cpu_sum - 1.0;
        eprintln!("band {}-{} m: GPU sky {:+.2}% from the quadrature", BANDS_M[b], BANDS_M[b + 1], 100.0 * error);
        assert!(error.abs() < 0.03, "band {} m: the sky lookup is {:+.3} off its integral", BANDS_M[b], error);
        compared += 1;
    }
    assert!(compared >= 4, "the view spans too few distance bands ({compared})");
}

/// Per-pixel and mean relative errors allowed for the sky, and per pixel for the full method's
/// refracted term (the paper's is analytic: 0.5%).
struct Tolerance {
    sky: f64,
    sky_mean: f64,
    sea_full: f64,
}

impl Tolerance {
    const STEEP: Tolerance = Tolerance { sky: 0.20, sky_mean: 0.08, sea_full: 0.05 };
}

fn check_against_reference(method: Method, scene: Scene, tolerance: Tolerance) {
    let setup = Setup::new(&scene);
    let reference = setup.reference(&scene, method == Method::Full);

    assert_nothing_displaced(&reference, &scene);
    let gpu = gpu();
    let only = |sun, sky, sea| render_terms_by(&gpu, &scene, W, H, Terms { sun, sky, sea }, method);
    let (sun_frame, sky_frame, sea_frame) =
        (only(true, false, false), only(false, true, false), only(false, false, true));
    let counts = gpu.validation_counts();
    assert_eq!(counts.error_total(), 0, "{counts:?}");

    let mut sun_peak = 0.0f64;
    let mut samples = Vec::new();
    let mut displaced = 0;
    for py in (3..H).step_by(9) {
        for px in (3..W).step_by(11) {
            // Where the grid displaces a packet the visible point is not the rest plane's.
            if reference.displaced_packet(scene.render.grid_cell_px, px as f64, py as f64).is_some() {
                displaced += 1;
                continue;
            }
            let Some(cpu) = reference.shade(px as f64, py as f64) else { continue };
            let i = (py * W + px) as usize;
            sun_peak = sun_peak.max(cpu.sun[1]);
            samples.push((px, py, cpu, sun_frame.hdr[i], sky_frame.hdr[i], sea_frame.hdr[i]));
        }
    }
    assert!(sun_peak > 1.0, "the test view must catch the glitter (peak {sun_peak})");
    assert!(displaced * 2 < samples.len(), "{displaced} pixels displaced, {} compared", samples.len());
    let (mut worst_sun, mut worst_sky, mut worst_sea) = (0.0f64, 0.0f64, 0.0f64);
    let (mut sky_sum, mut sky_count) = (0.0, 0.0);
    for (px, py, cpu, sun, sky, sea) in samples {
        for c in 0..3 {
            // The sun term is exponential in the slope: compare relative to 1% of the glitter's peak.
            let e_sun = relative_error(sun[c] as f64, cpu.sun[c], 0.01 * sun_peak);
            let e_sky = relative_error(sky[c] as f64, cpu.sky[c], 1e-3);
            let e_sea = relative_error(sea[c] as f64, cpu.sea[c], 1e-4);
            // Measured on lavapipe: sun 0.12%, sea 0.09%, sky 17% at worst (red, where the lobe
            // reaches the circumsolar peak) and 4.7% on average.
            assert!(e_sun < 0.01, "sun at ({px}, {py}) channel {c}: GPU {} CPU {} ({cpu:?})", sun[c], cpu.sun[c]);
            // The GPU filters the sky map with one trilinear textureGrad lookup over the 2-sigma
            // footprint; the CPU integrates the Gaussian: the paper's approximation, allowed 20%
            // per pixel and 8% on average.
            sky_sum += e_sky;
            sky_count += 1.0;
            assert!(e_sky < tolerance.sky, "sky at ({px}, {py}) channel {c}: GPU {} CPU {}", sky[c], cpu.sky[c]);
            // The paper's refracted term is analytic; the full method's takes the share of the
            // reflections entering the sea again from the same filtered lookup as the sky.
            let sea_limit = if method == Method::Full { tolerance.sea_full } else { 0.005 };
            assert!(e_sea < sea_limit, "sea at ({px}, {py}) channel {c}: GPU {} CPU {}", sea[c], cpu.sea[c]);
            worst_sun = worst_sun.max(e_sun);
            worst_sky = worst_sky.max(e_sky);
            worst_sea = worst_sea.max(e_sea);
        }
    }
    let sky_mean = sky_sum / sky_count;
    eprintln!(
        "largest relative errors: sun {worst_sun:.4}, sky {worst_sky:.4} (mean {sky_mean:.4}), sea {worst_sea:.4}"
    );
    assert!(sky_mean < tolerance.sky_mean, "mean sky error {sky_mean}");
}
