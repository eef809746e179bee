//! Stiff and extreme scenes (scenes/extreme/): every one renders under validation with finite,
//! sane radiance and no seam along the horizon; so do extreme image sizes.

mod common;

use common::{assert_clean, gpu, luminance, render};
use ocean::model::scene::Scene;
use ocean::render::renderer::RenderedFrame;
use std::path::Path;

fn extreme_scenes() -> Vec<(String, Scene)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/extreme");
    let mut scenes: Vec<(String, Scene)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), Scene::load(&p).unwrap()))
        .collect();
    scenes.sort_by(|a, b| a.0.cmp(&b.0));
    scenes
}

fn row_luminance(frame: &RenderedFrame, y: u32) -> f64 {
    (0..frame.width).map(|x| luminance(frame.hdr[(y * frame.width + x) as usize])).sum::<f64>() / frame.width as f64
}

/// A seam is a row around the horizon that stands out from both its neighbours (brighter or
/// darker than each by more than 15% of their difference plus 2%): a line, not a transition.
fn assert_no_seam(frame: &RenderedFrame, horizon_row: u32, name: &str) {
    let lo = horizon_row.saturating_sub(4).max(1);
    let hi = (horizon_row + 4).min(frame.height - 2);
    for y in lo..=hi {
        let (above, here, below) = (row_luminance(frame, y - 1), row_luminance(frame, y), row_luminance(frame, y + 1));
        let slack = 0.15 * (above - below).abs() + 0.02 * above.max(below);
        let spike = here > above.max(below) + slack || here < above.min(below) - slack;
        assert!(!spike, "{name}: row {y} ({here:.3}) stands out between {above:.3} and {below:.3}");
    }
}

#[test]
fn every_extreme_scene_renders_finite_and_sane() {
    let gpu = gpu();
    let scenes = extreme_scenes();
    assert!(scenes.len() >= 18, "the extreme suite is incomplete");
    for (name, scene) in &scenes {
        let (report, frame) = render(&gpu, scene, 64, 48);
        assert_clean(&report, name);
        let mean = report.mean_radiance;
        assert!(mean.iter().all(|&c| c.is_finite() && (0.0..1e5).contains(&c)), "{name}: mean radiance {mean:?}");
        if scene.sun.elevation_deg > -18.0 {
            assert!(mean.iter().all(|&c| c > 0.0), "{name}: black by day or twilight: {mean:?}");
        }
        assert!(
            frame.hdr.iter().all(|p| p[..3].iter().all(|&c| (0.0..=65504.0).contains(&c))),
            "{name}: radiance out of range"
        );
    }
}

#[test]
fn the_horizon_has_no_seam() {
    let gpu = gpu();
    let mut cases: Vec<(String, Scene)> = [("level", 0.0), ("slightly down", -5.0), ("slightly up", 5.0)]
        .into_iter()
        .map(|(name, pitch)| {
            let mut scene = Scene::default();
            scene.camera.pitch_deg = pitch;
            (name.to_owned(), scene)
        })
        .collect();
    cases.extend(extreme_scenes());
    let (w, h) = (128u32, 96u32);
    let mut checked = 0;
    for (name, scene) in &cases {
        // NDC y of the horizon: tan(pitch) / tan(fov/2), y pointing down.
        let tan_half = (scene.camera.fov_y_deg.to_radians() / 2.0).tan();
        let ndc = scene.camera.pitch_deg.to_radians().tan() / tan_half;
        let row = ((ndc + 1.0) / 2.0 * h as f64).round();
        if !(6.0..h as f64 - 6.0).contains(&row) {
            continue; // the horizon is off screen
        }
        let (report, frame) = render(&gpu, scene, w, h);
        assert_clean(&report, name);
        assert_no_seam(&frame, row as u32, name);
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} views had the horizon in view");
}

#[test]
fn extreme_sizes_render_clean() {
    let gpu = gpu();
    for (w, h) in [(1, 1), (7, 3), (4096, 16), (16, 4096)] {
        let (report, frame) = render(&gpu, &Scene::default(), w, h);
        assert_clean(&report, &format!("{w}x{h}"));
        assert_eq!(frame.hdr.len(), (w * h) as usize);
    }
}
