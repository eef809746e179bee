//! Readback: copies the HDR radiance into a host-visible buffer and makes both readback buffers
//! (the tone-mapped one is written by the tonemap pass) visible to the host.

use super::{Frame, Pass, Recorder};
use crate::render::resources::Resources;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::image::copy_to_buffer;

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
        copy_to_buffer(device, cmd, r.output().raw, r.output().extent, readback.hdr.raw);
        // The CPU reads both buffers after the frame's fence.
        rec.tracker.buffer(&readback.hdr, Access::HostRead);
        rec.tracker.buffer(&readback.ldr, Access::HostRead);
        rec.tracker.flush(device, cmd);
    }
}
