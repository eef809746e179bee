//! `bench speed`: GPU time per pass of every preset scene at 1024x768 (and the default scene at
//! 640x360) against the targets and the shading pass's arithmetic floor, and device memory at
//! 1920x1080. `--repeat R` runs every scene R times in rounds; `--variant LABEL=FLAGS` (given
//! twice or more) times builds or settings instead, each as `ocean render` processes whose
//! order rotates within every round, one file per variant for `bench compare`.

use crate::app::{median, minimum, pass_statistic};
use crate::error::{Error, Result};
use crate::measure::floor::{delivered_gflops, shade_work, ShadeWork};
use crate::measure::samples::{new_run_id, TimedScene, TimingFile};
use crate::model::scene::Scene;
use crate::output::progress::Progress;
use crate::output::write_text;
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

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
    /// Shared by the files of one interleaved run.
    pub run_id: String,
    /// What this file's frames ran ("default", or a variant's label and flags).
    pub settings: String,
    /// What the device delivers for independent FMAs (measure::floor).
    pub delivered_gflops: Option<f64>,
    pub frames: u32,
    pub repeat: u32,
    pub rows: Vec<SpeedRow>,
    pub memory_1080p_used_mib: Option<f64>,
    pub memory_1080p_reserved_mib: Option<f64>,
    /// Every timed frame (`bench compare` reads these).
    pub timings: Vec<TimedScene>,
}

/// A build or a setting to time: `LABEL=FLAGS`, FLAGS being `ocean render` flags, the first one
/// optionally `@PATH` naming another build's binary.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    pub label: String,
    pub binary: Option<PathBuf>,
    pub flags: Vec<String>,
}

/// Render flags a variant may not set: the bench sets them.
const BENCH_FLAGS: [&str; 6] = ["--scene", "--width", "--height", "--frames", "--report", "--out"];

pub fn parse_variant(text: &str) -> std::result::Result<Variant, String> {
    let (label, flags) = text.split_once('=').ok_or_else(|| format!("{text:?}: a variant is LABEL=FLAGS"))?;
    let label = label.trim();
    if label.is_empty() || !label.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return Err(format!(
            "{text:?}: the label must be letters, digits, - or _ (it names the file speed.LABEL.json)"
        ));
    }
    let mut flags: Vec<String> = flags.split_whitespace().map(str::to_owned).collect();
    let binary = match flags.first() {
        Some(first) if first.starts_with('@') => Some(PathBuf::from(&flags.remove(0)[1..])),
        _ => None,
    };
    if let Some(flag) = flags.iter().find(|f| BENCH_FLAGS.iter().any(|b| f.split('=').next() == Some(*b))) {
        return Err(format!("{text:?}: {flag} is set by the bench"));
    }
    Ok(Variant { label: label.to_owned(), binary, flags })
}

fn totals(passes: Vec<(String, f64)>) -> BTreeMap<String, f64> {
    let total = passes.iter().map(|(_, ms)| ms).sum();
    let mut map: BTreeMap<String, f64> = passes.into_iter().collect();
    map.insert("total".into(), total);
    map
}

/// A scene to time: its name, its file (None: the built-in defaults), the scene, the size.
struct Run {
    name: String,
    path: Option<PathBuf>,
    scene: Scene,
    size: (u32, u32),
}

/// Every preset of `scenes_dir` at 1024x768, the default scene first, then at the small size.
fn runs(scenes_dir: &Path) -> Result<Vec<Run>> {
    let mut paths: Vec<_> = std::fs::read_dir(scenes_dir)
        .map_err(|e| Error::io(scenes_dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml") && p.file_stem().is_some_and(|s| s != "default"))
        .collect();
    paths.sort();
    let default = |size| Run { name: "default".into(), path: None, scene: Scene::default(), size };
    let mut runs = vec![default((1024, 768))];
    for path in paths {
        let name = path.file_stem().unwrap_or_default().to_string_lossy().into_owned();
        runs.push(Run { name, scene: Scene::load(&path)?, path: Some(path), size: (1024, 768) });
    }
    runs.push(default(SMALL));
    Ok(runs)
}

/// Renders a scene `frames + 1` times and adds the frames after the first to `into`.
fn time_in_process(gpu: &Gpu, run: &Run, frames: u32, round: u32, into: &mut TimedScene) -> Result<()> {
    let (width, height) = run.size;
    let wave_set = crate::model::waves::generate(&run.scene);
    let (options, _) = crate::render::specialize::plan(&run.scene, &wave_set, width, height, Options::default());
    let mut renderer = Renderer::new(gpu, &run.scene, width, height, options)?;
    renderer.render(&run.scene)?; // warm-up: lazy shader compilation
    for _ in 0..frames {
        let frame = renderer.render(&run.scene)?;
        if frame.pass_ms.is_empty() {
            return Err(Error::Argument(format!("{} has no timestamp support", gpu.device.name)));
        }
        into.push(round, &frame.pass_ms);
    }
    Ok(())
}

/// Runs `ocean render` of a scene for a variant and adds its timed frames to `into`.
fn time_process(variant: &Variant, run: &Run, frames: u32, round: u32, into: &mut TimedScene) -> Result<()> {
    let binary = match &variant.binary {
        Some(path) => path.clone(),
        None => std::env::current_exe().map_err(|e| Error::io(Path::new("current executable"), e))?,
    };
    let dir = std::env::temp_dir().join(format!("ocean-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let (report, png) = (dir.join("report.json"), dir.join("frame.png"));
    let mut command = std::process::Command::new(&binary);
    command.arg("render");
    if let Some(path) = &run.path {
        command.arg("--scene").arg(path);
    }
    let (width, height) = run.size;
    command
        .args(["--width", &width.to_string(), "--height", &height.to_string(), "--frames", &(frames + 1).to_string()])
        .arg("--report")
        .arg(&report)
        .arg("--out")
        .arg(&png)
        .args(&variant.flags);
    let output = command.output().map_err(|e| Error::io(&binary, e))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(Error::Argument(format!(
            "variant {}: {} render failed: {}",
            variant.label,
            binary.display(),
            stderr.lines().last().unwrap_or("no message")
        )));
    }
    let text = std::fs::read_to_string(&report).map_err(|e| Error::io(&report, e))?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| Error::io(&report, e))?;
    let per_pass = json["gpu_ms_frames"].as_object().ok_or_else(|| {
        Error::Argument(format!(
            "variant {}: {} writes no per-frame times (gpu_ms_frames): a build older than bench compare",
            variant.label,
            binary.display()
        ))
    })?;
    let passes: Vec<(String, Vec<f64>)> = per_pass
        .iter()
        .filter(|(name, _)| *name != "total")
        .map(|(name, v)| {
            (name.clone(), v.as_array().map_or(Vec::new(), |a| a.iter().filter_map(|x| x.as_f64()).collect()))
        })
        .collect();
    for i in 0..frames as usize {
        let frame: Vec<(String, f64)> =
            passes.iter().filter_map(|(name, v)| v.get(i).map(|&ms| (name.clone(), ms))).collect();
        into.push(round, &frame);
    }
    Ok(())
}

fn row(t: &TimedScene) -> SpeedRow {
    // Per-frame pass lists back from the samples, for the shared statistics.
    let n = t.round.len();
    let frames: Vec<Vec<(String, f64)>> = (0..n)
        .map(|i| t.frames_ms.iter().filter(|(p, _)| *p != "total").map(|(p, v)| (p.clone(), v[i])).collect())
        .collect();
    SpeedRow {
        scene: t.scene.clone(),
        width: t.width,
        height: t.height,
        median_ms: totals(pass_statistic(&frames, median)),
        fastest_ms: totals(pass_statistic(&frames, minimum)),
        shade_work: None,
        shade_floor_ms: None,
    }
}

pub struct SpeedRequest<'a> {
    pub scenes_dir: &'a Path,
    pub frames: u32,
    pub repeat: u32,
    pub variants: Vec<Variant>,
    pub out_dir: &'a Path,
}

/// Times the presets in-process (no variants) and writes speed.json and speed.md, or each
/// variant as processes and writes speed.LABEL.json and speed.LABEL.md.
pub fn speed(gpu: &Gpu, request: &SpeedRequest) -> Result<Vec<SpeedReport>> {
    let runs = runs(request.scenes_dir)?;
    let run_id = new_run_id();
    let variants: Vec<Option<&Variant>> =
        if request.variants.is_empty() { vec![None] } else { request.variants.iter().map(Some).collect() };
    let settings = |v: Option<&Variant>| {
        v.map_or("default".to_owned(), |v| {
            let binary = v.binary.as_ref().map(|b| format!("@{} ", b.display())).unwrap_or_default();
            format!("{}: {binary}{}", v.label, v.flags.join(" "))
        })
    };
    let mut timings: Vec<Vec<TimedScene>> = variants
        .iter()
        .map(|&v| runs.iter().map(|r| TimedScene::new(&r.name, &r.scene, r.size.0, r.size.1, &settings(v))).collect())
        .collect();
    let gflops = if request.variants.is_empty() {
        let g = delivered_gflops(gpu, 3)?;
        crate::say!("the device delivers {g:.1} GFLOP/s of independent FMAs (glsl/flops.comp)");
        Some(g)
    } else {
        None
    };
    let steps = (request.repeat as usize * runs.len() * variants.len()) as u64;
    let mut progress = Progress::new("bench speed", steps + 1, "runs", true);
    let mut done = 0;
    for round in 0..request.repeat {
        for (s, run) in runs.iter().enumerate() {
            // The variants' order rotates with the round and the scene, so none is always first.
            for k in 0..variants.len() {
                let v = (k + round as usize + s) % variants.len();
                let label = variants[v].map_or("", |v| v.label.as_str());
                let (w, h) = run.size;
                let what = format!("round {}/{}: {} {label} at {w}x{h}", round + 1, request.repeat, run.name);
                progress.set(done, Some(&what));
                match variants[v] {
                    None => time_in_process(gpu, run, request.frames, round, &mut timings[v][s])?,
                    Some(variant) => time_process(variant, run, request.frames, round, &mut timings[v][s])?,
                }
                done += 1;
            }
        }
    }
    let memory = if request.variants.is_empty() {
        progress.set(done, Some("memory at 1920x1080"));
        let scene = Scene::default();
        let mut renderer = Renderer::new(gpu, &scene, 1920, 1080, Options::default())?;
        renderer.render(&scene)?;
        let m = renderer.memory();
        Some((m.used_bytes as f64 / 1048576.0, m.reserved_bytes as f64 / 1048576.0))
    } else {
        None
    };
    progress.set(steps + 1, None);
    std::fs::create_dir_all(request.out_dir).map_err(|e| Error::io(request.out_dir, e))?;
    let mut reports = Vec::new();
    for (v, timings) in variants.iter().zip(timings) {
        let mut rows: Vec<SpeedRow> = timings.iter().map(row).collect();
        if let Some(g) = gflops {
            for (row, run) in rows.iter_mut().zip(&runs) {
                let work = shade_work(&run.scene, &crate::model::waves::generate(&run.scene), run.size.0, run.size.1);
                row.shade_floor_ms = Some(work.gflop / g * 1e3);
                row.shade_work = Some(work);
            }
        }
        for row in &rows {
            crate::say!(
                "{:<14} {:<10} {}x{}  median {:7.1} ms  fastest {:7.1} ms",
                row.scene,
                v.map_or("", |v| v.label.as_str()),
                row.width,
                row.height,
                row.median_ms["total"],
                row.fastest_ms["total"]
            );
        }
        let report = SpeedReport {
            device: gpu.device.name.clone(),
            run_id: run_id.clone(),
            settings: settings(*v),
            delivered_gflops: gflops,
            frames: request.frames,
            repeat: request.repeat,
            rows,
            memory_1080p_used_mib: memory.map(|m| m.0),
            memory_1080p_reserved_mib: memory.map(|m| m.1),
            timings,
        };
        let stem = v.map_or("speed".to_owned(), |v| format!("speed.{}", v.label));
        let json = serde_json::to_string_pretty(&report).expect("serializes");
        write_text(&request.out_dir.join(format!("{stem}.json")), &json)?;
        write_text(&request.out_dir.join(format!("{stem}.md")), &markdown(&report))?;
        reports.push(report);
    }
    if let Some((used, reserved)) = memory {
        crate::say!("memory at 1920x1080: {used:.1} MiB used, {reserved:.1} MiB reserved (target < {TARGET_MIB} MiB)");
    }
    Ok(reports)
}

/// Reads what `bench compare` needs from a file that `bench speed` or `profile` wrote.
pub fn read_timing_file(path: &Path) -> Result<TimingFile> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| {
        Error::io(path, format!("not a timing file of bench speed or profile (device, run_id, timings): {e}"))
    })
}

fn markdown(r: &SpeedReport) -> String {
    // Every pass any row ran (scenes leave out what they do not need).
    let passes: std::collections::BTreeSet<&String> =
        r.rows.iter().flat_map(|row| row.median_ms.keys()).filter(|k| *k != "total").collect();
    let rounds = if r.repeat > 1 { format!(" in each of {} rounds", r.repeat) } else { String::new() };
    let mut s = format!(
        "GPU time per frame on {} ({}), median (fastest) of {} frames{rounds} after a warm-up frame, ms.\n\n| scene | size |",
        r.device, r.settings, r.frames
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
        "\nTargets: the default scene within {TARGET_MS} ms at 1024x768 and {TARGET_SMALL_MS} ms at {}x{} (total / target divides each row by its size's target).",
        SMALL.0, SMALL.1
    );
    if let Some(g) = r.delivered_gflops {
        s += &format!(
            " Shade floor: the shading pass's unavoidable floating-point work (the trains each sea pixel resolves, on average {}, and the BRDF; measure::floor) at the {g:.1} GFLOP/s the device delivers for independent FMAs; shade / floor divides the pass's fastest time by it.",
            r.rows.first().and_then(|row| row.shade_work).map_or("—".to_owned(), |w| format!("{:.1} in the first row", w.trains_per_sea_pixel)),
        );
    }
    if let (Some(used), Some(reserved)) = (r.memory_1080p_used_mib, r.memory_1080p_reserved_mib) {
        s += &format!(" Device memory at 1920x1080: {used:.1} MiB used, {reserved:.1} MiB reserved in blocks (target < {TARGET_MIB} MiB).");
    }
    s + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variants_parse_with_an_optional_binary_and_refuse_the_bench_s_own_flags() {
        let v = parse_variant("blocks=--train-reads blocks").unwrap();
        assert_eq!(
            (v.label.as_str(), v.binary.as_ref(), v.flags.as_slice()),
            ("blocks", None, &["--train-reads".to_owned(), "blocks".to_owned()][..])
        );
        let v = parse_variant("old=@/tmp/ocean --no-specialize").unwrap();
        assert_eq!(v.binary, Some(PathBuf::from("/tmp/ocean")));
        assert_eq!(v.flags, vec!["--no-specialize"]);
        assert_eq!(parse_variant("base=").unwrap().flags, Vec::<String>::new());
        assert!(parse_variant("no label").unwrap_err().contains("LABEL=FLAGS"));
        assert!(parse_variant("a b=--x").unwrap_err().contains("label"));
        assert!(parse_variant("a=--frames 3").unwrap_err().contains("--frames is set by the bench"));
    }
}
