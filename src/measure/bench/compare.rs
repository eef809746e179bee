//! `bench compare A.json B.json`: per scene and pass, B's GPU time over A's with a 95% interval
//! and a verdict. Files of one interleaved run (`bench speed --variant`, same run id) are compared
//! round by round: the ratio of the rounds' medians, its interval from Student's t on the log
//! ratios, so that the machine's drift between minutes falls on both sides alike. Files of
//! separate runs are compared by bootstrapping the medians (rounds resampled, then frames within
//! them), which cannot see drift between the runs: the output says so.

use crate::app::median;
use crate::error::{Error, Result};
use crate::measure::samples::{TimedScene, TimingFile};
use serde::Serialize;

/// Resamples of the bootstrap.
const RESAMPLES: usize = 2000;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    Faster,
    Slower,
    WithinNoise,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Faster => "faster",
            Verdict::Slower => "slower",
            Verdict::WithinNoise => "within noise",
        })
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// Interleaved rounds of one run: paired ratios of round medians.
    PairedRounds,
    /// Separate runs: bootstrap of the medians.
    Bootstrap,
}

#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub pass: String,
    pub a_median_ms: f64,
    pub b_median_ms: f64,
    /// B over A, and its 95% interval.
    pub ratio: f64,
    pub low: f64,
    pub high: f64,
    pub verdict: Verdict,
}

#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub method: Method,
    /// The smallest change called faster or slower (a fraction), besides the interval excluding 1.
    pub threshold: f64,
    pub rows: Vec<Row>,
    /// Passes that only one side ran, per scene.
    pub unmatched: Vec<String>,
}

/// Compares two timing files; refuses files of different devices, scenes or sizes, naming the
/// difference.
pub fn compare(a: &TimingFile, b: &TimingFile, threshold: f64) -> Result<Comparison> {
    if a.device != b.device {
        return Err(Error::Argument(format!(
            "the files were measured on different devices: {:?} and {:?}",
            a.device, b.device
        )));
    }
    let keys = |f: &TimingFile| f.timings.iter().map(|t| t.key()).collect::<std::collections::BTreeSet<_>>();
    let (ka, kb) = (keys(a), keys(b));
    if ka != kb {
        let name = |k: &(String, u32, u32)| format!("{} at {}x{}", k.0, k.1, k.2);
        let only_a: Vec<_> = ka.difference(&kb).map(name).collect();
        let only_b: Vec<_> = kb.difference(&ka).map(name).collect();
        return Err(Error::Argument(format!(
            "the files time different scenes or sizes: only in A: [{}]; only in B: [{}]",
            only_a.join(", "),
            only_b.join(", ")
        )));
    }
    let paired = a.run_id == b.run_id && a.timings.iter().all(|t| rounds(t).len() >= 2);
    let method = if paired { Method::PairedRounds } else { Method::Bootstrap };
    let mut rows = Vec::new();
    let mut unmatched = Vec::new();
    for ta in &a.timings {
        let tb = b.timings.iter().find(|t| t.key() == ta.key()).expect("same keys");
        if ta.fingerprint != tb.fingerprint {
            return Err(Error::Argument(format!(
                "scene {} differs between the files (fingerprint {} in A, {} in B)",
                ta.scene, ta.fingerprint, tb.fingerprint
            )));
        }
        for (pass, samples_a) in &ta.frames_ms {
            let Some(samples_b) = tb.frames_ms.get(pass) else {
                unmatched.push(format!("{}: {pass} only in A", ta.scene));
                continue;
            };
            let (ratio, low, high) = if paired {
                paired_ratio(ta, samples_a, tb, samples_b)
            } else {
                bootstrap_ratio(ta, samples_a, tb, samples_b)
            };
            let verdict = if low > 1.0 && ratio > 1.0 + threshold {
                Verdict::Slower
            } else if high < 1.0 && ratio < 1.0 - threshold {
                Verdict::Faster
            } else {
                Verdict::WithinNoise
            };
            rows.push(Row {
                scene: ta.scene.clone(),
                width: ta.width,
                height: ta.height,
                pass: pass.clone(),
                a_median_ms: sorted_median(samples_a.clone()),
                b_median_ms: sorted_median(samples_b.clone()),
                ratio,
                low,
                high,
                verdict,
            });
        }
        for pass in tb.frames_ms.keys().filter(|p| !ta.frames_ms.contains_key(*p)) {
            unmatched.push(format!("{}: {pass} only in B", ta.scene));
        }
    }
    Ok(Comparison { method, threshold, rows, unmatched })
}

fn sorted_median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        median(&v)
    }
}

/// The rounds of a scene's frames, in order, each with its frames' indices.
fn rounds(t: &TimedScene) -> Vec<(u32, Vec<usize>)> {
    let mut out: Vec<(u32, Vec<usize>)> = Vec::new();
    for (i, &r) in t.round.iter().enumerate() {
        match out.iter_mut().find(|(round, _)| *round == r) {
            Some((_, frames)) => frames.push(i),
            None => out.push((r, vec![i])),
        }
    }
    out
}

/// Ratio of round medians per common round; the mean log ratio with Student's t interval.
fn paired_ratio(ta: &TimedScene, sa: &[f64], tb: &TimedScene, sb: &[f64]) -> (f64, f64, f64) {
    let (ra, rb) = (rounds(ta), rounds(tb));
    let logs: Vec<f64> = ra
        .iter()
        .filter_map(|(round, frames_a)| {
            let (_, frames_b) = rb.iter().find(|(r, _)| r == round)?;
            let ma = sorted_median(frames_a.iter().map(|&i| sa[i]).collect());
            let mb = sorted_median(frames_b.iter().map(|&i| sb[i]).collect());
            (ma > 0.0 && mb > 0.0).then(|| (mb / ma).ln())
        })
        .collect();
    let n = logs.len();
    if n < 2 {
        return (f64::NAN, 0.0, f64::INFINITY);
    }
    let mean = logs.iter().sum::<f64>() / n as f64;
    let var = logs.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
    let half = student_t_975(n - 1) * (var / n as f64).sqrt();
    (mean.exp(), (mean - half).exp(), (mean + half).exp())
}

/// The 97.5% quantile of Student's t with `df` degrees of freedom (tabulated to 30, then the
/// normal's 1.96 with the first-order correction).
fn student_t_975(df: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
        2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042,
    ];
    match df {
        0 => f64::INFINITY,
        1..=30 => T[df - 1],
        _ => 1.96 + 2.4 / df as f64,
    }
}

/// Median of B over median of A, with the 2.5% and 97.5% percentiles of the same over resamples
/// (rounds drawn with replacement, then frames within each drawn round).
fn bootstrap_ratio(ta: &TimedScene, sa: &[f64], tb: &TimedScene, sb: &[f64]) -> (f64, f64, f64) {
    let point = sorted_median(sb.to_vec()) / sorted_median(sa.to_vec());
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let (ra, rb) = (rounds(ta), rounds(tb));
    let mut ratios: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            let ma = sorted_median(resample(&ra, sa, &mut rng));
            let mb = sorted_median(resample(&rb, sb, &mut rng));
            mb / ma
        })
        .filter(|r| r.is_finite())
        .collect();
    if ratios.is_empty() {
        return (point, 0.0, f64::INFINITY);
    }
    ratios.sort_by(f64::total_cmp);
    let at = |q: f64| ratios[((q * (ratios.len() - 1) as f64).round() as usize).min(ratios.len() - 1)];
    (point, at(0.025), at(0.975))
}

fn resample(rounds: &[(u32, Vec<usize>)], samples: &[f64], rng: &mut XorShift) -> Vec<f64> {
    let mut out = Vec::with_capacity(samples.len());
    for _ in 0..rounds.len() {
        let (_, frames) = &rounds[rng.below(rounds.len())];
        for _ in 0..frames.len() {
            out.push(samples[frames[rng.below(frames.len())]]);
        }
    }
    out
}

/// xorshift64*: a fixed seed makes every comparison reproducible.
struct XorShift(u64);

impl XorShift {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % n
    }
}

/// The comparison as a markdown table, with how it was made.
pub fn markdown(c: &Comparison, a_name: &str, b_name: &str) -> String {
    let how = match c.method {
        Method::PairedRounds => "paired rounds of one interleaved run: the ratio of each round's medians, 95% interval from Student's t on their logarithms",
        Method::Bootstrap => "separate runs: bootstrap of the medians (rounds, then frames within them, resampled 2000 times; 95% percentile interval). Drift of the machine between the two runs is not in the interval: interleave with `bench speed --variant` to control it",
    };
    let mut s = format!(
        "B = {b_name} against A = {a_name}: {how}. Verdict faster or slower when the interval excludes 1 and the ratio differs from 1 by more than {:.0}%.\n\n| scene | size | pass | A ms | B ms | B / A | 95% interval | verdict |\n|---|---|---|---|---|---|---|---|\n",
        100.0 * c.threshold
    );
    for r in &c.rows {
        s += &format!(
            "| {} | {}x{} | {} | {:.2} | {:.2} | {:.3} | {:.3}–{:.3} | {} |\n",
            r.scene, r.width, r.height, r.pass, r.a_median_ms, r.b_median_ms, r.ratio, r.low, r.high, r.verdict
        );
    }
    for u in &c.unmatched {
        s += &format!("\n- {u}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn scene(rounds: &[Vec<f64>]) -> TimedScene {
        let mut frames = Vec::new();
        let mut round = Vec::new();
        for (r, values) in rounds.iter().enumerate() {
            frames.extend_from_slice(values);
            round.extend(std::iter::repeat_n(r as u32, values.len()));
        }
        TimedScene {
            scene: "default".into(),
            fingerprint: "f".into(),
            width: 64,
            height: 48,
            settings: "default".into(),
            frames_ms: BTreeMap::from([("shade".to_owned(), frames)]),
            round,
        }
    }

    fn file(run: &str, t: TimedScene) -> TimingFile {
        TimingFile { device: "d".into(), run_id: run.into(), timings: vec![t] }
    }

    /// Rounds that drift by +-20% between them, with 1% jitter within.
    fn drifting(scale: f64) -> Vec<Vec<f64>> {
        [1.0, 1.2, 0.85, 1.1, 0.95]
            .iter()
            .enumerate()
            .map(|(r, d)| (0..8).map(|i| scale * d * (1.0 + 0.01 * ((i * 7 + r * 3) % 5) as f64 / 4.0)).collect())
            .collect()
    }

    #[test]
    fn interleaved_equal_runs_are_within_noise_and_a_slower_one_is_slower() {
        let a = file("run", scene(&drifting(10.0)));
        let same = compare(&a, &file("run", scene(&drifting(10.0))), 0.01).unwrap();
        assert_eq!(same.method, Method::PairedRounds);
        assert_eq!(same.rows[0].verdict, Verdict::WithinNoise, "{:?}", same.rows[0]);
        let slower = compare(&a, &file("run", scene(&drifting(10.6))), 0.01).unwrap();
        assert_eq!(slower.rows[0].verdict, Verdict::Slower, "{:?}", slower.rows[0]);
        assert!((slower.rows[0].ratio - 1.06).abs() < 0.01);
        let faster = compare(&a, &file("run", scene(&drifting(9.0))), 0.01).unwrap();
        assert_eq!(faster.rows[0].verdict, Verdict::Faster);
    }

    #[test]
    fn separate_runs_are_bootstrapped_and_drift_within_them_widens_the_interval() {
        let a = file("one", scene(&drifting(10.0)));
        let b = file("two", scene(&drifting(10.3)));
        let c = compare(&a, &b, 0.01).unwrap();
        assert_eq!(c.method, Method::Bootstrap);
        // 3% is well inside the +-20% drift between rounds.
        assert_eq!(c.rows[0].verdict, Verdict::WithinNoise, "{:?}", c.rows[0]);
        assert!(c.rows[0].low < 1.0 && c.rows[0].high > 1.0);
    }

    #[test]
    fn files_of_different_scenes_sizes_or_devices_are_refused_by_name() {
        let a = file("run", scene(&drifting(10.0)));
        let mut b = file("run", scene(&drifting(10.0)));
        b.timings[0].width = 128;
        let e = compare(&a, &b, 0.01).unwrap_err().to_string();
        assert!(e.contains("only in A: [default at 64x48]") && e.contains("only in B: [default at 128x48]"), "{e}");
        let mut b = file("run", scene(&drifting(10.0)));
        b.timings[0].fingerprint = "g".into();
        assert!(compare(&a, &b, 0.01).unwrap_err().to_string().contains("scene default differs"));
        let mut b = file("run", scene(&drifting(10.0)));
        b.device = "other".into();
        assert!(compare(&a, &b, 0.01).unwrap_err().to_string().contains("different devices"));
    }
}
