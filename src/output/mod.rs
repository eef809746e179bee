//! What the program hands the user: image files (PNG of the tone-mapped frame, linear EXR of the
//! radiance), text (JSON, CSV, markdown), plots, progress and status lines, and image
//! statistics, and timelines as Chrome Trace Event JSON (`trace`). Every output is encoded in memory and written through `target`, which knows a
//! regular file from a device, a pipe, a symlink or standard output.

pub mod plot;
pub mod progress;
pub mod target;
pub mod trace;

use crate::error::{Error, Result};
use std::io::Cursor;
use std::path::Path;

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ImageStats {
    pub nonfinite_pixels: u64,
    pub mean_radiance: [f64; 3],
}

/// Prints a status line to standard output, or to standard error once an output file took
/// standard output (`--out -`). A closed pipe (`ocean ... | head`) is not an error worth a
/// panic, so failures to print a status line are ignored.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if $crate::output::target::stdout_taken() {
            let _ = writeln!(std::io::stderr(), $($arg)*);
        } else {
            let _ = writeln!(std::io::stdout(), $($arg)*);
        }
    }};
}

/// Rec. 709 luminance of linear RGB (the alpha is ignored).
pub fn luminance(p: [f32; 4]) -> f64 {
    luminance_rgb([p[0] as f64, p[1] as f64, p[2] as f64])
}

/// Rec. 709 luminance of linear RGB in f64.
pub fn luminance_rgb(c: [f64; 3]) -> f64 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

pub fn stats(hdr: &[[f32; 4]]) -> ImageStats {
    let mut nonfinite = 0;
    let mut sum = [0.0f64; 3];
    let mut finite = 0u64;
    for p in hdr {
        if p[..3].iter().all(|c| c.is_finite()) {
            finite += 1;
            for c in 0..3 {
                sum[c] += p[c] as f64;
            }
        } else {
            nonfinite += 1;
        }
    }
    let n = finite.max(1) as f64;
    ImageStats { nonfinite_pixels: nonfinite, mean_radiance: sum.map(|s| s / n) }
}

/// Encodes an image in memory (the EXR encoder needs to seek) and writes it to `path`.
fn write_image(path: &Path, image: image::DynamicImage, format: image::ImageFormat) -> Result<()> {
    let mut bytes = Cursor::new(Vec::new());
    image.write_to(&mut bytes, format).map_err(|e| Error::io(path, e))?;
    target::write(path, bytes.get_ref())
}

/// The tone mapping of glsl/tone.glsl on the CPU, then sRGB, as RGBA8: the scene's curve and
/// exposure (automatic: from the log-average luminance of every 4th pixel of every 4th row, as
/// glsl/exposure.comp).
pub fn tonemap(hdr: &[[f32; 4]], width: u32, render: &crate::model::scene::Render) -> Vec<u8> {
    use crate::model::scene::{ev100_to_exposure, Exposure, ToneCurve};
    let exposure = match render.exposure() {
        Exposure::PerKcd(e) => e,
        Exposure::Auto => {
            let w = width.max(1) as usize;
            let logs: Vec<f64> = hdr
                .iter()
                .enumerate()
                .filter(|(i, _)| (i % w) % 4 == 0 && (i / w) % 4 == 0)
                .map(|(_, p)| (1000.0 * luminance(*p)).max(1e-3).log2())
                .collect();
            let key = logs.iter().sum::<f64>() / logs.len().max(1) as f64;
            ev100_to_exposure(key + (100.0f64 / 12.5).log2())
        }
    };
    let encode = |c: f64| {
        let c = c.clamp(0.0, 1.0);
        let s = if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
        (s * 255.0).round() as u8
    };
    hdr.iter()
        .flat_map(|p| {
            let x = [0, 1, 2].map(|c| exposure * p[c].max(0.0) as f64);
            let mapped = match render.tone_curve {
                ToneCurve::Exponential => x.map(|v| 1.0 - (-v).exp()),
                ToneCurve::Filmic => filmic_curve(x),
            };
            [encode(mapped[0]), encode(mapped[1]), encode(mapped[2]), 255]
        })
        .collect()
}

/// glsl/tone.glsl's filmic_curve: Narkowicz (2015)'s ACES fit on luminance, hue kept, the colour
/// moved towards its grey only as far as its brightest channel needs.
pub fn filmic_curve(x: [f64; 3]) -> [f64; 3] {
    let y = luminance_rgb(x);
    if y.is_nan() || y <= 0.0 {
        return [0.0; 3];
    }
    let yt = (y * (2.51 * y + 0.03) / (y * (2.43 * y + 0.59) + 0.14)).clamp(0.0, 1.0);
    let mut c = x.map(|v| v * yt / y);
    let peak = c[0].max(c[1]).max(c[2]);
    if peak > 1.0 {
        c = c.map(|v| yt + (v - yt) * (1.0 - yt) / (peak - yt));
    }
    c.map(|v| v.clamp(0.0, 1.0))
}

/// RGBA8 pixels as a PNG file's bytes (alpha dropped, as `write_png` writes them).
pub fn encode_png(width: u32, height: u32, rgba8: &[u8]) -> Result<Vec<u8>> {
    let rgb: Vec<u8> = rgba8.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let buffer = image::RgbImage::from_raw(width, height, rgb).expect("width * height pixels");
    let mut bytes = Cursor::new(Vec::new());
    image::DynamicImage::ImageRgb8(buffer)
        .write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Error::io(Path::new("PNG encoder"), e))?;
    Ok(bytes.into_inner())
}

pub fn write_png(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    let rgb: Vec<u8> = rgba8.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    let buffer = image::RgbImage::from_raw(width, height, rgb).expect("width * height pixels");
    write_image(path, image::DynamicImage::ImageRgb8(buffer), image::ImageFormat::Png)
}

/// Linear RGBA as OpenEXR (f32), alpha carried as given (the ground truth's resolved mask).
pub fn write_exr_rgba(path: &Path, width: u32, height: u32, rgba: &[[f32; 4]]) -> Result<()> {
    let data: Vec<f32> = rgba.iter().flatten().copied().collect();
    let buffer = image::Rgba32FImage::from_raw(width, height, data).expect("width * height pixels");
    write_image(path, image::DynamicImage::ImageRgba32F(buffer), image::ImageFormat::OpenExr)
}

/// Reads an OpenEXR written by `write_exr` or `write_exr_rgba` (alpha 1 when absent).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>)> {
    let image = image::open(path).map_err(|e| Error::io(path, e))?.into_rgba32f();
    let (w, h) = image.dimensions();
    Ok((w, h, image.pixels().map(|p| p.0).collect()))
}

pub fn write_exr(path: &Path, width: u32, height: u32, hdr: &[[f32; 4]]) -> Result<()> {
    let rgb: Vec<f32> = hdr.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let buffer = image::Rgb32FImage::from_raw(width, height, rgb).expect("width * height pixels");
    write_image(path, image::DynamicImage::ImageRgb32F(buffer), image::ImageFormat::OpenExr)
}

pub fn write_text(path: &Path, text: &str) -> Result<()> {
    target::write(path, text.as_bytes())
}
