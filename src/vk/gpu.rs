//! The GPU context: instance, device and allocator, torn down in reverse creation order.

use super::device::Device;
use super::instance::Instance;
use super::memory::Allocator;
use super::validation::MessageCounts;
use crate::error::Result;
use std::cell::RefCell;
use std::path::Path;

pub struct Gpu {
    // Field order is drop order: allocator, then device, then instance.
    pub allocator: RefCell<Allocator>,
    pub device: Device,
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
        let device = Device::new(&instance, device_filter, cache_dir)?;
        let allocator =
            RefCell::new(Allocator::new(device.raw.clone(), device.memory_properties, &device.properties.limits));
        Ok(Gpu { allocator, device, instance })
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
