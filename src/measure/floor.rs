//! The shading pass's arithmetic floor: the floating-point work a frame cannot avoid (the trains
//! each sea pixel resolves, the BRDF) over what the device delivers for such work, measured with
//! independent FMAs (glsl/flops.comp). No schedule of the same work beats that time on the
//! device; `bench speed` reports the shading pass against it.
//!
//! Operations are counted by hand from the shaders: +, -, * and / one each, an FMA two, exp,
//! log, pow, sqrt and inversesqrt one each (so the floor is optimistic), a 3-vector dot five.

use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::model::waves::WaveSet;
use crate::render::footprint::{normal_weight, Footprint};
use crate::render::frame::CameraFrame;
use crate::shaders;
use crate::vk::buffer::Buffer;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::memory::Location;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings, Specialization};
use crate::vk::profiler::Profiler;
use ash::vk;
use glam::DVec2;

/// Per train a pixel resolves (glsl/waves.glsl, surface_sample): the phase k.x (a mul, an FMA
/// and a sub: 4), sin and cos of it in turns (reduction 5, x^2 1, sine 3 FMA and a mul, cosine
/// 4 FMA: 21), the amplitudes (2), and the five slope sums (2 mul, 5 FMA: 12). Normalising the
/// train's direction is not counted: a layout could carry it.
pub const FLOPS_PER_TRAIN: f64 = 39.0;
/// Per sea pixel, once (shade.comp and brdf.glsl): the ray, its footprint and the normal (~80),
/// the wind frame and local directions (~45), the reflected sun with Smith shadowing (~130), the
/// mean Fresnel (~25), the sky lookup's three reflected directions and gradients (~160), the
/// refracted term (~10).
pub const FLOPS_PER_SEA_PIXEL: f64 = 450.0;

/// The unavoidable work of one frame's shading.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct ShadeWork {
    pub sea_pixels: f64,
    /// Trains with a non-zero weight in the per-pixel normal, on average over the sea.
    pub trains_per_sea_pixel: f64,
    pub gflop: f64,
}

/// Counts the trains each sea pixel resolves (f64, on every 4th pixel along each axis; the
/// rest-plane point stands for the displaced one, as in the footprint).
pub fn shade_work(scene: &Scene, waves: &WaveSet, width: u32, height: u32) -> ShadeWork {
    let camera = CameraFrame::new(scene, waves, width, height);
    let footprint = Footprint { camera: &camera, waves, time_s: scene.render.time_s, width, height, packets: None };
    const STRIDE: u32 = 4;
    let (mut sampled, mut sea, mut trains) = (0u64, 0u64, 0u64);
    for py in (0..height).step_by(STRIDE as usize) {
        for px in (0..width).step_by(STRIDE as usize) {
            sampled += 1;
            let ray = footprint.pixel_ray(px as f64, py as f64);
            let Some((_, a_u, a_v)) = footprint.rest_hit(ray) else { continue };
            sea += 1;
            trains += waves
                .trains
                .iter()
                .filter(|t| {
                    let k_turns = DVec2::from(t.direction) / t.wavelength;
                    normal_weight(k_turns, a_u, a_v) > 0.0
                })
                .count() as u64;
        }
    }
    let sea_pixels = sea as f64 / sampled.max(1) as f64 * width as f64 * height as f64;
    let trains_per_sea_pixel = if sea > 0 { trains as f64 / sea as f64 } else { 0.0 };
    let flops = sea_pixels * (trains_per_sea_pixel * FLOPS_PER_TRAIN + FLOPS_PER_SEA_PIXEL);
    ShadeWork { sea_pixels, trains_per_sea_pixel, gflop: flops * 1e-9 }
}

/// GFLOP/s the device delivers for independent FMAs in a compute shader (the best of `runs`).
pub fn delivered_gflops(gpu: &Gpu, runs: u32) -> Result<f64> {
    const GROUPS: u32 = 512;
    const ITERATIONS: u32 = 256; // of 8 rounds of 16 FMA chains (glsl/flops.comp)
    let device = &gpu.device;
    let invocations = GROUPS as u64 * 64;
    let sink = Buffer::new(gpu, "flops sink", invocations * 16, vk::BufferUsageFlags::STORAGE_BUFFER, Location::Gpu)?;
    let stage = vk::ShaderStageFlags::COMPUTE;
    let bindings = Bindings::new(device, "flops", &[(0, vk::DescriptorType::STORAGE_BUFFER, stage)])?;
    bindings.write_buffer(0, vk::DescriptorType::STORAGE_BUFFER, sink.raw);
    let spec = Specialization::words(&[ITERATIONS]);
    let pipeline = specialized_compute_pipeline(device, bindings.layout(), shaders::FLOPS_COMP, Some(&spec), "flops")?;
    let commands = Commands::new(device, "flops")?;
    let mut profiler = Profiler::new(device, 1, false)?;
    let flop = invocations as f64 * ITERATIONS as f64 * 8.0 * 16.0 * 2.0;
    let mut best: f64 = 0.0;
    for _ in 0..runs.max(1) + 1 {
        commands.begin()?;
        profiler.reset(&device.raw, commands.cmd);
        profiler.begin(device, commands.cmd, "flops");
        // SAFETY: recording; the set names a live buffer; nothing else uses the sink, and each
        // submission is waited on before the next records.
        unsafe {
            device.raw.cmd_bind_pipeline(commands.cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
        }
        bindings.bind(commands.cmd, vk::PipelineBindPoint::COMPUTE, &[]);
        // SAFETY: as above.
        unsafe { device.raw.cmd_dispatch(commands.cmd, GROUPS, 1, 1) };
        profiler.end(device, commands.cmd);
        commands.submit_and_wait()?;
        if let Some(times) = profiler.read(&device.raw)? {
            let ms = times[0].1;
            if ms > 0.0 {
                best = best.max(flop / (ms * 1e-3) * 1e-9);
            }
        }
    }
    if best == 0.0 {
        return Err(Error::Argument(format!("{} has no timestamp support", device.name)));
    }
    Ok(best)
}
