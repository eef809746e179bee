//! A Vulkan pipeline cache kept on disk between runs, so that the driver's shader compilation is
//! paid once per device and driver, not once per run. One file per device and driver version
//! under the user's cache folder; a file that is unreadable, truncated, or from another device
//! or driver is ignored (the report says why) and replaced when the run ends.

use super::device::Device;
use crate::error::{Result, VkContext};
use ash::vk;
use std::path::{Path, PathBuf};

/// Bytes of VkPipelineCacheHeaderVersionOne: header size, header version, vendor id, device id
/// (4 bytes each) and the 16-byte pipelineCacheUUID (Vulkan spec, "Pipeline Cache").
const HEADER_BYTES: usize = 32;

/// Where the cache files live: `$OCEAN_CACHE_DIR` (empty: no disk cache), else
/// `$XDG_CACHE_HOME/ocean`, else `$HOME/.cache/ocean` (the XDG base directory default).
pub fn default_dir() -> Option<PathBuf> {
    let var = |name| std::env::var_os(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(dir) = std::env::var_os("OCEAN_CACHE_DIR") {
        return (!dir.is_empty()).then(|| PathBuf::from(dir));
    }
    var("XDG_CACHE_HOME").map(|d| d.join("ocean")).or_else(|| var("HOME").map(|h| h.join(".cache/ocean")))
}

/// `pipelines-VENDOR-DEVICE-DRIVER-UUID.bin`: a new driver gets a new file rather than a rejected one.
pub fn file_name(properties: &vk::PhysicalDeviceProperties) -> String {
    let uuid: String = properties.pipeline_cache_uuid.iter().map(|b| format!("{b:02x}")).collect();
    format!(
        "pipelines-{:04x}-{:04x}-{:08x}-{uuid}.bin",
        properties.vendor_id, properties.device_id, properties.driver_version
    )
}

/// Checks the header the specification puts at the start of cache data; Err says what is off.
pub fn check_header(data: &[u8], properties: &vk::PhysicalDeviceProperties) -> Result<(), String> {
    if data.len() < HEADER_BYTES {
        return Err(format!("{} bytes, shorter than a cache header", data.len()));
    }
    let word = |i: usize| u32::from_le_bytes([data[4 * i], data[4 * i + 1], data[4 * i + 2], data[4 * i + 3]]);
    let (size, version, vendor, device) = (word(0), word(1), word(2), word(3));
    if (size as usize) < HEADER_BYTES || size as usize > data.len() {
        return Err(format!("header size {size} is not valid"));
    }
    if version != vk::PipelineCacheHeaderVersion::ONE.as_raw() as u32 {
        return Err(format!("header version {version} is not 1"));
    }
    if (vendor, device) != (properties.vendor_id, properties.device_id) {
        return Err(format!(
            "made by device {vendor:04x}:{device:04x}, this is {:04x}:{:04x}",
            properties.vendor_id, properties.device_id
        ));
    }
    if data[16..32] != properties.pipeline_cache_uuid {
        return Err("made by another driver (pipeline cache UUID differs)".into());
    }
    Ok(())
}

const LOADED: &str = "loaded";

/// What the run started from, for the report.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CacheReport {
    /// The cache file, or none where no disk cache is kept.
    pub file: Option<PathBuf>,
    /// Bytes of cache data given to the driver at start (0 when starting empty).
    pub loaded_bytes: u64,
    /// "loaded", "none yet", "disabled", or why the file was ignored.
    pub status: String,
}

pub struct PipelineCache {
    pub raw: vk::PipelineCache,
    pub report: CacheReport,
    /// The driver was given the file's data (so an unchanged size means nothing was added).
    loaded: bool,
}

impl PipelineCache {
    /// Creates the device's cache, seeded from `dir`'s file for this device where it is valid.
    pub fn open(raw: &ash::Device, properties: &vk::PhysicalDeviceProperties, dir: Option<&Path>) -> Result<Self> {
        let file = dir.map(|d| d.join(file_name(properties)));
        let (data, status) = match &file {
            None => (Vec::new(), "disabled".to_owned()),
            Some(path) => match std::fs::read(path) {
                Ok(data) => match check_header(&data, properties) {
                    Ok(()) => (data, LOADED.to_owned()),
                    Err(why) => (Vec::new(), format!("ignored: {why}")),
                },
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => (Vec::new(), "none yet".to_owned()),
                Err(e) => (Vec::new(), format!("ignored: {e}")),
            },
        };
        let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
        // SAFETY: `data` is empty or starts with a header that matches this device and driver;
        // the driver checks the rest and starts empty when it does not accept it.
        let cache = unsafe { raw.create_pipeline_cache(&info, None) }.during("vkCreatePipelineCache")?;
        let loaded = status == LOADED;
        let report = CacheReport { file, loaded_bytes: data.len() as u64, status };
        Ok(PipelineCache { raw: cache, report, loaded })
    }

    /// Writes the cache's data to its file (atomically) where it differs from what was loaded;
    /// returns the bytes written, or None when nothing was written.
    pub fn save(&self, device: &Device) -> Result<Option<usize>> {
        let Some(path) = &self.report.file else { return Ok(None) };
        // SAFETY: the cache is live and owned by this device.
        let data = unsafe { device.raw.get_pipeline_cache_data(self.raw) }.during("vkGetPipelineCacheData")?;
        if self.loaded && data.len() as u64 == self.report.loaded_bytes {
            return Ok(None); // nothing was added to what the file holds
        }
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
        }
        crate::output::target::write(path, &data)?;
        Ok(Some(data.len()))
    }
}
