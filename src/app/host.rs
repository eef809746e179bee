//! The commands' host of the ocean library: an offscreen frame drawn through `embed::Ocean` as
//! any engine would draw it. It owns an HDR colour image and an LDR image, a command buffer and
//! its fence, and reads both images back itself. A scene with `[[object]]`s has them drawn first
//! (app::objects) into the colour image and a depth image the ocean then depth-tests against.
//! Without objects it hands no depth: the ocean then owns every pixel and draws them in the
//! host's colour image in place (embed::OceanDesc::in_place), with nothing to composite. `render`,
//! `animate` and `profile` run through it; `view` hosts the ocean in its window the same way
//! (app/window/presenter.rs).

use crate::app::objects::{Objects, DEPTH_FORMAT};
use crate::embed::camera::scene_view;
use crate::embed::{
    FrameInput, GpuFrame, HostFormats, HostImage, ImageState, Ocean, OceanDesc, Shading, Targets, IN_PLACE_USAGE,
    IN_PLACE_VIEW_FORMATS,
};
use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::render::renderer::RenderedFrame;
use crate::render::timeline::{CpuSpans, Submission};
use crate::vk::barrier::{Access, Tracker};
use crate::vk::buffer::Buffer;
use crate::vk::clock::{host_now_ns, DeviceClock};
use crate::vk::commands::Commands;
use crate::vk::device::HDR_FORMAT;
use crate::vk::gpu::Gpu;
use crate::vk::image::{copy_to_buffer, Image};
use crate::vk::memory::Location;
use crate::vk::profiler::Profiler;
use ash::vk;

/// The LDR image's format: 8-bit UNORM, the tone mapping encodes sRGB (as a PNG stores it).
const LDR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The host's own pass: copying its two images to the CPU.
const READBACK: &str = "readback";

pub struct OffscreenHost<'g> {
    gpu: &'g Gpu,
    // Field order is drop order: the ocean (which waits for the device) before what it drew into.
    ocean: Ocean<'g>,
    commands: Commands<'g>,
    profiler: Profiler<'g>,
    clock: DeviceClock,
    tracker: Tracker,
    colour: Image<'g>,
    ldr: Image<'g>,
    /// The objects and the depth they are drawn with, where the scene has any.
    objects: Option<(Objects<'g>, Image<'g>)>,
    hdr_readback: Buffer<'g>,
    ldr_readback: Buffer<'g>,
    /// The CPU's steps of the last frame.
    cpu_spans: CpuSpans,
    /// The last frame's passes on the host clock, the host's readback among them.
    gpu_frame: Option<GpuFrame>,
}

impl<'g> OffscreenHost<'g> {
    /// A host of `width` x `height` frames of `scene` shaded as `shading` says; with
    /// `shading.shader.background` off the sky is black.
    pub fn new(gpu: &'g Gpu, scene: &Scene, width: u32, height: u32, shading: Shading) -> Result<Self> {
        // An ocean of no pixels is paused (a minimized window's); a picture needs some.
        if width == 0 || height == 0 {
            return Err(Error::Argument(format!("image size {width}x{height}: width and height must be at least 1")));
        }
        let extent = vk::Extent2D { width, height };
        use vk::ImageUsageFlags as U;
        // Without objects the frame is wholly the ocean's (the sky black where the shading leaves
        // it out): drawn in the colour image in place, or with supersampling resolved and copied
        // into it.
        let objects = if scene.objects.is_empty() {
            None
        } else {
            let objects = Objects::new(gpu, &scene.objects, HDR_FORMAT, DEPTH_FORMAT, true, 1)?;
            // Sampled too: the sea's reflections of the objects read it.
            let depth =
                Image::new(gpu, "host depth", DEPTH_FORMAT, extent, 1, U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED)?;
            Some((objects, depth))
        };
        let in_place = shading.ssaa == 1 && objects.is_none();
        let colour = if in_place {
            Image::aliased(gpu, "host colour", HDR_FORMAT, IN_PLACE_VIEW_FORMATS[1], extent, IN_PLACE_USAGE)?
        } else {
            let usage = U::COLOR_ATTACHMENT | U::SAMPLED | U::TRANSFER_DST | U::TRANSFER_SRC;
            Image::new(gpu, "host colour", HDR_FORMAT, extent, 1, usage)?
        };
        let ldr = Image::new(gpu, "host ldr", LDR_FORMAT, extent, 1, U::COLOR_ATTACHMENT | U::TRANSFER_SRC)?;
        let desc = OceanDesc {
            scene: scene.clone(),
            width,
            height,
            formats: HostFormats {
                colour: HDR_FORMAT,
                depth: objects.as_ref().map(|_| DEPTH_FORMAT),
                reversed_z: true,
                ldr: Some(LDR_FORMAT),
            },
            frames_in_flight: 1,
            sky: true,
            radiance_scale: 1.0,
            shading,
            in_place: in_place.then(|| HostImage::from(&colour)),
            shadow_casters: objects.is_some(),
        };
        let ocean = Ocean::new(gpu, desc)?;
        let pixels = width as u64 * height as u64;
        let usage = vk::BufferUsageFlags::TRANSFER_DST;
        Ok(OffscreenHost {
            gpu,
            ocean,
            commands: Commands::new(&gpu.device, "host frame")?,
            // Its own scope: the readback (the objects are timed in the ocean's frame, as a host
            // pass: embed::Ocean::record_host_pass).
            profiler: Profiler::new(&gpu.device, 1, false)?,
            clock: DeviceClock::new(&gpu.device),
            tracker: Tracker::default(),
            colour,
            ldr,
            objects,
            hdr_readback: Buffer::new(gpu, "host hdr readback", 8 * pixels, usage, Location::Readback)?,
            ldr_readback: Buffer::new(gpu, "host ldr readback", 4 * pixels, usage, Location::Readback)?,
            cpu_spans: CpuSpans::default(),
            gpu_frame: None,
        })
    }

    pub fn ocean(&self) -> &Ocean<'g> {
        &self.ocean
    }

    pub fn ocean_mut(&mut self) -> &mut Ocean<'g> {
        &mut self.ocean
    }

    /// The CPU's steps of the last frame (the ocean's update, recording, submit, the fence,
    /// readback).
    pub fn cpu_spans(&self) -> &CpuSpans {
        &self.cpu_spans
    }

    /// The last frame's passes on the host clock, with their statistics where asked.
    pub fn gpu_frame(&self) -> Option<&GpuFrame> {
        self.gpu_frame.as_ref()
    }

    /// Draws `scene` (the ocean's scene with its time and camera) from its own camera, waits for
    /// it and reads it back.
    pub fn render(&mut self, scene: &Scene) -> Result<RenderedFrame> {
        let (width, height) = (self.colour.extent.width, self.colour.extent.height);
        self.cpu_spans.clear();
        let t = host_now_ns();
        let (view, projection) = scene_view(scene, width as f64 / height as f64, true);
        if let Some((objects, _)) = &self.objects {
            self.ocean.set_shadow_casters(objects.shadow_casters(scene, view, projection))?;
        }
        self.ocean.update(0, &FrameInput { time_s: scene.render.time_s, view, projection })?;
        self.cpu_spans.push("scene and waves", t);
        if let Some((objects, _)) = &mut self.objects {
            let t = host_now_ns();
            objects.update_for(0, scene, view, projection, &self.ocean)?;
            self.cpu_spans.push("objects", t);
        }
        let t = host_now_ns();
        self.record()?;
        self.cpu_spans.push("record", t);
        let t = host_now_ns();
        self.commands.submit(&[], None)?;
        self.ocean.submitted(0)?;
        let submission = Submission { submit_ns: host_now_ns(), calibration: self.clock.calibrate(&self.gpu.device)? };
        self.cpu_spans.push("submit", t);
        let t = host_now_ns();
        self.commands.wait()?;
        let fence_ns = host_now_ns();
        self.ocean.finished(0)?;
        self.cpu_spans.push("wait for fence", t);
        let t = host_now_ns();
        let pixels = width as usize * height as usize;
        let hdr = self.hdr_readback.read_rgba16f(pixels)?;
        let ldr = self.ldr_readback.read(4 * pixels)?;
        self.cpu_spans.push("readback", t);
        let scopes = self.profiler.read_scopes(&self.gpu.device.raw)?.unwrap_or_default();
        let mut pass_ms: Vec<(String, f64)> = self.ocean.pass_ms().iter().map(|&(n, ms)| (n.to_owned(), ms)).collect();
        if !pass_ms.is_empty() {
            pass_ms.extend(scopes.iter().map(|s| (s.name.to_owned(), s.ms())));
        }
        self.gpu_frame = self.ocean.last_gpu_frame().cloned().map(|mut frame| {
            let own = GpuFrame::new(&scopes, submission, fence_ns, &self.clock);
            frame.passes.extend(own.passes);
            frame.fence_ns = fence_ns;
            frame
        });
        let frame = self.ocean.last_frame().cloned().expect("a recorded frame");
        let planar_cover_share = self.ocean.planar_cover_share();
        let packets = self.ocean.packet_stats();
        Ok(RenderedFrame { width, height, hdr, ldr, pass_ms, frame, planar_cover_share, packets })
    }

    /// Records the ocean into the host's images, then the host's readback of both.
    fn record(&mut self) -> Result<()> {
        let (device, cmd) = (&self.gpu.device, self.commands.cmd);
        self.commands.begin()?;
        self.profiler.reset(&device.raw, cmd);
        let (colour, ldr) = (HostImage::from(&self.colour), HostImage::from(&self.ldr));
        // The last frame's contents are not kept; the readback's copies are done (the fence).
        let discarded =
            ImageState::new(vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
        let mut targets = Targets { colour, colour_entry: discarded, depth: None, ldr: Some((ldr, discarded)) };
        if let Some((objects, depth_image)) = &self.objects {
            // The sun's map first (the waves and the objects), which the objects then sample.
            self.ocean.record_shadows(cmd, 0, &mut |cmd, _| objects.record_casters(cmd, 0))?;
            // Their mirror images, for the sea's planar reflections, where any is in view.
            if objects.mirrored_in_view(0) {
                self.ocean
                    .record_planar(cmd, 0, objects.mirror_cover(0), &mut |cmd, _| objects.record_mirrored(cmd, 0))?;
            }
            let depth = HostImage::from(depth_image);
            self.tracker.image(&colour, 0, 1, Access::ColorAttachmentWrite, true);
            self.tracker.image(&depth, 0, 1, Access::DepthAttachmentReadWrite, true);
            self.tracker.flush(&device.raw, cmd);
            // Reversed Z: the far plane is 0. Timed in the ocean's profile, as a host's pass.
            let name = crate::app::objects::NAME;
            self.ocean.record_host_pass(cmd, 0, name, &mut |cmd| objects.record(cmd, 0, &colour, &depth, 0.0))?;
            targets.colour_entry = ImageState::COLOR_ATTACHMENT;
            targets.depth = Some((depth, ImageState::DEPTH_ATTACHMENT));
            self.tracker.forget(depth.raw);
        }
        self.ocean.record(cmd, 0, &targets)?;
        // The exit states embed::Ocean::record documents for a frame with an LDR target.
        self.tracker.external(
            &colour,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::NONE,
        );
        let written = ImageState::COLOR_ATTACHMENT;
        self.tracker.external(&ldr, written.layout, written.stage, written.access);
        self.profiler.begin(device, cmd, READBACK);
        self.tracker.image(&colour, 0, 1, Access::TransferRead, false);
        self.tracker.image(&ldr, 0, 1, Access::TransferRead, false);
        self.tracker.buffer(&self.hdr_readback, Access::TransferWrite);
        self.tracker.buffer(&self.ldr_readback, Access::TransferWrite);
        self.tracker.flush(&device.raw, cmd);
        for (image, buffer) in [(&self.colour, &self.hdr_readback), (&self.ldr, &self.ldr_readback)] {
            copy_to_buffer(&device.raw, cmd, image.raw, image.extent, buffer.raw);
        }
        self.tracker.buffer(&self.hdr_readback, Access::HostRead);
        self.tracker.buffer(&self.ldr_readback, Access::HostRead);
        self.tracker.flush(&device.raw, cmd);
        self.profiler.end(device, cmd);
        // Each frame enters from its stated states, not from what the tracker last saw.
        self.tracker.forget(colour.raw);
        self.tracker.forget(ldr.raw);
        Ok(())
    }
}
