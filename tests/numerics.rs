//! The shader's functions, evaluated on the GPU over their whole domains including the limits,
//! against f64 implementations of the same formulas. Each has a stated bound on its largest
//! error; docs/numerics.md lists the measured values.

mod common;

use common::gpu;
use ocean::measure::numerics::{evaluate, Function};
use ocean::measure::reference;
use ocean::model::fresnel;
use ocean::render::footprint::Footprint;
use std::f64::consts::{PI, TAU};

/// Largest |gpu - cpu| / max(|cpu|, floor) over the sweep, with the arguments where it occurred.
fn worst(gpu_values: &[f64], cpu_values: &[f64], floor: f64) -> (f64, usize) {
    gpu_values
        .iter()
        .zip(cpu_values)
        .enumerate()
        .map(|(i, (g, c))| {
            assert!(g.is_finite(), "non-finite GPU value at {i}: {g} (f64 {c})");
            ((g - c).abs() / c.abs().max(floor), i)
        })
        .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
}

fn run(function: Function, args: &[[[f32; 4]; 2]], sun_var: f32) -> Vec<[f32; 4]> {
    let gpu = gpu();
    let out = evaluate(&gpu, function, args, sun_var).unwrap();
    assert_eq!(gpu.validation_counts().error_total(), 0);
    out
}

/// Values from 0 through tiny and moderate to the top of a range, the limits included.
fn sweep(top: f64) -> Vec<f64> {
    let mut v = vec![0.0, 1e-30, 1e-12, 1e-8, 1e-6, 1e-4];
    v.extend((1..=40).map(|i| top * i as f64 / 40.0));
    v.extend((0..20).map(|i| top * 10f64.powf(-3.0 + 3.0 * i as f64 / 20.0)));
    v
}

#[test]
fn smith_lambda_times_cosine() {
    // c Lambda(a), a = c / s, with the demo's erfc, written stably: exp(-a^2) (s / (2 sqrt(pi))
    // - c / (2.319 a + sqrt(4 + 1.52 a^2))). In f64 directly from the definition.
    let cpu = |c: f64, s: f64| {
        if s == 0.0 {
            return 0.0;
        }
        let a = c / s;
        if a == 0.0 {
            return s / (2.0 * PI.sqrt());
        }
        c * reference::smith_lambda(a)
    };
    let mut args = Vec::new();
    for c in sweep(1.0) {
        for s in sweep(3.0) {
            args.push([[c as f32, s as f32, 0.0, 0.0], [0.0; 4]]);
        }
    }
    let out = run(Function::CosTimesLambda, &args, 0.0);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> = args.iter().map(|a| cpu(a[0][0] as f64, a[0][1] as f64)).collect();
    // The value is at most s / (2 sqrt(pi)) ~ 0.85: errors relative to 1e-6 of that scale.
    let (e, i) = worst(&g, &c, 1e-6);
    eprintln!("c Lambda: largest error {e:.2e} at {:?}", args[i][0]);
    assert!(e < 2e-5, "c Lambda off by {e} at {:?}: {} vs {}", args[i][0], g[i], c[i]);
}

#[test]
fn mean_fresnel_over_its_domain() {
    let mut args = Vec::new();
    for cos_v in sweep(1.0) {
        for sigma in sweep(1.0) {
            args.push([[cos_v as f32, sigma as f32, 0.0, 0.0], [0.0; 4]]);
        }
    }
    let out = run(Function::MeanFresnel, &args, 0.0);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> = args.iter().map(|a| reference::mean_fresnel(a[0][0] as f64, a[0][1] as f64)).collect();
    let (e, i) = worst(&g, &c, 0.02);
    eprintln!("mean Fresnel: largest error {e:.2e} at {:?}", args[i][0]);
    assert!(e < 1e-5, "mean Fresnel off by {e} at {:?}", args[i][0]);
    assert!(g.iter().all(|&f| (0.02 - 1e-6..=1.0 + 1e-6).contains(&f)), "mean Fresnel leaves [R0, 1]");
}

#[test]
fn exact_fresnel_over_its_domain() {
    let args: Vec<_> = sweep(1.0).into_iter().map(|c| [[c as f32, 0.0, 0.0, 0.0], [0.0; 4]]).collect();
    let out = run(Function::ExactFresnel, &args, 0.0);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> = args.iter().map(|a| fresnel::fresnel_exact(a[0][0] as f64, fresnel::SEA_WATER_IOR)).collect();
    let (e, i) = worst(&g, &c, 0.02);
    eprintln!("exact Fresnel: largest error {e:.2e} at {:?}", args[i][0]);
    assert!(e < 1e-5, "exact Fresnel off by {e} at {:?}: {} vs {}", args[i][0], g[i], c[i]);
}

#[test]
fn the_visible_fresnel_table_matches_its_quadrature() {
    // The shader's bilinear lookup against the f64 quadrature itself (not the table) at the
    // sweep's points, which fall between the table's nodes, and at the domain's corners.
    let mut args = Vec::new();
    for cos_v in sweep(1.0) {
        for sigma in sweep(0.6) {
            args.push([[cos_v as f32, sigma as f32, 0.0, 0.0], [0.0; 4]]);
        }
    }
    let out = run(Function::VisibleFresnel, &args, 0.0);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> = args
        .iter()
        .map(|a| fresnel::visible_mean_fresnel(a[0][0] as f64, a[0][1] as f64, fresnel::SEA_WATER_IOR))
        .collect();
    let (e, i) = worst(&g, &c, 0.02);
    eprintln!("visible Fresnel: largest error {e:.2e} at {:?}", args[i][0]);
    assert!(e < 4e-3, "visible Fresnel off by {e} at {:?}: {} vs {}", args[i][0], g[i], c[i]);
    // Against the paper's fit where the fit is known to drift: grazing views read less.
    let fit = reference::mean_fresnel(0.02, 0.1);
    let exact = fresnel::visible_mean_fresnel(0.02, 0.1, fresnel::SEA_WATER_IOR);
    assert!(exact < 0.9 * fit, "at cos_v 0.02, sigma 0.1: exact average {exact}, the paper's fit {fit}");
}

#[test]
fn sin_and_cos_of_turns_stay_accurate_for_large_phases() {
    let mut args = Vec::new();
    for i in 0..4001 {
        // -2^20 .. 2^20 turns, and fine steps near 0 and the quadrant boundaries.
        let coarse = (i as f64 - 2000.0) / 2000.0 * 1048576.0 + 0.1234567 * (i % 7) as f64;
        args.push([[coarse as f32, 0.0, 0.0, 0.0], [0.0; 4]]);
        args.push([[(i as f64 / 4000.0 - 0.5) as f32, 0.0, 0.0, 0.0], [0.0; 4]]);
    }
    let out = run(Function::SinCosTurns, &args, 0.0);
    let mut worst_abs = 0.0f64;
    for (a, r) in args.iter().zip(&out) {
        // The argument as the GPU has it (f32), reduced exactly in f64.
        let t = a[0][0] as f64;
        let (s, c) = (TAU * t.rem_euclid(1.0)).sin_cos();
        worst_abs = worst_abs.max((r[0] as f64 - s).abs()).max((r[1] as f64 - c).abs());
    }
    eprintln!("sincos_turns: largest absolute error {worst_abs:.2e}");
    assert!(worst_abs < 1e-6, "sincos_turns off by {worst_abs}");
}

#[test]
fn trochoid_slope_variance_without_cancellation() {
    let args: Vec<[[f32; 4]; 2]> = sweep(1.0).iter().map(|&a| [[a as f32, 0.0, 0.0, 0.0], [0.0; 4]]).collect();
    let out = run(Function::TrochoidSlopeVariance, &args, 0.0);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> =
        args.iter().map(|a| ocean::model::waves::trochoid_slope_variance((a[0][0] as f64).powi(2))).collect();
    // Relative to the value itself down to 1e-30: the form a^2 / (1 + sqrt(1 - a^2)) keeps digits.
    let (e, i) = worst(&g, &c, 1e-30);
    eprintln!("trochoid variance: largest relative error {e:.2e} at {:?}", args[i][0]);
    assert!(e < 1e-6, "trochoid variance off by {e} at {:?}", args[i][0]);
}

fn direction(elevation: f64, azimuth: f64) -> [f32; 3] {
    [(elevation.cos() * azimuth.cos()) as f32, (elevation.cos() * azimuth.sin()) as f32, elevation.sin() as f32]
}

#[test]
fn reflected_sun_at_grazing_and_glassy_limits() {
    let sun_var = ocean::model::sky::SkyModel::sun_slope_variance() as f32;
    let elevations = [0.0, 1e-6, 1e-3, 0.01, 0.05, 0.2, 0.5, 1.0, 1.5, PI / 2.0];
    let variances = [0.0, 1e-6, 1e-4, 1e-3, 0.01, 0.05, 0.2, 1.0];
    let mut args = Vec::new();
    for &ev in &elevations {
        for &el in &elevations {
            for azimuth in [PI, PI - 0.02, PI - 0.2, 2.0] {
                for &sx in &variances {
                    for sy in [sx, sx * 0.5] {
                        let v = direction(ev, 0.0);
                        let l = direction(el, azimuth);
                        args.push([[v[0], v[1], v[2], sx as f32], [l[0], l[1], l[2], sy as f32]]);
                    }
                }
            }
        }
    }
    let out = run(Function::ReflectedSun, &args, sun_var);
    let to64 = |a: [f32; 4]| glam::DVec3::new(a[0] as f64, a[1] as f64, a[2] as f64);
    let g: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    let c: Vec<f64> = args
        .iter()
        .map(|a| reference::reflected_sun(to64(a[0]), to64(a[1]), [a[0][3] as f64, a[1][3] as f64], sun_var as f64))
        .collect();
    // The glitter of a glassy sea reaches 1e5 per unit irradiance; compare relative to the value,
    // with a floor of 1e-3 (a thousandth of a unit of irradiance reflected).
    let (e, i) = worst(&g, &c, 1e-3);
    eprintln!("reflected sun: largest error {e:.2e} at {:?}: {} vs {}", args[i], g[i], c[i]);
    assert!(e < 2e-5, "reflected sun off by {e} at {:?}: GPU {} f64 {}", args[i], g[i], c[i]);
}

#[test]
fn reflection_footprint_u_of_zeta() {
    let mut args = Vec::new();
    for ev in [0.0, 1e-4, 0.01, 0.1, 0.5, 1.0, 1.5, PI / 2.0] {
        for zx in [-10.0, -1.0, -0.1, 0.0, 1e-3, 0.1, 1.0, 10.0] {
            for zy in [-1.0, 0.0, 0.3] {
                let v = direction(ev, 0.3);
                args.push([[v[0], v[1], v[2], 0.0], [zx as f32, zy as f32, 0.0, 0.0]]);
            }
        }
    }
    let out = run(Function::ReflectedU, &args, 0.0);
    let mut worst_abs = 0.0f64;
    for (a, r) in args.iter().zip(&out) {
        let v = glam::DVec3::new(a[0][0] as f64, a[0][1] as f64, a[0][2] as f64);
        let f = glam::DVec3::new(-a[1][0] as f64, -a[1][1] as f64, 1.0).normalize();
        let refl = 2.0 * v.dot(f) * f - v;
        let u = [refl.x / (1.0 + refl.z.abs()), refl.y / (1.0 + refl.z.abs())];
        worst_abs = worst_abs.max((r[0] as f64 - u[0]).abs()).max((r[1] as f64 - u[1]).abs());
    }
    eprintln!("U(zeta): largest absolute error {worst_abs:.2e}");
    assert!(worst_abs < 2e-6, "U(zeta) off by {worst_abs}");
}

#[test]
fn normal_weights_across_the_screen() {
    // The default scene's camera at 64 x 64 (as numerics.rs sets up), trains of 2 cm to 30 m in
    // several directions, every pixel row from the horizon down: the GPU's weight against the f64
    // reference's (same footprint formula, same box filter).
    let scene = ocean::model::scene::Scene::default();
    let wave_set = ocean::model::waves::generate(&scene);
    let camera = ocean::render::frame::CameraFrame::new(&scene, &wave_set, 64, 64);
    let sky = ocean::model::sky::SkyModel::new(3.0, 0.0, 2.5);
    let reference = reference::ReferenceScene {
        footprint: Footprint { camera: &camera, waves: &wave_set, time_s: 0.0, width: 64, height: 64, packets: None },
        sky: &sky,
        full: false,
    };
    let mut args = Vec::new();
    let mut cpu = Vec::new();
    for py in (30..64).step_by(2) {
        for px in [0.0, 20.0, 32.0, 63.0] {
            let ray = reference.pixel_ray(px, py as f64);
            let Some((_, a_u, a_v)) = reference.rest_hit(ray) else { continue };
            for lambda in [0.02, 0.1, 0.5, 2.0, 8.0, 30.0] {
                for angle in [0.0f64, 0.7, 1.6] {
                    let k = glam::DVec2::new(angle.cos(), angle.sin()) / lambda;
                    let ndc = [(px + 0.5) / 32.0 - 1.0, (py as f64 + 0.5) / 32.0 - 1.0];
                    args.push([[ndc[0] as f32, ndc[1] as f32, k.x as f32, k.y as f32], [0.0; 4]]);
                    cpu.push(reference.normal_weight(k, a_u, a_v));
                }
            }
        }
    }
    let out = run(Function::NormalWeight, &args, 0.0);
    let gpu_w: Vec<f64> = out.iter().map(|r| r[0] as f64).collect();
    // Weights lie in [0, 1]: absolute error. The box transfer's slope is at most about 1.3 per
    // turn of step; measured 7.4e-7 with the former smoothstep.
    let worst_abs = gpu_w.iter().zip(&cpu).map(|(g, c)| (g - c).abs()).fold(0.0, f64::max);
    eprintln!("normal weights: largest absolute error {worst_abs:.2e} over {} cases", cpu.len());
    assert!(worst_abs < 1e-5, "normal weight off by {worst_abs}");
    assert!(gpu_w.iter().any(|&w| w > 0.999) && gpu_w.contains(&0.0) && gpu_w.iter().any(|&w| w > 0.1 && w < 0.9));
}

/// The visible facets' mean slope, integrated numerically in f64 over the Gaussian slopes with
/// each facet weighted by its projected area (v_z - zeta . v_xy)^+: independent of the closed form
/// the shader uses (glsl/slopes.glsl).
fn visible_mean_slope(v: [f64; 3], sigma2: [f64; 2]) -> [f64; 2] {
    let (mean, _) = visible_slope_moments(v, sigma2);
    mean
}

/// The visible facets' mean slope and slope covariance (xx, xy, yy), by the same integral.
fn visible_slope_moments(v: [f64; 3], sigma2: [f64; 2]) -> ([f64; 2], [f64; 3]) {
    let (sx, sy) = (sigma2[0].sqrt(), sigma2[1].sqrt());
    let n = 600;
    let (mut w_sum, mut zx_sum, mut zy_sum) = (0.0, 0.0, 0.0);
    let (mut xx, mut xy, mut yy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        for j in 0..n {
            // Midpoints over +-8 sigma on each axis.
            let (a, b) = (-8.0 + 16.0 * (i as f64 + 0.5) / n as f64, -8.0 + 16.0 * (j as f64 + 0.5) / n as f64);
            let (zx, zy) = (a * sx, b * sy);
            let w = (-0.5 * (a * a + b * b)).exp() * (v[2] - zx * v[0] - zy * v[1]).max(0.0);
            w_sum += w;
            zx_sum += w * zx;
            zy_sum += w * zy;
            xx += w * zx * zx;
            xy += w * zx * zy;
            yy += w * zy * zy;
        }
    }
    let (mx, my) = (zx_sum / w_sum, zy_sum / w_sum);
    ([mx, my], [xx / w_sum - mx * mx, xy / w_sum - mx * my, yy / w_sum - my * my])
}

#[test]
fn visible_slope_shift_matches_the_integral() {
    let mut args = Vec::new();
    for elevation_deg in [90.0, 60.0, 30.0, 10.0, 3.0, 1.0, 0.0] {
        for azimuth in [0.0, 0.7, PI / 2.0, 2.5] {
            for sigma2 in [[0.01, 0.01], [0.04, 0.01], [0.002, 0.03], [0.2, 0.1]] {
                let v = direction(f64::to_radians(elevation_deg), azimuth);
                args.push([[v[0], v[1], v[2], 0.0], [sigma2[0] as f32, sigma2[1] as f32, 0.0, 0.0]]);
            }
        }
    }
    let out = run(Function::VisibleSlopeShift, &args, 0.0);
    let mut worst_rel = 0.0f64;
    for (a, r) in args.iter().zip(&out) {
        let v = [a[0][0] as f64, a[0][1] as f64, a[0][2] as f64];
        let sigma2 = [a[1][0] as f64, a[1][1] as f64];
        let exact = visible_mean_slope(v, sigma2);
        // Relative to the slopes' spread: the shift is a fraction of sigma.
        let scale = sigma2[0].max(sigma2[1]).sqrt();
        let e = (r[0] as f64 - exact[0]).abs().max((r[1] as f64 - exact[1]).abs()) / scale;
        assert!(e < 1e-3, "shift off by {e} sigma at v {v:?}, sigma^2 {sigma2:?}: GPU {r:?}, integral {exact:?}");
        worst_rel = worst_rel.max(e);
    }
    eprintln!("visible slope shift: largest error {worst_rel:.2e} sigma");
    // The footprint's axes span the visible slopes' covariance (relative to sigma^2).
    let out = run(Function::VisibleSlopeCovariance, &args, 0.0);
    let mut worst_cov = 0.0f64;
    for (a, r) in args.iter().zip(&out) {
        let v = [a[0][0] as f64, a[0][1] as f64, a[0][2] as f64];
        let sigma2 = [a[1][0] as f64, a[1][1] as f64];
        let (_, exact) = visible_slope_moments(v, sigma2);
        let scale = sigma2[0].max(sigma2[1]);
        let e = (0..3).map(|i| (r[i] as f64 - exact[i]).abs()).fold(0.0, f64::max) / scale;
        assert!(
            e < 2e-3,
            "covariance off by {e} sigma^2 at v {v:?}, sigma^2 {sigma2:?}: GPU {r:?}, integral {exact:?}"
        );
        worst_cov = worst_cov.max(e);
    }
    eprintln!("visible slope covariance: largest error {worst_cov:.2e} sigma^2");
    // At grazing view the shift is Phi(0) / phi(0) = 1.2533 sigma towards the viewer.
    let grazing = run(Function::VisibleSlopeShift, &[[[1.0, 0.0, 0.0, 0.0], [0.01, 0.01, 0.0, 0.0]]], 0.0);
    assert!((grazing[0][0] as f64 + 0.1 * (PI / 2.0).sqrt()).abs() < 1e-5, "grazing shift {:?}", grazing[0]);
}

#[test]
fn the_whole_stereographic_plane_is_held_at_the_maps_extent() {
    let extent = ocean::render::frame::SKY_MAP_EXTENT as f64;
    let mut args = Vec::new();
    for elevation_deg in [90.0, 45.0, 1.0, 0.0, -1.0, -10.0, -22.0, -23.0, -45.0, -89.9, -90.0] {
        for azimuth in [0.0, 1.0, PI] {
            let v = direction(f64::to_radians(elevation_deg), azimuth);
            args.push([[v[0], v[1], v[2], 0.0], [0.0; 4]]);
        }
    }
    let out = run(Function::StereographicPlane, &args, 0.0);
    for (a, r) in args.iter().zip(&out) {
        let d = glam::DVec3::new(a[0][0] as f64, a[0][1] as f64, a[0][2] as f64);
        let xy = glam::DVec2::new(d.x, d.y);
        // Beyond the extent (|xy| / (1 + z) > R) the rim point along the azimuth.
        let u = if xy.length() == 0.0 && d.z < 0.0 {
            glam::DVec2::new(extent, 0.0)
        } else if xy.length() > extent * (1.0 + d.z) {
            xy.normalize() * extent
        } else {
            xy / (1.0 + d.z)
        };
        let e = (r[0] as f64 - u.x).abs().max((r[1] as f64 - u.y).abs());
        assert!(r[0].is_finite() && r[1].is_finite() && e < 1e-5, "u of {d:?}: GPU {r:?}, f64 {u:?}");
    }
}

/// The sea's sphere from 5 cm to beyond geostationary orbit, looking straight down to within
/// 1e-4 of the limb's depression: the shader's distance against the other root form in f64
/// (B - sqrt(B^2 - c), exact enough there), and the rays at or above the limb missing on both.
#[test]
fn the_spheres_distance_keeps_its_precision_at_planetary_scale() {
    let planet = ocean::model::scene::Planet::default();
    let r = planet.radius_m;
    let mut args = Vec::new();
    let mut expected = Vec::new();
    for h in [0.05f32, 2.0, 10.0, 1e3, 1.1e4, 4e5, 3.6e7, 4e7] {
        let h = h as f64; // the shader's own value
        let s = planet.dip(h).sin();
        for d in [1.0, 0.5, 0.1, 0.01, s * 1.01, s * 1.0001, s * 0.999, 0.0, -0.5] {
            let d32 = d as f32;
            let z = -(d32 as f64);
            let ray = [((1.0 - z * z).max(0.0)).sqrt() as f32, 0.0, -d32, 0.0];
            args.push([ray, [h as f32, r as f32, 0.0, 0.0]]);
            // The quadratic's near root by the other form, in f64 (its cancellation costs under
            // 1e-9 here).
            let (b, c) = ((r + h) * d32 as f64, h * (2.0 * r + h));
            let disc = b * b - c;
            expected.push(if b > 0.0 && disc > 0.0 { Some(b - disc.sqrt()) } else { None });
        }
    }
    let out = run(Function::SphereDistance, &args, 0.0);
    let mut worst = 0.0f64;
    for ((a, got), want) in args.iter().zip(&out).zip(&expected) {
        let (h, d) = (a[1][0], -a[0][2]);
        match want {
            Some(t) => {
                let e = (got[0] as f64 / t - 1.0).abs();
                worst = worst.max(e);
                assert!(e < 1e-4, "H {h} m, depression sine {d}: GPU {} against {t}", got[0]);
                let cpu = ocean::model::scene::Planet::default().ray_distance(h as f64, d as f64).unwrap();
                assert!((cpu / t - 1.0).abs() < 1e-7, "H {h}, d {d}: f64 product form {cpu} against {t}");
            }
            None => assert_eq!(got[0], -1.0, "H {h} m, depression sine {d}: the ray misses"),
        }
    }
    eprintln!("sphere distance: largest relative error {worst:.2e}");
    // The dip against arccos(R / (R + H)) where f64's cosine still resolves it.
    for h in [1e3, 4e5, 3.6e7] {
        let e = (planet.dip(h) - (r / (r + h)).acos()).abs();
        assert!(e < 1e-6, "dip at {h} m off by {e}");
    }
}

/// The binomial law's quantile at u in f64: the smallest k whose cumulative probability reaches u.
fn binomial_quantile(n: f64, p: f64, u: f64) -> (f64, f64) {
    let (mut k, mut pk) = (0.0, (1.0 - p).powf(n));
    let mut cdf = pk;
    // The distance from u to the nearest step of the law, where f32 rounding (of 1 - p to 5e-5
    // relative near p = 1, carried over a few terms) may pick its neighbour.
    let mut margin = (u - cdf).abs();
    while u > cdf && k < n {
        pk *= (n - k) / (k + 1.0) * p / (1.0 - p);
        k += 1.0;
        cdf += pk;
        margin = margin.min((u - cdf).abs());
    }
    (k, margin)
}

#[test]
fn the_glints_binomial_count_is_the_laws_quantile_and_keeps_its_mean() {
    // Small means by inversion: the f64 quantile of the same uniform, except within f32's rounding
    // of a step; over a stratified sweep of u the mean is n p.
    let cases = [(1.0, 0.3), (3.0, 0.5), (12.0, 0.25), (400.0, 0.01), (1.0e6, 5.0e-6), (7.0, 0.999)];
    let strata = 4096u32;
    let mut args = Vec::new();
    for &(n, p) in &cases {
        for i in 0..strata {
            let u = ((i as f64 + 0.5) / strata as f64 * 16_777_216.0).floor() / 16_777_216.0;
            args.push([[n as f32, p as f32, (n * p) as f32, u as f32], [0.5, 0.0, 0.0, 0.0]]);
        }
    }
    let out = run(Function::BinomialCount, &args, 0.0);
    for (c, &(n, p)) in cases.iter().enumerate() {
        let mut sum = 0.0;
        for i in 0..strata as usize {
            let a = args[c * strata as usize + i];
            let got = out[c * strata as usize + i][0] as f64;
            let (want, margin) = binomial_quantile(a[0][0] as f64, a[0][1] as f64, a[0][3] as f64);
            if margin > 1e-3 {
                assert_eq!(got, want, "n {n}, p {p}, u {}: count {got} against the quantile {want}", a[0][3]);
            }
            sum += got;
        }
        let mean = sum / strata as f64;
        // A stratified sweep's mean is within the law's largest step over the strata of n p.
        assert!((mean / (n * p) - 1.0).abs() < 0.01, "n {n}, p {p}: mean count {mean} against {}", n * p);
    }
    // Large means by the normal law: mean + sqrt(n p (1 - p)) z, z by Box-Muller from (u1, u2).
    let (n, p) = (1.0e5f64, 0.02f64);
    let mut args = Vec::new();
    for i in 0..64u32 {
        let (u1, u2) = ((i as f64 + 0.5) / 64.0, (i % 7) as f64 / 7.0);
        let q = |u: f64| ((u * 16_777_216.0).floor() / 16_777_216.0) as f32;
        args.push([[n as f32, p as f32, (n * p) as f32, 0.0], [q(u1), q(u2), 0.0, 0.0]]);
    }
    for (a, got) in args.iter().zip(run(Function::BinomialCount, &args, 0.0)) {
        let (u1, u2) = ((a[1][0] as f64 * 16_777_216.0 + 0.5) / 16_777_216.0, a[1][1] as f64);
        let z = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
        let want = n * p + (n * p * (1.0 - p)).sqrt() * z;
        assert!((got[0] as f64 - want).abs() < 1e-3 * want, "u1 {u1}, u2 {u2}: {} against {want}", got[0]);
    }
}

/// The standard normal's mass between a and b in f64, by Simpson's rule on its density (the
/// infinite ends cut at 12 standard deviations, where the tail is below 1e-32).
fn normal_mass(a: f64, b: f64) -> f64 {
    let (a, b) = (a.max(-12.0), b.min(12.0));
    if b <= a {
        return 0.0;
    }
    let n = 20_000;
    let h = (b - a) / n as f64;
    let density = |x: f64| (-0.5 * x * x).exp() / TAU.sqrt();
    let inner: f64 = (1..n).map(|k| density(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 }).sum();
    (density(a) + density(b) + inner) * h / 3.0
}

#[test]
fn a_reflection_cones_taps_share_the_gaussian_by_nearness() {
    // Each tap of a cone stands for the slopes nearer to it than to its neighbours: the masses
    // sum to 1, match the f64 integral, and favour the centre over equal parts.
    // The cone's own spacing for `count` taps (brdf.glsl reflection_cone: sqrt(12 (1 - s^2) /
    // (n^2 - 1)) at s^2 = 3 / (n^2 + 2)).
    let own_spacing = |count: u32| {
        let n2 = (count * count) as f64;
        if count > 1 {
            (12.0 * (1.0 - 3.0 / (n2 + 2.0)) / (n2 - 1.0)).sqrt()
        } else {
            0.0
        }
    };
    let mut args = Vec::new();
    for count in 1..=8u32 {
        // The cone's own spacing, and wider and narrower ones.
        for spacing in [own_spacing(count), 0.1, 0.5, 1.0, 2.0] {
            for tap in 0..count {
                args.push([[tap as f32, count as f32, spacing as f32, 0.0], [0.0; 4]]);
            }
        }
    }
    let out = run(Function::TapMass, &args, 0.0);
    let mut worst_error: f64 = 0.0;
    let mut sums = std::collections::BTreeMap::<(u32, u32), f64>::new();
    for (a, r) in args.iter().zip(&out) {
        let (tap, count, spacing) = (a[0][0] as f64, a[0][1] as u32, a[0][2] as f64);
        let at = (tap - 0.5 * (count as f64 - 1.0)) * spacing;
        let lower = if tap == 0.0 { f64::NEG_INFINITY } else { at - 0.5 * spacing };
        let upper = if tap as u32 == count - 1 { f64::INFINITY } else { at + 0.5 * spacing };
        let want = normal_mass(lower, upper);
        let got = r[0] as f64;
        assert!(got.is_finite() && got >= 0.0, "tap {tap} of {count} at spacing {spacing}: {got}");
        worst_error = worst_error.max((got - want).abs());
        *sums.entry((count, a[0][2].to_bits())).or_default() += got;
    }
    eprintln!("tap masses: largest error {worst_error:.2e}");
    assert!(worst_error < 1e-6, "tap masses off the Gaussian's by {worst_error}");
    for ((count, _), sum) in sums {
        assert!((sum - 1.0).abs() < 2e-6, "{count} taps' masses sum to {sum}");
    }
    // Eight taps at the cone's own spacing: the central pair stands for more than an equal
    // eighth, the outer ones for less.
    let eight: Vec<f64> = args
        .iter()
        .zip(&out)
        .filter(|(a, _)| a[0][1] == 8.0 && a[0][2] == own_spacing(8) as f32)
        .map(|(_, r)| r[0] as f64)
        .collect();
    assert_eq!(eight.len(), 8);
    assert!(eight[3] > 0.16 && eight[0] < 0.105, "eight taps' masses {eight:?}");
}
