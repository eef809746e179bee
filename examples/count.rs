use ocean::frame::{CameraFrame, GEOMETRY_STEPS, NORMAL_STEPS};
use ocean::reference::ReferenceScene;
use ocean::scene::Scene;
use ocean::sky::SkyModel;
use glam::DVec2;
fn main() {
    let scene = Scene::default();
    let waves = ocean::waves::generate(&scene);
    let (w, h) = (1024u32, 768u32);
    let camera = CameraFrame::new(&scene, &waves, w, h);
    let sky = SkyModel::new(3.0, 0.0, 2.5);
    let r = ReferenceScene { camera: &camera, waves: &waves, sky: &sky, time_s: 0.0, width: w, height: h };
    let (mut loop_total, mut geo_total, mut n_pix) = (0u64, 0u64, 0u64);
    for py in (384..768).step_by(16) {
        let (mut lp, mut geo) = (0, 0);
        for px in (0..1024).step_by(64) {
            let ray = r.pixel_ray(px as f64, py as f64);
            let Some((_, au, av)) = r.plane_hit(ray) else { continue };
            let v = -ray.normalize();
            // loop iterations: trains above the q_min-based cut, with and without the grazing bound
            let (qu, qv) = (au, av);
            let det = (qu.x * qv.y - qu.y * qv.x).abs();
            let diag = (qu - qv).length().max((qu + qv).length());
            let cut = det / diag / 0.25;
            let khmin = waves.trains.iter().map(|t| t.k * t.amplitude).fold(f64::MAX, f64::min);
            let g = (khmin * std::f64::consts::TAU / v.z).max(1.0);
            let iters = waves.trains.iter().filter(|t| t.wavelength > cut).count();
            let mut floor = f64::INFINITY; let floors: Vec<f64> = waves.trains.iter().map(|t| { floor = floor.min(t.k*t.amplitude); floor }).collect();
            let iters_g = waves.trains.iter().zip(&floors).rev().take_while(|(t, f)| t.wavelength > cut * (*f * std::f64::consts::TAU / v.z).max(1.0)).count();
            let _ = g;
            if px == 512 && py % 64 == 0 { println!("  iterations {iters}, with grazing bound {iters_g}, khmin {khmin:.3}"); }
            for t in &waves.trains {
                let k = DVec2::from(t.direction) / t.wavelength;
                let kh = t.k * t.amplitude;
                let wn = r.normal_weight(k, kh, au, av, v.z);
                let step_cell = k.dot(au * 8.0).abs().max(k.dot(av * 8.0).abs());
                if wn > 0.0 { lp += 1; }
                if step_cell <= GEOMETRY_STEPS[0] as f64 { geo += 1; }
            }
            n_pix += 1;
        }
        loop_total += lp; geo_total += geo;
        if py % 64 == 0 { println!("row {py}: trains with wn>0 per px {:.1}, fully geometric {:.1}", lp as f64 / 16.0, geo as f64 / 16.0); }
    }
    println!("mean: {:.1} trains in the normal loop, {:.1} fully geometric", loop_total as f64 / n_pix as f64, geo_total as f64 / n_pix as f64);
    let _ = NORMAL_STEPS;
}
#[allow(dead_code)]
fn unused() {}
