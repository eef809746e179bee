//! Tone mapping: HDR radiance to 8-bit sRGB with the scene's exposure (compute), written straight
//! into the host-visible readback buffer.

use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::exposure::Tone;
use crate::render::resources::{Resources, EXPOSURE_BINDING, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings};
use ash::vk;

pub struct TonemapPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// Whether the exposure is the exposure pass's measurement.
    auto: bool,
}

impl<'g> TonemapPass<'g> {
    /// Needs the resources' readback buffers.
    pub fn new(device: &'g Device, r: &Resources, tone: Tone) -> Result<Self> {
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
                (EXPOSURE_BINDING, D::UNIFORM_BUFFER, stages),
            ],
        )?;
        bindings.write_buffer(EXPOSURE_BINDING, D::UNIFORM_BUFFER, r.exposure.raw);
        write_frame_uniforms(&bindings, r, false);
        bindings.write_image(4, D::STORAGE_IMAGE, r.output().view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        bindings.write_buffer(5, D::STORAGE_BUFFER, readback.ldr.raw);
        let spec = tone.specialization(false);
        let pipeline =
            specialized_compute_pipeline(device, bindings.layout(), shaders::TONEMAP_COMP, Some(&spec), "tonemap")?;
        Ok(TonemapPass { bindings, pipeline, auto: tone.auto })
    }
}

impl Pass for TonemapPass<'_> {
    fn name(&self) -> &'static str {
        "tonemap"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::ComputeStorageRead, false);
        if self.auto {
            t.buffer(&r.exposure, Access::ComputeUniformRead);
        }
        if let Some(readback) = &r.readback {
            t.buffer(&readback.ldr, Access::ComputeStorageWrite);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.output().extent);
    }
}
