//! Leaving out what a scene does not need never changes the picture: each omission renders the
//! same image as the general pipeline, and the report says what was left out and why.

mod common;

use common::{assert_clean, gpu};
use ocean::app::report::Report;
use ocean::app::{render_on, RenderRequest};
use ocean::model::scene::Scene;
use ocean::render::renderer::RenderedFrame;
use ocean::vk::gpu::Gpu;
use std::path::Path;

fn render(gpu: &Gpu, scene: &Scene, specialize: bool) -> (Report, RenderedFrame) {
    let request = RenderRequest { validation: true, specialize, ..RenderRequest::new(scene.clone(), 96, 64) };
    let (report, frame) = render_on(gpu, &request).unwrap();
    assert_clean(&report, if specialize { "specialized" } else { "general" });
    (report, frame)
}

/// Largest difference between two frames, relative to the brightest channel of the general one.
fn difference(a: &RenderedFrame, b: &RenderedFrame) -> f64 {
    let peak = b.hdr.iter().flat_map(|p| p[..3].iter().copied()).fold(0.0f32, f32::max).max(1e-6) as f64;
    a.hdr.iter().zip(&b.hdr).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs() as f64)).fold(0.0, f64::max)
        / peak
}

#[test]
fn omissions_keep_the_picture() {
    let gpu = gpu();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    // (scene, what must be left out)
    let cases = [
        ("default.toml", vec![]),
        ("extreme/sun_just_below.toml", vec!["sun term"]),
        ("extreme/sun_night.toml", vec!["sun term", "sky term", "refracted term", "sky map", "sky behind the sea"]),
        ("extreme/camera_10km.toml", vec!["vertex displacement"]),
        ("high_altitude.toml", vec!["vertex displacement", "the step to where each pixel's ray meets the sea"]),
        ("orbit.toml", vec!["vertex displacement", "per-pixel wave normals"]),
        ("extreme/look_down_5cm.toml", vec!["aerial perspective"]),
    ];
    for (file, expected) in cases {
        let scene = Scene::load(&dir.join(file)).unwrap();
        let (special, fast) = render(&gpu, &scene, true);
        let (general, slow) = render(&gpu, &scene, false);
        // Without objects nothing is reflected locally, and without local waves no packet is
        // drawn, specialized or not.
        let structural = |o: &ocean::render::specialize::Omission| {
            o.what.starts_with("local reflections") || o.what.starts_with("wave packets")
        };
        assert!(general.omitted.iter().all(structural), "{:?}", general.omitted);
        for what in &expected {
            assert!(
                special.omitted.iter().any(|o| o.what.starts_with(what) && !o.why.is_empty()),
                "{file}: {what} not left out: {:?}",
                special.omitted
            );
        }
        if expected.is_empty() {
            let expected = |o: &ocean::render::specialize::Omission| o.what.starts_with("resolve") || structural(o);
            assert!(special.omitted.iter().all(expected), "{file}: {:?}", special.omitted);
        }
        // The same picture: to binary16 rounding of the brightest value.
        let d = difference(&fast, &slow);
        assert!(d < 1e-3, "{file}: specialized and general differ by {d} of the peak");
    }
}
