//! End-to-end renders on the test device under validation: clean, finite and plausible.

mod common;

use ash::vk;
use common::{assert_clean, gpu, luminance, render};
use ocean::model::scene::Scene;
use ocean::render::renderer::RenderedFrame;

fn mean_luminance(frame: &RenderedFrame, rows: std::ops::Range<u32>, cols: std::ops::Range<u32>) -> f64 {
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in rows {
        for x in cols.clone() {
            sum += luminance(frame.hdr[(y * frame.width + x) as usize]);
            n += 1.0;
        }
    }
    sum / n
}

/// Column (image x) whose sea rows are brightest, averaged over the lower half of the image.
fn brightest_sea_column(frame: &RenderedFrame) -> u32 {
    let (w, h) = (frame.width, frame.height);
    (0..w)
        .max_by(|&a, &b| {
            let la = mean_luminance(frame, h / 2 + 4..h, a..a + 1);
            let lb = mean_luminance(frame, h / 2 + 4..h, b..b + 1);
            la.total_cmp(&lb)
        })
        .unwrap()
}

#[test]
fn default_scene_is_clean_and_plausible() {
    let gpu = gpu();
    let scene = Scene::default();
    let (report, frame) = render(&gpu, &scene, 256, 192);
    assert_clean(&report, "default scene");
    assert_eq!(frame.hdr.len(), 256 * 192);
    assert!(report.gpu_ms.contains_key("shade") && report.gpu_ms.contains_key("total"));

    // Level camera: the horizon is the middle row. Sky above, sea below.
    let sky = mean_luminance(&frame, 0..80, 0..256);
    let sea_aside = mean_luminance(&frame, 110..192, 0..64);
    assert!(sky > 0.0 && sea_aside > 0.0);
    assert!(sky > 2.0 * sea_aside, "the sky ({sky:.3}) outshines the sea away from the glitter ({sea_aside:.3})");
    // The sky gets brighter towards the sun on the horizon (straight ahead).
    assert!(mean_luminance(&frame, 80..95, 112..144) > mean_luminance(&frame, 0..15, 112..144));
    // Sun glitter: brightest straight below the sun.
    let column = brightest_sea_column(&frame);
    assert!((118..138).contains(&column), "glitter column at x = {column}, the sun is at x = 128");
}

#[test]
fn glitter_follows_the_sun_azimuth() {
    let gpu = gpu();
    let mut scene = Scene::default();
    scene.sun.azimuth_deg = 15.0; // counter-clockwise: to the left of the view
    let (report, frame) = render(&gpu, &scene, 256, 192);
    assert_clean(&report, "sun to the left");
    let column = brightest_sea_column(&frame);
    // x = w/2 (1 - tan(15 deg) / tan(fov_x / 2)), fov_y 60 degrees at 4:3.
    let tan_half_x = (30f64.to_radians()).tan() * 256.0 / 192.0;
    let expected = 128.0 * (1.0 - 15f64.to_radians().tan() / tan_half_x);
    assert!((column as f64 - expected).abs() < 10.0, "glitter at x = {column}, expected near {expected:.0}");
}

#[test]
fn odd_sizes_render_clean() {
    let gpu = gpu();
    let scene = Scene::default();
    for (w, h) in [(333, 97), (7, 3), (1, 1)] {
        let (report, frame) = render(&gpu, &scene, w, h);
        assert_clean(&report, &format!("{w}x{h}"));
        assert_eq!(frame.ldr.len(), (4 * w * h) as usize);
    }
}

#[test]
fn every_preset_renders_clean() {
    let gpu = gpu();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for name in ["calm", "storm", "sunset", "noon", "high_altitude"] {
        let scene = Scene::load(&dir.join(format!("{name}.toml"))).unwrap();
        let (report, frame) = render(&gpu, &scene, 96, 64);
        assert_clean(&report, name);
        let mean = report.mean_radiance;
        assert!(mean.iter().all(|&c| c > 0.0 && c < 1e4), "{name}: mean radiance {mean:?}");
        assert!(frame.hdr.iter().all(|p| p[..3].iter().all(|&c| c >= 0.0)));
    }
}

#[test]
fn the_allocator_returns_everything() {
    let gpu = gpu();
    let (report, _) = render(&gpu, &Scene::default(), 64, 48);
    assert_clean(&report, "small render");
    assert!(report.memory.used_bytes > 0 && report.memory.blocks >= 1);
    assert!(
        gpu.allocator.borrow().live_allocations().is_empty(),
        "leaks: {:?}",
        gpu.allocator.borrow().live_allocations()
    );
}

#[test]
fn the_validation_canary_catches_errors() {
    // A deliberately invalid call must reach our counters; otherwise "0 errors" would mean nothing.
    let gpu = gpu();
    let before = gpu.validation_counts().error_total();
    let info = vk::BufferCreateInfo::default().size(0).usage(vk::BufferUsageFlags::UNIFORM_BUFFER);
    // SAFETY: an invalid create info (size 0) on purpose; a returned buffer is destroyed at once.
    if let Ok(buffer) = unsafe { gpu.raw().create_buffer(&info, None) } {
        unsafe { gpu.raw().destroy_buffer(buffer, None) };
    }
    let after = gpu.validation_counts();
    assert!(after.error_total() > before, "size-0 buffer went unreported: {after:?}");
    assert!(after.errors.keys().any(|id| id.contains("VUID-VkBufferCreateInfo-size")), "{after:?}");
}

/// The shading pass gives the top rows to the sky's shader alone only where no sea can be.
#[test]
fn only_rows_no_crest_can_reach_are_left_to_the_sky() {
    use ocean::model::waves;
    use ocean::render::frame;
    let rows = |scene: &Scene| frame::build(scene, &waves::generate(scene), 256, 192, 8.0).sky_rows;
    // Level camera 6 m up: the level ray is the lower edge of row 95, and the highest crests'
    // limb lies 0.07 degrees below it, within row 96 (0.31 degrees a row): rows 0..=95 pass above
    // it, and the last of them is left to the sea's shader.
    assert_eq!(rows(&Scene::default()), 95);
    // Looking up: the whole image rises, and no grid row is drawn: all rows are sky.
    let mut up = Scene::default();
    up.camera.pitch_deg = 45.0;
    assert_eq!(rows(&up), 192);
    // An eye below the highest crest sees sea above the horizon: every row may hold sea.
    let mut low = Scene::default();
    low.camera.height_m = 0.05;
    assert_eq!(rows(&low), 0);
    // Looking down past the field of view: no row rises.
    let mut down = Scene::default();
    down.camera.pitch_deg = -60.0;
    assert_eq!(rows(&down), 0);
}

/// The shading pass leaves the sky's code out only in rows where every ray falls.
#[test]
fn only_rows_whose_rays_all_fall_are_left_to_the_sea() {
    use ocean::model::waves;
    use ocean::render::frame;
    let rows = |scene: &Scene| frame::build(scene, &waves::generate(scene), 256, 192, 8.0).sea_rows;
    // Level camera: the horizon is the lower edge of row 95, so row 96's upper edge is level
    // (not falling); row 97's falls, and one row of margin makes 98 the first.
    assert_eq!(rows(&Scene::default()), 98);
    // An eye below the highest crest changes nothing: falling rays still meet only sea.
    let mut low = Scene::default();
    low.camera.height_m = 0.05;
    assert_eq!(rows(&low), 98);
    // Looking down past the field of view: every row falls, the first after the margin.
    let mut down = Scene::default();
    down.camera.pitch_deg = -60.0;
    assert_eq!(rows(&down), 1);
    // Looking up: no row falls, and no grid is drawn.
    let mut up = Scene::default();
    up.camera.pitch_deg = 45.0;
    assert_eq!(rows(&up), 192);
}

/// The arithmetic floor's parts: a level camera sees sea in the lower half, where each pixel
/// resolves a few dozen of the 60 trains; the device delivers a positive, finite FMA rate.
#[test]
fn the_shading_floor_counts_the_sea_and_the_device_rate() {
    use ocean::measure::floor::{delivered_gflops, shade_work};
    let scene = Scene::default();
    let work = shade_work(&scene, &ocean::model::waves::generate(&scene), 256, 192);
    let half = 256.0 * 192.0 / 2.0;
    assert!((work.sea_pixels - half).abs() < 0.02 * half, "sea pixels {}", work.sea_pixels);
    assert!((10.0..60.0).contains(&work.trains_per_sea_pixel), "{} trains per pixel", work.trains_per_sea_pixel);
    let gflops = delivered_gflops(&gpu(), 1).expect("timestamps");
    assert!(gflops.is_finite() && gflops > 0.1, "{gflops} GFLOP/s");
}

/// A frame keeps what its camera's change leaves valid: turning the eye keeps the sky seen from it
/// (it depends on the eye's height and the sun) and rebuilds the aerial perspective (it follows
/// the camera's rays); raising the eye rebuilds both.
#[test]
fn turning_the_eye_keeps_its_sky_and_rebuilds_its_aerial_perspective() {
    use ocean::render::renderer::{Options, Renderer};
    let gpu = gpu();
    let mut scene = Scene::default();
    let mut renderer = Renderer::new(&gpu, &scene, 64, 48, Options::default()).unwrap();
    renderer.render(&scene).unwrap();
    scene.camera.yaw_deg += 20.0;
    renderer.render(&scene).unwrap();
    let skipped = renderer.skipped_last_frame().to_vec();
    assert!(skipped.contains(&"eye_sky") && !skipped.contains(&"aerial_perspective"), "turned: {skipped:?}");
    scene.camera.height_m *= 2.0;
    renderer.render(&scene).unwrap();
    let skipped = renderer.skipped_last_frame().to_vec();
    assert!(!skipped.contains(&"eye_sky") && !skipped.contains(&"aerial_perspective"), "raised: {skipped:?}");
    drop(renderer);
    assert_eq!(gpu.validation_counts().error_total(), 0, "{:?}", gpu.validation_counts());
}

/// `ocean render` is a host of the library (app::host): its picture is the renderer's own
/// offscreen frame, whether drawn in the host's image in place (the sky on), with the sky left
/// black (a single term), or supersampled, resolved and copied.
#[test]
fn the_commands_host_draws_what_the_renderer_draws() {
    use ocean::app::{render_on, RenderRequest};
    use ocean::embed::{Method, ShaderConfig, Shading, Terms};
    use ocean::render::renderer::{Options, Renderer};
    let gpu = gpu();
    let scene = Scene::default();
    let sun_only = ShaderConfig::terms_only(Terms { sun: true, sky: false, sea: false }, Method::Full);
    for (shader, ssaa) in [(ShaderConfig::default(), 1), (sun_only, 1), (ShaderConfig::default(), 2)] {
        let shading = Shading { shader, ssaa, ..Shading::default() };
        let request =
            RenderRequest { validation: true, shading, specialize: false, ..RenderRequest::new(scene.clone(), 64, 48) };
        let (report, hosted) = render_on(&gpu, &request).unwrap();
        assert_clean(&report, "hosted");
        let own = Renderer::new(&gpu, &scene, 64, 48, Options { shader, ssaa, ..Options::default() })
            .unwrap()
            .render(&scene)
            .unwrap();
        let what = format!("{} terms, ssaa {ssaa}", if shader.background { "all" } else { "sun" });
        for (a, b) in hosted.hdr.iter().zip(&own.hdr) {
            for c in 0..3 {
                // The camera goes through f64 matrices and back: an ulp of a uniform at most.
                assert!((a[c] - b[c]).abs() <= 1e-3 * b[c].abs() + 1e-6, "{what}: {a:?} against {b:?}");
            }
        }
        let levels = hosted.ldr.iter().zip(&own.ldr).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
        assert!(levels <= 1, "{what}: the tone-mapped pictures differ by {levels} levels");
        assert!(hosted.hdr.iter().any(|p| p[0] > 0.0), "{what}: a black picture");
    }
}
