//! The applications on top of the library: what the commands do, each a host of `embed::Ocean`
//! with nothing private into the renderer. One render from a scene to files and a report
//! (`ocean render`), image sequences (`ocean animate`, in `animate`), frames on a timeline
//! (`ocean profile`, in `profile`), all through the offscreen host (`host`); the window of
//! `ocean view` (`window`), its own host.

pub mod animate;
pub mod host;
pub mod objects;
pub mod profile;
pub mod report;
pub mod window;

use crate::app::host::OffscreenHost;
use crate::app::report::{GridReport, Report, ShadowMapReport, WaveReport};
use crate::embed::Shading;
use crate::error::Result;
use crate::model::scene::Scene;
use crate::output;
use crate::render::passes::shadow::ShadowPass;
use crate::render::renderer::RenderedFrame;
use crate::vk::gpu::Gpu;
use std::collections::BTreeMap;
use std::path::PathBuf;

#[derive(Debug, Clone)]
pub struct RenderRequest {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub png: Option<PathBuf>,
    pub exr: Option<PathBuf>,
    pub report: Option<PathBuf>,
    pub validation: bool,
    pub device: Option<String>,
    /// Frames to render; with more than one, `gpu_ms` is the per-pass median of all frames after
    /// the first (which pays the driver's lazy shader compilation), `gpu_ms_min` the fastest.
    pub frames: u32,
    /// How the ocean shades (its `specialize_for_scene_camera` is `specialize`'s).
    pub shading: Shading,
    /// Leave out what the scene does not need (specialize::plan); false renders with the
    /// general pipeline, for comparison.
    pub specialize: bool,
}

impl RenderRequest {
    /// One frame of `scene`, written nowhere, without validation, with what the scene needs only.
    pub fn new(scene: Scene, width: u32, height: u32) -> RenderRequest {
        RenderRequest {
            scene,
            width,
            height,
            png: None,
            exr: None,
            report: None,
            validation: false,
            device: None,
            frames: 1,
            shading: Shading::default(),
            specialize: true,
        }
    }
}

/// Renders on a new GPU context and writes the requested files.
pub fn render(request: &RenderRequest) -> Result<(Report, RenderedFrame)> {
    let gpu = Gpu::new(request.validation, request.device.as_deref())?;
    let (report, frame) = render_on(&gpu, request)?;
    Ok((report, frame))
}

/// How the ocean shades for the commands' flags, specialized for the scene's camera where asked
/// (the commands' cameras do not move).
pub fn shading(shading: &Shading, specialize: bool) -> Shading {
    Shading { specialize_for_scene_camera: specialize, ..*shading }
}

/// Renders on an existing context (tests share one), through the ocean library as any host would
/// (host::OffscreenHost).
pub fn render_on(gpu: &Gpu, request: &RenderRequest) -> Result<(Report, RenderedFrame)> {
    let scene = &request.scene;
    let before = gpu.validation_counts();
    let wave_set = crate::model::waves::generate(scene);
    let shading = shading(&request.shading, request.specialize);
    let (frame, memory, fastest, timings, statistics, shadows, omitted, pipelines) = {
        let mut host = OffscreenHost::new(gpu, scene, request.width, request.height, shading)?;
        let mut frame = host.render(scene)?;
        let mut timings = Vec::new();
        for _ in 1..request.frames {
            frame = host.render(scene)?;
            timings.push(frame.pass_ms.clone());
        }
        let fastest = pass_statistic(&timings, minimum);
        if !timings.is_empty() {
            frame.pass_ms = pass_statistic(&timings, median);
        }
        let ocean = host.ocean();
        let mut omitted = ocean.omitted().to_vec();
        if request.frames > 1 {
            for pass in ocean.skipped_last_frame() {
                omitted.push(crate::render::specialize::Omission {
                    what: format!("{pass} in frames 2 to {}", request.frames),
                    why: "its result was still current: the sun, the sky and the view did not change".into(),
                });
            }
        }
        let statistics = host.gpu_frame().filter(|_| shading.statistics).map(|f| {
            f.passes.iter().filter_map(|p| p.statistics.map(|s| (p.name.to_owned(), s))).collect::<BTreeMap<_, _>>()
        });
        let shadows = ocean.pass_names().contains(&ShadowPass::NAME);
        (frame, ocean.memory(), fastest, timings, statistics, shadows, omitted, ocean.pipelines())
    };
    let mut gpu_ms_frames: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for frame_ms in &timings {
        for (pass, ms) in frame_ms {
            gpu_ms_frames.entry(pass.clone()).or_default().push(*ms);
        }
    }
    let statistics_note = match (&statistics, shading.statistics) {
        (_, false) => None,
        (Some(map), true) if !map.is_empty() => None,
        _ => Some(format!("{} has no pipeline statistics queries: none reported", gpu.device.name)),
    };
    if let Some(note) = &statistics_note {
        crate::say!("{note}");
    }
    let after = gpu.validation_counts();
    let stats = output::stats(&frame.hdr);
    let mut messages = after.errors.clone();
    messages.extend(after.warnings.clone());
    let report = Report {
        device: gpu.device.name.clone(),
        width: request.width,
        height: request.height,
        method: request.shading.shader.method,
        ssaa: request.shading.ssaa,
        gpu_ms: Report::gpu_total_ms(&frame.pass_ms),
        gpu_ms_min: Report::gpu_total_ms(&fastest),
        gpu_ms_frames,
        pipeline_statistics: statistics.filter(|m| !m.is_empty()),
        validation: request.validation,
        validation_errors: after.error_total() - before.error_total(),
        validation_warnings: after.warning_total() - before.warning_total(),
        validation_messages: messages,
        nonfinite_pixels: stats.nonfinite_pixels,
        mean_radiance: stats.mean_radiance,
        memory,
        pipeline_cache: gpu.device.pipeline_cache.report.clone(),
        eye_height_m: frame.frame.camera.eye_height,
        omitted,
        pipelines,
        planar_cover_share: frame.planar_cover_share,
        packets: frame.packets,
        grid: GridReport {
            columns: frame.frame.grid.columns,
            rows: frame.frame.grid.rows,
            cell_px: scene.render.grid_cell_px,
        },
        shadow_map: frame
            .frame
            .sun_view
            .filter(|_| shadows)
            .map(|s| ShadowMapReport { size: scene.render.shadow_map_size, texel_m: s.texel_m }),
        waves: WaveReport {
            count: wave_set.trains.len(),
            sigma2_along_wind: wave_set.sigma2[0],
            sigma2_across_wind: wave_set.sigma2[1],
            mean_height_offset_m: wave_set.mean_height_offset,
        },
    };
    if let Some(path) = &request.png {
        output::write_png(path, frame.width, frame.height, &frame.ldr)?;
    }
    if let Some(path) = &request.exr {
        output::write_exr(path, frame.width, frame.height, &frame.hdr)?;
    }
    if let Some(path) = &request.report {
        let json = serde_json::to_string_pretty(&report).expect("report serializes");
        output::write_text(path, &json)?;
    }
    Ok((report, frame))
}

/// Per-pass statistic over frames (every frame lists the same passes in the same order):
/// `pick` chooses from the sorted values of one pass.
pub fn pass_statistic(frames: &[Vec<(String, f64)>], pick: fn(&[f64]) -> f64) -> Vec<(String, f64)> {
    let Some(first) = frames.first() else { return Vec::new() };
    (0..first.len())
        .map(|i| {
            let mut values: Vec<f64> = frames.iter().map(|f| f[i].1).collect();
            values.sort_by(f64::total_cmp);
            (first[i].0.clone(), pick(&values))
        })
        .collect()
}

pub fn median(sorted: &[f64]) -> f64 {
    let mid = sorted.len() / 2;
    if sorted.len() % 2 == 1 {
        sorted[mid]
    } else {
        0.5 * (sorted[mid - 1] + sorted[mid])
    }
}

pub fn minimum(sorted: &[f64]) -> f64 {
    sorted[0]
}
