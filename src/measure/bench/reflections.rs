//! `bench reflections`: the sea's reflections of a scene's objects, method by method
//! (`render.reflections`: none, screen, planar, both), against a ground truth of the scene and one
//! of the same scene without its objects (the "bare" truth). Each method renders the whole view
//! through the commands' host (app::host, the only one that draws objects), timed, and once per
//! term; it is measured over the sea's pixels that no object covers, as `bench error-vs-time`
//! measures (RMSE and energy per term and distance band), and on the objects' reflection alone:
//! the truth's is its sky term less the bare truth's (the tracer puts an object met by a reflected
//! ray in the sky term's place), a method's its sky term less the bare scene's. Over the pixels
//! where the truth's reflection of the objects stands well above its sampling noise (by blocks of
//! 4x4): the reflection's energy error and its local contrast (within 8x8 blocks) against the
//! truth's.

use crate::app::host::OffscreenHost;
use crate::app::median;
use crate::embed::Shading;
use crate::error::{Error, Result};
use crate::measure::bench::error_vs_time::{
    band_label, csv_value, errors, sea_pixels_by_band_in, TermErrors, BANDS_M, TERMS,
};
use crate::measure::detail::Contrast;
use crate::measure::groundtruth::GroundTruthFiles;
use crate::model::scene::{Reflections, Scene};
use crate::model::waves;
use crate::output::progress::Progress;
use crate::output::{luminance, write_text};
use crate::render::frame::CameraFrame;
use crate::render::passes::ocean::{ShaderConfig, Terms};
use crate::vk::gpu::Gpu;
use std::fmt::Write as _;
use std::path::Path;

/// The methods compared, in this order.
pub const METHODS: [Reflections; 4] = [Reflections::None, Reflections::Screen, Reflections::Planar, Reflections::Both];
/// The targets where the truth's reflection of the objects is resolved: its energy within
/// 10% of the truth's, its local contrast within 20%.
pub const ENERGY_TARGET: f64 = 0.10;
pub const CONTRAST_TARGET: f64 = 0.20;
/// The truth's reflection of the objects is resolved over a block of RESOLVED_BLOCK_PX x
/// RESOLVED_BLOCK_PX pixels where its sum there stands this many standard deviations of the
/// truth's sampling noise above zero...
pub const RESOLVED_SIGMAS: f64 = 4.0;
/// ...and above this fraction of the bare truth's sky there (what a difference of two traces of
/// the same sky, sampled alike, may still show).
pub const RESOLVED_FRACTION: f64 = 0.01;
/// Side of the blocks the truth's reflection is resolved in (pixels): a faint reflection spread
/// over many pixels (a pier's underside through a rough sea) stands above the noise of a block's
/// sum where few single pixels do.
pub const RESOLVED_BLOCK_PX: usize = 4;
/// Side of the blocks the local contrast is measured in (pixels).
pub const CONTRAST_BLOCK_PX: usize = 8;
/// A raster pixel is an object's where the scene's sea term differs from the bare scene's by more
/// than this fraction (the sea's refracted light does not see the objects).
const OBJECT_DIFFERENCE: f64 = 1e-3;

/// The truth's reflection of the objects, per pixel of the images the truths traced.
pub struct TruthReflection {
    pub width: usize,
    /// Luminance of the objects' reflection alone: sky(truth) - sky(bare truth).
    pub reflection: Vec<f64>,
    /// An estimate of its sampling variance, which the contrast's noise is taken from: from the
    /// truths' halves (`with_halves`), else the bound (the sum of both truths' variances of their
    /// sky terms' means; the two are traced with the same samples, and agree wherever no object
    /// is met, so their difference is less noisy than that).
    pub noise: Vec<f64>,
    /// Whether each pixel is in a block where it is resolved (RESOLVED_SIGMAS, RESOLVED_FRACTION,
    /// RESOLVED_BLOCK_PX).
    pub resolved: Vec<bool>,
    /// The reflection its energy is measured on, and that one's sampling variance: with halves,
    /// the samples' half that did not decide where it is resolved (a selection by the same noisy
    /// values it then sums would keep the noise that lifted them over the bar, and inflate the
    /// truth's sum); without, the whole.
    pub measured: Vec<f64>,
    pub measured_noise: Vec<f64>,
    /// The bare truth's sky term (luminance), the sea the reflection is measured relative to.
    pub bare: Vec<f64>,
}

impl TruthReflection {
    /// From the luminances of the two truths' sky terms and the bound on their difference's
    /// variance, resolved over the `counted` pixels (the sea no object covers).
    pub fn new(
        width: usize,
        with_objects: &[f64],
        bare: &[f64],
        variance: &[f64],
        counted: &[bool],
    ) -> TruthReflection {
        let reflection: Vec<f64> = with_objects.iter().zip(bare).map(|(a, b)| a - b).collect();
        let resolved = resolve_blocks(width, &reflection, variance, bare, counted);
        TruthReflection {
            width,
            measured: reflection.clone(),
            measured_noise: variance.to_vec(),
            reflection,
            noise: variance.to_vec(),
            resolved,
            bare: bare.to_vec(),
        }
    }

    /// With both truths' half-estimates of their sky terms (the strata with i + j even of
    /// `samples_per_axis`^2, groundtruth.rs): the noise estimated from them, the blocks resolved
    /// by the half against the bound, the energy measured on the other half
    /// ((N^2 F - n_a A) / n_b). Call once, on a truth from `new`.
    pub fn with_halves(self, half: [&[f64]; 2], bare: &[f64], samples_per_axis: u32, counted: &[bool]) -> Self {
        let (all, n_a, n_b) = half_split(samples_per_axis);
        let with_objects: Vec<f64> = self.reflection.iter().zip(bare).map(|(r, b)| r + b).collect();
        let noise = half_difference_noise([&with_objects, bare], half, samples_per_axis);
        let deciding: Vec<f64> = half[0].iter().zip(half[1]).map(|(a, b)| a - b).collect();
        // The bar by the bound, scaled to the half: the estimate from the halves holds the other
        // half's values, and would let them choose the blocks too.
        let deciding_noise: Vec<f64> = self.noise.iter().map(|v| v * all / n_a).collect();
        let resolved = resolve_blocks(self.width, &deciding, &deciding_noise, bare, counted);
        let measured = self.reflection.iter().zip(&deciding).map(|(f, a)| (all * f - n_a * a) / n_b).collect();
        let measured_noise = noise.iter().map(|v| v * all / n_b).collect();
        TruthReflection { noise, resolved, measured, measured_noise, ..self }
    }
}

/// Each pixel: whether its block's sum of `reflection` over the `counted` pixels stands
/// RESOLVED_SIGMAS standard deviations (of the sum of `variance`) and RESOLVED_FRACTION of the
/// `bare` sky's sum above zero.
fn resolve_blocks(width: usize, reflection: &[f64], variance: &[f64], bare: &[f64], counted: &[bool]) -> Vec<bool> {
    let blocks_wide = width.div_ceil(RESOLVED_BLOCK_PX);
    let block_of = |i: usize| (i / width / RESOLVED_BLOCK_PX) * blocks_wide + (i % width) / RESOLVED_BLOCK_PX;
    let blocks = block_of(reflection.len().saturating_sub(1)) + 1;
    let (mut sum, mut var, mut sky) = (vec![0.0; blocks], vec![0.0; blocks], vec![0.0; blocks]);
    for i in (0..reflection.len()).filter(|&i| counted[i]) {
        let b = block_of(i);
        sum[b] += reflection[i];
        var[b] += variance[i].max(0.0);
        sky[b] += bare[i].abs();
    }
    let block_resolved: Vec<bool> = (0..blocks)
        .map(|b| sum[b].abs() > RESOLVED_SIGMAS * var[b].sqrt() && sum[b].abs() > RESOLVED_FRACTION * sky[b])
        .collect();
    (0..reflection.len()).map(|i| counted[i] && block_resolved[block_of(i)]).collect()
}

/// A pixel's samples at `samples_per_axis`^2: all of them, its half-estimate's n_a (the strata
/// with i + j even, groundtruth.rs) and the rest's n_b.
fn half_split(samples_per_axis: u32) -> (f64, f64, f64) {
    let all = samples_per_axis * samples_per_axis;
    let n_a = all.div_ceil(2);
    (all as f64, n_a as f64, (all - n_a) as f64)
}

/// Each pixel's estimate of the variance of the difference of two truths' means traced with the
/// same `samples_per_axis`^2 samples, from their full (`full`) and half (`half`: the strata with
/// i + j even, groundtruth.rs) estimates of one term: with A the half's mean over n_a samples and
/// B the other's over n_b, F - A = (n_b / N^2) (B - A), whose square has the expectation
/// var(F) n_b / n_a; the difference of the two truths' F - A, the same of their difference (one
/// degree of freedom a pixel: to be summed over many).
pub fn half_difference_noise(full: [&[f64]; 2], half: [&[f64]; 2], samples_per_axis: u32) -> Vec<f64> {
    let (_, n_a, n_b) = half_split(samples_per_axis);
    (0..full[0].len())
        .map(|i| {
            let d = (full[0][i] - half[0][i]) - (full[1][i] - half[1][i]);
            d * d * n_a / n_b
        })
        .collect()
}

/// A method's reflection of the objects against the truth's over one selection of the sea.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct ObjectReflection {
    /// The selection's pixels where the truth's reflection of the objects is resolved.
    pub resolved_pixels: usize,
    /// Sums of the reflection alone (luminance, kcd/m^2) over them: the truth's and the method's.
    pub truth_sum: f64,
    pub method_sum: f64,
    /// method_sum / truth_sum - 1 (NaN without resolved pixels), and its standard error from the
    /// truths' sampling noise.
    pub energy_error: f64,
    pub energy_uncertainty: f64,
    /// Blocks of CONTRAST_BLOCK_PX x CONTRAST_BLOCK_PX pixels holding a resolved pixel, which the
    /// contrast is measured over.
    pub contrast_blocks: usize,
    /// The standard deviation of the reflection alone within those blocks (pooled over them), the
    /// method's against the truth's with its noise removed.
    pub contrast: Contrast,
    /// The energy relative to each one's own sea (`relative_to_seas`; NaN until then).
    pub relative_energy_error: f64,
}

impl ObjectReflection {
    /// With the reflection's energy measured relative to each one's own sea: the method's sum over
    /// its bare scene's sky term there, against the truth's over the bare truth's, less 1. The
    /// objects change the sky term by their radiance less the sky's, both times the Fresnel, so a
    /// sea whose own sky term is off by a factor there changes the reflection's energy by about
    /// that factor: this share leaves the sea's own error out, and shows the reflection's.
    pub fn relative_to_seas(self, method_bare: &[f64], truth: &TruthReflection, select: &[usize]) -> Self {
        let resolved = select.iter().copied().filter(|&i| truth.resolved[i]);
        let (method_sea, truth_sea) = resolved.fold((0.0, 0.0), |(m, t), i| (m + method_bare[i], t + truth.bare[i]));
        let relative = (self.method_sum / method_sea) / (self.truth_sum / truth_sea) - 1.0;
        ObjectReflection { relative_energy_error: if relative.is_finite() { relative } else { f64::NAN }, ..self }
    }
}

/// The method's reflection alone (`method`, luminance per pixel) against the truth's over the
/// pixels `select`ed (the sea no object covers: the whole of it or a band).
pub fn object_reflection(method: &[f64], truth: &TruthReflection, select: &[usize]) -> ObjectReflection {
    let resolved: Vec<usize> = select.iter().copied().filter(|&i| truth.resolved[i]).collect();
    let truth_sum: f64 = resolved.iter().map(|&i| truth.measured[i]).sum();
    let method_sum: f64 = resolved.iter().map(|&i| method[i]).sum();
    let variance: f64 = resolved.iter().map(|&i| truth.measured_noise[i]).sum();
    let (energy_error, energy_uncertainty) = if resolved.is_empty() || truth_sum == 0.0 {
        (f64::NAN, f64::NAN)
    } else {
        // As error_vs_time's: the ratio moves by method_sum / truth_sum^2 per unit of truth_sum.
        (method_sum / truth_sum - 1.0, variance.sqrt() * (method_sum / (truth_sum * truth_sum)).abs())
    };
    // The selection's pixels by block; the blocks that hold a resolved pixel.
    let w = truth.width;
    let block_of = |i: usize| ((i / w) / CONTRAST_BLOCK_PX, (i % w) / CONTRAST_BLOCK_PX);
    let mut blocks: std::collections::BTreeMap<(usize, usize), (Vec<usize>, bool)> = Default::default();
    for &i in select {
        let block = blocks.entry(block_of(i)).or_default();
        block.0.push(i);
        block.1 |= truth.resolved[i];
    }
    let (mut method_sq, mut truth_sq, mut noise, mut dof, mut count) = (0.0, 0.0, 0.0, 0.0, 0);
    for (pixels, _) in blocks.values().filter(|(pixels, any)| *any && pixels.len() >= 2) {
        let n = pixels.len() as f64;
        let spread = |value: &dyn Fn(usize) -> f64| {
            let mean = pixels.iter().map(|&i| value(i)).sum::<f64>() / n;
            pixels.iter().map(|&i| (value(i) - mean).powi(2)).sum::<f64>()
        };
        method_sq += spread(&|i| method[i]);
        truth_sq += spread(&|i| truth.reflection[i]);
        // Independent noise of variance v_i adds (1 - 1/n) sum v_i to the squares about the mean.
        noise += (1.0 - 1.0 / n) * pixels.iter().map(|&i| truth.noise[i]).sum::<f64>();
        dof += n - 1.0;
        count += 1;
    }
    let contrast = if dof > 0.0 {
        Contrast::new(method_sq / dof, truth_sq / dof, noise / dof)
    } else {
        Contrast::new(0.0, 0.0, 0.0)
    };
    ObjectReflection {
        resolved_pixels: resolved.len(),
        truth_sum,
        method_sum,
        energy_error,
        energy_uncertainty,
        contrast_blocks: count,
        contrast,
        relative_energy_error: f64::NAN,
    }
}

/// Whether a measure meets its target: the energy within ENERGY_TARGET, the contrast ratio within
/// CONTRAST_TARGET of 1 (None where there is nothing to measure).
fn meets(value: f64, target: f64) -> Option<bool> {
    value.is_finite().then(|| value.abs() <= target)
}

/// What one method measured.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Measured {
    pub gpu_ms: f64,
    /// Over the sea no object covers, per term (error_vs_time's TERMS).
    pub all: TermErrors,
    /// Per distance band: (pixels, errors).
    pub bands: Vec<(usize, TermErrors)>,
    pub reflection: ObjectReflection,
    pub reflection_bands: Vec<ObjectReflection>,
}

impl Measured {
    pub fn energy_pass(&self) -> Option<bool> {
        meets(self.reflection.energy_error, ENERGY_TARGET)
    }

    pub fn contrast_pass(&self) -> Option<bool> {
        meets(self.reflection.contrast.ratio - 1.0, CONTRAST_TARGET)
    }
}

/// One method's row: what it measured, or why its render failed.
#[derive(Debug, Clone)]
pub struct Row {
    pub method: Reflections,
    pub outcome: std::result::Result<Measured, String>,
}

/// The inputs of one run.
pub struct Request<'a> {
    pub scene: &'a Scene,
    pub scene_name: &'a str,
    /// Ground truth of the scene, and of the same scene without its objects.
    pub reference: &'a Path,
    pub bare_reference: &'a Path,
    pub frames: u32,
    pub out_dir: &'a Path,
}

/// A ground truth, loaded, with what it failed on as one line naming the option.
fn load_truth(path: &Path, option: &str) -> Result<GroundTruthFiles> {
    GroundTruthFiles::load(path).map_err(|e| Error::Argument(format!("{option} {}: {e}", path.display())))
}

/// Whether `truth` was traced from `scene`; the reflection method is the raster's alone.
fn traced_from(truth: &GroundTruthFiles, scene: &Scene) -> bool {
    let mut scene = scene.clone();
    scene.render.reflections = truth.meta.scene.render.reflections;
    truth.meta.is_of(&scene)
}

/// The host's frame of `scene` with `shader`, read back.
fn render_once(gpu: &Gpu, scene: &Scene, (w, h): (u32, u32), shader: ShaderConfig) -> Result<Vec<[f32; 4]>> {
    let mut host = OffscreenHost::new(gpu, scene, w, h, Shading { shader, ..Shading::default() })?;
    Ok(host.render(scene)?.hdr)
}

fn terms(sun: bool, sky: bool, sea: bool, reflections: Reflections) -> ShaderConfig {
    let method = ShaderConfig::default().method;
    ShaderConfig { reflections, ..ShaderConfig::terms_only(Terms { sun, sky, sea }, method) }
}

/// A method's frame timed (median of `frames` after the one that is its image), and its terms:
/// total, sun, sky, sea of the whole view.
fn render_method(
    gpu: &Gpu,
    scene: &Scene,
    size: (u32, u32),
    reflections: Reflections,
    frames: u32,
) -> Result<([Vec<[f32; 4]>; 4], f64)> {
    let shader = ShaderConfig { reflections, ..ShaderConfig::default() };
    let mut host = OffscreenHost::new(gpu, scene, size.0, size.1, Shading { shader, ..Shading::default() })?;
    let total = host.render(scene)?; // warm-up, and the image
    let mut times = Vec::new();
    for _ in 0..frames {
        times.push(host.render(scene)?.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>());
    }
    drop(host);
    times.sort_by(f64::total_cmp);
    let sun = render_once(gpu, scene, size, terms(true, false, false, reflections))?;
    let sky = render_once(gpu, scene, size, terms(false, true, false, reflections))?;
    let sea = render_once(gpu, scene, size, terms(false, false, true, reflections))?;
    Ok(([total.hdr, sun, sky, sea], median(&times)))
}

/// The pixels an object covers: where the raster's sea term of the scene differs from the bare
/// scene's (the sea's refracted light does not see the objects), grown by a pixel for the edges
/// the truth's samples share between an object and the sea. (The truth's own terms cannot say:
/// its sea term falls beside the objects too, where a reflected ray meets one and bounces no
/// further.)
fn object_pixels((w, h): (usize, usize), with_objects: &[[f32; 4]], bare: &[[f32; 4]]) -> Vec<bool> {
    let differs = |a: [f32; 4], b: [f32; 4]| {
        (0..3).any(|c| (a[c] - b[c]).abs() as f64 > OBJECT_DIFFERENCE * (a[c].abs().max(b[c].abs()) as f64) + 1e-9)
    };
    let drawn: Vec<bool> = with_objects.iter().zip(bare).map(|(&a, &b)| differs(a, b)).collect();
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (y.saturating_sub(1)..(y + 2).min(h))
                .any(|yy| (x.saturating_sub(1)..(x + 2).min(w)).any(|xx| drawn[yy * w + xx]))
        })
        .collect()
}

pub fn run(gpu: &Gpu, request: &Request) -> Result<Vec<Row>> {
    let Request { scene, scene_name, reference, bare_reference, frames, out_dir } = *request;
    if scene.objects.is_empty() {
        return Err(Error::Argument(format!(
            "scene {scene_name} has no [[object]]: bench reflections compares the sea's reflections of objects"
        )));
    }
    let truth = load_truth(reference, "--reference")?;
    let bare_truth = load_truth(bare_reference, "--bare-reference")?;
    let mut bare_scene = scene.clone();
    bare_scene.objects.clear();
    if !traced_from(&truth, scene) {
        return Err(Error::Argument(format!(
            "--reference {} was made for another scene than {scene_name}: make it with `ocean reference --scene {scene_name}`",
            reference.display()
        )));
    }
    if !traced_from(&bare_truth, &bare_scene) {
        let what = if bare_truth.meta.scene.objects.is_empty() { "another scene" } else { "a scene with objects" };
        return Err(Error::Argument(format!(
            "--bare-reference {} was made for {what}: trace a copy of {scene_name} without its [[object]]s",
            bare_reference.display()
        )));
    }
    let (view_w, view_h) = (truth.meta.width, truth.meta.height);
    let region = truth.meta.region();
    if (bare_truth.meta.width, bare_truth.meta.height, bare_truth.meta.region()) != (view_w, view_h, region) {
        return Err(Error::Argument(format!(
            "--bare-reference {} is of {}x{} ({}), --reference of {view_w}x{view_h} ({}): trace both alike",
            bare_reference.display(),
            bare_truth.meta.width,
            bare_truth.meta.height,
            bare_truth.meta.region.map_or("the whole view".to_owned(), |r| format!("region {r}")),
            truth.meta.region.map_or("the whole view".to_owned(), |r| format!("region {r}")),
        )));
    }
    let (w, h) = (region.width as usize, region.height as usize);
    let size = (view_w, view_h);
    let crop = |image: Vec<[f32; 4]>| region.crop(&image, view_w);

    let mut progress = Progress::new("bench reflections", METHODS.len() as u64 + 1, "steps", false);
    progress.set(0, Some("the bare scene's sky and sea, the scene's sea"));
    let bare_sky = crop(render_once(gpu, &bare_scene, size, terms(false, true, false, Reflections::None))?);
    let bare_sea = crop(render_once(gpu, &bare_scene, size, terms(false, false, true, Reflections::None))?);
    let sea_with = crop(render_once(gpu, scene, size, terms(false, false, true, Reflections::None))?);
    let objects = object_pixels((w, h), &sea_with, &bare_sea);

    // The sea no object covers, by distance band (the region's indices), and all of it.
    let wave_set = waves::generate(scene);
    let camera = CameraFrame::new(scene, &wave_set, view_w, view_h);
    let whole_bands = sea_pixels_by_band_in(&camera, view_w, view_h, region);
    let covered = whole_bands.iter().flatten().filter(|&&i| objects[i]).count();
    let bands: Vec<Vec<usize>> =
        whole_bands.into_iter().map(|band| band.into_iter().filter(|&i| !objects[i]).collect()).collect();
    let mut sea: Vec<usize> = bands.iter().flatten().copied().collect();
    sea.sort_unstable();

    const SKY: usize = 2;
    let sky_with: Vec<f64> = truth.sky.iter().map(|&p| luminance(p)).collect();
    let sky_bare: Vec<f64> = bare_truth.sky.iter().map(|&p| luminance(p)).collect();
    let bound: Vec<f64> =
        truth.variance.iter().zip(&bare_truth.variance).map(|(a, b)| (a[SKY] + b[SKY]) as f64).collect();
    let mut counted = vec![false; w * h];
    sea.iter().for_each(|&i| counted[i] = true);
    let mut truth_reflection = TruthReflection::new(w, &sky_with, &sky_bare, &bound, &counted);
    let samples = truth.meta.samples_per_axis;
    let halves = match (&truth.half, &bare_truth.half) {
        (Some(a), Some(b)) if samples == bare_truth.meta.samples_per_axis && a.len() == w * h && b.len() == w * h => {
            let half = |image: &[[f32; 4]]| image.iter().map(|p| p[SKY] as f64).collect::<Vec<f64>>();
            truth_reflection = truth_reflection.with_halves([&half(a), &half(b)], &sky_bare, samples, &counted);
            true
        }
        _ => false,
    };
    let truth_images = [truth.total.as_slice(), truth.sun.as_slice(), truth.sky.as_slice(), truth.sea.as_slice()];
    let bare_sky_luminance: Vec<f64> = bare_sky.iter().map(|&p| luminance(p)).collect();

    let mut rows = Vec::new();
    for (k, &method) in METHODS.iter().enumerate() {
        progress.set(
            k as u64 + 1,
            Some(&format!("reflections = {}, {} frames and 3 term renders", method.name(), frames + 1)),
        );
        let outcome = render_method(gpu, scene, size, method, frames).map(|(images, gpu_ms)| {
            let images = images.map(crop);
            let reflection: Vec<f64> =
                images[SKY].iter().zip(&bare_sky_luminance).map(|(&p, &bare)| luminance(p) - bare).collect();
            Measured {
                gpu_ms,
                all: errors(&images, &truth_images, &truth.variance, &sea),
                bands: bands.iter().map(|b| (b.len(), errors(&images, &truth_images, &truth.variance, b))).collect(),
                reflection: object_reflection(&reflection, &truth_reflection, &sea).relative_to_seas(
                    &bare_sky_luminance,
                    &truth_reflection,
                    &sea,
                ),
                reflection_bands: bands
                    .iter()
                    .map(|b| {
                        object_reflection(&reflection, &truth_reflection, b).relative_to_seas(
                            &bare_sky_luminance,
                            &truth_reflection,
                            b,
                        )
                    })
                    .collect(),
            }
        });
        let row = Row { method, outcome: outcome.map_err(|e| e.to_string()) };
        progress.println(&summary(&row));
        rows.push(row);
    }
    progress.set(METHODS.len() as u64 + 1, None);
    let info = TruthInfo {
        reference,
        bare_reference,
        sampling: format!(
            "{n}x{n} and {m}x{m} samples per pixel",
            n = truth.meta.samples_per_axis,
            m = bare_truth.meta.samples_per_axis
        ),
        size: (w, h),
        halves,
        sea_pixels: sea.len(),
        object_pixels: covered,
    };
    write_outputs(&rows, out_dir, scene_name, &info, frames)?;
    Ok(rows)
}

fn verdict(pass: Option<bool>) -> &'static str {
    match pass {
        Some(true) => "pass",
        Some(false) => "FAIL",
        None => "n/a",
    }
}

/// The method's one line: time, the whole image's error, the reflected objects' energy and
/// contrast against the targets.
pub fn summary(row: &Row) -> String {
    let name = row.method.name();
    match &row.outcome {
        Err(e) => format!("{name:<7} failed: {e}"),
        Ok(m) => format!(
            "{name:<7} {:7.1} ms  rmse {:.4}  energy {:+.3}  sky energy {:+.3}  reflected objects: energy {:+.3} ± {:.3} ({} within {:.0}%; relative to its sea {:+.3}), contrast {:.3} ({} within {:.0}%)",
            m.gpu_ms,
            m.all.rmse[0],
            m.all.energy_error[0],
            m.all.energy_error[2],
            m.reflection.energy_error,
            m.reflection.energy_uncertainty,
            verdict(m.energy_pass()),
            100.0 * ENERGY_TARGET,
            m.reflection.relative_energy_error,
            m.reflection.contrast.ratio,
            verdict(m.contrast_pass()),
            100.0 * CONTRAST_TARGET,
        ),
    }
}

struct TruthInfo<'a> {
    reference: &'a Path,
    bare_reference: &'a Path,
    sampling: String,
    size: (usize, usize),
    /// Whether the truths' noise in the objects' reflection came from their half-estimates.
    halves: bool,
    sea_pixels: usize,
    object_pixels: usize,
}

/// A CSV field of text: quoted, its quotes doubled, on one line.
fn csv_text(text: &str) -> String {
    format!("\"{}\"", text.replace('"', "\"\"").replace(['\n', '\r'], " "))
}

fn csv_header() -> String {
    let terms: String =
        TERMS.iter().map(|t| format!(",rmse_{t},rmse_floor_{t},energy_error_{t},energy_uncertainty_{t}")).collect();
    format!(
        "method,status,gpu_ms,band,distance_min_m,distance_max_m,sea_pixels{terms},resolved_pixels,\
         truth_reflection_sum,method_reflection_sum,reflection_energy_error,reflection_energy_uncertainty,\
         reflection_relative_energy_error,contrast_blocks,contrast_method,contrast_truth,contrast_truth_signal,contrast_ratio,energy_pass,\
         contrast_pass,error"
    )
}

fn csv_line(method: &str, gpu_ms: f64, band: (&str, f64, f64, usize), e: &TermErrors, r: &ObjectReflection) -> String {
    let mut line = format!("{method},ok,{gpu_ms:.3},{},{},{},{}", band.0, band.1, band.2, band.3);
    for t in 0..4 {
        for v in [e.rmse[t], e.rmse_floor[t], e.energy_error[t], e.energy_uncertainty[t]] {
            write!(line, ",{}", csv_value(v)).unwrap();
        }
    }
    write!(line, ",{}", r.resolved_pixels).unwrap();
    for v in [r.truth_sum, r.method_sum, r.energy_error, r.energy_uncertainty, r.relative_energy_error] {
        write!(line, ",{}", csv_value(v)).unwrap();
    }
    write!(line, ",{}", r.contrast_blocks).unwrap();
    let c = &r.contrast;
    for v in [c.method, c.truth, c.truth_signal, c.ratio] {
        write!(line, ",{}", csv_value(v)).unwrap();
    }
    let pass = |p: Option<bool>| p.map_or(String::new(), |p| p.to_string());
    let (energy, contrast) = (meets(r.energy_error, ENERGY_TARGET), meets(r.contrast.ratio - 1.0, CONTRAST_TARGET));
    write!(line, ",{},{},", pass(energy), pass(contrast)).unwrap();
    line
}

/// A table cell: a signed fraction ± its uncertainty, a ratio, or a dash where there is none.
fn signed(v: f64, u: f64) -> String {
    match (v.is_finite(), u.is_finite()) {
        (true, true) => format!("{v:+.3} ± {u:.3}"),
        (true, false) => format!("{v:+.3}"),
        _ => "—".to_owned(),
    }
}

fn plain(v: f64, digits: usize) -> String {
    if v.is_finite() {
        format!("{v:.digits$}")
    } else {
        "—".to_owned()
    }
}

fn write_outputs(rows: &[Row], dir: &Path, scene_name: &str, info: &TruthInfo, frames: u32) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mut csv = csv_header() + "\n";
    let columns = csv_header().split(',').count();
    for r in rows {
        let name = r.method.name();
        match &r.outcome {
            Ok(m) => {
                let line =
                    csv_line(name, m.gpu_ms, ("all", 0.0, f64::INFINITY, info.sea_pixels), &m.all, &m.reflection);
                csv += &(line + "\n");
                for (b, ((n, e), reflection)) in m.bands.iter().zip(&m.reflection_bands).enumerate() {
                    let band = (b.to_string(), BANDS_M[b], BANDS_M[b + 1], *n);
                    let line = csv_line(name, m.gpu_ms, (&band.0, band.1, band.2, band.3), e, reflection);
                    csv += &(line + "\n");
                }
            }
            Err(e) => {
                // The method and its status, empty fields, the error.
                csv += &format!("{name},failed{}{}\n", ",".repeat(columns - 2), csv_text(e));
            }
        }
    }
    write_text(&dir.join("reflections.csv"), &csv)?;

    let (w, h) = info.size;
    let mut md = format!(
        "Reflections of the objects, method by method: scene `{scene_name}` at {w}x{h}, against the ground truth \
         `{}` and the bare ground truth `{}` (the same scene without its objects; {}), GPU time the median of \
         {frames} frames through the commands' host (its objects and readback passes included).\n\n\
         Measured over the {} sea pixels no object covers ({} more of the sea's are an object's or touch one: where \
         the raster's sea term differs from the bare scene's, grown by a pixel; the truth leaves an object's pixels \
         out of every term, the host draws them in every term's image). RMSE of Rec. 709 luminance (kcd/m²); \
         energy error = (sum - truth's sum) / truth's sum ± its standard error from the truth's sampling noise.\n\n\
         The reflected objects: the truth's reflection of them is its sky term less the bare truth's (an object \
         met by a reflected ray takes the sky's place), a method's its sky term less the bare scene's. Over the \
         {RESOLVED_BLOCK_PX}x{RESOLVED_BLOCK_PX} blocks of pixels where the truth's is resolved (its sum there above \
         {RESOLVED_SIGMAS} standard deviations of the truths' noise in their difference, and above {:.0}% of the \
         bare sky's; {}): energy = sum of the method's / sum of the truth's - 1 (target within {:.0}%); \
         contrast = the standard deviation of the reflection alone within the {CONTRAST_BLOCK_PX}x{CONTRAST_BLOCK_PX} \
         blocks holding a resolved pixel, the method's over the truth's with its noise removed (target within \
         {:.0}% of 1). The truths' noise in their difference, for the energy's ± and the contrast: {}. \
         Relative to its sea: the method's sum over its bare scene's sky term there against the truth's over the \
         bare truth's, less 1 (the objects replace the sky's radiance by theirs, both times the Fresnel: a sea whose \
         own sky term is off by a factor there moves the reflection's energy by about that factor, which this \
         leaves out).\n\n\
         | method | GPU ms | RMSE total | energy total | RMSE sky | energy sky | resolved pixels | reflected objects' energy | target | relative to its sea | contrast | target |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
        info.reference.display(),
        info.bare_reference.display(),
        info.sampling,
        info.sea_pixels,
        info.object_pixels,
        100.0 * RESOLVED_FRACTION,
        if info.halves {
            "decided by one half of each truth's samples, the truth's energy summed over the other half, so that \
             the noise which lifts a block over the bar does not count in its sum"
        } else {
            "decided and summed by the same samples, which inflates the truth's sum where the reflection is faint"
        },
        100.0 * ENERGY_TARGET,
        100.0 * CONTRAST_TARGET,
        if info.halves {
            "from their half-estimates (the difference of each truth's full and half estimate)"
        } else {
            "the bound (the truths lack half-estimates of the same samples)"
        },
    );
    for r in rows {
        match &r.outcome {
            Ok(m) => writeln!(
                md,
                "| {} | {:.1} | {:.4} | {} | {:.4} | {} | {} | {} | {} | {} | {} | {} |",
                r.method.name(),
                m.gpu_ms,
                m.all.rmse[0],
                signed(m.all.energy_error[0], m.all.energy_uncertainty[0]),
                m.all.rmse[2],
                signed(m.all.energy_error[2], m.all.energy_uncertainty[2]),
                m.reflection.resolved_pixels,
                signed(m.reflection.energy_error, m.reflection.energy_uncertainty),
                verdict(m.energy_pass()),
                signed(m.reflection.relative_energy_error, f64::NAN),
                plain(m.reflection.contrast.ratio, 3),
                verdict(m.contrast_pass()),
            )
            .unwrap(),
            Err(e) => {
                writeln!(md, "| {} | failed: {} | | | | | | | | | | |", r.method.name(), e.replace('|', "\\|")).unwrap()
            }
        }
    }
    // By distance: the reflected objects' energy and contrast.
    let labels: Vec<String> = (0..BANDS_M.len() - 1).map(band_label).collect();
    let head = format!(
        "| quantity | method | whole sea | {} m |\n|---|---|---|{}\n",
        labels.join(" m | "),
        "---|".repeat(labels.len())
    );
    md += "\n### The reflected objects by distance\n\n";
    md += &head;
    let measured: Vec<(&str, &Measured)> =
        rows.iter().filter_map(|r| r.outcome.as_ref().ok().map(|m| (r.method.name(), m))).collect();
    type Cell = fn(&ObjectReflection) -> String;
    let quantities: [(&str, &str, Cell, Cell); 4] = [
        ("resolved pixels", "truth", |r| r.resolved_pixels.to_string(), |_| String::new()),
        (
            "energy",
            "truth's sum (kcd/m²)",
            |r| plain(if r.resolved_pixels > 0 { r.truth_sum } else { f64::NAN }, 3),
            |r| signed(r.energy_error, r.energy_uncertainty),
        ),
        ("energy relative to its sea", "", |_| String::new(), |r| signed(r.relative_energy_error, f64::NAN)),
        (
            "contrast",
            "truth's std (kcd/m²)",
            |r| plain(if r.contrast_blocks > 0 { r.contrast.truth_signal } else { f64::NAN }, 4),
            |r| plain(r.contrast.ratio, 3),
        ),
    ];
    for (name, truth_label, of_truth, of_method) in quantities {
        let Some((_, first)) = measured.first() else { break };
        let cells = |m: &Measured, f: Cell| {
            (f(&m.reflection), m.reflection_bands.iter().map(f).collect::<Vec<_>>().join(" | "))
        };
        let (whole, bands) = cells(first, of_truth);
        writeln!(md, "| {name} | {truth_label} | {whole} | {bands} |").unwrap();
        if name == "resolved pixels" {
            continue;
        }
        for (method, m) in &measured {
            let (whole, bands) = cells(m, of_method);
            writeln!(md, "| | {method} | {whole} | {bands} |").unwrap();
        }
    }
    write_text(&dir.join("reflections.md"), &md)
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: usize = 16;
    const H: usize = 16;

    /// A truth whose objects' reflection is a bright bar over the image's left half (rows 4..12,
    /// columns 2..8: resolved) and noise-sized specks elsewhere (not resolved).
    fn synthetic_truth(noise_variance: f64) -> (Vec<f64>, TruthReflection) {
        let bare = vec![10.0; W * H];
        let signal: Vec<f64> = (0..W * H)
            .map(|i| {
                let (x, y) = (i % W, i / W);
                if (4..12).contains(&y) && (2..8).contains(&x) {
                    if x % 2 == 0 {
                        3.0
                    } else {
                        1.0
                    }
                } else if (x + y) % 5 == 0 {
                    0.5 * noise_variance.sqrt() // within the noise: unresolved
                } else {
                    0.0
                }
            })
            .collect();
        let with: Vec<f64> = signal.iter().zip(&bare).map(|(s, b)| s + b).collect();
        let variance = vec![noise_variance; W * H];
        (signal, TruthReflection::new(W, &with, &bare, &variance, &[true; W * H]))
    }

    #[test]
    fn the_objects_energy_counts_the_resolved_blocks_alone() {
        let (signal, truth) = synthetic_truth(0.04);
        // The bar (rows 4..12, columns 2..8) lies in the 2 x 2 blocks of rows 4..12, columns 0..8.
        let blocks = 8 * 8;
        assert_eq!(truth.resolved.iter().filter(|&&r| r).count(), blocks, "the bar's blocks, not the specks'");
        assert!((0..W * H).all(|i| !truth.resolved[i] || ((4..12).contains(&(i / W)) && i % W < 8)));
        let all: Vec<usize> = (0..W * H).collect();
        // 10% too bright on the bar's blocks, and anything at all off them.
        let method: Vec<f64> =
            signal.iter().enumerate().map(|(i, s)| if truth.resolved[i] { 1.1 * s } else { 7.0 }).collect();
        let r = object_reflection(&method, &truth, &all);
        assert_eq!(r.resolved_pixels, blocks);
        let truth_sum: f64 = (0..W * H).filter(|&i| truth.resolved[i]).map(|i| signal[i]).sum();
        assert!(truth_sum > 48.0 * 2.0, "the bar and the specks beside it in its blocks");
        assert!((r.truth_sum - truth_sum).abs() < 1e-9, "{}", r.truth_sum);
        assert!((r.energy_error - 0.1).abs() < 1e-9, "{}", r.energy_error);
        // Its standard error: sqrt(sum var) * method_sum / truth_sum^2.
        let expected = (blocks as f64 * 0.04).sqrt() * 1.1 / truth_sum;
        assert!((r.energy_uncertainty - expected).abs() < 1e-12, "{}", r.energy_uncertainty);
        assert_eq!(meets(r.energy_error, ENERGY_TARGET), Some(true), "10% is within the target");
        // No reflection at all: -1, and a selection without the bar has nothing to measure.
        let none = object_reflection(&vec![0.0; W * H], &truth, &all);
        assert!((none.energy_error + 1.0).abs() < 1e-12);
        let right: Vec<usize> = all.iter().copied().filter(|&i| i % W >= 8).collect();
        assert!(object_reflection(&method, &truth, &right).energy_error.is_nan());
        // A dark object's reflection (negative) is measured the same way.
        let (dark, dark_truth) = {
            let (s, _) = synthetic_truth(0.04);
            let neg: Vec<f64> = s.iter().map(|v| -v).collect();
            let bare = vec![10.0; W * H];
            let with: Vec<f64> = neg.iter().zip(&bare).map(|(a, b)| a + b).collect();
            (neg, TruthReflection::new(W, &with, &bare, &vec![0.04; W * H], &[true; W * H]))
        };
        let half: Vec<f64> = dark.iter().map(|v| 0.5 * v).collect();
        assert!((object_reflection(&half, &dark_truth, &all).energy_error + 0.5).abs() < 1e-9);
    }

    /// A sea whose own sky term is 1.5 times the truth's, reflecting the objects in the same
    /// proportion: 50% too much energy, none relative to its sea; and a reflection of the truth's
    /// energy over that sea is a third short of it relative to its sea.
    #[test]
    fn the_energy_relative_to_its_sea_leaves_the_sea_s_own_error_out() {
        let (signal, truth) = synthetic_truth(0.04);
        let all: Vec<usize> = (0..W * H).collect();
        let bright_sea: Vec<f64> = truth.bare.iter().map(|b| 1.5 * b).collect();
        let scaled: Vec<f64> = signal.iter().map(|s| 1.5 * s).collect();
        let r = object_reflection(&scaled, &truth, &all);
        assert!(r.relative_energy_error.is_nan(), "not measured until asked");
        let r = r.relative_to_seas(&bright_sea, &truth, &all);
        assert!((r.energy_error - 0.5).abs() < 1e-9, "{}", r.energy_error);
        assert!(r.relative_energy_error.abs() < 1e-9, "{}", r.relative_energy_error);
        let same = object_reflection(&signal, &truth, &all).relative_to_seas(&bright_sea, &truth, &all);
        assert!(same.energy_error.abs() < 1e-9 && (same.relative_energy_error + 1.0 / 3.0).abs() < 1e-9);
        // Without resolved pixels there is nothing to measure.
        let right: Vec<usize> = all.iter().copied().filter(|&i| i % W >= 8).collect();
        let none = object_reflection(&signal, &truth, &right).relative_to_seas(&bright_sea, &truth, &right);
        assert!(none.relative_energy_error.is_nan());
    }

    #[test]
    fn the_objects_contrast_is_within_blocks_with_the_truths_noise_removed() {
        let all: Vec<usize> = (0..W * H).collect();
        // Without noise: the truth's own contrast is 1, a flattened or halved bar's less, a
        // doubled one's 2.
        let (signal, truth) = synthetic_truth(0.0);
        let r = object_reflection(&signal, &truth, &all);
        assert!((r.contrast.ratio - 1.0).abs() < 1e-12, "{:?}", r.contrast);
        // Columns 2..8 are in the first column of blocks, rows 4..12 in the first two rows.
        assert_eq!(r.contrast_blocks, 2);
        let flat: Vec<f64> = signal.iter().map(|&s| if s > 0.0 { 2.0 } else { 0.0 }).collect();
        let flat_ratio = object_reflection(&flat, &truth, &all).contrast.ratio;
        // The flattened bar keeps its edge against the sea around it within the blocks, not its
        // stripes: each block holds 12 pixels of 3, 12 of 1 and 40 of 0 (squares about the mean
        // 0.75: 84) in the truth, 24 of 2 and 40 of 0 (60) in the flattened bar.
        assert!((flat_ratio - (60.0f64 / 84.0).sqrt()).abs() < 1e-12, "{flat_ratio}");
        let halved: Vec<f64> = signal.iter().map(|s| 0.5 * s).collect();
        let halved_ratio = object_reflection(&halved, &truth, &all).contrast.ratio;
        assert!((halved_ratio - 0.5).abs() < 1e-12, "{halved_ratio}");
        let doubled: Vec<f64> = signal.iter().map(|s| 2.0 * s).collect();
        assert!((object_reflection(&doubled, &truth, &all).contrast.ratio - 2.0).abs() < 1e-12);
        // With noise in the truth: its own variance within the blocks less the pixels' noise is
        // the signal's, so the noiseless signal scores 1 against the noisy truth.
        let v: f64 = 0.25;
        let noisy: Vec<f64> = signal
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let (x, y) = (i % W, i / W);
                // +-sigma in a pattern uncorrelated with the bar's stripes (which run along x).
                s + if (y / 2 + x / 2) % 2 == 0 { v.sqrt() } else { -v.sqrt() }
            })
            .collect();
        let bare = vec![10.0; W * H];
        let with: Vec<f64> = noisy.iter().zip(&bare).map(|(a, b)| a + b).collect();
        let noisy_truth = TruthReflection::new(W, &with, &bare, &vec![v; W * H], &[true; W * H]);
        let c = object_reflection(&signal, &noisy_truth, &all).contrast;
        assert!(c.truth > r.contrast.truth, "the noise adds to the truth's spread");
        // Per block: squares 84 + 64 v about the mean over 63 degrees of freedom, less the noise's
        // (1 - 1/64) 64 v: (84 + v) / 63 against the method's 84 / 63 (without the noise removed
        // the ratio would be sqrt(84 / (84 + 64 v)) = 0.917).
        assert!((c.ratio - (84.0 / (84.0 + v)).sqrt()).abs() < 1e-12, "the noise removed: {c:?}");
        assert_eq!(meets(c.ratio - 1.0, CONTRAST_TARGET), Some(true));
        assert_eq!(meets(flat_ratio - 1.0, CONTRAST_TARGET), Some(true), "15% less: within 20%");
        assert_eq!(meets(halved_ratio - 1.0, CONTRAST_TARGET), Some(false));
    }

    /// Uniform numbers in [0, 1), reproducibly (xorshift64).
    fn uniform_numbers() -> impl FnMut() -> f64 {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    #[test]
    fn a_faint_reflection_is_measured_by_the_half_that_did_not_select_it() {
        // A faint darkening, -0.2 over every pixel, under noise of 0.9 a sample at 3x3 samples:
        // one block in a few rises over the bar. Selected by the values it sums, the truth's sum
        // keeps the noise that lifted those blocks, and a method exactly right reads low; selected
        // by one half and summed over the other, it reads right within its error.
        let (w, h, n, sigma) = (256usize, 128usize, 3u32, 0.9);
        let (n_a, n_b) = (5usize, 4usize);
        let mut uniform = uniform_numbers();
        // A sample's noise: uniform with the standard deviation sigma.
        let mut noise = move || (uniform() - 0.5) * sigma * 12f64.sqrt();
        let signal = vec![-0.2; w * h];
        let bare = vec![1.0; w * h];
        let (mut full, mut half) = (vec![], vec![]);
        for s in &signal {
            let a = (0..n_a).map(|_| s + noise()).sum::<f64>();
            let b = (0..n_b).map(|_| s + noise()).sum::<f64>();
            full.push(1.0 + (a + b) / (n * n) as f64);
            half.push(1.0 + a / n_a as f64);
        }
        let variance = vec![sigma * sigma / (n * n) as f64; w * h];
        let counted = vec![true; w * h];
        let by_itself = TruthReflection::new(w, &full, &bare, &variance, &counted);
        let by_halves =
            TruthReflection::new(w, &full, &bare, &variance, &counted).with_halves([&half, &bare], &bare, n, &counted);
        let all: Vec<usize> = (0..w * h).collect();
        let selected = object_reflection(&signal, &by_itself, &all);
        let split = object_reflection(&signal, &by_halves, &all);
        assert!(split.resolved_pixels > 40 * 16 && selected.resolved_pixels > 40 * 16, "{split:?} {selected:?}");
        assert!(selected.energy_error < -0.25, "the selection's noise inflates the truth: {selected:?}");
        assert!(split.energy_error.abs() < 3.0 * split.energy_uncertainty.max(0.02), "{split:?}");
    }

    #[test]
    fn the_halves_estimate_the_noise_of_the_truths_difference() {
        // Two truths of the same samples: the bare one sees x, the other x + o where o, the
        // object's part, is 1 in a random share of the samples. The difference's noise is o's
        // alone, var(o) / N^2, whatever x's; with N = 3 the halves are 5 and 4 samples.
        let mut uniform = uniform_numbers();
        let (n, pixels, share) = (3u32, 20000, 0.3);
        let (mut full, mut half) = ([vec![], vec![]], [vec![], vec![]]);
        for _ in 0..pixels {
            let samples: Vec<(f64, f64)> =
                (0..n * n).map(|_| (10.0 * uniform(), if uniform() < share { 1.0 } else { 0.0 })).collect();
            let n_a = (n * n).div_ceil(2) as usize;
            for (t, with) in [(0, 1.0), (1, 0.0)] {
                let value = |&(x, o): &(f64, f64)| x + with * o;
                full[t].push(samples.iter().map(value).sum::<f64>() / (n * n) as f64);
                half[t].push(samples[..n_a].iter().map(value).sum::<f64>() / n_a as f64);
            }
        }
        let noise = half_difference_noise([&full[0], &full[1]], [&half[0], &half[1]], n);
        let mean = noise.iter().sum::<f64>() / pixels as f64;
        let expected = share * (1.0 - share) / (n * n) as f64;
        assert!((mean / expected - 1.0).abs() < 0.05, "{mean} against {expected}");
        // Identical truths have no noise in their difference, however noisy each is.
        assert!(half_difference_noise([&full[1], &full[1]], [&half[1], &half[1]], n).iter().all(|&v| v == 0.0));
    }

    #[test]
    fn a_failed_method_is_a_row_of_its_own() {
        let dir = std::env::temp_dir().join(format!("ocean-reflections-test-{}", std::process::id()));
        let (signal, truth) = synthetic_truth(0.0);
        let all: Vec<usize> = (0..W * H).collect();
        let reflection = object_reflection(&signal, &truth, &all);
        let measured = Measured {
            gpu_ms: 1.0,
            all: TermErrors::default(),
            bands: (0..BANDS_M.len() - 1).map(|_| (1, TermErrors::default())).collect(),
            reflection,
            reflection_bands: vec![reflection; BANDS_M.len() - 1],
        };
        let rows = [
            Row { method: Reflections::Screen, outcome: Ok(measured) },
            Row { method: Reflections::Planar, outcome: Err("planar: not \"yet\", sorry".into()) },
        ];
        let info = TruthInfo {
            reference: Path::new("ref.exr"),
            bare_reference: Path::new("bare.exr"),
            sampling: "synthetic".into(),
            size: (W, H),
            halves: true,
            sea_pixels: W * H,
            object_pixels: 0,
        };
        write_outputs(&rows, &dir, "synthetic", &info, 1).unwrap();
        let csv = std::fs::read_to_string(dir.join("reflections.csv")).unwrap();
        let width = csv.lines().next().unwrap().split(',').count();
        assert_eq!(csv.lines().count(), 1 + BANDS_M.len() + 1, "{csv}");
        for line in csv.lines().filter(|l| !l.contains("failed")) {
            assert_eq!(line.split(',').count(), width, "{line}");
        }
        assert!(csv.contains("planar,failed,") && csv.contains("\"planar: not \"\"yet\"\", sorry\""), "{csv}");
        let md = std::fs::read_to_string(dir.join("reflections.md")).unwrap();
        assert!(md.contains("| planar | failed: planar") && md.contains("| screen |"), "{md}");
        assert!(summary(&rows[1]).contains("failed"));
        assert!(summary(&rows[0]).contains("pass"), "{}", summary(&rows[0]));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
