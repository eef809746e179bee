//! `ocean`: the command-line program.

use clap::{Parser, Subcommand};
use ocean::app::{self, RenderRequest};
use ocean::render::passes::ocean::{Method, ShaderConfig, Terms, TrainReads};

/// The sea's radiance terms, for --terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Term {
    Sun,
    Sky,
    Sea,
}
use ocean::app::window::view::PresentMode;
use ocean::embed::Shading;
use ocean::model::scene::{Reflections, Scene};
use ocean::output::progress::Progress;
use ocean::output::target::is_stdout;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(name = "ocean", version, about = "Vulkan ocean renderer (Bruneton, Neyret & Holzschuch 2010)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// What `render`, `reference` and `animate` all take: the scene, the image size, the device.
#[derive(clap::Args)]
struct ViewArgs {
    /// Scene file (TOML); without it, the built-in defaults (scenes/default.toml).
    #[arg(long)]
    scene: Option<PathBuf>,
    #[arg(long, default_value_t = 1024)]
    width: u32,
    #[arg(long, default_value_t = 768)]
    height: u32,
    /// Enable the Khronos validation layer with synchronization validation.
    #[arg(long)]
    validation: bool,
    /// Use the first device whose name contains this text.
    #[arg(long)]
    device: Option<String>,
}

/// Glints on or off (--glints).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Switch {
    On,
    Off,
}

/// The method and its glints, for the commands that render with one.
#[derive(clap::Args)]
struct MethodArgs {
    /// How waves are split between geometry, normals and BRDF.
    #[arg(long, value_enum, default_value_t = Method::Full)]
    method: Method,
    /// The reflected sun as glints, a count of lit facets per pixel (the full method's default),
    /// or as its expected value (every other method's, and the only one they have).
    #[arg(long, value_enum)]
    glints: Option<Switch>,
    /// How the sea reflects the scene's objects: `screen` traces each pixel's reflection in
    /// screen space against the objects' depth (glsl/shade.glsl local_reflection), `planar` reads
    /// the objects drawn again mirrored about the sea (planar_reflection), `both` the mirror's
    /// where it holds an object and the screen's elsewhere, `none` leaves them to the sky's
    /// reflection alone. Default: the scene's `render.reflections`. Without objects there is
    /// nothing to reflect either way.
    #[arg(long, value_enum)]
    reflections: Option<Reflections>,
}

impl MethodArgs {
    /// The shader's method, glints and reflections for `scene`; glints asked of a method without
    /// them is an error.
    fn shader(&self, scene: &Scene) -> ocean::Result<ShaderConfig> {
        let glints = match self.glints {
            Some(Switch::On) if self.method != Method::Full => {
                return Err(ocean::Error::Argument(format!(
                    "--glints on: only --method full draws glints (not {})",
                    self.method.name()
                )))
            }
            Some(Switch::On) => true,
            Some(Switch::Off) => false,
            None => self.method == Method::Full,
        };
        let reflections = self.reflections.unwrap_or(scene.render.reflections);
        Ok(ShaderConfig { method: self.method, glints, reflections, ..ShaderConfig::default() })
    }
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (and optionally a linear EXR and a JSON report).
    Render {
        #[command(flatten)]
        view: ViewArgs,
        /// Output PNG (tone-mapped sRGB); `-` for standard output.
        #[arg(long, default_value = "out.png")]
        out: PathBuf,
        /// Also write the linear HDR radiance as OpenEXR; `-` for standard output.
        #[arg(long)]
        exr: Option<PathBuf>,
        /// Write a JSON report (timings, validation counts, image statistics, memory); `-` for
        /// standard output.
        #[arg(long)]
        report: Option<PathBuf>,
        #[command(flatten)]
        method: MethodArgs,
        /// Supersampling: K x K samples per pixel, box-filtered in linear radiance.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=16))]
        ssaa: u32,
        /// Render with the general pipeline: leave nothing out (for comparison).
        #[arg(long)]
        no_specialize: bool,
        /// Shade every tile of the sea with the mirror's code, unsorted (for comparison; see
        /// src/render/passes/planar_tiles.rs).
        #[arg(long)]
        no_planar_tiles: bool,
        /// Build the mirror's images over the whole view, not only where the objects' mirror
        /// images may lie (for comparison; see src/render/passes/planar.rs).
        #[arg(long)]
        no_planar_cover: bool,
        /// How the shading loop reads the wave table: in blocks shared by subgroup broadcasts
        /// (where the device allows; else per train), or per train.
        #[arg(long, value_enum, default_value_t = TrainReads::Blocks)]
        train_reads: TrainReads,
        /// Which of the sea's terms to render (comma-separated: sun, sky, sea).
        #[arg(long, value_delimiter = ',', default_value = "sun,sky,sea")]
        terms: Vec<Term>,
        /// Render this many frames; timings are then the median after the first (warm-up).
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        /// Also collect pipeline statistics per pass (vertices, primitives, invocations) into the
        /// report, where the device has them.
        #[arg(long)]
        stats: bool,
    },
    /// Frames of a scene on a timeline: a Chrome Trace Event JSON trace (Perfetto,
    /// chrome://tracing) of the GPU's passes and the CPU's steps, and a report of per-pass times,
    /// pipeline statistics and the figures that explain them.
    Profile {
        #[command(flatten)]
        view: ViewArgs,
        /// Frames rendered, the warm-up ones included.
        #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(0..=10000))]
        frames: u32,
        /// Frames first rendered untimed (the driver compiles shaders lazily): less than --frames.
        #[arg(long, default_value_t = 2)]
        warmup: u32,
        /// The trace (Chrome Trace Event JSON); `-` for standard output.
        #[arg(long, default_value = "trace.json")]
        out: PathBuf,
        /// The profile report (JSON, also read by `bench compare`).
        #[arg(long, default_value = "profile.json")]
        report: PathBuf,
        /// Also write the last frame's image (its encoding and writing are spans of the trace).
        #[arg(long)]
        png: Option<PathBuf>,
        #[command(flatten)]
        method: MethodArgs,
        /// Profile the general pipeline: leave nothing out.
        #[arg(long)]
        no_specialize: bool,
        /// Shade every tile of the sea with the mirror's code, unsorted (for comparison).
        #[arg(long)]
        no_planar_tiles: bool,
        /// Build the mirror's images over the whole view (for comparison).
        #[arg(long)]
        no_planar_cover: bool,
        #[arg(long, value_enum, default_value_t = TrainReads::Blocks)]
        train_reads: TrainReads,
    },
    /// Ground truth: N x N stratified samples per pixel, every wave as exact geometry, to linear EXR
    /// (alpha 0 marks pixels whose samples cannot resolve the shortest wave), with the reflected
    /// sun, reflected sky and refracted sea light beside it (NAME.sun.exr, ...) and NAME.exr.json.
    Reference {
        #[command(flatten)]
        view: ViewArgs,
        /// Samples per pixel along each axis (N x N per pixel).
        #[arg(long, default_value_t = 8)]
        samples: u32,
        /// Times a reflected ray that meets the sea again is shaded there (its reflection and
        /// refracted light); the report gives the reflected weight cut off after the last.
        #[arg(long, default_value_t = ocean::measure::groundtruth::DEFAULT_BOUNCES)]
        bounces: u32,
        /// Angular radius (degrees) of the cone the reflected sun's energy is spread over for its
        /// estimate, from the sun's own radius (0.2666: the disc, a scatter of rare glints) to 10.
        #[arg(long, default_value_t = ocean::measure::groundtruth::DEFAULT_SUN_KERNEL_DEG)]
        sun_kernel_deg: f64,
        /// X,Y,WIDTH,HEIGHT: trace only these pixels of the --width x --height view (the images
        /// written are the region's size; `bench error-vs-time` compares the same pixels).
        #[arg(long, value_parser = ocean::measure::region::Region::parse)]
        region: Option<ocean::measure::region::Region>,
        #[arg(long, default_value = "reference.exr")]
        out: PathBuf,
        /// Also write tone-mapped PNGs (the scene's exposure): the total, and NAME.sun.png,
        /// NAME.sky.png, NAME.sea.png beside it.
        #[arg(long)]
        png: Option<PathBuf>,
        #[arg(long)]
        report: Option<PathBuf>,
    },
    /// An image sequence: DIR/frame_00000.png, ... at --fps frames per second from the scene's
    /// time_s; frames already written are skipped (resumable) unless --force.
    Animate {
        #[command(flatten)]
        view: ViewArgs,
        /// Length of the sequence in seconds of scene time.
        #[arg(long)]
        seconds: f64,
        #[arg(long, default_value_t = 30.0)]
        fps: f64,
        /// Folder for the frames (made if missing).
        #[arg(long)]
        out: PathBuf,
        /// Also write each frame's linear radiance as frame_NNNNN.exr.
        #[arg(long)]
        exr: bool,
        /// Render every frame, also those already written.
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        method: MethodArgs,
    },
    /// A window on the sea: animated with the wall clock, interactive (press H for the controls),
    /// presented through our own swapchain; the automation flags script a session for tests.
    View {
        /// Scene file (TOML), watched: saving it reloads it.
        #[arg(long)]
        scene: Option<PathBuf>,
        #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=16384))]
        width: u32,
        #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=16384))]
        height: u32,
        /// Present mode; a mode the surface lacks falls back to fifo (logged).
        #[arg(long, value_enum, default_value_t = PresentMode::Fifo)]
        present: PresentMode,
        /// Enable the Khronos validation layer with synchronization validation.
        #[arg(long)]
        validation: bool,
        /// Use the first device whose name contains this text.
        #[arg(long)]
        device: Option<String>,
        #[command(flatten)]
        method: MethodArgs,
        /// Frames the CPU may prepare while the GPU runs earlier ones.
        #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=4))]
        frames_in_flight: u32,
        /// Scene seconds per second of wall time (0: a still frame at the scene's time_s).
        #[arg(long, default_value_t = 1.0, value_parser = parse_time_scale)]
        time_scale: f64,
        /// Exit after N presented frames.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        frames: Option<u64>,
        /// Save the last presented frame (PNG of what is shown).
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// FRAME:WIDTHxHEIGHT: ask the window for a new size after FRAME frames (repeatable).
        #[arg(long, value_parser = ocean::app::window::script::parse_resize)]
        resize_at: Vec<ocean::app::window::script::ResizeAt>,
        /// FRAME:FRAMES: minimize after FRAME frames, restore FRAMES frame periods later (repeatable).
        #[arg(long, value_parser = ocean::app::window::script::parse_minimize)]
        minimize_at: Vec<ocean::app::window::script::MinimizeAt>,
        /// Write a JSON report (device, present mode, surface format, frames, recreations, fps,
        /// CPU and GPU times, validation counts).
        #[arg(long)]
        report: Option<PathBuf>,
        /// Write the session's timeline (Chrome Trace Event JSON, as `ocean profile`).
        #[arg(long)]
        trace: Option<PathBuf>,
    },
    /// Benchmarks that print their numbers and write them under --out.
    Bench {
        #[command(subcommand)]
        bench: Bench,
    },
}

/// A bench against a ground truth of its scene.
#[derive(clap::Args)]
struct AgainstTruth {
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Ground truth made by `ocean reference` for this scene (its size is the bench's size).
    #[arg(long)]
    reference: PathBuf,
    #[arg(long, default_value = "docs/bench")]
    out: PathBuf,
    #[arg(long)]
    device: Option<String>,
}

#[derive(Subcommand)]
enum Bench {
    /// Error against GPU time of every method and setting, against a ground truth of the scene.
    ErrorVsTime {
        #[command(flatten)]
        against: AgainstTruth,
        /// Timed frames per setting, after one warm-up frame.
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        /// Ground truth made by `ocean reference` of a copy of the scene without its `[[wake]]`s and
        /// `[[splash]]`es, at the same size (and region) as --reference: adds the local waves' own
        /// change, the full method's against the truth's (local_waves.md).
        #[arg(long)]
        bare_reference: Option<PathBuf>,
    },
    /// The sea's reflections of the scene's objects, method by method (none, screen, planar,
    /// both): GPU time, error over the sea, and the reflected objects' energy and local contrast,
    /// against a ground truth of the scene and one of the same scene without its objects.
    Reflections {
        #[command(flatten)]
        against: AgainstTruth,
        /// Ground truth made by `ocean reference` of a copy of the scene without its `[[object]]`s,
        /// at the same size (and region) as --reference.
        #[arg(long)]
        bare_reference: PathBuf,
        /// Timed frames per method, after one warm-up frame.
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
    },
    /// Where the reflected sky's error comes from, per distance band: the ground truth against
    /// the f64 quadrature of each method's model and against its GPU lookup; and the sea's own
    /// masking at grazing view against the model's.
    SkyModel {
        #[command(flatten)]
        against: AgainstTruth,
    },
    /// Temporal flicker per distance band of every method over a short animation, against a
    /// heavily supersampled render of the full method.
    Flicker {
        #[arg(long)]
        scene: Option<PathBuf>,
        #[arg(long, default_value_t = 320)]
        width: u32,
        #[arg(long, default_value_t = 240)]
        height: u32,
        /// Frames of the animation (the change is measured between consecutive ones).
        #[arg(long, default_value_t = 30)]
        frames: u32,
        #[arg(long, default_value_t = 30.0)]
        fps: f64,
        /// Also trace the ground truth's own frames at N x N samples (2 to 64) and measure every
        /// method against its change (hours for a whole view: see --region).
        #[arg(long)]
        truth_samples: Option<u32>,
        /// X,Y,WIDTH,HEIGHT: measure only these pixels of the view (the truth traces only them).
        #[arg(long, value_parser = ocean::measure::region::Region::parse)]
        region: Option<ocean::measure::region::Region>,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
        #[arg(long)]
        device: Option<String>,
    },
    /// GPU time of every preset and extreme scene with the general pipeline and with what it needs.
    Specialize {
        /// Timed frames per scene and pipeline, after one warm-up frame.
        #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
        #[arg(long)]
        device: Option<String>,
    },
    /// Wall time of `ocean render` as new processes: without the pipeline cache on disk, with an
    /// empty cache folder, and with a previous run's cache file.
    Startup {
        /// Runs of each setup, interleaved.
        #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
        runs: u32,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
        #[arg(long)]
        device: Option<String>,
    },
    /// `ocean view` as new processes on the current display: fps, CPU frame time and waiting,
    /// per present mode and frames in flight.
    View {
        #[arg(long, default_value_t = 1280)]
        width: u32,
        #[arg(long, default_value_t = 720)]
        height: u32,
        /// Presented frames per run.
        #[arg(long, default_value_t = 120, value_parser = clap::value_parser!(u32).range(2..=100000))]
        frames: u32,
        /// Runs of each setup, interleaved.
        #[arg(long, default_value_t = 2, value_parser = clap::value_parser!(u32).range(1..=100))]
        rounds: u32,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
    },
    /// GPU time per pass of every preset scene at 1024x768, and memory at 1920x1080; with
    /// --variant, of builds or settings interleaved in one run.
    Speed {
        #[arg(long, default_value = "scenes")]
        scenes: PathBuf,
        /// Timed frames per scene, after one warm-up frame.
        #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        /// Rounds: every scene (and every variant) this many times, interleaved.
        #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
        repeat: u32,
        /// LABEL=FLAGS: time `ocean render FLAGS` as a variant (FLAGS may start with @PATH, another
        /// build's binary); give two or more, written to speed.LABEL.json each for `bench compare`.
        #[arg(long, value_parser = ocean::measure::bench::speed::parse_variant)]
        variant: Vec<ocean::measure::bench::speed::Variant>,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
        #[arg(long)]
        device: Option<String>,
    },
    /// What drawing through `ocean::embed` (a host's frame: composited into its colour and depth,
    /// tone-mapped into its LDR image) costs against `ocean render`'s own frame, interleaved.
    Embed {
        #[command(flatten)]
        view: ViewArgs,
        #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
    },
    /// What a moving sun costs: the default scene with the sun still and moving, frames interleaved.
    Sky {
        #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10000))]
        frames: u32,
        #[arg(long, default_value = "docs/bench")]
        out: PathBuf,
        #[arg(long)]
        device: Option<String>,
    },
    /// B's GPU time against A's per scene and pass, with a 95% interval and a verdict (faster,
    /// slower, within noise); A and B are JSON files of `bench speed` or `profile`.
    Compare {
        a: PathBuf,
        b: PathBuf,
        /// The smallest change (a fraction) called faster or slower.
        #[arg(long, default_value_t = 0.02, value_parser = parse_threshold)]
        threshold: f64,
        /// Also write the table as markdown.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// Reserves standard output for the one option given `-` (binary ones never for a terminal).
fn claim_stdout(outputs: &[(&str, Option<&Path>, bool)]) -> ocean::Result<()> {
    for &(option, path, binary) in outputs {
        if let Some(path) = path {
            ocean::output::target::claim_stdout(option, path, binary)?;
        }
    }
    Ok(())
}

/// A path as status lines name it.
fn shown(path: &Path) -> String {
    if is_stdout(path) {
        "standard output".to_owned()
    } else {
        path.display().to_string()
    }
}

/// The scene from `--scene`, or the built-in defaults (scenes/default.toml), with its name.
fn parse_time_scale(text: &str) -> Result<f64, String> {
    text.parse::<f64>()
        .ok()
        .filter(|s| s.is_finite() && s.abs() <= 1e4)
        .ok_or_else(|| format!("{text:?}: the time scale must be a number in [-10000, 10000]"))
}

fn parse_threshold(text: &str) -> Result<f64, String> {
    text.parse::<f64>()
        .ok()
        .filter(|t| t.is_finite() && (0.0..0.5).contains(t))
        .ok_or_else(|| format!("{text:?}: the threshold is a fraction in [0, 0.5)"))
}

fn load_scene(path: Option<PathBuf>) -> ocean::Result<(Scene, String)> {
    match path {
        Some(path) => Ok((Scene::load(&path)?, path.display().to_string())),
        None => Ok((Scene::default(), "scenes/default.toml".to_owned())),
    }
}

fn run(cli: Cli) -> ocean::Result<()> {
    match cli.command {
        Command::Render {
            view: ViewArgs { scene, width, height, validation, device },
            out,
            exr,
            report,
            method,
            ssaa,
            terms,
            frames,
            no_specialize,
            no_planar_tiles,
            no_planar_cover,
            train_reads,
            stats,
        } => {
            claim_stdout(&[
                ("--out", Some(&out), true),
                ("--exr", exr.as_deref(), true),
                ("--report", report.as_deref(), false),
            ])?;
            let (scene, _) = load_scene(scene)?;
            let terms = Terms {
                sun: terms.contains(&Term::Sun),
                sky: terms.contains(&Term::Sky),
                sea: terms.contains(&Term::Sea),
            };
            let base = method.shader(&scene)?;
            let shader = if terms == Terms::ALL {
                base
            } else {
                // The terms alone on black, by the same method, glints and reflections.
                ShaderConfig { terms, background: false, ..base }
            };
            let shader =
                ShaderConfig { train_reads, planar_tiles: !no_planar_tiles, planar_cover: !no_planar_cover, ..shader };
            let shading = Shading { shader, ssaa, statistics: stats, ..Shading::default() };
            let request = RenderRequest {
                scene,
                width,
                height,
                png: Some(out.clone()),
                exr,
                report,
                validation,
                device,
                frames,
                shading,
                specialize: !no_specialize,
            };
            let (report, _) = app::render(&request)?;
            let total = match report.gpu_ms.get("total") {
                None => "n/a".to_owned(),
                Some(ms) if frames == 1 => format!("{ms:.1} ms (first frame, with the driver's shader compilation)"),
                Some(ms) => format!("{ms:.1} ms (median of {} frames after the first)", frames - 1),
            };
            ocean::say!(
                "{}: {}x{} on {}, GPU {total}, {} validation errors, {} non-finite pixels",
                shown(&out),
                report.width,
                report.height,
                report.device,
                report.validation_errors,
                report.nonfinite_pixels
            );
            Ok(())
        }
        Command::Reference {
            view: ViewArgs { scene, width, height, validation, device },
            samples,
            bounces,
            sun_kernel_deg,
            region,
            out,
            png,
            report,
        } => {
            // The per-term images and the metadata are named after these files.
            for (option, path) in [("--out", Some(&out)), ("--png", png.as_ref())] {
                if path.is_some_and(|p| is_stdout(p)) {
                    return Err(ocean::Error::Argument(format!(
                        "reference {option} - : the per-term files written beside it are named after it; give a file name"
                    )));
                }
            }
            claim_stdout(&[("--report", report.as_deref(), false)])?;
            // A ground truth takes minutes to hours: a folder that is missing or not writable
            // fails now, not after the trace.
            for path in [Some(&out), png.as_ref(), report.as_ref()].into_iter().flatten() {
                ocean::output::target::check_writable(path)?;
            }
            let (scene, _) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(validation, device.as_deref())?;
            let part = region.map_or(String::new(), |r| format!(" ({r})"));
            let label = format!("ground truth {width}x{height}{part}, {samples}x{samples} samples per pixel");
            let mut progress: Option<Progress> = None;
            let sampling = ocean::measure::groundtruth::Sampling { samples, bounces, sun_kernel_deg, region };
            let truth = ocean::measure::groundtruth::render(&gpu, &scene, width, height, &sampling, |done, total| {
                // Work units are weighted by what a tile costs, so the time left holds.
                progress.get_or_insert_with(|| Progress::new(&label, total, "", true)).set(done, None)
            })?;
            truth.save(&scene, &out)?;
            if let Some(path) = png {
                // The total, and each term beside it (NAME.sun.png, NAME.sky.png, NAME.sea.png).
                let stem = path.file_stem().unwrap_or_default().to_string_lossy().into_owned();
                let images = [("", &truth.radiance), (".sun", &truth.sun), (".sky", &truth.sky), (".sea", &truth.sea)];
                for (suffix, pixels) in images {
                    let rgba = ocean::output::tonemap(pixels, truth.width, &scene.render);
                    ocean::output::write_png(
                        &path.with_file_name(format!("{stem}{suffix}.png")),
                        truth.width,
                        truth.height,
                        &rgba,
                    )?;
                }
            }
            if let Some(path) = report {
                let json = serde_json::to_string_pretty(&truth.report).expect("report serializes");
                ocean::output::write_text(&path, &json)?;
            }
            let r = &truth.report;
            let convergence = r.convergence_rms_relative.map_or("n/a".into(), |c| format!("{:.2}%", 100.0 * c));
            // The physical sky's own error: its tables, quadrature and f32 against the f64 model.
            let sky = r.sky_error.map_or(String::new(), |e| {
                format!("; the physical sky's own error at most {:.1e} of its radiance", e.largest())
            });
            ocean::say!(
                "{}: {}x{}{part} with {}x{} samples per pixel, {} bounces ({:.2}% of the reflected light cut off after them; out of marching steps: {:.3}% of the camera rays, {:.3}% of the reflected light), in {:.1} s; convergence {convergence}{sky}; {} pixels unresolved; {} validation errors, {} non-finite pixels",
                out.display(),
                width,
                height,
                samples,
                samples,
                r.bounces,
                100.0 * r.cut_off_fraction,
                100.0 * r.unfinished_camera_fraction,
                100.0 * r.unfinished_reflected_fraction,
                r.gpu_seconds,
                r.unresolved_pixels,
                r.validation_errors,
                r.nonfinite_pixels
            );
            Ok(())
        }
        Command::Animate {
            view: ViewArgs { scene, width, height, validation, device },
            seconds,
            fps,
            out,
            exr,
            force,
            method,
        } => {
            ocean::app::animate::frame_count(seconds, fps)?; // bad arguments before the GPU starts
            let (scene, _) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(validation, device.as_deref())?;
            let shading = Shading { shader: method.shader(&scene)?, ..Shading::default() };
            let request = ocean::app::animate::AnimateRequest {
                scene,
                seconds,
                fps,
                width,
                height,
                out_dir: out.clone(),
                exr,
                force,
                shading,
                specialize: true,
            };
            let r = ocean::app::animate::animate(&gpu, &request)?;
            let gpu_ms = r.gpu_ms_median.map_or("n/a".to_owned(), |ms| format!("{ms:.1} ms median"));
            ocean::say!(
                "{}: {} frames at {} fps, {} rendered, {} already there; GPU {gpu_ms}; {} validation errors, {} non-finite pixels",
                out.display(),
                r.frames,
                r.fps,
                r.rendered,
                r.skipped,
                r.validation_errors,
                r.nonfinite_pixels
            );
            Ok(())
        }
        Command::View {
            scene,
            width,
            height,
            present,
            validation,
            device,
            method,
            frames_in_flight,
            time_scale,
            frames,
            screenshot,
            resize_at,
            minimize_at,
            report,
            trace,
        } => {
            let (loaded, _) = load_scene(scene.clone())?;
            let shader = method.shader(&loaded)?;
            let options = ocean::app::window::view::ViewOptions {
                scene_path: scene,
                scene: loaded,
                width,
                height,
                present,
                validation,
                device,
                shader,
                frames_in_flight,
                time_scale,
                frames,
                screenshot,
                resize_at,
                minimize_at,
                trace,
            };
            let r = ocean::app::window::view::run(&options)?;
            if let Some(path) = report {
                let json = serde_json::to_string_pretty(&r).expect("report serializes");
                ocean::output::write_text(&path, &json)?;
            }
            ocean::say!(
                "{} frames at {:.1} fps ({}, {}), {} swapchain recreations, {} validation errors",
                r.frames,
                r.summary.fps,
                r.present_mode,
                r.surface_format,
                r.swapchain_recreations,
                r.validation_errors
            );
            Ok(())
        }
        Command::Bench {
            bench:
                Bench::ErrorVsTime { against: AgainstTruth { scene, reference, out, device }, frames, bare_reference },
        } => {
            let (scene, name) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            let bare = bare_reference.as_deref();
            ocean::measure::bench::error_vs_time::run(&gpu, &scene, &name, &reference, bare, frames, &out)?;
            ocean::say!(
                "wrote {}/error_vs_time.csv, error_by_distance.csv, error_vs_time.md and .svg, energy_by_distance.svg{}",
                out.display(),
                if bare.is_some() { ", local_waves.md and .csv" } else { "" }
            );
            Ok(())
        }
        Command::Bench {
            bench:
                Bench::Reflections { against: AgainstTruth { scene, reference, out, device }, bare_reference, frames },
        } => {
            let (scene, name) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            let request = ocean::measure::bench::reflections::Request {
                scene: &scene,
                scene_name: &name,
                reference: &reference,
                bare_reference: &bare_reference,
                frames,
                out_dir: &out,
            };
            ocean::measure::bench::reflections::run(&gpu, &request)?;
            ocean::say!("wrote {}/reflections.csv and reflections.md", out.display());
            Ok(())
        }
        Command::Bench { bench: Bench::SkyModel { against: AgainstTruth { scene, reference, out, device } } } => {
            let (scene, name) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            ocean::measure::bench::sky_model::run(&gpu, &scene, &name, &reference, &out)?;
            ocean::say!("wrote {}/sky_model.md", out.display());
            Ok(())
        }
        Command::Bench {
            bench: Bench::Flicker { scene, width, height, frames, fps, truth_samples, region, out, device },
        } => {
            let (scene, name) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            let run = ocean::measure::bench::flicker::FlickerRun { width, height, frames, fps, truth_samples, region };
            ocean::measure::bench::flicker::run(&gpu, &scene, &name, run, &out)?;
            ocean::say!("wrote {}/flicker.csv and flicker.md", out.display());
            Ok(())
        }
        Command::Bench { bench: Bench::Specialize { frames, out, device } } => {
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            ocean::measure::bench::specialize(&gpu, &[Path::new("scenes"), Path::new("scenes/extreme")], frames, &out)?;
            ocean::say!("wrote {}/specialize.md and specialize.json", out.display());
            Ok(())
        }
        Command::Bench { bench: Bench::View { width, height, frames, rounds, out } } => {
            let bench = ocean::measure::bench::view::run(width, height, frames, rounds, &out)?;
            for r in &bench.rows {
                ocean::say!(
                    "{:<10} {} in flight: {:.1} fps, CPU frame {:.1} ms ({:.0}% waiting, {:.1} ms in present), GPU {:.1} ms",
                    r.present_mode,
                    r.frames_in_flight,
                    r.fps,
                    r.cpu_frame_ms,
                    100.0 * r.cpu_wait_fraction,
                    r.cpu_present_ms,
                    r.gpu_total_ms
                );
            }
            ocean::say!("wrote {}/view.md and view.json", out.display());
            Ok(())
        }
        Command::Bench { bench: Bench::Startup { runs, out, device } } => {
            let name = ocean::vk::gpu::Gpu::with_cache_dir(false, device.as_deref(), None)?.device.name.clone();
            let report = ocean::measure::bench::startup::run(&name, device.as_deref(), runs, &out)?;
            for row in &report.rows {
                ocean::say!(
                    "{:<40} wall {:.3} s (fastest {:.3} s), first frame {:.1} ms GPU, {} cache bytes loaded",
                    row.setup,
                    row.wall_median_s,
                    row.wall_fastest_s,
                    row.first_frame_gpu_median_ms,
                    row.cache_loaded_bytes
                );
            }
            ocean::say!("wrote {}/startup.md and startup.json", out.display());
            Ok(())
        }
        Command::Bench { bench: Bench::Speed { scenes, frames, repeat, variant, out, device } } => {
            if variant.len() == 1 {
                return Err(ocean::Error::Argument(
                    "--variant: give two or more to compare (a baseline too, e.g. --variant base=)".into(),
                ));
            }
            if let Some(v) =
                variant.iter().enumerate().find_map(|(i, v)| variant[..i].iter().find(|w| w.label == v.label))
            {
                return Err(ocean::Error::Argument(format!("--variant: the label {:?} is given twice", v.label)));
            }
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            let request = ocean::measure::bench::speed::SpeedRequest {
                scenes_dir: &scenes,
                frames,
                repeat,
                variants: variant.clone(),
                out_dir: &out,
            };
            ocean::measure::bench::speed::speed(&gpu, &request)?;
            if variant.is_empty() {
                ocean::say!("wrote {}/speed.md and speed.json", out.display());
            } else {
                let files: Vec<String> = variant.iter().map(|v| format!("speed.{}.json", v.label)).collect();
                ocean::say!("wrote {}/{} (compare with `ocean bench compare`)", out.display(), files.join(", "));
            }
            Ok(())
        }
        Command::Bench {
            bench: Bench::Embed { view: ViewArgs { scene, width, height, validation, device }, frames, out },
        } => {
            let (scene, name) = load_scene(scene)?;
            let gpu = ocean::vk::gpu::Gpu::new(validation, device.as_deref())?;
            let t = ocean::measure::bench::embed::run(&gpu, &scene, &name, width, height, frames, &out)?;
            ocean::say!(
                "render {:.1} ms, embedded {:.1} ms a frame (ratio {:.3}, quartiles {:.3}-{:.3}); wrote {}/embed.md and embed.json",
                t.render_ms["frame"],
                t.embedded_ms["frame"],
                t.ratio[1],
                t.ratio[0],
                t.ratio[2],
                out.display()
            );
            Ok(())
        }
        Command::Bench { bench: Bench::Sky { frames, out, device } } => {
            let gpu = ocean::vk::gpu::Gpu::new(false, device.as_deref())?;
            let r = ocean::measure::bench::sky::run(&gpu, frames, &out)?;
            ocean::say!(
                "still sun {:.1} ms, moving sun {:.1} ms per frame; wrote {}/sky.md and sky.json",
                r.still_sun_ms["total"],
                r.moving_sun_ms["total"],
                out.display()
            );
            Ok(())
        }
        Command::Bench { bench: Bench::Compare { a, b, threshold, out } } => {
            let (fa, fb) = (
                ocean::measure::bench::speed::read_timing_file(&a)?,
                ocean::measure::bench::speed::read_timing_file(&b)?,
            );
            let c = ocean::measure::bench::compare::compare(&fa, &fb, threshold)?;
            let text = ocean::measure::bench::compare::markdown(&c, &a.display().to_string(), &b.display().to_string());
            ocean::say!("{text}");
            if let Some(path) = out {
                ocean::output::write_text(&path, &text)?;
            }
            Ok(())
        }
        Command::Profile {
            view: ViewArgs { scene, width, height, validation, device },
            frames,
            warmup,
            out,
            report,
            png,
            method,
            no_specialize,
            no_planar_tiles,
            no_planar_cover,
            train_reads,
        } => {
            claim_stdout(&[
                ("--out", Some(&out), false),
                ("--report", Some(&report), false),
                ("--png", png.as_deref(), true),
            ])?;
            let (scene, scene_name) = load_scene(scene)?;
            let shader = ShaderConfig {
                train_reads,
                planar_tiles: !no_planar_tiles,
                planar_cover: !no_planar_cover,
                ..method.shader(&scene)?
            };
            let request = ocean::app::profile::ProfileRequest {
                scene,
                scene_name,
                width,
                height,
                frames,
                warmup,
                trace: Some(out.clone()),
                report: Some(report.clone()),
                png,
                shading: Shading { shader, ..Shading::default() },
                specialize: !no_specialize,
                validation,
                device,
            };
            let r = ocean::app::profile::profile(&request)?;
            for p in r.passes.iter().chain(std::iter::once(&r.total)) {
                let per = match (p.ns_per_fragment, p.ns_per_invocation) {
                    (Some(f), _) => format!(", {f:.1} ns per fragment"),
                    (None, Some(i)) => format!(", {i:.1} ns per invocation"),
                    _ => String::new(),
                };
                ocean::say!(
                    "{:<10} median {:7.2} ms  fastest {:7.2} ms  p90 {:7.2} ms{per}",
                    p.name,
                    p.median_ms,
                    p.fastest_ms,
                    p.p90_ms
                );
            }
            if let Some(t) = r.derived.trains_evaluated_per_sea_pixel {
                ocean::say!(
                    "shade: {t:.1} trains evaluated per sea pixel ({:.1} with a weight){}",
                    r.derived.trains_weighted_per_sea_pixel.unwrap_or(0.0),
                    r.derived.shade_over_floor.map_or(String::new(), |f| format!(", {f:.1}x its arithmetic floor"))
                );
            }
            if let Some(p) = &r.derived.packets {
                let opt = |v: Option<f64>, unit: &str| v.map_or("-".to_owned(), |v| format!("{v:.2} {unit}"));
                ocean::say!(
                    "packets: {} alive, {} list entries in {} cells ({:.1} a packet), binned by {} tiles listing {}; binning {} a packet, {} a tile, {} an entry; {} packet terms per sea pixel",
                    p.alive,
                    p.entries,
                    p.cells,
                    p.entries_per_packet,
                    p.tiles,
                    p.tile_entries,
                    opt(p.bins_us_per_packet, "us"),
                    opt(p.bins_us_per_tile, "us"),
                    opt(p.bins_ns_per_entry, "ns"),
                    p.terms_per_sea_pixel.map_or("-".to_owned(), |t| format!("{t:.1}"))
                );
            }
            for note in &r.notes {
                ocean::say!("{note}");
            }
            ocean::say!("{}; wrote {} and {}", r.clock, shown(&out), shown(&report));
            Ok(())
        }
    }
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
