//! Progress of long commands on standard error: a bar redrawn in place on a terminal, plain
//! lines otherwise (a log, CI), each with the elapsed time and, where the work is measured in
//! units of known cost, an estimate of the time left.

use std::io::{IsTerminal, Write};
use std::time::{Duration, Instant};

/// Plain lines are printed at each tenth of the work, for every step that names itself, and
/// at least once a minute while the work goes on.
const LINE_FRACTION: f64 = 0.1;
const LINE_INTERVAL: Duration = Duration::from_secs(60);
/// The bar is redrawn at most this often (a terminal redraw costs more than a tile).
const BAR_INTERVAL: Duration = Duration::from_millis(100);
const BAR_WIDTH: usize = 30;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A bar redrawn with carriage returns.
    Bar,
    /// One line at a time.
    Lines,
}

pub struct Progress {
    label: String,
    unit: &'static str,
    total: u64,
    done: u64,
    style: Style,
    estimate: bool,
    started: Instant,
    last_draw: Option<Instant>,
    last_line_fraction: f64,
    sink: Box<dyn Write + Send>,
}

impl Progress {
    /// Progress over `total` units (`unit` names them: "scenes", "settings"; empty where the
    /// units are no more than weights, and only the percentage is shown) on standard error,
    /// as a bar on a terminal and as lines otherwise. `estimate` adds the time left, for work
    /// whose units cost about the same.
    pub fn new(label: &str, total: u64, unit: &'static str, estimate: bool) -> Progress {
        let style = if std::io::stderr().is_terminal() { Style::Bar } else { Style::Lines };
        Progress::to(Box::new(std::io::stderr()), style, label, total, unit, estimate)
    }

    /// The same, drawn on any writer (tests read it back).
    pub fn to(
        sink: Box<dyn Write + Send>,
        style: Style,
        label: &str,
        total: u64,
        unit: &'static str,
        estimate: bool,
    ) -> Progress {
        Progress {
            label: label.to_owned(),
            unit,
            total: total.max(1),
            done: 0,
            style,
            estimate,
            started: Instant::now(),
            last_draw: None,
            last_line_fraction: 0.0,
            sink,
        }
    }

    /// `done` of the total units are finished; `what` names the step just finished, if any.
    pub fn set(&mut self, done: u64, what: Option<&str>) {
        self.done = done.min(self.total);
        let fraction = self.done as f64 / self.total as f64;
        let finished = self.done == self.total;
        let now = Instant::now();
        let line = match self.style {
            Style::Bar => {
                let due = self.last_draw.is_none_or(|t| now - t >= BAR_INTERVAL);
                if !(due || finished) {
                    return;
                }
                let filled = (fraction * BAR_WIDTH as f64).round() as usize;
                let bar = format!("{}{}", "#".repeat(filled), " ".repeat(BAR_WIDTH - filled));
                let end = if finished { "\n" } else { "" };
                // \x1b[K clears what a longer previous line left behind.
                format!("\r{} [{bar}] {}\x1b[K{end}", self.label, self.status(what))
            }
            Style::Lines => {
                let tenth = (fraction / LINE_FRACTION).floor() * LINE_FRACTION;
                let quiet_too_long = now - self.last_draw.unwrap_or(self.started) >= LINE_INTERVAL;
                if !(what.is_some() || finished || tenth > self.last_line_fraction || quiet_too_long) {
                    return;
                }
                self.last_line_fraction = tenth;
                format!("{}: {}\n", self.label, self.status(what))
            }
        };
        self.last_draw = Some(now);
        // Progress is a courtesy: a closed standard error must not stop the work.
        let _ = self.sink.write_all(line.as_bytes()).and_then(|()| self.sink.flush());
    }

    /// Prints a result line (`say!`) without tearing the bar: the bar is cleared first and
    /// redrawn after it.
    pub fn println(&mut self, line: &str) {
        if self.style == Style::Bar && self.last_draw.is_some() {
            let _ = self.sink.write_all(b"\r\x1b[K").and_then(|()| self.sink.flush());
            self.last_draw = None;
        }
        crate::say!("{line}");
        if self.style == Style::Bar && self.done < self.total {
            self.set(self.done, None);
        }
    }

    /// "12/48 tiles (25%), 8.1 s, about 24 s left: what" (without a unit: "25%, 8.1 s, ...").
    fn status(&self, what: Option<&str>) -> String {
        let elapsed = self.started.elapsed().as_secs_f64();
        let percent = 100.0 * self.done as f64 / self.total as f64;
        let mut text = if self.unit.is_empty() {
            format!("{percent:.0}%, {}", seconds(elapsed))
        } else {
            format!("{}/{} {} ({percent:.0}%), {}", self.done, self.total, self.unit, seconds(elapsed))
        };
        if self.estimate && self.done < self.total {
            if let Some(left) = time_left(elapsed, self.done, self.total) {
                text.push_str(&format!(", about {} left", seconds(left)));
            }
        }
        if let Some(what) = what {
            text.push_str(": ");
            text.push_str(what);
        }
        text
    }
}

/// Seconds left at the rate so far: elapsed (total - done) / done; none before the first unit.
pub fn time_left(elapsed_s: f64, done: u64, total: u64) -> Option<f64> {
    (done > 0).then(|| elapsed_s * (total.saturating_sub(done)) as f64 / done as f64)
}

/// "0.4 s", "12 s", "3 min 05 s", "2 h 04 min".
pub fn seconds(s: f64) -> String {
    let s = s.max(0.0);
    if s < 10.0 {
        format!("{s:.1} s")
    } else if s < 60.0 {
        format!("{s:.0} s")
    } else if s < 3600.0 {
        let whole = s.round() as u64;
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        let minutes = (s / 60.0).round() as u64;
        format!("{} h {:02} min", minutes / 60, minutes % 60)
    }
}
