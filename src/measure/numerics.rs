//! Runs the shading functions on the GPU over arrays of arguments (glsl/numerics.comp), so that
//! tests can sweep their whole domains against f64 implementations of the same formulas.

use crate::error::{Result, VkContext};
use crate::model::scene::Scene;
use crate::model::waves;
use crate::render::frame::{self, FrameUniforms, GpuWaves};
use crate::render::resources::{mean_fresnel_buffer, MEAN_FRESNEL_BINDING};
use crate::shaders;
use crate::vk::buffer::Buffer;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

/// The functions numerics.comp evaluates, by index.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Function {
    /// (c, s) -> c Lambda(c / s)
    CosTimesLambda = 0,
    /// (cos_v, sigma_v) -> mean Fresnel
    MeanFresnel = 1,
    /// t -> (sin 2 pi t, cos 2 pi t)
    SinCosTurns = 2,
    /// k h -> 1 - sqrt(1 - (k h)^2)
    TrochoidSlopeVariance = 3,
    /// (v, sigma_x^2), (l, sigma_y^2) -> reflected sun per unit irradiance (rgb equal)
    ReflectedSun = 4,
    /// (v), (zeta) -> stereographic u of v reflected about the facet
    ReflectedU = 5,
    /// (ndc x, ndc y, k turns x, y), (k h) -> the train's weight in the per-pixel normal, for the
    /// default scene's camera at 64 x 64
    NormalWeight = 6,
    /// (v in the local frame), (sigma_x^2, sigma_y^2) -> the visible facets' mean slope
    VisibleSlopeShift = 7,
    /// (direction) -> its u on the whole stereographic plane, held at the sky map's extent
    StereographicPlane = 8,
    /// (v in the local frame), (sigma_x^2, sigma_y^2) -> the visible facets' slope covariance
    /// (xx, xy, yy) from the footprint's two axes
    VisibleSlopeCovariance = 9,
    /// (cos_v, sigma_v) -> the exact Fresnel averaged over the visible slopes (its table)
    VisibleFresnel = 10,
    /// (cos of incidence) -> the exact Fresnel of sea water
    ExactFresnel = 11,
    /// (unit ray), (eye height H, planet radius R) -> distance to the sphere, -1 where it misses
    SphereDistance = 12,
    /// (n, p, n p, u0), (u1, u2) -> the glints' binomial count drawn from uniforms in [0, 1)
    /// (multiples of 2^-24)
    BinomialCount = 13,
    /// (tap, count, spacing in standard deviations) -> the Gaussian's share that a reflection
    /// cone's tap stands for (slopes.glsl tap_mass)
    TapMass = 14,
}

/// Evaluates `function` at every pair of argument vectors. `sun_slope_variance` is the sun disc's
/// slope variance added in the sun term (the frame's sun irradiance is set to 1).
pub fn evaluate(
    gpu: &Gpu,
    function: Function,
    arguments: &[[[f32; 4]; 2]],
    sun_slope_variance: f32,
) -> Result<Vec<[f32; 4]>> {
    let device = &gpu.device;
    let scene = Scene::default();
    let wave_set = waves::generate(&scene);
    let mut uniforms: FrameUniforms = frame::build(&scene, &wave_set, 64, 64, 8.0).uniforms;
    uniforms.sun_irradiance = [1.0, 1.0, 1.0, 1.0];
    uniforms.sun_radiance[3] = sun_slope_variance;
    use vk::BufferUsageFlags as B;
    let count = arguments.len().max(1);
    let frame_buffer = Buffer::new(
        gpu,
        "numerics frame",
        std::mem::size_of::<FrameUniforms>() as u64,
        B::UNIFORM_BUFFER,
        Location::Upload,
    )?;
    frame_buffer.write(std::slice::from_ref(&uniforms))?;
    let waves_buffer = Buffer::new(
        gpu,
        "numerics waves",
        std::mem::size_of::<GpuWaves>() as u64,
        B::UNIFORM_BUFFER,
        Location::Upload,
    )?;
    waves_buffer.write(std::slice::from_ref(frame::build(&scene, &wave_set, 64, 64, 8.0).waves.as_ref()))?;
    let input = Buffer::new(gpu, "numerics arguments", 32 * count as u64, B::STORAGE_BUFFER, Location::Upload)?;
    input.write(arguments)?;
    let output = Buffer::new(gpu, "numerics results", 16 * count as u64, B::STORAGE_BUFFER, Location::Readback)?;

    // A 1x1 sampled image for the (unused) sky map binding.
    let image = crate::vk::image::Image::new(
        gpu,
        "numerics sky",
        crate::vk::device::HDR_FORMAT,
        vk::Extent2D { width: 1, height: 1 },
        1,
        vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
    )?;
    // SAFETY: a plain sampler create info.
    let sampler =
        unsafe { device.raw.create_sampler(&vk::SamplerCreateInfo::default(), None) }.during("vkCreateSampler")?;
    let sampler = Owned::new(device, sampler, "numerics sampler");

    use vk::DescriptorType as D;
    let s = vk::ShaderStageFlags::COMPUTE;
    let bindings = Bindings::with_push_constants(
        device,
        "numerics",
        &[
            (0, D::UNIFORM_BUFFER, s),
            (1, D::UNIFORM_BUFFER, s),
            (2, D::COMBINED_IMAGE_SAMPLER, s),
            (9, D::STORAGE_BUFFER, s),
            (10, D::STORAGE_BUFFER, s),
            (MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, s),
        ],
        8,
    )?;
    let mean_fresnel = mean_fresnel_buffer(gpu)?;
    bindings.write_buffer(MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, mean_fresnel.raw);
    bindings.write_buffer(0, D::UNIFORM_BUFFER, frame_buffer.raw);
    bindings.write_buffer(1, D::UNIFORM_BUFFER, waves_buffer.raw);
    bindings.write_image(
        2,
        D::COMBINED_IMAGE_SAMPLER,
        image.view,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        sampler.raw,
    );
    bindings.write_buffer(9, D::STORAGE_BUFFER, input.raw);
    bindings.write_buffer(10, D::STORAGE_BUFFER, output.raw);
    let pipeline = compute_pipeline(device, bindings.layout(), shaders::NUMERICS_COMP, "numerics")?;

    let commands = Commands::new(device, "numerics")?;
    let cmd = commands.cmd;
    let push = [function as u32, arguments.len() as u32];
    // SAFETY: recording into a fresh buffer; every binding names a live resource; the sampled
    // image is moved to SHADER_READ_ONLY_OPTIMAL before the dispatch; the fence is waited on
    // before anything is read or dropped.
    unsafe {
        let raw = &device.raw;
        raw.begin_command_buffer(
            cmd,
            &vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
        )
        .during("vkBeginCommandBuffer")?;
        let to_sampled = vk::ImageMemoryBarrier2::default()
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(vk::AccessFlags2::SHADER_SAMPLED_READ)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
            .image(image.raw)
            .subresource_range(image.full_range());
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(std::slice::from_ref(&to_sampled)),
        );
        raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
        bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &[]);
        let bytes = std::slice::from_raw_parts(push.as_ptr() as *const u8, 8);
        raw.cmd_push_constants(cmd, bindings.layout(), s, 0, bytes);
        raw.cmd_dispatch(cmd, (count as u32).div_ceil(64), 1, 1);
        let to_host = vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ);
        raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(std::slice::from_ref(&to_host)));
    }
    commands.submit_and_wait()?;
    let words: Vec<f32> = output.read(4 * arguments.len())?;
    Ok(words.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]).collect())
}
