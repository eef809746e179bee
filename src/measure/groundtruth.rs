//! Ground truth for measuring the renderer: every wave as exact geometry, N x N stratified samples
//! per pixel (glsl/groundtruth.comp), dispatched in tiles so that any size works and no single
//! submission runs long. Reports its own convergence and the pixels whose sub-samples still
//! cannot resolve the shortest wave.

use crate::error::{Error, Result};
use crate::measure::region::Region;
use crate::measure::truth_objects::{self, TruthObjects};
use crate::measure::truth_sky::{self, TruthSkyError, TruthSkyTables};
use crate::model::packets::sources::Sources;
use crate::model::scene::{Scene, SkyKind};
use crate::model::waves;
use crate::render::frame;
use crate::render::packets::{FramePackets, GpuPacket};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::buffer::Buffer;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::memory::Location;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings, Specialization};
use ash::vk;
use std::time::Instant;

/// Floats per pixel in the accumulation buffer: seven vec4 (total and mask, subset, sun, sky, the
/// sums of squares, the half estimate's luminances, the refracted light; glsl/groundtruth.comp,
/// Pixels).
const WORDS_PER_PIXEL: usize = 28;
const BYTES_PER_PIXEL: u64 = 4 * WORDS_PER_PIXEL as u64;
/// Pixels per tile side: one dispatch and one fence per tile.
const TILE: u32 = 32;
/// Largest samples per pixel per axis: 64 x 64 = 4096 samples.
pub const MAX_SAMPLES: u32 = 64;

#[repr(C)]
#[derive(Clone, Copy)]
struct TilePush {
    origin: [u32; 2],
    samples: u32,
    stratum: u32,
    wave_count: u32,
    slab: f32,
    lipschitz: f32,
    ior: f32,
    seed: u32,
    max_march: u32,
    bounces: u32,
    bounce_march: u32,
    sun_cos_kernel: f32,
    sun_kernel_scale: f32,
    /// The region traced: its first pixel and size (the image's pixels; the buffer holds these).
    region: [u32; 4],
    /// The trains' own slab and slope bound: the surface's outside `packet_reach`.
    train_slab: f32,
    train_lipschitz: f32,
    /// The rest plane's box (min, max) over which packets shape the surface; min > max: none.
    packet_reach: [[f32; 2]; 2],
}

/// Loop iterations one invocation may run in total on lavapipe 22.3 (gallivm's loop limiter,
/// LP_MAX_TGSI_LOOP_ITERATIONS), past which every loop silently stops.
const LOOP_BUDGET: u32 = 65535;
/// Marching steps of the camera ray where the budget allows, at the longest lists (the reflected
/// rays share the rest).
const MAX_MARCH: u32 = 4096;

/// Trains the shader's surface loop adds per iteration (glsl/groundtruth.comp `surface`): the
/// budget counts iterations, so each step costs an eighth of the trains' count in it.
const TRAINS_PER_ITERATION: usize = 8;
/// Packets the shader's loop over a cell adds per iteration (glsl/groundtruth.comp `add_packets`).
const PACKETS_PER_ITERATION: u32 = 8;
/// The ground truth's packet cells a side at most: finer than a frame's (whose GPU scan takes
/// grid::MAX_CELLS_PER_SIDE), for shorter lists where the packets are small.
const TRUTH_CELLS_PER_SIDE: u32 = 512;

/// Newton steps that invert the displacement at each evaluation of the gap (glsl/groundtruth.comp
/// `invert`): each a loop iteration of its own.
const NEWTON_STEPS: u32 = 2;

/// Bisection steps after a bracketed crossing (glsl/groundtruth.comp).
const BISECTION_STEPS: u32 = 16;

/// Reflected rays a sample may trace again after the first: `--bounces` (glsl/groundtruth.comp).
pub const DEFAULT_BOUNCES: u32 = 3;
pub const MAX_BOUNCES: u32 = 16;

/// Angular radius (degrees) of the cone over which the reflected sun's energy is spread for its
/// estimate (`--sun-kernel-deg`): a reflected ray within it gathers the sun's irradiance over the
/// cone's solid angle. At the sun's own radius (0.27 degrees) the estimate is the sun disc itself,
/// unbiased but a scatter of rare glints; 2 degrees makes a hit (2 / 0.27)^2 ~ 55 times likelier,
/// its standard error 7 times smaller, and moves each band's energy only by the curvature of the
/// reflected directions' density over the cone, whose spread is the slopes' (tens of degrees):
/// below a percent (docs/results.md measures it).
pub const DEFAULT_SUN_KERNEL_DEG: f64 = 2.0;
pub const MAX_SUN_KERNEL_DEG: f64 = 10.0;

/// How and where the ground truth samples: N x N strata per pixel, the bounces traced, the sun's
/// kernel, and the region of the image it traces (the whole image where None).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sampling {
    pub samples: u32,
    pub bounces: u32,
    pub sun_kernel_deg: f64,
    pub region: Option<Region>,
}

impl Sampling {
    /// `samples` per axis with the default bounces and sun kernel.
    pub fn new(samples: u32) -> Sampling {
        Sampling { samples, bounces: DEFAULT_BOUNCES, sun_kernel_deg: DEFAULT_SUN_KERNEL_DEG, region: None }
    }

    fn check(&self) -> Result<()> {
        let Sampling { samples, bounces, sun_kernel_deg, .. } = *self;
        if samples == 0 || samples > MAX_SAMPLES {
            return Err(Error::Argument(format!("--samples {samples} is out of range [1, {MAX_SAMPLES}] per axis")));
        }
        if !(1..=MAX_BOUNCES).contains(&bounces) {
            return Err(Error::Argument(format!("--bounces {bounces} is out of range [1, {MAX_BOUNCES}]")));
        }
        let sun_deg = sun_disc_deg();
        if !(sun_kernel_deg >= sun_deg && sun_kernel_deg <= MAX_SUN_KERNEL_DEG) {
            return Err(Error::Argument(format!(
                "--sun-kernel-deg {sun_kernel_deg} is out of range [{sun_deg:.4}, {MAX_SUN_KERNEL_DEG}] (the sun's own radius to 10 degrees)"
            )));
        }
        Ok(())
    }

    /// cos of the kernel's radius, and the sun disc's solid angle over the kernel's: 1 - cos x as
    /// 2 sin^2(x / 2), which keeps its digits at fractions of a degree.
    fn sun_kernel(&self) -> (f32, f32) {
        let one_minus_cos = |x: f64| 2.0 * (x / 2.0).sin().powi(2);
        let kernel = self.sun_kernel_deg.to_radians();
        let scale = one_minus_cos(crate::model::sky::SUN_ANGULAR_RADIUS) / one_minus_cos(kernel);
        (kernel.cos() as f32, scale.min(1.0) as f32)
    }
}

/// Loop iterations one surface evaluation costs where the cells' lists are `packet_run` long:
/// the trains eight at a time and the packets eight at a time (glsl/groundtruth.comp `surface`).
fn evaluation_iterations(wave_count: u32, packet_run: u32) -> u32 {
    wave_count.div_ceil(TRAINS_PER_ITERATION as u32) + packet_run.div_ceil(PACKETS_PER_ITERATION)
}

/// Loop iterations one marching (or bisection) step costs where the cells' lists are
/// `packet_run` long: itself, its Newton loop and its NEWTON_STEPS + 1 surface evaluations.
fn step_iterations(wave_count: u32, packet_run: u32) -> u32 {
    (NEWTON_STEPS + 1) * evaluation_iterations(wave_count, packet_run) + 1 + NEWTON_STEPS
}

/// The loop iterations one sample's marches may spend within the loop budget: (camera ray, all
/// reflected rays together). Every marching step (and bisection step) evaluates the surface three
/// times (NEWTON_STEPS Newton steps, each a loop iteration, and the result); a march charges each
/// step what it spent (itself, its Newton loop's and its own
/// evaluations' trains and its own cells' packets, glsl/groundtruth.comp `intersect`), so over
/// short lists it takes more steps than over the longest, `packet_run`, at which the rest is
/// reserved: the camera ray and the `bounces + 1` reflected rays may each end in a bisection,
/// and each march may overrun its pool by one step. The camera ray, which may have to skim
/// hundreds of metres of crests at grazing view, gets two thirds of the pool; the reflected rays
/// share the rest in the order they are traced, so the first reflection, which decides the
/// reflected sun and sky, may use what the rarer later ones do not. A ray that runs out is
/// counted in the report (`unfinished_*`), never taken silently as a miss.
fn march_budget(wave_count: u32, packet_run: u32, bounces: u32, physical: bool, objects: bool) -> Result<(u32, u32)> {
    let iterations = evaluation_iterations(wave_count, packet_run);
    let per_eval = step_iterations(wave_count, packet_run);
    let rays = bounces + 2;
    // The physical sky's loops: one sky ray and one aerial path per sample at most.
    let air = if physical { (truth_sky::SKY_STEPS + truth_sky::AERIAL_STEPS) as u32 } else { 0 };
    // The objects' walks: the camera ray's, each reflected ray's, and an object's two rays, and
    // at an object its sky (physical: a sky ray each for the mirrored sky below and the sky).
    let walks =
        if objects { truth_objects::BVH_VISITS * truth_objects::walks_per_sample(bounces) + 2 * air } else { 0 };
    let fixed = rays * (BISECTION_STEPS + 3) * per_eval + 4 * iterations + 64 + air + walks;
    let pool = LOOP_BUDGET.saturating_sub(fixed);
    // Fewer than MIN_MARCH steps (at the longest lists) a ray cannot cross the slab: refused
    // rather than cut short.
    if pool / per_eval < MIN_MARCH * rays {
        return Err(Error::Argument(format!(
            "the ground truth cannot trace waves.count = {wave_count} with --bounces {bounces}: a sample's loops \
             would pass the {LOOP_BUDGET} iterations an invocation may run; use fewer trains or bounces"
        )));
    }
    let primary = (pool * 2 / 3).clamp(MIN_MARCH * per_eval, MAX_MARCH * per_eval);
    Ok((primary, pool - primary))
}

/// Probes of the marching slope's bound, and its margin over their steepest.
const SLOPE_PROBES: usize = 65536;
const SLOPE_MARGIN: f64 = 2.0;
/// The R2 sequence's steps (Roberts 2018: the plastic number's powers): probe n sits at the
/// fractional parts of 0.5 + n times these.
const R2: (f64, f64) = (0.754_877_666_246_692_7, 0.569_840_290_998_053_3);

/// The rest plane's box over which the packets shape the surface: their cells (which hold every
/// packet's reach; the truth's map is the plane's own) widened by `reach`, how far the surface's
/// points move horizontally from their rest positions (at most the sum of the amplitudes).
fn packet_reach(grid: &crate::model::packets::grid::PacketGrid, reach: f64) -> [[f32; 2]; 2] {
    let size = glam::DVec2::new(grid.cols as f64, grid.rows as f64) * grid.cell;
    let (lo, hi) = (grid.origin - reach, grid.origin + size + reach);
    [[lo.x as f32, lo.y as f32], [hi.x as f32, hi.y as f32]]
}

/// A frame's packets with their cells' lists (PacketGrid::lists: starts, then indices).
type ListedPackets<'a> = (&'a FramePackets, &'a (Vec<u32>, Vec<u32>));

/// The slope bounds the march steps by (glsl/groundtruth.comp `intersect`): how fast the displaced
/// surface's height can change along a horizontal line.
///
/// Where the trains cannot fold (sum k h < 0.9), sum k h / (1 - sum k h) bounds it, but it grows
/// without limit towards 1 (8.9 on the kilometre swell, whose sum is 0.90) where the slopes a
/// surface of many trains reaches stay near 1: a march at that bound runs out of the loop budget,
/// a certain error. So the bound is the smaller of it and the steepest slope of the displaced
/// surface over `SLOPE_PROBES` rest positions times `SLOPE_MARGIN`: a sum of many trains with
/// independent phases has sub-Gaussian slopes (Hoeffding), the probes' maximum sits near 4.3
/// standard deviations, so twice it stands 8 or more from the mean, where the tail's probability
/// is below 1e-15. A probe on a fold (the Jacobian's determinant not positive) keeps the strict
/// bound, or the former fixed 10 (84 degrees) where there is none. The wave packets add their
/// cells' largest slope sum (grid::PacketGrid::slope) to the strict bound and their own probed
/// steepest slope (`packet_steepest`) to the probes'.
///
/// Returned twice: for the trains alone (the surface where no packet reaches), then for the
/// whole surface.
fn marching_slopes(wave_set: &crate::model::waves::WaveSet, packets: Option<ListedPackets>) -> (f64, f64) {
    const FOLDING_BOUND: f64 = 10.0;
    let train_kh: f64 = wave_set.trains.iter().map(|t| t.k * t.amplitude).sum();
    let strict = |kh_sum: f64| (kh_sum < 0.9).then(|| kh_sum / (1.0 - kh_sum));
    let kh_sum = train_kh + packets.map_or(0.0, |(p, _)| p.grid.slope);
    // Rest positions over a square many of the longest waves wide, by the R2 sequence (Roberts
    // 2018: the plastic number's powers), which covers it evenly whatever the count; the phases
    // at time 0 (time only shifts the surface, its slopes' statistics stay).
    let longest = wave_set.trains.iter().map(|t| t.wavelength).fold(1.0, f64::max);
    let side = 64.0 * longest;
    let mut steepest: Option<f64> = Some(0.0);
    for n in 0..SLOPE_PROBES {
        let x = [side * (0.5 + R2.0 * n as f64).fract(), side * (0.5 + R2.1 * n as f64).fract()];
        match displaced_slope(wave_set, x) {
            Some(slope) => steepest = steepest.map(|s| s.max(slope)),
            None => {
                steepest = None;
                break;
            }
        }
    }
    // A probe on a fold leaves the strict bound (below 9), or FOLDING_BOUND where there is none.
    let bound = |kh_sum: f64, probed: Option<f64>| {
        let probed = probed.map_or(FOLDING_BOUND, |s| (SLOPE_MARGIN * s).min(FOLDING_BOUND));
        strict(kh_sum).map_or(probed, |strict| strict.min(probed))
    };
    // The packets' steepest beside the trains': the sum of the two bounds the surface's.
    let with_packets = steepest.and_then(|s| packets.map_or(Some(0.0), packet_steepest).map(|p| s + p));
    (bound(train_kh, steepest), bound(kh_sum, with_packets))
}

/// The steepest height slope of the packets' own surface over SLOPE_PROBES rest positions
/// spread evenly (the R2 sequence) over their cells, each reading its cell's list; None where it
/// folds.
fn packet_steepest((packets, (starts, lists)): ListedPackets) -> Option<f64> {
    let g = &packets.grid;
    let size = glam::DVec2::new(g.cols as f64, g.rows as f64) * g.cell;
    let mut steepest: f64 = 0.0;
    for n in 0..SLOPE_PROBES {
        let x = g.origin + size * glam::DVec2::new((0.5 + R2.0 * n as f64).fract(), (0.5 + R2.1 * n as f64).fract());
        let Some(cell) = g.cell(x) else { continue };
        let mut sum = crate::model::packets::SurfaceSum::default();
        for &i in &lists[starts[cell as usize] as usize..starts[cell as usize + 1] as usize] {
            let p = &packets.field.packets[i as usize];
            if p.reaches(x) {
                p.add_to(x, &mut sum);
            }
        }
        steepest = steepest.max(slope_through(sum.tx + glam::DVec3::X, sum.ty + glam::DVec3::Y)?);
    }
    Some(steepest)
}

/// The height slope of the displaced surface over the point whose rest position is x at time 0:
/// the height's gradient through the inverse of the displacement's Jacobian I + J (the tangents'
/// horizontal parts, src/model/masking.rs `surface`), symmetric for trochoids; None where the
/// surface folds (det <= 0).
fn displaced_slope(wave_set: &crate::model::waves::WaveSet, x: [f64; 2]) -> Option<f64> {
    let (_, tx, ty) = crate::model::masking::surface(wave_set, 0.0, glam::DVec2::from(x));
    slope_through(tx, ty)
}

/// The height slope of a surface with tangents tx = d p / d x, ty = d p / d y at a rest position:
/// the height's gradient through the inverse of their horizontal parts; None where it folds.
fn slope_through(tx: glam::DVec3, ty: glam::DVec3) -> Option<f64> {
    let det = tx.x * ty.y - ty.x * tx.y;
    (det > 0.0).then(|| ((ty.y * tx.z - ty.x * ty.z) / det).hypot((tx.x * ty.z - tx.y * tx.z) / det))
}

/// The fewest marching steps a ray gets.
const MIN_MARCH: u32 = 8;

#[derive(Debug, Clone, serde::Serialize)]
pub struct GroundTruthReport {
    pub device: String,
    /// The image's size; the region traced where only part of it was (`--region`).
    pub width: u32,
    pub height: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub region: Option<Region>,
    pub samples_per_axis: u32,
    pub gpu_seconds: f64,
    /// RMS over all pixels of |L_N - L_(N/2)| / mean L: the N x N estimate against its
    /// (N/2) x (N/2) subset of strata, a measure of how far the estimate still moves.
    pub convergence_rms_relative: Option<f64>,
    /// The estimate's own noise over the sea, as an RMSE of Rec. 709 luminance (kcd/m^2): the
    /// error a perfect method would still show against it (see `noise_floor`).
    pub noise_floor_rmse: Option<f64>,
    /// Pixels whose sub-samples step more than half a turn of the shortest wave.
    pub unresolved_pixels: u64,
    /// Reflected rays traced again where they meet the sea (`--bounces`).
    pub bounces: u32,
    /// The cone (angular radius, degrees) the reflected sun's energy is spread over
    /// (`--sun-kernel-deg`, narrowed to the sun's elevation where that is lower).
    pub sun_kernel_deg: f64,
    /// The reflected weight left untraced after the last bounce, as a fraction of the sea's
    /// samples' reflected weight, and its mean over the sea's pixels (what `--bounces` cuts off).
    pub cut_off_fraction: f64,
    /// The camera rays over the sea that ran out of marching steps, as a fraction of the sea's
    /// samples: their hit was found by bisecting a bracket, which may hold a later crossing than
    /// the first (a crest hidden behind another).
    #[serde(default)]
    pub unfinished_camera_fraction: f64,
    /// The reflected weight whose rays ran out of marching steps (going up, taken as leaving:
    /// the sky and sun they may not see), as a fraction of the sea's samples' reflected weight.
    #[serde(default)]
    pub unfinished_reflected_fraction: f64,
    pub nonfinite_pixels: u64,
    pub mean_radiance: [f64; 3],
    pub validation_errors: u32,
    /// The physical sky's own error (absent under Preetham's, which is evaluated in closed form):
    /// what the tables, the quadrature and the GPU's f32 carry of it (truth_sky).
    pub sky_error: Option<TruthSkyError>,
}

pub struct GroundTruth {
    /// The size of the images below: the region traced (the whole image by default).
    pub width: u32,
    pub height: u32,
    /// Mean radiance per pixel (rgb) and 1 where resolved, 0 where not (a).
    pub radiance: Vec<[f32; 4]>,
    /// The (N/2) x (N/2) subset estimate (rgb, a unused).
    pub subset: Vec<[f32; 4]>,
    /// The reflected sun, the reflected sky and the refracted sea light (rgb; a = 1).
    pub sun: Vec<[f32; 4]>,
    pub sky: Vec<[f32; 4]>,
    pub sea: Vec<[f32; 4]>,
    /// The variance of each pixel's mean luminance: total, sun, sky, sea (rgba), for the
    /// uncertainty of the energies compared with it (NAME.var.exr).
    pub variance: Vec<[f32; 4]>,
    /// The luminance of each pixel's estimate from half its samples (the strata with i + j even):
    /// total, sun, sky, sea (rgba; NAME.half.exr). Independent of the other half's, so the noise
    /// of any statistic of the image shows in the halves' difference. None below 2 x 2 samples.
    pub half: Option<Vec<[f32; 4]>>,
    pub report: GroundTruthReport,
}

/// What a sky pixel costs against a sea pixel (no march, no sun ray): a sky tile is far from free,
/// but an order of magnitude cheaper. Only the estimate of the time left depends on it.
const SKY_PIXEL_COST: u64 = 1;
const SEA_PIXEL_COST: u64 = 16;

/// Each tile's share of the work, in units of one sky pixel (`sees_sea[y * width + x]` marks the
/// pixels that see the sea): for an estimate of the time left that holds while the top rows
/// (sky) go fast and the rows near the eye go slow.
fn tile_costs(sees_sea: &[bool], width: u32, height: u32) -> Vec<u64> {
    let (tiles_x, tiles_y) = (width.div_ceil(TILE), height.div_ceil(TILE));
    let mut costs = Vec::with_capacity((tiles_x * tiles_y) as usize);
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            let xs = tx * TILE..((tx + 1) * TILE).min(width);
            let ys = ty * TILE..((ty + 1) * TILE).min(height);
            let cost = ys
                .flat_map(|y| xs.clone().map(move |x| (y * width + x) as usize))
                .map(|i| if sees_sea[i] { SEA_PIXEL_COST } else { SKY_PIXEL_COST })
                .sum();
            costs.push(cost);
        }
    }
    costs
}

/// Renders the ground truth of `scene`; `progress(done, total)` is called before the first tile
/// and after every tile, in units of work (`tile_costs`), not tiles.
pub fn render(
    gpu: &Gpu,
    scene: &Scene,
    width: u32,
    height: u32,
    sampling: &Sampling,
    mut progress: impl FnMut(u64, u64),
) -> Result<GroundTruth> {
    sampling.check()?;
    // A cone reaching below the horizon would lose the part of the sun's energy that no
    // reflected ray can gather there: it is narrowed to the sun's elevation (the disc at least).
    let sampling = Sampling {
        sun_kernel_deg: sampling.sun_kernel_deg.min(scene.sun.elevation_deg.max(sun_disc_deg())),
        ..*sampling
    };
    let Sampling { samples, bounces, sun_kernel_deg, region } = sampling;
    let (sun_cos_kernel, sun_kernel_scale) = sampling.sun_kernel();
    let physical = scene.sky.model == SkyKind::Physical;
    let device = &gpu.device;
    if width == 0 || height == 0 {
        return Err(Error::Argument(format!("ground-truth size {width}x{height} is out of range: at least 1x1")));
    }
    let region = region.unwrap_or(Region::whole(width, height));
    region.check(width, height)?;
    let pixels = region.pixels() as u64;
    let limits = &device.properties.limits;
    if BYTES_PER_PIXEL * pixels > limits.max_storage_buffer_range as u64 {
        return Err(Error::Argument(format!(
            "ground-truth size {}x{} is out of range on {} (at most {} pixels; --region traces part of it)",
            region.width,
            region.height,
            device.name,
            limits.max_storage_buffer_range as u64 / BYTES_PER_PIXEL
        )));
    }
    let before = gpu.validation_counts().error_total();
    let mut wave_set = waves::generate(scene);
    // The scene's local waves at its time, every packet (no budget), binned here.
    let sources = Sources::of_named_scene(scene, "(scene)")?;
    let packets = (!sources.is_empty()).then(|| {
        let eye = glam::DVec2::new(scene.camera.x_m, scene.camera.y_m);
        let all = Sources { max_alive: usize::MAX, ..sources.clone() };
        FramePackets::everywhere(&all, scene.render.time_s, eye, usize::MAX, TRUTH_CELLS_PER_SIDE)
    });
    wave_set.packet_crest_m = packets.as_ref().map_or(0.0, |p| p.grid.crest_m);
    wave_set.packet_longest_m = packets.as_ref().map_or(0.0, |p| p.field.longest_wavelength());
    let mut data = frame::build(scene, &wave_set, width, height, scene.render.grid_cell_px);
    let field = packets.as_ref().map(|p| &p.field);
    let objects = TruthObjects::new(scene, &wave_set, field, width as f64 / height as f64)?;
    let lists = packets.as_ref().map(|p| p.grid.lists());
    let (packet_words, cell_words, packet_run) = match packets.as_ref().zip(lists.as_ref()) {
        Some((p, (starts, lists))) => {
            (data.uniforms.packet_grid, data.uniforms.packet_map, data.uniforms.packet_dims) = p.uniforms();
            // Each run padded to whole iterations of the shader's loop with a packet past the
            // last, which reaches nowhere (its centre beyond every rest position).
            let pad = PACKETS_PER_ITERATION as usize;
            let nowhere = p.gpu.len() as u32;
            let mut cells = Vec::with_capacity(starts.len() + lists.len() * 2);
            let mut padded = Vec::with_capacity(lists.len() * 2);
            for w in starts.windows(2) {
                cells.push(padded.len() as u32);
                padded.extend(&lists[w[0] as usize..w[1] as usize]);
                padded.resize(padded.len().next_multiple_of(pad), nowhere);
            }
            cells.push(padded.len() as u32);
            let run =
                starts.windows(2).map(|w| (w[1] - w[0]).next_multiple_of(PACKETS_PER_ITERATION)).max().unwrap_or(0);
            cells.extend(padded);
            let mut words = p.gpu.clone();
            // Far from every rest position (a finite distance: the envelope's products stay finite).
            words.push(GpuPacket {
                centre_k: [1e30, 1e30, 1.0, 0.0],
                envelope: [1.0, 0.0, 0.0, 1.0],
                ..GpuPacket::default()
            });
            (words, cells, run)
        }
        None => (vec![GpuPacket::default()], vec![0u32], 0),
    };

    use vk::BufferUsageFlags as B;
    let uniforms = Buffer::new(
        gpu,
        "ground truth frame",
        std::mem::size_of_val(&data.uniforms) as u64,
        B::UNIFORM_BUFFER,
        Location::Upload,
    )?;
    uniforms.write(std::slice::from_ref(&data.uniforms))?;
    let mut exact: Vec<[f32; 4]> = wave_set
        .trains
        .iter()
        .map(|t| {
            [
                (t.direction[0] / t.wavelength) as f32,
                (t.direction[1] / t.wavelength) as f32,
                (t.phase_at(scene.render.time_s) / std::f64::consts::TAU) as f32,
                t.amplitude as f32,
            ]
        })
        .collect();
    // Padded to whole iterations with trains of no amplitude (a unit wave vector keeps their
    // direction finite); the shortest train stays first.
    exact.resize(exact.len().next_multiple_of(TRAINS_PER_ITERATION), [1.0, 0.0, 0.0, 0.0]);
    let waves_buffer = Buffer::new(gpu, "exact waves", (16 * exact.len()) as u64, B::STORAGE_BUFFER, Location::Upload)?;
    waves_buffer.write(&exact)?;
    let output =
        Buffer::new(gpu, "ground truth pixels", BYTES_PER_PIXEL * pixels, B::STORAGE_BUFFER, Location::Readback)?;

    use vk::DescriptorType as D;
    let stages = vk::ShaderStageFlags::COMPUTE;
    // The physical sky's tables (a word in their place under Preetham's), and its check's results.
    let camera = frame::CameraFrame::new(scene, &wave_set, width, height);
    let sky_tables = physical.then(|| TruthSkyTables::new(scene, camera.eye_height, data.sky.sun_dir));
    let table_words: &[[f32; 4]] = sky_tables.as_ref().map_or(&[[0.0; 4]], |t| &t.words);
    let tables = Buffer::new(
        gpu,
        "ground truth sky tables",
        (16 * table_words.len()) as u64,
        B::STORAGE_BUFFER,
        Location::Upload,
    )?;
    tables.write(table_words)?;
    let check_words = 2 * truth_sky::CHECKS as usize;
    let check =
        Buffer::new(gpu, "ground truth sky check", (16 * check_words) as u64, B::STORAGE_BUFFER, Location::Readback)?;
    // The objects' hierarchy, triangles and materials (a word each in their place without).
    let words: [&[[u32; 4]]; 3] = match &objects {
        Some(o) => [&o.nodes, &o.triangles, &o.materials],
        None => [&[[0; 4]]; 3],
    };
    let object_buffers =
        ["ground truth object nodes", "ground truth object triangles", "ground truth object materials"]
            .iter()
            .zip(&words)
            .map(|(name, words)| {
                let buffer = Buffer::new(gpu, name, (16 * words.len()) as u64, B::STORAGE_BUFFER, Location::Upload)?;
                buffer.write(words)?;
                Ok(buffer)
            })
            .collect::<Result<Vec<_>>>()?;
    let bindings = Bindings::with_push_constants(
        device,
        "ground truth",
        &[
            (0, D::UNIFORM_BUFFER, stages),
            (1, D::STORAGE_BUFFER, stages),
            (2, D::STORAGE_BUFFER, stages),
            (3, D::STORAGE_BUFFER, stages),
            (4, D::STORAGE_BUFFER, stages),
            (5, D::STORAGE_BUFFER, stages),
            (6, D::STORAGE_BUFFER, stages),
            (8, D::STORAGE_BUFFER, stages),
            (9, D::STORAGE_BUFFER, stages),
            (10, D::STORAGE_BUFFER, stages),
        ],
        std::mem::size_of::<TilePush>() as u32,
    )?;
    for (binding, buffer) in (4..).zip(&object_buffers) {
        bindings.write_buffer(binding, D::STORAGE_BUFFER, buffer.raw);
    }
    bindings.write_buffer(0, D::UNIFORM_BUFFER, uniforms.raw);
    bindings.write_buffer(1, D::STORAGE_BUFFER, waves_buffer.raw);
    bindings.write_buffer(2, D::STORAGE_BUFFER, tables.raw);
    bindings.write_buffer(3, D::STORAGE_BUFFER, check.raw);
    bindings.write_buffer(8, D::STORAGE_BUFFER, output.raw);
    let packet_buffer = Buffer::new(
        gpu,
        "ground truth packets",
        std::mem::size_of_val(packet_words.as_slice()) as u64,
        B::STORAGE_BUFFER,
        Location::Upload,
    )?;
    packet_buffer.write(&packet_words)?;
    let cell_buffer = Buffer::new(
        gpu,
        "ground truth packet cells",
        4 * cell_words.len() as u64,
        B::STORAGE_BUFFER,
        Location::Upload,
    )?;
    cell_buffer.write(&cell_words)?;
    bindings.write_buffer(9, D::STORAGE_BUFFER, packet_buffer.raw);
    bindings.write_buffer(10, D::STORAGE_BUFFER, cell_buffer.raw);
    // Specialization constants 8 (glsl/sky.glsl SKY_PHYSICAL): which sky the samples see; 20
    // and 21 (glsl/groundtruth_objects.glsl HAS_OBJECTS, BVH_VISITS): whether rays meet objects,
    // and the visits a walk may take, as the loop budget reserved them.
    let specialization = Specialization::constants(&[
        (8, physical as u32),
        (20, objects.is_some() as u32),
        (21, truth_objects::BVH_VISITS),
    ]);
    let pipeline = specialized_compute_pipeline(
        device,
        bindings.layout(),
        shaders::GROUNDTRUTH_COMP,
        Some(&specialization),
        "ground truth",
    )?;

    let commands = Commands::new(device, "ground truth")?;
    let cmd = commands.cmd;

    let (max_march, bounce_march) = march_budget(exact.len() as u32, packet_run, bounces, physical, objects.is_some())?;
    let slopes = marching_slopes(&wave_set, packets.as_ref().zip(lists.as_ref()));
    let slab = wave_set.highest_crest();
    let push = TilePush {
        origin: [0, 0],
        samples,
        stratum: 0,
        max_march,
        bounces,
        bounce_march,
        wave_count: exact.len() as u32,
        slab: slab as f32,
        lipschitz: slopes.1 as f32,
        ior: crate::model::fresnel::SEA_WATER_IOR as f32,
        seed: scene.waves.seed as u32,
        sun_cos_kernel,
        sun_kernel_scale,
        region: [region.x, region.y, region.width, region.height],
        train_slab: wave_set.trains_highest_crest() as f32,
        train_lipschitz: slopes.0 as f32,
        packet_reach: packets.as_ref().map_or([[1.0; 2], [-1.0; 2]], |p| packet_reach(&p.grid, slab)),
    };
    let tiles_x = region.width.div_ceil(TILE);
    let tiles_y = region.height.div_ceil(TILE);
    let sky_error = match &sky_tables {
        Some(t) => {
            let results = check_sky(device, &commands, &bindings, pipeline.raw, &check, push, stages)?;
            Some(t.errors(&results, camera.eye_height, data.sky.sun_dir))
        }
        None => None,
    };
    // Which of the region's pixels see the sea: for the tiles' costs and the noise floor.
    let sees_sea: Vec<bool> = (0..region.pixels())
        .map(|i| region.image_pixel(i))
        .map(|(x, y)| camera.pixel_distance(x, y, width, height).is_some())
        .collect();
    let costs = tile_costs(&sees_sea, region.width, region.height);
    let total: u64 = costs.iter().sum();
    let mut done = 0;
    progress(0, total);
    let started = Instant::now();
    for ty in 0..tiles_y {
        for tx in 0..tiles_x {
            let origin = [tx * TILE, ty * TILE];
            commands.begin()?;
            // Each tile's submission is waited for before the next: its barriers start afresh.
            let mut barriers = Tracker::default();
            // SAFETY: `cmd` is recording; every binding refers to live buffers; the push range
            // matches the layout.
            unsafe {
                let raw = &device.raw;
                raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &[]);
                // One dispatch per stratum, each adding to the pixels the previous one wrote.
                for stratum in 0..samples * samples {
                    barriers.buffer(&output, Access::ComputeStorageReadWrite);
                    barriers.flush(raw, cmd);
                    let push = TilePush { origin, stratum, ..push };
                    raw.cmd_push_constants(cmd, bindings.layout(), stages, 0, push_bytes(&push));
                    raw.cmd_dispatch(cmd, TILE.div_ceil(8), TILE.div_ceil(8), 1);
                }
                // The host reads the pixels after the last tile's fence.
                barriers.buffer(&output, Access::HostRead);
                barriers.flush(raw, cmd);
            }
            commands.submit_and_wait()?;
            done += costs[(ty * tiles_x + tx) as usize];
            progress(done, total);
        }
    }
    let gpu_seconds = started.elapsed().as_secs_f64();
    let words: Vec<f32> = output.read(WORDS_PER_PIXEL * pixels as usize)?;
    // Sums to means: N x N samples, and the strata with even indices on both axes.
    let all = (samples * samples) as f32;
    let even = samples.div_ceil(2).pow(2) as f32;
    let mean = |p: &[f32], count: f32, a: f32| [p[0] / count, p[1] / count, p[2] / count, a];
    let radiance: Vec<[f32; 4]> = words.chunks_exact(WORDS_PER_PIXEL).map(|p| mean(&p[0..4], all, p[3])).collect();
    let subset: Vec<[f32; 4]> = words.chunks_exact(WORDS_PER_PIXEL).map(|p| mean(&p[4..8], even, 0.0)).collect();
    let sun: Vec<[f32; 4]> = words.chunks_exact(WORDS_PER_PIXEL).map(|p| mean(&p[8..12], all, 1.0)).collect();
    let sky: Vec<[f32; 4]> = words.chunks_exact(WORDS_PER_PIXEL).map(|p| mean(&p[12..16], all, 1.0)).collect();
    // The refracted light: the weight 1 - F times the light entering the water at each sample's
    // sea point (the sky's irradiance there), summed by the shader.
    let sea: Vec<[f32; 4]> = words.chunks_exact(WORDS_PER_PIXEL).map(|p| mean(&p[24..28], all, 1.0)).collect();
    // The sea's luminance per unit of refracted weight in a pixel (the light entering there).
    let sea_per_weight = |p: &[f32]| if p[7] > 0.0 { luminance3(&p[24..27]) / p[7] } else { 0.0 };
    // The cut-off weight (sun's sums, a) over the sea's pixels, against their reflected weight:
    // the mean of F summed over the hits traced, i.e. the samples less the refracted weight.
    let (cut, reflected): (f64, f64) = sees_sea
        .iter()
        .zip(words.chunks_exact(WORDS_PER_PIXEL))
        .filter(|(sea, _)| **sea)
        .fold((0.0, 0.0), |(c, r), (_, p)| (c + p[11] as f64, r + (all - p[7]).max(0.0) as f64));
    let cut_off_fraction = if reflected > 0.0 { cut / reflected } else { 0.0 };
    // The rays that ran out of steps: the reflected weight (sky's sums, a) and the camera rays
    // (sea's sums, a), over the sea's pixels.
    let (unfinished_reflected, unfinished_camera, sea_samples) = sees_sea
        .iter()
        .zip(words.chunks_exact(WORDS_PER_PIXEL))
        .filter(|(sea, _)| **sea)
        .fold((0.0, 0.0, 0.0), |(r, c, n), (_, p)| (r + p[15] as f64, c + p[27] as f64, n + all as f64));
    let unfinished_reflected_fraction = if reflected > 0.0 { unfinished_reflected / reflected } else { 0.0 };
    let unfinished_camera_fraction = if sea_samples > 0.0 { unfinished_camera / sea_samples } else { 0.0 };
    // The variance of each pixel's mean (luminance, per term): the samples' variance over their
    // count, strata taken as independent samples (stratification only lowers it: an upper bound).
    let variance: Vec<[f32; 4]> = words
        .chunks_exact(WORDS_PER_PIXEL)
        .map(|p| {
            let sums = [
                crate::output::luminance([p[0], p[1], p[2], 0.0]) as f32,
                luminance3(&p[8..11]),
                luminance3(&p[12..15]),
                p[7],
            ];
            std::array::from_fn(|t| {
                if all < 2.0 {
                    return 0.0;
                }
                let mean = sums[t] / all;
                let var = ((p[16 + t] - all * mean * mean) / (all - 1.0)).max(0.0) / all;
                if t == 3 {
                    var * sea_per_weight(p).powi(2)
                } else {
                    var
                }
            })
        })
        .collect();
    // The half estimate: the strata with i + j even, ceil(N^2 / 2) of them.
    let half_count = (samples * samples).div_ceil(2) as f32;
    let half = (samples >= 2).then(|| {
        words
            .chunks_exact(WORDS_PER_PIXEL)
            .map(|p| {
                let h = &p[20..24];
                [h[0] / half_count, h[1] / half_count, h[2] / half_count, h[3] / half_count * sea_per_weight(p)]
            })
            .collect()
    });
    let stats = crate::output::stats(&radiance);
    let unresolved_pixels = radiance.iter().filter(|p| p[3] == 0.0).count() as u64;
    let convergence_rms_relative = (samples >= 2).then(|| convergence(&radiance, &subset, stats.mean_radiance));
    let sea_pixels: Vec<usize> = (0..sees_sea.len()).filter(|&i| sees_sea[i]).collect();
    let noise_floor_rmse = (samples >= 2).then(|| noise_floor(&radiance, &subset, &sea_pixels));
    let report = GroundTruthReport {
        device: device.name.clone(),
        width,
        height,
        region: (region != Region::whole(width, height)).then_some(region),
        samples_per_axis: samples,
        gpu_seconds,
        convergence_rms_relative,
        noise_floor_rmse,
        unresolved_pixels,
        bounces,
        sun_kernel_deg,
        cut_off_fraction,
        unfinished_camera_fraction,
        unfinished_reflected_fraction,
        nonfinite_pixels: stats.nonfinite_pixels,
        mean_radiance: stats.mean_radiance,
        validation_errors: gpu.validation_counts().error_total() - before,
        sky_error,
    };
    Ok(GroundTruth {
        width: region.width,
        height: region.height,
        radiance,
        subset,
        sun,
        sky,
        sea,
        variance,
        half,
        report,
    })
}

/// Runs the physical sky's check (glsl/groundtruth.comp `check`: truth_sky::CHECKS evaluations at
/// arguments the CPU repeats in f64) and reads its results back.
fn check_sky(
    device: &crate::vk::device::Device,
    commands: &Commands,
    bindings: &Bindings,
    pipeline: vk::Pipeline,
    results: &Buffer,
    push: TilePush,
    stages: vk::ShaderStageFlags,
) -> Result<Vec<[f32; 4]>> {
    let cmd = commands.cmd;
    commands.begin()?;
    let push = TilePush { stratum: CHECK_STRATUM, samples: truth_sky::CHECKS, ..push };
    let mut barriers = Tracker::default();
    barriers.buffer(results, Access::ComputeStorageWrite);
    // SAFETY: `cmd` is recording; the bindings refer to live buffers; the push range matches the
    // layout.
    unsafe {
        let raw = &device.raw;
        raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline);
        bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &[]);
        raw.cmd_push_constants(cmd, bindings.layout(), stages, 0, push_bytes(&push));
        raw.cmd_dispatch(cmd, truth_sky::CHECKS.div_ceil(64), 1, 1);
        barriers.buffer(results, Access::HostRead);
        barriers.flush(raw, cmd);
    }
    commands.submit_and_wait()?;
    let words: Vec<f32> = results.read(8 * truth_sky::CHECKS as usize)?;
    Ok(words.chunks_exact(4).map(|w| [w[0], w[1], w[2], w[3]]).collect())
}

/// The stratum that asks glsl/groundtruth.comp for the sky's check instead of samples.
const CHECK_STRATUM: u32 = u32::MAX;

fn push_bytes(push: &TilePush) -> &[u8] {
    // SAFETY: TilePush is repr(C) plain data without padding (u32 and f32 fields only).
    unsafe { std::slice::from_raw_parts(push as *const TilePush as *const u8, std::mem::size_of::<TilePush>()) }
}

fn luminance3(c: &[f32]) -> f32 {
    crate::output::luminance([c[0], c[1], c[2], 0.0]) as f32
}

fn convergence(full: &[[f32; 4]], subset: &[[f32; 4]], mean: [f64; 3]) -> f64 {
    let mean_l = (mean[0] + mean[1] + mean[2]) / 3.0;
    let (mut sum, mut n) = (0.0, 0.0);
    for (a, b) in full.iter().zip(subset) {
        for c in 0..3 {
            let d = (a[c] - b[c]) as f64;
            sum += d * d;
        }
        n += 3.0;
    }
    if n == 0.0 || mean_l <= 0.0 {
        0.0
    } else {
        (sum / n).sqrt() / mean_l
    }
}

/// The ground truth's noise as an RMSE over `pixels`, in luminance: with the N x N mean F and its
/// (N/2) x (N/2) subset S (a quarter of the samples), F - S = 3/4 (R - S) for the mean R of the
/// other three quarters, so Var(F - S) = 9/16 (4 + 4/3) Var(F) = 3 Var(F): the noise of F is
/// RMS(F - S) / sqrt(3), strata taken as independent samples.
fn noise_floor(full: &[[f32; 4]], subset: &[[f32; 4]], pixels: &[usize]) -> f64 {
    if pixels.is_empty() {
        return 0.0;
    }
    let luminance = crate::output::luminance;
    let sum: f64 = pixels.iter().map(|&i| (luminance(full[i]) - luminance(subset[i])).powi(2)).sum();
    (sum / pixels.len() as f64 / 3.0).sqrt()
}

/// What a saved ground truth carries besides its images: enough to refuse comparing it with
/// another scene or size.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct GroundTruthMeta {
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub samples_per_axis: u32,
    /// `GroundTruthReport::noise_floor_rmse` (absent in files from before it was measured).
    #[serde(default)]
    pub noise_floor_rmse: Option<f64>,
    /// `GroundTruthReport::sun_kernel_deg` (absent in files from before the kernel: the disc).
    #[serde(default = "sun_disc_deg")]
    pub sun_kernel_deg: f64,
    /// `GroundTruthReport::bounces` (absent in files from before bounces were traced: none).
    #[serde(default)]
    pub bounces: u32,
    /// `GroundTruthReport::sky_error` (absent under Preetham's sky and in older files).
    #[serde(default)]
    pub sky_error: Option<TruthSkyError>,
    /// The part of the width x height image traced (`--region`; the images are its size), or
    /// None for the whole image.
    #[serde(default)]
    pub region: Option<Region>,
}

impl GroundTruthMeta {
    /// The region traced: the whole image unless `--region` said otherwise.
    pub fn region(&self) -> Region {
        self.region.unwrap_or(Region::whole(self.width, self.height))
    }
}

impl GroundTruthMeta {
    /// Whether this ground truth is one of `scene`: equal but for the render settings the ground
    /// truth never reads (the grid, the sky map's sampler, the shadow map, the display's exposure
    /// and curve: it traces the waves exactly and writes linear radiance), so the methods can be
    /// measured with those settings changed. The waves' time, the camera, sun, sky and sea count.
    pub fn is_of(&self, scene: &Scene) -> bool {
        let mut as_traced = scene.clone();
        let (ours, theirs) = (&self.scene.render, &mut as_traced.render);
        theirs.grid_cell_px = ours.grid_cell_px;
        theirs.sky_anisotropy = ours.sky_anisotropy;
        theirs.shadow_map = ours.shadow_map;
        theirs.shadow_map_size = ours.shadow_map_size;
        theirs.exposure = ours.exposure;
        theirs.ev100 = ours.ev100;
        theirs.tone_curve = ours.tone_curve;
        as_traced == self.scene
    }
}

fn sun_disc_deg() -> f64 {
    crate::model::sky::SUN_ANGULAR_RADIUS.to_degrees()
}

/// The images of a ground truth on disk: `ref.exr` (total, alpha = resolved), and `ref.sun.exr`,
/// `ref.sky.exr`, `ref.sea.exr`, `ref.var.exr` and `ref.half.exr` (where it has halves) beside it,
/// plus `ref.exr.json` (GroundTruthMeta).
pub struct GroundTruthFiles {
    pub meta: GroundTruthMeta,
    pub total: Vec<[f32; 4]>,
    pub sun: Vec<[f32; 4]>,
    pub sky: Vec<[f32; 4]>,
    pub sea: Vec<[f32; 4]>,
    /// Variance of each pixel's mean luminance: total, sun, sky, sea.
    pub variance: Vec<[f32; 4]>,
    /// The half estimate's luminances: total, sun, sky, sea (GroundTruth::half); None in files
    /// from before halves were kept, or below 2 x 2 samples.
    pub half: Option<Vec<[f32; 4]>>,
}

fn sibling(path: &std::path::Path, suffix: &str) -> std::path::PathBuf {
    let stem = path.file_stem().unwrap_or_default().to_string_lossy();
    path.with_file_name(format!("{stem}.{suffix}"))
}

fn meta_path(path: &std::path::Path) -> std::path::PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".json");
    path.with_file_name(name)
}

impl GroundTruth {
    pub fn save(&self, scene: &Scene, path: &std::path::Path) -> Result<()> {
        use crate::output::{write_exr_rgba, write_text};
        write_exr_rgba(path, self.width, self.height, &self.radiance)?;
        write_exr_rgba(&sibling(path, "sun.exr"), self.width, self.height, &self.sun)?;
        write_exr_rgba(&sibling(path, "sky.exr"), self.width, self.height, &self.sky)?;
        write_exr_rgba(&sibling(path, "sea.exr"), self.width, self.height, &self.sea)?;
        write_exr_rgba(&sibling(path, "var.exr"), self.width, self.height, &self.variance)?;
        let half_path = sibling(path, "half.exr");
        match &self.half {
            Some(half) => write_exr_rgba(&half_path, self.width, self.height, half)?,
            // A stale file of an earlier ground truth must not pass for this one's halves.
            None => match std::fs::remove_file(&half_path) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(Error::io(&half_path, e)),
                _ => {}
            },
        }
        let meta = GroundTruthMeta {
            scene: scene.clone(),
            width: self.report.width,
            height: self.report.height,
            samples_per_axis: self.report.samples_per_axis,
            noise_floor_rmse: self.report.noise_floor_rmse,
            sun_kernel_deg: self.report.sun_kernel_deg,
            bounces: self.report.bounces,
            sky_error: self.report.sky_error,
            region: self.report.region,
        };
        write_text(&meta_path(path), &serde_json::to_string_pretty(&meta).expect("serializes"))
    }
}

impl GroundTruthFiles {
    pub fn load(path: &std::path::Path) -> Result<GroundTruthFiles> {
        let meta_file = meta_path(path);
        let text = std::fs::read_to_string(&meta_file)
            .map_err(|e| Error::Io { path: meta_file.clone(), message: format!("ground truth metadata: {e}") })?;
        let meta: GroundTruthMeta = serde_json::from_str(&text)
            .map_err(|e| Error::Io { path: meta_file.clone(), message: format!("not ground truth metadata: {e}") })?;
        let read = |p: &std::path::Path| -> Result<Vec<[f32; 4]>> {
            let (w, h, pixels) = crate::output::read_exr(p)?;
            let region = meta.region();
            if (w, h) != (region.width, region.height) {
                return Err(Error::Io {
                    path: p.to_owned(),
                    message: format!("is {w}x{h}, its metadata says {}x{}", region.width, region.height),
                });
            }
            Ok(pixels)
        };
        Ok(GroundTruthFiles {
            total: read(path)?,
            sun: read(&sibling(path, "sun.exr"))?,
            sky: read(&sibling(path, "sky.exr"))?,
            sea: read(&sibling(path, "sea.exr"))?,
            variance: read(&sibling(path, "var.exr"))?,
            half: {
                let half_path = sibling(path, "half.exr");
                if half_path.exists() {
                    Some(read(&half_path)?)
                } else {
                    None
                }
            },
            meta,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::ShadowMapMode;

    fn meta(scene: Scene) -> GroundTruthMeta {
        GroundTruthMeta {
            scene,
            width: 8,
            height: 8,
            samples_per_axis: 2,
            noise_floor_rmse: None,
            sun_kernel_deg: 2.0,
            bounces: 3,
            sky_error: None,
            region: None,
        }
    }

    #[test]
    fn the_loop_budget_fits_every_scene_and_names_what_it_cannot_trace() {
        // In steps at the evaluation's cost (the pools are loop iterations).
        let steps = |waves: u32, iterations: u32| iterations / step_iterations(waves, 0);
        let limit = crate::model::scene::MAX_WAVES;
        let (camera, reflected) = march_budget(limit, 0, MAX_BOUNCES, true, true).unwrap();
        let (camera, reflected) = (steps(limit, camera), steps(limit, reflected));
        assert!(camera > reflected && reflected >= MIN_MARCH * 8, "{camera}, {reflected}");
        // The default scene's march: about 1 450 steps for the camera ray.
        let (camera, reflected) = march_budget(60, 0, DEFAULT_BOUNCES, true, true).unwrap();
        let (camera, reflected) = (steps(60, camera), steps(60, reflected));
        assert!(camera >= 1400 && reflected >= 700, "{camera}, {reflected}");
        // Over lists shorter than the longest a march takes more steps than the longest allows.
        let (camera, _) = march_budget(60, 256, DEFAULT_BOUNCES, true, false).unwrap();
        let (at_longest, over_none) = (camera / step_iterations(60, 256), steps(60, camera));
        assert!(at_longest >= MIN_MARCH && over_none > 3 * at_longest, "{at_longest} {over_none}");
        let e = march_budget(4096, 0, 3, true, false).unwrap_err().to_string();
        assert!(e.contains("waves.count = 4096") && e.contains("--bounces 3"), "{e}");
    }

    #[test]
    fn the_marching_slope_bounds_the_surfaces_slope_and_is_strict_where_it_can_be() {
        // A calm sea cannot fold: the strict bound sum k h / (1 - sum k h) holds, or a lower one.
        let mut calm = Scene::default();
        calm.wind.speed_mps = 3.0;
        calm.waves.count = 8;
        let waves = crate::model::waves::generate(&calm);
        let kh: f64 = waves.trains.iter().map(|t| t.k * t.amplitude).sum();
        assert!(kh < 0.9, "{kh}");
        assert!(marching_slopes(&waves, None).0 <= kh / (1.0 - kh));
        // The default's 60 trains sum past 1: the probed bound, below the former fixed 10 and
        // above the displaced surface's slope at points the probes never met.
        let waves = crate::model::waves::generate(&Scene::default());
        let bound = marching_slopes(&waves, None).0;
        assert!(bound < 5.0, "{bound}");
        let mut steepest: f64 = 0.0;
        for n in 0..20_000u32 {
            // Other rest positions: a coarse lattice far from the probes' square.
            let x = [1.0e4 + 0.37 * n as f64, -2.0e4 + 0.61 * (n % 997) as f64];
            steepest = steepest.max(displaced_slope(&waves, x).expect("no fold"));
        }
        assert!(steepest < bound / 1.5, "slope {steepest} against the bound {bound}");
    }

    #[test]
    fn a_ground_truth_serves_every_setting_it_never_reads() {
        let truth = meta(Scene::default());
        let mut scene = Scene::default();
        scene.render.shadow_map = ShadowMapMode::On;
        scene.render.grid_cell_px = 4.0;
        scene.render.sky_anisotropy = 1.0;
        scene.render.exposure = Some(0.5);
        assert!(truth.is_of(&scene), "render-only settings must not refuse the ground truth");
        // What the ground truth traces must match.
        for change in [
            |s: &mut Scene| s.render.time_s += 1.0,
            |s: &mut Scene| s.camera.pitch_deg -= 1.0,
            |s: &mut Scene| s.sun.elevation_deg += 1.0,
            |s: &mut Scene| s.wind.speed_mps += 1.0,
        ] {
            let mut other = Scene::default();
            change(&mut other);
            assert!(!truth.is_of(&other), "{other:?}");
        }
    }
}
