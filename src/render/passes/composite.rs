//! Composite: the ocean into a host's frame (embed::Ocean). A full-screen triangle writes each
//! pixel's shaded radiance to the host's HDR colour attachment and the sea's depth, in the host's
//! projection, to the host's depth attachment, depth-tested against what the host drew before
//! (glsl/composite.frag). A host without depth drew no objects: the sea covers whatever it
//! reaches, and the host keeps its colour elsewhere only when it draws its own sky. Only in a
//! frame recorded for a host; a host whose whole frame is the ocean's gets a copy instead
//! (passes/host_copy.rs).

use super::{whole_viewport, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::ocean::ShaderConfig;
use crate::render::resources::{Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{graphics_pipeline, Bindings, GraphicsDesc};
use ash::vk;

const RADIANCE_BINDING: u32 = 2;
const SEA_DEPTH_BINDING: u32 = 3;

/// What a host's targets are made of, fixed for the ocean's pipelines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HostFormats {
    /// The HDR colour attachment's format (vk::external::hdr_format_max lists them).
    pub colour: vk::Format,
    /// The depth attachment's format (vk::external::HOST_DEPTH_FORMATS); None: the host draws no
    /// objects of its own and hands no depth (the sea is then not depth-tested).
    pub depth: Option<vk::Format>,
    /// Whether the host's depth is reversed (1 near, 0 far) or standard (0 near, 1 far).
    pub reversed_z: bool,
    /// The LDR target's format, when the ocean also tone-maps the host's frame into one
    /// (vk::external::ldr_encodes_srgb lists them).
    pub ldr: Option<vk::Format>,
}

pub struct CompositePass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// LOAD where pixels keep the host's colour, DONT_CARE where every pixel is written.
    load: vk::AttachmentLoadOp,
}

impl CompositePass<'_> {
    pub const NAME: &'static str = "composite";
}

impl<'g> CompositePass<'g> {
    /// With `config.background`, the sky is written where the host drew nothing (else those
    /// pixels keep the host's); `config.geometry` says whether the grid may be displaced.
    pub fn new(device: &'g Device, r: &Resources, formats: HostFormats, config: ShaderConfig) -> Result<Self> {
        use vk::DescriptorType as D;
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        let bindings = Bindings::new(
            device,
            Self::NAME,
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, fragment),
                (RADIANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, fragment),
                (SEA_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, fragment),
            ],
        )?;
        write_frame_uniforms(&bindings, r, false);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // texelFetch ignores the samplers' filtering; any valid sampler does.
        bindings.write_image(RADIANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, r.output().view, read, r.sky_sampler.raw);
        bindings.write_image(SEA_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, r.depth.view, read, r.depth_sampler.raw);
        let spec = config.specialization();
        // Equal passes too: the sky's fragments lie exactly on the far plane the host cleared to.
        let compare = if formats.reversed_z { vk::CompareOp::GREATER_OR_EQUAL } else { vk::CompareOp::LESS_OR_EQUAL };
        let pipeline = graphics_pipeline(
            device,
            bindings.layout(),
            &GraphicsDesc {
                name: Self::NAME,
                vertex: shaders::FULLSCREEN_VERT,
                fragment: Some(shaders::COMPOSITE_FRAG),
                specialization: Some(&spec),
                color_format: Some(formats.colour),
                depth_format: formats.depth.unwrap_or(vk::Format::UNDEFINED),
                depth_write: formats.depth.is_some(),
                depth_compare: if formats.depth.is_some() { compare } else { vk::CompareOp::ALWAYS },
                depth_bias: None,
                cull_back_faces: None,
            },
        )?;
        // Without depth and with the sky, every pixel is written: the host's colour is not read.
        let load = if formats.depth.is_none() && config.background {
            vk::AttachmentLoadOp::DONT_CARE
        } else {
            vk::AttachmentLoadOp::LOAD
        };
        Ok(CompositePass { bindings, pipeline, load })
    }
}

impl Pass for CompositePass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::FragmentSampled, false);
        t.image(&r.depth, 0, 1, Access::FragmentSampled, false);
        if let Some(host) = &f.host {
            if self.load == vk::AttachmentLoadOp::LOAD {
                // The pixels the sea and sky do not cover keep the host's colour.
                t.image(&host.colour, 0, 1, Access::ColorAttachmentReadWrite, false);
            } else {
                t.image(&host.colour, 0, 1, Access::ColorAttachmentWrite, true);
            }
            if let Some(depth) = &host.depth {
                t.image(depth, 0, 1, Access::DepthAttachmentReadWrite, false);
            }
        }
    }

    fn record(&self, rec: &mut Recorder, _r: &Resources) {
        let Some(host) = rec.frame.host else { return };
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(host.colour.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(self.load)
            .store_op(vk::AttachmentStoreOp::STORE)];
        let depth = host.depth.map(|depth| {
            vk::RenderingAttachmentInfo::default()
                .image_view(depth.view)
                .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::LOAD)
                .store_op(vk::AttachmentStoreOp::STORE)
        });
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: host.colour.extent };
        let mut info = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&color);
        if let Some(depth) = &depth {
            info = info.depth_attachment(depth);
        }
        // SAFETY: the host's attachments are in the layouts declared above (the tracker moved
        // them from the host's stated entry state), the pipeline was built for their formats, and
        // the sampled images were declared FragmentSampled.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_set_viewport(cmd, 0, &[whole_viewport(host.colour.extent)]);
            device.cmd_set_scissor(cmd, 0, &[area]);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
            self.bindings.bind(cmd, vk::PipelineBindPoint::GRAPHICS, &rec.frame.uniform_offsets);
            device.cmd_draw(cmd, 3, 1, 0, 0);
            device.cmd_end_rendering(cmd);
        }
    }
}
