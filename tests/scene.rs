//! Scene files: defaults, presets, and one clear line for every kind of bad input.

mod common;

use ocean::model::scene::{wrap_degrees, LongestWave, Scene};
use std::path::Path;

fn parse_error(text: &str) -> String {
    match Scene::parse(text, "test.toml") {
        Ok(scene) => panic!("expected an error for {text:?}, parsed {scene:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn defaults_are_the_demo_values() {
    let scene = Scene::parse("", "empty.toml").unwrap();
    assert_eq!(scene, Scene::default());
    assert_eq!(scene.camera.height_m, 6.0);
    assert_eq!(scene.camera.pitch_deg, 0.0);
    assert_eq!(scene.sun.elevation_deg, 3.0);
    assert_eq!(scene.wind.speed_mps, 10.0);
    assert_eq!(scene.waves.count, 60);
    assert_eq!((scene.waves.lambda_min_m, scene.waves.lambda_max_m), (0.02, LongestWave::Metres(30.0)));
    assert_eq!(scene.render.grid_cell_px, 8.0);
}

#[test]
fn every_preset_parses() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
            names.push(path.file_stem().unwrap().to_string_lossy().into_owned());
        }
    }
    for wanted in ["default", "calm", "storm", "sunset", "noon", "high_altitude"] {
        assert!(names.iter().any(|n| n == wanted), "missing preset {wanted}");
    }
    let default = Scene::load(&dir.join("default.toml")).unwrap();
    assert_eq!(default, Scene::default(), "scenes/default.toml spells out the defaults");
}

#[test]
fn unknown_keys_are_named() {
    let e = parse_error("[camera]\nheight = 3.0\n");
    assert!(e.contains("test.toml line 2") && e.contains("height"), "{e}");
    let e = parse_error("[oceans]\nx = 1\n");
    assert!(e.contains("oceans"), "{e}");
}

#[test]
fn malformed_toml_names_the_line() {
    let e = parse_error("[camera]\nheight_m = = 3\n");
    assert!(e.contains("line 2"), "{e}");
    let e = parse_error("[camera]\nheight_m = \"high\"\n");
    assert!(e.contains("line 2"), "{e}");
}

#[test]
fn out_of_range_values_name_key_and_range() {
    let cases = [
        ("[camera]\nheight_m = -1.0", "camera.height_m"),
        ("[camera]\nheight_m = 0.0", "camera.height_m"),
        ("[camera]\nheight_m = 5e7", "camera.height_m"),
        ("[camera]\nheight_m = nan", "camera.height_m"),
        ("[planet]\nradius_m = 0.0", "planet.radius_m"),
        ("[planet]\nradius_m = -6360e3", "planet.radius_m"),
        ("[planet]\nradius_m = inf", "planet.radius_m"),
        ("[planet]\nradius_m = nan", "planet.radius_m"),
        ("[camera]\nfov_y_deg = 180.0", "camera.fov_y_deg"),
        ("[camera]\npitch_deg = 91.0", "camera.pitch_deg"),
        ("[waves]\ncount = 0", "waves.count"),
        ("[waves]\ncount = 257", "waves.count"),
        ("[waves]\nlambda_min_m = 40.0", "waves.lambda_min_m"),
        ("[wind]\nspeed_mps = nan", "wind.speed_mps"),
        ("[render]\nexposure = inf", "render.exposure"),
        ("[render]\nexposure = 0.0", "render.exposure"),
        ("[render]\nexposure = nan", "render.exposure"),
        ("[render]\nev100 = nan", "render.ev100"),
        ("[render]\nev100 = 40.0", "render.ev100"),
        ("[render]\ngrid_cell_px = 0.5", "render.grid_cell_px"),
        ("[render]\nshadow_map_size = 32", "render.shadow_map_size"),
        ("[render]\nshadow_map_size = 16384", "render.shadow_map_size"),
        ("[sky]\nturbidity = 1.0", "sky.turbidity"),
        ("[sun]\nelevation_deg = -90.5", "sun.elevation_deg"),
        ("[camera]\nfov_y_deg = 0.0", "camera.fov_y_deg"),
        ("[waves]\nlambda_max_m = 20000", "waves.lambda_max_m"),
        ("[wind]\nspeed_mps = 2.0\n[waves]\nlambda_min_m = 5.0\nlambda_max_m = \"peak\"", "waves.lambda_max_m"),
    ];
    for (text, key) in cases {
        let e = parse_error(text);
        assert!(e.contains(key), "{text:?}: {e}");
        assert!(e.contains("range") || e.contains("below"), "{text:?}: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
    // Not ranges: two keys that set the same thing, and words that are not allowed values.
    let others = [
        ("[render]\nev100 = 12.0\nexposure = 0.1", "render.exposure and render.ev100 both set"),
        ("[render]\nev100 = \"bright\"", "an exposure value (EV100) or \"auto\""),
        ("[render]\ntone_curve = \"reinhard\"", "unknown variant"),
        ("[render]\nshadow_map = \"sometimes\"", "unknown variant"),
        (
            "[sun]\nelevation_deg = -2.0\n[render]\nshadow_map = \"on\"",
            "render.shadow_map = \"on\" needs the sun above the horizon",
        ),
    ];
    for (text, what) in others {
        let e = parse_error(text);
        assert!(e.contains(what) && !e.contains('\n'), "{text:?}: {e}");
    }
}

#[test]
fn azimuths_wrap_and_only_non_finite_angles_are_refused() {
    let scene = Scene::parse(
        "[camera]\nyaw_deg = 720.0\n[sun]\nazimuth_deg = -540.0\n[wind]\ndirection_deg = 1e300\n",
        "t.toml",
    )
    .unwrap();
    assert_eq!(scene.camera.yaw_deg, 0.0);
    assert_eq!(scene.sun.azimuth_deg, 180.0, "-540 is the direction 180");
    assert!(scene.wind.direction_deg > -180.0 && scene.wind.direction_deg <= 180.0);
    // The same direction written two ways is the same scene.
    let a = Scene::parse("[camera]\nyaw_deg = -90\n", "a.toml").unwrap();
    let b = Scene::parse("[camera]\nyaw_deg = 270\n", "b.toml").unwrap();
    assert_eq!(a, b);
    for (value, expected) in
        [(180.0, 180.0), (-180.0, 180.0), (540.0, 180.0), (359.5, -0.5), (-0.25, -0.25), (1e-30, 1e-30)]
    {
        assert_eq!(wrap_degrees(value), expected, "wrap {value}");
    }
    for key in ["[camera]\nyaw_deg", "[sun]\nazimuth_deg", "[wind]\ndirection_deg"] {
        for bad in ["nan", "inf", "-inf"] {
            let e = parse_error(&format!("{key} = {bad}"));
            assert!(e.contains("not a finite angle"), "{key} = {bad}: {e}");
            assert!(!e.contains('\n'), "one line: {e}");
        }
    }
}

#[test]
fn the_longest_wave_can_come_from_the_wind() {
    let scene = Scene::parse("[wind]\nspeed_mps = 20.0\n[waves]\nlambda_max_m = \"peak\"\n", "t.toml").unwrap();
    assert_eq!(scene.waves.lambda_max_m, LongestWave::Peak);
    // Pierson-Moskowitz: omega_p = (4 beta / 5)^(1/4) g / U, lambda = 2 pi g / omega_p^2.
    let omega_p = (4.0f64 * 0.74 / 5.0).powf(0.25) * 9.81 / 20.0;
    let expected = std::f64::consts::TAU * 9.81 / (omega_p * omega_p);
    assert!((scene.lambda_max_m() - expected).abs() < 1e-9 * expected, "{}", scene.lambda_max_m());
    assert!((scene.lambda_max_m() - 333.0).abs() < 1.0, "about 333 m at 20 m/s: {}", scene.lambda_max_m());
    // The longest train is the peak's wavelength, to the binary16 precision its wave vector is
    // snapped to (2^-11 relative; waves::binary16_wave_vector).
    let waves = ocean::model::waves::generate(&scene);
    let longest = waves.trains.last().unwrap().wavelength;
    assert!((longest - expected).abs() < 2f64.powi(-11) * expected, "{longest}");
    let e = parse_error("[wind]\nspeed_mps = 0.0\n[waves]\nlambda_max_m = \"peak\"\n");
    assert!(e.contains("waves.lambda_max_m") && e.contains("wind"), "{e}");
    let e = parse_error("[waves]\nlambda_max_m = \"long\"\n");
    assert!(e.contains("line 2") && e.contains("peak"), "{e}");
    // Round trip through the report's JSON keeps the keyword.
    let json = serde_json::to_string(&scene).unwrap();
    assert!(json.contains("\"lambda_max_m\":\"peak\""), "{json}");
    assert_eq!(serde_json::from_str::<Scene>(&json).unwrap(), scene);
}

#[test]
fn every_preset_fits_its_wind() {
    // No preset wastes trains on waves the wind does not make: the longest train is at most
    // twice the spectrum's peak (beyond it lies under 1% of the height variance).
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for name in ["calm", "storm", "sunset", "noon", "high_altitude"] {
        let scene = Scene::load(&dir.join(format!("{name}.toml"))).unwrap();
        let peak = ocean::model::waves::peak_wavelength(scene.wind.speed_mps);
        let longest = scene.lambda_max_m();
        assert!(longest <= 2.0 * peak && longest >= 0.5 * peak, "{name}: longest {longest} m, peak {peak} m");
    }
}

fn run_cli(args: &[&str]) -> (bool, String) {
    let output = common::ocean_cli(args);
    (output.status.success(), String::from_utf8_lossy(&output.stderr).into_owned())
}

#[test]
fn the_cli_reports_bad_input_in_one_line() {
    let dir = std::env::temp_dir().join(format!("ocean-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[waves]\ncount = 0\n").unwrap();
    let out = dir.join("never.png");
    let cases: Vec<Vec<String>> = vec![
        vec!["--scene".into(), bad.display().to_string()],
        vec!["--scene".into(), dir.join("missing.toml").display().to_string()],
        vec!["--width".into(), "0".into()],
    ];
    for extra in cases {
        let mut args = vec!["render".to_string(), "--out".into(), out.display().to_string()];
        args.extend(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (ok, stderr) = run_cli(&args);
        assert!(!ok, "{args:?} must fail");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: one line, got {stderr:?}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(!out.exists(), "no output file after a failure");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
