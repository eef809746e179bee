//! Chrome Trace Event JSON (the format Perfetto and chrome://tracing load): tracks as threads of
//! one process, spans as complete events ("X"), counters ("C"), and notes in `otherData`.
//! Times are given on the host clock in nanoseconds and written in microseconds from the
//! trace's origin.

use serde_json::{json, Map, Value};

/// A track: a thread of the trace's one process.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Track(pub u32);

pub struct Trace {
    origin_ns: f64,
    events: Vec<Value>,
    notes: Map<String, Value>,
}

const PID: u32 = 1;

impl Trace {
    /// A trace whose time 0 is `origin_ns` on the host clock.
    pub fn new(process: &str, origin_ns: f64) -> Trace {
        let mut trace = Trace { origin_ns, events: Vec::new(), notes: Map::new() };
        trace.events.push(json!({"name": "process_name", "ph": "M", "pid": PID, "args": {"name": process}}));
        trace
    }

    /// Names track `track`, shown in the order of `sort`.
    pub fn track(&mut self, track: Track, name: &str, sort: i32) {
        self.events.push(json!({"name": "thread_name", "ph": "M", "pid": PID, "tid": track.0, "args": {"name": name}}));
        self.events.push(
            json!({"name": "thread_sort_index", "ph": "M", "pid": PID, "tid": track.0, "args": {"sort_index": sort}}),
        );
    }

    fn micros(&self, ns: f64) -> f64 {
        // Nanosecond resolution, written as microseconds.
        (ns - self.origin_ns).round() / 1e3
    }

    /// A span on `track`; spans of one track must nest (a viewer stacks them by containment).
    pub fn span(
        &mut self,
        track: Track,
        name: &str,
        category: &str,
        begin_ns: f64,
        end_ns: f64,
        args: Map<String, Value>,
    ) {
        let ts = self.micros(begin_ns);
        let dur = (self.micros(end_ns.max(begin_ns)) - ts).max(0.0);
        self.events.push(json!({
            "name": name, "cat": category, "ph": "X", "pid": PID, "tid": track.0,
            "ts": ts, "dur": dur, "args": Value::Object(args),
        }));
    }

    /// A counter sample: each (series, value) at `at_ns`.
    pub fn counter(&mut self, name: &str, at_ns: f64, values: &[(&str, f64)]) {
        let args: Map<String, Value> = values.iter().map(|(k, v)| ((*k).to_owned(), json!(v))).collect();
        self.events.push(json!({"name": name, "ph": "C", "pid": PID, "ts": self.micros(at_ns), "args": args}));
    }

    /// A note for `otherData` (how the clocks were aligned, what was left out).
    pub fn note(&mut self, key: &str, value: Value) {
        self.notes.insert(key.to_owned(), value);
    }

    /// The trace as JSON text, events in time order (metadata first).
    pub fn to_json(&self) -> String {
        let mut events = self.events.clone();
        // Stable: equal times keep their order, so a parent written before its child stays outside it.
        events.sort_by(|a, b| {
            let key = |e: &Value| if e["ph"] == "M" { f64::NEG_INFINITY } else { e["ts"].as_f64().unwrap_or(0.0) };
            key(a).total_cmp(&key(b))
        });
        let doc =
            json!({"traceEvents": events, "displayTimeUnit": "ms", "otherData": Value::Object(self.notes.clone())});
        serde_json::to_string(&doc).expect("trace serializes")
    }
}
