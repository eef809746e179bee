//! Reflection sources (compute and blits): what the sea's local reflections read, built from the
//! host's colour and depth after it drew its objects, where the sea's depth (the visibility
//! pass's) leaves them in view, before the shading pass traces the
//! reflected rays (glsl/shade.glsl local_reflection). Level 0 of the objects' premultiplied
//! radiance and of their forward depth (glsl/reflection_sources.comp), the radiance's mipmap by
//! linear blits (each level the mean radiance and coverage of its footprint), the depth's by a
//! nearest-of reduction per level (glsl/reflection_depth_mip.comp). Only in a host's frame with
//! depth whose shading reflects objects. The host's images may change from frame to frame, so
//! each frame slot has its own set, rewritten as the frame is recorded (the slot's previous frame
//! has finished: the host's precondition), with its own view of the host depth's depth aspect.

use super::pyramid::LevelReduction;
use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{ReflectionImages, Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::external::HostImage;
use crate::vk::gpu::Gpu;
use crate::vk::image::{host_depth_view, level_extent};
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, specialized_compute_pipeline, Bindings, Specialization};
use ash::vk;
use std::cell::RefCell;

const HOST_COLOUR_BINDING: u32 = 1;
const HOST_DEPTH_BINDING: u32 = 2;
const SOURCE_COLOUR_BINDING: u32 = 3;
const SOURCE_DEPTH_BINDING: u32 = 4;
const SEA_DEPTH_BINDING: u32 = 5;
/// Cells of the pyramid level the objects' screen rectangle is found from, at most: 64 per
/// invocation of glsl/reflection_bounds.comp's one workgroup of 64 (larger groups sharing
/// memory are advised against).
const BOUNDS_CELLS: u32 = 4096;

/// The host depth view a slot's set names, and the image it views.
type SlotView<'g> = Option<(vk::Image, Owned<'g, vk::ImageView>)>;

pub struct ReflectionsPass<'g> {
    gpu: &'g Gpu,
    /// One set per frame slot, identically laid out.
    sources: Vec<Bindings<'g>>,
    sources_pipeline: Owned<'g, vk::Pipeline>,
    /// The depth's levels from 1, each the nearest of the texels below it.
    mips: LevelReduction<'g>,
    /// The objects' screen rectangle from the pyramid's level `bounds_level`.
    bounds: Bindings<'g>,
    bounds_pipeline: Owned<'g, vk::Pipeline>,
    bounds_level: u32,
    /// Each slot's view of the host depth's depth aspect (made again when the host's image
    /// changes).
    depth_views: RefCell<Vec<SlotView<'g>>>,
}

impl ReflectionsPass<'_> {
    pub const NAME: &'static str = "reflection sources";
}

impl<'g> ReflectionsPass<'g> {
    pub fn new(gpu: &'g Gpu, r: &Resources, images: &ReflectionImages, slots: u32) -> Result<Self> {
        let device: &'g Device = &gpu.device;
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let sources = (0..slots)
            .map(|_| {
                let b = Bindings::new(
                    device,
                    Self::NAME,
                    &[
                        (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                        (HOST_COLOUR_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                        (HOST_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                        (SOURCE_COLOUR_BINDING, D::STORAGE_IMAGE, compute),
                        (SOURCE_DEPTH_BINDING, D::STORAGE_IMAGE, compute),
                        (SEA_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                    ],
                )?;
                write_frame_uniforms(&b, r, false);
                let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
                b.write_image(SEA_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, r.depth.view, read, r.depth_sampler.raw);
                let general = vk::ImageLayout::GENERAL;
                let none = vk::Sampler::null();
                b.write_image(SOURCE_COLOUR_BINDING, D::STORAGE_IMAGE, images.colour.level0_view, general, none);
                b.write_image(SOURCE_DEPTH_BINDING, D::STORAGE_IMAGE, images.depth_levels[0].raw, general, none);
                Ok(b)
            })
            .collect::<Result<Vec<_>>>()?;
        let sources_pipeline =
            compute_pipeline(device, sources[0].layout(), shaders::REFLECTION_SOURCES_COMP, Self::NAME)?;
        let mips = LevelReduction::new(
            device,
            &images.depth_levels,
            shaders::REFLECTION_DEPTH_MIP_COMP,
            "reflection depth mip",
        )?;
        // The finest level with at most BOUNDS_CELLS cells: a few reads per invocation of one
        // workgroup, cells of 16 pixels at 1024 x 768 and 32 at 1920 x 1080.
        let extent = images.depth.extent;
        let bounds_level = (0..images.depth.mip_levels)
            .find(|&l| {
                let cells = level_extent(extent, l);
                cells.width * cells.height <= BOUNDS_CELLS
            })
            .unwrap_or(images.depth.mip_levels - 1);
        let bounds = Bindings::new(
            device,
            "reflection bounds",
            &[(0, D::STORAGE_IMAGE, compute), (1, D::STORAGE_IMAGE, compute), (2, D::STORAGE_BUFFER, compute)],
        )?;
        let general = vk::ImageLayout::GENERAL;
        bounds.write_image(0, D::STORAGE_IMAGE, images.depth_levels[0].raw, general, vk::Sampler::null());
        let coarse = images.depth_levels[bounds_level as usize].raw;
        bounds.write_image(1, D::STORAGE_IMAGE, coarse, general, vk::Sampler::null());
        bounds.write_buffer(2, D::STORAGE_BUFFER, images.bounds.raw);
        let spec = Specialization::words(&[bounds_level]);
        let bounds_pipeline = specialized_compute_pipeline(
            device,
            bounds.layout(),
            shaders::REFLECTION_BOUNDS_COMP,
            Some(&spec),
            "reflection bounds",
        )?;
        Ok(ReflectionsPass {
            gpu,
            sources,
            sources_pipeline,
            mips,
            bounds,
            bounds_pipeline,
            bounds_level,
            depth_views: RefCell::new((0..slots).map(|_| None).collect()),
        })
    }

    /// Slot `slot`'s set pointed at this frame's host images.
    fn bind_host(&self, slot: usize, colour: &HostImage, depth: &HostImage, sampler: vk::Sampler) -> Result<()> {
        let mut views = self.depth_views.borrow_mut();
        if views[slot].as_ref().is_none_or(|(image, _)| *image != depth.raw) {
            // The slot's previous frame, the last user of the old view, has finished.
            views[slot] = Some((depth.raw, host_depth_view(self.gpu, depth)?));
        }
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let b = &self.sources[slot];
        let view = views[slot].as_ref().map(|(_, v)| v.raw).expect("made above");
        b.write_image(HOST_COLOUR_BINDING, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, colour.view, read, sampler);
        b.write_image(HOST_DEPTH_BINDING, vk::DescriptorType::COMBINED_IMAGE_SAMPLER, view, read, sampler);
        Ok(())
    }
}

impl Pass for ReflectionsPass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, f: &Frame, t: &mut Tracker) {
        let Some(images) = &r.reflections else { return };
        if let Some(host) = &f.host {
            t.image(&host.colour, 0, 1, Access::ComputeSampled, false);
            if let Some(depth) = &host.depth {
                t.image(depth, 0, 1, Access::ComputeSampled, false);
            }
        }
        t.image(&r.depth, 0, 1, Access::ComputeSampled, false);
        t.image(&images.colour, 0, 1, Access::ComputeStorageWrite, true);
        t.image(&images.depth, 0, 1, Access::ComputeStorageWrite, true);
        t.buffer(&images.bounds, Access::ComputeStorageWrite);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let (Some(images), Some(host)) = (&r.reflections, rec.frame.host) else { return };
        let Some(depth) = host.depth else { return };
        // texelFetch ignores the sampler's filtering; any valid sampler does.
        if let Err(e) = self.bind_host(rec.frame.slot, &host.colour, &depth, r.depth_sampler.raw) {
            // A view that cannot be made (out of memory) leaves this frame without reflections.
            crate::say!("local reflections left out this frame: {e}");
            return;
        }
        dispatch_over(rec, self.sources_pipeline.raw, &self.sources[rec.frame.slot], images.colour.extent);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        // The radiance's levels: each the linear mean of the one above.
        let colour = &images.colour;
        crate::vk::image::mipmap(device, cmd, rec.tracker, colour);
        rec.tracker.image(colour, 0, colour.mip_levels, Access::ComputeSampled, false);
        // The depth's levels: each the nearest of the texels below it.
        self.mips.record(rec, &images.depth);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        // The rectangle, from the level written last or before (level 0 is bound for its size).
        rec.tracker.image(&images.depth, 0, 1, Access::ComputeStorageRead, false);
        rec.tracker.image(&images.depth, self.bounds_level, 1, Access::ComputeStorageRead, false);
        rec.tracker.flush(device, cmd);
        // SAFETY: `cmd` is recording outside a rendering scope; the set was made for this
        // pipeline's layout and its images and buffer were declared above.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.bounds_pipeline.raw) };
        self.bounds.bind(cmd, vk::PipelineBindPoint::COMPUTE, &[]);
        // SAFETY: as above.
        unsafe { device.cmd_dispatch(cmd, 1, 1, 1) };
        rec.tracker.image(&images.depth, 0, images.depth.mip_levels, Access::ComputeSampled, false);
        rec.tracker.flush(device, cmd);
    }
}
