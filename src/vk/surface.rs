//! The window's surface: created from the platform's raw handles (X11, Wayland, Win32, Metal
//! through ash-window), destroyed before the instance.

use super::instance::Instance;
use crate::error::{Error, Result, VkContext};
use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

pub struct Surface {
    pub raw: vk::SurfaceKHR,
    pub loader: khr::surface::Instance,
}

/// The instance extensions a surface on `display` needs; a clear error when the loader lacks them.
pub fn required_extensions(entry: &ash::Entry, display: RawDisplayHandle) -> Result<Vec<&'static std::ffi::CStr>> {
    let names = ash_window::enumerate_required_extensions(display)
        .map_err(|e| Error::NoSurface(format!("this window system has no Vulkan surface extension ({e})")))?;
    // SAFETY: plain enumeration on a loaded entry.
    let available = unsafe { entry.enumerate_instance_extension_properties(None) }
        .during("vkEnumerateInstanceExtensionProperties")?;
    names
        .iter()
        .map(|&p| {
            // SAFETY: ash-window returns pointers to its static, NUL-terminated extension names.
            let name = unsafe { std::ffi::CStr::from_ptr(p) };
            if available.iter().any(|e| e.extension_name_as_c_str() == Ok(name)) {
                Ok(name)
            } else {
                Err(Error::NoSurface(format!("the Vulkan loader lacks {}", name.to_string_lossy())))
            }
        })
        .collect()
}

impl Surface {
    pub fn new(instance: &Instance, display: RawDisplayHandle, window: RawWindowHandle) -> Result<Surface> {
        // SAFETY: the handles come from a live winit window that outlives the surface (the
        // window's owner drops the GPU context, and so this surface, first).
        let raw = unsafe { ash_window::create_surface(&instance.entry, &instance.raw, display, window, None) }
            .during("vkCreate*SurfaceKHR")?;
        Ok(Surface { raw, loader: khr::surface::Instance::new(&instance.entry, &instance.raw) })
    }

    /// Whether queue family `family` of `physical` can present to this surface.
    pub fn supports(&self, physical: vk::PhysicalDevice, family: u32) -> bool {
        // SAFETY: `physical` belongs to the surface's instance; `family` is one of its families.
        unsafe { self.loader.get_physical_device_surface_support(physical, family, self.raw) }.unwrap_or(false)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: the swapchain made on it is destroyed first (its owner drops before the GPU
        // context), and the instance outlives this field (Gpu's field order).
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}
