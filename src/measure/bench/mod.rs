//! Benchmarks that print numbers and write them to files: GPU time per pass over the preset
//! scenes and device memory at 1920x1080 (`speed`), the comparison of two such runs
//! (`compare`), error against time, the sea's reflections of a scene's objects method by method
//! (`reflections`), where the sky's error comes from (`sky_model`), temporal
//! flicker, start-up, the window, and what
//! specialization saves (here).
//! Timings come from timestamp queries of frames after a warm-up frame; what is compared is
//! measured in one run, so ratios hold on a noisy machine.

pub mod compare;
pub mod embed;
pub mod error_detail;
pub mod error_vs_time;
pub mod flicker;
pub mod local_waves;
pub mod reflections;
pub mod sky;
pub mod sky_model;
pub mod speed;
pub mod startup;
pub mod view;

use crate::app::median;
use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::output::progress::Progress;
use crate::output::write_text;
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use serde::Serialize;
use std::path::Path;

#[derive(Debug, Serialize)]
pub struct SpecializeRow {
    pub scene: String,
    pub omitted: Vec<String>,
    /// Median and fastest frame of each pipeline.
    pub general_ms: f64,
    pub specialized_ms: f64,
    pub general_fastest_ms: f64,
    pub specialized_fastest_ms: f64,
}

/// Frame times of two renderers of one scene, frames interleaved so that the machine's drift
/// falls on both alike: (median, fastest) of each.
fn interleaved(gpu: &Gpu, scene: &Scene, frames: u32, a: Options, b: Options) -> Result<[(f64, f64); 2]> {
    let mut renderers = [Renderer::new(gpu, scene, 1024, 768, a)?, Renderer::new(gpu, scene, 1024, 768, b)?];
    let mut times = [Vec::new(), Vec::new()];
    for r in &mut renderers {
        r.render(scene)?; // warm-up
    }
    for _ in 0..frames {
        for (r, t) in renderers.iter_mut().zip(&mut times) {
            t.push(r.render(scene)?.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>());
        }
    }
    Ok(times.map(|mut t| {
        t.sort_by(f64::total_cmp);
        (median(&t), t[0])
    }))
}

/// Every scene of `dirs` at 1024x768 with the general pipeline and with what it needs only,
/// alternating per scene in one run; median frame time of each.
pub fn specialize(gpu: &Gpu, dirs: &[&Path], frames: u32, out_dir: &Path) -> Result<Vec<SpecializeRow>> {
    let mut paths = Vec::new();
    for dir in dirs {
        let mut found: Vec<_> = std::fs::read_dir(dir)
            .map_err(|e| Error::io(dir, e))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .collect();
        found.sort();
        paths.extend(found);
    }
    let mut rows = Vec::new();
    let mut progress = Progress::new("bench specialize", paths.len() as u64, "scenes", true);
    for (i, path) in paths.iter().enumerate() {
        let scene = Scene::load(path)?;
        let name = path.display().to_string();
        progress.set(i as u64, Some(&format!("timing {name}, both pipelines, {} frames each", frames + 1)));
        let wave_set = crate::model::waves::generate(&scene);
        let (options, omitted) = crate::render::specialize::plan(&scene, &wave_set, 1024, 768, Options::default());
        let [general, special] = interleaved(gpu, &scene, frames, Options::default(), options)?;
        let row = SpecializeRow {
            scene: name,
            omitted: omitted.into_iter().filter(|o| !o.what.starts_with("resolve")).map(|o| o.what).collect(),
            general_ms: general.0,
            specialized_ms: special.0,
            general_fastest_ms: general.1,
            specialized_fastest_ms: special.1,
        };
        progress.println(&format!(
            "{:<40} general {:7.1} ms  specialized {:7.1} ms  {}",
            row.scene,
            row.general_ms,
            row.specialized_ms,
            row.omitted.join(", ")
        ));
        rows.push(row);
    }
    progress.set(paths.len() as u64, None);
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    write_text(&out_dir.join("specialize.json"), &serde_json::to_string_pretty(&rows).expect("serializes"))?;
    let mut md = format!(
        "GPU time per frame at 1024x768 on {}: median (fastest) of {frames} frames after a warm-up, the general pipeline and the one the scene needs rendering alternate frames in one run. Rows that leave nothing out show the machine's noise.\n\n| scene | left out | general ms | specialized ms | saving (median) |\n|---|---|---|---|---|\n",
        gpu.device.name
    );
    for r in &rows {
        let omitted = if r.omitted.is_empty() { "nothing".to_owned() } else { r.omitted.join(", ") };
        md += &format!(
            "| {} | {omitted} | {:.1} ({:.1}) | {:.1} ({:.1}) | {:+.0}% |\n",
            r.scene,
            r.general_ms,
            r.general_fastest_ms,
            r.specialized_ms,
            r.specialized_fastest_ms,
            100.0 * (r.general_ms - r.specialized_ms) / r.general_ms
        );
    }
    write_text(&out_dir.join("specialize.md"), &md)?;
    Ok(rows)
}
