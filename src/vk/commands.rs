//! One primary command buffer with its pool and fence: begin, record, submit, and wait for the
//! fence only when the buffer (or what it used) is about to be reused. Every frame, ground-truth
//! tile and harness call goes through one of these.

use super::device::Device;
use super::owned::Owned;
use super::sync::fence;
use crate::error::{Result, VkContext};
use ash::vk;
use std::cell::Cell;

pub struct Commands<'g> {
    device: &'g Device,
    pub cmd: vk::CommandBuffer,
    /// Submitted and not yet waited for: the fence will signal when the GPU is done.
    pending: Cell<bool>,
    // Drop order: the fence, then the pool (which frees `cmd`).
    fence: Owned<'g, vk::Fence>,
    pool: Owned<'g, vk::CommandPool>,
}

/// A semaphore a submission waits on, and the stages that wait.
pub struct Wait {
    pub semaphore: vk::Semaphore,
    pub stages: vk::PipelineStageFlags2,
}

impl<'g> Commands<'g> {
    pub fn new(device: &'g Device, name: &str) -> Result<Self> {
        // One buffer per pool, reset with its pool (no per-buffer reset flag).
        let pool_info = vk::CommandPoolCreateInfo::default().queue_family_index(device.queue_family);
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
        let fence = fence(device, &format!("{name} done"), false)?;
        Ok(Commands { device, cmd, pending: Cell::new(false), fence, pool })
    }

    /// Begins a one-time recording.
    pub fn begin(&self) -> Result<()> {
        assert!(!self.pending.get(), "begin on a command buffer the GPU may still run: wait() first");
        let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the pool's one buffer is not pending (checked above: every submission is
        // waited on first).
        unsafe {
            self.device
                .raw
                .reset_command_pool(self.pool.raw, vk::CommandPoolResetFlags::empty())
                .during("vkResetCommandPool")?;
            self.device.raw.begin_command_buffer(self.cmd, &begin).during("vkBeginCommandBuffer")
        }
    }

    /// Ends the recording and submits it: after `waits`, signalling `signal` and the fence.
    pub fn submit(&self, waits: &[Wait], signal: Option<vk::Semaphore>) -> Result<()> {
        let raw = &self.device.raw;
        let wait_infos: Vec<_> = waits
            .iter()
            .map(|w| vk::SemaphoreSubmitInfo::default().semaphore(w.semaphore).stage_mask(w.stages))
            .collect();
        let signal_infos: Vec<_> = signal
            .iter()
            .map(|&s| vk::SemaphoreSubmitInfo::default().semaphore(s).stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS))
            .collect();
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&wait_infos)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signal_infos);
        // SAFETY: recording began in `begin`; the fence is unsignalled (reset after every wait);
        // host writes to mapped memory made before the submit are visible to the device
        // (vkQueueSubmit's implicit host-write ordering).
        unsafe {
            raw.end_command_buffer(self.cmd).during("vkEndCommandBuffer")?;
            raw.queue_submit2(self.device.queue, &[submit], self.fence.raw).during("vkQueueSubmit2")?;
        }
        self.pending.set(true);
        Ok(())
    }

    /// Waits until the last submission has finished (at once if nothing is pending), so that the
    /// buffer and everything it used may be reused. Returns whether a submission was pending.
    pub fn wait(&self) -> Result<bool> {
        if !self.pending.get() {
            return Ok(false);
        }
        let raw = &self.device.raw;
        // SAFETY: the fence was given to the pending submission; it is reset only after it signals.
        unsafe {
            raw.wait_for_fences(&[self.fence.raw], true, u64::MAX).during("vkWaitForFences")?;
            raw.reset_fences(&[self.fence.raw]).during("vkResetFences")?;
        }
        self.pending.set(false);
        Ok(true)
    }

    /// Ends the recording, submits it and waits until the GPU has finished it.
    pub fn submit_and_wait(&self) -> Result<()> {
        self.submit(&[], None)?;
        self.wait().map(|_| ())
    }
}
