//! The machine-readable report of one render.

use crate::vk::memory::MemoryReport;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Debug, Serialize)]
pub struct Report {
    pub device: String,
    pub width: u32,
    pub height: u32,
    pub method: crate::render::passes::ocean::Method,
    /// Supersampling: samples per pixel along each axis.
    pub ssaa: u32,
    /// GPU time per pass and in total (ms), from timestamp queries.
    pub gpu_ms: BTreeMap<String, f64>,
    /// With several frames: the fastest frame's time per pass after the first frame (the least
    /// disturbed by other work on a shared machine). Empty for a single frame.
    pub gpu_ms_min: BTreeMap<String, f64>,
    /// Every frame's time per pass after the first (what `bench speed --variant` reads).
    pub gpu_ms_frames: BTreeMap<String, Vec<f64>>,
    /// With --stats: the last frame's pipeline statistics per pass (absent where the device has
    /// none, or without --stats).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pipeline_statistics: Option<BTreeMap<String, crate::vk::profiler::PipelineStatistics>>,
    pub validation: bool,
    pub validation_errors: u32,
    pub validation_warnings: u32,
    /// Message ids seen, with counts.
    pub validation_messages: BTreeMap<String, u32>,
    pub nonfinite_pixels: u64,
    /// Mean linear radiance of the HDR image (kcd/m^2 per channel).
    pub mean_radiance: [f64; 3],
    pub memory: MemoryReport,
    /// The pipeline cache this run started from (file, bytes loaded, or why none was used).
    pub pipeline_cache: crate::vk::pipeline_cache::CacheReport,
    pub grid: GridReport,
    /// The sun's shadow map, where the frame drew one.
    pub shadow_map: Option<ShadowMapReport>,
    /// The eye's height above mean sea level as rendered: the scene's, raised by a crest under it.
    pub eye_height_m: f64,
    /// What this scene did not need and was left out, with why (empty with --no-specialize).
    pub omitted: Vec<crate::render::specialize::Omission>,
    /// The pipelines the frame used.
    pub pipelines: Vec<String>,
    /// The share of the mirror's images its pass built (the objects' mirrored boxes' cover),
    /// where the frame drew one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub planar_cover_share: Option<f64>,
    /// The frame's wave packets (local waves), where the scene has any: how many were drawn, in
    /// how many cells, the share of their sources' energy the budget left out, their crest.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub packets: Option<crate::render::renderer::PacketStats>,
    pub waves: WaveReport,
}

#[derive(Debug, Serialize)]
pub struct GridReport {
    pub columns: u32,
    pub rows: u32,
    pub cell_px: f64,
}

#[derive(Debug, Serialize)]
pub struct ShadowMapReport {
    pub size: u32,
    /// A texel's sides (m): across the sunlight, and across it in its vertical plane (on the
    /// sea, that over the sine of the sun's elevation), over the sea the grid displaces in view.
    pub texel_m: [f64; 2],
}

#[derive(Debug, Serialize)]
pub struct WaveReport {
    pub count: usize,
    pub sigma2_along_wind: f64,
    pub sigma2_across_wind: f64,
    pub mean_height_offset_m: f64,
}

impl Report {
    pub fn gpu_total_ms(pass_ms: &[(String, f64)]) -> BTreeMap<String, f64> {
        let mut map: BTreeMap<String, f64> = pass_ms.iter().cloned().collect();
        if !pass_ms.is_empty() {
            map.insert("total".into(), pass_ms.iter().map(|(_, ms)| ms).sum());
        }
        map
    }
}
