//! GPU timestamps per pass, in nanoseconds through timestampPeriod, with a debug label around
//! each pass so RenderDoc, Nsight and our reports show the same names.

use super::device::Device;
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;

pub struct Profiler<'g> {
    pool: Owned<'g, vk::QueryPool>,
    capacity: u32,
    names: Vec<&'static str>,
    period_ns: f64,
    valid_bits: u32,
}

impl<'g> Profiler<'g> {
    pub fn new(device: &'g Device, max_scopes: u32) -> Result<Self> {
        let info = vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(2 * max_scopes);
        // SAFETY: valid create info.
        let pool = unsafe { device.raw.create_query_pool(&info, None) }.during("vkCreateQueryPool")?;
        let pool = Owned::new(device, pool, "pass timestamps");
        Ok(Profiler {
            pool,
            capacity: max_scopes,
            names: Vec::new(),
            period_ns: device.properties.limits.timestamp_period as f64,
            valid_bits: device.timestamp_valid_bits,
        })
    }

    /// Resets the pool for a new frame; recorded outside any rendering scope.
    pub fn reset(&mut self, device: &ash::Device, cmd: vk::CommandBuffer) {
        self.names.clear();
        // SAFETY: `cmd` is recording and the pool's queries are not in use by a pending submission.
        unsafe { device.cmd_reset_query_pool(cmd, self.pool.raw, 0, 2 * self.capacity) };
    }

    pub fn begin(&mut self, device: &Device, cmd: vk::CommandBuffer, name: &'static str) {
        if let Some(du) = &device.debug_utils {
            let label = std::ffi::CString::new(name).unwrap_or_default();
            // SAFETY: `cmd` is recording; the label string lives through the call.
            unsafe { du.cmd_begin_debug_utils_label(cmd, &vk::DebugUtilsLabelEXT::default().label_name(&label)) };
        }
        let index = self.names.len() as u32;
        assert!(index < self.capacity, "more timestamp scopes than the profiler was made for");
        self.names.push(name);
        if self.valid_bits > 0 {
            // SAFETY: query 2*index was reset this frame.
            unsafe {
                device.raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::ALL_COMMANDS, self.pool.raw, 2 * index)
            };
        }
    }

    pub fn end(&mut self, device: &Device, cmd: vk::CommandBuffer) {
        let index = self.names.len() as u32 - 1;
        if self.valid_bits > 0 {
            // SAFETY: query 2*index+1 was reset this frame.
            unsafe {
                device.raw.cmd_write_timestamp2(
                    cmd,
                    vk::PipelineStageFlags2::ALL_COMMANDS,
                    self.pool.raw,
                    2 * index + 1,
                )
            };
        }
        if let Some(du) = &device.debug_utils {
            // SAFETY: matches the begin label above.
            unsafe { du.cmd_end_debug_utils_label(cmd) };
        }
    }

    /// Milliseconds per scope of the last submitted frame (after its fence signalled); None when
    /// the queue has no timestamps.
    pub fn read(&self, device: &ash::Device) -> Result<Option<Vec<(&'static str, f64)>>> {
        if self.valid_bits == 0 || self.names.is_empty() {
            return Ok(None);
        }
        let mut data = vec![0u64; 2 * self.names.len()];
        // SAFETY: the frame's fence was waited on; the queries were written.
        unsafe {
            device.get_query_pool_results(
                self.pool.raw,
                0,
                &mut data,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .during("vkGetQueryPoolResults")?;
        let mask = if self.valid_bits >= 64 { u64::MAX } else { (1u64 << self.valid_bits) - 1 };
        Ok(Some(
            self.names
                .iter()
                .enumerate()
                .map(|(i, &name)| {
                    let ticks = (data[2 * i + 1] & mask).wrapping_sub(data[2 * i] & mask) & mask;
                    (name, ticks as f64 * self.period_ns * 1e-6)
                })
                .collect(),
        ))
    }
}
