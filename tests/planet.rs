//! The spherical sea: the limb at the analytic dip within a pixel, a picture that changes
//! smoothly with the eye's height, and the flat sea's picture kept where the curvature is
//! negligible.

mod common;

use common::{assert_clean, gpu, luminance, render, render_terms, render_with};
use ocean::embed::Shading;
use ocean::model::scene::Scene;
use ocean::render::frame::CameraFrame;
use ocean::render::passes::ocean::{ShaderConfig, Terms};
use ocean::render::renderer::RenderedFrame;

/// The first row (from the top) of column `x` where a render of the sea's terms alone (no sky
/// behind) has any light: the pixel the limb crosses, which holds its share of the sea.
fn first_sea_row(frame: &RenderedFrame, x: u32) -> Option<u32> {
    (0..frame.height).find(|&y| luminance(frame.hdr[(y * frame.width + x) as usize]) > 0.0)
}

/// The analytic limb's row at column x: the pixel whose span holds the ray of depression
/// arcsin(s) = the dip, found by bisection on the depression's sine -r.z / |r|, which grows down
/// every column of a camera with no roll.
fn limb_row(camera: &CameraFrame, x: u32, width: u32, height: u32) -> f64 {
    let ndc_x = (x as f64 + 0.5) / width as f64 * 2.0 - 1.0;
    let depression = |y: f64| {
        let r = camera.ray([ndc_x, y]);
        -r.z / r.length()
    };
    let (mut lo, mut hi) = (-1.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if depression(mid) > camera.dip_sine() {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo + 1.0) / 2.0 * height as f64
}

#[test]
fn the_limb_sits_at_the_analytic_dip_within_a_pixel() {
    let gpu = gpu();
    let (w, h) = (96u32, 72u32);
    // A field of view four dips tall, level: the limb lies a quarter of the image below the centre,
    // where a flat sea's horizon would be. At 2 m the dip is 0.045 degrees.
    for height_m in [2.0, 100.0, 10e3, 100e3] {
        let mut scene = Scene::default();
        scene.camera.height_m = height_m;
        scene.camera.fov_y_deg = 4.0 * scene.planet.dip(height_m).to_degrees();
        let frame = render_terms(&gpu, &scene, w, h, Terms::ALL);
        let camera = &frame.frame.camera;
        assert!(
            limb_row(camera, w / 2, w, h) - h as f64 / 2.0 > 10.0,
            "{height_m} m: the test needs the limb well below the level horizon"
        );
        for x in [0, w / 4, w / 2, w - 1] {
            let expected = limb_row(camera, x, w, h).floor();
            let found = first_sea_row(&frame, x).unwrap_or(h) as f64;
            assert!(
                (found - expected).abs() <= 1.0,
                "{height_m} m, column {x}: the sea begins at row {found}, the limb is in row {expected}"
            );
        }
    }
}

/// Rec. 709 luminance summed over the pixels whose ray meets the sea below the limb, and their count.
fn sea_mean(frame: &RenderedFrame) -> f64 {
    let camera = &frame.frame.camera;
    let (w, h) = (frame.width, frame.height);
    let (mut sum, mut count) = (0.0, 0);
    for y in 0..h {
        for x in 0..w {
            if camera.pixel_distance(x, y, w, h).is_some() {
                sum += luminance(frame.hdr[(y * w + x) as usize]);
                count += 1;
            }
        }
    }
    assert!(count > 0, "no sea in view");
    sum / count as f64
}

#[test]
fn the_picture_changes_smoothly_from_a_deck_to_the_top_of_the_sky() {
    let gpu = gpu();
    let (w, h) = (48u32, 36u32);
    // The sun 30 degrees up: twelve heights a decade from 2 m to beyond geostationary orbit, where
    // the whole disc is in view.
    let heights: Vec<f64> = (0..=92).map(|i| 2.0 * 10f64.powf(i as f64 / 12.0)).filter(|&h| h <= 40e6).collect();
    // The view looks 15 degrees below the limb (straight down once the limb is 75 degrees down),
    // so that near the sea the image spans many waves out to the limb, not a patch of a few.
    let means: Vec<f64> = heights
        .iter()
        .map(|&height_m| {
            let mut scene = Scene::default();
            scene.camera.height_m = height_m;
            let dip = scene.planet.dip(height_m).to_degrees();
            scene.camera.pitch_deg = -(dip + 15.0).min(90.0);
            scene.camera.fov_y_deg = 60.0;
            scene.sun.elevation_deg = 30.0;
            // The sky's and the water's light, the sun's glitter apart: resolved pixel by pixel
            // (the normal keeps what a pixel's box filter keeps), its glints' mean over a 48 x 36
            // image moves by several percent from one height to the next (measured -4.2%, -0.1%,
            // -6.1% over the first three steps), as a real glitter's does.
            let shader = ShaderConfig { terms: Terms { sun: false, sky: true, sea: true }, ..ShaderConfig::default() };
            let (report, frame) = render_with(&gpu, &scene, w, h, Shading { shader, ..Shading::default() });
            assert_clean(&report, &format!("{height_m} m"));
            sea_mean(&frame)
        })
        .collect();
    // A jump is a step out of line with both of its neighbours: at twelve heights a decade the
    // picture's own changes (the glint and the night side entering and leaving the frame as it
    // turns down) take several steps alike, under 12% each.
    let steps: Vec<f64> = means.windows(2).map(|m| (m[1] / m[0]).ln()).collect();
    for i in 0..steps.len() {
        let neighbours = [i.checked_sub(1), Some(i + 1)]
            .iter()
            .filter_map(|j| j.and_then(|j| steps.get(j)))
            .fold(0.0f64, |a, s| a.max(s.abs()));
        assert!(
            steps[i].abs() <= 0.15 && steps[i].abs() <= 2.0 * neighbours + 0.03,
            "the sea's mean radiance jumps by {:.1}% from {:.0} m to {:.0} m ({:.4} -> {:.4}; its neighbouring steps {:.1}%)",
            100.0 * steps[i].exp_m1(),
            heights[i],
            heights[i + 1],
            means[i],
            means[i + 1],
            100.0 * neighbours
        );
    }
}

#[test]
fn where_the_curvature_is_negligible_the_flat_seas_picture_is_kept() {
    let gpu = gpu();
    let (w, h) = (96u32, 72u32);
    let scene =
        Scene::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/high_altitude.toml"))).unwrap();
    // Preetham's sky, which does not depend on the planet's radius (the physical sky's air is a
    // shell over it).
    let mut scene = scene;
    scene.sky.model = ocean::model::scene::SkyKind::Preetham;
    let mut flat = scene.clone();
    flat.planet.radius_m = 1e9;
    let (report, round) = render(&gpu, &scene, w, h);
    assert_clean(&report, "the Earth");
    let (report, nearly_flat) = render(&gpu, &flat, w, h);
    assert_clean(&report, "a planet of 10^6 km");
    // Rows whose sea lies within 10 km (the sphere's drop there is 7.9 m below an eye 1 km up, its
    // normal tilted 0.09 degrees): each row's mean within 1% of the nearly flat sea's.
    let camera = &round.frame.camera;
    let mut rows = 0;
    for y in 0..h {
        if !(0..w).all(|x| camera.pixel_distance(x, y, w, h).is_some_and(|d| d < 10e3)) {
            continue;
        }
        let mean = |f: &RenderedFrame| (0..w).map(|x| luminance(f.hdr[(y * w + x) as usize])).sum::<f64>() / w as f64;
        let (a, b) = (mean(&round), mean(&nearly_flat));
        assert!((a / b - 1.0).abs() < 0.01, "row {y}: {a:.4} on the Earth, {b:.4} on a nearly flat sea");
        rows += 1;
    }
    assert!(rows > h / 2, "only {rows} rows within 10 km");
}

/// A view straight down from `height_m` with a field of view `fov_deg`, the sun `sun_deg` up
/// (towards +x, the top of the image) at the point below the eye.
fn straight_down(height_m: f64, fov_deg: f64, sun_deg: f64) -> Scene {
    let mut scene = Scene::default();
    scene.camera.height_m = height_m;
    scene.camera.pitch_deg = -90.0;
    scene.camera.fov_y_deg = fov_deg;
    scene.sun.elevation_deg = sun_deg;
    scene
}

#[test]
fn from_geostationary_orbit_the_sea_is_a_disc_with_a_limb() {
    let gpu = gpu();
    let (w, h) = (96u32, 96u32);
    // The sun overhead: every visible point has it at least 9 degrees up, so the whole disc is lit.
    let scene = straight_down(35_786e3, 20.0, 90.0);
    let frame = render_terms(&gpu, &scene, w, h, Terms::ALL);
    let camera = &frame.frame.camera;
    // Each pixel against the limb's cone: its centre ray's depression sine over the dip's, in
    // pixels of that sine's change across the pixel; the pixels the limb crosses are left out.
    let mut inside = 0;
    for y in 0..h {
        for x in 0..w {
            let ndc = |px: f64, n: u32| (px + 0.5) / n as f64 * 2.0 - 1.0;
            let depression = |px: f64, py: f64| {
                let r = camera.ray([ndc(px, w), ndc(py, h)]);
                -r.z / r.length()
            };
            let g = depression(x as f64, y as f64);
            let step =
                (depression(x as f64 + 1.0, y as f64) - g).abs() + (depression(x as f64, y as f64 + 1.0) - g).abs();
            let margin = (g - camera.dip_sine()) / step.max(f64::MIN_POSITIVE);
            let lit = luminance(frame.hdr[(y * w + x) as usize]) > 0.0;
            if margin > 1.0 {
                assert!(lit, "pixel ({x}, {y}) is inside the disc but shows no sea");
                inside += 1;
            } else if margin < -1.0 {
                assert!(!lit, "pixel ({x}, {y}) is outside the limb but shows sea");
            }
        }
    }
    // The disc's angular radius is arcsin(R / (R + H)) = 8.7 degrees of the 10 each side.
    let (r, height_m) = (scene.planet.radius_m, scene.camera.height_m);
    let radius = (r / (r + height_m)).asin().tan() / 10f64.to_radians().tan() * w as f64 / 2.0;
    let expected = std::f64::consts::PI * radius * radius;
    assert!((inside as f64 / expected - 1.0).abs() < 0.1, "{inside} pixels well inside a disc of {expected:.0}");
}

#[test]
fn from_orbit_the_night_side_is_dark_past_the_terminator() {
    let gpu = gpu();
    let (w, h) = (64u32, 64u32);
    // The sun on the horizon below the eye: the terminator runs through the disc's centre, the
    // day side towards the sun (the top of the image), the night side away from it. The refracted
    // light alone, which is the sky's irradiance on the sea there.
    let frame =
        render_terms(&gpu, &straight_down(35_786e3, 20.0, 0.0), w, h, Terms { sun: false, sky: false, sea: true });
    let half_mean = |rows: std::ops::Range<u32>| {
        let (mut sum, mut n) = (0.0, 0);
        for y in rows {
            for x in 0..w {
                if frame.frame.camera.pixel_distance(x, y, w, h).is_some() {
                    sum += luminance(frame.hdr[(y * w + x) as usize]);
                    n += 1;
                }
            }
        }
        sum / n.max(1) as f64
    };
    // Past the terminator's twilight (the rows a quarter of the disc away from it).
    let (day, night) = (half_mean(0..h / 4 + 4), half_mean(3 * h / 4 - 4..h));
    assert!(day > 0.0 && night < 1e-3 * day, "the day side's sea {day:.3e}, the night side's {night:.3e}");
}
