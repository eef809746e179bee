//! The window as a render target: the swapchain and a renderer whose frames end in its images,
//! both recreated together when the surface changes (resize, out of date, suboptimal, restore
//! after a minimize). While the window has no area there is no swapchain and nothing is drawn.

use crate::error::Result;
use crate::model::scene::Scene;
use crate::render::passes::ocean::ShaderConfig;
use crate::render::renderer::{Capture, Captured, Options, Output, Renderer};
use crate::say;
use crate::vk::gpu::Gpu;
use crate::vk::swapchain::{present_mode_name, Acquired, Swapchain};
use ash::vk;

pub struct Presenter<'g> {
    gpu: &'g Gpu,
    requested: vk::PresentModeKHR,
    shader: ShaderConfig,
    frames_in_flight: u32,
    // Drop order: the renderer (waits for the device), then the swapchains.
    pub renderer: Option<Renderer<'g>>,
    pub swapchain: Option<Swapchain<'g>>,
    /// Replaced swapchains, with the presents left until they are destroyed: without
    /// VK_EXT_swapchain_maintenance1 nothing says when the presentation engine is done with a
    /// present's semaphore, but it has been once as many later presents as the old chain had
    /// images have gone through (no more than that can be queued).
    retired: Vec<(Swapchain<'g>, usize)>,
    /// Swapchains made after the first one.
    pub recreations: u32,
    made_one: bool,
    /// The surface format and present mode were logged (once; again only if they change).
    logged: Option<(vk::SurfaceFormatKHR, vk::PresentModeKHR)>,
}

/// How a frame went.
pub enum Drawn {
    /// Presented; the swapchain may want recreating (suboptimal or out of date at present).
    /// `wait_ms`: CPU time waiting for the frame slot and the image; `present_ms`: in the
    /// present call (which a software presenter spends copying the finished frame out).
    Presented { stale: bool, captured: Option<Captured>, wait_ms: f64, present_ms: f64 },
    /// The swapchain was out of date at acquire: nothing drawn, recreate and try again.
    OutOfDate,
}

impl<'g> Presenter<'g> {
    /// `frames_in_flight`: frames the CPU may prepare while the GPU runs earlier ones.
    pub fn new(
        gpu: &'g Gpu,
        requested: vk::PresentModeKHR,
        shader: ShaderConfig,
        frames_in_flight: u32,
    ) -> Presenter<'g> {
        Presenter {
            gpu,
            requested,
            shader,
            frames_in_flight,
            renderer: None,
            swapchain: None,
            retired: Vec::new(),
            recreations: 0,
            made_one: false,
            logged: None,
        }
    }

    /// Changes the ocean shaders (a method switch): the renderer is rebuilt.
    pub fn set_shader(&mut self, shader: ShaderConfig, scene: &Scene) -> Result<()> {
        self.shader = shader;
        self.rebuild_renderer(scene)
    }

    /// (Re)creates the swapchain for a drawable area of `extent`, and the renderer if the image
    /// size or format changed. Ok(false): the area is empty (minimized), nothing to draw into.
    pub fn recreate(&mut self, extent: vk::Extent2D, scene: &Scene) -> Result<bool> {
        // Every frame that rendered into the old images is done before they can go.
        if let Some(renderer) = &mut self.renderer {
            renderer.wait_idle()?;
        }
        let old = self.swapchain.take();
        let made = Swapchain::new(self.gpu, self.requested, extent, old.as_ref())?;
        if let Some(old) = old {
            if let Some(renderer) = &mut self.renderer {
                renderer.forget_images(&old.images);
            }
            let presents_left = old.images.len();
            self.retired.push((old, presents_left));
        }
        let Some((swapchain, fell_back)) = made else {
            return Ok(false);
        };
        if self.made_one {
            self.recreations += 1;
        }
        self.made_one = true;
        let choice = swapchain.choice;
        if self.logged != Some((choice.format, choice.present_mode)) {
            if fell_back {
                say!("present mode {} is not offered by this surface; using fifo", present_mode_name(self.requested));
            }
            say!(
                "swapchain: {}x{} {:?} ({}), {} images, present mode {}",
                swapchain.extent.width,
                swapchain.extent.height,
                choice.format.format,
                if choice.encode_srgb_in_shader {
                    "UNORM: sRGB encoded by the display shader"
                } else {
                    "sRGB: encoded on store"
                },
                swapchain.images.len(),
                present_mode_name(choice.present_mode)
            );
            self.logged = Some((choice.format, choice.present_mode));
        }
        let rebuild = match &self.renderer {
            Some(r) => {
                r.size() != (swapchain.extent.width, swapchain.extent.height) || r.output() != self.output(&swapchain)
            }
            None => true,
        };
        self.swapchain = Some(swapchain);
        if rebuild {
            self.rebuild_renderer(scene)?;
        }
        Ok(true)
    }

    fn output(&self, swapchain: &Swapchain) -> Output {
        Output::Window { format: swapchain.choice.format.format, encode_srgb: swapchain.choice.encode_srgb_in_shader }
    }

    /// Rebuilds the renderer for the current swapchain (a scene whose sky sampler changed).
    pub fn rebuild(&mut self, scene: &Scene) -> Result<()> {
        self.rebuild_renderer(scene)
    }

    fn rebuild_renderer(&mut self, scene: &Scene) -> Result<()> {
        let Some(swapchain) = &self.swapchain else {
            // Minimized: the next recreate builds one for the restored swapchain.
            self.renderer = None;
            return Ok(());
        };
        let options = Options {
            shader: self.shader,
            output: self.output(swapchain),
            frames_in_flight: self.frames_in_flight,
            ..Options::default()
        };
        self.renderer = None; // wait for and free the old one before placing the new one
        let extent = swapchain.extent;
        self.renderer = Some(Renderer::new(self.gpu, scene, extent.width, extent.height, options)?);
        Ok(())
    }

    /// Whether the swapchain's images can be copied out (screenshots of what is shown).
    pub fn can_copy_shown(&self) -> bool {
        self.swapchain.as_ref().is_some_and(|s| s.choice.copyable)
    }

    /// Draws and presents one frame of `scene`.
    pub fn draw(&mut self, scene: &Scene, capture: Capture) -> Result<Drawn> {
        let (Some(renderer), Some(swapchain)) = (&mut self.renderer, &self.swapchain) else {
            return Ok(Drawn::OutOfDate);
        };
        assert!(capture != Capture::Shown || swapchain.choice.copyable, "check can_copy_shown() first");
        let waited = std::time::Instant::now();
        let slot = renderer.begin_frame()?;
        let mut wait_ms = waited.elapsed().as_secs_f64() * 1e3;
        // Whatever can fail on the host fails here, before an image is acquired.
        let prepared = renderer.prepare(slot, scene, capture)?;
        let waited = std::time::Instant::now();
        let (image, suboptimal) = match swapchain.acquire(renderer.image_available(slot))? {
            Acquired::Image { image, suboptimal } => (image, suboptimal),
            Acquired::OutOfDate => return Ok(Drawn::OutOfDate),
        };
        wait_ms += waited.elapsed().as_secs_f64() * 1e3;
        let rendered = swapchain.render_finished[image.index as usize].raw;
        let captured = renderer.draw(slot, prepared, image, rendered)?;
        let presenting = std::time::Instant::now();
        let current = swapchain.present(&image)?;
        let present_ms = presenting.elapsed().as_secs_f64() * 1e3;
        self.retired.retain_mut(|(_, presents_left)| {
            *presents_left = presents_left.saturating_sub(1);
            *presents_left > 0
        });
        Ok(Drawn::Presented { stale: suboptimal || !current, captured, wait_ms, present_ms })
    }
}
