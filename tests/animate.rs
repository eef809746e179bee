//! Image sequences: frame i is the scene at time_s + i / fps, the same picture `render` makes at
//! that time; an interrupted sequence resumes; bad lengths and rates are one clear line.

mod common;

use ocean::app::animate::{animate, frame_count, frame_path, AnimateRequest};
use ocean::app::{render_on, RenderRequest};
use ocean::embed::Shading;
use ocean::model::scene::Scene;
use std::path::Path;

fn request(dir: &Path, force: bool) -> AnimateRequest {
    let mut scene = Scene::default();
    scene.render.time_s = 2.0;
    AnimateRequest {
        scene,
        seconds: 0.3,
        fps: 10.0,
        width: 48,
        height: 36,
        out_dir: dir.to_owned(),
        exr: false,
        force,
        shading: Shading::default(),
        specialize: true,
    }
}

fn rgb(path: &Path) -> Vec<u8> {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgb8().into_raw()
}

#[test]
fn frames_are_the_scene_at_their_times_and_a_sequence_resumes() {
    let gpu = common::gpu();
    let dir = std::env::temp_dir().join(format!("ocean-animate-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let first = animate(&gpu, &request(&dir, false)).unwrap();
    assert_eq!((first.frames, first.rendered, first.skipped), (3, 3, 0));
    assert_eq!((first.validation_errors, first.nonfinite_pixels), (0, 0));
    // Frame 2 is the scene at 2.0 + 2 / 10 s, as `ocean render` makes it.
    let mut at = request(&dir, false).scene;
    at.render.time_s = 2.2;
    let (report, still) =
        render_on(&gpu, &RenderRequest { validation: true, ..RenderRequest::new(at, 48, 36) }).unwrap();
    common::assert_clean(&report, "render at 2.2 s");
    let still_rgb: Vec<u8> = still.ldr.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let frame2 = rgb(&frame_path(&dir, 2, "png"));
    let differing = frame2.iter().zip(&still_rgb).filter(|(a, b)| a.abs_diff(**b) > 1).count();
    assert_eq!(differing, 0, "frame 2 against `render` at its time: {differing} channels differ by more than 1");
    // The sea moves between frames.
    let frame0 = rgb(&frame_path(&dir, 0, "png"));
    let moved = frame0.iter().zip(&frame2).filter(|(a, b)| a.abs_diff(**b) > 8).count();
    assert!(moved > frame0.len() / 50, "frames 0 and 2 should differ: {moved} channels");
    // Interrupted after frame 0 and 2: only frame 1 is rendered again, the others are left alone.
    std::fs::remove_file(frame_path(&dir, 1, "png")).unwrap();
    let kept = std::fs::metadata(frame_path(&dir, 0, "png")).unwrap().modified().unwrap();
    let resumed = animate(&gpu, &request(&dir, false)).unwrap();
    assert_eq!((resumed.rendered, resumed.skipped), (1, 2));
    assert_eq!(std::fs::metadata(frame_path(&dir, 0, "png")).unwrap().modified().unwrap(), kept);
    assert!(frame_path(&dir, 1, "png").is_file());
    // --force renders everything; --exr adds the radiance beside each frame.
    let forced = animate(&gpu, &AnimateRequest { exr: true, ..request(&dir, true) }).unwrap();
    assert_eq!((forced.rendered, forced.skipped), (3, 0));
    assert!((0..3).all(|i| frame_path(&dir, i, "exr").is_file()));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("animation.json")).unwrap()).unwrap();
    assert_eq!(json["frames"], 3);
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.contains("partial")), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn lengths_and_rates_are_checked() {
    assert_eq!(frame_count(0.5, 10.0).unwrap(), 5);
    assert_eq!(frame_count(1.0, 29.97).unwrap(), 30);
    assert_eq!(frame_count(0.001, 10.0).unwrap(), 1, "at least one frame");
    for (seconds, fps, key) in [
        (0.0, 30.0, "--seconds"),
        (-1.0, 30.0, "--seconds"),
        (f64::NAN, 30.0, "--seconds"),
        (f64::INFINITY, 30.0, "--seconds"),
        (1.0, 0.0, "--fps"),
        (1.0, 5000.0, "--fps"),
        (1.0, f64::NAN, "--fps"),
        (1e9, 30.0, "frames"),
    ] {
        let e = frame_count(seconds, fps).unwrap_err().to_string();
        assert!(e.contains(key) && !e.contains('\n'), "{seconds} s at {fps} fps: {e}");
    }
    assert_eq!(frame_path(Path::new("d"), 42, "png"), Path::new("d/frame_00042.png"));
    assert_eq!(frame_path(Path::new("d"), 123_456, "exr"), Path::new("d/frame_123456.exr"));
}
