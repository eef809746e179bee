//! Display: the HDR radiance tone-mapped into the window's swapchain image (a full-screen
//! triangle, one texel per pixel, the same curve as the offscreen tonemap pass).

use super::{write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::exposure::Tone;
use crate::render::resources::{Resources, EXPOSURE_BINDING, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{graphics_pipeline, Bindings, GraphicsDesc};
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
        let pipeline = graphics_pipeline(
            device,
            bindings.layout(),
            &GraphicsDesc {
                name: "display",
                vertex: shaders::FULLSCREEN_VERT,
                fragment: Some(shaders::DISPLAY_FRAG),
                specialization: Some(&spec),
                color_format: Some(format),
                depth_format: vk::Format::UNDEFINED,
                depth_write: false,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_bias: None,
            },
        )?;
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
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(image.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::DONT_CARE) // every pixel is written
            .store_op(vk::AttachmentStoreOp::STORE)];
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: image.extent };
        let info = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&color);
        let viewport = vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: image.extent.width as f32,
            height: image.extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        };
        // SAFETY: the swapchain image is in COLOR_ATTACHMENT_OPTIMAL and the radiance in
        // SHADER_READ_ONLY_OPTIMAL (declared); the pipeline was built for the image's format.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
            self.bindings.bind(cmd, vk::PipelineBindPoint::GRAPHICS, &rec.frame.uniform_offsets);
            device.cmd_draw(cmd, 3, 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
    }
}
