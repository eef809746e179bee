//! GPU timestamps per pass, and pipeline statistics where asked for and offered, with a debug
//! label around each pass so RenderDoc, Nsight, our traces and our reports show the same names.
//! Timestamps are masked to the queue's `timestampValidBits` and scaled by `timestampPeriod`.

use super::device::Device;
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;
use serde::Serialize;

/// The counters a pass's pipeline statistics query collects, in the order of their flag bits
/// (the order the results come back in).
const STATISTICS: [vk::QueryPipelineStatisticFlags; 6] = [
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_VERTICES,
    vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::COMPUTE_SHADER_INVOCATIONS,
];

/// What one pass did, counted by the device.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct PipelineStatistics {
    pub input_assembly_vertices: u64,
    pub input_assembly_primitives: u64,
    pub vertex_shader_invocations: u64,
    pub clipping_primitives: u64,
    pub fragment_shader_invocations: u64,
    pub compute_shader_invocations: u64,
}

impl PipelineStatistics {
    fn from_results(r: &[u64]) -> Self {
        PipelineStatistics {
            input_assembly_vertices: r[0],
            input_assembly_primitives: r[1],
            vertex_shader_invocations: r[2],
            clipping_primitives: r[3],
            fragment_shader_invocations: r[4],
            compute_shader_invocations: r[5],
        }
    }
}

/// One scope of a finished frame.
#[derive(Clone, Debug)]
pub struct Scope {
    pub name: &'static str,
    /// Begin and end on the device's clock in nanoseconds, the end unwrapped past the valid bits'
    /// overflow (None when the queue has no timestamps).
    pub device_ns: Option<(u64, u64)>,
    pub statistics: Option<PipelineStatistics>,
}

impl Scope {
    pub fn ms(&self) -> f64 {
        self.device_ns.map_or(0.0, |(begin, end)| (end - begin) as f64 * 1e-6)
    }
}

/// Where a scope's timestamps are written: once every earlier command has completed (as
/// ALL_COMMANDS would, which the best-practices checks flag for timestamps), so that a pass's
/// span holds its own work and none of the pass before it.
const SCOPE_EDGE: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::BOTTOM_OF_PIPE;

pub struct Profiler<'g> {
    timestamps: Option<Owned<'g, vk::QueryPool>>,
    statistics: Option<Owned<'g, vk::QueryPool>>,
    capacity: u32,
    names: Vec<&'static str>,
    period_ns: f64,
    valid_bits: u32,
}

impl<'g> Profiler<'g> {
    /// Room for `max_scopes` scopes a frame; with `statistics`, a pipeline statistics query per
    /// scope too where the device has them (`Device::pipeline_statistics`).
    pub fn new(device: &'g Device, max_scopes: u32, statistics: bool) -> Result<Self> {
        let pool = |info: vk::QueryPoolCreateInfo, name: &str| -> Result<Owned<'g, vk::QueryPool>> {
            // SAFETY: valid create info on a live device.
            let raw = unsafe { device.raw.create_query_pool(&info, None) }.during("vkCreateQueryPool")?;
            Ok(Owned::new(device, raw, name))
        };
        let timestamps = if device.timestamp_valid_bits > 0 {
            let info =
                vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(2 * max_scopes);
            Some(pool(info, "pass timestamps")?)
        } else {
            None
        };
        let statistics = if statistics && device.pipeline_statistics {
            let flags = STATISTICS.iter().fold(vk::QueryPipelineStatisticFlags::empty(), |all, &f| all | f);
            let info = vk::QueryPoolCreateInfo::default()
                .query_type(vk::QueryType::PIPELINE_STATISTICS)
                .pipeline_statistics(flags)
                .query_count(max_scopes);
            Some(pool(info, "pass pipeline statistics")?)
        } else {
            None
        };
        Ok(Profiler {
            timestamps,
            statistics,
            capacity: max_scopes,
            names: Vec::new(),
            period_ns: device.properties.limits.timestamp_period as f64,
            valid_bits: device.timestamp_valid_bits,
        })
    }

    /// Whether this profiler collects pipeline statistics.
    pub fn collects_statistics(&self) -> bool {
        self.statistics.is_some()
    }

    /// Resets the pools for a new frame; recorded outside any rendering scope.
    pub fn reset(&mut self, device: &ash::Device, cmd: vk::CommandBuffer) {
        self.names.clear();
        for (pool, count) in [(&self.timestamps, 2 * self.capacity), (&self.statistics, self.capacity)] {
            if let Some(pool) = pool {
                // SAFETY: `cmd` is recording and the pool's queries are not in use by a pending submission.
                unsafe { device.cmd_reset_query_pool(cmd, pool.raw, 0, count) };
            }
        }
    }

    /// Opens a scope, outside any rendering scope (a statistics query spans the pass's rendering).
    pub fn begin(&mut self, device: &Device, cmd: vk::CommandBuffer, name: &'static str) {
        if let Some(du) = &device.debug_utils {
            let label = std::ffi::CString::new(name).unwrap_or_default();
            // SAFETY: `cmd` is recording; the label string lives through the call.
            unsafe { du.cmd_begin_debug_utils_label(cmd, &vk::DebugUtilsLabelEXT::default().label_name(&label)) };
        }
        let index = self.names.len() as u32;
        assert!(index < self.capacity, "more timestamp scopes than the profiler was made for");
        self.names.push(name);
        if let Some(pool) = &self.timestamps {
            // SAFETY: query 2*index was reset this frame.
            unsafe { device.raw.cmd_write_timestamp2(cmd, SCOPE_EDGE, pool.raw, 2 * index) };
        }
        if let Some(pool) = &self.statistics {
            // SAFETY: query `index` was reset this frame and no other query of the pool is active.
            unsafe { device.raw.cmd_begin_query(cmd, pool.raw, index, vk::QueryControlFlags::empty()) };
        }
    }

    pub fn end(&mut self, device: &Device, cmd: vk::CommandBuffer) {
        let index = self.names.len() as u32 - 1;
        if let Some(pool) = &self.statistics {
            // SAFETY: the query began in `begin` in this command buffer, outside rendering as now.
            unsafe { device.raw.cmd_end_query(cmd, pool.raw, index) };
        }
        if let Some(pool) = &self.timestamps {
            // SAFETY: query 2*index+1 was reset this frame.
            unsafe { device.raw.cmd_write_timestamp2(cmd, SCOPE_EDGE, pool.raw, 2 * index + 1) };
        }
        if let Some(du) = &device.debug_utils {
            // SAFETY: matches the begin label above.
            unsafe { du.cmd_end_debug_utils_label(cmd) };
        }
    }

    /// Milliseconds per scope of the last submitted frame (after its fence signalled); None when
    /// the queue has no timestamps.
    pub fn read(&self, device: &ash::Device) -> Result<Option<Vec<(&'static str, f64)>>> {
        if self.timestamps.is_none() {
            return Ok(None);
        }
        Ok(self.read_scopes(device)?.map(|scopes| scopes.iter().map(|s| (s.name, s.ms())).collect()))
    }

    /// Every scope of the last submitted frame (after its fence signalled), with its timestamps
    /// and statistics; None when the frame recorded no scope.
    pub fn read_scopes(&self, device: &ash::Device) -> Result<Option<Vec<Scope>>> {
        self.read_scopes_with(device, vk::QueryResultFlags::WAIT)
    }

    /// The same without waiting, for frames recorded into a host's command buffer: None until
    /// every query of the frame has a result (a host may drop a recorded frame unsubmitted).
    pub fn try_read_scopes(&self, device: &ash::Device) -> Result<Option<Vec<Scope>>> {
        match self.read_scopes_with(device, vk::QueryResultFlags::empty()) {
            Err(crate::error::Error::Vulkan { result: vk::Result::NOT_READY, .. }) => Ok(None),
            other => other,
        }
    }

    fn read_scopes_with(&self, device: &ash::Device, wait: vk::QueryResultFlags) -> Result<Option<Vec<Scope>>> {
        if self.names.is_empty() {
            return Ok(None);
        }
        let n = self.names.len();
        let mut ticks = vec![0u64; 2 * n];
        if let Some(pool) = &self.timestamps {
            // SAFETY: the queries were reset in the frame's commands; without WAIT an unwritten one
            // answers NOT_READY.
            unsafe { device.get_query_pool_results(pool.raw, 0, &mut ticks, vk::QueryResultFlags::TYPE_64 | wait) }
                .during("vkGetQueryPoolResults (timestamps)")?;
        }
        let mut counts = vec![[0u64; STATISTICS.len()]; n];
        if let Some(pool) = &self.statistics {
            // SAFETY: as above; each element holds one query's STATISTICS.len() counters.
            unsafe { device.get_query_pool_results(pool.raw, 0, &mut counts, vk::QueryResultFlags::TYPE_64 | wait) }
                .during("vkGetQueryPoolResults (pipeline statistics)")?;
        }
        let mask = tick_mask(self.valid_bits);
        let ns = |t: u64| (t as f64 * self.period_ns).round() as u64;
        Ok(Some(
            (0..n)
                .map(|i| Scope {
                    name: self.names[i],
                    device_ns: self.timestamps.as_ref().map(|_| {
                        let begin = ticks[2 * i] & mask;
                        let elapsed = (ticks[2 * i + 1] & mask).wrapping_sub(begin) & mask;
                        (ns(begin), ns(begin) + ns(elapsed))
                    }),
                    statistics: self.statistics.as_ref().map(|_| PipelineStatistics::from_results(&counts[i])),
                })
                .collect(),
        ))
    }
}

/// The bits of a timestamp that hold time (`timestampValidBits`, 1 to 64).
pub fn tick_mask(valid_bits: u32) -> u64 {
    if valid_bits >= 64 {
        u64::MAX
    } else {
        (1u64 << valid_bits) - 1
    }
}
