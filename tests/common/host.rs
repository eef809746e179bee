//! A headless host, as an engine would be: its own device (enabling what embed::requirements
//! lists), its own HDR colour and depth images, command buffer and fence, written in plain ash.
//! Only its instance is the crate's, for the validation layer's canary (Instance::log).
#![allow(dead_code)]

use ash::vk;
use ocean::embed::ImageState;
use ocean::embed::{self, HostDevice, HostEnabled, HostImage};
use ocean::vk::instance::Instance;

pub const COLOUR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

pub struct HostImageMemory {
    pub image: HostImage,
    memory: vk::DeviceMemory,
}

pub struct Host {
    pub instance: Instance,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    pub queue: vk::Queue,
    pub enabled: HostEnabled,
    pool: vk::CommandPool,
    pub cmd: vk::CommandBuffer,
    fence: vk::Fence,
}

impl Host {
    pub fn new() -> Host {
        let instance = Instance::new(true).unwrap_or_else(|e| panic!("the host needs Vulkan with validation: {e}"));
        // SAFETY (test host): enumeration and queries on a live instance.
        let physicals = unsafe { instance.raw.enumerate_physical_devices() }.unwrap();
        let physical = physicals
            .into_iter()
            .find(|&p| embed::check_physical_device(&instance.entry, &instance.raw, p).is_ok())
            .expect("a device the ocean supports");
        let families = unsafe { instance.raw.get_physical_device_queue_family_properties(physical) };
        let queue_family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE))
            .unwrap() as u32;
        let supported = unsafe { instance.raw.get_physical_device_features(physical) };
        let enabled = HostEnabled {
            synchronization2: true,
            dynamic_rendering: true,
            sampler_anisotropy: supported.sampler_anisotropy == vk::TRUE,
            pipeline_statistics_query: false,
            calibrated_timestamps: false,
        };
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true).dynamic_rendering(true);
        let base = vk::PhysicalDeviceFeatures::default().sampler_anisotropy(enabled.sampler_anisotropy);
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let info =
            vk::DeviceCreateInfo::default().queue_create_infos(&queues).enabled_features(&base).push_next(&mut f13);
        let device = unsafe { instance.raw.create_device(physical, &info, None) }.unwrap();
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { device.create_command_pool(&pool_info, None) }.unwrap();
        let alloc = vk::CommandBufferAllocateInfo::default().command_pool(pool).command_buffer_count(1);
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }.unwrap()[0];
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }.unwrap();
        Host { instance, physical, device, queue_family, queue, enabled, pool, cmd, fence }
    }

    /// What the ocean borrows.
    pub fn borrowed(&self) -> HostDevice<'_> {
        HostDevice {
            entry: &self.instance.entry,
            instance: &self.instance.raw,
            physical_device: self.physical,
            device: &self.device,
            queue_family: self.queue_family,
            queue: self.queue,
            enabled: self.enabled,
            debug_utils: self.instance.debug_utils.is_some(),
        }
    }

    /// Fails on any validation error so far, naming `what` and the message ids.
    pub fn assert_clean(&self, what: &str) {
        let counts = self.instance.log.snapshot();
        assert_eq!(counts.error_total(), 0, "{what}: validation errors {:?}", counts.errors);
    }

    fn memory_type(&self, bits: u32, flags: vk::MemoryPropertyFlags) -> u32 {
        let props = unsafe { self.instance.raw.get_physical_device_memory_properties(self.physical) };
        (0..props.memory_type_count)
            .find(|&i| bits & (1 << i) != 0 && props.memory_types[i as usize].property_flags.contains(flags))
            .expect("a memory type")
    }

    pub fn image(&self, format: vk::Format, width: u32, height: u32, usage: vk::ImageUsageFlags) -> HostImageMemory {
        self.image_with(format, width, height, usage, &[])
    }

    /// A colour image the ocean may draw in place (embed::OceanDesc::in_place).
    pub fn in_place_image(&self, width: u32, height: u32) -> HostImageMemory {
        let formats = embed::IN_PLACE_VIEW_FORMATS;
        self.image_with(formats[0], width, height, embed::IN_PLACE_USAGE, &formats)
    }

    /// `view_formats`: the formats its views may have (MUTABLE_FORMAT), none for its own alone.
    fn image_with(
        &self,
        format: vk::Format,
        width: u32,
        height: u32,
        usage: vk::ImageUsageFlags,
        view_formats: &[vk::Format],
    ) -> HostImageMemory {
        let extent = vk::Extent2D { width, height };
        let mut list = vk::ImageFormatListCreateInfo::default().view_formats(view_formats);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width, height, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        let info = if view_formats.is_empty() {
            info
        } else {
            info.flags(vk::ImageCreateFlags::MUTABLE_FORMAT).push_next(&mut list)
        };
        let raw = unsafe { self.device.create_image(&info, None) }.unwrap();
        let req = unsafe { self.device.get_image_memory_requirements(raw) };
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(self.memory_type(req.memory_type_bits, vk::MemoryPropertyFlags::DEVICE_LOCAL));
        let memory = unsafe { self.device.allocate_memory(&alloc, None) }.unwrap();
        unsafe { self.device.bind_image_memory(raw, memory, 0) }.unwrap();
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: embed::aspect_of(format) & !vk::ImageAspectFlags::STENCIL,
                base_mip_level: 0,
                level_count: 1,
                base_array_layer: 0,
                layer_count: 1,
            });
        let view = unsafe { self.device.create_image_view(&view_info, None) }.unwrap();
        HostImageMemory { image: HostImage { raw, view, format, extent }, memory }
    }

    pub fn destroy_image(&self, image: HostImageMemory) {
        unsafe {
            self.device.destroy_image_view(image.image.view, None);
            self.device.destroy_image(image.image.raw, None);
            self.device.free_memory(image.memory, None);
        }
    }

    /// A host-visible buffer of `bytes` for copies out of the images.
    pub fn readback(&self, bytes: u64) -> (vk::Buffer, vk::DeviceMemory) {
        let info = vk::BufferCreateInfo::default().size(bytes).usage(vk::BufferUsageFlags::TRANSFER_DST);
        let buffer = unsafe { self.device.create_buffer(&info, None) }.unwrap();
        let req = unsafe { self.device.get_buffer_memory_requirements(buffer) };
        let flags = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
        let alloc = vk::MemoryAllocateInfo::default()
            .allocation_size(req.size)
            .memory_type_index(self.memory_type(req.memory_type_bits, flags));
        let memory = unsafe { self.device.allocate_memory(&alloc, None) }.unwrap();
        unsafe { self.device.bind_buffer_memory(buffer, memory, 0) }.unwrap();
        (buffer, memory)
    }

    pub fn read<T: Copy>(&self, memory: vk::DeviceMemory, count: usize) -> Vec<T> {
        let bytes = (count * std::mem::size_of::<T>()) as u64;
        let ptr = unsafe { self.device.map_memory(memory, 0, bytes, vk::MemoryMapFlags::empty()) }.unwrap();
        let values = unsafe { std::slice::from_raw_parts(ptr as *const T, count) }.to_vec();
        unsafe { self.device.unmap_memory(memory) };
        values
    }

    pub fn destroy_buffer(&self, (buffer, memory): (vk::Buffer, vk::DeviceMemory)) {
        unsafe {
            self.device.destroy_buffer(buffer, None);
            self.device.free_memory(memory, None);
        }
    }

    pub fn begin(&self) {
        unsafe {
            self.device.reset_command_buffer(self.cmd, vk::CommandBufferResetFlags::empty()).unwrap();
            let info = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            self.device.begin_command_buffer(self.cmd, &info).unwrap();
        }
    }

    pub fn submit_and_wait(&self) {
        unsafe {
            self.device.end_command_buffer(self.cmd).unwrap();
            let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(self.cmd)];
            let submit = vk::SubmitInfo2::default().command_buffer_infos(&cmds);
            self.device.queue_submit2(self.queue, &[submit], self.fence).unwrap();
            self.device.wait_for_fences(&[self.fence], true, u64::MAX).unwrap();
            self.device.reset_fences(&[self.fence]).unwrap();
        }
    }

    /// Clears the colour to black and the depth to `far` (the attachments in their attachment
    /// layouts), as a host's frame begins.
    pub fn clear(&self, colour: &HostImage, depth: &HostImage, far: f32) {
        embed::clear_targets(&self.device, self.cmd, colour, depth, far);
    }

    pub fn barrier(
        &self,
        image: &HostImage,
        from: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
        to: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    ) {
        let state = |(layout, stage, access)| ImageState::new(layout, stage, access);
        ocean::embed::transition(&self.device, self.cmd, &[(*image, state(from), state(to))]);
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
        }
    }
}
