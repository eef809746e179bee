//! `ocean view` as a user runs it, measured: frames per second, CPU frame time and the share of
//! it spent waiting, per present mode and number of frames in flight. Each setup is a new
//! `ocean view --frames N --report` process on the current display, the setups interleaved over
//! the rounds so that the machine's drift falls on all alike.

use crate::app::median;
use crate::error::{Error, Result};
use crate::output::progress::Progress;
use crate::output::write_text;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Debug, Serialize)]
pub struct ViewRow {
    /// The present mode asked for and the one the surface gave.
    pub present_asked: String,
    pub present_mode: String,
    pub frames_in_flight: u32,
    /// Medians over the rounds of each run's own figures.
    pub fps: f64,
    pub frame_interval_ms: f64,
    pub cpu_frame_ms: f64,
    pub cpu_wait_ms: f64,
    pub cpu_present_ms: f64,
    pub cpu_wait_fraction: f64,
    pub gpu_total_ms: f64,
}

#[derive(Debug, Serialize)]
pub struct ViewBench {
    pub device: String,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub rounds: u32,
    pub rows: Vec<ViewRow>,
}

const SETUPS: [(&str, u32); 6] =
    [("fifo", 2), ("mailbox", 2), ("immediate", 2), ("fifo", 1), ("mailbox", 1), ("immediate", 1)];

fn run_once(exe: &Path, args: &[String], report: &Path) -> Result<serde_json::Value> {
    let output = Command::new(exe).args(args).arg("--report").arg(report).output().map_err(|e| Error::io(exe, e))?;
    if !output.status.success() {
        let stderr = String::from_utf8_lossy(&output.stderr);
        return Err(Error::Argument(format!("ocean view failed in the view bench: {}", stderr.trim())));
    }
    let text = std::fs::read_to_string(report).map_err(|e| Error::io(report, e))?;
    serde_json::from_str(&text).map_err(|e| Error::io(report, e))
}

/// Runs every setup `rounds` times and writes view.md and view.json to `out_dir`.
pub fn run(width: u32, height: u32, frames: u32, rounds: u32, out_dir: &Path) -> Result<ViewBench> {
    let exe = std::env::current_exe().map_err(|e| Error::io(Path::new("the ocean executable"), e))?;
    let work: PathBuf = std::env::temp_dir().join(format!("ocean-view-bench-{}", std::process::id()));
    std::fs::create_dir_all(&work).map_err(|e| Error::io(&work, e))?;
    let mut samples: Vec<Vec<serde_json::Value>> = SETUPS.iter().map(|_| Vec::new()).collect();
    let mut progress = Progress::new("bench view", (rounds as usize * SETUPS.len()) as u64, "runs", true);
    for round in 0..rounds {
        for (i, &(present, in_flight)) in SETUPS.iter().enumerate() {
            let name = format!("{present}, {in_flight} in flight");
            progress.set((round as usize * SETUPS.len() + i) as u64, Some(&name));
            let args: Vec<String> = [
                "view",
                "--frames",
                &frames.to_string(),
                "--width",
                &width.to_string(),
                "--height",
                &height.to_string(),
                "--present",
                present,
                "--frames-in-flight",
                &in_flight.to_string(),
            ]
            .iter()
            .map(|s| s.to_string())
            .collect();
            samples[i].push(run_once(&exe, &args, &work.join("report.json"))?);
        }
    }
    progress.set((rounds as usize * SETUPS.len()) as u64, None);
    let _ = std::fs::remove_dir_all(&work);
    let device = samples[0][0]["device"].as_str().unwrap_or("unknown").to_owned();
    let rows = SETUPS
        .iter()
        .zip(&samples)
        .map(|(&(present, in_flight), runs)| {
            let med = |key: &str| {
                let mut v: Vec<f64> = runs.iter().filter_map(|r| r[key].as_f64()).collect();
                v.sort_by(f64::total_cmp);
                if v.is_empty() {
                    f64::NAN
                } else {
                    median(&v)
                }
            };
            ViewRow {
                present_asked: present.to_owned(),
                present_mode: runs[0]["present_mode"].as_str().unwrap_or("?").to_owned(),
                frames_in_flight: in_flight,
                fps: med("fps"),
                frame_interval_ms: med("frame_interval_ms"),
                cpu_frame_ms: med("cpu_frame_ms"),
                cpu_wait_ms: med("cpu_wait_ms"),
                cpu_present_ms: med("cpu_present_ms"),
                cpu_wait_fraction: med("cpu_wait_fraction"),
                gpu_total_ms: med("gpu_total_ms"),
            }
        })
        .collect();
    let bench = ViewBench { device, width, height, frames, rounds, rows };
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    write_text(&out_dir.join("view.json"), &serde_json::to_string_pretty(&bench).expect("serializes"))?;
    write_text(&out_dir.join("view.md"), &markdown(&bench))?;
    Ok(bench)
}

fn markdown(b: &ViewBench) -> String {
    let mut s = format!(
        "`ocean view` of the default scene at {}x{} on {}, {} frames per run, {} rounds of the setups interleaved \
         (medians over the rounds). CPU frame: from the start of a frame to its present, waits included; waiting: for \
         the frame slot's fence and the next swapchain image; in present: inside vkQueuePresentKHR.\n\n\
         | present (given) | frames in flight | fps | frame interval ms | CPU frame ms | CPU waiting ms | waiting share | in present ms | GPU ms |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        b.width, b.height, b.device, b.frames, b.rounds
    );
    for r in &b.rows {
        s += &format!(
            "| {} ({}) | {} | {:.1} | {:.1} | {:.1} | {:.1} | {:.0}% | {:.1} | {:.1} |\n",
            r.present_asked,
            r.present_mode,
            r.frames_in_flight,
            r.fps,
            r.frame_interval_ms,
            r.cpu_frame_ms,
            r.cpu_wait_ms,
            100.0 * r.cpu_wait_fraction,
            r.cpu_present_ms,
            r.gpu_total_ms
        );
    }
    s
}
