//! Frame-time samples as `bench speed` and `profile` write them, so that `bench compare` reads
//! either: per scene and size, every timed frame's GPU time per pass, with the round each frame
//! belongs to (rounds interleave builds or settings in one run).

use crate::model::scene::Scene;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct TimedScene {
    /// The scene's name (file stem or path) and a fingerprint of its contents.
    pub scene: String,
    pub fingerprint: String,
    pub width: u32,
    pub height: u32,
    /// What was varied (render flags of a `--variant`, or "default").
    pub settings: String,
    /// GPU ms per pass (and "total") of every timed frame, in order.
    pub frames_ms: BTreeMap<String, Vec<f64>>,
    /// The round of each frame (all 0 without `--repeat`).
    pub round: Vec<u32>,
}

impl TimedScene {
    pub fn new(scene_name: &str, scene: &Scene, width: u32, height: u32, settings: &str) -> TimedScene {
        TimedScene {
            scene: scene_name.to_owned(),
            fingerprint: fingerprint(scene),
            width,
            height,
            settings: settings.to_owned(),
            frames_ms: BTreeMap::new(),
            round: Vec::new(),
        }
    }

    /// Adds one frame's passes (a pass a frame lacks counts 0 in it; "total" is their sum).
    pub fn push(&mut self, round: u32, passes: &[(String, f64)]) {
        let n = self.round.len();
        for (name, ms) in passes {
            self.frames_ms.entry(name.clone()).or_insert_with(|| vec![0.0; n]).push(*ms);
        }
        let total: f64 = passes.iter().map(|(_, ms)| ms).sum();
        self.frames_ms.entry("total".into()).or_insert_with(|| vec![0.0; n]).push(total);
        for samples in self.frames_ms.values_mut() {
            samples.resize(n + 1, 0.0);
        }
        self.round.push(round);
    }

    /// The key two files' rows are matched by.
    pub fn key(&self) -> (String, u32, u32) {
        (self.scene.clone(), self.width, self.height)
    }
}

/// What a timing file holds beside its own fields: the device, the run that made it (files of one
/// interleaved run share it) and the samples.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TimingFile {
    pub device: String,
    /// Shared by the files of one interleaved run (`bench speed --variant`).
    pub run_id: String,
    pub timings: Vec<TimedScene>,
}

/// FNV-1a over the scene's full description: equal for equal scenes, different when any key differs.
pub fn fingerprint(scene: &Scene) -> String {
    let text = format!("{scene:?}");
    let hash = text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3));
    format!("{hash:016x}")
}

/// A run id from the host clock and the process: distinct between runs.
pub fn new_run_id() -> String {
    format!("{:x}-{:x}", crate::vk::clock::host_now_ns(), std::process::id())
}
