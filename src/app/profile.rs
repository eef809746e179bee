//! `ocean profile`: frames of a scene on a timeline (Chrome Trace Event JSON: the GPU queue's
//! passes nested in their frames, the CPU's steps, GPU ms per frame as a counter) and a report of
//! per-pass statistics, pipeline statistics, and the figures that explain the time: ns per
//! fragment or invocation, the trains the shading pass evaluates per sea pixel (counted by the
//! shader in one extra frame, specialized to count), and the shading pass against its floor.

use crate::app::host::OffscreenHost;
use crate::embed::{Shading, TrainCounts};
use crate::error::{Error, Result};
use crate::measure::floor::{delivered_gflops, shade_work};
use crate::measure::samples::{new_run_id, TimedScene};
use crate::model::scene::Scene;
use crate::output::trace::{Trace, Track};
use crate::render::passes::packets::PacketBinsPass;
use crate::render::renderer::PacketStats;
use crate::render::timeline::{Alignment, CpuSpans, GpuFrame, Span};
use crate::vk::clock::host_now_ns;
use crate::vk::gpu::Gpu;
use crate::vk::profiler::PipelineStatistics;
use serde::Serialize;
use serde_json::{json, Map, Value};
use std::collections::BTreeMap;
use std::path::PathBuf;

pub const CPU_TRACK: Track = Track(1);
pub const GPU_TRACK: Track = Track(2);

#[derive(Debug, Clone)]
pub struct ProfileRequest {
    pub scene: Scene,
    pub scene_name: String,
    pub width: u32,
    pub height: u32,
    /// Frames rendered, the first `warmup` of them untimed (they are in the trace, marked).
    pub frames: u32,
    pub warmup: u32,
    pub trace: Option<PathBuf>,
    pub report: Option<PathBuf>,
    /// The last frame's image (encoding and writing it are CPU spans of the trace).
    pub png: Option<PathBuf>,
    pub shading: Shading,
    pub specialize: bool,
    pub validation: bool,
    pub device: Option<String>,
}

#[derive(Debug, Serialize)]
pub struct PassProfile {
    pub name: String,
    pub median_ms: f64,
    pub fastest_ms: f64,
    pub p90_ms: f64,
    /// The last timed frame's counters (absent where the device has no pipeline statistics).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pipeline_statistics: Option<PipelineStatistics>,
    /// Median time over the fragment-shader invocations (graphics passes) or compute invocations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ns_per_fragment: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ns_per_invocation: Option<f64>,
}

#[derive(Debug, Serialize)]
pub struct Derived {
    /// The shading pass's trains per sea pixel, counted by the shader in one extra frame.
    pub train_counts: Option<TrainCounts>,
    pub trains_evaluated_per_sea_pixel: Option<f64>,
    pub trains_weighted_per_sea_pixel: Option<f64>,
    /// What the device delivers for independent FMAs, the shading pass's unavoidable work at that
    /// rate (measure::floor), and the pass's median over it.
    pub delivered_gflops: Option<f64>,
    pub shade_floor_ms: Option<f64>,
    pub shade_over_floor: Option<f64>,
    /// The frame's wave packets and what they cost (None without local waves).
    pub packets: Option<PacketCost>,
}

/// A frame's wave packets: how many, their cells' lists and the tiles that bin them, the binning's
/// time per packet, per tile and per list entry, and the shading pass's packet terms per sea pixel (what a pixel's cost grows with).
#[derive(Debug, Serialize)]
pub struct PacketCost {
    pub alive: usize,
    pub cells: u32,
    pub entries: usize,
    pub entries_per_packet: f64,
    pub tiles: u32,
    pub tile_entries: usize,
    pub bins_us_per_packet: Option<f64>,
    pub bins_us_per_tile: Option<f64>,
    pub bins_ns_per_entry: Option<f64>,
    pub terms_per_sea_pixel: Option<f64>,
}

impl PacketCost {
    fn new(stats: PacketStats, bins_ms: Option<f64>, counts: Option<TrainCounts>) -> PacketCost {
        let per = |n: usize| bins_ms.filter(|_| n > 0).map(|ms| ms * 1e6 / n as f64);
        PacketCost {
            alive: stats.alive,
            cells: stats.cells,
            entries: stats.entries,
            entries_per_packet: stats.entries as f64 / stats.alive.max(1) as f64,
            tiles: stats.tiles,
            tile_entries: stats.tile_entries,
            bins_us_per_packet: per(stats.alive).map(|ns| ns * 1e-3),
            bins_us_per_tile: per(stats.tiles as usize).map(|ns| ns * 1e-3),
            bins_ns_per_entry: per(stats.entries),
            terms_per_sea_pixel: counts.map(|c| c.packet_terms_per_sea_pixel()),
        }
    }
}

#[derive(Debug, Serialize)]
pub struct ProfileReport {
    pub device: String,
    pub run_id: String,
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub warmup: u32,
    pub timestamp_period_ns: f32,
    pub timestamp_valid_bits: u32,
    /// How the GPU spans were put on the CPU's clock.
    pub clock: String,
    pub pipelines: Vec<String>,
    pub passes: Vec<PassProfile>,
    pub total: PassProfile,
    pub derived: Derived,
    /// What was left out, with why (a device without statistics or calibration, ...).
    pub notes: Vec<String>,
    pub validation: bool,
    pub validation_errors: u32,
    /// Every timed frame (`bench compare` reads these).
    pub timings: Vec<TimedScene>,
}

/// Checks the arguments before any GPU work.
pub fn check(request: &ProfileRequest) -> Result<()> {
    if request.frames == 0 {
        return Err(Error::Argument("--frames 0: profile at least one frame".into()));
    }
    if request.warmup >= request.frames {
        return Err(Error::Argument(format!(
            "--warmup {} must be less than --frames {}: no frame would be timed",
            request.warmup, request.frames
        )));
    }
    for path in [&request.trace, &request.report, &request.png].into_iter().flatten() {
        crate::output::target::check_writable(path)?;
    }
    Ok(())
}

/// Profiles on a new context (its creation is the trace's first span); bad arguments are refused
/// before the context is made.
pub fn profile(request: &ProfileRequest) -> Result<ProfileReport> {
    check(request)?;
    let origin = host_now_ns();
    let mut setup = CpuSpans::default();
    let gpu = setup.time("Vulkan instance and device", || Gpu::new(request.validation, request.device.as_deref()))?;
    profile_checked(&gpu, request, setup, origin)
}

/// Profiles on an existing context (tests share one); `setup`: spans already spent, from `origin`
/// on the host clock (the trace's time 0).
pub fn profile_on(gpu: &Gpu, request: &ProfileRequest, setup: CpuSpans, origin: u64) -> Result<ProfileReport> {
    check(request)?;
    profile_checked(gpu, request, setup, origin)
}

fn profile_checked(gpu: &Gpu, request: &ProfileRequest, mut setup: CpuSpans, origin: u64) -> Result<ProfileReport> {
    let before = gpu.validation_counts();
    let scene = &request.scene;
    let (width, height) = (request.width, request.height);
    let wave_set = setup.time("scene and waves", || crate::model::waves::generate(scene));
    let mut shading = super::shading(&request.shading, request.specialize);
    shading.statistics = true;
    let mut notes = Vec::new();
    if !gpu.device.pipeline_statistics {
        notes.push(format!("{} has no pipeline statistics queries: left out", gpu.device.name));
    }
    let mut trace = Trace::new("ocean", origin as f64);
    trace.track(CPU_TRACK, "CPU main thread", 0);
    trace.track(GPU_TRACK, &format!("GPU queue ({})", gpu.device.name), 1);
    let mut timed = TimedScene::new(&request.scene_name, scene, width, height, "default");
    let mut last_stats: BTreeMap<String, PipelineStatistics> = BTreeMap::new();
    let mut alignment = Alignment::NoTimestamps;
    let mut gflops = None;
    let pipelines = {
        let mut host =
            setup.time("pipelines and resources", || OffscreenHost::new(gpu, scene, width, height, shading))?;
        // The device's delivered rate, measured before the frames (as `bench speed` does), where
        // the specialized frame shades anything.
        if !host.ocean().shader().draws_nothing() {
            gflops = Some(delivered_gflops(gpu, 3)?);
        }
        for span in &setup.spans {
            trace.span(CPU_TRACK, &span.name, "setup", span.begin_ns, span.end_ns, Map::new());
        }
        let mut frame = None;
        for i in 0..request.frames {
            let rendered = host.render(scene)?;
            let warmup = i < request.warmup;
            let gpu_frame = host.gpu_frame().cloned();
            add_frame(&mut trace, i, warmup, &host.cpu_spans().spans, gpu_frame.as_ref());
            if let Some(f) = &gpu_frame {
                alignment = f.alignment;
                if !warmup {
                    last_stats = f.passes.iter().filter_map(|p| p.statistics.map(|s| (p.name.to_owned(), s))).collect();
                }
            }
            if !warmup {
                timed.push(0, &rendered.pass_ms);
            }
            frame = Some(rendered);
        }
        if let (Some(frame), Some(path)) = (frame, &request.png) {
            let mut files = CpuSpans::default();
            let encoded =
                files.time("encode PNG", || crate::output::encode_png(frame.width, frame.height, &frame.ldr))?;
            files.time("write PNG", || crate::output::target::write(path, &encoded))?;
            for span in &files.spans {
                trace.span(CPU_TRACK, &span.name, "files", span.begin_ns, span.end_ns, Map::new());
            }
        }
        host.ocean().pipelines()
    };
    if alignment == Alignment::NoTimestamps {
        notes.push(format!("{}: {}", gpu.device.name, alignment.describe()));
    }
    // One more frame, specialized to count the trains the shading pass evaluates.
    let (counts, packet_stats) = count_trains(gpu, scene, width, height, shading)?;
    let passes: Vec<PassProfile> = timed
        .frames_ms
        .iter()
        .filter(|(name, _)| *name != "total")
        .map(|(name, samples)| pass_profile(name, samples, last_stats.get(name).copied()))
        .collect();
    let total = pass_profile("total", &timed.frames_ms["total"], None);
    let median = |name: &str| passes.iter().find(|p| p.name == name).map(|p| p.median_ms);
    let shade_median = median("shade");
    let floor_ms = gflops.map(|g| shade_work(scene, &wave_set, width, height).gflop / g * 1e3);
    let derived = Derived {
        train_counts: counts,
        trains_evaluated_per_sea_pixel: counts.map(|c| c.evaluated_per_sea_pixel()),
        trains_weighted_per_sea_pixel: counts.map(|c| c.weighted_per_sea_pixel()),
        delivered_gflops: gflops,
        shade_floor_ms: floor_ms,
        shade_over_floor: shade_median.zip(floor_ms).filter(|(_, f)| *f > 0.0).map(|(s, f)| s / f),
        packets: packet_stats.map(|p| PacketCost::new(p, median(PacketBinsPass::NAME), counts)),
    };
    trace.note("clock", json!(alignment.describe()));
    trace.note("device", json!(gpu.device.name));
    trace.note("scene", json!(request.scene_name));
    trace.note("size", json!(format!("{width}x{height}")));
    trace.note("notes", json!(notes));
    let report = ProfileReport {
        device: gpu.device.name.clone(),
        run_id: new_run_id(),
        scene: request.scene_name.clone(),
        width,
        height,
        frames: request.frames,
        warmup: request.warmup,
        timestamp_period_ns: gpu.device.properties.limits.timestamp_period,
        timestamp_valid_bits: gpu.device.timestamp_valid_bits,
        clock: alignment.describe(),
        pipelines,
        passes,
        total,
        derived,
        notes,
        validation: request.validation,
        validation_errors: gpu.validation_counts().error_total() - before.error_total(),
        timings: vec![timed],
    };
    if let Some(path) = &request.trace {
        crate::output::write_text(path, &trace.to_json())?;
    }
    if let Some(path) = &request.report {
        crate::output::write_text(path, &serde_json::to_string_pretty(&report).expect("report serializes"))?;
    }
    Ok(report)
}

/// A frame's spans: on the CPU track the frame around its steps, on the GPU track the frame
/// around its passes (with their statistics as arguments), and the frame's GPU time as a counter.
pub fn add_frame(trace: &mut Trace, index: u32, warmup: bool, cpu: &[Span], gpu: Option<&GpuFrame>) {
    let name = format!("frame {index}");
    let args = |extra: Map<String, Value>| {
        let mut m = Map::new();
        m.insert("frame".into(), json!(index));
        m.insert("warmup".into(), json!(warmup));
        m.extend(extra);
        m
    };
    if let (Some(first), Some(last)) = (cpu.first(), cpu.last()) {
        trace.span(CPU_TRACK, &name, "frame", first.begin_ns, last.end_ns, args(Map::new()));
        for s in cpu {
            trace.span(CPU_TRACK, &s.name, "cpu", s.begin_ns, s.end_ns, args(Map::new()));
        }
    }
    let Some(gpu) = gpu.filter(|g| !g.passes.is_empty()) else { return };
    let begin = gpu.passes.iter().map(|p| p.begin_ns).fold(f64::INFINITY, f64::min);
    let end = gpu.passes.iter().map(|p| p.end_ns).fold(f64::NEG_INFINITY, f64::max);
    let total_ms: f64 = gpu.passes.iter().map(|p| p.ms()).sum();
    let mut frame_args = Map::new();
    frame_args.insert("gpu_ms".into(), json!(total_ms));
    frame_args
        .insert("submit_to_fence_ms".into(), json!((gpu.fence_ns as f64 - gpu.submission.submit_ns as f64) * 1e-6));
    trace.span(GPU_TRACK, &name, "frame", begin, end, args(frame_args));
    for p in &gpu.passes {
        let mut extra = Map::new();
        extra.insert("ms".into(), json!(p.ms()));
        if let Some(stats) = &p.statistics {
            extra.insert("pipeline_statistics".into(), serde_json::to_value(stats).expect("serializes"));
        }
        trace.span(GPU_TRACK, p.name, "gpu", p.begin_ns, p.end_ns, args(extra));
    }
    trace.counter("GPU ms per frame", begin, &[("ms", total_ms)]);
}

fn pass_profile(name: &str, samples: &[f64], stats: Option<PipelineStatistics>) -> PassProfile {
    let mut sorted = samples.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = crate::app::median(&sorted);
    let p90 = sorted[((0.9 * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1)];
    let per = |count: u64| (count > 0).then(|| median * 1e6 / count as f64);
    PassProfile {
        name: name.to_owned(),
        median_ms: median,
        fastest_ms: sorted[0],
        p90_ms: p90,
        pipeline_statistics: stats,
        ns_per_fragment: stats.and_then(|s| per(s.fragment_shader_invocations)),
        ns_per_invocation: stats.and_then(|s| per(s.compute_shader_invocations)),
    }
}

/// One frame with the shading pass specialized to count (no counts when nothing is shaded), and
/// its wave packets (None without local waves).
fn count_trains(
    gpu: &Gpu,
    scene: &Scene,
    width: u32,
    height: u32,
    mut shading: Shading,
) -> Result<(Option<TrainCounts>, Option<PacketStats>)> {
    shading.shader.count_trains = !shading.shader.draws_nothing();
    shading.statistics = false;
    let mut host = OffscreenHost::new(gpu, scene, width, height, shading)?;
    host.render(scene)?;
    let counts = if shading.shader.count_trains { host.ocean().train_counts()? } else { None };
    Ok((counts, host.ocean().packet_stats()))
}
