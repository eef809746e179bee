//! One primary command buffer with its pool and fence: begin, record, submit and wait. Every
//! frame, ground-truth tile and harness call goes through one of these.

use super::device::Device;
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;

pub struct Commands<'g> {
    device: &'g Device,
    pub cmd: vk::CommandBuffer,
    // Drop order: the fence, then the pool (which frees `cmd`).
    fence: Owned<'g, vk::Fence>,
    _pool: Owned<'g, vk::CommandPool>,
}

impl<'g> Commands<'g> {
    pub fn new(device: &'g Device, name: &str) -> Result<Self> {
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(device.queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: valid create info on a live device.
        let pool = unsafe { device.raw.create_command_pool(&pool_info, None) }.during("vkCreateCommandPool")?;
        let pool = Owned::new(device, pool, name);
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool.raw)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: one primary buffer from the pool just made.
        let cmd = unsafe { device.raw.allocate_command_buffers(&alloc) }.during("vkAllocateCommandBuffers")?[0];
        device.set_name(cmd, name);
        // SAFETY: a plain fence on a live device.
        let fence =
            unsafe { device.raw.create_fence(&vk::FenceCreateInfo::default(), None) }.during("vkCreateFence")?;
        let fence = Owned::new(device, fence, &format!("{name} done"));
        Ok(Commands { device, cmd, fence, _pool: pool })
    }

    /// Begins a one-time recording; the previous submission has completed (submit_and_wait).
    pub fn begin(&self) -> Result<()> {
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the buffer is not pending: every submission is waited on before the next begin.
        unsafe { self.device.raw.begin_command_buffer(self.cmd, &begin) }.during("vkBeginCommandBuffer")
    }

    /// Ends the recording, submits it and waits until the GPU has finished it.
    pub fn submit_and_wait(&self) -> Result<()> {
        let raw = &self.device.raw;
        let cmds = [self.cmd];
        let submit = vk::SubmitInfo::default().command_buffers(&cmds);
        // SAFETY: recording began in `begin`; the fence is unsignalled (reset after every wait);
        // host writes to mapped memory made before the submit are visible to the device
        // (vkQueueSubmit's implicit host-write ordering).
        unsafe {
            raw.end_command_buffer(self.cmd).during("vkEndCommandBuffer")?;
            raw.queue_submit(self.device.queue, &[submit], self.fence.raw).during("vkQueueSubmit")?;
            raw.wait_for_fences(&[self.fence.raw], true, u64::MAX).during("vkWaitForFences")?;
            raw.reset_fences(&[self.fence.raw]).during("vkResetFences")
        }
    }
}
