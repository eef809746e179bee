//! The physical sky against numbers: the f64 model's tables against direct integration, the
//! GPU's sky (tables, map) against the f64 model, published figures, and bad input.

mod common;

use common::{assert_clean, gpu, luminance, render_with};
use ocean::embed::Shading;
use ocean::model::atmosphere::{self, transmittance_to_top, Atmosphere, AtmosphereParams, SKY_STEPS};
use ocean::model::scene::{Scene, SkyKind};

fn sun(elevation_deg: f64) -> [f64; 3] {
    let e = elevation_deg.to_radians();
    [e.cos(), 0.0, e.sin()]
}

use ocean::output::luminance_rgb as lum;

#[test]
fn the_tables_match_direct_integration_and_the_raymarch_converges() {
    let p = AtmosphereParams::default();
    let a = atmosphere::shared(&p);
    for (h, mu) in [(6.0, 1.0), (6.0, 0.3), (6.0, 0.02), (1000.0, 0.1), (20e3, -0.05), (50e3, 0.5)] {
        let r = p.bottom_radius_m + h;
        let (table, exact) = (a.transmittance(r, mu), transmittance_to_top(&p, r, mu, 4000));
        for c in 0..3 {
            // Bilinear interpolation of a 256x64 table: within 1% (the worst is the blue channel
            // a degree above the horizon, where the transmittance falls by 10^3 over the table's rows).
            assert!(
                (table[c] - exact[c]).abs() <= 1e-2 * exact[c] + 1e-6,
                "h {h} mu {mu}: {table:?} against {exact:?}"
            );
        }
    }
    // The sky's 40 quadratically spaced samples against 4000, where the sun is up.
    for (elevation, dir) in
        [(30.0, [0.0, 0.0, 1.0]), (3.0, [0.0, 0.6, 0.8]), (3.0, [-0.995, 0.0, 0.0998]), (60.0, [0.7, 0.7, 0.141])]
    {
        let coarse = a.sky_radiance(6.0, dir, sun(elevation), SKY_STEPS);
        let fine = a.sky_radiance(6.0, dir, sun(elevation), 4000);
        for c in 0..3 {
            assert!(
                (coarse[c] - fine[c]).abs() <= 0.02 * fine[c],
                "sun {elevation}, dir {dir:?}: {coarse:?} against {fine:?}"
            );
        }
    }
}

#[test]
fn the_sun_and_sky_agree_with_published_figures() {
    let a = Atmosphere::new(&AtmosphereParams::default());
    // The sun at the zenith, seen from sea level: about 1.6e9 cd/m^2 (1.6e6 kcd/m^2).
    let noon = a.sun_radiance(0.0, 1.0);
    assert!((1.4e6..2.0e6).contains(&lum(noon)), "noon sun {:.3e} kcd/m^2", lum(noon));
    // At 3 degrees the sun is orange-red: red > green > blue, blue under a tenth of red.
    let low = a.sun_radiance(0.0, 3f64.to_radians().sin());
    assert!(low[0] > low[1] && low[1] > low[2] && low[2] < 0.1 * low[0], "low sun {low:?}");
    // The clear sky's zenith at a high sun: blue, a few kcd/m^2 (measured clear skies, e.g. the
    // CIE standard clear sky's zenith luminances); brighter towards the horizon.
    let zenith = a.sky_radiance(0.0, [0.0, 0.0, 1.0], sun(60.0), SKY_STEPS);
    assert!(zenith[2] > zenith[1] && zenith[1] > zenith[0], "zenith {zenith:?}");
    assert!((1.0..8.0).contains(&lum(zenith)), "zenith luminance {} kcd/m^2", lum(zenith));
    let horizon = a.sky_radiance(0.0, [-0.995, 0.0, 0.0998], sun(60.0), SKY_STEPS);
    assert!(lum(horizon) > lum(zenith), "the horizon ({horizon:?}) outshines the zenith ({zenith:?})");
    // Energy: the sky's irradiance at a high sun is a fraction of the sun's (5-25% on clear days).
    let e_sky = lum(a.sky_irradiance(0.0, sun(60.0)));
    let e_sun = lum(a.sun_radiance(0.0, 60f64.to_radians().sin()))
        * ocean::model::sky::SkyModel::sun_solid_angle()
        * 60f64.to_radians().sin();
    assert!((0.05..0.25).contains(&(e_sky / e_sun)), "sky {e_sky:.2} klux against sun {e_sun:.2} klux");
}

#[test]
fn the_gpu_sky_matches_the_f64_model() {
    let gpu = gpu();
    let mut scene = Scene::default();
    scene.sky.model = SkyKind::Physical;
    let (w, h) = (256, 192);
    let (report, frame) = render_with(&gpu, &scene, w, h, Shading::default());
    assert_clean(&report, "physical sky");
    let a = atmosphere::shared(&scene.atmosphere());
    let camera = &frame.frame.camera;
    let sun_dir = frame.frame.sky.sun_dir;
    let mut worst: f64 = 0.0;
    // The top rows (20 to 30 degrees up): the map's interpolation is well within the tolerance there.
    for y in (0..40).step_by(7) {
        for x in (0..w).step_by(17) {
            let ndc = [(x as f64 + 0.5) / w as f64 * 2.0 - 1.0, (y as f64 + 0.5) / h as f64 * 2.0 - 1.0];
            let dir = camera.ray(ndc).normalize().to_array();
            let cpu = a.sky_radiance(camera.eye_height, dir, sun_dir, SKY_STEPS);
            let p = frame.hdr[(y * w + x) as usize];
            for c in 0..3 {
                let rel = (p[c] as f64 - cpu[c]).abs() / cpu[c];
                worst = worst.max(rel);
            }
        }
    }
    // f32 tables in binary16, bilinear lookups, the map's texels and the HDR image's binary16.
    assert!(worst < 0.03, "GPU sky within {:.2}% of the f64 model", 100.0 * worst);
    // The sun disc is there (its radiance beyond binary16's range: the HDR image holds its limit).
    let bright = frame.hdr.iter().map(|p| luminance(*p)).fold(0.0, f64::max);
    assert!(bright > 60_000.0, "the sun disc at {bright}");
}

#[test]
fn out_of_range_atmospheres_are_refused_by_key() {
    let cases = [
        ("[sky.atmosphere]\nmie_g = 1.0", "sky.atmosphere.mie_g"),
        ("[planet]\nradius_m = 0.0", "planet.radius_m"),
        ("[planet]\nradius_m = -6360e3", "planet.radius_m"),
        ("[planet]\nradius_m = inf", "planet.radius_m"),
        ("[planet]\nradius_m = nan", "planet.radius_m"),
        ("[sky.atmosphere]\nbottom_radius_m = 6360e3", "unknown field"),
        ("[sky.atmosphere]\nrayleigh_scale_height_m = -8000.0", "sky.atmosphere.rayleigh_scale_height_m"),
        ("[sky.atmosphere]\nozone_absorption_per_m = [nan, 0.0, 0.0]", "sky.atmosphere.ozone_absorption_per_m[0]"),
        ("[sky.atmosphere]\nthickness_m = 0.0", "sky.atmosphere.thickness_m"),
        ("[planet]\nradius_m = 50e3", "sky.atmosphere.thickness_m"),
        ("[sky]\nmodel = \"hosek\"", "unknown variant"),
    ];
    for (text, key) in cases {
        let e = Scene::parse(text, "bad.toml").unwrap_err().to_string();
        assert!(e.contains(key) && !e.contains('\n'), "{text:?}: {e}");
    }
}

#[test]
fn every_extreme_scene_renders_clean_and_finite_under_the_physical_sky() {
    let gpu = gpu();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/extreme");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    for path in paths {
        let mut scene = Scene::load(&path).unwrap();
        scene.sky.model = SkyKind::Physical;
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        let (report, frame) = render_with(&gpu, &scene, 96, 64, Shading::default());
        assert_clean(&report, &name);
        assert!(frame.hdr.iter().all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)), "{name}");
        // Day scenes show a sky: some light in the image.
        if scene.sun.elevation_deg > 0.0 {
            assert!(
                report.mean_radiance.iter().any(|&m| m > 0.0),
                "{name}: black under a sun {} degrees up",
                scene.sun.elevation_deg
            );
        }
    }
}

/// One ground for the sea and the air: `[planet] radius_m` places the atmosphere's bottom, its
/// top `thickness_m` above, in what the shaders read.
#[test]
fn the_planets_radius_is_the_atmospheres_ground() {
    let scene =
        Scene::parse("[planet]\nradius_m = 3389.5e3\n[sky.atmosphere]\nthickness_m = 80e3", "mars.toml").unwrap();
    let a = scene.atmosphere();
    assert_eq!((a.bottom_radius_m, a.top_radius_m), (3389.5e3, 3469.5e3));
    let waves = ocean::model::waves::generate(&scene);
    let u = ocean::render::frame::build(&scene, &waves, 64, 48, 8.0).uniforms;
    assert_eq!((u.atmosphere[0][0], u.atmosphere[0][1]), (3389.5e3, 3469.5e3));
    let earth = Scene::default().atmosphere();
    assert_eq!((earth.bottom_radius_m, earth.top_radius_m), (6360e3, 6420e3));
}
