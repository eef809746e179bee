//! The reflected sun's glints (glsl/glints.glsl): the full method's sun path broken into lit and
//! dark facets at the same mean, fixed within a frame and drawn anew as the waves move, and
//! absent from every other method.

mod common;

use common::{gpu, luminance, ocean_cli, render_shader};
use ocean::model::scene::Scene;
use ocean::render::passes::ocean::{Method, ShaderConfig, Terms};
use ocean::vk::gpu::Gpu;

const W: u32 = 640;
const H: u32 = 480;

/// The sun term alone (sun luminance per pixel), with or without glints.
fn sun_term(gpu: &Gpu, scene: &Scene, method: Method, glints: bool) -> Vec<f64> {
    let shader =
        ShaderConfig { glints, ..ShaderConfig::terms_only(Terms { sun: true, sky: false, sea: false }, method) };
    let frame = render_shader(gpu, scene, W, H, shader);
    assert!(frame.hdr.iter().all(|p| p.iter().all(|c| c.is_finite())), "non-finite pixels");
    frame.hdr.iter().map(|&p| luminance(p)).collect()
}

/// The sun's path: pixels whose expected sun is at least 1% of its brightest.
fn path(expected: &[f64]) -> Vec<usize> {
    let top = expected.iter().cloned().fold(0.0, f64::max);
    (0..expected.len()).filter(|&i| expected[i] >= 0.01 * top).collect()
}

/// The mean square of a pixel's difference from its 3x3 neighbourhood's mean, over `select`.
fn pixel_scale_variance(lum: &[f64], select: &[usize]) -> f64 {
    let at = |x: i64, y: i64| lum[(y.clamp(0, H as i64 - 1) * W as i64 + x.clamp(0, W as i64 - 1)) as usize];
    let sum: f64 = select
        .iter()
        .map(|&i| {
            let (x, y) = ((i as u32 % W) as i64, (i as u32 / W) as i64);
            let mean = (-1..=1)
                .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
                .map(|(dx, dy)| at(x + dx, y + dy))
                .sum::<f64>()
                / 9.0;
            (lum[i] - mean).powi(2)
        })
        .sum();
    sum / select.len() as f64
}

#[test]
fn glints_keep_the_suns_mean_and_break_its_path_into_facets() {
    let gpu = gpu();
    let scene = Scene::default();
    let expected = sun_term(&gpu, &scene, Method::Full, false);
    let glints = sun_term(&gpu, &scene, Method::Full, true);
    let select = path(&expected);
    assert!(select.len() > 1000, "the default view's sun path: {} pixels", select.len());
    let (sum_e, sum_g) =
        (select.iter().map(|&i| expected[i]).sum::<f64>(), select.iter().map(|&i| glints[i]).sum::<f64>());
    // The count's mean is the expected value: over the path's thousands of facets, within 3%.
    assert!((sum_g / sum_e - 1.0).abs() < 0.03, "the path's sun: {sum_g:.1} with glints against {sum_e:.1}");
    // Lit facets far above the expected value, and dark pixels where it is bright (measured at
    // 0.1% and 5.8% of the path at 640x480: most footprints here hold tens of facets).
    let lit = select.iter().filter(|&&i| glints[i] > 4.0 * expected[i]).count();
    let dark = select.iter().filter(|&&i| glints[i] < 0.25 * expected[i]).count() as f64 / select.len() as f64;
    let (v_e, v_g) = (pixel_scale_variance(&expected, &select), pixel_scale_variance(&glints, &select));
    eprintln!("sun path {} pixels: {lit} lit, dark {dark:.3}, pixel-scale variance x{:.3}", select.len(), v_g / v_e);
    assert!(lit >= 1 && dark > 0.03, "{lit} lit pixels, dark share {dark:.3}");
    assert!(v_g > 1.03 * v_e, "pixel-scale variance {v_g:.1} with glints against {v_e:.1}");
}

#[test]
fn glints_hold_within_a_frame_and_are_drawn_anew_as_the_waves_move() {
    let gpu = gpu();
    let scene = Scene::default();
    let a = sun_term(&gpu, &scene, Method::Full, true);
    assert_eq!(a, sun_term(&gpu, &scene, Method::Full, true), "the same frame draws the same glints");
    let mut later = scene.clone();
    later.render.time_s += 1.0 / 30.0;
    let b = sun_term(&gpu, &later, Method::Full, true);
    // Where the expected value itself holds (its change under a tenth), a pixel that changes by
    // half is a glint drawn anew; without glints none can.
    let (a0, b0) = (sun_term(&gpu, &scene, Method::Full, false), sun_term(&gpu, &later, Method::Full, false));
    let steady: Vec<usize> =
        path(&a0).into_iter().filter(|&i| (a0[i] - b0[i]).abs() < 0.1 * a0[i].max(b0[i])).collect();
    let redrawn = steady.iter().filter(|&&i| (a[i] - b[i]).abs() > 0.5 * a[i].max(b[i])).count();
    let share = redrawn as f64 / steady.len() as f64;
    eprintln!("of {} path pixels whose expected sun holds within a tenth, {redrawn} change by half", steady.len());
    assert!(steady.len() > 300, "the path's steady pixels: {}", steady.len());
    assert!(share > 0.05, "{redrawn} of {} steady path pixels redrawn", steady.len());
}

#[test]
fn only_the_full_method_draws_glints() {
    let gpu = gpu();
    let scene = Scene::default();
    for method in [Method::Paper, Method::ConstantBrdf, Method::NoFilter] {
        assert_eq!(sun_term(&gpu, &scene, method, true), sun_term(&gpu, &scene, method, false), "{method:?}");
    }
    let full = ShaderConfig::default();
    assert!(full.draws_glints(), "the full method's default");
    let no_sun = ShaderConfig::terms_only(Terms { sun: false, sky: true, sea: true }, Method::Full);
    assert!(!no_sun.draws_glints(), "no sun term, no glints");
}

#[test]
fn glints_asked_of_another_method_are_refused_by_name() {
    let out = ocean_cli(&["render", "--method", "paper", "--glints", "on", "--out", "/dev/null"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert_eq!(stderr.trim_end(), "error: invalid argument: --glints on: only --method full draws glints (not paper)");
    let out = ocean_cli(&["render", "--glints", "sometimes", "--out", "/dev/null"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("sometimes"), "clap names the bad value");
}
