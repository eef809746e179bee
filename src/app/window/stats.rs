//! What a window session measures without adding waits: frame intervals, CPU time split into
//! work and waiting (for a frame slot's fence, for the next swapchain image), and the GPU time
//! per pass of frames already finished. Medians go to the title and the `--report` JSON.

use crate::app::median;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Default)]
pub struct FrameStats {
    /// Wall time between consecutive presents (ms).
    intervals: Vec<f64>,
    /// CPU time per frame spent waiting on the slot's fence and on acquire (ms).
    waits: Vec<f64>,
    /// CPU time per frame inside vkQueuePresentKHR (ms).
    presents: Vec<f64>,
    /// CPU time per frame from its start to its present, waits included (ms).
    frame_cpu: Vec<f64>,
    gpu: BTreeMap<&'static str, Vec<f64>>,
    gpu_total: Vec<f64>,
    /// For the title: the last second's intervals.
    recent: Vec<f64>,
}

fn sorted_median(values: &[f64]) -> f64 {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        0.0
    } else {
        median(&v)
    }
}

impl FrameStats {
    pub fn frame(
        &mut self,
        interval_ms: Option<f64>,
        cpu_ms: f64,
        wait_ms: f64,
        present_ms: f64,
        gpu: &[(&'static str, f64)],
    ) {
        self.presents.push(present_ms);
        if let Some(i) = interval_ms {
            self.intervals.push(i);
            self.recent.push(i);
        }
        self.frame_cpu.push(cpu_ms);
        self.waits.push(wait_ms);
        for &(name, ms) in gpu {
            self.gpu.entry(name).or_default().push(ms);
        }
        if !gpu.is_empty() {
            self.gpu_total.push(gpu.iter().map(|(_, ms)| ms).sum());
        }
    }

    /// The title line: frames per second over the recent frames, CPU frame time, GPU per pass.
    pub fn title(&mut self, gpu: &[(&'static str, f64)], method: &str, paused: bool) -> String {
        let fps = if self.recent.is_empty() {
            0.0
        } else {
            1000.0 * self.recent.len() as f64 / self.recent.iter().sum::<f64>()
        };
        self.recent.clear();
        let cpu = self.frame_cpu.last().copied().unwrap_or(0.0);
        let passes: Vec<String> = gpu.iter().map(|(n, ms)| format!("{n} {ms:.1}")).collect();
        let total: f64 = gpu.iter().map(|(_, ms)| ms).sum();
        format!(
            "ocean - {method}{} - {fps:.1} fps - CPU {cpu:.1} ms - GPU {total:.1} ms ({})",
            if paused { " (paused)" } else { "" },
            passes.join(", ")
        )
    }

    pub fn summary(&self) -> Summary {
        let total_ms: f64 = self.intervals.iter().sum();
        Summary {
            fps: if total_ms > 0.0 { 1000.0 * self.intervals.len() as f64 / total_ms } else { 0.0 },
            frame_interval_ms: sorted_median(&self.intervals),
            cpu_frame_ms: sorted_median(&self.frame_cpu),
            cpu_wait_ms: sorted_median(&self.waits),
            cpu_present_ms: sorted_median(&self.presents),
            cpu_wait_fraction: {
                let cpu: f64 = self.frame_cpu.iter().sum();
                if cpu > 0.0 {
                    self.waits.iter().sum::<f64>() / cpu
                } else {
                    0.0
                }
            },
            gpu_ms: self.gpu.iter().map(|(&n, v)| (n.to_owned(), sorted_median(v))).collect(),
            gpu_total_ms: sorted_median(&self.gpu_total),
        }
    }
}

#[derive(Debug, Serialize)]
pub struct Summary {
    /// Presented frames per second of wall time (between the first and the last present).
    pub fps: f64,
    /// Median wall time between presents.
    pub frame_interval_ms: f64,
    /// Median CPU time of a frame, from its start to its present (waits included).
    pub cpu_frame_ms: f64,
    /// Median CPU time a frame spends waiting (the slot's fence, the next swapchain image).
    pub cpu_wait_ms: f64,
    /// Median CPU time inside the present call.
    pub cpu_present_ms: f64,
    /// Share of all frames' CPU time spent waiting (fence and acquire; not the present call).
    pub cpu_wait_fraction: f64,
    /// Median GPU time per pass (timestamps of finished frames; a pass that runs only when
    /// needed, such as the sky map's, over the frames that ran it).
    pub gpu_ms: BTreeMap<String, f64>,
    /// Median GPU time of a whole frame.
    pub gpu_total_ms: f64,
}
