//! What a host with objects pays through `ocean::embed` against `ocean render`'s frame, itself a
//! host without objects (app::host): the same scene and size, one frame of each in turn in one
//! run, each after its warm-up. The embedded frame is a host's with its own HDR colour, depth and
//! LDR images (made on the host's side of the same device), cleared, then the ocean composited,
//! depth-tested, and tone-mapped into them. Its GPU time is the ocean's passes (the host's clear
//! and transitions are the host's); `render`'s is the ocean's passes and its host's readback.

use crate::app::host::OffscreenHost;
use crate::app::median;
use crate::embed::camera::scene_view;
use crate::embed::Shading;
use crate::embed::{
    clear_targets, transition, FrameInput, HostDevice, HostEnabled, HostFormats, HostImage, ImageState, Ocean,
    OceanDesc, Targets,
};
use crate::error::Result;
use crate::model::scene::Scene;
use crate::output::write_text;
use crate::vk::commands::Commands;
use crate::vk::device::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use ash::vk;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The LDR format the embedded frame is tone-mapped into (the shader encodes sRGB, as `render`'s).
const LDR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

#[derive(Debug, Serialize)]
pub struct EmbedTiming {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    /// Median GPU ms per pass, and of the frame's sum, of each way.
    pub render_ms: BTreeMap<String, f64>,
    pub embedded_ms: BTreeMap<String, f64>,
    /// Median and quartiles of the frame-by-frame ratio embedded / render.
    pub ratio: [f64; 3],
}

/// The host's images for one frame, on the host's side of the device.
struct HostTargets<'g> {
    colour: Image<'g>,
    depth: Image<'g>,
    ldr: Image<'g>,
}

/// Times `frames` frames of each way after a warm-up, interleaved; writes embed.md and embed.json.
pub fn run(
    gpu: &Gpu,
    scene: &Scene,
    name: &str,
    width: u32,
    height: u32,
    frames: u32,
    out_dir: &Path,
) -> Result<EmbedTiming> {
    // The host's side: the ocean borrows the same instance and device, as a host's.
    let host = HostDevice {
        entry: &gpu.instance.entry,
        instance: &gpu.instance.raw,
        physical_device: gpu.device.physical,
        device: &gpu.device.raw,
        queue_family: gpu.device.queue_family,
        queue: gpu.device.queue,
        enabled: HostEnabled {
            synchronization2: true,
            dynamic_rendering: true,
            sampler_anisotropy: gpu.device.anisotropy,
            pipeline_statistics_query: false,
            calibrated_timestamps: false,
        },
        debug_utils: gpu.instance.debug_utils.is_some(),
    };
    let borrowed = Gpu::from_host(&host, None)?;
    let extent = vk::Extent2D { width, height };
    use vk::ImageUsageFlags as U;
    let targets = HostTargets {
        colour: Image::new(gpu, "host colour", HDR_FORMAT, extent, 1, U::COLOR_ATTACHMENT | U::SAMPLED)?,
        // Sampled too: the ocean's reflections of the host's objects read it.
        depth: Image::new(gpu, "host depth", DEPTH_FORMAT, extent, 1, U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED)?,
        ldr: Image::new(gpu, "host ldr", LDR_FORMAT, extent, 1, U::COLOR_ATTACHMENT)?,
    };
    let desc = OceanDesc {
        scene: scene.clone(),
        width,
        height,
        formats: HostFormats { colour: HDR_FORMAT, depth: Some(DEPTH_FORMAT), reversed_z: true, ldr: Some(LDR_FORMAT) },
        frames_in_flight: 1,
        sky: true,
        radiance_scale: 1.0,
        shading: Default::default(),
        in_place: None,
        shadow_casters: false,
    };
    let mut ocean = Ocean::new(&borrowed, desc)?;
    let mut render = OffscreenHost::new(gpu, scene, width, height, Shading::default())?;
    let commands = Commands::new(&gpu.device, "host frame")?;
    let (view, projection) = scene_view(scene, width as f64 / height as f64, true);
    let input = FrameInput { time_s: scene.render.time_s, view, projection };
    let mut render_frames = Vec::new();
    let mut embedded_frames = Vec::new();
    // An embedded frame's times are read at its slot's next update: the times a frame returns
    // are the frame before's, so the loop runs one frame further and drops the warm-up's.
    for frame in 0..=frames + 1 {
        let rendered = (frame <= frames).then(|| render.render(scene)).transpose()?;
        let previous = embedded_frame(gpu, &commands, &mut ocean, &targets, &input, frame > frames)?;
        if let Some(rendered) = rendered.filter(|_| frame > 0) {
            render_frames.push(rendered.pass_ms);
        }
        if frame > 1 {
            embedded_frames.push(previous);
        }
    }
    drop(ocean);
    drop(borrowed);
    let per_pass = |frames: &[Vec<(String, f64)>]| {
        let mut passes: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        for f in frames {
            for (name, ms) in f {
                passes.entry(name.clone()).or_default().push(*ms);
            }
            passes.entry("frame".into()).or_default().push(f.iter().map(|(_, ms)| ms).sum());
        }
        passes
            .into_iter()
            .map(|(name, mut v)| {
                v.sort_by(f64::total_cmp);
                (name, median(&v))
            })
            .collect::<BTreeMap<_, _>>()
    };
    let total = |f: &Vec<(String, f64)>| f.iter().map(|(_, ms)| ms).sum::<f64>();
    let mut ratios: Vec<f64> = render_frames.iter().zip(&embedded_frames).map(|(r, e)| total(e) / total(r)).collect();
    ratios.sort_by(f64::total_cmp);
    let quartile = |q: f64| ratios[((ratios.len() - 1) as f64 * q).round() as usize];
    let timing = EmbedTiming {
        scene: name.to_owned(),
        width,
        height,
        frames,
        render_ms: per_pass(&render_frames),
        embedded_ms: per_pass(&embedded_frames),
        ratio: [quartile(0.25), median(&ratios), quartile(0.75)],
    };
    std::fs::create_dir_all(out_dir).map_err(|e| crate::error::Error::io(out_dir, e))?;
    write_text(&out_dir.join("embed.json"), &serde_json::to_string_pretty(&timing).expect("serializes"))?;
    write_text(&out_dir.join("embed.md"), &markdown(&timing, &gpu.device.name))?;
    Ok(timing)
}

/// One host frame: the ocean updated (which reads the frame before's pass times, returned),
/// then unless `times_only`, the host's images to attachments and cleared, the ocean recorded,
/// submitted and waited for.
fn embedded_frame(
    gpu: &Gpu,
    commands: &Commands,
    ocean: &mut Ocean,
    targets: &HostTargets,
    input: &FrameInput,
    times_only: bool,
) -> Result<Vec<(String, f64)>> {
    ocean.update(0, input)?;
    let previous = ocean.pass_ms().iter().map(|&(n, ms)| (n.to_owned(), ms)).collect();
    if times_only {
        return Ok(previous);
    }
    commands.begin()?;
    let cmd = commands.cmd;
    let (colour, depth, ldr) =
        (HostImage::from(&targets.colour), HostImage::from(&targets.depth), HostImage::from(&targets.ldr));
    let undefined = |stage| ImageState::new(vk::ImageLayout::UNDEFINED, stage, vk::AccessFlags2::NONE);
    transition(
        &gpu.device.raw,
        cmd,
        &[
            (colour, undefined(vk::PipelineStageFlags2::FRAGMENT_SHADER), ImageState::COLOR_ATTACHMENT),
            (depth, undefined(ImageState::DEPTH_ATTACHMENT.stage), ImageState::DEPTH_ATTACHMENT),
        ],
    );
    clear_targets(&gpu.device.raw, cmd, &colour, &depth, 0.0);
    let ldr_entry = undefined(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT);
    let t = Targets {
        colour,
        colour_entry: ImageState::COLOR_ATTACHMENT,
        depth: Some((depth, ImageState::DEPTH_ATTACHMENT)),
        ldr: Some((ldr, ldr_entry)),
    };
    ocean.record(cmd, 0, &t)?;
    commands.submit_and_wait()?;
    Ok(previous)
}

fn markdown(t: &EmbedTiming, device: &str) -> String {
    let mut md = format!(
        "`ocean bench embed`: {} at {}x{} on {device}, {} frames of each after a warm-up, interleaved. \
         GPU ms per pass (median); `render` is `ocean render`'s frame (a host without objects: drawn \
         in its colour image in place, tone-mapped into its LDR image, both read back), `embedded` \
         a host's with objects (composited into its colour and depth, depth-tested, tone-mapped).\n\n\
         | pass | render | embedded |\n|---|---|---|\n",
        t.scene, t.width, t.height, t.frames
    );
    let names: std::collections::BTreeSet<&String> = t.render_ms.keys().chain(t.embedded_ms.keys()).collect();
    for name in names.into_iter().filter(|n| *n != "frame") {
        let cell = |m: &BTreeMap<String, f64>| m.get(name).map_or("—".to_owned(), |v| format!("{v:.2}"));
        md += &format!("| {name} | {} | {} |\n", cell(&t.render_ms), cell(&t.embedded_ms));
    }
    md += &format!(
        "| **frame** | **{:.1}** | **{:.1}** |\n\nEmbedded over render, frame by frame: median {:.3}, quartiles {:.3}–{:.3}.\n",
        t.render_ms["frame"], t.embedded_ms["frame"], t.ratio[1], t.ratio[0], t.ratio[2]
    );
    md
}
