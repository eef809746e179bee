//! Shading, once per pixel (compute): the sea with the paper's BRDF at the rest position the
//! visibility pass (ocean.rs) left in the pixel, the sky where it left none; the radiance
//! replaces those bits in the HDR image.

use super::ocean::ShaderConfig;
use super::{write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{Resources, FRAME_BINDING, WAVES_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings};
use ash::vk;

pub struct ShadePass<'g> {
    bindings: Bindings<'g>,
    /// The sea's shader (and the sky where no sea was drawn).
    sea: Owned<'g, vk::Pipeline>,
    /// The sky's alone, for the top rows that only sky covers.
    sky: Owned<'g, vk::Pipeline>,
}

impl<'g> ShadePass<'g> {
    pub fn new(device: &'g Device, r: &Resources, config: ShaderConfig) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::new(
            device,
            "shade",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (WAVES_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (2, D::COMBINED_IMAGE_SAMPLER, compute),
                (3, D::STORAGE_IMAGE, compute),
            ],
        )?;
        write_frame_uniforms(&bindings, r, true);
        bindings.write_image(
            2,
            D::COMBINED_IMAGE_SAMPLER,
            r.sky_map.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            r.sky_sampler.raw,
        );
        bindings.write_image(3, D::STORAGE_IMAGE, r.hdr.alias_view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        let pipeline = |may_hold_sea: bool, name: &str| {
            let spec = config.specialization(may_hold_sea);
            specialized_compute_pipeline(device, bindings.layout(), shaders::SHADE_COMP, Some(&spec), name)
        };
        Ok(ShadePass { sea: pipeline(true, "shade sea")?, sky: pipeline(false, "shade sky")?, bindings })
    }
}

impl Pass for ShadePass<'_> {
    fn name(&self) -> &'static str {
        "shade"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(&r.sky_map, 0, r.sky_map.mip_levels, Access::ComputeSampled, false);
        t.image(&r.hdr, 0, 1, Access::ComputeStorageReadWrite, false);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let extent = r.hdr.extent;
        // Whole 8-row groups of sky-only rows go to the sky's shader, the rest to the sea's.
        let groups = (extent.width.div_ceil(8), extent.height.div_ceil(8));
        let sky_groups = (rec.frame.sky_rows / 8).min(groups.1);
        self.bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &rec.frame.uniform_offsets);
        for (pipeline, first, count) in [(&self.sky, 0, sky_groups), (&self.sea, sky_groups, groups.1 - sky_groups)] {
            if count == 0 {
                continue;
            }
            // SAFETY: outside a rendering scope; the set (bound above) was made for this layout
            // and the pass's images were declared; the pipelines allow a base group.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                device.cmd_dispatch_base(cmd, 0, first, 0, groups.0, count, 1);
            }
        }
    }
}
