//! `ocean view`: the loop. Each turn pumps the window's events, applies controls, the script and
//! scene-file reloads, then draws and presents one frame at the wall clock's time. Rendering
//! pauses while the window has no area; the CPU waits only for the frame slot it reuses.

use super::controls::{Action, Controls, HELP};
use super::presenter::{Drawn, Presenter};
use super::script::{MinimizeAt, ResizeAt, Script, Step};
use super::stats::{FrameStats, Summary};
use super::Events;
use crate::app::window::presenter::{Capture, Captured};
use crate::embed::{GpuFrame, Method, ShaderConfig};
use crate::error::{Error, Result};
use crate::model::scene::Scene;
use crate::output;
use crate::say;
use crate::vk::clock::host_now_ns;
use crate::vk::gpu::Gpu;
use crate::vk::memory::MemoryReport;
use crate::vk::swapchain::present_mode_name;
use ash::vk;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime};
use winit::dpi::PhysicalSize;
use winit::event::WindowEvent;
use winit::event_loop::EventLoop;
use winit::keyboard::PhysicalKey;
use winit::platform::pump_events::{EventLoopExtPumpEvents, PumpStatus};
use winit::raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::window::Window;

/// One frame period while nothing is drawn (minimized): how long a loop turn sleeps in events.
const IDLE_TICK: Duration = Duration::from_micros(16_667);
/// How often the title is refreshed and the scene file's modification time checked.
const REFRESH: Duration = Duration::from_millis(500);

#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PresentMode {
    /// Waits for vertical blank; never tears; always available.
    Fifo,
    /// Replaces the queued image; no tearing, no waiting.
    Mailbox,
    /// Presents at once; may tear.
    Immediate,
}

impl PresentMode {
    fn vk(self) -> vk::PresentModeKHR {
        match self {
            PresentMode::Fifo => vk::PresentModeKHR::FIFO,
            PresentMode::Mailbox => vk::PresentModeKHR::MAILBOX,
            PresentMode::Immediate => vk::PresentModeKHR::IMMEDIATE,
        }
    }
}

#[derive(Clone, Debug)]
pub struct ViewOptions {
    pub scene_path: Option<PathBuf>,
    pub scene: Scene,
    pub width: u32,
    pub height: u32,
    pub present: PresentMode,
    pub validation: bool,
    pub device: Option<String>,
    /// The method and its glints at the start (keys 1-4 switch the method, the glints kept).
    pub shader: ShaderConfig,
    /// Frames the CPU may prepare while the GPU runs earlier ones (2 by default).
    pub frames_in_flight: u32,
    /// Scene seconds per wall-clock second (0: a still frame at the scene's time).
    pub time_scale: f64,
    /// Exit after this many presented frames.
    pub frames: Option<u64>,
    /// Save the last presented frame here (PNG).
    pub screenshot: Option<PathBuf>,
    pub resize_at: Vec<ResizeAt>,
    pub minimize_at: Vec<MinimizeAt>,
    /// Write the session's timeline here (Chrome Trace Event JSON, as `ocean profile`).
    pub trace: Option<PathBuf>,
}

#[derive(Debug, Serialize)]
pub struct ViewReport {
    pub device: String,
    pub present_mode: String,
    pub surface_format: String,
    /// The window's size at the end.
    pub width: u32,
    pub height: u32,
    pub frames: u64,
    pub frames_in_flight: u32,
    pub swapchain_recreations: u32,
    /// Times the window was seen minimized (or with no area).
    pub minimized_seen: u32,
    pub scene_reloads: u32,
    #[serde(flatten)]
    pub summary: Summary,
    pub validation: bool,
    pub validation_errors: u32,
    pub validation_warnings: u32,
    /// Message ids seen (errors and warnings), with counts.
    pub validation_messages: BTreeMap<String, u32>,
    pub memory: MemoryReport,
}

fn extent_of(size: PhysicalSize<u32>) -> vk::Extent2D {
    vk::Extent2D { width: size.width, height: size.height }
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

fn save(captured: Captured, path: &Path) -> Result<()> {
    match captured {
        Captured::Shown { width, height, rgba } => output::write_png(path, width, height, &rgba),
        Captured::Radiance { width, height, rgba } => output::write_exr_rgba(path, width, height, &rgba),
    }
}

/// Opens the window and runs until Escape, the window is closed, or `--frames` are presented.
pub fn run(options: &ViewOptions) -> Result<ViewReport> {
    if let Some(path) = &options.trace {
        output::target::check_writable(path)?;
    }
    let mut event_loop = EventLoop::new().map_err(|e| {
        Error::NoSurface(format!(
            "cannot open a display ({e}): set DISPLAY (X11) or WAYLAND_DISPLAY, or run under xvfb-run; `ocean render` needs none"
        ))
    })?;
    let attributes = Window::default_attributes()
        .with_title("ocean")
        .with_inner_size(PhysicalSize::new(options.width, options.height));
    // Declared before the GPU context, so the window outlives the surface made on it.
    let mut events = Events::new(attributes);
    let opened = Instant::now();
    while events.window.is_none() {
        if let Some(e) = &events.failed {
            return Err(Error::NoSurface(format!("cannot create a window: {e}")));
        }
        if opened.elapsed() > Duration::from_secs(10) {
            return Err(Error::NoSurface("the window system made no window within 10 s".into()));
        }
        if let PumpStatus::Exit(_) = event_loop.pump_app_events(Some(IDLE_TICK), &mut events) {
            return Err(Error::NoSurface("the window system closed the event loop at start".into()));
        }
    }
    let handles = {
        let window = events.window.as_ref().expect("made above");
        let display = window.display_handle().map_err(|e| Error::NoSurface(e.to_string()))?.as_raw();
        let raw = window.window_handle().map_err(|e| Error::NoSurface(e.to_string()))?.as_raw();
        (display, raw)
    };
    let gpu = Gpu::for_window(options.validation, options.device.as_deref(), handles.0, handles.1)?;
    say!("ocean view on {}: press H for the controls", gpu.device.name);
    let shader = options.shader;
    let mut presenter = Presenter::new(&gpu, options.present.vk(), shader, options.frames_in_flight)?;
    let mut session = Session::new(options);
    let result = session.run(&mut event_loop, &mut events, &mut presenter);
    // Stop the GPU before reporting, whatever happened.
    presenter.wait_idle()?;
    result?;
    if let (Some(path), Some(timeline)) = (&options.trace, &session.timeline) {
        output::write_text(path, &timeline.trace.to_json())?;
    }
    let counts = gpu.validation_counts();
    let mut messages = counts.errors.clone();
    messages.extend(counts.warnings.iter().map(|(k, v)| (k.clone(), *v)));
    let (present_mode, surface_format) = match &presenter.swapchain {
        Some(s) => (present_mode_name(s.choice.present_mode).to_owned(), format!("{:?}", s.choice.format.format)),
        None => ("none".to_owned(), "none".to_owned()),
    };
    let size = events.window.as_ref().map_or(PhysicalSize::new(0, 0), |w| w.inner_size());
    let memory = gpu.allocator.borrow().report();
    Ok(ViewReport {
        device: gpu.device.name.clone(),
        present_mode,
        surface_format,
        width: size.width,
        height: size.height,
        frames: session.frames,
        frames_in_flight: options.frames_in_flight,
        swapchain_recreations: presenter.recreations,
        minimized_seen: session.minimized_seen,
        scene_reloads: session.reloads,
        summary: session.stats.summary(),
        validation: options.validation,
        validation_errors: counts.error_total(),
        validation_warnings: counts.warning_total(),
        validation_messages: messages,
        memory,
    })
}

/// The state of one window session.
struct Session<'o> {
    options: &'o ViewOptions,
    scene: Scene,
    method: Method,
    controls: Controls,
    script: Script,
    stats: FrameStats,
    frames: u64,
    reloads: u32,
    minimized_seen: u32,
    /// Scene time (s): the scene's time_s plus the wall clock's elapsed time, scaled, unpaused.
    time_s: f64,
    paused: bool,
    file_time: Option<SystemTime>,
    pending_capture: Option<(Capture, PathBuf)>,
    quit: bool,
    /// With --trace: the session's timeline so far.
    timeline: Option<Timeline>,
}

/// A window session on a timeline: each presented frame's CPU span (its present inside), each
/// finished GPU frame's passes, and the frame interval and GPU time as counters.
struct Timeline {
    trace: crate::output::trace::Trace,
    /// The submit time of the last GPU frame added (frames in flight finish later than drawn).
    last_gpu_submit: Option<u64>,
}

impl Timeline {
    fn new() -> Self {
        use crate::app::profile::{CPU_TRACK, GPU_TRACK};
        let mut trace = crate::output::trace::Trace::new("ocean view", host_now_ns() as f64);
        trace.track(CPU_TRACK, "CPU main thread", 0);
        trace.track(GPU_TRACK, "GPU queue", 1);
        Timeline { trace, last_gpu_submit: None }
    }

    fn frame(&mut self, index: u64, begin_ns: u64, present_ms: f64, interval_ms: Option<f64>, gpu: Option<&GpuFrame>) {
        use crate::render::timeline::Span;
        let end = host_now_ns() as f64;
        let present = Span { name: "present".into(), begin_ns: end - present_ms * 1e6, end_ns: end };
        let draw = Span {
            name: "acquire, prepare, record, submit".into(),
            begin_ns: begin_ns as f64,
            end_ns: present.begin_ns,
        };
        let gpu = gpu.filter(|g| self.last_gpu_submit != Some(g.submission.submit_ns));
        if let Some(g) = gpu {
            self.last_gpu_submit = Some(g.submission.submit_ns);
        }
        crate::app::profile::add_frame(&mut self.trace, index as u32, false, &[draw, present], gpu);
        if let Some(ms) = interval_ms {
            self.trace.counter("frame interval ms", end, &[("ms", ms)]);
        }
    }
}

impl<'o> Session<'o> {
    fn new(options: &'o ViewOptions) -> Self {
        Session {
            options,
            scene: options.scene.clone(),
            method: options.shader.method,
            controls: Controls::default(),
            script: Script::new(options.resize_at.clone(), options.minimize_at.clone()),
            stats: FrameStats::default(),
            frames: 0,
            reloads: 0,
            minimized_seen: 0,
            time_s: options.scene.render.time_s,
            paused: false,
            file_time: options.scene_path.as_deref().and_then(modified),
            pending_capture: None,
            quit: false,
            timeline: options.trace.as_ref().map(|_| Timeline::new()),
        }
    }

    fn run(&mut self, event_loop: &mut EventLoop<()>, events: &mut Events, presenter: &mut Presenter) -> Result<()> {
        let mut need_swapchain = true;
        let mut minimized = false;
        let mut last_turn = Instant::now();
        let mut last_present: Option<Instant> = None;
        let mut last_refresh = Instant::now();
        loop {
            let idle = minimized || self.script.minimized_by_script();
            let timeout = if idle { IDLE_TICK } else { Duration::ZERO };
            if let PumpStatus::Exit(_) = event_loop.pump_app_events(Some(timeout), events) {
                break;
            }
            let window = events.window.as_ref().expect("made before the loop");
            for event in std::mem::take(&mut events.queue) {
                match event {
                    WindowEvent::CloseRequested => self.quit = true,
                    WindowEvent::Resized(_) => need_swapchain = true,
                    WindowEvent::ModifiersChanged(m) => self.controls.set_shift(m.state().shift_key()),
                    WindowEvent::KeyboardInput { event, .. } => {
                        if let PhysicalKey::Code(code) = event.physical_key {
                            if let Some(action) = self.controls.key(code, event.state, &mut self.scene) {
                                self.act(action, presenter)?;
                            }
                        }
                    }
                    WindowEvent::MouseInput { state, button, .. } => self.controls.mouse_button(button, state),
                    WindowEvent::CursorMoved { position, .. } => {
                        self.controls.cursor(position.x, position.y, &mut self.scene)
                    }
                    WindowEvent::MouseWheel { delta, .. } => self.controls.wheel(delta, &mut self.scene),
                    _ => {}
                }
            }
            for step in self.script.due(self.frames) {
                match step {
                    Step::Resize(w, h) => {
                        say!("script: resize to {w}x{h} after frame {}", self.frames);
                        if let Some(size) = window.request_inner_size(PhysicalSize::new(w, h)) {
                            need_swapchain = need_swapchain || size != window.inner_size();
                        }
                    }
                    Step::Minimize => {
                        say!("script: minimize after frame {}", self.frames);
                        window.set_minimized(true);
                    }
                    Step::Restore => window.set_minimized(false),
                }
            }
            let size = window.inner_size();
            let now_minimized = window.is_minimized() == Some(true) || size.width == 0 || size.height == 0;
            if now_minimized && !minimized {
                self.minimized_seen += 1;
            }
            if minimized && !now_minimized {
                need_swapchain = true; // after a minimize the surface may have changed
            }
            minimized = now_minimized;
            let now = Instant::now();
            let dt = now.duration_since(last_turn).as_secs_f64();
            last_turn = now;
            if now.duration_since(last_refresh) >= REFRESH {
                last_refresh = now;
                self.watch_file()?;
                let title = self.stats.title(presenter.pass_ms(), self.method.name(), self.paused);
                window.set_title(&title);
            }
            // A quit with --screenshot draws one last frame to capture, unless nothing can be drawn.
            if self.quit && (minimized || !self.wants_final_screenshot()) {
                break;
            }
            if self.script.minimized_by_script() {
                if let Some(Step::Restore) = self.script.tick_minimized() {
                    say!("script: restore");
                    window.set_minimized(false);
                    need_swapchain = true;
                }
                continue;
            }
            if minimized {
                continue;
            }
            if need_swapchain {
                if !presenter.recreate(extent_of(size), &self.scene)? {
                    continue; // no area yet
                }
                need_swapchain = false;
            }
            self.controls.update(&mut self.scene, dt);
            if !self.paused {
                self.time_s += dt * self.options.time_scale;
            }
            let mut frame_scene = self.scene.clone();
            frame_scene.render.time_s = self.time_s;
            let last_frame = self.options.frames == Some(self.frames + 1) || self.quit;
            let capture = match (&self.options.screenshot, last_frame) {
                (Some(path), true) => Some((Capture::Shown, path.clone())),
                _ => self.pending_capture.take(),
            };
            let capture = match capture {
                Some((Capture::Shown, path)) if !presenter.can_copy_shown() => {
                    let why = "this surface's images cannot be copied out (no TRANSFER_SRC usage)";
                    if self.options.screenshot.as_ref() == Some(&path) {
                        return Err(Error::NoSurface(format!("--screenshot {}: {why}", path.display())));
                    }
                    say!("no screenshot: {why}; Shift+F12 saves the radiance");
                    None
                }
                capture => capture,
            };
            let started = Instant::now();
            let started_ns = host_now_ns();
            match presenter.draw(&frame_scene, capture.as_ref().map_or(Capture::None, |c| c.0))? {
                Drawn::OutOfDate => {
                    need_swapchain = true;
                    self.pending_capture = capture.filter(|_| !last_frame).or(self.pending_capture.take());
                    continue;
                }
                Drawn::Presented { stale, captured, wait_ms, present_ms } => {
                    let presented = Instant::now();
                    self.frames += 1;
                    let interval = last_present.map(|t| presented.duration_since(t).as_secs_f64() * 1e3);
                    last_present = Some(presented);
                    let cpu_ms = presented.duration_since(started).as_secs_f64() * 1e3;
                    let gpu = presenter.pass_ms();
                    self.stats.frame(interval, cpu_ms, wait_ms, present_ms, gpu);
                    if let Some(timeline) = &mut self.timeline {
                        let finished = presenter.gpu_frame();
                        timeline.frame(self.frames - 1, started_ns, present_ms, interval, finished);
                    }
                    if let (Some(captured), Some((_, path))) = (captured, capture) {
                        save(captured, &path)?;
                        say!("{}: screenshot of frame {}", path.display(), self.frames);
                    }
                    need_swapchain |= stale;
                }
            }
            if last_frame {
                break;
            }
        }
        Ok(())
    }

    fn wants_final_screenshot(&self) -> bool {
        self.options.screenshot.is_some() && self.frames > 0
    }

    fn act(&mut self, action: Action, presenter: &mut Presenter) -> Result<()> {
        match action {
            Action::Quit => self.quit = true,
            Action::Help => say!("{HELP}"),
            Action::Reload => self.reload()?,
            Action::TogglePause => {
                self.paused = !self.paused;
                say!("time {} at {:.2} s", if self.paused { "paused" } else { "running" }, self.time_s);
            }
            Action::Screenshot { radiance } => {
                let (kind, ext) = if radiance { (Capture::Radiance, "exr") } else { (Capture::Shown, "png") };
                let path = PathBuf::from(format!("ocean-{:06}.{ext}", self.frames + 1));
                self.pending_capture = Some((kind, path));
            }
            Action::Method(method) => {
                self.method = method;
                presenter.set_shader(ShaderConfig { method, ..self.options.shader }, &self.scene)?;
                say!("method: {}", method.name());
            }
            Action::SceneChanged => {
                let sun = &self.scene.sun;
                let exposure = match (self.scene.render.ev100, self.scene.render.exposure()) {
                    (Some(crate::model::scene::Ev100::Value(ev)), _) => format!("EV100 {ev:.2}"),
                    (_, crate::model::scene::Exposure::PerKcd(e)) => format!("{e:.4} per kcd/m^2"),
                    (_, crate::model::scene::Exposure::Auto) => "automatic".to_owned(),
                };
                say!(
                    "sun elevation {:.0}, azimuth {:.0} degrees; exposure {exposure}",
                    sun.elevation_deg,
                    sun.azimuth_deg
                );
            }
        }
        Ok(())
    }

    /// Reloads the scene file when it changed on disk.
    fn watch_file(&mut self) -> Result<()> {
        let Some(path) = &self.options.scene_path else { return Ok(()) };
        let time = modified(path);
        if time != self.file_time {
            self.file_time = time;
            self.reload()?;
        }
        Ok(())
    }

    /// Loads the scene file again; a broken file keeps the last good scene, with one line why.
    fn reload(&mut self) -> Result<()> {
        let Some(path) = &self.options.scene_path else {
            say!("no scene file to reload (started without --scene)");
            return Ok(());
        };
        match Scene::load(path) {
            Ok(scene) => {
                if scene.render.time_s != self.scene.render.time_s {
                    self.time_s = scene.render.time_s;
                }
                // The next frame hands the ocean the new scene (rebuilding what depends on it).
                self.scene = scene;
                self.reloads += 1;
                say!("{}: reloaded", path.display());
            }
            Err(e) => say!("{e}; keeping the last good scene"),
        }
        Ok(())
    }
}
