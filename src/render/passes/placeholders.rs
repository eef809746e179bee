//! The placeholder images cleared to zero (resources::Resources::placeholders): they stand in
//! for the sky map, the aerial perspective, the eye's sky or the shadow map where a frame leaves
//! those out, so that every sampled binding reads defined texels. Once for a sky: a later frame
//! under the same sky skips it.

use super::{Frame, Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::{Access, Tracker};
use ash::vk;

pub struct PlaceholdersPass;

impl Pass for PlaceholdersPass {
    fn name(&self) -> &'static str {
        "placeholders"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        for image in r.placeholders() {
            let access = if is_depth(image) { Access::DepthAttachmentReadWrite } else { Access::ClearWrite };
            t.image(image, 0, image.mip_levels, access, true);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        for image in r.placeholders() {
            if is_depth(image) {
                // A depth image is cleared as an attachment, its load op (the way every GPU
                // clears depth cheapest).
                let depth = vk::RenderingAttachmentInfo::default()
                    .image_view(image.view)
                    .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 },
                    });
                let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: image.extent };
                let info = vk::RenderingInfo::default().render_area(area).layer_count(1).depth_attachment(&depth);
                // SAFETY: the image was declared a depth attachment (DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
                // and made with that usage.
                unsafe {
                    rec.device.raw.cmd_begin_rendering(rec.cmd, &info);
                    rec.device.raw.cmd_end_rendering(rec.cmd);
                }
            } else {
                let zero = vk::ClearColorValue { float32: [0.0; 4] };
                let layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                // SAFETY: outside a rendering scope; the image was declared ClearWrite
                // (TRANSFER_DST_OPTIMAL) and placeholders are made with TRANSFER_DST usage.
                unsafe {
                    rec.device.raw.cmd_clear_color_image(rec.cmd, image.raw, layout, &zero, &[image.full_range()])
                };
            }
        }
    }

    fn builds_for_sky(&self) -> bool {
        true
    }
}

fn is_depth(image: &crate::vk::image::Image) -> bool {
    image.aspect.contains(vk::ImageAspectFlags::DEPTH)
}
