//! Tone mapping: HDR radiance to 8-bit sRGB with the scene's exposure (compute), written straight
//! into the host-visible readback buffer.

use super::{dispatch_over, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::Resources;
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

pub struct TonemapPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> TonemapPass<'g> {
    pub fn new(device: &'g Device, r: &Resources) -> Result<Self> {
        use vk::DescriptorType as D;
        let stages = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::new(
            device,
            "tonemap",
            &[(0, D::UNIFORM_BUFFER, stages), (4, D::STORAGE_IMAGE, stages), (5, D::STORAGE_BUFFER, stages)],
        )?;
        bindings.write_buffer(0, D::UNIFORM_BUFFER, r.frame_uniforms.raw);
        bindings.write_image(4, D::STORAGE_IMAGE, r.output().view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        bindings.write_buffer(5, D::STORAGE_BUFFER, r.ldr_readback.raw);
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::TONEMAP_COMP, "tonemap")?;
        Ok(TonemapPass { bindings, pipeline })
    }
}

impl Pass for TonemapPass<'_> {
    fn name(&self) -> &'static str {
        "tonemap"
    }

    fn declare(&self, r: &Resources, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::ComputeStorageRead, false);
        t.buffer(&r.ldr_readback, Access::ComputeStorageWrite);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.output().extent);
    }
}
