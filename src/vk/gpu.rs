//! The GPU context: instance, device and allocator, torn down in reverse creation order.

use super::device::Device;
use super::instance::Instance;
use super::memory::Allocator;
use super::validation::MessageCounts;
use crate::error::Result;
use std::cell::RefCell;

pub struct Gpu {
    // Field order is drop order: allocator, then device, then instance.
    pub allocator: RefCell<Allocator>,
    pub device: Device,
    pub instance: Instance,
}

impl Gpu {
    pub fn new(validation: bool, device_filter: Option<&str>) -> Result<Gpu> {
        let instance = Instance::new(validation)?;
        let device = Device::new(&instance, device_filter)?;
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
    }
}
