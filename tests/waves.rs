//! Wave generation: slope variance against its formula, determinism, the k h <= 1 clamp, the
//! Cox-Munk order of magnitude, and the phase reduction for large times.

use ocean::model::scene::{LongestWave, Scene};
use ocean::model::waves::{cox_munk_total_variance, generate, G};
use std::f64::consts::TAU;

fn scene_with_wind(speed: f64) -> Scene {
    let mut scene = Scene::default();
    scene.wind.speed_mps = speed;
    scene
}

#[test]
fn slope_variance_matches_the_trochoid_formula() {
    for speed in [2.0, 10.0, 25.0] {
        let set = generate(&scene_with_wind(speed));
        // Direct, cancellation-prone form in f64: sum cos^2(phi) (1 - sqrt(1 - (k h)^2)).
        let (mut sx, mut sy) = (0.0, 0.0);
        for t in &set.trains {
            let v = 1.0 - (1.0 - (t.k * t.amplitude).powi(2)).sqrt();
            sx += t.angle_from_wind.cos().powi(2) * v;
            sy += t.angle_from_wind.sin().powi(2) * v;
        }
        assert!((set.sigma2[0] - sx).abs() <= 1e-9 * sx, "along wind: {} vs {sx}", set.sigma2[0]);
        assert!((set.sigma2[1] - sy).abs() <= 1e-9 * sy.max(1e-12), "across wind: {} vs {sy}", set.sigma2[1]);
        assert!(set.sigma2[0] > set.sigma2[1], "waves are spread around the wind, so most slope lies along it");
    }
}

#[test]
fn generation_is_deterministic_and_seeded() {
    let a = generate(&Scene::default());
    let b = generate(&Scene::default());
    assert_eq!(a, b);
    let mut other = Scene::default();
    other.waves.seed = 2;
    let c = generate(&other);
    assert_ne!(a.trains, c.trains, "another seed draws other directions and phases");
    assert_eq!(a.trains.len(), 60);
}

#[test]
fn trains_never_loop_and_are_sorted() {
    for speed in [0.0, 1.0, 10.0, 40.0, 60.0] {
        let set = generate(&scene_with_wind(speed));
        for t in &set.trains {
            assert!(t.k * t.amplitude <= 1.0 + 1e-12, "k h = {} at {speed} m/s", t.k * t.amplitude);
            assert!(t.amplitude.is_finite() && t.amplitude >= 0.0);
            assert!((t.omega * t.omega - G * t.k).abs() < 1e-9 * G * t.k, "deep-water dispersion w^2 = g k");
        }
        assert!(set.trains.windows(2).all(|p| p[0].wavelength < p[1].wavelength));
    }
    let glassy = generate(&scene_with_wind(0.0));
    assert!(glassy.trains.iter().all(|t| t.amplitude == 0.0), "no wind, no waves");
    assert_eq!(glassy.sigma2, [0.0, 0.0]);
}

#[test]
fn slope_variance_is_of_the_cox_munk_order() {
    for speed in [5.0, 10.0, 15.0] {
        let set = generate(&scene_with_wind(speed));
        let total = set.sigma2[0] + set.sigma2[1];
        let measured = cox_munk_total_variance(speed);
        let ratio = total / measured;
        assert!((0.3..3.0).contains(&ratio), "{speed} m/s: sigma^2 {total:.4} vs Cox-Munk {measured:.4}");
    }
    let calm = generate(&scene_with_wind(3.0));
    let storm = generate(&scene_with_wind(20.0));
    assert!(storm.sigma2[0] + storm.sigma2[1] > calm.sigma2[0] + calm.sigma2[1]);
}

#[test]
fn mean_height_offset_is_the_trochoid_mean() {
    let set = generate(&Scene::default());
    let expected: f64 = set.trains.iter().map(|t| t.k * t.amplitude * t.amplitude / 2.0).sum();
    assert!((set.mean_height_offset - expected).abs() < 1e-15);
    assert!(set.mean_height_offset > 0.0);
}

#[test]
fn phases_stay_precise_at_large_times() {
    let set = generate(&Scene::default());
    let t = 1.0e7;
    for train in &set.trains {
        let phase = train.phase_at(t);
        assert!((0.0..TAU).contains(&phase));
        // Against the phase advanced from t - 1 s by one second of omega: equal modulo 2 pi.
        let earlier = train.phase_at(t - 1.0);
        let step = (phase - earlier - train.omega).rem_euclid(TAU);
        assert!(step < 1e-6 || TAU - step < 1e-6, "phase drift {step} at t = {t}");
    }
}

#[test]
fn water_height_under_the_eye_solves_the_trochoid() {
    // One train along +x: the displaced point x + h sin(phi - k x) is 0 at the eye; bisection on
    // that (monotone for k h < 1) gives the height h cos(phi - k x) to compare with.
    let mut scene = Scene::default();
    scene.waves.count = 1;
    scene.waves.lambda_min_m = 10.0;
    scene.waves.lambda_max_m = LongestWave::Metres(10.0);
    scene.wind.direction_deg = 0.0;
    for time in [0.0, 1.3, 4.7, 123.0] {
        let set = generate(&scene);
        let t = &set.trains[0];
        let (k, h) = (t.k, t.amplitude);
        let dir = t.direction;
        let phase = t.phase_at(time);
        let f = |s: f64| s + h * (phase - k * s).sin(); // along the train's direction
        let (mut lo, mut hi) = (-2.0 * h - 1.0, 2.0 * h + 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if f(mid) > 0.0 {
                hi = mid
            } else {
                lo = mid
            }
        }
        let s = 0.5 * (lo + hi);
        let expected = set.mean_height_offset + h * (phase - k * s).cos();
        let got = set.water_height_at_origin(time);
        assert!((got - expected).abs() < 1e-9, "t = {time}: {got} vs {expected} (direction {dir:?})");
    }
}

#[test]
fn moving_the_eye_moves_the_waves_past_it() {
    // The world frame's origin is the eye: the phase of every train at the origin, with the eye
    // at p, is the phase the eye-at-zero waves have at p (omega t - k.p + phase0), mod 2 pi.
    let mut moved = Scene::default();
    moved.camera.x_m = 1234.5;
    moved.camera.y_m = -678.25;
    let (here, there) = (generate(&Scene::default()), generate(&moved));
    let time = 17.0;
    for (a, b) in here.trains.iter().zip(&there.trains) {
        let k_dot_p = a.k * (a.direction[0] * moved.camera.x_m + a.direction[1] * moved.camera.y_m);
        let expected = (a.phase_at(time) - k_dot_p).rem_euclid(TAU);
        let diff = (b.phase_at(time) - expected).rem_euclid(TAU);
        let diff = diff.min(TAU - diff);
        assert!(diff < 1e-9, "train of {} m: phase off by {diff} rad", a.wavelength);
        assert_eq!((a.k, a.amplitude, a.direction), (b.k, b.amplitude, b.direction), "only phases move");
    }
}

#[test]
fn wave_vectors_are_binary16_values() {
    // The shaders read each wave vector as two binary16 halves: the model's trains must be
    // exactly those values, never subnormal ones (a device may flush those), and within 2^-11 of
    // the geometric progression they were drawn on where no component was that small.
    let halves_only = |scene: &Scene| {
        let set = generate(scene);
        for (i, t) in set.trains.iter().enumerate() {
            for c in t.direction.map(|d| d / t.wavelength) {
                let half = half::f16::from_f64(c).to_f64();
                assert!((half - c).abs() <= 1e-12 * c.abs(), "train {i}: component {c} is not a half");
                assert!(c.abs() < 1e-12 || c.abs() >= 2f64.powi(-14), "train {i}: component {c} is subnormal");
            }
        }
        set
    };
    let scene = Scene::default();
    let set = halves_only(&scene);
    let (lo, hi) = (scene.waves.lambda_min_m, scene.lambda_max_m());
    for (i, t) in set.trains.iter().enumerate() {
        let nominal = lo * (hi / lo).powf(i as f64 / (set.trains.len() - 1) as f64);
        assert!(
            (t.wavelength / nominal - 1.0).abs() < 2f64.powi(-11),
            "train {i}: {} m, drawn at {nominal} m",
            t.wavelength
        );
    }
    // Kilometre waves can have components near the smallest normal half.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/extreme/kilometre_waves.toml");
    halves_only(&Scene::load(&dir).unwrap());
}
