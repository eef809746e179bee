//! What the pipeline cache saves: `ocean render` run as a user runs it, a new process each time,
//! with no disk cache, with an empty cache folder (the first run on a machine) and with the file
//! a previous run left (every later run), interleaved so that the machine's drift falls on all
//! alike; and, for scale, with the driver's own shader cache off where the driver has one that
//! an environment variable turns off (Mesa: MESA_SHADER_CACHE_DISABLE).

use crate::app::median;
use crate::error::{Error, Result};
use crate::output::progress::Progress;
use crate::output::write_text;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// One way of starting `ocean render`.
struct Setup {
    name: &'static str,
    /// OCEAN_CACHE_DIR for the run: None for an empty value (no disk cache).
    cache: CacheFolder,
    driver_cache_off: bool,
}

enum CacheFolder {
    None,
    /// A new empty folder for every run.
    Empty,
    /// The folder a first run filled.
    Filled,
}

#[derive(Debug, Serialize)]
pub struct StartupRow {
    pub setup: String,
    /// Wall time of the whole process, median and fastest (s).
    pub wall_median_s: f64,
    pub wall_fastest_s: f64,
    /// GPU time of the first (and only) frame, median (ms): where the driver compiles lazily.
    pub first_frame_gpu_median_ms: f64,
    /// Cache bytes the run started from.
    pub cache_loaded_bytes: u64,
}

#[derive(Debug, Serialize)]
pub struct StartupReport {
    pub device: String,
    pub runs: u32,
    pub width: u32,
    pub height: u32,
    /// Size of the cache file the runs leave behind.
    pub cache_file_bytes: u64,
    pub rows: Vec<StartupRow>,
}

const SETUPS: [Setup; 4] = [
    Setup { name: "no disk cache", cache: CacheFolder::None, driver_cache_off: false },
    Setup { name: "empty cache folder (first run)", cache: CacheFolder::Empty, driver_cache_off: false },
    Setup { name: "cache file of a previous run", cache: CacheFolder::Filled, driver_cache_off: false },
    Setup { name: "no disk cache, driver's own cache off", cache: CacheFolder::None, driver_cache_off: true },
];

/// (wall seconds, first-frame GPU ms, cache bytes loaded) of one `ocean render` process.
fn run_once(
    exe: &Path,
    cache_dir: Option<&Path>,
    driver_cache_off: bool,
    work: &Path,
    device: Option<&str>,
) -> Result<(f64, f64, u64)> {
    let report = work.join("report.json");
    let mut command = Command::new(exe);
    command.args(["render", "--out"]).arg(work.join("frame.png")).arg("--report").arg(&report);
    if let Some(device) = device {
        command.args(["--device", device]);
    }
    command.env("OCEAN_CACHE_DIR", cache_dir.map(|d| d.as_os_str().to_owned()).unwrap_or_default());
    if driver_cache_off {
        command.env("MESA_SHADER_CACHE_DISABLE", "true");
    }
    let started = Instant::now();
    let output = command.output().map_err(|e| Error::io(exe, e))?;
    let wall = started.elapsed().as_secs_f64();
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(Error::Argument(format!("ocean render failed in the startup bench: {}", stderr.trim())));
    }
    let text = std::fs::read_to_string(&report).map_err(|e| Error::io(&report, e))?;
    let json: serde_json::Value = serde_json::from_str(&text).map_err(|e| Error::io(&report, e))?;
    let gpu_ms = json["gpu_ms"]["total"].as_f64().unwrap_or(f64::NAN);
    let loaded = json["pipeline_cache"]["loaded_bytes"].as_u64().unwrap_or(0);
    Ok((wall, gpu_ms, loaded))
}

/// Runs every setup `runs` times, interleaved, and writes startup.md and startup.json to `out_dir`.
pub fn run(device_name: &str, device: Option<&str>, runs: u32, out_dir: &Path) -> Result<StartupReport> {
    let exe = std::env::current_exe().map_err(|e| Error::io(Path::new("the ocean executable"), e))?;
    let work: PathBuf = std::env::temp_dir().join(format!("ocean-startup-bench-{}", std::process::id()));
    let filled = work.join("filled");
    std::fs::create_dir_all(&filled).map_err(|e| Error::io(&filled, e))?;
    // The first run fills the folder the "previous run" setup starts from.
    run_once(&exe, Some(&filled), false, &work, device)?;
    let mut samples: Vec<Vec<(f64, f64, u64)>> = SETUPS.iter().map(|_| Vec::new()).collect();
    let mut progress = Progress::new("bench startup", (runs as usize * SETUPS.len()) as u64, "runs", true);
    for round in 0..runs {
        for (i, setup) in SETUPS.iter().enumerate() {
            progress.set((round as usize * SETUPS.len() + i) as u64, Some(setup.name));
            let empty = work.join(format!("empty-{round}-{i}"));
            let cache = match setup.cache {
                CacheFolder::None => None,
                CacheFolder::Empty => Some(empty.as_path()),
                CacheFolder::Filled => Some(filled.as_path()),
            };
            samples[i].push(run_once(&exe, cache, setup.driver_cache_off, &work, device)?);
        }
    }
    progress.set((runs as usize * SETUPS.len()) as u64, None);
    let cache_file_bytes = std::fs::read_dir(&filled)
        .map_err(|e| Error::io(&filled, e))?
        .filter_map(|e| e.ok()?.metadata().ok())
        .map(|m| m.len())
        .sum();
    let _ = std::fs::remove_dir_all(&work);
    let rows: Vec<StartupRow> = SETUPS
        .iter()
        .zip(samples)
        .map(|(setup, s)| {
            let sorted = |f: fn(&(f64, f64, u64)) -> f64| {
                let mut v: Vec<f64> = s.iter().map(f).collect();
                v.sort_by(f64::total_cmp);
                v
            };
            let wall = sorted(|x| x.0);
            StartupRow {
                setup: setup.name.to_owned(),
                wall_median_s: median(&wall),
                wall_fastest_s: wall[0],
                first_frame_gpu_median_ms: median(&sorted(|x| x.1)),
                cache_loaded_bytes: s.iter().map(|x| x.2).max().unwrap_or(0),
            }
        })
        .collect();
    let report =
        StartupReport { device: device_name.to_owned(), runs, width: 1024, height: 768, cache_file_bytes, rows };
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    write_text(&out_dir.join("startup.json"), &serde_json::to_string_pretty(&report).expect("serializes"))?;
    write_text(&out_dir.join("startup.md"), &markdown(&report))?;
    Ok(report)
}

fn markdown(r: &StartupReport) -> String {
    let base = r.rows[0].wall_median_s;
    let mut s = format!(
        "`ocean render` of the default scene at {}x{} on {}, a new process per run, {} runs of each setup interleaved: \
         median (fastest) wall time of the whole process, and the GPU time of its one frame (where a driver that \
         compiles lazily pays for it). The cache file is {} bytes.\n\n\
         | setup | wall s | against no disk cache | first frame GPU ms | cache bytes loaded |\n|---|---|---|---|---|\n",
        r.width, r.height, r.device, r.runs, r.cache_file_bytes
    );
    for row in &r.rows {
        s += &format!(
            "| {} | {:.3} ({:.3}) | {:+.0}% | {:.1} | {} |\n",
            row.setup,
            row.wall_median_s,
            row.wall_fastest_s,
            100.0 * (row.wall_median_s - base) / base,
            row.first_frame_gpu_median_ms,
            row.cache_loaded_bytes
        );
    }
    s
}
