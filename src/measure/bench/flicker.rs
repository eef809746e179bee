//! Temporal stability: how much each pixel's luminance changes from one frame to the next over a
//! short animation at a fixed frame rate, per distance band, for every method, against the same
//! measure on a heavily supersampled render of the full method. The waves' own motion changes a
//! pixel too; shimmer is what a method adds on top of that (aliased glints and normals flashing
//! on and off as crests pass under a pixel's few samples), so the ratio to the reference is what
//! ranks the methods, band by band. With `--truth-samples`, the reference is the ground truth's own
//! change over the same frames (of the whole view, or of a `--region` of it): as alive as the
//! truth, no more and no less.

use crate::error::{Error, Result};
use crate::measure::bench::error_vs_time::{band_label, csv_value, sea_pixels_by_band_in, BANDS_M};
use crate::measure::groundtruth::{self, Sampling};
use crate::measure::region::Region;
use crate::model::scene::Scene;
use crate::model::waves;
use crate::output::progress::Progress;
use crate::output::{luminance, write_text};
use crate::render::frame::CameraFrame;
use crate::render::passes::ocean::{Method, ShaderConfig};
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use std::fmt::Write as _;
use std::path::Path;

/// Supersampling of the reference render (per axis).
pub const REFERENCE_SSAA: u32 = 4;
/// Below this relative change (0.1% a frame) the reference is steady: a ratio to it says nothing.
const STEADY: f64 = 1e-3;

/// What is measured and at what size.
#[derive(Debug, Clone, Copy)]
pub struct FlickerRun {
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub fps: f64,
    /// The ground truth's samples per axis for its own frames (None: no truth, the supersampled
    /// method is the reference), and the part of the view measured (None: all of it).
    pub truth_samples: Option<u32>,
    pub region: Option<Region>,
}

/// One method's (or the reference's) flicker per distance band.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FlickerRow {
    pub method: String,
    pub ssaa: u32,
    /// Per band: (pixels, mean luminance, relative frame-to-frame change, its ratio to the
    /// reference's in that band, NaN where the reference is steady).
    pub bands: Vec<(usize, f64, f64, f64)>,
}

/// The RMS over frames of the change of each pixel's luminance from one frame to the next, and
/// the pixel's mean luminance.
fn temporal_change(frames: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let pixels = frames[0].len();
    let steps = (frames.len() - 1) as f64;
    let change = (0..pixels)
        .map(|p| (frames.windows(2).map(|w| (w[1][p] - w[0][p]).powi(2)).sum::<f64>() / steps).sqrt())
        .collect();
    let mean = (0..pixels).map(|p| frames.iter().map(|f| f[p]).sum::<f64>() / frames.len() as f64).collect();
    (change, mean)
}

pub fn run(gpu: &Gpu, scene: &Scene, scene_name: &str, run: FlickerRun, out_dir: &Path) -> Result<Vec<FlickerRow>> {
    let FlickerRun { width, height, frames, fps, .. } = run;
    if !(2..=1000).contains(&frames) {
        return Err(Error::Argument(format!("--frames {frames} is out of range [2, 1000]")));
    }
    if !(fps.is_finite() && (1.0..=1000.0).contains(&fps)) {
        return Err(Error::Argument(format!("--fps {fps} is out of range [1, 1000]")));
    }
    let region = run.region.unwrap_or(Region::whole(width, height));
    region.check(width, height)?;
    if let Some(samples) = run.truth_samples {
        if !(2..=groundtruth::MAX_SAMPLES).contains(&samples) {
            return Err(Error::Argument(format!(
                "--truth-samples {samples} is out of range [2, {}]: the truth's noise is removed with its two halves",
                groundtruth::MAX_SAMPLES
            )));
        }
    }
    let wave_set = waves::generate(scene);
    let camera = CameraFrame::new(scene, &wave_set, width, height);
    // The bands' pixels, as the region's indices.
    let bands = sea_pixels_by_band_in(&camera, width, height, region);
    let mut configs: Vec<(Method, u32)> = vec![(Method::Full, REFERENCE_SSAA)];
    configs.extend(Method::ALL.iter().map(|&m| (m, 1)));
    let mut progress = Progress::new("bench flicker", configs.len() as u64, "renders", true);
    let mut measured = Vec::new();
    let per_band = |change: &[f64], mean: &[f64]| -> Vec<(usize, f64, f64)> {
        bands
            .iter()
            .map(|b| {
                let n = b.len() as f64;
                let l = b.iter().map(|&p| mean[p]).sum::<f64>() / n;
                let c = b.iter().map(|&p| change[p]).sum::<f64>() / n;
                (b.len(), l, if l > 0.0 { c / l } else { f64::NAN })
            })
            .collect()
    };
    for (i, &(method, ssaa)) in configs.iter().enumerate() {
        progress.set(i as u64, Some(&format!("{} at {ssaa}x{ssaa} samples, {frames} frames", method.name())));
        let shader = ShaderConfig { method, ..ShaderConfig::default() };
        let mut renderer = Renderer::new(gpu, scene, width, height, Options { shader, ssaa, ..Options::default() })?;
        let mut images = Vec::with_capacity(frames as usize);
        for f in 0..frames {
            let mut at = scene.clone();
            at.render.time_s += f as f64 / fps;
            let frame = renderer.render(&at)?;
            images.push(region.crop(&frame.hdr, width).iter().map(|&p| luminance(p)).collect::<Vec<f64>>());
        }
        let (change, mean) = temporal_change(&images);
        measured.push((method.name().to_owned(), ssaa, per_band(&change, &mean)));
    }
    progress.set(configs.len() as u64, None);
    if let Some(samples) = run.truth_samples {
        let (change, mean) = truth_change(gpu, scene, run, region, samples)?;
        measured.insert(0, ("ground truth".to_owned(), samples, per_band(&change, &mean)));
    }
    let reference: Vec<f64> = measured[0].2.iter().map(|b| b.2).collect();
    let rows: Vec<FlickerRow> = measured
        .into_iter()
        .map(|(method, ssaa, per_band)| FlickerRow {
            method,
            ssaa,
            bands: per_band
                .iter()
                .zip(&reference)
                .map(|(&(n, l, c), &r)| (n, l, c, if r >= STEADY { c / r } else { f64::NAN }))
                .collect(),
        })
        .collect();
    write_outputs(&rows, out_dir, scene_name, run)?;
    Ok(rows)
}

/// The ground truth's own frame-to-frame change per pixel (RMS over the frames) and its mean
/// luminance, its sampling noise removed: each frame's estimate F is the mean of two independent
/// halves A and B = 2F - A, so for a frame step's differences d_A and d_B the mean of d_A d_B is
/// the square of the change alone (their noises are independent and average out of the product).
fn truth_change(
    gpu: &Gpu,
    scene: &Scene,
    run: FlickerRun,
    region: Region,
    samples: u32,
) -> Result<(Vec<f64>, Vec<f64>)> {
    let sampling = Sampling { region: Some(region), ..Sampling::new(samples) };
    let mut progress = Progress::new("bench flicker: ground truth frames", run.frames as u64, "frames", true);
    let (mut full, mut half) = (Vec::new(), Vec::new());
    for f in 0..run.frames {
        progress.set(f as u64, None);
        let mut at = scene.clone();
        at.render.time_s += f as f64 / run.fps;
        let truth = groundtruth::render(gpu, &at, run.width, run.height, &sampling, |_, _| {})?;
        let halves = truth.half.ok_or_else(|| Error::Argument("the ground truth kept no halves".into()))?;
        full.push(truth.radiance.iter().map(|&p| luminance(p)).collect::<Vec<f64>>());
        half.push(halves.iter().map(|h| h[0] as f64).collect::<Vec<f64>>());
    }
    progress.set(run.frames as u64, None);
    let steps = (run.frames - 1) as f64;
    let pixels = region.pixels();
    let change = (0..pixels)
        .map(|p| {
            let product: f64 = (1..run.frames as usize)
                .map(|t| {
                    let d_a = half[t][p] - half[t - 1][p];
                    let d_b = (2.0 * full[t][p] - half[t][p]) - (2.0 * full[t - 1][p] - half[t - 1][p]);
                    d_a * d_b
                })
                .sum();
            (product / steps).max(0.0).sqrt()
        })
        .collect();
    let mean = (0..pixels).map(|p| full.iter().map(|f| f[p]).sum::<f64>() / full.len() as f64).collect();
    Ok((change, mean))
}

fn write_outputs(rows: &[FlickerRow], dir: &Path, scene_name: &str, run: FlickerRun) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut csv =
        String::from("method,ssaa,band,distance_min_m,distance_max_m,pixels,mean_luminance,flicker,flicker_ratio\n");
    for r in rows {
        for (b, &(n, l, c, ratio)) in r.bands.iter().enumerate() {
            let (lo, hi) = (BANDS_M[b], BANDS_M[b + 1]);
            writeln!(
                csv,
                "{},{},{b},{lo},{hi},{n},{},{},{}",
                r.method,
                r.ssaa,
                csv_value(l),
                csv_value(c),
                csv_value(ratio)
            )
            .unwrap();
        }
    }
    write_text(&dir.join("flicker.csv"), &csv)?;
    let shown: Vec<usize> = (0..BANDS_M.len() - 1).filter(|&b| rows[0].bands[b].0 > 0).collect();
    let reference = match run.truth_samples {
        Some(n) => format!(
            "the ground truth at {n}x{n} samples per pixel, its sampling noise removed with its two half-estimates \
             (the mean product of their frame differences)"
        ),
        None => format!(
            "the full method at {REFERENCE_SSAA}x{REFERENCE_SSAA} samples per pixel, whose change is the waves' own motion"
        ),
    };
    let part = run.region.map_or(String::new(), |r| format!(", {r}"));
    let mut md = format!(
        "Flicker: scene `{scene_name}` at {}x{}{part}, {} frames at {} frames per second. Per distance band (m), the RMS \
         change of a pixel's luminance from one frame to the next over its mean (percent), and in brackets its ratio \
         to the reference's: {reference} (no ratio where the reference changes by under 0.1% a frame). Above 1, the \
         method shimmers; below 1, it is stiller than the reference.\n\n| method | samples |",
        run.width, run.height, run.frames, run.fps
    );
    for &b in &shown {
        write!(md, " {} |", band_label(b)).unwrap();
    }
    md.push_str("\n|---|---|");
    md.push_str(&"---|".repeat(shown.len()));
    md.push('\n');
    for r in rows {
        write!(md, "| {} | {}x{} |", r.method, r.ssaa, r.ssaa).unwrap();
        for &b in &shown {
            let (_, _, c, ratio) = r.bands[b];
            if ratio.is_finite() {
                write!(md, " {:.2}% ({:.2}) |", 100.0 * c, ratio).unwrap();
            } else {
                write!(md, " {:.2}% |", 100.0 * c).unwrap();
            }
        }
        md.push('\n');
    }
    write_text(&dir.join("flicker.md"), &md)
}

#[cfg(test)]
mod tests {
    use super::temporal_change;

    #[test]
    fn a_steady_pixel_has_no_change_and_a_blinking_one_its_amplitude() {
        let frames = vec![vec![1.0, 0.0], vec![1.0, 2.0], vec![1.0, 0.0]];
        let (change, mean) = temporal_change(&frames);
        assert_eq!(change, vec![0.0, 2.0]);
        assert_eq!(mean, vec![1.0, 2.0 / 3.0]);
    }
}
