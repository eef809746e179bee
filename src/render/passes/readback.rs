//! Readback: copies the HDR radiance into a host-visible buffer and makes both readback buffers
//! (the tone-mapped one is written by the tonemap pass) visible to the host.

use super::{Frame, Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::{Access, Tracker};
use ash::vk;

pub struct ReadbackPass;

impl Pass for ReadbackPass {
    fn name(&self) -> &'static str {
        "readback"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(r.output(), 0, 1, Access::TransferRead, false);
        if let Some(readback) = &r.readback {
            t.buffer(&readback.hdr, Access::TransferWrite);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let Some(readback) = &r.readback else { return };
        let region = vk::BufferImageCopy {
            buffer_offset: 0,
            buffer_row_length: 0,
            buffer_image_height: 0,
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_offset: vk::Offset3D::default(),
            image_extent: vk::Extent3D { width: r.output().extent.width, height: r.output().extent.height, depth: 1 },
        };
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (declared); the buffer holds the full image.
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                r.output().raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                readback.hdr.raw,
                &[region],
            );
        }
        // The CPU reads both buffers after the frame's fence.
        rec.tracker.buffer(&readback.hdr, Access::HostRead);
        rec.tracker.buffer(&readback.ldr, Access::HostRead);
        rec.tracker.flush(device, cmd);
    }
}
