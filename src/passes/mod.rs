//! The frame's passes, in order. Each declares what it reads and writes; the frame derives the
//! barriers from those declarations (vk::barrier), then records the pass inside a debug label
//! and a timestamp scope of the pass's name.

pub mod ocean;
pub mod readback;
pub mod resolve;
pub mod sky_map;
pub mod tonemap;

use crate::resources::Resources;
use crate::vk::barrier::Tracker;
use crate::vk::device::Device;
use ash::vk;

pub struct Recorder<'a> {
    pub device: &'a Device,
    pub cmd: vk::CommandBuffer,
    pub tracker: &'a mut Tracker,
}

pub trait Pass {
    fn name(&self) -> &'static str;
    /// Declares every resource access of the pass (queued as barriers on the tracker).
    fn declare(&self, resources: &Resources, tracker: &mut Tracker);
    fn record(&self, rec: &mut Recorder, resources: &Resources);
    /// Whether the pass only (re)builds the sky map, which a frame under the same sky can skip.
    fn builds_sky_map(&self) -> bool {
        false
    }
}

pub fn dispatch_size(extent: vk::Extent2D, local: u32) -> (u32, u32) {
    (extent.width.div_ceil(local), extent.height.div_ceil(local))
}
