//! The window's swapchain: surface format and present mode choice, image views, one
//! render-finished semaphore per image, acquire and present with their results mapped on purpose,
//! and recreation (the old swapchain handed to the new one; its owner destroys it later).

use super::barrier::{single_layer_levels, TrackedImage};
use super::device::Device;
use super::gpu::Gpu;
use super::owned::Owned;
use super::surface::Surface;
use super::sync::semaphore;
use crate::error::{Error, Result, VkContext};
use ash::vk;

/// One swapchain image as the frame sees it.
#[derive(Clone, Copy, Debug)]
pub struct SwapImage {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub extent: vk::Extent2D,
    pub format: vk::Format,
    pub index: u32,
}

impl TrackedImage for SwapImage {
    fn raw(&self) -> vk::Image {
        self.raw
    }
    fn mip_levels(&self) -> u32 {
        1
    }
    fn levels(&self, base: u32, count: u32) -> vk::ImageSubresourceRange {
        single_layer_levels(vk::ImageAspectFlags::COLOR, base, count)
    }
}

/// What the user asked for and what the surface gave.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Choice {
    pub format: vk::SurfaceFormatKHR,
    pub present_mode: vk::PresentModeKHR,
    /// The format stores what it is given (UNORM): the display shader applies the sRGB encoding.
    pub encode_srgb_in_shader: bool,
    /// Images can be copied out (TRANSFER_SRC), for screenshots of what is shown.
    pub copyable: bool,
}

pub enum Acquired {
    Image {
        image: SwapImage,
        suboptimal: bool,
    },
    /// The surface changed (resize): recreate and try again.
    OutOfDate,
}

pub struct Swapchain<'g> {
    device: &'g Device,
    pub raw: vk::SwapchainKHR,
    pub images: Vec<SwapImage>,
    pub choice: Choice,
    pub extent: vk::Extent2D,
    /// One per image: signalled by the submission that renders the image, waited on by its
    /// present. Per image, not per frame, so a semaphore is never signalled again while a present
    /// may still wait on it (the image is re-acquired only after that present).
    pub render_finished: Vec<Owned<'g, vk::Semaphore>>,
    _views: Vec<Owned<'g, vk::ImageView>>,
}

pub fn present_mode_name(mode: vk::PresentModeKHR) -> &'static str {
    match mode {
        vk::PresentModeKHR::FIFO => "fifo",
        vk::PresentModeKHR::MAILBOX => "mailbox",
        vk::PresentModeKHR::IMMEDIATE => "immediate",
        vk::PresentModeKHR::FIFO_RELAXED => "fifo-relaxed",
        _ => "other",
    }
}

/// sRGB formats first (the hardware encodes), then UNORM ones (our shader encodes).
const PREFERRED_FORMATS: [(vk::Format, bool); 4] = [
    (vk::Format::B8G8R8A8_SRGB, false),
    (vk::Format::R8G8B8A8_SRGB, false),
    (vk::Format::B8G8R8A8_UNORM, true),
    (vk::Format::R8G8B8A8_UNORM, true),
];

/// Chooses the surface format and present mode; Err when the surface offers none we can draw to.
fn choose(gpu: &Gpu, surface: &Surface, requested: vk::PresentModeKHR) -> Result<(Choice, bool)> {
    let physical = gpu.device.physical;
    // SAFETY: the surface and physical device belong to this instance.
    let formats = unsafe { surface.loader.get_physical_device_surface_formats(physical, surface.raw) }
        .during("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
    // SAFETY: as above.
    let modes = unsafe { surface.loader.get_physical_device_surface_present_modes(physical, surface.raw) }
        .during("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
    // SAFETY: as above.
    let caps = unsafe { surface.loader.get_physical_device_surface_capabilities(physical, surface.raw) }
        .during("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
    let (format, encode_srgb_in_shader) = PREFERRED_FORMATS
        .iter()
        .find_map(|&(wanted, encode)| {
            formats
                .iter()
                .find(|f| f.format == wanted && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR)
                .map(|&f| (f, encode))
        })
        .ok_or_else(|| {
            Error::NoSurface(format!("the surface offers no 8-bit sRGB or UNORM RGBA/BGRA format ({formats:?})"))
        })?;
    let fell_back = !modes.contains(&requested);
    let present_mode = if fell_back { vk::PresentModeKHR::FIFO } else { requested }; // FIFO is always there
    let copyable = caps.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_SRC);
    Ok((Choice { format, present_mode, encode_srgb_in_shader, copyable }, fell_back))
}

impl<'g> Swapchain<'g> {
    /// A swapchain for a window whose drawable area is `window_extent`; None while that area is
    /// empty (minimized). `old`: the swapchain being replaced (retired: the caller keeps it until
    /// its last presents are done). The returned flag: the requested present mode was missing (FIFO instead).
    pub fn new(
        gpu: &'g Gpu,
        requested: vk::PresentModeKHR,
        window_extent: vk::Extent2D,
        old: Option<&Swapchain>,
    ) -> Result<Option<(Swapchain<'g>, bool)>> {
        let device = &gpu.device;
        let surface = gpu.surface.as_ref().expect("a context made for a window");
        let loader = device.swapchain.as_ref().expect("a device opened for a window");
        let (choice, fell_back) = choose(gpu, surface, requested)?;
        // SAFETY: as in `choose`.
        let caps = unsafe { surface.loader.get_physical_device_surface_capabilities(device.physical, surface.raw) }
            .during("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        // u32::MAX: the surface takes its size from the swapchain (Wayland), so use the window's
        // (an empty one first: clamping would turn a minimized window into the minimum size).
        if caps.current_extent.width == u32::MAX && (window_extent.width == 0 || window_extent.height == 0) {
            return Ok(None);
        }
        let extent = if caps.current_extent.width == u32::MAX {
            vk::Extent2D {
                width: window_extent.width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: window_extent.height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        } else {
            caps.current_extent
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        // One more than the minimum, so that acquiring never waits for the presentation engine to
        // release the image it is scanning out while we have a frame ready.
        let wanted = caps.min_image_count + 1;
        let image_count = if caps.max_image_count > 0 { wanted.min(caps.max_image_count) } else { wanted };
        let mut usage = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        if choice.copyable {
            usage |= vk::ImageUsageFlags::TRANSFER_SRC;
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(choice.format.format)
            .image_color_space(choice.format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(if caps.supported_transforms.contains(vk::SurfaceTransformFlagsKHR::IDENTITY) {
                vk::SurfaceTransformFlagsKHR::IDENTITY
            } else {
                caps.current_transform
            })
            .composite_alpha(alpha)
            .present_mode(choice.present_mode)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.raw));
        // SAFETY: the values were chosen from the surface's capabilities, formats and modes.
        let raw = unsafe { loader.create_swapchain(&info, None) }.map_err(|result| match result {
            vk::Result::ERROR_SURFACE_LOST_KHR => Error::NoSurface("the window's surface was lost".into()),
            result => Error::Vulkan { call: "vkCreateSwapchainKHR", result },
        })?;
        // From here the swapchain is owned: its Drop destroys it on any later error.
        let mut swapchain = Swapchain {
            device,
            raw,
            images: Vec::new(),
            choice,
            extent,
            render_finished: Vec::new(),
            _views: Vec::new(),
        };
        // SAFETY: `raw` was just created on this device.
        let images = unsafe { loader.get_swapchain_images(raw) }.during("vkGetSwapchainImagesKHR")?;
        for (index, &image) in images.iter().enumerate() {
            device.set_name(image, &format!("swapchain image {index}"));
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(choice.format.format)
                .subresource_range(vk::ImageSubresourceRange {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    base_mip_level: 0,
                    level_count: 1,
                    base_array_layer: 0,
                    layer_count: 1,
                });
            // SAFETY: a view of a live swapchain image in the swapchain's format.
            let view = unsafe { device.raw.create_image_view(&view_info, None) }.during("vkCreateImageView")?;
            let view = Owned::new(device, view, &format!("swapchain view {index}"));
            swapchain.images.push(SwapImage {
                raw: image,
                view: view.raw,
                extent,
                format: choice.format.format,
                index: index as u32,
            });
            swapchain._views.push(view);
            swapchain.render_finished.push(semaphore(device, &format!("rendered swapchain image {index}"))?);
        }
        Ok(Some((swapchain, fell_back)))
    }

    /// Acquires the next image; `signal` is signalled when the image may be written.
    pub fn acquire(&self, signal: vk::Semaphore) -> Result<Acquired> {
        let loader = self.device.swapchain.as_ref().expect("a device opened for a window");
        // SAFETY: `signal` is unsignalled with no pending wait (its frame slot's fence was waited).
        match unsafe { loader.acquire_next_image(self.raw, u64::MAX, signal, vk::Fence::null()) } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { image: self.images[index as usize], suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => Err(Error::NoSurface("the window's surface was lost".into())),
            Err(result) => Err(Error::Vulkan { call: "vkAcquireNextImageKHR", result }),
        }
    }

    /// Presents `image` once its render-finished semaphore signals. Ok(false): the swapchain no
    /// longer matches the surface (out of date or suboptimal) and should be recreated.
    pub fn present(&self, image: &SwapImage) -> Result<bool> {
        let loader = self.device.swapchain.as_ref().expect("a device opened for a window");
        let waits = [self.render_finished[image.index as usize].raw];
        let swapchains = [self.raw];
        let indices = [image.index];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
        // SAFETY: the image was acquired and its rendering submitted with a signal of `waits`.
        match unsafe { loader.queue_present(self.device.queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => Err(Error::NoSurface("the window's surface was lost".into())),
            Err(result) => Err(Error::Vulkan { call: "vkQueuePresentKHR", result }),
        }
    }
}

impl Drop for Swapchain<'_> {
    fn drop(&mut self) {
        if let Some(loader) = &self.device.swapchain {
            // SAFETY: the owner waited for every frame that rendered into the images and for their
            // presents; the views and semaphores drop after this (field order).
            unsafe { loader.destroy_swapchain(self.raw, None) };
        }
    }
}
