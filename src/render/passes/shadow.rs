//! The sun's shadow map: the visibility pass's displaced grid (the same vertices, trains and
//! filtering) drawn depth-only from the sun (sun_shadow.rs fits the view), for the shading pass
//! to shadow the reflected sun where a resolved crest stands between a facet and the sun; a host's
//! shadow casters are drawn into it too (embed::Ocean::record_shadows), for the sea and the
//! host's objects to be shadowed by them. Frames whose sun has no view (down, or nothing displaced
//! and no casters) only clear it, to "lit".

use super::ocean::ShaderConfig;
use super::packets::{
    declare_packet_reads, write_packet_bindings, PACKETS_BINDING_READ, PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE,
};
use super::{whole_viewport, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{Resources, FRAME_BINDING, WAVES_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::{Device, DEPTH_FORMAT};
use crate::vk::owned::Owned;
use crate::vk::pipeline::{graphics_pipeline, Bindings, GraphicsDesc};
use ash::vk;

/// Depth bias of the sun's view, in the units Vulkan defines: the constant in steps of the
/// depth's float precision, the slope in multiples of the triangle's depth change per texel.
/// A receiver sits on the same triangles it is compared with; between the texel centres that
/// the comparison blends (2 x 2, or the nearest) its depth differs from theirs by up to 1.5
/// texels' worth of its slope (half a texel to the nearest centre, one more across the blend).
pub const DEPTH_BIAS: (f32, f32) = (4.0, 1.5);

/// What a host's shadow casters are drawn with into the sun's map (embed::Ocean::record_shadows),
/// inside the pass's rendering scope, its viewport and scissor the map's: a depth-only pipeline
/// for DEPTH_FORMAT (no colour attachment), compare LESS, bias DEPTH_BIAS.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CasterView {
    /// Camera-relative world (z up, m) to the map's clip space: depth 0 nearest the sun, 1 the
    /// farthest that the map holds.
    pub clip_from_relative: glam::Mat4,
}

/// A host's casters, drawn with their view.
pub type Casters<'a, 'f> = (CasterView, &'a mut (dyn FnMut(vk::CommandBuffer, &CasterView) + 'f));

pub struct ShadowPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> ShadowPass<'g> {
    pub const NAME: &'static str = "sun shadow";

    pub fn new(device: &'g Device, r: &Resources, config: ShaderConfig) -> Result<Self> {
        use vk::DescriptorType as D;
        let vertex = vk::ShaderStageFlags::VERTEX;
        let bindings = Bindings::new(
            device,
            "sun shadow",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, vertex),
                (WAVES_BINDING, D::UNIFORM_BUFFER_DYNAMIC, vertex),
                (PACKETS_BINDING_READ, PACKET_READ_TYPE, vertex),
                (PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE, vertex),
            ],
        )?;
        write_frame_uniforms(&bindings, r, true);
        write_packet_bindings(&bindings, r);
        let spec = config.sun_view_specialization();
        let pipeline = graphics_pipeline(
            device,
            bindings.layout(),
            &GraphicsDesc {
                name: "sun shadow",
                vertex: shaders::OCEAN_VERT,
                fragment: None,
                specialization: Some(&spec),
                color_format: None,
                depth_format: DEPTH_FORMAT,
                depth_write: true,
                depth_compare: vk::CompareOp::LESS, // 0 nearest the sun
                depth_bias: Some(DEPTH_BIAS),
                cull_back_faces: None,
            },
        )?;
        Ok(ShadowPass { bindings, pipeline })
    }
}

impl Pass for ShadowPass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(&r.shadow_map, 0, 1, Access::DepthAttachmentReadWrite, true);
        declare_packet_reads(r, t, Access::VertexSampled);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        self.record_casting(rec, r, None);
    }
}

impl ShadowPass<'_> {
    /// The pass, with a host's `casters` drawn after the grid (none where the sun has no view).
    pub fn record_casting(&self, rec: &mut Recorder, r: &Resources, casters: Option<Casters>) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let extent = r.shadow_map.extent;
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(r.shadow_map.view)
            .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } });
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let info = vk::RenderingInfo::default().render_area(area).layer_count(1).depth_attachment(&depth);
        let viewport = whole_viewport(extent);
        // SAFETY: the map is in the layout declared above; the pipeline was built for its format
        // and no colour attachment; the slot's index buffer holds `count` valid indices.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            if rec.frame.sun_view {
                device.cmd_set_viewport(cmd, 0, &[viewport]);
                device.cmd_set_scissor(cmd, 0, &[area]);
            }
            if let (Some((indices, count)), true) = (rec.frame.grid, rec.frame.sun_view) {
                self.bindings.bind(cmd, vk::PipelineBindPoint::GRAPHICS, &rec.frame.uniform_offsets);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
                device.cmd_bind_index_buffer(cmd, indices, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, count, 1, 0, 0, 0);
            }
        }
        if let (Some((view, draw)), true) = (casters, rec.frame.sun_view) {
            draw(cmd, &view);
        }
        // SAFETY: the scope begun above, the host's draws recorded inside it.
        unsafe { device.cmd_end_rendering(cmd) };
    }
}
