//! Benchmarks that print numbers and write them to files: GPU time per pass over the preset
//! scenes, and device memory at 1920x1080. Timings are the median and the fastest of the frames
//! after a warm-up frame, from timestamp queries; all in one run, so ratios between rows hold on
//! a noisy machine.

pub mod error_vs_time;
pub mod startup;
pub mod view;

use crate::app::{median, minimum, pass_statistic};
use crate::error::{Error, Result};
use crate::measure::floor::{delivered_gflops, shade_work, ShadeWork};
use crate::model::scene::Scene;
use crate::output::progress::Progress;
use crate::output::write_text;
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// The speed targets: the default scene within 40 ms of GPU time per frame at 1024x768 and
/// within 14 ms at 640x360 (more than twice as fast as the authors' demo at equal filtering).
pub const TARGET_MS: f64 = 40.0;
pub const TARGET_SMALL_MS: f64 = 14.0;
/// The small size the default scene is also timed at.
pub const SMALL: (u32, u32) = (640, 360);
/// The memory target at 1920x1080.
pub const TARGET_MIB: f64 = 64.0;

#[derive(Debug, Serialize)]
pub struct SpeedRow {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub median_ms: BTreeMap<String, f64>,
    pub fastest_ms: BTreeMap<String, f64>,
    /// The shading pass's unavoidable work and its time at the device's delivered rate.
    pub shade_work: Option<ShadeWork>,
    pub shade_floor_ms: Option<f64>,
}

#[derive(Debug, Serialize)]
pub struct SpeedReport {
    pub device: String,
    /// What the device delivers for independent FMAs (measure::floor).
    pub delivered_gflops: f64,
    pub frames: u32,
    pub rows: Vec<SpeedRow>,
    pub memory_1080p_used_mib: f64,
    pub memory_1080p_reserved_mib: f64,
}

fn totals(passes: Vec<(String, f64)>) -> BTreeMap<String, f64> {
    let total = passes.iter().map(|(_, ms)| ms).sum();
    let mut map: BTreeMap<String, f64> = passes.into_iter().collect();
    map.insert("total".into(), total);
    map
}

/// Renders each scene `frames + 1` times at `width` x `height` and keeps per-pass statistics.
pub fn time_scene(
    gpu: &Gpu,
    name: &str,
    scene: &Scene,
    width: u32,
    height: u32,
    frames: u32,
    options: Options,
) -> Result<SpeedRow> {
    let mut renderer = Renderer::new(gpu, scene, width, height, options)?;
    renderer.render(scene)?; // warm-up: lazy shader compilation
    let mut timings = Vec::new();
    for _ in 0..frames {
        let frame = renderer.render(scene)?;
        if frame.pass_ms.is_empty() {
            return Err(Error::Argument(format!("{} has no timestamp support", gpu.device.name)));
        }
        timings.push(frame.pass_ms);
    }
    Ok(SpeedRow {
        scene: name.to_owned(),
        width,
        height,
        median_ms: totals(pass_statistic(&timings, median)),
        fastest_ms: totals(pass_statistic(&timings, minimum)),
        shade_work: None,
        shade_floor_ms: None,
    })
}

pub fn speed(gpu: &Gpu, scenes_dir: &Path, frames: u32, out_dir: &Path) -> Result<SpeedReport> {
    let mut scenes = vec![("default".to_owned(), Scene::default())];
    let mut paths: Vec<_> = std::fs::read_dir(scenes_dir)
        .map_err(|e| Error::io(scenes_dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml") && p.file_stem().is_some_and(|s| s != "default"))
        .collect();
    paths.sort();
    for path in paths {
        let name = path.file_stem().unwrap_or_default().to_string_lossy().into_owned();
        scenes.push((name, Scene::load(&path)?));
    }
    let mut rows = Vec::new();
    // Every scene at 1024x768, then the default scene at the small size.
    let runs: Vec<_> = scenes
        .iter()
        .map(|(name, scene)| (name, scene, (1024, 768)))
        .chain(std::iter::once((&scenes[0].0, &scenes[0].1, SMALL)))
        .collect();
    let gflops = delivered_gflops(gpu, 3)?;
    crate::say!("the device delivers {gflops:.1} GFLOP/s of independent FMAs (glsl/flops.comp)");
    let mut progress = Progress::new("bench speed", runs.len() as u64 + 1, "scenes", true);
    for (i, &(name, scene, (width, height))) in runs.iter().enumerate() {
        progress.set(i as u64, Some(&format!("timing {name} at {width}x{height}, {} frames", frames + 1)));
        let wave_set = crate::model::waves::generate(scene);
        let (options, _) = crate::render::specialize::plan(scene, &wave_set, width, height, Options::default());
        let mut row = time_scene(gpu, name, scene, width, height, frames, options)?;
        let work = shade_work(scene, &wave_set, width, height);
        row.shade_floor_ms = Some(work.gflop / gflops * 1e3);
        row.shade_work = Some(work);
        progress.println(&format!(
            "{:<14} {}x{}  median {:7.1} ms  fastest {:7.1} ms",
            row.scene, row.width, row.height, row.median_ms["total"], row.fastest_ms["total"]
        ));
        rows.push(row);
    }
    progress.set(runs.len() as u64, Some("memory at 1920x1080"));
    let (used, reserved) = {
        let scene = Scene::default();
        let mut renderer = Renderer::new(gpu, &scene, 1920, 1080, Options::default())?;
        renderer.render(&scene)?;
        let m = renderer.memory();
        (m.used_bytes as f64 / 1048576.0, m.reserved_bytes as f64 / 1048576.0)
    };
    progress.set(runs.len() as u64 + 1, None);
    crate::say!("memory at 1920x1080: {used:.1} MiB used, {reserved:.1} MiB reserved (target < {TARGET_MIB} MiB)");
    let report = SpeedReport {
        device: gpu.device.name.clone(),
        delivered_gflops: gflops,
        frames,
        rows,
        memory_1080p_used_mib: used,
        memory_1080p_reserved_mib: reserved,
    };
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    write_text(&out_dir.join("speed.json"), &serde_json::to_string_pretty(&report).expect("serializes"))?;
    write_text(&out_dir.join("speed.md"), &markdown(&report))?;
    Ok(report)
}

fn markdown(r: &SpeedReport) -> String {
    // Every pass any row ran (scenes leave out what they do not need).
    let passes: std::collections::BTreeSet<&String> =
        r.rows.iter().flat_map(|row| row.median_ms.keys()).filter(|k| *k != "total").collect();
    let mut s = format!(
        "GPU time per frame on {}, median (fastest) of {} frames after a warm-up frame, ms.\n\n| scene | size |",
        r.device, r.frames
    );
    for p in &passes {
        s += &format!(" {p} |");
    }
    s += " total | total / target | shade floor | shade / floor |\n|---|---|";
    s += &"---|".repeat(passes.len() + 4);
    s += "\n";
    for row in &r.rows {
        let target = if (row.width, row.height) == SMALL { TARGET_SMALL_MS } else { TARGET_MS };
        s += &format!("| {} | {}x{} |", row.scene, row.width, row.height);
        for p in &passes {
            match (row.median_ms.get(*p), row.fastest_ms.get(*p)) {
                (Some(median), Some(fastest)) => s += &format!(" {median:.1} ({fastest:.1}) |"),
                _ => s += " — |",
            }
        }
        s += &format!(
            " {:.1} ({:.1}) | {:.2} ({:.2}) |",
            row.median_ms["total"],
            row.fastest_ms["total"],
            row.median_ms["total"] / target,
            row.fastest_ms["total"] / target
        );
        match (row.shade_floor_ms, row.fastest_ms.get("shade")) {
            (Some(floor), Some(&shade)) if floor > 0.0 => s += &format!(" {floor:.1} | {:.1} |\n", shade / floor),
            _ => s += " — | — |\n",
        }
    }
    s += &format!(
        "\nTargets: the default scene within {TARGET_MS} ms at 1024x768 and {TARGET_SMALL_MS} ms at {}x{} (total / target divides each row by its size's target). Shade floor: the shading pass's unavoidable floating-point work (the trains each sea pixel resolves, on average {}, and the BRDF; measure::floor) at the {:.1} GFLOP/s the device delivers for independent FMAs; shade / floor divides the pass's fastest time by it. Device memory at 1920x1080: {:.1} MiB used, {:.1} MiB reserved in blocks (target < {TARGET_MIB} MiB).\n",
        SMALL.0,
        SMALL.1,
        r.rows.first().and_then(|row| row.shade_work).map_or("—".to_owned(), |w| format!("{:.1} in the first row", w.trains_per_sea_pixel)),
        r.delivered_gflops,
        r.memory_1080p_used_mib,
        r.memory_1080p_reserved_mib
    );
    s
}

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
