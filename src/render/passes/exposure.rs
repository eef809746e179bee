//! Automatic exposure (compute, render.ev100 = "auto"): the frame's log-average luminance into the
//! measured-exposure block that the tone mapping reads (glsl/exposure.comp). Also the tone
//! mapping's specialization, shared by the offscreen and the window's passes.

use super::{Frame, Pass, Recorder};
use crate::error::Result;
use crate::model::scene::{Exposure, Scene, ToneCurve};
use crate::render::resources::{Resources, EXPOSURE_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings, Specialization};
use ash::vk;

/// The tone mapping's specialization (glsl/tone.glsl): the curve and where the exposure comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Tone {
    pub filmic: bool,
    pub auto: bool,
}

impl Tone {
    pub fn of(scene: &Scene) -> Tone {
        Tone { filmic: scene.render.tone_curve == ToneCurve::Filmic, auto: scene.render.exposure() == Exposure::Auto }
    }

    /// Constants 0 (the display's sRGB encoding), 1 (filmic) and 2 (automatic exposure).
    pub fn specialization(&self, encode_srgb: bool) -> Specialization {
        Specialization::words(&[encode_srgb as u32, self.filmic as u32, self.auto as u32])
    }
}

pub struct ExposurePass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> ExposurePass<'g> {
    pub fn new(device: &'g Device, r: &Resources) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::new(
            device,
            "exposure",
            &[(4, D::STORAGE_IMAGE, compute), (EXPOSURE_BINDING, D::STORAGE_BUFFER, compute)],
        )?;
        bindings.write_image(4, D::STORAGE_IMAGE, r.output().view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        bindings.write_buffer(EXPOSURE_BINDING, D::STORAGE_BUFFER, r.exposure.raw);
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::EXPOSURE_COMP, "exposure")?;
        Ok(ExposurePass { bindings, pipeline })
    }
}

impl Pass for ExposurePass<'_> {
    fn name(&self) -> &'static str {
        "exposure"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::ComputeStorageRead, false);
        t.buffer(&r.exposure, Access::ComputeStorageWrite);
    }

    fn record(&self, rec: &mut Recorder, _r: &Resources) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        // SAFETY: outside a rendering scope; the set was made for this pipeline's layout and the
        // pass's resources were declared. One workgroup reduces the whole image.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.raw) };
        self.bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &[]);
        // SAFETY: as above.
        unsafe { device.cmd_dispatch(cmd, 1, 1, 1) };
    }
}
