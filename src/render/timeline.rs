//! A frame on the host clock (vk::clock): the CPU's steps as spans, and the GPU's passes from
//! their timestamps, mapped through a calibration or aligned at submit.

use crate::vk::clock::{host_now_ns, Calibration, DeviceClock};
use crate::vk::profiler::{PipelineStatistics, Scope};

/// A named interval on the host clock (ns).
#[derive(Clone, Debug)]
pub struct Span {
    pub name: String,
    pub begin_ns: f64,
    pub end_ns: f64,
}

/// A pass on the GPU, on the host clock.
#[derive(Clone, Debug)]
pub struct GpuSpan {
    pub name: &'static str,
    pub begin_ns: f64,
    pub end_ns: f64,
    pub statistics: Option<PipelineStatistics>,
}

impl GpuSpan {
    pub fn ms(&self) -> f64 {
        (self.end_ns - self.begin_ns) * 1e-6
    }
}

/// How a frame's GPU spans were put on the host clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Alignment {
    /// Through VK_EXT_calibrated_timestamps, within the driver's stated deviation.
    Calibrated { max_deviation_ns: u64 },
    /// The first timestamp placed at the host time of the submit (the device has no calibration).
    AtSubmit,
    /// The queue has no timestamps: no GPU spans.
    NoTimestamps,
}

impl Alignment {
    pub fn describe(&self) -> String {
        match self {
            Alignment::Calibrated { max_deviation_ns } => format!(
                "GPU spans on the CPU clock through VK_EXT_calibrated_timestamps (max deviation {max_deviation_ns} ns)"
            ),
            Alignment::AtSubmit => {
                "GPU spans aligned with their submit (no VK_EXT_calibrated_timestamps with the host clock): their offset from the CPU spans is not measured".to_owned()
            }
            Alignment::NoTimestamps => "the queue has no timestamps: CPU spans only".to_owned(),
        }
    }
}

/// What the host knew about a submission: when it went, and the clocks sampled then.
#[derive(Clone, Copy, Debug)]
pub struct Submission {
    pub submit_ns: u64,
    pub calibration: Option<Calibration>,
}

/// A finished frame's GPU side.
#[derive(Clone, Debug)]
pub struct GpuFrame {
    pub submission: Submission,
    /// When the host saw the frame's fence signalled.
    pub fence_ns: u64,
    pub passes: Vec<GpuSpan>,
    pub alignment: Alignment,
}

impl GpuFrame {
    /// The frame's scopes on the host clock.
    pub fn new(scopes: &[Scope], submission: Submission, fence_ns: u64, clock: &DeviceClock) -> GpuFrame {
        let first = scopes.iter().find_map(|s| s.device_ns.map(|(begin, _)| begin));
        // Without a calibration, the first timestamp and the submit stand for one.
        let (alignment, at) = match (first, submission.calibration) {
            (None, _) => {
                return GpuFrame { submission, fence_ns, passes: Vec::new(), alignment: Alignment::NoTimestamps }
            }
            (Some(_), Some(cal)) => (Alignment::Calibrated { max_deviation_ns: cal.max_deviation_ns }, cal),
            (Some(first), None) => (
                Alignment::AtSubmit,
                Calibration { device_ns: first, host_ns: submission.submit_ns, max_deviation_ns: 0 },
            ),
        };
        let passes = scopes
            .iter()
            .filter_map(|s| {
                s.device_ns.map(|(begin, end)| GpuSpan {
                    name: s.name,
                    begin_ns: clock.to_host(begin, &at),
                    end_ns: clock.to_host(end, &at),
                    statistics: s.statistics,
                })
            })
            .collect();
        GpuFrame { submission, fence_ns, passes, alignment }
    }
}

/// The CPU's spans of one frame, in the order they began.
#[derive(Default, Debug, Clone)]
pub struct CpuSpans {
    pub spans: Vec<Span>,
}

impl CpuSpans {
    /// Runs `f` inside a span called `name`.
    pub fn time<T>(&mut self, name: &str, f: impl FnOnce() -> T) -> T {
        let begin = host_now_ns();
        let value = f();
        self.spans.push(Span { name: name.to_owned(), begin_ns: begin as f64, end_ns: host_now_ns() as f64 });
        value
    }

    /// Closes a span that began at `begin_ns` (host_now_ns), now.
    pub fn push(&mut self, name: &str, begin_ns: u64) {
        self.spans.push(Span { name: name.to_owned(), begin_ns: begin_ns as f64, end_ns: host_now_ns() as f64 });
    }

    pub fn clear(&mut self) {
        self.spans.clear();
    }
}
