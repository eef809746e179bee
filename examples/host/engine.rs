//! The engine's side of the example host, as any Vulkan application has it: instance, device,
//! queue, swapchain, per-frame objects and the HDR colour and depth targets the frame is drawn
//! into. Nothing here knows the ocean beyond `ocean::embed`'s requirements and `HostImage`.

use super::{DEPTH_FORMAT, FRAMES_IN_FLIGHT, HDR_FORMAT};
use ash::{ext, khr, vk};
use ocean::embed::{self, HostDevice, HostEnabled, HostImage, ImageState};
use std::sync::atomic::{AtomicU32, Ordering};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

pub static VALIDATION_ERRORS: AtomicU32 = AtomicU32::new(0);

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    _user: *mut std::ffi::c_void,
) -> vk::Bool32 {
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        VALIDATION_ERRORS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: the layer passes a valid callback data whose message is a C string.
        let message = unsafe { (*data).message_as_c_str() }.map(|m| m.to_string_lossy()).unwrap_or_default();
        eprintln!("validation: {message}");
    }
    vk::FALSE
}

/// The engine's side: instance, device and queue, made as any Vulkan application makes them,
/// with what `ocean::embed::requirements` lists enabled.
pub struct Host {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub debug: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    pub surface_fns: khr::surface::Instance,
    pub surface: vk::SurfaceKHR,
    pub physical: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    pub queue: vk::Queue,
    pub swapchain: khr::swapchain::Device,
    pub enabled: HostEnabled,
    pub pool: vk::CommandPool,
}

impl Host {
    pub fn new(window: &Window, validation: bool) -> Result<Host, Box<dyn std::error::Error>> {
        // SAFETY: loads the system's Vulkan loader.
        let entry = unsafe { ash::Entry::load() }?;
        let display = window.display_handle()?.as_raw();
        let mut extensions = ash_window::enumerate_required_extensions(display)?.to_vec();
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        if validation {
            extensions.push(ext::debug_utils::NAME.as_ptr());
        }
        let app = vk::ApplicationInfo::default()
            .application_name(c"ocean host example")
            .api_version(embed::requirements().api_version);
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app).enabled_extension_names(&extensions);
        if validation {
            info = info.enabled_layer_names(&layers).push_next(&mut features);
        }
        // SAFETY: every pointer in `info` refers to locals alive through the call.
        let instance = unsafe { entry.create_instance(&info, None) }?;
        let debug = if validation {
            let fns = ext::debug_utils::Instance::new(&entry, &instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::ERROR | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::GENERAL,
                )
                .pfn_user_callback(Some(on_message));
            // SAFETY: the callback is a plain function with no user data.
            let messenger = unsafe { fns.create_debug_utils_messenger(&info, None) }?;
            Some((fns, messenger))
        } else {
            None
        };
        // SAFETY: the window outlives the surface (destroyed in Drop before the window goes).
        let surface =
            unsafe { ash_window::create_surface(&entry, &instance, display, window.window_handle()?.as_raw(), None) }?;
        let surface_fns = khr::surface::Instance::new(&entry, &instance);
        // The first device the ocean can run on whose graphics queue presents to the window.
        // SAFETY: enumeration and queries on a live instance.
        let physicals = unsafe { instance.enumerate_physical_devices() }?;
        let (physical, queue_family) = physicals
            .iter()
            .filter(|&&p| embed::check_physical_device(&entry, &instance, p).is_ok())
            .find_map(|&p| {
                // SAFETY: as above.
                let families = unsafe { instance.get_physical_device_queue_family_properties(p) };
                families.iter().enumerate().find_map(|(i, f)| {
                    let graphics = f.queue_flags.contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE);
                    // SAFETY: as above.
                    let presents = unsafe { surface_fns.get_physical_device_surface_support(p, i as u32, surface) };
                    (graphics && presents == Ok(true)).then_some((p, i as u32))
                })
            })
            .ok_or("no Vulkan device runs the ocean and presents to this window")?;
        // SAFETY: as above.
        let supported = unsafe { instance.get_physical_device_features(physical) };
        let enabled = HostEnabled {
            synchronization2: true,
            dynamic_rendering: true,
            sampler_anisotropy: supported.sampler_anisotropy == vk::TRUE,
            ..HostEnabled::default()
        };
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true).dynamic_rendering(true);
        let base = vk::PhysicalDeviceFeatures::default().sampler_anisotropy(enabled.sampler_anisotropy);
        let priorities = [1.0];
        let queues =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let device_extensions = [khr::swapchain::NAME.as_ptr()];
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&device_extensions)
            .enabled_features(&base)
            .push_next(&mut f13);
        // SAFETY: the features were checked by check_physical_device; pointers are locals.
        let device = unsafe { instance.create_device(physical, &info, None) }?;
        // SAFETY: queue 0 of the one family created.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let swapchain = khr::swapchain::Device::new(&instance, &device);
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: a live device.
        let pool = unsafe { device.create_command_pool(&pool_info, None) }?;
        Ok(Host {
            entry,
            instance,
            debug,
            surface_fns,
            surface,
            physical,
            device,
            queue_family,
            queue,
            swapchain,
            enabled,
            pool,
        })
    }

    /// What the ocean borrows.
    pub fn borrowed(&self) -> HostDevice<'_> {
        HostDevice {
            entry: &self.entry,
            instance: &self.instance,
            physical_device: self.physical,
            device: &self.device,
            queue_family: self.queue_family,
            queue: self.queue,
            enabled: self.enabled,
            debug_utils: self.debug.is_some(),
        }
    }

    pub fn memory(
        &self,
        requirements: vk::MemoryRequirements,
        flags: vk::MemoryPropertyFlags,
    ) -> Result<vk::DeviceMemory, vk::Result> {
        // SAFETY: plain queries and an allocation on a live device.
        unsafe {
            let props = self.instance.get_physical_device_memory_properties(self.physical);
            let index = (0..props.memory_type_count)
                .find(|&i| {
                    requirements.memory_type_bits & (1 << i) != 0
                        && props.memory_types[i as usize].property_flags.contains(flags)
                })
                .ok_or(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)?;
            let info = vk::MemoryAllocateInfo::default().allocation_size(requirements.size).memory_type_index(index);
            self.device.allocate_memory(&info, None)
        }
    }

    pub fn image(
        &self,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Target, vk::Result> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .usage(usage);
        // SAFETY: valid create infos on a live device; the memory suits the image.
        unsafe {
            let raw = self.device.create_image(&info, None)?;
            let memory =
                self.memory(self.device.get_image_memory_requirements(raw), vk::MemoryPropertyFlags::DEVICE_LOCAL)?;
            self.device.bind_image_memory(raw, memory, 0)?;
            let view = self.device.create_image_view(&view_info(raw, format, aspect), None)?;
            Ok(Target { image: HostImage { raw, view, format, extent }, memory })
        }
    }

    pub fn barrier(
        &self,
        cmd: vk::CommandBuffer,
        image: &HostImage,
        from: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
        to: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    ) {
        let state = |(layout, stage, access)| ImageState::new(layout, stage, access);
        ocean::embed::transition(&self.device, cmd, &[(*image, state(from), state(to))]);
    }

    /// Copies a colour image (last written as `from`) into a new host-visible buffer.
    pub fn copy_out(
        &self,
        cmd: vk::CommandBuffer,
        image: &HostImage,
        from: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    ) -> (vk::Buffer, vk::DeviceMemory) {
        let bytes = 4 * image.extent.width as u64 * image.extent.height as u64;
        let info = vk::BufferCreateInfo::default().size(bytes).usage(vk::BufferUsageFlags::TRANSFER_DST);
        // SAFETY: a live device; the buffer is bound to host-visible memory of its size.
        let (buffer, memory) = unsafe {
            let buffer = self.device.create_buffer(&info, None).expect("a readback buffer");
            let flags = vk::MemoryPropertyFlags::HOST_VISIBLE | vk::MemoryPropertyFlags::HOST_COHERENT;
            let memory =
                self.memory(self.device.get_buffer_memory_requirements(buffer), flags).expect("readback memory");
            self.device.bind_buffer_memory(buffer, memory, 0).expect("bound");
            (buffer, memory)
        };
        self.barrier(
            cmd,
            image,
            from,
            (vk::ImageLayout::TRANSFER_SRC_OPTIMAL, vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ),
        );
        let region = vk::BufferImageCopy {
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_extent: vk::Extent3D { width: image.extent.width, height: image.extent.height, depth: 1 },
            ..Default::default()
        };
        // SAFETY: the image is in TRANSFER_SRC_OPTIMAL and the buffer holds it.
        unsafe {
            self.device.cmd_copy_image_to_buffer(
                cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                &[region],
            )
        };
        (buffer, memory)
    }

    pub fn read_and_free(&self, (buffer, memory): (vk::Buffer, vk::DeviceMemory), extent: vk::Extent2D) -> Vec<u8> {
        let bytes = 4 * extent.width as usize * extent.height as usize;
        // SAFETY: the copy's frame was waited on; the memory is host-coherent and mapped whole.
        unsafe {
            let ptr = self.device.map_memory(memory, 0, bytes as u64, vk::MemoryMapFlags::empty()).expect("mapped");
            let rgba = std::slice::from_raw_parts(ptr as *const u8, bytes).to_vec();
            self.device.unmap_memory(memory);
            self.device.destroy_buffer(buffer, None);
            self.device.free_memory(memory, None);
            rgba
        }
    }
}

impl Drop for Host {
    fn drop(&mut self) {
        // SAFETY: everything made on the device was destroyed before (finish); reverse order.
        unsafe {
            let _ = self.device.device_wait_idle();
            self.device.destroy_command_pool(self.pool, None);
            self.device.destroy_device(None);
            self.surface_fns.destroy_surface(self.surface, None);
            if let Some((fns, messenger)) = &self.debug {
                fns.destroy_debug_utils_messenger(*messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

pub fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

pub fn view_info(
    image: vk::Image,
    format: vk::Format,
    aspect: vk::ImageAspectFlags,
) -> vk::ImageViewCreateInfo<'static> {
    vk::ImageViewCreateInfo::default()
        .image(image)
        .view_type(vk::ImageViewType::TYPE_2D)
        .format(format)
        .subresource_range(range(aspect))
}

/// An image of the host's with its memory.
pub struct Target {
    pub image: HostImage,
    pub memory: vk::DeviceMemory,
}

impl Target {
    pub fn destroy(&self, host: &Host) {
        // SAFETY: the device is idle (callers wait first).
        unsafe {
            host.device.destroy_image_view(self.image.view, None);
            host.device.destroy_image(self.image.raw, None);
            host.device.free_memory(self.memory, None);
        }
    }
}

/// A frame slot's objects: its command buffer, fence, acquire semaphore and HDR and depth targets.
pub struct Slot {
    pub cmd: vk::CommandBuffer,
    pub fence: vk::Fence,
    pub image_available: vk::Semaphore,
    pub hdr: Target,
    pub depth: Target,
}

/// The swapchain, its images and everything sized to them.
pub struct Swapchain {
    pub raw: vk::SwapchainKHR,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub images: Vec<HostImage>,
    /// One per swapchain image: a present waits on its own image's semaphore.
    pub render_finished: Vec<vk::Semaphore>,
    pub slots: Vec<Slot>,
}

impl Swapchain {
    pub fn new(host: &Host, window: &Window) -> Result<Swapchain, Box<dyn std::error::Error>> {
        // SAFETY: queries on the live surface and device.
        let caps = unsafe { host.surface_fns.get_physical_device_surface_capabilities(host.physical, host.surface) }?;
        let formats = unsafe { host.surface_fns.get_physical_device_surface_formats(host.physical, host.surface) }?;
        let supported = |f: vk::Format| embed::ldr_encodes_srgb(f).is_some();
        let surface_format = formats
            .iter()
            .find(|f| f.format == vk::Format::B8G8R8A8_SRGB)
            .or_else(|| formats.iter().find(|f| supported(f.format)))
            .ok_or("no swapchain format the ocean tone-maps into")?;
        let size = window.inner_size();
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D { width: size.width, height: size.height }
        };
        let mut swapchain = Swapchain {
            raw: vk::SwapchainKHR::null(),
            format: surface_format.format,
            extent,
            images: Vec::new(),
            render_finished: Vec::new(),
            slots: Vec::new(),
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(swapchain); // minimized
        }
        let usage =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | (caps.supported_usage_flags & vk::ImageUsageFlags::TRANSFER_SRC);
        let count =
            (caps.min_image_count + 1).min(if caps.max_image_count == 0 { u32::MAX } else { caps.max_image_count });
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(host.surface)
            .min_image_count(count)
            .image_format(surface_format.format)
            .image_color_space(surface_format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true);
        // SAFETY: valid create infos on live objects; each object made here is destroyed in destroy().
        unsafe {
            swapchain.raw = host.swapchain.create_swapchain(&info, None)?;
            for raw in host.swapchain.get_swapchain_images(swapchain.raw)? {
                let view = host
                    .device
                    .create_image_view(&view_info(raw, surface_format.format, vk::ImageAspectFlags::COLOR), None)?;
                swapchain.images.push(HostImage { raw, view, format: surface_format.format, extent });
                swapchain
                    .render_finished
                    .push(host.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?);
            }
            let alloc = vk::CommandBufferAllocateInfo::default()
                .command_pool(host.pool)
                .command_buffer_count(FRAMES_IN_FLIGHT as u32);
            let cmds = host.device.allocate_command_buffers(&alloc)?;
            use vk::ImageUsageFlags as U;
            for cmd in cmds {
                swapchain.slots.push(Slot {
                    cmd,
                    fence: host
                        .device
                        .create_fence(&vk::FenceCreateInfo::default().flags(vk::FenceCreateFlags::SIGNALED), None)?,
                    image_available: host.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?,
                    // Sampled: the ocean tone-maps from it.
                    hdr: host.image(
                        HDR_FORMAT,
                        extent,
                        U::COLOR_ATTACHMENT | U::SAMPLED,
                        vk::ImageAspectFlags::COLOR,
                    )?,
                    depth: host.image(
                        DEPTH_FORMAT,
                        extent,
                        // Sampled too: the ocean's reflections of the host's objects read it.
                        U::DEPTH_STENCIL_ATTACHMENT | U::SAMPLED,
                        vk::ImageAspectFlags::DEPTH,
                    )?,
                });
            }
        }
        Ok(swapchain)
    }

    pub fn destroy(&self, host: &Host) {
        // SAFETY: the device is idle (callers wait first).
        unsafe {
            for s in &self.slots {
                host.device.free_command_buffers(host.pool, &[s.cmd]);
                host.device.destroy_fence(s.fence, None);
                host.device.destroy_semaphore(s.image_available, None);
                s.hdr.destroy(host);
                s.depth.destroy(host);
            }
            for (image, &semaphore) in self.images.iter().zip(&self.render_finished) {
                host.device.destroy_image_view(image.view, None);
                host.device.destroy_semaphore(semaphore, None);
            }
            if self.raw != vk::SwapchainKHR::null() {
                host.swapchain.destroy_swapchain(self.raw, None);
            }
        }
    }
}
