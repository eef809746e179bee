//! The headless renderer: builds the frame's resources and passes for one image size, records
//! the passes with declared-access barriers and timestamps, submits, waits and reads back.

use crate::error::{Error, Result, VkContext};
use crate::frame::{self, FrameData};
use crate::passes::ocean::{OceanPass, ShaderConfig};
use crate::passes::readback::ReadbackPass;
use crate::passes::resolve::ResolvePass;
use crate::passes::sky_map::{SkyMapPass, SkyMipsPass};
use crate::passes::tonemap::TonemapPass;
use crate::passes::{Pass, Recorder};
use crate::resources::Resources;
use crate::scene::Scene;
use crate::vk::barrier::Tracker;
use crate::vk::gpu::Gpu;
use crate::vk::memory::MemoryReport;
use crate::vk::owned::Owned;
use crate::vk::profiler::Profiler;
use crate::waves;
use ash::vk;

/// A rendered frame, read back to the CPU.
pub struct RenderedFrame {
    pub width: u32,
    pub height: u32,
    /// Linear HDR radiance, RGBA, row-major from the top-left.
    pub hdr: Vec<[f32; 4]>,
    /// Tone-mapped sRGB, RGBA8.
    pub ldr: Vec<u8>,
    /// GPU time per pass (ms); empty when the queue has no timestamps.
    pub pass_ms: Vec<(String, f64)>,
    pub frame: FrameData,
}

/// How a renderer renders: the ocean shaders' specialization and the supersampling factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    pub shader: ShaderConfig,
    /// Samples per pixel along each axis (1: none).
    pub ssaa: u32,
}

impl Default for Options {
    fn default() -> Self {
        Options { shader: ShaderConfig::default(), ssaa: 1 }
    }
}

pub struct Renderer<'g> {
    gpu: &'g Gpu,
    width: u32,
    height: u32,
    ssaa: u32,
    anisotropy: f64,
    // Field order is drop order (after Drop::drop waits for the device): the fence and command
    // pool, the passes, then the resources they refer to.
    fence: Owned<'g, vk::Fence>,
    /// Owns `cmd`.
    _command_pool: Owned<'g, vk::CommandPool>,
    cmd: vk::CommandBuffer,
    profiler: Profiler<'g>,
    /// In execution order.
    passes: Vec<Box<dyn Pass + 'g>>,
    resources: Resources<'g>,
    tracker: Tracker,
    /// The sun and sky the sky map holds, once built: frames under the same sky skip rebuilding it.
    sky_in_map: Option<(crate::scene::Sun, crate::scene::Sky)>,
}

impl<'g> Renderer<'g> {
    /// A renderer for `width` x `height` images of scenes with `scene`'s sky-map anisotropy.
    /// With supersampling the grid keeps its cell size in output pixels.
    pub fn new(gpu: &'g Gpu, scene: &Scene, width: u32, height: u32, options: Options) -> Result<Renderer<'g>> {
        let device = &gpu.device;
        let resources = Resources::new(gpu, width, height, options.ssaa, scene.render.sky_anisotropy as f32)?;
        let mut passes: Vec<Box<dyn Pass + 'g>> = vec![
            Box::new(SkyMapPass::new(device, &resources)?),
            Box::new(SkyMipsPass),
            Box::new(OceanPass::new(device, &resources, options.shader)?),
        ];
        if let Some(resolved) = &resources.resolved {
            passes.push(Box::new(ResolvePass::new(device, &resources.hdr, resolved)?));
        }
        passes.push(Box::new(TonemapPass::new(device, &resources)?));
        passes.push(Box::new(ReadbackPass));
        let profiler = Profiler::new(device, passes.len() as u32)?;
        let raw = &device.raw;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create info on a live device.
        let command_pool = unsafe { raw.create_command_pool(&pool_info, None) }.during("vkCreateCommandPool")?;
        let command_pool = Owned::new(device, command_pool, "frame commands");
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(command_pool.raw)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: one primary buffer from the pool just made.
        let cmd = unsafe { raw.allocate_command_buffers(&alloc) }.during("vkAllocateCommandBuffers")?[0];
        device.set_name(cmd, "frame");
        // SAFETY: a plain fence on a live device.
        let fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) }.during("vkCreateFence")?;
        let fence = Owned::new(device, fence, "frame done");
        Ok(Renderer {
            gpu,
            width,
            height,
            ssaa: options.ssaa,
            anisotropy: scene.render.sky_anisotropy,
            fence,
            _command_pool: command_pool,
            cmd,
            profiler,
            passes,
            resources,
            tracker: Tracker::default(),
            sky_in_map: None,
        })
    }

    pub fn memory(&self) -> MemoryReport {
        self.gpu.allocator.borrow().report()
    }

    pub fn render(&mut self, scene: &Scene) -> Result<RenderedFrame> {
        if scene.render.sky_anisotropy != self.anisotropy {
            return Err(Error::Argument(format!(
                "this renderer's sky sampler was built for sky_anisotropy = {}, the scene asks {}",
                self.anisotropy, scene.render.sky_anisotropy
            )));
        }
        let wave_set = waves::generate(scene);
        let k = self.ssaa;
        let data =
            frame::build(scene, &wave_set, self.width * k, self.height * k, scene.render.grid_cell_px * k as f64);
        let resources = &mut self.resources;
        resources.set_grid(data.grid.columns, data.grid.rows)?;
        resources.frame_uniforms.write(std::slice::from_ref(&data.uniforms))?;
        resources.waves.write(std::slice::from_ref(data.waves.as_ref()))?;
        let sky = (scene.sun.clone(), scene.sky.clone());
        let sky_current = self.sky_in_map.as_ref() == Some(&sky);
        self.submit_frame(sky_current)?;
        self.sky_in_map = Some(sky);

        let pixels = self.width as usize * self.height as usize;
        let hdr_bits: Vec<u16> = self.resources.hdr_readback.read(4 * pixels)?;
        let hdr =
            hdr_bits.chunks_exact(4).map(|p| std::array::from_fn(|c| half::f16::from_bits(p[c]).to_f32())).collect();
        let ldr = self.resources.ldr_readback.read(4 * pixels)?;
        let pass_ms = self
            .profiler
            .read(&self.gpu.device.raw)?
            .unwrap_or_default()
            .into_iter()
            .map(|(n, ms)| (n.to_owned(), ms))
            .collect();
        Ok(RenderedFrame { width: self.width, height: self.height, hdr, ldr, pass_ms, frame: data })
    }

    /// Records and runs one frame; `sky_current`: the sky map already holds this frame's sky.
    fn submit_frame(&mut self, sky_current: bool) -> Result<()> {
        let device = &self.gpu.device;
        let raw = &device.raw;
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the previous submission's fence was waited on, so the buffer is not pending.
        unsafe { raw.begin_command_buffer(self.cmd, &begin) }.during("vkBeginCommandBuffer")?;
        self.profiler.reset(raw, self.cmd);
        for pass in self.passes.iter().filter(|p| !(sky_current && p.builds_sky_map())) {
            self.profiler.begin(device, self.cmd, pass.name());
            pass.declare(&self.resources, &mut self.tracker);
            self.tracker.flush(raw, self.cmd);
            pass.record(&mut Recorder { device, cmd: self.cmd, tracker: &mut self.tracker }, &self.resources);
            self.profiler.end(device, self.cmd);
        }
        // SAFETY: recording began above.
        unsafe { raw.end_command_buffer(self.cmd) }.during("vkEndCommandBuffer")?;
        let cmds = [self.cmd];
        let submit = vk::SubmitInfo::default().command_buffers(&cmds);
        // SAFETY: the fence is unsignalled; host writes to mapped memory made before the submit
        // are visible to the device (vkQueueSubmit's implicit host-write ordering).
        unsafe { raw.queue_submit(device.queue, &[submit], self.fence.raw) }.during("vkQueueSubmit")?;
        // SAFETY: waits on and resets our own fence.
        unsafe { raw.wait_for_fences(&[self.fence.raw], true, u64::MAX) }.during("vkWaitForFences")?;
        // SAFETY: the fence was waited on, so it is signalled and unused.
        unsafe { raw.reset_fences(&[self.fence.raw]) }.during("vkResetFences")?;
        Ok(())
    }
}

impl Drop for Renderer<'_> {
    fn drop(&mut self) {
        // Nothing may be destroyed while the GPU still uses it; the fields then drop in order.
        let _ = self.gpu.device.wait_idle();
    }
}
