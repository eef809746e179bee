//! The detail columns and tables of `bench error-vs-time`: each method's local contrast and glitter
//! against the ground truth's (measure::detail), over the whole sea and per distance band. The
//! ground truth's side (its contrast, its noise, the sun's path) is computed once for all rows.

use crate::error::{Error, Result};
use crate::measure::bench::error_vs_time::{band_label, csv_value, Row, BANDS_M, TERMS};
use crate::measure::detail::{self, Contrast, GlitterComparison, MIN_BAND_PATH_PIXELS};
use crate::measure::groundtruth::GroundTruthFiles;
use crate::output::luminance;
use crate::output::plot::three_digits;
use std::fmt::Write as _;

const SUN: usize = 1;

/// A method's detail over one selection of the sea (the whole sea, or a band).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Detail {
    /// Pixels with a whole 3x3 neighbourhood on the sea, which the contrast is measured over.
    pub contrast_pixels: usize,
    /// Per term: total, sun, sky, sea.
    pub contrast: [Contrast; 4],
    /// Over the sun's path in the selection.
    pub glitter: GlitterComparison,
}

/// The ground truth's side of one selection.
struct Selection {
    contrast_pixels: Vec<usize>,
    path_pixels: Vec<usize>,
    min_path_pixels: usize,
    /// Per term, the variance of the truth's high pass and its sampling noise's part of it.
    variance: [f64; 4],
    noise: [f64; 4],
}

/// What the detail statistics read of a ground truth.
pub struct TruthImages<'a> {
    pub width: usize,
    pub height: usize,
    /// Total, sun, sky, sea.
    pub terms: [&'a [[f32; 4]]; 4],
    /// Each pixel's variance of its mean luminance, per term.
    pub variance: &'a [[f32; 4]],
    /// Each pixel's luminance from half the samples, per term, where the truth has it.
    pub half: Option<&'a [[f32; 4]]>,
}

impl<'a> TruthImages<'a> {
    pub fn of(files: &'a GroundTruthFiles) -> Self {
        // The images are the region the truth traced (the whole view by default).
        let region = files.meta.region();
        TruthImages {
            width: region.width as usize,
            height: region.height as usize,
            terms: [&files.total, &files.sun, &files.sky, &files.sea],
            variance: &files.variance,
            half: files.half.as_deref(),
        }
    }
}

/// The ground truth's luminance, the sun's path and its contrast per selection, for every row.
pub struct TruthDetail {
    width: usize,
    luminance: [Vec<f64>; 4],
    sun_variance: Vec<f64>,
    /// The whole sea, then each distance band.
    selections: Vec<Selection>,
    /// Whether its noise came from an independent half-estimate (else from pixel variances).
    pub from_halves: bool,
    pub path_pixels: usize,
}

impl TruthDetail {
    /// `sea`: the sea's pixels; `bands`: by distance band; `on_sea`: the mask of both.
    pub fn new(truth: &TruthImages, on_sea: &[bool], sea: &[usize], bands: &[Vec<usize>]) -> Result<Self> {
        let (w, h) = (truth.width, truth.height);
        let luminance = truth.terms.map(|image| image.iter().map(|&p| luminance(p)).collect::<Vec<f64>>());
        let pixel_variance = |t: usize| truth.variance.iter().map(|v| v[t] as f64).collect::<Vec<f64>>();
        let half = match truth.half {
            Some(half) if half.len() != w * h => {
                return Err(Error::Argument(format!(
                    "the ground truth's half-estimate has {} pixels, its images {}",
                    half.len(),
                    w * h
                )))
            }
            Some(half) => Some([0, 1, 2, 3].map(|t| half.iter().map(|p| p[t] as f64).collect::<Vec<f64>>())),
            None => None,
        };
        let neighbourhood = detail::whole_neighbourhood(on_sea, w, h);
        let path = detail::sun_path(&luminance[SUN], on_sea, w, h);
        let variances = [0, 1, 2, 3].map(pixel_variance);
        let selections = std::iter::once((sea, 1))
            .chain(bands.iter().map(|b| (b.as_slice(), MIN_BAND_PATH_PIXELS)))
            .map(|(pixels, min_path_pixels)| {
                let contrast_pixels: Vec<usize> = pixels.iter().copied().filter(|&i| neighbourhood[i]).collect();
                let noise = [0, 1, 2, 3].map(|t| match &half {
                    Some(half) => detail::half_noise_variance(&luminance[t], &half[t], w, &contrast_pixels),
                    None => detail::pixel_noise_variance(&variances[t], w, &contrast_pixels),
                });
                Selection {
                    variance: [0, 1, 2, 3].map(|t| detail::contrast_variance(&luminance[t], w, &contrast_pixels)),
                    noise,
                    path_pixels: pixels.iter().copied().filter(|&i| path[i]).collect(),
                    contrast_pixels,
                    min_path_pixels,
                }
            })
            .collect();
        let [_, sun_variance, _, _] = variances;
        let path_pixels = path.iter().filter(|&&p| p).count();
        Ok(TruthDetail { width: w, luminance, sun_variance, selections, from_halves: half.is_some(), path_pixels })
    }

    /// The detail of a method's images (total, sun, sky, sea): the whole sea, then each band.
    pub fn of(&self, images: &[Vec<[f32; 4]>; 4]) -> (Detail, Vec<Detail>) {
        let method = images.each_ref().map(|image| image.iter().map(|&p| luminance(p)).collect::<Vec<f64>>());
        let mut all = self.selections.iter().map(|s| Detail {
            contrast_pixels: s.contrast_pixels.len(),
            contrast: [0, 1, 2, 3].map(|t| {
                let method_variance = detail::contrast_variance(&method[t], self.width, &s.contrast_pixels);
                Contrast::new(method_variance, s.variance[t], s.noise[t])
            }),
            glitter: detail::compare_glitter(
                &method[SUN],
                &self.luminance[SUN],
                &self.sun_variance,
                &s.path_pixels,
                s.min_path_pixels,
            ),
        });
        let whole = all.next().expect("the whole sea is the first selection");
        (whole, all.collect())
    }

    /// Which estimate of its own noise the truth's contrast was corrected with, in words.
    pub fn noise_estimate(&self) -> &'static str {
        if self.from_halves {
            "its noise from an independent half-estimate: var(hp(A - B)) / 4"
        } else {
            "its noise from each pixel's variance, pixels assumed independent: this ground truth has no \
             half-estimate"
        }
    }
}

pub fn detail_columns() -> String {
    let contrast: String = TERMS
        .iter()
        .map(|t| format!(",contrast_{t},contrast_truth_{t},contrast_truth_signal_{t},contrast_ratio_{t}"))
        .collect();
    format!(
        ",contrast_pixels{contrast},glitter_pixels,glitter_mean,glitter_var,glitter_bright_share,glitter_truth_mean,\
         glitter_truth_var,glitter_truth_bright_share,glitter_var_ratio,glitter_bright_share_ratio"
    )
}

pub fn detail_values(d: &Detail) -> String {
    let mut out = format!(",{}", d.contrast_pixels);
    for c in &d.contrast {
        for v in [c.method, c.truth, c.truth_signal, c.ratio] {
            write!(out, ",{}", csv_value(v)).unwrap();
        }
    }
    let g = &d.glitter;
    write!(out, ",{}", g.method.pixels).unwrap();
    for v in [
        g.method.mean,
        g.method.var,
        g.method.bright_share,
        g.truth.mean,
        g.truth.var,
        g.truth.bright_share,
        g.var_ratio,
        g.bright_share_ratio,
    ] {
        write!(out, ",{}", csv_value(v)).unwrap();
    }
    out
}

/// A table cell: the value to three digits, or a dash where there is none.
fn cell(v: f64) -> String {
    match v {
        0.0 => "0".to_owned(),
        v if v.is_finite() => three_digits(v),
        _ => "—".to_owned(),
    }
}

/// One table row: its two leading cells, then a cell for the whole sea and each band.
fn table_row(md: &mut String, first: &str, second: &str, whole: String, bands: impl Iterator<Item = String>) {
    let bands: Vec<String> = bands.collect();
    writeln!(md, "| {first} | {second} | {whole} | {} |", bands.join(" | ")).unwrap();
}

fn table_head(md: &mut String, first: &str, whole: &str) {
    let bands: Vec<String> = (0..BANDS_M.len() - 1).map(band_label).collect();
    writeln!(md, "| {first} | method | {whole} | {} m |", bands.join(" m | ")).unwrap();
    writeln!(md, "|---|---|---|{}", "---|".repeat(bands.len())).unwrap();
}

/// "Detail a pixel can see": the contrast ratios and the glitter of each method's default setting.
pub fn markdown(rows: &[Row], truth: &TruthDetail) -> String {
    let defaults: Vec<&Row> = rows.iter().filter(|r| r.setting == "default").collect();
    let Some(first) = defaults.first() else { return String::new() };
    let mut md = format!(
        "\n## Detail a pixel can see\n\n\
         Local contrast: the standard deviation of the pixel-scale high pass (luminance less its 3x3 mean) over \
         the sea pixels whose whole 3x3 neighbourhood sees the sea, of each method's default setting over the \
         ground truth's with its own sampling noise removed ({}). 1 keeps the truth's detail; below 1 smooths \
         it away, above 1 adds some (aliasing or noise). The ground truth's rows give its standard deviation \
         without noise and, in brackets, as sampled (kcd/m²).\n\n",
        truth.noise_estimate()
    );
    table_head(&mut md, "term", "whole sea");
    for (t, name) in [(1, "reflected sun"), (2, "reflected sky"), (3, "refracted sea")] {
        let truth_cell = |d: &Detail| format!("{} ({})", cell(d.contrast[t].truth_signal), cell(d.contrast[t].truth));
        table_row(&mut md, name, "ground truth", truth_cell(&first.detail), first.detail_bands.iter().map(truth_cell));
        for r in &defaults {
            let ratio = |d: &Detail| cell(d.contrast[t].ratio);
            table_row(&mut md, "", &r.method, ratio(&r.detail), r.detail_bands.iter().map(ratio));
        }
    }
    write!(
        md,
        "\n### Glitter (reflected sun)\n\n\
         The sun's path: the {} sea pixels where the ground truth's sun luminance, averaged over the sea pixels \
         of a 9x9 box, is at least 10% of its maximum. Over it: the variance of the pixels' sun luminance, and \
         the share of pixels brighter than 4x the path's mean (the glints), each method's over the ground \
         truth's (its variance less its own sampling noise). Bands with fewer than {MIN_BAND_PATH_PIXELS} \
         path pixels are left out.\n\n",
        truth.path_pixels
    )
    .unwrap();
    table_head(&mut md, "quantity", "whole path");
    let pixels = |d: &Detail| d.glitter.method.pixels.to_string();
    table_row(&mut md, "path pixels", "", pixels(&first.detail), first.detail_bands.iter().map(pixels));
    type Field = fn(&GlitterComparison) -> f64;
    let quantities: [(&str, Field, Field); 2] = [
        ("variance", |g| g.truth.var, |g| g.var_ratio),
        ("bright share", |g| g.truth.bright_share, |g| g.bright_share_ratio),
    ];
    for (name, of_truth, ratio) in quantities {
        let truth_cell = |d: &Detail| cell(of_truth(&d.glitter));
        let head = format!("{name} (truth; ratios below)");
        table_row(&mut md, &head, "ground truth", truth_cell(&first.detail), first.detail_bands.iter().map(truth_cell));
        for r in &defaults {
            let ratio_cell = |d: &Detail| cell(ratio(&d.glitter));
            table_row(&mut md, "", &r.method, ratio_cell(&r.detail), r.detail_bands.iter().map(ratio_cell));
        }
    }
    md
}
