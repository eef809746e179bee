//! Error against run time: every method at several quality settings, timed on the GPU and compared
//! with a ground truth, in total and per term (reflected sun, reflected sky, refracted sea) and
//! per distance band, with the detail a pixel can see (local contrast and the sun's glitter,
//! error_detail). Writes CSVs, markdown tables and plots: the Pareto front, energy and contrast by
//! distance.

use crate::app::median;
use crate::error::{Error, Result};
use crate::measure::bench::error_detail::{self, Detail, TruthDetail, TruthImages};
use crate::measure::bench::local_waves;
use crate::measure::groundtruth::GroundTruthFiles;
use crate::measure::region::Region;
use crate::model::scene::Scene;
use crate::model::waves;
use crate::output::plot::{self, Point};
use crate::output::progress::Progress;
use crate::output::{luminance, write_text};
use crate::render::frame::CameraFrame;
use crate::render::passes::ocean::{Method, ShaderConfig, Terms};
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use std::fmt::Write as _;
use std::path::Path;

/// Distance bands (m) for the per-distance table: the near field to the horizon.
pub const BANDS_M: [f64; 9] = [0.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, f64::INFINITY];
pub const TERMS: [&str; 4] = ["total", "sun", "sky", "sea"];

/// One configuration of the renderer.
#[derive(Debug, Clone)]
pub struct Setting {
    pub method: Method,
    pub label: String,
    pub scene: Scene,
    pub ssaa: u32,
    /// Whether the reflected sun is drawn as glints (the full method's default; its "glints=off"
    /// setting keeps the expected value).
    pub glints: bool,
}

/// Side of the blocks whose mean luminance the block RMSE compares (pixels).
pub const BLOCK_PX: u32 = 8;

/// RMSE (kcd/m^2, Rec. 709 luminance) and signed relative energy error per term; the energy
/// error is NaN where the ground truth has no energy in that term (written as an empty field).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct TermErrors {
    pub rmse: [f64; 4],
    /// The RMSE a perfect method would still show against the ground truth's own sampling
    /// noise: the root of the mean variance of its pixels' means.
    pub rmse_floor: [f64; 4],
    pub energy_error: [f64; 4],
    /// The standard error of the energy error from the ground truth's own sampling noise: the
    /// square root of the summed variances of its pixels' means, over its summed energy.
    pub energy_uncertainty: [f64; 4],
}

#[derive(Debug, Clone, serde::Serialize)]
pub struct Row {
    pub method: String,
    pub setting: String,
    pub gpu_ms: f64,
    pub all: TermErrors,
    /// Per distance band: (pixels, unresolved fraction in the ground truth, errors).
    pub bands: Vec<(usize, f64, TermErrors)>,
    /// On BLOCK_PX x BLOCK_PX block means over the sea.
    pub blocks: BlockErrors,
    /// Local contrast and glitter against the ground truth's, over the whole sea.
    pub detail: Detail,
    /// The same per distance band.
    pub detail_bands: Vec<Detail>,
}

/// RMSE of the mean luminance of BLOCK_PX x BLOCK_PX blocks wholly on the sea, per term, and its
/// floor: the glints' noise averages out over a block (its variance falls as 1 / pixels), the
/// methods' differences in mean radiance do not.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct BlockErrors {
    pub count: usize,
    pub rmse: [f64; 4],
    pub rmse_floor: [f64; 4],
}

/// The indices of the pixels of a `w` x `h` image of `camera` that see the sea, by distance band
/// (BANDS_M), each band in row-major order.
pub fn sea_pixels_by_band(camera: &CameraFrame, w: u32, h: u32) -> Vec<Vec<usize>> {
    sea_pixels_by_band_in(camera, w, h, Region::whole(w, h))
}

/// The same over `region` of the image, as the region's indices (row-major in it).
pub fn sea_pixels_by_band_in(camera: &CameraFrame, w: u32, h: u32, region: Region) -> Vec<Vec<usize>> {
    let mut bands: Vec<Vec<usize>> = vec![Vec::new(); BANDS_M.len() - 1];
    for i in 0..region.pixels() {
        let (x, y) = region.image_pixel(i);
        if let Some(d) = camera.pixel_distance(x, y, w, h) {
            let band = BANDS_M.windows(2).position(|b| d >= b[0] && d < b[1]).expect("bands cover [0, inf)");
            bands[band].push(i);
        }
    }
    bands
}

/// The blocks of `w` x `h` wholly on the sea (`on_sea`), each as its pixels' indices.
fn sea_blocks(w: u32, h: u32, on_sea: &[bool]) -> Vec<Vec<usize>> {
    let (bw, bh) = (w / BLOCK_PX, h / BLOCK_PX);
    (0..bh * bw)
        .map(|b| {
            let (x0, y0) = ((b % bw) * BLOCK_PX, (b / bw) * BLOCK_PX);
            (0..BLOCK_PX * BLOCK_PX).map(|k| ((y0 + k / BLOCK_PX) * w + x0 + k % BLOCK_PX) as usize).collect::<Vec<_>>()
        })
        .filter(|block| block.iter().all(|&i| on_sea[i]))
        .collect()
}

fn block_errors(
    images: &[Vec<[f32; 4]>; 4],
    truth: &[&[[f32; 4]]; 4],
    variance: &[[f32; 4]],
    blocks: &[Vec<usize>],
) -> BlockErrors {
    let mut e = BlockErrors { count: blocks.len(), rmse: [f64::NAN; 4], rmse_floor: [f64::NAN; 4] };
    if blocks.is_empty() {
        return e;
    }
    for t in 0..4 {
        let (mut sq, mut var) = (0.0, 0.0);
        for block in blocks {
            let n = block.len() as f64;
            let m: f64 = block.iter().map(|&i| luminance(images[t][i])).sum::<f64>() / n;
            let r: f64 = block.iter().map(|&i| luminance(truth[t][i])).sum::<f64>() / n;
            sq += (m - r) * (m - r);
            // The block mean's variance: its pixels' means are independent samples.
            var += block.iter().map(|&i| variance[i][t] as f64).sum::<f64>() / (n * n);
        }
        let k = blocks.len() as f64;
        e.rmse[t] = (sq / k).sqrt();
        e.rmse_floor[t] = (var / k).sqrt();
    }
    e
}

/// The settings benched for every method: the default, finer and coarser grids, fewer trains,
/// and supersampling.
pub fn settings(scene: &Scene) -> Vec<Setting> {
    let mut out = Vec::new();
    for method in Method::ALL {
        let glints = method == Method::Full;
        let with = |label: String, scene: Scene, ssaa: u32| Setting { method, label, scene, ssaa, glints };
        out.push(with("default".into(), scene.clone(), 1));
        if glints {
            out.push(Setting { glints: false, ..with("glints=off".into(), scene.clone(), 1) });
        }
        for cell in [4.0, 16.0] {
            let mut s = scene.clone();
            s.render.grid_cell_px = cell;
            out.push(with(format!("grid_cell_px={cell}"), s, 1));
        }
        let mut fewer = scene.clone();
        fewer.waves.count = (scene.waves.count / 2).max(1);
        out.push(with(format!("waves={}", fewer.waves.count), fewer, 1));
        for k in [2, 3] {
            out.push(with(format!("ssaa={k}"), scene.clone(), k));
        }
    }
    out
}

/// Errors of `images` (total, sun, sky, sea) against the ground truth over the pixels `select`ed.
/// `variance`: the ground truth's variance of each pixel's mean luminance, per term.
pub fn errors(
    images: &[Vec<[f32; 4]>; 4],
    truth: &[&[[f32; 4]]; 4],
    variance: &[[f32; 4]],
    select: &[usize],
) -> TermErrors {
    let mut e = TermErrors::default();
    if select.is_empty() {
        return TermErrors {
            rmse: [f64::NAN; 4],
            rmse_floor: [f64::NAN; 4],
            energy_error: [f64::NAN; 4],
            energy_uncertainty: [f64::NAN; 4],
        };
    }
    for t in 0..4 {
        let (mut sq, mut sum_m, mut sum_r, mut var) = (0.0, 0.0, 0.0, 0.0);
        for &i in select {
            let (m, r) = (luminance(images[t][i]), luminance(truth[t][i]));
            sq += (m - r) * (m - r);
            sum_m += m;
            sum_r += r;
            var += variance[i][t] as f64;
        }
        let n = select.len() as f64;
        e.rmse[t] = (sq / n).sqrt();
        e.rmse_floor[t] = (var / n).sqrt();
        e.energy_error[t] = if sum_r > 0.0 { (sum_m - sum_r) / sum_r } else { f64::NAN };
        // (sum_m - sum_r) / sum_r moves by sum_m / sum_r^2 per unit of sum_r: the truth's standard
        // error carried through (the method's own frames are deterministic).
        e.energy_uncertainty[t] = if sum_r > 0.0 { var.sqrt() * sum_m / (sum_r * sum_r) } else { f64::NAN };
    }
    e
}

/// Every setting against the scene's ground truth `reference`; with `bare_reference` (a truth of
/// the scene without its local waves, `local_waves`), the local waves' own change too.
pub fn run(
    gpu: &Gpu,
    scene: &Scene,
    scene_name: &str,
    reference: &Path,
    bare_reference: Option<&Path>,
    frames: u32,
    out_dir: &Path,
) -> Result<Vec<Row>> {
    let truth = GroundTruthFiles::load(reference)?;
    // The view's size, and the region of it the ground truth traced: the methods render the
    // whole view, and every statistic is taken over the region's pixels.
    let (view_w, view_h) = (truth.meta.width, truth.meta.height);
    let region = truth.meta.region();
    let (w, h) = (region.width, region.height);
    if !truth.meta.is_of(scene) {
        return Err(Error::Argument(format!(
            "reference {} was made for another scene than {scene_name}: make it with `ocean reference --scene {scene_name}`",
            reference.display()
        )));
    }
    let bare = bare_reference.map(|p| local_waves::BareTruth::load(p, scene, scene_name, &truth)).transpose()?;
    let wave_set = waves::generate(scene);
    let camera = CameraFrame::new(scene, &wave_set, view_w, view_h);
    // Sea pixels by distance band (the region's indices); the whole sea for the overall numbers.
    let bands = sea_pixels_by_band_in(&camera, view_w, view_h, region);
    let mut on_sea = vec![false; (w * h) as usize];
    for &i in bands.iter().flatten() {
        on_sea[i] = true;
    }
    let sea: Vec<usize> = (0..on_sea.len()).filter(|&i| on_sea[i]).collect();
    let blocks = sea_blocks(w, h, &on_sea);
    let truth_detail = TruthDetail::new(&TruthImages::of(&truth), &on_sea, &sea, &bands)?;
    let truth_images = [truth.total.as_slice(), truth.sun.as_slice(), truth.sky.as_slice(), truth.sea.as_slice()];
    let mut rows = Vec::new();
    // The full method's default setting's sky and sea images, for the local waves' change.
    let mut full_default: Option<[Vec<[f32; 4]>; 2]> = None;
    let settings = settings(scene);
    let mut progress = Progress::new("bench error-vs-time", settings.len() as u64, "settings", true);
    for (i, setting) in settings.into_iter().enumerate() {
        progress.set(
            i as u64,
            Some(&format!("{} {}, {} frames and 3 term renders", setting.method.name(), setting.label, frames + 1)),
        );
        // The whole view, whatever region the truth traced.
        let renderer_with = |shader: ShaderConfig| {
            let options = Options { shader, ssaa: setting.ssaa, ..Options::default() };
            Renderer::new(gpu, &setting.scene, view_w, view_h, options)
        };
        let mut renderer =
            renderer_with(ShaderConfig { method: setting.method, glints: setting.glints, ..ShaderConfig::default() })?;
        let total = renderer.render(&setting.scene)?; // warm-up, and the image
        let mut times = Vec::new();
        for _ in 0..frames {
            times.push(renderer.render(&setting.scene)?.pass_ms.iter().map(|(_, ms)| ms).sum::<f64>());
        }
        drop(renderer);
        times.sort_by(f64::total_cmp);
        let only = |sun, sky, sea| -> Result<Vec<[f32; 4]>> {
            let terms = ShaderConfig::terms_only(Terms { sun, sky, sea }, setting.method);
            let mut r = renderer_with(ShaderConfig { glints: setting.glints, ..terms })?;
            Ok(r.render(&setting.scene)?.hdr)
        };
        let images = [total.hdr, only(true, false, false)?, only(false, true, false)?, only(false, false, true)?]
            .map(|image| region.crop(&image, view_w));
        let band_rows = bands
            .iter()
            .map(|b| {
                let unresolved = b.iter().filter(|&&i| truth.total[i][3] == 0.0).count() as f64 / b.len().max(1) as f64;
                (b.len(), unresolved, errors(&images, &truth_images, &truth.variance, b))
            })
            .collect();
        let (detail, detail_bands) = truth_detail.of(&images);
        if setting.method == Method::Full && setting.label == "default" {
            full_default = Some([images[2].clone(), images[3].clone()]);
        }
        let row = Row {
            method: setting.method.name().into(),
            setting: setting.label.clone(),
            gpu_ms: median(&times),
            all: errors(&images, &truth_images, &truth.variance, &sea),
            bands: band_rows,
            blocks: block_errors(&images, &truth_images, &truth.variance, &blocks),
            detail,
            detail_bands,
        };
        progress.println(&format!(
            "{:<14} {:<18} {:7.1} ms  rmse {:8.4}  block rmse {:8.4}  energy {:+7.3}",
            row.method, row.setting, row.gpu_ms, row.all.rmse[0], row.blocks.rmse[0], row.all.energy_error[0]
        ));
        rows.push(row);
    }
    progress.set(rows.len() as u64, None);
    let truth_info = Truth {
        path: reference,
        noise_floor: truth.meta.noise_floor_rmse,
        sampling: format!(
            "{n}x{n} samples per pixel, {} bounces, the reflected sun over a {:.2}-degree cone{}",
            truth.meta.bounces,
            truth.meta.sun_kernel_deg,
            truth.meta.region.map_or(String::new(), |r| format!("; {r} of the {view_w}x{view_h} view")),
            n = truth.meta.samples_per_axis
        ),
        detail: &truth_detail,
    };
    write_outputs(&rows, out_dir, scene_name, truth_info, (w, h), frames)?;
    if let (Some(bare), Some([sky, sea])) = (&bare, &full_default) {
        let labels: Vec<String> = (0..BANDS_M.len() - 1).map(band_label).collect();
        local_waves::measure(local_waves::Request {
            gpu,
            scene_name,
            bare,
            truth: &truth,
            scene_images: [sky, sea],
            bands: &bands,
            labels: &labels,
            out_dir,
        })?;
    }
    Ok(rows)
}

fn term_columns() -> String {
    TERMS.iter().map(|t| format!(",rmse_{t},rmse_floor_{t},energy_error_{t},energy_uncertainty_{t}")).collect()
}

/// A CSV field: the value, or empty where it is not finite.
pub fn csv_value(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.6}")
    } else {
        String::new()
    }
}

fn term_values(e: &TermErrors) -> String {
    (0..4)
        .map(|t| {
            format!(
                ",{},{},{},{}",
                csv_value(e.rmse[t]),
                csv_value(e.rmse_floor[t]),
                csv_value(e.energy_error[t]),
                csv_value(e.energy_uncertainty[t])
            )
        })
        .collect()
}

fn block_columns() -> String {
    TERMS.iter().map(|t| format!(",block_rmse_{t},block_rmse_floor_{t}")).collect()
}

fn block_values(e: &BlockErrors) -> String {
    (0..4).map(|t| format!(",{},{}", csv_value(e.rmse[t]), csv_value(e.rmse_floor[t]))).collect()
}

/// What the outputs say of the ground truth they were measured against.
struct Truth<'a> {
    path: &'a Path,
    noise_floor: Option<f64>,
    /// How it was sampled, in words.
    sampling: String,
    /// Its side of the detail statistics.
    detail: &'a TruthDetail,
}

fn write_outputs(
    rows: &[Row],
    dir: &Path,
    scene_name: &str,
    truth: Truth,
    (w, h): (u32, u32),
    frames: u32,
) -> Result<()> {
    let Truth { path: reference, noise_floor, sampling, detail } = truth;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let detail_columns = error_detail::detail_columns();
    let mut csv = format!("method,setting,gpu_ms{},blocks{}{detail_columns}\n", term_columns(), block_columns());
    for r in rows {
        let (all, blocks, details) =
            (term_values(&r.all), block_values(&r.blocks), error_detail::detail_values(&r.detail));
        writeln!(csv, "{},{},{:.3}{all},{}{blocks}{details}", r.method, r.setting, r.gpu_ms, r.blocks.count).unwrap();
    }
    write_text(&dir.join("error_vs_time.csv"), &csv)?;
    let mut by_distance = format!(
        "method,setting,band,distance_min_m,distance_max_m,pixels,unresolved_fraction{}{detail_columns}\n",
        term_columns()
    );
    for r in rows {
        for (b, ((n, unresolved, e), d)) in r.bands.iter().zip(&r.detail_bands).enumerate() {
            writeln!(
                by_distance,
                "{},{},{b},{},{},{n},{unresolved:.4}{}{}",
                r.method,
                r.setting,
                BANDS_M[b],
                BANDS_M[b + 1],
                term_values(e),
                error_detail::detail_values(d)
            )
            .unwrap();
        }
    }
    write_text(&dir.join("error_by_distance.csv"), &by_distance)?;
    let front = pareto_front(rows);
    // The floors depend on the ground truth alone: the same in every row.
    let floors = rows.first().map_or(([f64::NAN; 4], [f64::NAN; 4]), |r| (r.all.rmse_floor, r.blocks.rmse_floor));
    let block_count = rows.first().map_or(0, |r| r.blocks.count);
    let mut md = format!(
        "Error against GPU time: scene `{scene_name}` at {w}x{h}, reference `{}` ({sampling}), median of {frames} frames.\n\
         RMSE of Rec. 709 luminance (kcd/m^2) over the sea, per pixel and on the means of the {block_count} blocks of \
         {BLOCK_PX}x{BLOCK_PX} pixels wholly on the sea (the ground truth's glints average out over a block); \
         energy error = (mean - reference mean) / reference mean, ± its standard error from the reference's own sampling noise.\n\
         `*` marks the Pareto front (no other row is both faster and smaller in block RMSE).\n\
         The first row is the ground truth's own noise floor: the RMSE a perfect method would still show against it \
         (from the variance of its pixels' means; `noise_floor_rmse` of its report, from its even strata: {}).\n\n\
         | method | setting | GPU ms | RMSE total | block RMSE total | block RMSE sun | block RMSE sky | energy total | energy sun | energy sky | energy sea |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n\
         | ground truth's noise floor | | | {:.4} | {:.4} | {:.4} | {:.4} | | | | |\n",
        reference.display(),
        noise_floor.map_or("not measured".to_owned(), |f| format!("{f:.4}")),
        floors.0[0],
        floors.1[0],
        floors.1[1],
        floors.1[2],
    );
    for (i, r) in rows.iter().enumerate() {
        let star = if front.contains(&i) { " *" } else { "" };
        // A term the ground truth does not have (the sun behind the eye) has no relative error.
        let energy = |t: usize| match (r.all.energy_error[t], r.all.energy_uncertainty[t]) {
            (e, u) if e.is_finite() && u.is_finite() => format!("{e:+.3} ± {u:.3}"),
            _ => "—".to_owned(),
        };
        writeln!(
            md,
            "| {}{star} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.4} | {} | {} | {} | {} |",
            r.method,
            r.setting,
            r.gpu_ms,
            r.all.rmse[0],
            r.blocks.rmse[0],
            r.blocks.rmse[1],
            r.blocks.rmse[2],
            energy(0),
            energy(1),
            energy(2),
            energy(3)
        )
        .unwrap();
    }
    md.push_str(&error_detail::markdown(rows, detail));
    write_text(&dir.join("error_vs_time.md"), &md)?;
    let title = format!("Error against GPU time: {scene_name}, {w}x{h}");
    let points: Vec<Point> = rows
        .iter()
        .map(|r| Point { method: &r.method, setting: &r.setting, gpu_ms: r.gpu_ms, rmse: ranking_rmse(r) })
        .collect();
    let what = format!("RMSE of {BLOCK_PX}x{BLOCK_PX}-block mean luminance over the sea");
    let floor = Some(floors.1[0]).filter(|f| f.is_finite());
    plot::error_vs_time(&dir.join("error_vs_time.svg"), &title, &points, &front, floor, &what)?;
    // Energy against distance of each method's default setting, sun and sky (indices 1 and 2).
    let series: Vec<(&str, Vec<[f64; 2]>)> = rows
        .iter()
        .filter(|r| r.setting == "default")
        .map(|r| (r.method.as_str(), r.bands.iter().map(|(_, _, e)| [e.energy_error[1], e.energy_error[2]]).collect()))
        .collect();
    let title = format!("Energy error by distance, default settings: {scene_name}, {w}x{h}");
    let bands: Vec<String> = (0..BANDS_M.len() - 1).map(band_label).collect();
    plot::energy_by_distance(&dir.join("energy_by_distance.svg"), &title, &bands, &series)?;
    // The reflected sky's local contrast against the truth's, by distance: where detail is lost.
    let series: Vec<(&str, Vec<f64>)> = rows
        .iter()
        .filter(|r| r.setting == "default")
        .map(|r| (r.method.as_str(), r.detail_bands.iter().map(|d| d.contrast[2].ratio).collect()))
        .collect();
    let title = format!("Local contrast of the reflected sky by distance, default settings: {scene_name}, {w}x{h}");
    let what = "3x3 high-pass std / the ground truth's without its noise";
    plot::ratio_by_distance(&dir.join("contrast_by_distance.svg"), &title, what, &bands, &series)
}

/// "0–10", ..., "≥1000" (metres) for band `i` of BANDS_M.
pub fn band_label(i: usize) -> String {
    let (lo, hi) = (BANDS_M[i], BANDS_M[i + 1]);
    if hi.is_finite() {
        format!("{lo}–{hi}")
    } else {
        format!("≥{lo}")
    }
}

/// The RMSE that ranks the rows: on block means, where the image has a whole block of sea (the
/// per-pixel RMSE is mostly the ground truth's glint noise), else per pixel.
fn ranking_rmse(r: &Row) -> f64 {
    if r.blocks.count > 0 {
        r.blocks.rmse[0]
    } else {
        r.all.rmse[0]
    }
}

/// Indices of rows no other row beats in both GPU time and total RMSE (ranking_rmse).
pub fn pareto_front(rows: &[Row]) -> Vec<usize> {
    (0..rows.len())
        .filter(|&i| {
            let (ms, e) = (rows[i].gpu_ms, ranking_rmse(&rows[i]));
            !rows.iter().any(|o| {
                let (o_ms, o_e) = (o.gpu_ms, ranking_rmse(o));
                o_ms <= ms && o_e <= e && (o_ms < ms || o_e < e)
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: usize = 24;
    const H: usize = 20;

    /// A synthetic truth: sky in the top two rows, a checkered sky term, a column of glints.
    fn truth_terms() -> [Vec<[f32; 4]>; 4] {
        let grey = |v: f32| [v, v, v, 1.0];
        let pattern = |f: fn(usize, usize) -> f32| (0..W * H).map(|i| grey(f(i % W, i / W))).collect::<Vec<_>>();
        let sun = pattern(|x, y| if x == 12 && y % 2 == 0 { 9.0 } else { 0.5 });
        let sky = pattern(|x, y| if (x + y) % 2 == 0 { 2.0 } else { 1.0 });
        let sea = pattern(|x, _| 0.1 * x as f32);
        let total = (0..W * H).map(|i| grey(sun[i][0] + sky[i][0] + sea[i][0])).collect();
        [total, sun, sky, sea]
    }

    fn row(method: &str, images: &[Vec<[f32; 4]>; 4], truth: &TruthDetail) -> Row {
        let (detail, detail_bands) = truth.of(images);
        let bands = detail_bands.iter().map(|_| (1, 0.0, TermErrors::default())).collect();
        let (all, blocks) = (TermErrors::default(), BlockErrors::default());
        Row { method: method.into(), setting: "default".into(), gpu_ms: 1.0, all, bands, blocks, detail, detail_bands }
    }

    #[test]
    fn the_detail_columns_and_tables_are_written_for_every_row() {
        let terms = truth_terms();
        let variance = vec![[0.0f32; 4]; W * H];
        let images = TruthImages {
            width: W,
            height: H,
            terms: terms.each_ref().map(|t| t.as_slice()),
            variance: &variance,
            half: None,
        };
        let on_sea: Vec<bool> = (0..W * H).map(|i| i >= 2 * W).collect();
        let sea: Vec<usize> = (2 * W..W * H).collect();
        // Two sea rows a band (the last band empty): a band's pixels need not be its own neighbours.
        let bands: Vec<Vec<usize>> = (0..BANDS_M.len() - 1)
            .map(|b| sea.iter().copied().filter(|&i| (i / W - 2) / 2 == b && b < BANDS_M.len() - 2).collect())
            .collect();
        let truth = TruthDetail::new(&images, &on_sea, &sea, &bands).unwrap();
        // One method is the truth, the other has its sky flattened and no glints.
        let mut flat = terms.clone();
        flat[2].iter_mut().for_each(|p| *p = [1.5, 1.5, 1.5, 1.0]);
        flat[1].iter_mut().for_each(|p| *p = [1.0, 1.0, 1.0, 1.0]);
        let rows = [row("full", &terms, &truth), row("paper", &flat, &truth)];
        assert!((rows[0].detail.contrast[2].ratio - 1.0).abs() < 1e-12, "the truth's own contrast ratio is 1");
        assert!((rows[0].detail.glitter.var_ratio - 1.0).abs() < 1e-12, "and its glitter ratios");
        assert_eq!(rows[1].detail.contrast[2].ratio, 0.0, "a flat sky has no contrast");
        assert_eq!(rows[1].detail.glitter.bright_share_ratio, 0.0, "and a flat sun no glints");

        let dir = std::env::temp_dir().join(format!("ocean-detail-test-{}", std::process::id()));
        let info =
            Truth { path: Path::new("ref.exr"), noise_floor: None, sampling: "synthetic".into(), detail: &truth };
        write_outputs(&rows, &dir, "synthetic", info, (W as u32, H as u32), 1).unwrap();
        let read = |file: &str| std::fs::read_to_string(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        for (file, old_head) in [
            ("error_vs_time.csv", format!("method,setting,gpu_ms{},blocks{}", term_columns(), block_columns())),
            (
                "error_by_distance.csv",
                format!(
                    "method,setting,band,distance_min_m,distance_max_m,pixels,unresolved_fraction{}",
                    term_columns()
                ),
            ),
        ] {
            let csv = read(file);
            let header = csv.lines().next().unwrap();
            assert!(header.starts_with(&old_head), "{file}: the old columns first, in order: {header}");
            for column in ["contrast_ratio_sky", "contrast_truth_signal_sea", "glitter_var_ratio", "glitter_truth_var"]
            {
                assert!(header.split(',').any(|c| c == column), "{file} lacks {column}");
            }
            let width = header.split(',').count();
            for line in csv.lines().skip(1) {
                assert_eq!(line.split(',').count(), width, "{file}: {line}");
            }
        }
        let md = read("error_vs_time.md");
        assert!(md.contains("## Detail a pixel can see") && md.contains("### Glitter"), "{md}");
        assert!(md.contains("pixels assumed independent"), "says which noise estimate: {md}");
        let svg = read("contrast_by_distance.svg");
        assert!(svg.contains("Local contrast of the reflected sky by distance"), "{svg}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
