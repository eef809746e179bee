//! The GPU context: instance, device and allocator, torn down in reverse creation order.

use super::device::{Device, HostEnabled};
use super::instance::Instance;
use super::memory::Allocator;
use super::surface::{self, Surface};
use super::validation::MessageCounts;
use crate::error::Result;
use std::cell::RefCell;
use std::path::Path;

/// A host's Vulkan objects, which the ocean borrows (embed::Ocean's creation).
#[derive(Clone, Copy)]
pub struct HostDevice<'a> {
    /// The loader the host's instance was created through.
    pub entry: &'a ash::Entry,
    /// The host's instance (Vulkan 1.3).
    pub instance: &'a ash::Instance,
    /// The physical device `device` was created from.
    pub physical_device: ash::vk::PhysicalDevice,
    /// The host's device, with what `enabled` states enabled.
    pub device: &'a ash::Device,
    /// The family of the queue the host submits the ocean's commands on: graphics and compute.
    pub queue_family: u32,
    /// A queue of that family (named in debug tools; the ocean never submits to it).
    pub queue: ash::vk::Queue,
    /// What the host enabled on `device` (embed::requirements lists what is needed).
    pub enabled: HostEnabled,
    /// Whether the host enabled VK_EXT_debug_utils on its instance: the ocean's passes then
    /// carry debug labels and its objects names.
    pub debug_utils: bool,
}

pub struct Gpu {
    // Field order is drop order: allocator, then device, then instance.
    pub allocator: RefCell<Allocator>,
    pub device: Device,
    /// The window's surface, for a context made with `for_window`.
    pub surface: Option<Surface>,
    pub instance: Instance,
}

impl Gpu {
    /// A context whose pipeline cache is kept in the user's cache folder (`pipeline_cache::default_dir`).
    pub fn new(validation: bool, device_filter: Option<&str>) -> Result<Gpu> {
        Gpu::with_cache_dir(validation, device_filter, super::pipeline_cache::default_dir().as_deref())
    }

    /// A context whose pipeline cache file lives in `cache_dir` (None: in memory for this run only).
    pub fn with_cache_dir(validation: bool, device_filter: Option<&str>, cache_dir: Option<&Path>) -> Result<Gpu> {
        let instance = Instance::new(validation)?;
        let device = Device::new(&instance, device_filter, cache_dir, None)?;
        Ok(Gpu::assemble(instance, None, device))
    }

    /// A context that presents to a window: its surface extensions on the instance, a device
    /// whose queue presents to the window's surface. The window must outlive the context.
    pub fn for_window(
        validation: bool,
        device_filter: Option<&str>,
        display: raw_window_handle::RawDisplayHandle,
        window: raw_window_handle::RawWindowHandle,
    ) -> Result<Gpu> {
        let entry = Instance::load()?;
        let extensions = surface::required_extensions(&entry, display)?;
        let instance = Instance::with_extensions(entry, validation, &extensions)?;
        let surface = Surface::new(&instance, display, window)?;
        let cache_dir = super::pipeline_cache::default_dir();
        let device = Device::new(&instance, device_filter, cache_dir.as_deref(), Some(&surface))?;
        Ok(Gpu::assemble(instance, Some(surface), device))
    }

    /// A context on a host's instance and device, borrowed (never destroyed here): our
    /// sub-allocator draws its blocks from the host's device. The host keeps both alive until
    /// this context and everything made on it are dropped.
    pub fn from_host(host: &HostDevice, cache_dir: Option<&Path>) -> Result<Gpu> {
        let instance = Instance::from_host(host.entry.clone(), host.instance.clone(), host.debug_utils);
        let device = Device::from_host(
            &instance,
            host.physical_device,
            host.device.clone(),
            host.queue_family,
            host.queue,
            host.enabled,
            cache_dir,
        )?;
        Ok(Gpu::assemble(instance, None, device))
    }

    fn assemble(instance: Instance, surface: Option<Surface>, device: Device) -> Gpu {
        let allocator =
            RefCell::new(Allocator::new(device.raw.clone(), device.memory_properties, &device.properties.limits));
        Gpu { allocator, device, surface, instance }
    }

    pub fn raw(&self) -> &ash::Device {
        &self.device.raw
    }

    pub fn validation_counts(&self) -> MessageCounts {
        self.instance.log.snapshot()
    }
}

impl Drop for Gpu {
    fn drop(&mut self) {
        let _ = self.device.wait_idle();
        // The cache only saves time: a run whose results are written does not fail for it.
        if let Err(e) = self.device.pipeline_cache.save(&self.device) {
            eprintln!("warning: pipeline cache not saved: {e}");
        }
    }
}
