//! `bench sky`: what a moving sun costs. The default scene at 1024x768 rendered with the sun still
//! and with the sun climbing 0.05 degrees a frame (so that the sky map and the aerial perspective
//! are rebuilt every frame, the atmosphere's tables kept: they hold the air, not the sun), frames
//! of the two renderers interleaved; per-pass medians of each.

use crate::app::{median, pass_statistic};
use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::output::write_text;
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Debug, Serialize)]
pub struct SkyBench {
    pub device: String,
    pub frames: u32,
    pub still_sun_ms: BTreeMap<String, f64>,
    pub moving_sun_ms: BTreeMap<String, f64>,
}

fn with_total(passes: Vec<(String, f64)>) -> BTreeMap<String, f64> {
    let total = passes.iter().map(|(_, ms)| ms).sum();
    let mut map: BTreeMap<String, f64> = passes.into_iter().collect();
    map.insert("total".into(), total);
    map
}

pub fn run(gpu: &Gpu, frames: u32, out_dir: &Path) -> Result<SkyBench> {
    let scene = Scene::default();
    let (w, h) = (1024, 768);
    let mut still = Renderer::new(gpu, &scene, w, h, Options::default())?;
    let mut moving = Renderer::new(gpu, &scene, w, h, Options::default())?;
    let mut sun = scene.clone();
    // Warm-up: the first frame of each compiles the driver's shaders lazily.
    still.render(&scene)?;
    moving.render(&sun)?;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        a.push(still.render(&scene)?.pass_ms);
        sun.sun.elevation_deg += 0.05;
        b.push(moving.render(&sun)?.pass_ms);
    }
    if a.iter().any(|f| f.is_empty()) {
        return Err(Error::Argument(format!("{} has no timestamp support", gpu.device.name)));
    }
    // Frames list different passes (the still sun's leave the sky's out): fill the missing as 0.
    let names: Vec<String> = b[0].iter().map(|(n, _)| n.clone()).collect();
    let fill = |frames: Vec<Vec<(String, f64)>>| -> Vec<Vec<(String, f64)>> {
        frames
            .into_iter()
            .map(|f| names.iter().map(|n| (n.clone(), f.iter().find(|(m, _)| m == n).map_or(0.0, |p| p.1))).collect())
            .collect()
    };
    let bench = SkyBench {
        device: gpu.device.name.clone(),
        frames,
        still_sun_ms: with_total(pass_statistic(&fill(a), median)),
        moving_sun_ms: with_total(pass_statistic(&fill(b), median)),
    };
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    write_text(&out_dir.join("sky.json"), &serde_json::to_string_pretty(&bench).expect("serializes"))?;
    let mut md = format!(
        "GPU time per frame of the default scene at 1024x768 on {}, median of {frames} interleaved frames after a warm-up, ms: the sun still, and the sun climbing 0.05 degrees a frame.\n\n| pass | still sun | moving sun |\n|---|---|---|\n",
        bench.device
    );
    for (pass, ms) in &bench.moving_sun_ms {
        md += &format!("| {pass} | {:.2} | {ms:.2} |\n", bench.still_sun_ms.get(pass).copied().unwrap_or(0.0));
    }
    write_text(&out_dir.join("sky.md"), &md)?;
    Ok(bench)
}
