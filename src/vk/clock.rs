//! Putting GPU timestamps on the CPU's clock. The host clock of our traces is CLOCK_MONOTONIC on
//! Unix (what VK_EXT_calibrated_timestamps calls VK_TIME_DOMAIN_CLOCK_MONOTONIC_EXT); where the
//! device can sample its timestamp counter together with that clock, a GPU span maps exactly,
//! within the deviation the driver reports. Elsewhere the caller aligns a frame's first
//! timestamp with its submit and says so.

use super::device::Device;
use super::profiler::tick_mask;
use crate::error::{Result, VkContext};
use ash::vk;

/// The host time domain our clock reads, where Vulkan has a name for it.
#[cfg(unix)]
pub const HOST_DOMAIN: Option<vk::TimeDomainEXT> = Some(vk::TimeDomainEXT::CLOCK_MONOTONIC);
#[cfg(not(unix))]
pub const HOST_DOMAIN: Option<vk::TimeDomainEXT> = None;

/// Nanoseconds on the host clock (CLOCK_MONOTONIC on Unix; elsewhere since the first call).
#[cfg(unix)]
pub fn host_now_ns() -> u64 {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `t` is a valid timespec to write; CLOCK_MONOTONIC exists on every Unix we build for.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut t) };
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}

#[cfg(not(unix))]
pub fn host_now_ns() -> u64 {
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    START.get_or_init(std::time::Instant::now).elapsed().as_nanos() as u64
}

/// The device's timestamp counter and the host clock read at one moment.
#[derive(Clone, Copy, Debug)]
pub struct Calibration {
    /// The device's clock in nanoseconds (ticks masked to the valid bits, times the period).
    pub device_ns: u64,
    pub host_ns: u64,
    /// The driver's bound on how far apart the two samples may be (ns).
    pub max_deviation_ns: u64,
}

/// How the device's clock relates to the host's.
#[derive(Clone, Copy, Debug)]
pub struct DeviceClock {
    period_ns: f64,
    /// The span of the masked counter in nanoseconds (it wraps after that).
    wrap_ns: f64,
}

impl DeviceClock {
    pub fn new(device: &Device) -> Self {
        let period_ns = device.properties.limits.timestamp_period as f64;
        let wrap_ns = (tick_mask(device.timestamp_valid_bits.max(1)) as f64 + 1.0) * period_ns;
        DeviceClock { period_ns, wrap_ns }
    }

    /// Samples both clocks together, where the device has VK_EXT_calibrated_timestamps with the
    /// host's domain (None otherwise).
    pub fn calibrate(&self, device: &Device) -> Result<Option<Calibration>> {
        let (Some(calibrated), Some(host)) = (&device.calibrated_timestamps, HOST_DOMAIN) else {
            return Ok(None);
        };
        let infos = [
            vk::CalibratedTimestampInfoEXT::default().time_domain(vk::TimeDomainEXT::DEVICE),
            vk::CalibratedTimestampInfoEXT::default().time_domain(host),
        ];
        // SAFETY: both domains were listed by vkGetPhysicalDeviceCalibrateableTimeDomainsEXT.
        let (values, deviation) =
            unsafe { calibrated.get_calibrated_timestamps(&infos) }.during("vkGetCalibratedTimestampsEXT")?;
        let mask = tick_mask(device.timestamp_valid_bits.max(1));
        Ok(Some(Calibration {
            device_ns: ((values[0] & mask) as f64 * self.period_ns).round() as u64,
            host_ns: values[1],
            max_deviation_ns: deviation,
        }))
    }

    /// A device time (ns, as `Profiler` reports it) on the host clock, through `at`; the
    /// counter's wrap is undone for times within half its span of the calibration.
    pub fn to_host(&self, device_ns: u64, at: &Calibration) -> f64 {
        let mut delta = device_ns as f64 - at.device_ns as f64;
        if delta > self.wrap_ns / 2.0 {
            delta -= self.wrap_ns;
        } else if delta < -self.wrap_ns / 2.0 {
            delta += self.wrap_ns;
        }
        at.host_ns as f64 + delta
    }
}
