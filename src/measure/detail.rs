//! Detail statistics for comparing a method's image with the ground truth beyond mean energy: the
//! pixel-scale local contrast (does a method keep, smooth away or alias the detail a pixel can
//! see?) and the glitter of the reflected sun (the spread and the bright outliers of the sun's
//! path). The ground truth is a Monte Carlo estimate whose own noise adds contrast and variance, so
//! both are also given with that noise removed.
//!
//! Images are row-major slices of luminance (f64), `w` pixels wide; selections are pixel indices.

/// Pixels the glitter statistics need in a distance band before they mean anything.
pub const MIN_BAND_PATH_PIXELS: usize = 20;
/// Half-side of the box that smooths the sun's path out of the glints (a 9x9 box).
const PATH_BOX_RADIUS: usize = 4;
/// The path: where the smoothed sun is at least this share of its maximum over the sea.
const PATH_THRESHOLD: f64 = 0.1;
/// A glint is a path pixel brighter than this many times the path's mean.
const BRIGHT_OVER_MEAN: f64 = 4.0;

/// The pixels of a `w` x `h` image whose whole 3x3 neighbourhood lies inside it and on the sea:
/// only there does the high pass compare sea with sea (not with sky, or with nothing at the edge).
pub fn whole_neighbourhood(on_sea: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut inside = vec![false; w * h];
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let i = y * w + x;
            inside[i] = (0..9).all(|k| on_sea[i + k % 3 + (k / 3) * w - 1 - w]);
        }
    }
    inside
}

/// The pixel-scale high pass: luminance minus its 3x3 mean (itself included). `i` must have a
/// whole 3x3 neighbourhood in the image (`whole_neighbourhood`).
pub fn high_pass(lum: &[f64], w: usize, i: usize) -> f64 {
    let mean = (0..9).map(|k| lum[i + k % 3 + (k / 3) * w - 1 - w]).sum::<f64>() / 9.0;
    lum[i] - mean
}

/// `v`, or 0 where it is negative: a variance less an estimate of its noise. NaN (nothing
/// measured) stays NaN, where `f64::max` would make it 0.
fn floor_at_zero(v: f64) -> f64 {
    if v < 0.0 {
        0.0
    } else {
        v
    }
}

/// Mean and population variance of `values` (NaN for none).
fn mean_variance(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (mean, values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n)
}

/// The variance over `select` of the high pass of `lum`: the local contrast, squared.
pub fn contrast_variance(lum: &[f64], w: usize, select: &[usize]) -> f64 {
    let hp: Vec<f64> = select.iter().map(|&i| high_pass(lum, w, i)).collect();
    mean_variance(&hp).1
}

/// The part of the contrast variance of the full estimate `full` (mean of halves A and B) that is
/// its sampling noise, from the half-estimate A (`half`): B = 2F - A, the high pass is linear and
/// A - B holds no signal, only noise of twice F's variance in each half: var(hp(A - B)) / 4.
pub fn half_noise_variance(full: &[f64], half: &[f64], w: usize, select: &[usize]) -> f64 {
    let difference: Vec<f64> = full.iter().zip(half).map(|(f, a)| a - (2.0 * f - a)).collect();
    contrast_variance(&difference, w, select) / 4.0
}

/// The same from each pixel's variance `variance` of its mean, where there is no half-estimate,
/// assuming pixels' noises independent: hp = (8/9) L - (1/9) (sum of the 8 neighbours), so its
/// noise variance is (8/9)^2 v + (1/9)^2 (sum of the neighbours' v), averaged over `select`.
pub fn pixel_noise_variance(variance: &[f64], w: usize, select: &[usize]) -> f64 {
    let per_pixel = |i: usize| {
        let neighbours = (0..9).map(|k| variance[i + k % 3 + (k / 3) * w - 1 - w]).sum::<f64>() - variance[i];
        (64.0 * variance[i] + neighbours) / 81.0
    };
    select.iter().map(|&i| per_pixel(i)).sum::<f64>() / select.len() as f64
}

/// Local contrast (standard deviation of the high pass) of a method and of the ground truth, raw
/// and with its sampling noise removed; `ratio` is the method's over the latter (NaN where the
/// truth has no signal contrast): 1 keeps the truth's detail, below smooths it, above adds some.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Contrast {
    pub method: f64,
    pub truth: f64,
    pub truth_signal: f64,
    pub ratio: f64,
}

impl Contrast {
    /// From the variances of the high passes and the truth's noise part of its own.
    pub fn new(method_variance: f64, truth_variance: f64, truth_noise_variance: f64) -> Contrast {
        let truth_signal = floor_at_zero(truth_variance - truth_noise_variance).sqrt();
        let method = method_variance.sqrt();
        let ratio = if truth_signal > 0.0 { method / truth_signal } else { f64::NAN };
        Contrast { method, truth: truth_variance.sqrt(), truth_signal, ratio }
    }
}

/// The mean of `lum` over the sea pixels of the (2r+1)^2 box around each sea pixel, clipped at the
/// image's edges (0 off the sea): the sun's path without its glints, and without the sky's light
/// bleeding in at the horizon.
pub fn sea_box_mean(lum: &[f64], on_sea: &[bool], w: usize, h: usize, r: usize) -> Vec<f64> {
    let mut out = vec![0.0; w * h];
    for y in 0..h {
        for x in 0..w {
            if !on_sea[y * w + x] {
                continue;
            }
            let (mut sum, mut n) = (0.0, 0usize);
            for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                for i in yy * w + x.saturating_sub(r)..yy * w + (x + r + 1).min(w) {
                    if on_sea[i] {
                        sum += lum[i];
                        n += 1;
                    }
                }
            }
            out[y * w + x] = sum / n as f64; // n >= 1: the pixel itself
        }
    }
    out
}

/// The sun's path: sea pixels where the ground truth's sun luminance `sun`, smoothed over 9x9
/// boxes (`sea_box_mean`), is at least a tenth of its maximum over the sea; none where the sea
/// reflects no sun. The glints live there, so their statistics are not diluted by dark sea.
pub fn sun_path(sun: &[f64], on_sea: &[bool], w: usize, h: usize) -> Vec<bool> {
    let smooth = sea_box_mean(sun, on_sea, w, h, PATH_BOX_RADIUS);
    let max = (0..w * h).filter(|&i| on_sea[i]).map(|i| smooth[i]).fold(0.0, f64::max);
    (0..w * h).map(|i| on_sea[i] && max > 0.0 && smooth[i] >= PATH_THRESHOLD * max).collect()
}

/// Glitter over a set of path pixels: how many, the mean luminance, its variance over the pixels,
/// and the share brighter than 4x the mean (the glints).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Glitter {
    pub pixels: usize,
    pub mean: f64,
    pub var: f64,
    pub bright_share: f64,
}

/// The glitter of `lum` over `select`, less `noise_variance` (the mean variance of the pixels'
/// own estimates: 0 for a rendered image) from its variance, floored at 0: a Monte Carlo truth's
/// noise spreads its pixels without being glitter.
pub fn glitter(lum: &[f64], select: &[usize], noise_variance: f64) -> Glitter {
    let values: Vec<f64> = select.iter().map(|&i| lum[i]).collect();
    let (mean, var) = mean_variance(&values);
    let bright = values.iter().filter(|&&v| v > BRIGHT_OVER_MEAN * mean).count();
    Glitter {
        pixels: values.len(),
        mean,
        var: floor_at_zero(var - noise_variance),
        bright_share: bright as f64 / values.len() as f64,
    }
}

/// A method's glitter against the truth's over the same pixels, with the ratios method / truth
/// (NaN where the truth has none, or where there are fewer than `min_pixels`).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct GlitterComparison {
    pub method: Glitter,
    pub truth: Glitter,
    pub var_ratio: f64,
    pub bright_share_ratio: f64,
}

/// `method` and `truth` sun luminance over `select`; `truth_variance`: each pixel's variance of
/// the truth's mean (its noise, removed from its variance).
pub fn compare_glitter(
    method: &[f64],
    truth: &[f64],
    truth_variance: &[f64],
    select: &[usize],
    min_pixels: usize,
) -> GlitterComparison {
    let none = Glitter { pixels: select.len(), mean: f64::NAN, var: f64::NAN, bright_share: f64::NAN };
    if select.len() < min_pixels.max(1) {
        return GlitterComparison { method: none, truth: none, var_ratio: f64::NAN, bright_share_ratio: f64::NAN };
    }
    let noise = select.iter().map(|&i| truth_variance[i]).sum::<f64>() / select.len() as f64;
    let (m, t) = (glitter(method, select, 0.0), glitter(truth, select, noise));
    let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { f64::NAN };
    GlitterComparison {
        method: m,
        truth: t,
        var_ratio: ratio(m.var, t.var),
        bright_share_ratio: ratio(m.bright_share, t.bright_share),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: usize = 200;
    const H: usize = 200;

    fn all_sea() -> Vec<bool> {
        vec![true; W * H]
    }

    fn interior() -> Vec<usize> {
        let inside = whole_neighbourhood(&all_sea(), W, H);
        (0..W * H).filter(|&i| inside[i]).collect()
    }

    /// A tiny LCG (Numerical Recipes' constants): uniform noise of unit variance, seeded.
    struct Lcg(u64);

    impl Lcg {
        fn unit(&mut self) -> f64 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (self.0 >> 11) as f64 / (1u64 << 53) as f64;
            (2.0 * u - 1.0) * 3f64.sqrt()
        }
    }

    #[test]
    fn the_neighbourhood_excludes_edges_and_pixels_next_to_the_sky() {
        let mut on_sea = vec![true; 25];
        on_sea[0] = false; // (0, 0): its neighbour (1, 1) loses its whole neighbourhood
        let inside = whole_neighbourhood(&on_sea, 5, 5);
        // The 3x3 interior less (1, 1) = 6, which touches the sky at (0, 0).
        assert_eq!((0..25).filter(|&i| inside[i]).collect::<Vec<_>>(), [7, 8, 11, 12, 13, 16, 17, 18]);
    }

    #[test]
    fn a_flat_image_has_no_detail_contrast() {
        let flat = vec![3.5; W * H];
        assert_eq!(contrast_variance(&flat, W, &interior()), 0.0);
    }

    #[test]
    fn a_checkerboard_has_its_analytic_contrast() {
        // At a +a pixel the 3x3 holds itself and the 4 diagonals (+a) and the 4 edge neighbours
        // (-a): mean a/9, hp = 8a/9; at a -a pixel -8a/9. So the std is 8a/9.
        let a = 2.0;
        let board: Vec<f64> = (0..W * H).map(|i| if (i % W + i / W) % 2 == 0 { a } else { -a }).collect();
        let std = contrast_variance(&board, W, &interior()).sqrt();
        assert!((std - 8.0 * a / 9.0).abs() < 1e-12, "{std}");
    }

    #[test]
    fn pixel_noise_of_uniform_variance_is_eight_ninths_of_it() {
        // (8/9)^2 v + 8 (1/9)^2 v = 72/81 v; and pure noise of variance v shows that contrast.
        let v = 0.25;
        let select = interior();
        let predicted = pixel_noise_variance(&vec![v; W * H], W, &select);
        assert!((predicted - 8.0 * v / 9.0).abs() < 1e-12, "{predicted}");
        let mut rng = Lcg(7);
        let noise: Vec<f64> = (0..W * H).map(|_| v.sqrt() * rng.unit()).collect();
        let measured = contrast_variance(&noise, W, &select);
        assert!((measured / predicted - 1.0).abs() < 0.03, "{measured} against {predicted}");
    }

    #[test]
    fn noise_removal_recovers_the_signal_contrast() {
        // A smooth signal with pixel-scale detail, and two independent half-estimates of it each
        // with noise of variance 2 sigma^2, so that F = (A + B) / 2 has sigma^2.
        let signal: Vec<f64> = (0..W * H)
            .map(|i| {
                let (x, y) = ((i % W) as f64, (i / W) as f64);
                10.0 + (0.9 * x).sin() * (0.7 * y).cos() + 0.5 * (0.05 * x + 0.03 * y).sin()
            })
            .collect();
        let select = interior();
        let truth = contrast_variance(&signal, W, &select).sqrt();
        let sigma = 0.2;
        let mut rng = Lcg(12345);
        let half = |rng: &mut Lcg| -> Vec<f64> {
            signal.iter().map(|s| s + 2f64.sqrt() * sigma * rng.unit()).collect::<Vec<f64>>()
        };
        let (a, b) = (half(&mut rng), half(&mut rng));
        let full: Vec<f64> = a.iter().zip(&b).map(|(a, b)| (a + b) / 2.0).collect();
        let raw = contrast_variance(&full, W, &select);
        assert!(raw.sqrt() / truth > 1.1, "the noise adds contrast: raw {} against {truth}", raw.sqrt());
        let from_halves = Contrast::new(0.0, raw, half_noise_variance(&full, &a, W, &select)).truth_signal;
        assert!((from_halves / truth - 1.0).abs() < 0.03, "from halves {from_halves} against {truth}");
        let from_pixels =
            Contrast::new(0.0, raw, pixel_noise_variance(&vec![sigma * sigma; W * H], W, &select)).truth_signal;
        assert!((from_pixels / truth - 1.0).abs() < 0.03, "from pixel variances {from_pixels} against {truth}");
    }

    #[test]
    fn the_ratio_compares_with_the_signal_and_is_nan_without_one() {
        let c = Contrast::new(1.0, 5.0, 1.0);
        assert_eq!((c.method, c.truth_signal, c.ratio), (1.0, 2.0, 0.5));
        assert!((c.truth - 5f64.sqrt()).abs() < 1e-15);
        assert!(Contrast::new(1.0, 1.0, 2.0).ratio.is_nan(), "noise above the raw variance: no signal");
        let nothing = Contrast::new(f64::NAN, f64::NAN, f64::NAN);
        assert!(nothing.truth_signal.is_nan() && nothing.ratio.is_nan(), "no pixels: nothing measured, not 0");
    }

    #[test]
    fn a_constant_path_has_no_glitter() {
        let lum = vec![2.0; 100];
        let g = glitter(&lum, &(0..100).collect::<Vec<_>>(), 0.0);
        assert_eq!((g.pixels, g.mean, g.var, g.bright_share), (100, 2.0, 0.0, 0.0));
    }

    #[test]
    fn five_percent_of_glints_ten_times_as_bright_are_a_five_percent_share() {
        // Mean (95 + 5 * 10) / 100 = 1.45: the glints are above 4x it, the rest below.
        let lum: Vec<f64> = (0..100).map(|i| if i % 20 == 0 { 10.0 } else { 1.0 }).collect();
        let select: Vec<usize> = (0..100).collect();
        let g = glitter(&lum, &select, 0.0);
        assert!((g.bright_share - 0.05).abs() < 1e-12, "{}", g.bright_share);
        assert!((g.var - (0.05 * 8.55f64.powi(2) + 0.95 * 0.45f64.powi(2))).abs() < 1e-12, "{}", g.var);
        // The truth's noise comes off its variance; the method's 2 glints are 2/5 of its share.
        let method: Vec<f64> = (0..100).map(|i| if i % 50 == 0 { 10.0 } else { 1.0 }).collect();
        let c = compare_glitter(&method, &lum, &vec![0.5; 100], &select, MIN_BAND_PATH_PIXELS);
        assert!((c.truth.var - (g.var - 0.5)).abs() < 1e-12, "{}", c.truth.var);
        assert!((c.bright_share_ratio - 0.4).abs() < 1e-12, "{}", c.bright_share_ratio);
        let few = compare_glitter(&method, &lum, &vec![0.5; 100], &select[..19], MIN_BAND_PATH_PIXELS);
        assert!(few.var_ratio.is_nan() && few.bright_share_ratio.is_nan(), "19 pixels are too few");
    }

    #[test]
    fn the_path_follows_the_smoothed_sun_on_the_sea_only() {
        // A column of glints at x = 10 on a 21 x 5 sea; the top row is sky, brighter than any glint.
        let (w, h) = (21, 5);
        let on_sea: Vec<bool> = (0..w * h).map(|i| i >= w).collect();
        let sun: Vec<f64> = (0..w * h)
            .map(|i| match (i < w, i % w == 10) {
                (true, _) => 1e3,
                (false, true) => 1.0,
                (false, false) => 0.0,
            })
            .collect();
        let path = sun_path(&sun, &on_sea, w, h);
        let columns: Vec<usize> = (w..w * h).filter(|&i| path[i]).map(|i| i % w).collect();
        assert!(columns.iter().all(|&x| (6..=14).contains(&x)), "within the box of the glints: {columns:?}");
        assert_eq!(columns.len(), 4 * 9, "the 9 columns the box reaches, on every sea row");
        assert!(!path[..w].iter().any(|&p| p), "the sky is never on the path");
        assert!(!sun_path(&vec![0.0; w * h], &on_sea, w, h).iter().any(|&p| p), "no sun, no path");
    }
}
