//! The local waves' own change to the picture (`bench error-vs-time --bare-reference`): the
//! scene's image less its bare sea's (the same scene without its `[[wake]]`s and `[[splash]]`es),
//! the full method's against the ground truth's, per distance band. A band's energy error says how
//! far the sea is off with a wake in it, the trains' error included; this says whether the wake
//! itself is drawn: how much it brightens or darkens the sea (its mean change), and whether its
//! pattern is the truth's (the two changes blurred over CHANGE_BLUR_PX pixels, where the truth's
//! sampling noise would otherwise drown a faint wake: their rms and correlation, the truth's noise,
//! drawn from its half estimates, taken out of both). The reflected sky and the refracted light only: at a truth's sampling its
//! glints are noise, which a wake moves about.

use crate::error::{Error, Result};
use crate::measure::bench::reflections::half_difference_noise;
use crate::measure::groundtruth::{GroundTruthFiles, GroundTruthMeta};
use crate::model::scene::Scene;
use crate::output::{luminance, write_text};
use crate::render::passes::ocean::{Method, ShaderConfig, Terms};
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use std::fmt::Write as _;
use std::path::Path;

/// The blur's standard deviation (pixels): the truth's noise, independent from pixel to pixel,
/// falls by 2 sqrt(pi) 1.5 = 5.3 in standard deviation, and a wake's waves a few pixels long keep
/// most of their pattern.
pub const CHANGE_BLUR_PX: f64 = 1.5;

/// The wake's pixels are where the method's image changes by more than this share of its bare
/// sea's, widened by the blur: where the local waves reach, since the method draws a packet
/// wherever its envelope does, less the envelopes' far tails (a tenth of the 1% an eye can tell
/// apart). The truth's change cannot tell them: its noise is as large as a faint wake.
pub const WAKE_CHANGE: f64 = 1e-3;

/// `scene` without its local waves, for the bare sea's image: its `[[wake]]`s and `[[splash]]`es
/// gone. An object that moves sheds a wake no copy of the scene can leave out without stopping it,
/// and a floating one rocked by the packets radiates rings: both refused, naming the object.
pub fn bare_scene(scene: &Scene, scene_name: &str) -> Result<Scene> {
    if let Some((i, _)) = scene.objects.iter().enumerate().find(|(_, o)| o.velocity_mps != [0.0, 0.0]) {
        return Err(Error::Argument(format!(
            "--bare-reference: {scene_name}'s object {} moves (velocity_mps), and its wake cannot be left out of a bare sea: \
             measure a [[wake]] instead",
            i + 1
        )));
    }
    if scene.wakes.is_empty() && scene.splashes.is_empty() {
        return Err(Error::Argument(format!(
            "--bare-reference: {scene_name} has no [[wake]] or [[splash]], so no local waves to measure"
        )));
    }
    Ok(Scene { wakes: Vec::new(), splashes: Vec::new(), ..scene.clone() })
}

/// The ground truth of the bare sea, checked against the scene's before anything is rendered.
pub struct BareTruth {
    pub scene: Scene,
    pub files: GroundTruthFiles,
    pub path: String,
}

impl BareTruth {
    /// Loads `path`, which must be `scene`'s bare sea (`bare_scene`) at the size, region and
    /// sampling of the scene's own truth, `of`, both with their half estimates.
    pub fn load(path: &Path, scene: &Scene, scene_name: &str, of: &GroundTruthFiles) -> Result<BareTruth> {
        let bare = bare_scene(scene, scene_name)?;
        let files = GroundTruthFiles::load(path)?;
        let at = |m: &GroundTruthMeta| (m.width, m.height, m.region(), m.samples_per_axis);
        if files.half.is_none() || of.half.is_none() {
            return Err(Error::Argument(format!(
                "--bare-reference: {} has no half estimate (NAME.half.exr: traced with fewer than 2x2 samples, or before \
                 halves were kept), which the truth's noise is drawn from: trace it again",
                if of.half.is_none() { "--reference" } else { "--bare-reference" }
            )));
        }
        let of = &of.meta;
        if at(&files.meta) != at(of) {
            return Err(Error::Argument(format!(
                "--bare-reference {}: {}x{} ({:?}, {n}x{n} samples), where --reference is {}x{} ({:?}, {m}x{m}): trace both \
                 at one size, region and sampling",
                path.display(),
                files.meta.width,
                files.meta.height,
                files.meta.region(),
                of.width,
                of.height,
                of.region(),
                n = files.meta.samples_per_axis,
                m = of.samples_per_axis
            )));
        }
        if !files.meta.is_of(&bare) {
            return Err(Error::Argument(format!(
                "--bare-reference {} was not made for {scene_name} without its [[wake]]s and [[splash]]es: trace a copy of                  the scene without them",
                path.display()
            )));
        }
        Ok(BareTruth { scene: bare, files, path: path.display().to_string() })
    }
}

/// The local waves' change by band and over the whole sea (last), written to `local_waves.md`
/// and `local_waves.csv` in `out_dir` and said a line a band. `scene_images`: the full method's default setting's
/// reflected sky and refracted light of the scene itself, cropped to the truth's region; `truth`:
/// the scene's truth; `bands`: the region's sea pixels by band, their `labels`.
pub struct Request<'a> {
    pub gpu: &'a Gpu,
    pub scene_name: &'a str,
    pub bare: &'a BareTruth,
    pub truth: &'a GroundTruthFiles,
    pub scene_images: [&'a [[f32; 4]]; 2],
    pub bands: &'a [Vec<usize>],
    pub labels: &'a [String],
    pub out_dir: &'a Path,
}

pub fn measure(r: Request) -> Result<Vec<WaveChange>> {
    let meta = &r.truth.meta;
    let region = meta.region();
    let (view_w, view_h) = (meta.width, meta.height);
    let bare_term = |sky: bool, sea: bool| -> Result<Vec<[f32; 4]>> {
        let terms = ShaderConfig::terms_only(Terms { sun: false, sky, sea }, Method::Full);
        let mut renderer =
            Renderer::new(r.gpu, &r.bare.scene, view_w, view_h, Options { shader: terms, ..Options::default() })?;
        Ok(region.crop(&renderer.render(&r.bare.scene)?.hdr, view_w))
    };
    let method_bare = sky_and_sea(&bare_term(true, false)?, &bare_term(false, true)?);
    let method_scene = sky_and_sea(r.scene_images[0], r.scene_images[1]);
    let bare = &r.bare.files;
    let truth_scene = sky_and_sea(&r.truth.sky, &r.truth.sea);
    let truth_bare = sky_and_sea(&bare.sky, &bare.sea);
    let half = |f: &GroundTruthFiles| -> Vec<f64> {
        // BareTruth::load made sure both have one.
        f.half.as_ref().map_or_else(Vec::new, |h| h.iter().map(|v| v[2] as f64 + v[3] as f64).collect())
    };
    let (w, h) = (region.width as usize, region.height as usize);
    let changes = Changes::new(
        [&method_scene, &method_bare],
        [&truth_scene, &truth_bare],
        [&half(r.truth), &half(bare)],
        meta.samples_per_axis,
        w,
        h,
    );
    let sea: Vec<usize> = r.bands.iter().flatten().copied().collect();
    let mut out: Vec<WaveChange> = r.bands.iter().map(|b| wave_change(&changes, b)).collect();
    out.push(wave_change(&changes, &sea));
    let mut labels = r.labels.to_vec();
    labels.push("whole sea".into());
    std::fs::create_dir_all(r.out_dir).map_err(|e| Error::io(r.out_dir, e))?;
    write_text(&r.out_dir.join("local_waves.md"), &markdown(r.scene_name, &r.bare.path, &labels, &out))?;
    let mut csv = String::from(
        "band,pixels,truth_mean,truth_uncertainty,method_mean,wake_pixels,truth_rms,truth_noise_rms,method_rms,correlation,\
         correlation_without_noise\n",
    );
    for (label, c) in labels.iter().zip(&out) {
        csv.push_str(&format!(
            "{label},{},{},{},{},{},{},{},{},{},{}\n",
            c.pixels,
            c.truth_mean,
            c.truth_uncertainty,
            c.method_mean,
            c.wake_pixels,
            c.truth_rms,
            c.truth_noise_rms,
            c.method_rms,
            c.correlation,
            c.correlation_without_noise
        ));
    }
    write_text(&r.out_dir.join("local_waves.csv"), &csv)?;
    for (label, c) in labels.iter().zip(&out).filter(|(_, c)| c.pixels > 0) {
        crate::say!(
            "local waves {label:>10} m: mean change truth {:+.4} ± {:.4}, ours {:+.4}; over {} wake pixels rms truth {:.4} \
             (noise {:.4}), ours {:.4}, correlation {:.2} ({:.2} without the truth's noise)",
            c.truth_mean,
            c.truth_uncertainty,
            c.method_mean,
            c.wake_pixels,
            c.truth_rms,
            c.truth_noise_rms,
            c.method_rms,
            c.correlation,
            c.correlation_without_noise
        );
    }
    Ok(out)
}

/// The reflected sky plus the refracted light, Rec. 709 luminance (kcd/m²) per pixel.
pub fn sky_and_sea(sky: &[[f32; 4]], sea: &[[f32; 4]]) -> Vec<f64> {
    sky.iter().zip(sea).map(|(a, b)| luminance(*a) + luminance(*b)).collect()
}

/// A Gaussian blur of standard deviation `sigma` pixels, separable, its taps to 3 sigma, the
/// image's edge repeated beyond it.
pub fn blur(image: &[f64], w: usize, h: usize, sigma: f64) -> Vec<f64> {
    let reach = (3.0 * sigma).ceil() as isize;
    let taps: Vec<f64> = (-reach..=reach).map(|i| (-0.5 * (i as f64 / sigma).powi(2)).exp()).collect();
    let total: f64 = taps.iter().sum();
    let taps: Vec<f64> = taps.iter().map(|t| t / total).collect();
    let pass = |source: &[f64], along_x: bool| -> Vec<f64> {
        let mut out = vec![0.0; source.len()];
        for y in 0..h {
            for x in 0..w {
                out[y * w + x] = taps
                    .iter()
                    .enumerate()
                    .map(|(j, t)| {
                        let d = j as isize - reach;
                        let (sx, sy) = if along_x {
                            ((x as isize + d).clamp(0, w as isize - 1) as usize, y)
                        } else {
                            (x, (y as isize + d).clamp(0, h as isize - 1) as usize)
                        };
                        t * source[sy * w + sx]
                    })
                    .sum();
            }
        }
        out
    };
    pass(&pass(image, true), false)
}

/// The changes the local waves make, the method's and the truth's, over one image's pixels.
pub struct Changes {
    pub method: Vec<f64>,
    pub truth: Vec<f64>,
    /// The truth's change's noise at each pixel, one draw of it: from the two truths' full and
    /// half estimates (`reflections::half_difference_noise`, before its square), so that what
    /// their samples share (the same places where the waves leave the surface alone) cancels.
    pub truth_noise: Vec<f64>,
    pub method_blurred: Vec<f64>,
    pub truth_blurred: Vec<f64>,
    /// The same draw of the truth's noise, blurred as its change is.
    pub truth_noise_blurred: Vec<f64>,
    /// Whether a pixel is the wake's (WAKE_CHANGE).
    pub wake: Vec<bool>,
}

impl Changes {
    /// From the method's and the truth's images with and without the local waves (sky and sea
    /// luminance, `sky_and_sea`) and the truth's half estimates of the same, traced with
    /// `samples_per_axis`^2 samples a pixel.
    pub fn new(
        method: [&[f64]; 2],
        truth: [&[f64]; 2],
        truth_half: [&[f64]; 2],
        samples_per_axis: u32,
        w: usize,
        h: usize,
    ) -> Changes {
        let bare_method = method[1];
        let difference = |[a, b]: [&[f64]; 2]| a.iter().zip(b).map(|(a, b)| a - b).collect::<Vec<f64>>();
        let noise_squared = half_difference_noise(truth, truth_half, samples_per_axis);
        // Its sign is the draw's: the full estimate less the half's, of the change.
        let truth_noise: Vec<f64> = (0..noise_squared.len())
            .map(|i| {
                noise_squared[i].sqrt().copysign((truth[0][i] - truth_half[0][i]) - (truth[1][i] - truth_half[1][i]))
            })
            .collect();
        let (method, truth) = (difference(method), difference(truth));
        let method_blurred = blur(&method, w, h, CHANGE_BLUR_PX);
        let truth_blurred = blur(&truth, w, h, CHANGE_BLUR_PX);
        let truth_noise_blurred = blur(&truth_noise, w, h, CHANGE_BLUR_PX);
        let changed: Vec<f64> = method
            .iter()
            .zip(bare_method)
            .map(|(c, b)| if c.abs() > WAKE_CHANGE * b.abs() { 1.0 } else { 0.0 })
            .collect();
        // Widened by the blur: a pixel whose blurred change holds mostly the wake's.
        let wake = blur(&changed, w, h, CHANGE_BLUR_PX).iter().map(|&v| v > 0.5).collect();
        Changes { method, truth, truth_noise, method_blurred, truth_blurred, truth_noise_blurred, wake }
    }
}

/// The local waves' change over a set of pixels (a distance band's sea).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct WaveChange {
    pub pixels: usize,
    /// Mean change (kcd/m²) over the pixels: the truth's, its standard error (from its noise's
    /// draws, one a pixel), the method's.
    pub truth_mean: f64,
    pub truth_uncertainty: f64,
    pub method_mean: f64,
    /// The pixels the local waves reach (WAKE_CHANGE).
    pub wake_pixels: usize,
    /// Over those, the rms of the blurred changes, the truth's as it is and of its noise alone.
    pub truth_rms: f64,
    pub truth_noise_rms: f64,
    pub method_rms: f64,
    /// Their correlation as they are, and with the truth's noise taken out of its variance (its
    /// covariance with the method's holds none): 1 draws the truth's pattern, whatever its scale.
    /// The half estimates count what a pixel's strata see apart as noise too, so that where its
    /// pixels hold a wake's waves this errs high, even past 1.
    pub correlation: f64,
    pub correlation_without_noise: f64,
}

impl WaveChange {
    /// The truth's rms with its noise taken out (0 where the noise is all of it).
    pub fn truth_signal_rms(&self) -> f64 {
        (self.truth_rms * self.truth_rms - self.truth_noise_rms * self.truth_noise_rms).max(0.0).sqrt()
    }

    /// Nothing measured over the wake's pixels (fewer than two of them).
    fn no_wake() -> WaveChange {
        WaveChange {
            truth_rms: f64::NAN,
            truth_noise_rms: f64::NAN,
            method_rms: f64::NAN,
            correlation: f64::NAN,
            correlation_without_noise: f64::NAN,
            ..Default::default()
        }
    }
}

/// The local waves' change over the pixels `select`ed (a band's sea, or the whole of it).
pub fn wave_change(c: &Changes, select: &[usize]) -> WaveChange {
    let n = select.len();
    if n == 0 {
        return WaveChange { truth_mean: f64::NAN, method_mean: f64::NAN, ..WaveChange::no_wake() };
    }
    let mean = |v: &[f64], at: &[usize]| at.iter().map(|&i| v[i]).sum::<f64>() / at.len() as f64;
    let truth_uncertainty = select.iter().map(|&i| c.truth_noise[i] * c.truth_noise[i]).sum::<f64>().sqrt() / n as f64;
    let wake: Vec<usize> = select.iter().copied().filter(|&i| c.wake[i]).collect();
    let mut out = WaveChange {
        pixels: n,
        truth_mean: mean(&c.truth, select),
        truth_uncertainty,
        method_mean: mean(&c.method, select),
        wake_pixels: wake.len(),
        ..WaveChange::no_wake()
    };
    if wake.len() >= 2 {
        let (tm, mm) = (mean(&c.truth_blurred, &wake), mean(&c.method_blurred, &wake));
        let (mut tt, mut mmv, mut tmv, mut noise, mut t2, mut m2) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        for &i in &wake {
            let (t, m) = (c.truth_blurred[i], c.method_blurred[i]);
            tt += (t - tm) * (t - tm);
            mmv += (m - mm) * (m - mm);
            tmv += (t - tm) * (m - mm);
            noise += c.truth_noise_blurred[i] * c.truth_noise_blurred[i];
            t2 += t * t;
            m2 += m * m;
        }
        let k = wake.len() as f64;
        out.truth_rms = (t2 / k).sqrt();
        out.truth_noise_rms = (noise / k).sqrt();
        out.method_rms = (m2 / k).sqrt();
        let correlate = |truth_variance: f64| {
            if truth_variance > 0.0 && mmv > 0.0 {
                tmv / (truth_variance * mmv).sqrt()
            } else {
                f64::NAN
            }
        };
        out.correlation = correlate(tt);
        // A truth whose change is all noise has no pattern to correlate with.
        out.correlation_without_noise = correlate(tt - noise);
    }
    out
}

/// The markdown table of the changes by band (`labels`, then the whole sea last).
pub fn markdown(scene_name: &str, bare_reference: &str, labels: &[String], changes: &[WaveChange]) -> String {
    let mut md = format!(
        "The local waves' own change: scene `{scene_name}` less its bare sea (`{bare_reference}` the truth's), the full \
         method's default setting against the ground truth, the reflected sky plus the refracted light (kcd/m²). The mean \
         change over the band's sea, the truth's ± its standard error; then over the pixels the local waves reach (where \
         ours changes by more than {WAKE_CHANGE} of its bare sea, widened by the blur), the changes blurred over \
         {CHANGE_BLUR_PX} pixels: the rms of each (the truth's beside its noise's, drawn from its half estimates) and \
         ours over the truth's without its noise, and their correlation, as they are and without the truth's noise (1: \
         the truth's pattern; where pixels hold a wake's waves the half estimates take some of them for noise, and this \
         errs high).\n\n\
         | band (m) | pixels | truth's mean change | ours | ours / truth's | wake pixels | truth's rms (its noise's) | ours | ours / truth's without noise | correlation (without noise) |\n\
         |---|---|---|---|---|---|---|---|---|---|\n"
    );
    let ratio = |a: f64, b: f64| if b != 0.0 && (a / b).is_finite() { format!("{:.2}", a / b) } else { "—".into() };
    let value = |v: f64| if v.is_finite() { format!("{v:+.4}") } else { "—".into() };
    let plain = |v: f64| if v.is_finite() { format!("{v:.4}") } else { "—".into() };
    let two = |v: f64| if v.is_finite() { format!("{v:.2}") } else { "—".into() };
    for (label, c) in labels.iter().zip(changes) {
        if c.pixels == 0 {
            continue;
        }
        writeln!(
            md,
            "| {label} | {} | {} ± {:.4} | {} | {} | {} | {} ({}) | {} | {} | {} ({}) |",
            c.pixels,
            value(c.truth_mean),
            c.truth_uncertainty,
            value(c.method_mean),
            ratio(c.method_mean, c.truth_mean),
            c.wake_pixels,
            plain(c.truth_rms),
            plain(c.truth_noise_rms),
            plain(c.method_rms),
            ratio(c.method_rms, c.truth_signal_rms()),
            two(c.correlation),
            two(c.correlation_without_noise)
        )
        .unwrap();
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic noise of standard deviation `sd`, independent per pixel and per `seed`.
    fn noise(len: usize, seed: u64, sd: f64) -> Vec<f64> {
        (0..len as u64)
            .map(|i| {
                let x = (i ^ (seed << 32)).wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let x = (x ^ (x >> 29)).wrapping_mul(0xbf58476d1ce4e5b9);
                ((x >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * sd * 12f64.sqrt()
            })
            .collect()
    }

    /// A wake drawn at half its strength, the truth's change under its sampling noise (its two
    /// halves of 2 samples each drawn apart): half the mean change, half the rms, and the truth's
    /// pattern (correlation near 1 once the noise is taken out).
    #[test]
    fn a_wake_at_half_strength_reads_half_with_the_truth_s_pattern() {
        let (w, h) = (96usize, 64usize);
        let pattern: Vec<f64> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                let inside = (20.0..76.0).contains(&x) && (16.0..48.0).contains(&y);
                if inside {
                    -0.2 + 0.3 * (x * 0.7 + y * 0.3).sin()
                } else {
                    0.0
                }
            })
            .collect();
        // 2 x 2 samples: the half estimate holds 2 of them, the rest 2.
        let (a, b) = (noise(w * h, 1, 0.15), noise(w * h, 2, 0.15));
        let bare = vec![1.0; w * h];
        let truth_half: Vec<f64> = (0..w * h).map(|i| 1.0 + pattern[i] + a[i]).collect();
        let truth: Vec<f64> = (0..w * h).map(|i| 1.0 + pattern[i] + 0.5 * (a[i] + b[i])).collect();
        let method: Vec<f64> = (0..w * h).map(|i| 1.0 + 0.5 * pattern[i]).collect();
        let c = Changes::new([&method, &bare], [&truth, &bare], [&truth_half, &bare], 2, w, h);
        let all: Vec<usize> = (0..w * h).collect();
        let r = wave_change(&c, &all);
        assert!((r.method_mean / r.truth_mean - 0.5).abs() < 0.05, "{r:?}");
        assert!((r.method_rms / r.truth_signal_rms() - 0.5).abs() < 0.1, "{r:?}");
        assert!(r.correlation_without_noise > 0.9 && r.correlation_without_noise < 1.1, "{r:?}");
        // The noise lowers the correlation as it is.
        assert!(r.correlation < r.correlation_without_noise, "{r:?}");
        // The truth's noise in its mean: 0.15 / sqrt(2) over sqrt(w h) pixels.
        let expected = 0.15 / 2f64.sqrt() / ((w * h) as f64).sqrt();
        assert!((r.truth_uncertainty / expected - 1.0).abs() < 0.1, "{r:?}: {expected}");
        // The wake's pixels are the pattern's rectangle, give or take its edge's blur.
        assert!(r.wake_pixels.abs_diff(56 * 32) < 100, "{r:?}");
        // Drawn with no wake, it reads none, and reaches no pixel.
        let none = Changes::new([&bare, &bare], [&truth, &bare], [&truth_half, &bare], 2, w, h);
        let r = wave_change(&none, &all);
        assert_eq!((r.method_mean, r.wake_pixels), (0.0, 0), "{r:?}");
    }

    /// The bare sea drops the scene's [[wake]]s and [[splash]]es and keeps the rest; a scene
    /// whose object moves, or that has no local waves, is refused with one line naming why.
    #[test]
    fn the_bare_sea_is_the_scene_without_its_local_waves() {
        let load =
            |path: &str| Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path).as_path()).unwrap();
        let scene = load("scenes/wake_mast.toml");
        let bare = bare_scene(&scene, "wake_mast").unwrap();
        assert!(bare.wakes.is_empty() && bare.splashes.is_empty());
        assert_eq!(Scene { wakes: scene.wakes.clone(), ..bare }, scene);
        let moving = bare_scene(&load("scenes/objects/wake_sunset.toml"), "wake_sunset").unwrap_err().to_string();
        assert!(moving.contains("moves (velocity_mps)") && !moving.contains('\n'), "{moving}");
        let calm = bare_scene(&load("scenes/default.toml"), "default").unwrap_err().to_string();
        assert!(calm.contains("no [[wake]] or [[splash]]"), "{calm}");
    }

    #[test]
    fn the_blur_keeps_a_constant_and_spreads_a_point_as_its_gaussian() {
        assert!(blur(&[2.0; 20 * 10], 20, 10, CHANGE_BLUR_PX).iter().all(|v| (v - 2.0).abs() < 1e-12));
        let mut point = vec![0.0; 21 * 21];
        point[10 * 21 + 10] = 1.0;
        let spread = blur(&point, 21, 21, CHANGE_BLUR_PX);
        let at = |dx: usize, dy: usize| spread[(10 + dy) * 21 + 10 + dx];
        let gaussian = |d2: f64| (-0.5 * d2 / (CHANGE_BLUR_PX * CHANGE_BLUR_PX)).exp();
        assert!((at(2, 1) / at(0, 0) - gaussian(5.0)).abs() < 1e-3, "{} {}", at(2, 1) / at(0, 0), gaussian(5.0));
        assert!((spread.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }
}
