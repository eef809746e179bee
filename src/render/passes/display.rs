//! Display: the HDR radiance tone-mapped into the window's swapchain image (a full-screen
//! triangle, one texel per pixel, the same curve as the offscreen tonemap pass).

use super::{colour_only_pipeline, draw_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::exposure::Tone;
use crate::render::resources::{Resources, EXPOSURE_BINDING, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::Bindings;
use ash::vk;

pub struct DisplayPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// Whether the exposure is the exposure pass's measurement.
    auto: bool,
}

impl<'g> DisplayPass<'g> {
    /// For swapchain images of `format`; `encode_srgb`: the format is UNORM and the shader encodes.
    pub fn new(device: &'g Device, r: &Resources, format: vk::Format, encode_srgb: bool, tone: Tone) -> Result<Self> {
        use vk::DescriptorType as D;
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        let bindings = Bindings::new(
            device,
            "display",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, fragment),
                (4, D::COMBINED_IMAGE_SAMPLER, fragment),
                (EXPOSURE_BINDING, D::UNIFORM_BUFFER, fragment),
            ],
        )?;
        bindings.write_buffer(EXPOSURE_BINDING, D::UNIFORM_BUFFER, r.exposure.raw);
        write_frame_uniforms(&bindings, r, false);
        // texelFetch ignores the sampler's filtering; any valid sampler does.
        bindings.write_image(
            4,
            D::COMBINED_IMAGE_SAMPLER,
            r.output().view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            r.sky_sampler.raw,
        );
        let spec = tone.specialization(encode_srgb);
        let pipeline =
            colour_only_pipeline(device, bindings.layout(), "display", shaders::DISPLAY_FRAG, &spec, format)?;
        Ok(DisplayPass { bindings, pipeline, auto: tone.auto })
    }
}

impl Pass for DisplayPass<'_> {
    fn name(&self) -> &'static str {
        "display"
    }

    fn declare(&self, r: &Resources, f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::FragmentSampled, false);
        if self.auto {
            t.buffer(&r.exposure, Access::FragmentUniformRead);
        }
        if let Some(image) = &f.swap_image {
            t.image(image, 0, 1, Access::ColorAttachmentWrite, true);
        }
    }

    fn record(&self, rec: &mut Recorder, _r: &Resources) {
        let Some(image) = rec.frame.swap_image else { return };
        draw_over(rec, self.pipeline.raw, &self.bindings, image.view, image.extent);
    }
}
