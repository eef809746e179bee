//! The window as a host of the ocean library (embed::Ocean), as an engine would host it: the
//! swapchain, an HDR colour image the ocean draws into, each frame slot's command buffer, fence
//! and acquire semaphore, and the copies a screenshot needs. The ocean tone-maps into the
//! acquired swapchain image; this host moves it to present. The swapchain and the ocean's size
//! are recreated together when the surface changes (resize, out of date, suboptimal, restore
//! after a minimize); while the window has no area there is no swapchain and nothing is drawn.

use crate::app::objects::{Objects, DEPTH_FORMAT};
use crate::embed::camera::scene_view;
use crate::embed::{
    FrameInput, GpuFrame, HostFormats, HostImage, ImageState, Ocean, OceanDesc, ShaderConfig, Shading, Targets,
    IN_PLACE_USAGE, IN_PLACE_VIEW_FORMATS,
};
use crate::error::Result;
use crate::model::scene::Scene;
use crate::say;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::buffer::Buffer;
use crate::vk::commands::{Commands, Wait};
use crate::vk::device::HDR_FORMAT;
use crate::vk::gpu::Gpu;
use crate::vk::image::{copy_to_buffer, Image};
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use crate::vk::swapchain::{present_mode_name, Acquired, SwapImage, Swapchain};
use crate::vk::sync::semaphore;
use ash::vk;

/// What a frame copies out besides showing it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Capture {
    None,
    /// The swapchain image as shown (8-bit, in the swapchain's format).
    Shown,
    /// The linear HDR radiance (RGBA16F).
    Radiance,
}

/// Pixels copied out of a frame, row-major from the top-left.
pub enum Captured {
    /// RGBA8 as shown (BGRA swapchain formats already swizzled).
    Shown {
        width: u32,
        height: u32,
        rgba: Vec<u8>,
    },
    Radiance {
        width: u32,
        height: u32,
        rgba: Vec<[f32; 4]>,
    },
}

/// One frame in flight: its commands and fence, and the semaphore its image is acquired with.
struct HostSlot<'g> {
    commands: Commands<'g>,
    image_available: Owned<'g, vk::Semaphore>,
}

/// The ocean and what it draws into, for one swapchain size.
struct Drawing<'g> {
    // Field order is drop order: the ocean waits for the device before anything goes.
    ocean: Ocean<'g>,
    colour: Image<'g>,
    /// The scene's objects and their depth (shared by the frames in flight, like the colour).
    objects: Option<(Objects<'g>, Image<'g>)>,
}

pub struct Presenter<'g> {
    gpu: &'g Gpu,
    requested: vk::PresentModeKHR,
    shader: ShaderConfig,
    /// The scene the ocean was last given (its camera and time come with each frame).
    scene: Option<Scene>,
    // Drop order: the ocean (waits for the device), the slots, the capture buffer, the swapchains.
    drawing: Option<Drawing<'g>>,
    slots: Vec<HostSlot<'g>>,
    next_slot: usize,
    capture: Option<Buffer<'g>>,
    tracker: Tracker,
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
    ) -> Result<Presenter<'g>> {
        let slots = (0..frames_in_flight.max(1))
            .map(|i| {
                Ok(HostSlot {
                    commands: Commands::new(&gpu.device, &format!("frame {i}"))?,
                    image_available: semaphore(&gpu.device, &format!("image for frame {i}"))?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Presenter {
            gpu,
            requested,
            shader,
            scene: None,
            drawing: None,
            slots,
            next_slot: 0,
            capture: None,
            tracker: Tracker::default(),
            swapchain: None,
            retired: Vec::new(),
            recreations: 0,
            made_one: false,
            logged: None,
        })
    }

    /// GPU time per pass (ms) of the latest finished frame.
    pub fn pass_ms(&self) -> &[(&'static str, f64)] {
        self.drawing.as_ref().map_or(&[], |d| d.ocean.pass_ms())
    }

    /// The latest finished frame's passes on the host clock.
    pub fn gpu_frame(&self) -> Option<&GpuFrame> {
        self.drawing.as_ref().and_then(|d| d.ocean.last_gpu_frame())
    }

    /// Waits for every frame in flight, keeping the last one's times.
    pub fn wait_idle(&mut self) -> Result<()> {
        for (i, slot) in self.slots.iter().enumerate() {
            if slot.commands.wait()? {
                if let Some(d) = &mut self.drawing {
                    d.ocean.finished(i)?;
                }
            }
        }
        Ok(())
    }

    /// Changes the ocean shaders (a method switch): the ocean is rebuilt.
    pub fn set_shader(&mut self, shader: ShaderConfig, scene: &Scene) -> Result<()> {
        self.shader = shader;
        self.rebuild(scene)
    }

    /// (Re)creates the swapchain for a drawable area of `extent`, and the ocean if the image size
    /// or format changed. Ok(false): the area is empty (minimized), nothing to draw into.
    pub fn recreate(&mut self, extent: vk::Extent2D, scene: &Scene) -> Result<bool> {
        // Every frame that rendered into the old images is done before they can go.
        self.wait_idle()?;
        let old = self.swapchain.take();
        let made = Swapchain::new(self.gpu, self.requested, extent, old.as_ref())?;
        if let Some(old) = old {
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
                    "UNORM: sRGB encoded by the tone mapping"
                } else {
                    "sRGB: encoded on store"
                },
                swapchain.images.len(),
                present_mode_name(choice.present_mode)
            );
            self.logged = Some((choice.format, choice.present_mode));
        }
        let rebuild = match &self.drawing {
            Some(d) => {
                let desc = d.ocean.desc();
                (desc.width, desc.height) != (swapchain.extent.width, swapchain.extent.height)
                    || desc.formats.ldr != Some(choice.format.format)
            }
            None => true,
        };
        self.swapchain = Some(swapchain);
        if rebuild {
            self.rebuild(scene)?;
        }
        Ok(true)
    }

    /// Rebuilds the ocean for the current swapchain (its old resources go first).
    pub fn rebuild(&mut self, scene: &Scene) -> Result<()> {
        self.wait_idle()?;
        self.drawing = None;
        let Some(swapchain) = &self.swapchain else {
            return Ok(()); // minimized: the next recreate builds one for the restored swapchain
        };
        let extent = swapchain.extent;
        let objects = if scene.objects.is_empty() {
            None
        } else {
            let slots = self.slots.len() as u32;
            let objects = Objects::new(self.gpu, &scene.objects, HDR_FORMAT, DEPTH_FORMAT, true, slots)?;
            // Sampled too: the sea's reflections of the objects read it.
            let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
            Some((objects, Image::new(self.gpu, "window depth", DEPTH_FORMAT, extent, 1, usage)?))
        };
        // A frame without objects is wholly the ocean's: it draws in the colour image in place.
        let colour = if objects.is_none() {
            Image::aliased(self.gpu, "window colour", HDR_FORMAT, IN_PLACE_VIEW_FORMATS[1], extent, IN_PLACE_USAGE)?
        } else {
            use vk::ImageUsageFlags as U;
            let usage = U::COLOR_ATTACHMENT | U::SAMPLED | U::TRANSFER_SRC;
            Image::new(self.gpu, "window colour", HDR_FORMAT, extent, 1, usage)?
        };
        let desc = OceanDesc {
            scene: scene.clone(),
            width: extent.width,
            height: extent.height,
            formats: HostFormats {
                colour: HDR_FORMAT,
                depth: objects.as_ref().map(|_| DEPTH_FORMAT),
                reversed_z: true,
                ldr: Some(swapchain.choice.format.format),
            },
            frames_in_flight: self.slots.len() as u32,
            sky: true,
            radiance_scale: 1.0,
            shading: Shading { shader: self.shader, ..Shading::default() },
            in_place: objects.is_none().then(|| HostImage::from(&colour)),
            shadow_casters: objects.is_some(),
        };
        let ocean = Ocean::new(self.gpu, desc)?;
        self.drawing = Some(Drawing { ocean, colour, objects });
        self.scene = Some(scene.clone());
        Ok(())
    }

    /// Whether the swapchain's images can be copied out (screenshots of what is shown).
    pub fn can_copy_shown(&self) -> bool {
        self.swapchain.as_ref().is_some_and(|s| s.choice.copyable)
    }

    /// Draws and presents one frame of `scene`.
    pub fn draw(&mut self, scene: &Scene, capture: Capture) -> Result<Drawn> {
        if self.drawing.is_none() || self.swapchain.is_none() {
            return Ok(Drawn::OutOfDate);
        }
        let changed = self.scene.as_ref().is_none_or(|s| !same_but_view(s, scene));
        let waited = std::time::Instant::now();
        let slot = self.next_slot;
        self.next_slot = (slot + 1) % self.slots.len();
        let drawing = self.drawing.as_mut().expect("checked above");
        if self.slots[slot].commands.wait()? {
            drawing.ocean.finished(slot)?;
        }
        let mut wait_ms = waited.elapsed().as_secs_f64() * 1e3;
        if changed {
            // A change the pipelines depend on rebuilds them: every frame in flight is done first.
            self.wait_idle()?;
            let drawing = self.drawing.as_mut().expect("checked above");
            let same_objects = match &drawing.objects {
                Some((objects, _)) => objects.draws(&scene.objects),
                None => scene.objects.is_empty(),
            };
            if same_objects {
                drawing.ocean.set_scene(scene.clone())?;
                self.scene = Some(scene.clone());
            } else {
                // Other objects: other models, and with or without a depth to composite against.
                self.rebuild(scene)?;
            }
        }
        let drawing = self.drawing.as_mut().expect("checked above");
        // Whatever can fail on the host fails here, before an image is acquired.
        let (width, height) = (drawing.colour.extent.width, drawing.colour.extent.height);
        let (view, projection) = scene_view(scene, width as f64 / height as f64, true);
        if let Some((objects, _)) = &drawing.objects {
            drawing.ocean.set_shadow_casters(objects.shadow_casters(scene, view, projection))?;
        }
        drawing.ocean.update(slot, &FrameInput { time_s: scene.render.time_s, view, projection })?;
        if let Some((objects, _)) = &mut drawing.objects {
            objects.update_for(slot, scene, view, projection, &drawing.ocean)?;
        }
        self.prepare_capture(capture)?;
        let swapchain = self.swapchain.as_ref().expect("checked above");
        assert!(capture != Capture::Shown || swapchain.choice.copyable, "check can_copy_shown() first");
        let waited = std::time::Instant::now();
        let (image, suboptimal) = match swapchain.acquire(self.slots[slot].image_available.raw)? {
            Acquired::Image { image, suboptimal } => (image, suboptimal),
            Acquired::OutOfDate => return Ok(Drawn::OutOfDate),
        };
        wait_ms += waited.elapsed().as_secs_f64() * 1e3;
        self.record(slot, image, capture)?;
        let captured = self.read_capture(slot, capture, image)?;
        let swapchain = self.swapchain.as_ref().expect("checked above");
        let presenting = std::time::Instant::now();
        let current = swapchain.present(&image)?;
        let present_ms = presenting.elapsed().as_secs_f64() * 1e3;
        self.retired.retain_mut(|(_, presents_left)| {
            *presents_left = presents_left.saturating_sub(1);
            *presents_left > 0
        });
        Ok(Drawn::Presented { stale: suboptimal || !current, captured, wait_ms, present_ms })
    }

    /// Records and submits the frame in `slot`: the ocean into the colour and the swapchain
    /// `image`, the capture's copy, the image's move to present.
    fn record(&mut self, slot: usize, image: SwapImage, capture: Capture) -> Result<()> {
        let device = &self.gpu.device.raw;
        let drawing = self.drawing.as_mut().expect("drawn only with an ocean");
        let s = &self.slots[slot];
        let cmd = s.commands.cmd;
        s.commands.begin()?;
        let colour = HostImage::from(&drawing.colour);
        let shown = HostImage { raw: image.raw, view: image.view, format: image.format, extent: image.extent };
        // The colour's contents are not kept; the frame before last read it (tone mapping, or a
        // radiance screenshot's copy), earlier on this queue: the ocean's first write waits.
        let stage = vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::COPY;
        let mut colour_entry = ImageState::new(vk::ImageLayout::UNDEFINED, stage, vk::AccessFlags2::NONE);
        let mut depth = None;
        if let Some((objects, depth_image)) = &drawing.objects {
            // The sun's map first (the waves and the objects), which the objects then sample.
            drawing.ocean.record_shadows(cmd, slot, &mut |cmd, _| objects.record_casters(cmd, slot))?;
            // Their mirror images, for the sea's planar reflections, where any is in view.
            if objects.mirrored_in_view(slot) {
                drawing.ocean.record_planar(cmd, slot, objects.mirror_cover(slot), &mut |cmd, _| {
                    objects.record_mirrored(cmd, slot)
                })?;
            }
            // The objects come next: their writes wait for the frame before's reads of the
            // colour, and of the depth for its tests (the frames in flight share both).
            let depth_target = HostImage::from(depth_image);
            let t = &mut self.tracker;
            t.external(&colour, colour_entry.layout, colour_entry.stage, colour_entry.access);
            t.image(&colour, 0, 1, Access::ColorAttachmentWrite, true);
            let tests = ImageState::DEPTH_ATTACHMENT;
            t.external(&depth_target, vk::ImageLayout::UNDEFINED, tests.stage, tests.access);
            t.image(&depth_target, 0, 1, Access::DepthAttachmentReadWrite, true);
            t.flush(device, cmd);
            let name = crate::app::objects::NAME;
            drawing
                .ocean
                .record_host_pass(cmd, slot, name, &mut |cmd| objects.record(cmd, slot, &colour, &depth_target, 0.0))?;
            t.forget(depth_target.raw);
            colour_entry = ImageState::COLOR_ATTACHMENT;
            depth = Some((depth_target, tests));
        }
        let targets = Targets { colour, colour_entry, depth, ldr: Some((shown, ImageState::ACQUIRED)) };
        drawing.ocean.record(cmd, slot, &targets)?;
        // From the exit states embed::Ocean::record documents for a frame with an LDR target.
        let t = &mut self.tracker;
        let drawn = ImageState::COLOR_ATTACHMENT;
        t.external(&shown, drawn.layout, drawn.stage, drawn.access);
        // The buffer stays between screenshots: only a frame that asks copies into it (sized for
        // this capture's texels by prepare_capture).
        if let (Some(buffer), true) = (&self.capture, capture != Capture::None) {
            if capture == Capture::Shown {
                t.image(&shown, 0, 1, Access::TransferRead, false);
            } else {
                let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
                t.external(&colour, read, vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::NONE);
                t.image(&colour, 0, 1, Access::TransferRead, false);
            }
            t.buffer(buffer, Access::TransferWrite);
            t.flush(device, cmd);
            let source = if capture == Capture::Shown { shown } else { colour };
            copy_to_buffer(device, cmd, source.raw, source.extent, buffer.raw);
            t.buffer(buffer, Access::HostRead);
        }
        // The present waits on the render-finished semaphore, signalled after all commands.
        t.image(&shown, 0, 1, Access::Present, false);
        t.flush(device, cmd);
        t.forget(shown.raw);
        t.forget(colour.raw);
        let wait = Wait { semaphore: s.image_available.raw, stages: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT };
        let swapchain = self.swapchain.as_ref().expect("drawn only with a swapchain");
        s.commands.submit(&[wait], Some(swapchain.render_finished[image.index as usize].raw))?;
        drawing.ocean.submitted(slot)
    }

    /// Makes (or keeps) the host buffer a capture is copied into.
    fn prepare_capture(&mut self, capture: Capture) -> Result<()> {
        let Some(drawing) = &self.drawing else { return Ok(()) };
        let texel_bytes = match capture {
            Capture::None => {
                return Ok(());
            }
            Capture::Shown => 4,
            Capture::Radiance => 8,
        };
        let extent = drawing.colour.extent;
        let bytes = texel_bytes * extent.width as u64 * extent.height as u64;
        if self.capture.as_ref().is_none_or(|b| b.size != bytes) {
            if let Some(old) = self.capture.take() {
                self.tracker.forget_buffer(old.raw);
            }
            let usage = vk::BufferUsageFlags::TRANSFER_DST;
            self.capture = Some(Buffer::new(self.gpu, "capture", bytes, usage, Location::Readback)?);
        }
        Ok(())
    }

    /// With a capture, waits for the frame in `slot` and returns its pixels.
    fn read_capture(&mut self, slot: usize, capture: Capture, image: SwapImage) -> Result<Option<Captured>> {
        let (Some(buffer), Some(drawing)) = (&self.capture, &mut self.drawing) else { return Ok(None) };
        if capture == Capture::None {
            return Ok(None);
        }
        self.slots[slot].commands.wait()?;
        drawing.ocean.finished(slot)?;
        let (width, height) = (image.extent.width, image.extent.height);
        let pixels = width as usize * height as usize;
        Ok(Some(if capture == Capture::Shown {
            let mut rgba: Vec<u8> = buffer.read(4 * pixels)?;
            if matches!(image.format, vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM) {
                rgba.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
            }
            Captured::Shown { width, height, rgba }
        } else {
            Captured::Radiance { width, height, rgba: buffer.read_rgba16f(pixels)? }
        }))
    }
}

/// Whether two scenes differ in the camera and the time alone (which come with each frame).
fn same_but_view(a: &Scene, b: &Scene) -> bool {
    let mut b = b.clone();
    b.camera = a.camera.clone();
    b.render.time_s = a.render.time_s;
    *a == b
}
