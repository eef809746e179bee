//! Image sequences for offline use (`ocean animate`): frame i of a sequence at F frames per second
//! is the scene at time_s + i / F, rendered by one renderer (the sky map is built once) and
//! written as DIR/frame_00000.png (and .exr). Every file is written atomically, so a frame that
//! exists is whole: an interrupted run resumes where it stopped.

use crate::app::host::OffscreenHost;
use crate::embed::Shading;
use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::output::progress::Progress;
use crate::output::{self, write_text};
use crate::vk::gpu::Gpu;
use std::path::{Path, PathBuf};

/// Most frames one sequence may have (an hour at 60 fps would be 216,000).
pub const MAX_FRAMES: u64 = 1_000_000;

#[derive(Debug, Clone)]
pub struct AnimateRequest {
    pub scene: Scene,
    pub seconds: f64,
    pub fps: f64,
    pub width: u32,
    pub height: u32,
    pub out_dir: PathBuf,
    pub exr: bool,
    /// Render frames whose files exist too.
    pub force: bool,
    pub shading: Shading,
    pub specialize: bool,
}

/// What a run did, also written to DIR/animation.json.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AnimateReport {
    pub device: String,
    pub frames: u64,
    pub rendered: u64,
    /// Frames whose files were already there.
    pub skipped: u64,
    pub fps: f64,
    pub first_time_s: f64,
    pub width: u32,
    pub height: u32,
    /// Median GPU time of the rendered frames after the first (ms; none with fewer than two).
    pub gpu_ms_median: Option<f64>,
    pub nonfinite_pixels: u64,
    pub validation_errors: u32,
}

/// Number of frames of `seconds` at `fps`: round(seconds fps), at least one; Err names the bad value.
pub fn frame_count(seconds: f64, fps: f64) -> Result<u64> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(Error::Argument(format!("--seconds {seconds} must be a positive number")));
    }
    if !(fps.is_finite() && fps > 0.0 && fps <= 1000.0) {
        return Err(Error::Argument(format!("--fps {fps} is out of range (0, 1000]")));
    }
    let frames = (seconds * fps).round().max(1.0);
    if frames > MAX_FRAMES as f64 {
        return Err(Error::Argument(format!(
            "--seconds {seconds} at --fps {fps} is {frames} frames, more than {MAX_FRAMES}"
        )));
    }
    Ok(frames as u64)
}

/// `DIR/frame_00042.EXT` (five digits, more past 99,999).
pub fn frame_path(dir: &Path, index: u64, extension: &str) -> PathBuf {
    dir.join(format!("frame_{index:05}.{extension}"))
}

pub fn animate(gpu: &Gpu, request: &AnimateRequest) -> Result<AnimateReport> {
    let frames = frame_count(request.seconds, request.fps)?;
    let dir = &request.out_dir;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let before = gpu.validation_counts().error_total();
    let mut scene = request.scene.clone();
    let start = scene.render.time_s;
    // Specialized for the first frame's scene: the camera does not move, only the waves.
    let shading = super::shading(&request.shading, request.specialize);
    let mut host = OffscreenHost::new(gpu, &scene, request.width, request.height, shading)?;
    // Frames already written are whole (written atomically): only the others are rendered, and
    // the progress and its time left count only those.
    let wanted = |i: u64| {
        let exr_done = !request.exr || frame_path(dir, i, "exr").is_file();
        request.force || !(frame_path(dir, i, "png").is_file() && exr_done)
    };
    let todo: Vec<u64> = (0..frames).filter(|&i| wanted(i)).collect();
    let label = format!("animate {} ({} of {frames} frames to render)", dir.display(), todo.len());
    let mut progress = Progress::new(&label, todo.len() as u64, "frames", true);
    let mut nonfinite = 0;
    let mut gpu_ms = Vec::new();
    for (done, &i) in todo.iter().enumerate() {
        // Time from the index, not by accumulating steps: frame i is exact however long the run.
        scene.render.time_s = start + i as f64 / request.fps;
        let frame = host.render(&scene)?;
        nonfinite += output::stats(&frame.hdr).nonfinite_pixels;
        if done > 0 {
            gpu_ms.push(frame.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>());
        }
        output::write_png(&frame_path(dir, i, "png"), frame.width, frame.height, &frame.ldr)?;
        if request.exr {
            output::write_exr(&frame_path(dir, i, "exr"), frame.width, frame.height, &frame.hdr)?;
        }
        progress.set(done as u64 + 1, None);
    }
    drop(host);
    gpu_ms.sort_by(f64::total_cmp);
    let report = AnimateReport {
        device: gpu.device.name.clone(),
        frames,
        rendered: todo.len() as u64,
        skipped: frames - todo.len() as u64,
        fps: request.fps,
        first_time_s: start,
        width: request.width,
        height: request.height,
        gpu_ms_median: (!gpu_ms.is_empty()).then(|| super::median(&gpu_ms)),
        nonfinite_pixels: nonfinite,
        validation_errors: gpu.validation_counts().error_total() - before,
    };
    let json = serde_json::to_string_pretty(&report).expect("report serializes");
    write_text(&dir.join("animation.json"), &json)?;
    Ok(report)
}
