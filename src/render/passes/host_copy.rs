//! The radiance copied into a host's colour when the whole frame is the ocean's: the host drew no
//! objects (no depth), the sky fills what the sea does not, the colour's format is the ocean's
//! own and its unit too (radiance scale 1). Compositing then changes no value, so a copy does it
//! at a fraction of a full-screen draw's cost (`ocean render` and the other commands are such
//! hosts).

use super::{Frame, Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::{Access, Tracker};
use ash::vk;

pub struct HostCopyPass;

impl HostCopyPass {
    pub const NAME: &'static str = "host copy";
}

impl Pass for HostCopyPass {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::TransferRead, false);
        if let Some(host) = &f.host {
            t.image(&host.colour, 0, 1, Access::TransferWrite, true);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let Some(host) = rec.frame.host else { return };
        let layers = vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        };
        let extent = r.output().extent;
        let region = vk::ImageCopy {
            src_subresource: layers,
            src_offset: vk::Offset3D::default(),
            dst_subresource: layers,
            dst_offset: vk::Offset3D::default(),
            extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
        };
        // SAFETY: both images were declared (TRANSFER_SRC / TRANSFER_DST_OPTIMAL), share the
        // format (the renderer chose this pass for it) and the extent (embed::Ocean checks it).
        unsafe {
            rec.device.raw.cmd_copy_image(
                rec.cmd,
                r.output().raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                host.colour.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[region],
            )
        };
    }
}
