//! Image files and image statistics: PNG of the tone-mapped frame, linear EXR of the radiance,
//! non-finite counts and mean radiance. Files are written under a temporary name and renamed,
//! so an interrupted run never leaves a half-written file under the final name.

use crate::error::{Error, Result};
use std::path::Path;

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ImageStats {
    pub nonfinite_pixels: u64,
    pub mean_radiance: [f64; 3],
}

/// Prints a line to standard output; a closed pipe (`ocean ... | head`) is not an error worth a
/// panic, so write failures are ignored.
#[macro_export]
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
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

fn io_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Io { path: path.to_owned(), message: e.to_string() }
}

/// Writes through `<path>.partial` then renames over `path`.
fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let mut partial = path.as_os_str().to_owned();
    partial.push(".partial");
    let partial = Path::new(&partial);
    if let Err(e) = write(partial) {
        let _ = std::fs::remove_file(partial);
        return Err(e);
    }
    std::fs::rename(partial, path).map_err(|e| io_error(path, e))
}

/// The tone mapping of glsl/tonemap.comp on the CPU: 1 - exp(-exposure L), then sRGB, as RGBA8.
pub fn tonemap(hdr: &[[f32; 4]], exposure: f64) -> Vec<u8> {
    let encode = |c: f64| {
        let c = c.clamp(0.0, 1.0);
        let s = if c <= 0.0031308 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
        (s * 255.0).round() as u8
    };
    hdr.iter()
        .flat_map(|p| {
            let m = |c: f32| encode(1.0 - (-exposure * (c.max(0.0) as f64)).exp());
            [m(p[0]), m(p[1]), m(p[2]), 255]
        })
        .collect()
}

pub fn write_png(path: &Path, width: u32, height: u32, rgba8: &[u8]) -> Result<()> {
    let rgb: Vec<u8> = rgba8.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect();
    write_atomically(path, |tmp| {
        image::save_buffer_with_format(
            tmp,
            &rgb,
            width,
            height,
            image::ExtendedColorType::Rgb8,
            image::ImageFormat::Png,
        )
        .map_err(|e| io_error(path, e))
    })
}

/// Linear RGBA as OpenEXR (f32), alpha carried as given (the ground truth's resolved mask).
pub fn write_exr_rgba(path: &Path, width: u32, height: u32, rgba: &[[f32; 4]]) -> Result<()> {
    let data: Vec<f32> = rgba.iter().flatten().copied().collect();
    let buffer = image::Rgba32FImage::from_raw(width, height, data).expect("width * height pixels");
    write_atomically(path, |tmp| {
        image::DynamicImage::ImageRgba32F(buffer)
            .save_with_format(tmp, image::ImageFormat::OpenExr)
            .map_err(|e| io_error(path, e))
    })
}

/// Reads an OpenEXR written by `write_exr` or `write_exr_rgba` (alpha 1 when absent).
pub fn read_exr(path: &Path) -> Result<(u32, u32, Vec<[f32; 4]>)> {
    let image = image::open(path).map_err(|e| io_error(path, e))?.into_rgba32f();
    let (w, h) = image.dimensions();
    Ok((w, h, image.pixels().map(|p| p.0).collect()))
}

pub fn write_exr(path: &Path, width: u32, height: u32, hdr: &[[f32; 4]]) -> Result<()> {
    let rgb: Vec<f32> = hdr.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let buffer = image::Rgb32FImage::from_raw(width, height, rgb).expect("width * height pixels");
    write_atomically(path, |tmp| {
        image::DynamicImage::ImageRgb32F(buffer)
            .save_with_format(tmp, image::ImageFormat::OpenExr)
            .map_err(|e| io_error(path, e))
    })
}

pub fn write_text(path: &Path, text: &str) -> Result<()> {
    write_atomically(path, |tmp| std::fs::write(tmp, text).map_err(|e| io_error(path, e)))
}
