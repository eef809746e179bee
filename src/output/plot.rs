//! Small raster plots for the error bench (no text: the markdown beside them carries the numbers).
//! Methods by colour: full blue, constant-brdf orange, no-filter red.

use crate::bench::error_vs_time::Row;
use crate::error::{Error, Result};
use image::{Rgb, RgbImage};
use std::path::Path;

const W: u32 = 720;
const H: u32 = 480;
const MARGIN: i32 = 40;

/// full: blue, constant-brdf: orange, no-filter: red (the markdown table says so too).
fn colour(method: &str) -> Rgb<u8> {
    match method {
        "full" => Rgb([31, 119, 180]),
        "constant-brdf" => Rgb([255, 127, 14]),
        _ => Rgb([214, 39, 40]),
    }
}

fn put(img: &mut RgbImage, x: i32, y: i32, c: Rgb<u8>) {
    if x >= 0 && y >= 0 && (x as u32) < W && (y as u32) < H {
        img.put_pixel(x as u32, y as u32, c);
    }
}

fn line(img: &mut RgbImage, (x0, y0): (i32, i32), (x1, y1): (i32, i32), c: Rgb<u8>) {
    let steps = (x1 - x0).abs().max((y1 - y0).abs()).max(1);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        put(img, x0 + ((x1 - x0) as f64 * t).round() as i32, y0 + ((y1 - y0) as f64 * t).round() as i32, c);
    }
}

fn disc(img: &mut RgbImage, (cx, cy): (i32, i32), r: i32, c: Rgb<u8>) {
    for y in -r..=r {
        for x in -r..=r {
            if x * x + y * y <= r * r {
                put(img, cx + x, cy + y, c);
            }
        }
    }
}

/// Error against GPU time: time from zero, error over the rows' range, a tick every tenth of each
/// axis, the Pareto front as a grey line with its points ringed.
pub fn error_vs_time(path: &Path, rows: &[Row], front: &[usize]) -> Result<()> {
    let mut img = RgbImage::from_pixel(W, H, Rgb([255, 255, 255]));
    let max_t = rows.iter().map(|r| r.gpu_ms).fold(0.0, f64::max).max(1e-9) * 1.1;
    let errors = rows.iter().map(|r| r.all.rmse[0]).filter(|e| e.is_finite());
    let (min_e, max_e) = errors.fold((f64::INFINITY, 0.0f64), |(lo, hi), e| (lo.min(e), hi.max(e)));
    let span = (max_e - min_e).max(1e-9);
    let (min_e, max_e) = ((min_e - 0.05 * span).max(0.0), max_e + 0.05 * span);
    let to_px = |t: f64, e: f64| {
        let x = MARGIN + ((t / max_t) * (W as i32 - 2 * MARGIN) as f64).round() as i32;
        let y = H as i32 - MARGIN - (((e - min_e) / (max_e - min_e)) * (H as i32 - 2 * MARGIN) as f64).round() as i32;
        (x, y)
    };
    let axis = Rgb([0, 0, 0]);
    line(&mut img, to_px(0.0, min_e), to_px(max_t, min_e), axis);
    line(&mut img, to_px(0.0, min_e), to_px(0.0, max_e), axis);
    for i in 1..=10 {
        let (x, y) = to_px(max_t * i as f64 / 10.0, min_e);
        line(&mut img, (x, y), (x, y + 5), axis);
        let (x, y) = to_px(0.0, min_e + (max_e - min_e) * i as f64 / 10.0);
        line(&mut img, (x - 5, y), (x, y), axis);
    }
    let mut on_front: Vec<&Row> = front.iter().map(|&i| &rows[i]).collect();
    on_front.sort_by(|a, b| a.gpu_ms.total_cmp(&b.gpu_ms));
    for pair in on_front.windows(2) {
        line(
            &mut img,
            to_px(pair[0].gpu_ms, pair[0].all.rmse[0]),
            to_px(pair[1].gpu_ms, pair[1].all.rmse[0]),
            Rgb([150, 150, 150]),
        );
    }
    for (i, r) in rows.iter().enumerate() {
        let p = to_px(r.gpu_ms, r.all.rmse[0]);
        if front.contains(&i) {
            disc(&mut img, p, 7, Rgb([0, 0, 0]));
        }
        disc(&mut img, p, 5, colour(&r.method));
    }
    save(&img, path)
}

fn save(img: &RgbImage, path: &Path) -> Result<()> {
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png)
        .map_err(|e| Error::Io { path: path.to_owned(), message: e.to_string() })?;
    super::target::write(path, bytes.get_ref())
}

/// Energy error against distance band, for the sun (left half) and the sky (right half) of each
/// method's default setting: a zero line, y from -1 (all energy lost) to +2 (three times the
/// reference), one tick per band and per 0.5 of error; missing values leave gaps.
pub fn energy_by_distance(path: &Path, series: &[(&str, Vec<[f64; 2]>)]) -> Result<()> {
    let mut img = RgbImage::from_pixel(W, H, Rgb([255, 255, 255]));
    let (lo, hi) = (-1.0, 2.0);
    let bands = series.first().map_or(1, |s| s.1.len()).max(2);
    let panel_w = (W as i32 - 3 * MARGIN) / 2;
    let to_px = |panel: i32, band: usize, e: f64| {
        let x0 = MARGIN + panel * (panel_w + MARGIN);
        let x = x0 + (band as f64 / (bands - 1) as f64 * panel_w as f64).round() as i32;
        let y =
            H as i32 - MARGIN - (((e.clamp(lo, hi) - lo) / (hi - lo)) * (H as i32 - 2 * MARGIN) as f64).round() as i32;
        (x, y)
    };
    let axis = Rgb([0, 0, 0]);
    for panel in 0..2 {
        line(&mut img, to_px(panel, 0, 0.0), to_px(panel, bands - 1, 0.0), Rgb([120, 120, 120]));
        line(&mut img, to_px(panel, 0, lo), to_px(panel, 0, hi), axis);
        for b in 0..bands {
            let (x, y) = to_px(panel, b, lo);
            line(&mut img, (x, y), (x, y + 5), axis);
        }
        for k in 0..=6 {
            let (x, y) = to_px(panel, 0, lo + 0.5 * k as f64);
            line(&mut img, (x - 5, y), (x, y), axis);
        }
    }
    for (method, values) in series {
        for panel in 0..2usize {
            let points: Vec<Option<(i32, i32)>> = values
                .iter()
                .enumerate()
                .map(|(b, v)| v[panel].is_finite().then(|| to_px(panel as i32, b, v[panel])))
                .collect();
            for pair in points.windows(2) {
                if let (Some(a), Some(b)) = (pair[0], pair[1]) {
                    line(&mut img, a, b, colour(method));
                }
            }
            for p in points.into_iter().flatten() {
                disc(&mut img, p, 4, colour(method));
            }
        }
    }
    save(&img, path)
}
