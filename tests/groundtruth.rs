//! The ground truth and the error bench: convergence, the paper's energy claim on a test scene,
//! the bench's CSV, and bad input.

mod common;

use common::gpu;
use ocean::measure::bench::error_vs_time as errorbench;
use ocean::measure::groundtruth::{self, Sampling};
use ocean::model::scene::Scene;
use std::path::PathBuf;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ocean-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The sun below the horizon: no glints, so a few samples already say something.
fn twilight() -> Scene {
    let mut s = Scene::default();
    // The ground truth traces Preetham's sky.
    s.sky.model = ocean::model::scene::SkyKind::Preetham;
    s.camera.height_m = 10.0;
    s.camera.pitch_deg = -12.0;
    s.sun.elevation_deg = -4.0;
    s
}

fn rms_difference(a: &[[f32; 4]], b: &[[f32; 4]]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(p, q)| (0..3).map(|c| ((p[c] - q[c]) as f64).powi(2)).sum::<f64>()).sum();
    (sum / (3 * a.len()) as f64).sqrt()
}

#[test]
fn the_reference_converges_as_samples_grow() {
    let gpu = gpu();
    let scene = twilight();
    let (w, h) = (32, 24);
    let truth = |n| groundtruth::render(&gpu, &scene, w, h, &Sampling::new(n), |_, _| {}).unwrap();
    let best = truth(8);
    assert_eq!(best.report.nonfinite_pixels, 0);
    assert_eq!(best.report.validation_errors, 0);
    let coarse: Vec<_> = [1, 2, 4].iter().map(|&n| truth(n)).collect();
    let errors: Vec<f64> = coarse.iter().map(|t| rms_difference(&t.radiance, &best.radiance)).collect();
    assert!(errors[0] > errors[1] && errors[1] > errors[2], "error against 8x8 samples for 1, 2, 4: {errors:?}");
    // The noise floor each estimate reports of itself falls with the samples, and the 4x4 one
    // predicts its real distance from the 8x8 estimate: RMS(F4 - F8) = sqrt(s4^2 + s8^2), with
    // s8 = s4 / 2, is 1.12 s4 (luminance over the sea).
    let floors: Vec<f64> = [&coarse[1], &coarse[2], &best].iter().map(|t| t.report.noise_floor_rmse.unwrap()).collect();
    assert!(coarse[0].report.noise_floor_rmse.is_none(), "one sample has no subset to compare with");
    assert!(floors[0] > floors[1] && floors[1] > floors[2] && floors[2] > 0.0, "noise floors for 2, 4, 8: {floors:?}");
    let camera = ocean::render::frame::CameraFrame::new(&scene, &ocean::model::waves::generate(&scene), w, h);
    let sea: Vec<usize> =
        (0..w * h).filter(|i| camera.pixel_distance(i % w, i / w, w, h).is_some()).map(|i| i as usize).collect();
    let lum = ocean::output::luminance;
    let measured = (sea.iter().map(|&i| (lum(coarse[2].radiance[i]) - lum(best.radiance[i])).powi(2)).sum::<f64>()
        / sea.len() as f64)
        .sqrt();
    let predicted = 1.12 * floors[1];
    assert!(
        measured / predicted > 0.5 && measured / predicted < 2.0,
        "4x4 noise: predicted {predicted}, measured {measured}"
    );
    // Each pixel's variance of its mean (what the bench's energy uncertainties are made of) falls
    // as 1 / N^2 per axis: 2x2 to 4x4 samples about a quarter, and it predicts the 4x4 estimate's
    // real scatter about the 8x8 one (the mean of (F4 - F8)^2 is s4^2 + s8^2, 1.25 s4^2).
    let mean_variance =
        |t: &groundtruth::GroundTruth| sea.iter().map(|&i| t.variance[i][0] as f64).sum::<f64>() / sea.len() as f64;
    let (v2, v4) = (mean_variance(&coarse[1]), mean_variance(&coarse[2]));
    assert!(v2 > 0.0 && v4 < 0.5 * v2, "variance of the mean for 2x2 and 4x4 samples: {v2}, {v4}");
    let ratio = measured * measured / (1.25 * v4);
    assert!(ratio > 0.25 && ratio < 4.0, "the 4x4 variance predicts its scatter within a factor 4: {ratio}");
}

#[test]
fn the_full_method_keeps_energy_better_than_the_paper_and_the_paper_better_than_the_constant_brdf() {
    // 10 m above a 10 m/s sea, looking 12 degrees down, the sun behind: the sky's reflection and
    // the refracted light per distance band, against exact geometry (64x48, 4x4 samples; reflected
    // rays that meet the sea again traced up to 3 times). Measured (sky / sea, by band from the
    // eye, 10-500 m and beyond): full +11.9, +6.8, +10.1, +19.7, +31.8, +35.4% / -0.5, -1.7, -4.8,
    // -8.2, -11.9, -12.9%; the paper +15, +24, +39, +59, +82, +92% / -0.2, -2.5, -7.7, -13, -20,
    // -23%; the constant BRDF +15, +29, +63, +98, +132, +150%. These are against the ground truth
    // whose reflected rays march to the wave that stops them (docs/results.md, "The ground truth
    // at grazing rays"); the truth before it let them leave and read the sky, and full was within
    // 12% there. The drift towards the horizon is the methods' masking: Smith's shadowing
    // counts too few reflections stopped by the next wave at grazing (the truth's sky fell
    // 20-35% at 20-700 m on the default view when they were traced).
    // Asserted: full within FULL_SKY (sky) out to 100 m and FULL_SKY_FAR to 500 m, its refracted
    // light within FULL_SEA everywhere, both methods within 5% (sea) where the view is at least
    // 10 degrees down and the paper within PAPER_SKY_STEEP (sky) there; each never further off
    // than the next simpler method in any band (sky and sea).
    let gpu = gpu();
    let mut scene = twilight();
    scene.sun.elevation_deg = 25.0;
    scene.sun.azimuth_deg = 180.0; // behind: its glints are out of view
    let dir = temp_dir("energy");
    let reference = dir.join("ref.exr");
    groundtruth::render(&gpu, &scene, 64, 48, &Sampling::new(4), |_, _| {}).unwrap().save(&scene, &reference).unwrap();
    let rows = errorbench::run(&gpu, &scene, "test scene", &reference, None, 1, &dir).unwrap();
    let bands = |method: &str| &rows.iter().find(|r| r.method == method && r.setting == "default").unwrap().bands;
    const SKY: usize = 2;
    const SEA: usize = 3;
    let steep = scene.camera.height_m / 10f64.to_radians().tan(); // farthest point seen 10 degrees down
    let mut compared = 0;
    let (full, paper, constant) = (bands("full"), bands("paper"), bands("constant-brdf"));
    for b in (0..full.len()).filter(|&b| full[b].0 >= 50) {
        let (f, p, c) = (&full[b].2, &paper[b].2, &constant[b].2);
        eprintln!(
            "band {b}: sky full {:+.3} paper {:+.3} constant {:+.3}; sea full {:+.3} paper {:+.3}",
            f.energy_error[SKY], p.energy_error[SKY], c.energy_error[SKY], f.energy_error[SEA], p.energy_error[SEA]
        );
    }
    for b in 0..full.len() {
        let (n, _, f) = &full[b];
        if *n < 50 {
            continue; // too few pixels for an energy
        }
        compared += 1;
        let (p, c) = (&paper[b].2, &constant[b].2);
        let sky = |e: &errorbench::TermErrors| e.energy_error[SKY].abs();
        let sea = |e: &errorbench::TermErrors| e.energy_error[SEA].abs();
        assert!(
            sky(f) <= sky(p) + 0.02,
            "band {b}: full's sky energy ({:.3}) drifts more than the paper's ({:.3})",
            sky(f),
            sky(p)
        );
        assert!(
            sky(p) <= sky(c) + 0.02,
            "band {b}: the paper's sky energy ({:.3}) drifts more than the baseline's ({:.3})",
            sky(p),
            sky(c)
        );
        assert!(
            sea(f) <= sea(p) + 0.01,
            "band {b}: full's refracted energy ({:.3}) drifts more than the paper's ({:.3})",
            sea(f),
            sea(p)
        );
        let far_edge = errorbench::BANDS_M[b + 1];
        if far_edge <= 100.0 {
            assert!(sky(f) < FULL_SKY, "band {b}: full's sky energy off by {:.3}", sky(f));
        } else if far_edge <= 500.0 {
            assert!(sky(f) < FULL_SKY_FAR, "band {b}: full's sky energy off by {:.3}", sky(f));
        }
        assert!(sea(f) < FULL_SEA, "band {b}: full's refracted energy off by {:.3}", sea(f));
        if errorbench::BANDS_M[b + 1] <= steep {
            assert!(sea(f) < 0.05, "band {b}: full's refracted energy off by {:.3}", sea(f));
            assert!(sky(p) < PAPER_SKY_STEEP, "band {b}: the paper's sky energy off by {:.3}", sky(p));
            assert!(sea(p) < 0.05, "band {b}: the paper's refracted energy off by {:.3}", sea(p));
        }
    }
    assert!(compared >= 4, "the test view spans too few distance bands");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Full's energy bounds in the test view above: its measured worst plus about twice the band's
/// standard error (1-2 points): the sky out to 100 m (11.9%) and to 500 m (31.8%), the refracted
/// light in every band (12.9%, beyond 500 m); the paper's sky where the view is steep (24.2%).
const FULL_SKY: f64 = 0.15;
const FULL_SKY_FAR: f64 = 0.36;
const FULL_SEA: f64 = 0.16;
const PAPER_SKY_STEEP: f64 = 0.28;

#[test]
fn the_bench_writes_a_finite_row_per_method() {
    let gpu = gpu();
    let scene = twilight();
    let dir = temp_dir("bench");
    let reference = dir.join("ref.exr");
    groundtruth::render(&gpu, &scene, 32, 24, &Sampling::new(2), |_, _| {}).unwrap().save(&scene, &reference).unwrap();
    errorbench::run(&gpu, &scene, "test scene", &reference, None, 1, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("error_vs_time.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    for column in [
        "method",
        "setting",
        "gpu_ms",
        "rmse_total",
        "energy_error_total",
        "rmse_sun",
        "energy_error_sun",
        "rmse_sky",
        "energy_error_sky",
        "rmse_floor_total",
        "energy_uncertainty_total",
        "blocks",
        "block_rmse_total",
        "block_rmse_floor_total",
    ] {
        assert!(header.contains(&column), "missing column {column}");
    }
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for method in ["full", "paper", "constant-brdf", "no-filter"] {
        let row = rows.iter().find(|r| r[0] == method).unwrap_or_else(|| panic!("no row for {method}"));
        let columns =
            ["gpu_ms", "rmse_total", "energy_error_total", "rmse_sky", "energy_error_sky", "rmse_floor_total"];
        for column in columns.into_iter().chain(["block_rmse_total", "block_rmse_floor_total"]) {
            let i = header.iter().position(|c| *c == column).unwrap();
            let value: f64 = row[i].parse().unwrap_or_else(|_| panic!("{method} {column} = {:?}", row[i]));
            assert!(value.is_finite(), "{method} {column} = {value}");
        }
    }
    for file in ["error_by_distance.csv", "error_vs_time.md"] {
        assert!(dir.join(file).is_file(), "{file} missing");
    }
    let md = std::fs::read_to_string(dir.join("error_vs_time.md")).unwrap();
    assert!(md.contains("| ground truth's noise floor |"), "the table states the ground truth's noise: {md}");
    // The plots say what they show: a title, axes with units and values, a legend.
    let texts = |file: &str| -> Vec<String> {
        let svg = std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"), "{file} is SVG");
        svg.split("<text")
            .skip(1)
            .map(|t| t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()].trim().replace("&apos;", "'"))
            .collect()
    };
    let error = texts("error_vs_time.svg");
    for wanted in [
        "Error against GPU time: test scene, 32x24",
        "GPU time per frame (ms)",
        "RMSE of 8x8-block mean luminance over the sea (kcd/m²",
        "full",
        "paper",
        "constant-brdf",
        "no-filter",
        "Pareto front (ringed)",
        "ground truth's noise floor (",
        "ssaa=2",
    ] {
        assert!(error.iter().any(|t| t.starts_with(wanted)), "error_vs_time.svg lacks {wanted:?}: {error:?}");
    }
    let ticks = error.iter().filter(|t| t.parse::<f64>().is_ok()).count();
    assert!(ticks >= 6, "tick values on both axes: {error:?}");
    let energy = texts("energy_by_distance.svg");
    for wanted in [
        "Energy error by distance",
        "reflected sun",
        "reflected sky",
        "distance from the eye (m)",
        "energy error against the ground truth (%)",
        "±5% target",
        "10–20",
        "≥1000",
        "full",
    ] {
        assert!(energy.iter().any(|t| t.starts_with(wanted)), "energy_by_distance.svg lacks {wanted:?}: {energy:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `bench error-vs-time --bare-reference`: the local waves' own change, the mast's wake less its
/// bare sea, ours against the truth's (both traced at 48x36, 2x2 samples). Measured over the
/// wake's 328 pixels: a correlation of 0.56 with the truth's blurred change as it is, and ours
/// 0.65 times its rms, its noise included (at this size the half estimates take nearly all of it
/// for noise, a pixel's strata seeing the wake's waves apart, so the figures without it are not
/// asserted). A bare truth that is not the scene's bare sea, or a scene with no local waves, is
/// refused before anything is drawn.
#[test]
fn the_local_waves_own_change_is_measured_against_a_bare_truth() {
    let gpu = gpu();
    let scene =
        Scene::load(std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/wake_mast.toml"))).unwrap();
    let bare = Scene { wakes: Vec::new(), ..scene.clone() };
    let dir = temp_dir("local-waves");
    let (reference, bare_reference) = (dir.join("wake.exr"), dir.join("bare.exr"));
    for (s, path) in [(&scene, &reference), (&bare, &bare_reference)] {
        groundtruth::render(&gpu, s, 48, 36, &Sampling::new(2), |_, _| {}).unwrap().save(s, path).unwrap();
    }
    // The scene's own truth is no bare sea; a scene without local waves has none to measure.
    let refused = |scene: &Scene, reference: &std::path::Path, bare_path: &std::path::Path| {
        let Err(e) = errorbench::run(&gpu, scene, "wake_mast", reference, Some(bare_path), 1, &dir) else {
            panic!("{} must be refused", bare_path.display());
        };
        e.to_string()
    };
    let e = refused(&scene, &reference, &reference);
    assert!(e.contains("--bare-reference") && e.contains("wake.exr") && e.contains("without its [[wake]]s"), "{e}");
    let e = refused(&bare, &bare_reference, &bare_reference);
    assert!(e.contains("no [[wake]] or [[splash]]"), "{e}");
    assert!(!dir.join("local_waves.csv").exists(), "nothing written for a refused bench");
    errorbench::run(&gpu, &scene, "wake_mast", &reference, Some(&bare_reference), 1, &dir).unwrap();
    let csv = std::fs::read_to_string(dir.join("local_waves.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let whole: Vec<&str> =
        csv.lines().find(|l| l.starts_with("whole sea,")).expect("the whole sea's row").split(',').collect();
    let at = |name: &str| -> f64 { whole[header.iter().position(|h| *h == name).unwrap()].parse().unwrap() };
    eprintln!("{csv}");
    assert!(at("wake_pixels") > 200.0, "{csv}");
    let scale = at("method_rms") / at("truth_rms");
    assert!(scale > 0.4 && scale < 1.2, "ours {scale} times the truth's change: {csv}");
    assert!(at("correlation") > 0.4, "{csv}");
    assert!(std::fs::read_to_string(dir.join("local_waves.md")).unwrap().contains("| whole sea |"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_references_and_sample_counts_are_refused() {
    let gpu = gpu();
    let scene = twilight();
    for n in [0, groundtruth::MAX_SAMPLES + 1] {
        let e = groundtruth::render(&gpu, &scene, 8, 8, &Sampling::new(n), |_, _| {}).err().expect("refused");
        assert!(e.to_string().contains("--samples"), "{e}");
    }
    for b in [0, groundtruth::MAX_BOUNCES + 1] {
        let e = groundtruth::render(&gpu, &scene, 8, 8, &Sampling { bounces: b, ..Sampling::new(1) }, |_, _| {})
            .err()
            .expect("refused");
        assert!(e.to_string().contains(&format!("--bounces {b} is out of range [1, 16]")), "{e}");
    }
    for k in [0.1, 10.5, f64::NAN] {
        let sampling = Sampling { sun_kernel_deg: k, ..Sampling::new(1) };
        let e = groundtruth::render(&gpu, &scene, 8, 8, &sampling, |_, _| {}).err().expect("refused");
        assert!(e.to_string().contains("--sun-kernel-deg") && e.to_string().contains("out of range"), "{e}");
    }
    let dir = temp_dir("mismatch");
    let reference = dir.join("ref.exr");
    groundtruth::render(&gpu, &scene, 16, 12, &Sampling::new(1), |_, _| {}).unwrap().save(&scene, &reference).unwrap();
    let Err(e) = errorbench::run(&gpu, &Scene::default(), "scenes/default.toml", &reference, None, 1, &dir) else {
        panic!("a reference of another scene must be refused");
    };
    let message = e.to_string();
    assert!(message.contains("ref.exr") && message.contains("scenes/default.toml"), "{message}");
    assert!(!dir.join("error_vs_time.csv").exists(), "nothing written for a refused bench");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn reflected_rays_that_meet_the_sea_again_are_traced_and_what_is_cut_off_shrinks_with_bounces() {
    let gpu = gpu();
    // Grazing over a rough sea: reflected rays often run into the next wave.
    let mut scene = Scene::default();
    scene.sky.model = ocean::model::scene::SkyKind::Preetham;
    scene.camera.height_m = 3.0;
    scene.camera.pitch_deg = -4.0;
    scene.wind.speed_mps = 15.0;
    scene.sun.elevation_deg = 20.0;
    let cut = |bounces| {
        let truth =
            groundtruth::render(&gpu, &scene, 32, 24, &Sampling { bounces, ..Sampling::new(1) }, |_, _| {}).unwrap();
        assert_eq!(truth.report.validation_errors, 0);
        assert_eq!(truth.report.nonfinite_pixels, 0);
        truth.report.cut_off_fraction
    };
    let (one, three, eight) = (cut(1), cut(3), cut(8));
    assert!(one > 0.0, "some reflected rays meet another wave ({one})");
    assert!(three < one && eight < three, "cut off: {one} after 1 bounce, {three} after 3, {eight} after 8");
}

#[test]
fn the_sun_kernel_keeps_the_reflected_suns_energy_and_cuts_its_noise() {
    // The sun 20 degrees up ahead, its glitter in view: the disc itself (the kernel at the sun's
    // radius) against the default 2-degree cone, each with its standard error over the sea.
    let gpu = gpu();
    let mut scene = twilight();
    scene.sun.elevation_deg = 20.0;
    scene.sun.azimuth_deg = scene.camera.yaw_deg;
    let energy = |kernel: f64| {
        let sampling = Sampling { sun_kernel_deg: kernel, ..Sampling::new(6) };
        let truth = groundtruth::render(&gpu, &scene, 40, 30, &sampling, |_, _| {}).unwrap();
        assert_eq!(truth.report.validation_errors, 0);
        assert_eq!(truth.report.sun_kernel_deg, kernel);
        let sum: f64 = truth.sun.iter().map(|p| ocean::output::luminance(*p)).sum();
        let variance: f64 = truth.variance.iter().map(|v| v[1] as f64).sum();
        (sum, variance.sqrt())
    };
    let disc = energy(ocean::model::sky::SUN_ANGULAR_RADIUS.to_degrees());
    let cone = energy(groundtruth::DEFAULT_SUN_KERNEL_DEG);
    eprintln!("reflected sun: disc {:.1} ± {:.1}, 2-degree cone {:.1} ± {:.1}", disc.0, disc.1, cone.0, cone.1);
    assert!(disc.0 > 0.0, "the view catches some glints");
    assert!(cone.1 < disc.1 / 3.0, "the cone's standard error {} against the disc's {}", cone.1, disc.1);
    let apart = (cone.0 - disc.0).abs();
    assert!(apart < 3.0 * (disc.1 * disc.1 + cone.1 * cone.1).sqrt() + 0.01 * disc.0, "energies {disc:?} and {cone:?}");
}

/// The default (physical) sky, 10 m up, 12 degrees down, the sun 25 degrees up behind the eye.
fn physical_view() -> Scene {
    let mut s = Scene::default();
    assert_eq!(s.sky.model, ocean::model::scene::SkyKind::Physical, "the default sky is the physical one");
    s.camera.height_m = 10.0;
    s.camera.pitch_deg = -12.0;
    s.sun.elevation_deg = 25.0;
    s.sun.azimuth_deg = 180.0;
    s
}

#[test]
fn the_physical_sky_is_traced_and_its_own_error_sits_below_the_truths_noise() {
    let gpu = gpu();
    let scene = physical_view();
    let (w, h) = (40, 30);
    let truth = groundtruth::render(&gpu, &scene, w, h, &Sampling::new(4), |_, _| {}).unwrap();
    assert_eq!(truth.report.validation_errors, 0);
    assert_eq!(truth.report.nonfinite_pixels, 0);
    let e = truth.report.sky_error.expect("the physical sky reports its error");
    // Measured: 8e-6 (f32 against f64), 3e-4 (128 samples a ray against 4096), 3e-5 (the table
    // along a 25-degree sun), 4e-8 (a low eye's nodes hold one value).
    assert!(e.gpu_against_f64 < 1e-4, "{e:?}");
    assert!(e.quadrature < 2e-3, "{e:?}");
    assert!(e.sun_transmittance_table < 1e-2, "{e:?}");
    assert!(e.sea_light_interpolation < 1e-3, "{e:?}");
    // Below the ground truth's own noise over the sea, as a share of the sea's mean luminance.
    let camera = ocean::render::frame::CameraFrame::new(&scene, &ocean::model::waves::generate(&scene), w, h);
    let sea: Vec<usize> =
        (0..w * h).filter(|&i| camera.pixel_distance(i % w, i / w, w, h).is_some()).map(|i| i as usize).collect();
    let mean = sea.iter().map(|&i| ocean::output::luminance(truth.radiance[i])).sum::<f64>() / sea.len() as f64;
    let noise = truth.report.noise_floor_rmse.unwrap() / mean;
    assert!(e.largest() < noise, "the sky's own error {:.2e} against the truth's noise {noise:.2e}", e.largest());
    // The top row sees the sky from the eye: the f64 model's, converged, at the pixel's centre
    // (the sky varies by well under a percent across a pixel there).
    let atmosphere = ocean::model::atmosphere::shared(&scene.atmosphere());
    let sun = {
        let (el, az) = (scene.sun.elevation_deg.to_radians(), scene.sun.azimuth_deg.to_radians());
        [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()]
    };
    for x in [3, w / 2, w - 4] {
        let ndc = [(x as f64 + 0.5) / w as f64 * 2.0 - 1.0, 1.0 / h as f64 - 1.0];
        let dir = camera.ray(ndc).normalize().to_array();
        let exact = atmosphere.sky_radiance(camera.eye_height, dir, sun, 4096);
        let traced = truth.radiance[x as usize];
        for c in 0..3 {
            assert!(
                (traced[c] as f64 - exact[c]).abs() <= 0.01 * exact[c],
                "column {x}: traced {traced:?} against the model's {exact:?}"
            );
        }
    }
    // Every half estimate's luminance lies near the full one's (each is a mean of half the samples).
    let half = truth.half.as_ref().expect("4 x 4 samples have halves");
    let total_lum: f64 = sea.iter().map(|&i| ocean::output::luminance(truth.radiance[i])).sum();
    let half_lum: f64 = sea.iter().map(|&i| half[i][0] as f64).sum();
    assert!((half_lum / total_lum - 1.0).abs() < 0.05, "half {half_lum} against full {total_lum}");
}

#[test]
fn the_full_method_keeps_the_physical_skys_energy() {
    // Against the physical ground truth of the view above (40x30, 4x4): measured over the whole
    // sea, full's sky +6.2% and refracted light -2.5%, the paper's sky +67% (against the truth
    // before its grazing rays marched to their end: -6.9%, -1.6% and +40%; before the rays the
    // next wave stops were mirrored about the facet they strike, full's sky was +11.0%;
    // docs/results.md).
    let gpu = gpu();
    let scene = physical_view();
    let dir = temp_dir("physical-energy");
    let reference = dir.join("ref.exr");
    groundtruth::render(&gpu, &scene, 40, 30, &Sampling::new(4), |_, _| {}).unwrap().save(&scene, &reference).unwrap();
    let rows = errorbench::run(&gpu, &scene, "physical test scene", &reference, None, 1, &dir).unwrap();
    let all = |method: &str| rows.iter().find(|r| r.method == method && r.setting == "default").unwrap().all;
    let (full, paper) = (all("full"), all("paper"));
    eprintln!(
        "full sky {:+.3} sea {:+.3}; paper sky {:+.3}",
        full.energy_error[2], full.energy_error[3], paper.energy_error[2]
    );
    assert!(full.energy_error[2].abs() < PHYSICAL_FULL, "full's sky off by {:+.3}", full.energy_error[2]);
    assert!(full.energy_error[3].abs() < PHYSICAL_FULL, "full's refracted light off by {:+.3}", full.energy_error[3]);
    assert!(full.energy_error[2].abs() < paper.energy_error[2].abs(), "full's sky no closer than the paper's");
    // The detail a pixel can see: full's local contrast over the truth's (its noise removed), sky
    // and refracted light, over the whole sea. The former normal weights (a smoothstep from 1/8
    // to 1/4 turn and a grazing criterion) kept 0.22 and 0.23 of it here.
    let detail = &rows.iter().find(|r| r.method == "full" && r.setting == "default").unwrap().detail;
    for (t, name) in [(2, "sky"), (3, "refracted light")] {
        let ratio = detail.contrast[t].ratio;
        eprintln!("full's {name} contrast over the truth's: {ratio:.3}");
        assert!(
            (CONTRAST_LOW..CONTRAST_HIGH).contains(&ratio),
            "full's {name} keeps {ratio:.3} of the truth's contrast"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Full's whole-sea contrast over the physical truth's, noise removed: measured 0.78 and 0.89
/// (sky, refracted light) on the view above; the bounds hold a change that smooths the sea (the
/// former weights kept a quarter) or makes it shimmer.
const CONTRAST_LOW: f64 = 0.7;
const CONTRAST_HIGH: f64 = 1.4;

/// Full's whole-sea energy bound against the physical ground truth: the measured worst (6.2%)
/// plus about three of its standard errors (1 point); the former mirroring of the stopped rays
/// along themselves (+11.0%) fails it.
const PHYSICAL_FULL: f64 = 0.09;

#[test]
fn night_and_orbit_are_traced_and_too_many_trains_are_refused_by_name() {
    let gpu = gpu();
    // 30 degrees below every horizon in view: the planet hides the sun from all the air.
    let mut night = physical_view();
    night.sun.elevation_deg = -30.0;
    let truth = groundtruth::render(&gpu, &night, 16, 12, &Sampling::new(1), |_, _| {}).unwrap();
    assert_eq!((truth.report.validation_errors, truth.report.nonfinite_pixels), (0, 0));
    assert!(truth.report.mean_radiance.iter().all(|&l| l == 0.0), "night: {:?}", truth.report.mean_radiance);
    // From orbit: the limb, space and the sea under their own suns.
    let orbit = Scene::load(std::path::Path::new("scenes/orbit.toml")).unwrap();
    let truth = groundtruth::render(&gpu, &orbit, 24, 18, &Sampling::new(1), |_, _| {}).unwrap();
    assert_eq!((truth.report.validation_errors, truth.report.nonfinite_pixels), (0, 0));
    assert!(truth.report.mean_radiance.iter().all(|&l| l > 0.0));
    let e = truth.report.sky_error.unwrap();
    assert!(e.gpu_against_f64 < 1e-4 && e.sea_light_interpolation < 0.03, "{e:?}");
    // The most trains and bounces a scene may ask for still fit a sample's loops (the budget's
    // refusal is unit-tested in src/measure/groundtruth.rs).
    let mut many = physical_view();
    many.waves.count = ocean::model::scene::MAX_WAVES;
    let sampling = Sampling { bounces: groundtruth::MAX_BOUNCES, ..Sampling::new(1) };
    let truth = groundtruth::render(&gpu, &many, 8, 8, &sampling, |_, _| {}).unwrap();
    assert_eq!((truth.report.validation_errors, truth.report.nonfinite_pixels), (0, 0));
}

#[test]
fn grazing_rays_march_to_their_first_crossing_within_the_loop_budget() {
    // The default view's far rows: camera rays skim crests for hundreds of metres and reflected
    // rays leave a 3-degree sun's facets nearly level; a march cut short would take a hidden
    // crossing for the hit, or a blocked reflection for the sky and sun.
    let gpu = gpu();
    let scene = Scene::default();
    let region = ocean::measure::region::Region { x: 16, y: 60, width: 128, height: 8 };
    let sampling = Sampling { region: Some(region), ..Sampling::new(2) };
    let truth = groundtruth::render(&gpu, &scene, 160, 120, &sampling, |_, _| {}).unwrap();
    let r = &truth.report;
    assert_eq!((r.validation_errors, r.nonfinite_pixels), (0, 0));
    eprintln!(
        "out of steps: camera {:.4}, reflected {:.5}",
        r.unfinished_camera_fraction, r.unfinished_reflected_fraction
    );
    assert!(r.unfinished_camera_fraction < 0.01, "camera rays out of steps: {}", r.unfinished_camera_fraction);
    assert!(
        r.unfinished_reflected_fraction < 0.002,
        "reflected light out of steps: {}",
        r.unfinished_reflected_fraction
    );
}

#[test]
fn a_wakes_slopes_do_not_hold_back_the_march_over_the_far_sea() {
    // The deck's horizon row: camera rays skim the sea for kilometres past a wake whose crests
    // and slopes (2.2 m, 2.0) are far above the trains' (0.3 m, 1.4). Marched at the wake's
    // bounds the whole way, 22% of them ran out of steps there and the row read 2.5% darker than
    // the same sea without the wake; beyond the wake's reach they step by the trains' alone.
    let gpu = gpu();
    let wake = Scene::load(std::path::Path::new("scenes/wake_deck.toml")).unwrap();
    let bare = Scene { wakes: Vec::new(), ..wake.clone() };
    let region = ocean::measure::region::Region { x: 0, y: 33, width: 120, height: 2 };
    let sampling = Sampling { region: Some(region), ..Sampling::new(2) };
    let [with, without] = [&wake, &bare].map(|s| groundtruth::render(&gpu, s, 120, 90, &sampling, |_, _| {}).unwrap());
    for r in [&with.report, &without.report] {
        assert_eq!((r.validation_errors, r.nonfinite_pixels), (0, 0));
    }
    let luminance = |t: &groundtruth::GroundTruth| ocean::output::luminance_rgb(t.report.mean_radiance);
    let change = luminance(&with) / luminance(&without) - 1.0;
    eprintln!(
        "camera rays out of steps {:.4}; the row against the bare sea's {change:+.4}",
        with.report.unfinished_camera_fraction
    );
    assert!(with.report.unfinished_camera_fraction < 0.05, "{}", with.report.unfinished_camera_fraction);
    assert!(change.abs() < 0.015, "the far row moved by {change:+.4} with the wake");
}

#[test]
fn a_region_of_the_view_is_traced_as_in_the_whole_and_benched_on_its_pixels() {
    let gpu = gpu();
    let scene = physical_view();
    let (w, h) = (32, 24);
    let whole = groundtruth::render(&gpu, &scene, w, h, &Sampling::new(2), |_, _| {}).unwrap();
    let region = ocean::measure::region::Region { x: 9, y: 13, width: 12, height: 7 };
    let part =
        groundtruth::render(&gpu, &scene, w, h, &Sampling { region: Some(region), ..Sampling::new(2) }, |_, _| {})
            .unwrap();
    assert_eq!((part.width, part.height), (12, 7));
    assert_eq!((part.report.validation_errors, part.report.nonfinite_pixels), (0, 0));
    // The same samples (each pixel's strata hash its place in the view): the same values.
    assert_eq!(part.radiance, region.crop(&whole.radiance, w));
    assert_eq!(part.sky, region.crop(&whole.sky, w));
    // The bench compares the methods' pixels there, the view rendered whole.
    let dir = temp_dir("region");
    let reference = dir.join("ref.exr");
    part.save(&scene, &reference).unwrap();
    let rows = errorbench::run(&gpu, &scene, "region", &reference, None, 1, &dir).unwrap();
    let full = rows.iter().find(|r| r.method == "full" && r.setting == "default").unwrap();
    let pixels: usize = full.bands.iter().map(|b| b.0).sum();
    assert!(pixels > 0 && pixels <= region.pixels(), "{pixels} sea pixels in a region of {}", region.pixels());
    assert!(full.all.energy_error[2].abs() < 0.3, "full's sky in the region: {:+.3}", full.all.energy_error[2]);
    // Out of the view: refused by name.
    let outside = Sampling { region: Some(ocean::measure::region::Region { x: 30, ..region }), ..Sampling::new(1) };
    let e = groundtruth::render(&gpu, &scene, w, h, &outside, |_, _| {}).err().expect("refused").to_string();
    assert!(e.contains("--region 30,13,12,7") && e.contains("32x24"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
