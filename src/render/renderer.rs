//! The headless renderer: builds the frame's resources and passes for one image size, records
//! the passes with declared-access barriers and timestamps, submits, waits and reads back.

use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::model::waves;
use crate::render::frame::{self, FrameData};
use crate::render::passes::ocean::{OceanPass, ShaderConfig};
use crate::render::passes::readback::ReadbackPass;
use crate::render::passes::resolve::ResolvePass;
use crate::render::passes::sky_map::{SkyMapPass, SkyMipsPass};
use crate::render::passes::tonemap::TonemapPass;
use crate::render::passes::{Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::Tracker;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::memory::MemoryReport;
use crate::vk::profiler::Profiler;

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
    /// Whether the sky map is built (without it, a 1x1 placeholder keeps the descriptor valid
    /// and its passes are left out); only a shader without the sky term may do without.
    pub sky_map: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options { shader: ShaderConfig::default(), ssaa: 1, sky_map: true }
    }
}

pub struct Renderer<'g> {
    gpu: &'g Gpu,
    width: u32,
    height: u32,
    ssaa: u32,
    anisotropy: f64,
    // Field order is drop order (after Drop::drop waits for the device): the command buffer, the
    // passes, then the resources they refer to.
    commands: Commands<'g>,
    profiler: Profiler<'g>,
    /// In execution order.
    passes: Vec<Box<dyn Pass + 'g>>,
    resources: Resources<'g>,
    tracker: Tracker,
    /// The sun and sky the sky map holds, once built: frames under the same sky skip rebuilding it.
    sky_in_map: Option<(crate::model::scene::Sun, crate::model::scene::Sky)>,
}

impl<'g> Renderer<'g> {
    /// A renderer for `width` x `height` images of scenes with `scene`'s sky-map anisotropy.
    /// With supersampling the grid keeps its cell size in output pixels.
    pub fn new(gpu: &'g Gpu, scene: &Scene, width: u32, height: u32, options: Options) -> Result<Renderer<'g>> {
        let device = &gpu.device;
        assert!(options.sky_map || !options.shader.terms.sky, "the sky term samples the sky map");
        let resources =
            Resources::new(gpu, width, height, options.ssaa, options.sky_map, scene.render.sky_anisotropy as f32)?;
        let mut passes: Vec<Box<dyn Pass + 'g>> = Vec::new();
        if options.sky_map {
            passes.push(Box::new(SkyMapPass::new(device, &resources)?));
            passes.push(Box::new(SkyMipsPass));
        }
        passes.push(Box::new(OceanPass::new(device, &resources, options.shader)?));
        if let Some(resolved) = &resources.resolved {
            passes.push(Box::new(ResolvePass::new(device, &resources.hdr, resolved)?));
        }
        passes.push(Box::new(TonemapPass::new(device, &resources)?));
        passes.push(Box::new(ReadbackPass));
        let profiler = Profiler::new(device, passes.len() as u32)?;
        let commands = Commands::new(device, "frame")?;
        Ok(Renderer {
            gpu,
            width,
            height,
            ssaa: options.ssaa,
            anisotropy: scene.render.sky_anisotropy,
            commands,
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
        let cmd = self.commands.cmd;
        self.commands.begin()?;
        self.profiler.reset(&device.raw, cmd);
        for pass in self.passes.iter().filter(|p| !(sky_current && p.builds_sky_map())) {
            self.profiler.begin(device, cmd, pass.name());
            pass.declare(&self.resources, &mut self.tracker);
            self.tracker.flush(&device.raw, cmd);
            pass.record(&mut Recorder { device, cmd, tracker: &mut self.tracker }, &self.resources);
            self.profiler.end(device, cmd);
        }
        self.commands.submit_and_wait()
    }
}

impl Drop for Renderer<'_> {
    fn drop(&mut self) {
        // Nothing may be destroyed while the GPU still uses it; the fields then drop in order.
        let _ = self.gpu.device.wait_idle();
    }
}
