//! Semaphores and fences, owned (destroyed when dropped).

use super::device::Device;
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;

pub fn semaphore<'g>(device: &'g Device, name: &str) -> Result<Owned<'g, vk::Semaphore>> {
    // SAFETY: a plain binary semaphore on a live device.
    let raw = unsafe { device.raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
        .during("vkCreateSemaphore")?;
    Ok(Owned::new(device, raw, name))
}

/// A fence, created signalled when `signalled` (so that the first wait on it returns at once).
pub fn fence<'g>(device: &'g Device, name: &str, signalled: bool) -> Result<Owned<'g, vk::Fence>> {
    let flags = if signalled { vk::FenceCreateFlags::SIGNALED } else { vk::FenceCreateFlags::empty() };
    // SAFETY: a plain fence on a live device.
    let raw = unsafe { device.raw.create_fence(&vk::FenceCreateInfo::default().flags(flags), None) }
        .during("vkCreateFence")?;
    Ok(Owned::new(device, raw, name))
}
