//! The sun's shadow map of the displaced grid: validation-clean, it only ever takes sunlight away
//! (never adds it, never touches the sky or the refracted light), it takes a real share under a
//! low sun and none under a high one, and it is left out, with its reason, where nothing can cast
//! a shadow.

mod common;

use common::{assert_clean, gpu, luminance, render_terms, render_with};
use ocean::embed::Shading;
use ocean::model::scene::{Scene, ShadowMapMode};
use ocean::model::waves;
use ocean::render::passes::ocean::Terms;
use ocean::render::renderer::{Options, RenderedFrame};
use ocean::render::specialize;

const SIZE: (u32, u32) = (160, 120);

/// The grazing figure scene's light: the eye 4 m up looking 4 degrees down, 8 m/s, the sun ahead.
fn low_sun(elevation_deg: f64, shadow_map: ShadowMapMode) -> Scene {
    let mut scene = Scene::default();
    scene.camera.height_m = 4.0;
    scene.camera.pitch_deg = -4.0;
    scene.camera.fov_y_deg = 50.0;
    scene.sun.elevation_deg = elevation_deg;
    scene.wind.speed_mps = 8.0;
    scene.sky.model = ocean::model::scene::SkyKind::Preetham;
    scene.render.shadow_map = shadow_map;
    scene
}

fn sum_luminance(frame: &RenderedFrame, rows: std::ops::Range<u32>) -> f64 {
    rows.flat_map(|y| (0..frame.width).map(move |x| (x, y)))
        .map(|(x, y)| luminance(frame.hdr[(y * frame.width + x) as usize]))
        .sum()
}

#[test]
fn the_shadow_map_only_takes_sunlight_away() {
    let gpu = gpu();
    let (w, h) = SIZE;
    // The whole frame, validated, with its report.
    let (report, _) = render_with(&gpu, &low_sun(3.0, ShadowMapMode::On), w, h, Shading::default());
    assert_clean(&report, "low sun with shadows");
    let map = report.shadow_map.as_ref().expect("the report names the shadow map it drew");
    assert_eq!(map.size, 1024);
    assert!(map.texel_m.iter().all(|t| t.is_finite() && *t > 0.0), "{:?}", map.texel_m);

    let sun = Terms { sun: true, sky: false, sea: false };
    let lit = render_terms(&gpu, &low_sun(3.0, ShadowMapMode::Off), w, h, sun);
    let shadowed = render_terms(&gpu, &low_sun(3.0, ShadowMapMode::On), w, h, sun);
    // Per pixel: never brighter than unshadowed, to binary16's rounding (2^-10 relative).
    for (i, (s, l)) in shadowed.hdr.iter().zip(&lit.hdr).enumerate() {
        for c in 0..3 {
            assert!(s[c] <= l[c] * (1.0 + 2f32.powi(-10)), "pixel {i} channel {c}: {} over {}", s[c], l[c]);
        }
    }
    // The near half, where the grid resolves the waves, loses a real share of its glitter.
    let near = h / 2..h;
    let (before, after) = (sum_luminance(&lit, near.clone()), sum_luminance(&shadowed, near));
    assert!(before > 0.0 && after < 0.9 * before, "sun in the near half: {after} with shadows, {before} without");
    // The sky's reflection and the refracted light do not depend on the sun's shadows: all the
    // terms together change by what the sun alone changes.
    let all_lit = render_terms(&gpu, &low_sun(3.0, ShadowMapMode::Off), w, h, Terms::ALL);
    let all_shadowed = render_terms(&gpu, &low_sun(3.0, ShadowMapMode::On), w, h, Terms::ALL);
    for i in 0..all_lit.hdr.len() {
        for c in 0..3 {
            let total = all_lit.hdr[i][c] as f64 - all_shadowed.hdr[i][c] as f64;
            let sun = lit.hdr[i][c] as f64 - shadowed.hdr[i][c] as f64;
            let ulps = 2f64.powi(-9) * (all_lit.hdr[i][c] as f64 + lit.hdr[i][c] as f64);
            assert!((total - sun).abs() <= ulps + 1e-6, "pixel {i} channel {c}: the total lost {total}, the sun {sun}");
        }
    }
}

#[test]
fn a_high_sun_casts_no_shadow_on_these_waves() {
    // At 40 degrees up the sunlight is steeper than any slope the grid holds (the trains' steepest
    // k h is well below tan 50 degrees): not one pixel may change.
    let gpu = gpu();
    let (w, h) = SIZE;
    let sun = Terms { sun: true, sky: false, sea: false };
    let lit = render_terms(&gpu, &low_sun(40.0, ShadowMapMode::Off), w, h, sun);
    let shadowed = render_terms(&gpu, &low_sun(40.0, ShadowMapMode::On), w, h, sun);
    assert!(sum_luminance(&lit, 0..h) > 0.0);
    assert_eq!(lit.hdr, shadowed.hdr, "a high sun's shadow map must leave every pixel lit");
}

#[test]
fn the_shadow_map_is_left_out_where_nothing_casts_a_shadow() {
    let (w, h) = SIZE;
    let plan = |scene: &Scene| {
        let wave_set = waves::generate(scene);
        specialize::plan(scene, &wave_set, w, h, Options::default())
    };
    let has_pass = |options: &Options| specialize::pipelines(options).iter().any(|p| p == "sun shadow");
    let (options, _) = plan(&low_sun(3.0, ShadowMapMode::Auto));
    assert!(has_pass(&options), "auto with the sun up over displaced waves draws the map");
    // The sun down (the sun term goes); waves too short for the grid.
    let mut too_short = low_sun(3.0, ShadowMapMode::On);
    too_short.waves.lambda_max_m = ocean::model::scene::LongestWave::Metres(0.05);
    too_short.waves.lambda_min_m = 0.01;
    // Off is the scene's choice: no pass, and nothing reported as dropped.
    let (options, omitted) = plan(&low_sun(3.0, ShadowMapMode::Off));
    assert!(!has_pass(&options) && !omitted.iter().any(|o| o.what.starts_with("sun shadow")), "{omitted:?}");
    let cases = [
        (low_sun(-5.0, ShadowMapMode::Auto), "no sun term"),
        (too_short, "no train is displaced by the grid, so none casts a shadow (render.shadow_map = \"on\")"),
    ];
    for (scene, why) in cases {
        let (options, omitted) = plan(&scene);
        assert!(!has_pass(&options), "{why}: {:?}", specialize::pipelines(&options));
        let omission = omitted.iter().find(|o| o.what.starts_with("sun shadow map"));
        assert!(omission.is_some_and(|o| o.why.contains(why)), "{why}: {omitted:?}");
    }
}
