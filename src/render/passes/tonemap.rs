//! Tone mapping: HDR radiance to 8-bit sRGB with the scene's exposure (compute), written straight
//! into the host-visible readback buffer.

use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{Resources, FRAME_BINDING};
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
    /// Needs the resources' readback buffers.
    pub fn new(device: &'g Device, r: &Resources) -> Result<Self> {
        let readback = r.readback.as_ref().expect("an offscreen renderer's resources");
        use vk::DescriptorType as D;
        let stages = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::new(
            device,
            "tonemap",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, stages),
                (4, D::STORAGE_IMAGE, stages),
                (5, D::STORAGE_BUFFER, stages),
            ],
        )?;
        write_frame_uniforms(&bindings, r, false);
        bindings.write_image(4, D::STORAGE_IMAGE, r.output().view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        bindings.write_buffer(5, D::STORAGE_BUFFER, readback.ldr.raw);
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::TONEMAP_COMP, "tonemap")?;
        Ok(TonemapPass { bindings, pipeline })
    }
}

impl Pass for TonemapPass<'_> {
    fn name(&self) -> &'static str {
        "tonemap"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::ComputeStorageRead, false);
        if let Some(readback) = &r.readback {
            t.buffer(&readback.ldr, Access::ComputeStorageWrite);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.output().extent);
    }
}
