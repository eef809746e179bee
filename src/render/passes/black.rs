//! A frame with nothing to shade (no term and no sky behind the sea, as at night): the HDR
//! image is cleared to black instead of drawing the grid and shading every pixel to zero.

use super::{Frame, Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::{Access, Tracker};
use ash::vk;

pub struct BlackPass;

impl Pass for BlackPass {
    fn name(&self) -> &'static str {
        "black"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(&r.hdr, 0, 1, Access::ClearWrite, true);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let black = vk::ClearColorValue { float32: [0.0, 0.0, 0.0, 1.0] };
        // SAFETY: outside a rendering scope; the image was declared ClearWrite
        // (TRANSFER_DST_OPTIMAL) and was made with TRANSFER_DST usage.
        unsafe {
            rec.device.raw.cmd_clear_color_image(
                rec.cmd,
                r.hdr.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &black,
                &[r.hdr.full_range()],
            )
        };
    }
}
