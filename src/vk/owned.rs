//! Ownership of plain Vulkan handles: `Owned` destroys its handle when dropped, so objects made
//! before a failure are released on the error path too. Owners borrow the device, so none can
//! outlive it.

use super::device::Device;
use ash::vk;

/// A handle type that the device can destroy.
pub trait Destroy: Copy + vk::Handle {
    /// # Safety
    /// The handle belongs to `device` and no pending GPU work uses it.
    unsafe fn destroy(self, device: &ash::Device);
}

macro_rules! destroy_with {
    ($($handle:ty => $method:ident),* $(,)?) => {$(
        impl Destroy for $handle {
            unsafe fn destroy(self, device: &ash::Device) {
                // SAFETY: forwarded from the caller.
                unsafe { device.$method(self, None) }
            }
        }
    )*};
}

destroy_with! {
    vk::Pipeline => destroy_pipeline,
    vk::PipelineLayout => destroy_pipeline_layout,
    vk::DescriptorSetLayout => destroy_descriptor_set_layout,
    vk::DescriptorPool => destroy_descriptor_pool,
    vk::ShaderModule => destroy_shader_module,
    vk::Sampler => destroy_sampler,
    vk::QueryPool => destroy_query_pool,
    vk::CommandPool => destroy_command_pool,
    vk::Fence => destroy_fence,
    vk::Semaphore => destroy_semaphore,
    vk::ImageView => destroy_image_view,
    vk::BufferView => destroy_buffer_view,
}

pub struct Owned<'g, H: Destroy> {
    device: &'g Device,
    pub raw: H,
}

impl<'g, H: Destroy> Owned<'g, H> {
    /// Takes ownership of `raw`, created on `device`, and gives it a debug name.
    pub fn new(device: &'g Device, raw: H, name: &str) -> Self {
        device.set_name(raw, name);
        Owned { device, raw }
    }
}

impl<H: Destroy> Drop for Owned<'_, H> {
    fn drop(&mut self) {
        // SAFETY: owners drop only after the device is idle (Renderer's Drop waits for it, and
        // error paths have submitted nothing that uses the handle).
        unsafe { self.raw.destroy(&self.device.raw) };
    }
}
