//! A host that embeds the ocean: the tutorial of docs/embedding.md, in plain ash.
//!
//! It owns everything an engine owns (window, instance, device, swapchain, frame loop, HDR
//! colour and depth targets) and draws its own object, a buoy standing half in the sea, with its
//! own pipeline. The ocean is drawn around it through `ocean::embed` and tone-maps the frame
//! into the swapchain image.
//!
//! `cargo run --release --example host -- [--frames N] [--screenshot FILE.png] [--validation]`
//! Keys: W/S forward and back, A/D sideways, Q/E down and up, arrows turn; drag to look.

use ash::vk;
use clap::Parser;
use glam::{Mat4, Vec3};
use ocean::embed::{FrameInput, Gpu, HostFormats, ImageState, Ocean, OceanDesc, Targets};
use ocean::model::scene::Scene;

use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::platform::pump_events::{EventLoopExtPumpEvents, PumpStatus};
use winit::window::{Window, WindowId};

mod buoy;
mod engine;

use buoy::BuoyPipeline;
use engine::{Host, Swapchain, VALIDATION_ERRORS};

mod shaders {
    include!(concat!(env!("OUT_DIR"), "/example_shaders.rs"));
}

#[derive(Parser)]
#[command(about = "A host drawing its own object with the ocean around it")]
struct Args {
    /// Stop after this many frames.
    #[arg(long)]
    frames: Option<u64>,
    /// Write the last frame to this PNG.
    #[arg(long)]
    screenshot: Option<std::path::PathBuf>,
    /// Khronos validation with synchronization validation; errors make the exit status 1.
    #[arg(long)]
    validation: bool,
    /// Resize the window to WxH half way through --frames (exercises the swapchain's re-creation).
    #[arg(long, value_parser = parse_size)]
    resize: Option<(u32, u32)>,
    #[arg(long, default_value_t = 1024)]
    width: u32,
    #[arg(long, default_value_t = 768)]
    height: u32,
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let parse = |v: &str| v.parse::<u32>().ok().filter(|&n| n > 0);
    match text.split_once('x').map(|(w, h)| (parse(w), parse(h))) {
        Some((Some(w), Some(h))) => Ok((w, h)),
        _ => Err(format!("{text:?} is not WIDTHxHEIGHT")),
    }
}

const FRAMES_IN_FLIGHT: usize = 2;
const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The buoy: centre and half size (m), standing half in the sea.
const BUOY: (Vec3, Vec3) = (Vec3::new(40.0, 6.0, 0.5), Vec3::new(1.5, 1.5, 3.0));

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("host: {e}");
        std::process::exit(2);
    }
    let errors = VALIDATION_ERRORS.load(Ordering::Relaxed);
    if args.validation {
        println!("validation errors: {errors}");
    }
    std::process::exit(if errors > 0 { 1 } else { 0 });
}

/// The window's events between frames (the loop is ours, so the Vulkan objects and the ocean,
/// which borrows them, live on its stack).
#[derive(Default)]
struct Events {
    window: Option<Window>,
    queue: Vec<WindowEvent>,
    size: (u32, u32),
}

impl ApplicationHandler for Events {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_none() {
            let attributes = Window::default_attributes()
                .with_title("ocean: example host")
                .with_inner_size(winit::dpi::PhysicalSize::new(self.size.0, self.size.1));
            self.window = Some(event_loop.create_window(attributes).expect("a window"));
        }
    }
    fn window_event(&mut self, _: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        self.queue.push(event);
    }
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let mut event_loop = EventLoop::new()?;
    let mut events = Events { size: (args.width, args.height), ..Default::default() };
    while events.window.is_none() {
        if let PumpStatus::Exit(_) = event_loop.pump_app_events(Some(Duration::from_millis(10)), &mut events) {
            return Ok(());
        }
    }
    let window = events.window.take().expect("made above");
    let host = Host::new(&window, args.validation)?;
    // The ocean borrows the host's instance and device; our scene is the default one.
    let gpu = Gpu::from_host(&host.borrowed(), None)?;
    let scene = Scene::default();
    let mut targets = Swapchain::new(&host, &window)?;
    let desc = OceanDesc {
        scene: scene.clone(),
        width: targets.extent.width,
        height: targets.extent.height,
        formats: HostFormats {
            colour: HDR_FORMAT,
            depth: Some(DEPTH_FORMAT),
            reversed_z: true,
            ldr: Some(targets.format),
        },
        frames_in_flight: FRAMES_IN_FLIGHT as u32,
        sky: true,
        radiance_scale: 1.0,
        shading: Default::default(),
        in_place: None, // the buoy is drawn into our colour first: the ocean composites into it
        shadow_casters: false,
    };
    let mut ocean = Ocean::new(&gpu, desc)?;
    let buoy = BuoyPipeline::new(&host)?;
    let result = frame_loop(args, &mut event_loop, &mut events, &window, &host, &mut ocean, &buoy, &mut targets);
    // What the ocean costs this host: its memory on our device, and its passes' GPU time.
    let memory = ocean.memory();
    let mib = |bytes: u64| bytes as f64 / (1 << 20) as f64;
    println!(
        "ocean memory: {:.1} MiB used in {} blocks ({:.1} MiB reserved)",
        mib(memory.used_bytes),
        memory.blocks,
        mib(memory.reserved_bytes)
    );
    let passes: Vec<String> = ocean.pass_ms().iter().map(|(name, ms)| format!("{name} {ms:.2}")).collect();
    println!("ocean passes (ms): {}", passes.join(", "));
    if let Some(light) = ocean.light() {
        let klux = |e: [f32; 3]| format!("{:.2} {:.2} {:.2}", e[0], e[1], e[2]);
        println!("ocean light (klux, RGB): sun {}, sky {}", klux(light.sun_illuminance), klux(light.sky_illuminance));
    }
    // Teardown in reverse creation order, after the device is idle.
    // SAFETY: nothing may be destroyed while the GPU still uses it.
    unsafe { host.device.device_wait_idle() }?;
    drop(ocean);
    drop(gpu);
    buoy.destroy(&host);
    targets.destroy(&host);
    result
}

/// Pumps the window's events, moves the camera and draws, until the window closes or the frames
/// asked for are drawn.
#[allow(clippy::too_many_arguments)]
fn frame_loop(
    args: &Args,
    event_loop: &mut EventLoop<()>,
    events: &mut Events,
    window: &Window,
    host: &Host,
    ocean: &mut Ocean,
    buoy: &BuoyPipeline,
    targets: &mut Swapchain,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut camera = Camera { eye: Vec3::new(0.0, 0.0, 6.0), yaw: 0.0, pitch: -2f32.to_radians() };
    let (mut frame, mut held, mut dragging, mut last_cursor) = (0u64, Vec::new(), false, None);
    let (start, mut last) = (Instant::now(), Instant::now());
    loop {
        if let PumpStatus::Exit(_) = event_loop.pump_app_events(Some(Duration::ZERO), events) {
            return Ok(());
        }
        let mut stale = false;
        for event in events.queue.drain(..) {
            match event {
                WindowEvent::CloseRequested => return Ok(()),
                WindowEvent::Resized(_) => stale = true,
                WindowEvent::KeyboardInput { event, .. } => {
                    if let PhysicalKey::Code(code) = event.physical_key {
                        held.retain(|&k| k != code);
                        if event.state == ElementState::Pressed {
                            held.push(code);
                        }
                    }
                }
                WindowEvent::MouseInput { button: MouseButton::Left, state, .. } => {
                    dragging = state == ElementState::Pressed;
                    last_cursor = None;
                }
                WindowEvent::CursorMoved { position, .. } => {
                    if let (true, Some((x, y))) = (dragging, last_cursor) {
                        camera.turn((position.x - x) as f32 * -0.003, (position.y - y) as f32 * -0.003);
                    }
                    last_cursor = Some((position.x, position.y));
                }
                _ => {}
            }
        }
        camera.drive(&held, last.elapsed().as_secs_f32());
        last = Instant::now();
        let size = window.inner_size();
        if stale || (size.width, size.height) != (targets.extent.width, targets.extent.height) {
            remake(host, window, targets, ocean)?;
        }
        if targets.extent.width == 0 || targets.extent.height == 0 {
            std::thread::sleep(Duration::from_millis(16)); // minimized: nothing to draw
            continue;
        }
        if let (Some((w, h)), Some(n)) = (args.resize, args.frames) {
            if frame == n / 2 && (size.width, size.height) != (w, h) {
                let _ = window.request_inner_size(winit::dpi::PhysicalSize::new(w, h));
            }
        }
        let last_frame = args.frames.is_some_and(|n| frame + 1 >= n);
        let shot = if last_frame { args.screenshot.as_deref() } else { None };
        let time = start.elapsed().as_secs_f64();
        if draw(host, targets, ocean, buoy, &camera, frame, time, shot)? {
            frame += 1;
        } else {
            remake(host, window, targets, ocean)?; // out of date
        }
        if last_frame {
            return Ok(());
        }
    }
}

/// The swapchain and the targets sized to it made anew (a resize, or out of date), and the
/// ocean told; a window with no area gets none until it has one again.
fn remake(
    host: &Host,
    window: &Window,
    targets: &mut Swapchain,
    ocean: &mut Ocean,
) -> Result<(), Box<dyn std::error::Error>> {
    // SAFETY: waits for every frame before the targets they use are replaced.
    unsafe { host.device.device_wait_idle() }?;
    targets.destroy(host);
    *targets = Swapchain::new(host, window)?;
    ocean.resize(targets.extent.width, targets.extent.height)?;
    Ok(())
}

/// Records, submits and presents one frame; false when the swapchain is out of date.
#[allow(clippy::too_many_arguments)]
fn draw(
    host: &Host,
    targets: &mut Swapchain,
    ocean: &mut Ocean,
    buoy: &BuoyPipeline,
    camera: &Camera,
    frame: u64,
    time_s: f64,
    screenshot: Option<&std::path::Path>,
) -> Result<bool, Box<dyn std::error::Error>> {
    let slot = (frame % FRAMES_IN_FLIGHT as u64) as usize;
    let s = &targets.slots[slot];
    // SAFETY: the fence was submitted with the slot's last frame (or made signalled).
    unsafe { host.device.wait_for_fences(&[s.fence], true, u64::MAX) }?;
    let aspect = targets.extent.width as f32 / targets.extent.height as f32;
    // Vulkan's clip y points down; reversed Z with an infinite far plane.
    let projection =
        Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0)) * Mat4::perspective_infinite_reverse_rh(1.0, aspect, 0.05);
    let view = camera.view();
    // The host's part of the frame, before acquiring (an error here leaves no image pending):
    // the ocean's uniforms for this slot, whose last frame the fence above has seen finish.
    ocean.update(slot, &FrameInput { time_s, view: view.as_dmat4(), projection: projection.as_dmat4() })?;

    // SAFETY: a live swapchain; the slot's semaphore is unsignalled (its last wait completed).
    let index =
        match unsafe { host.swapchain.acquire_next_image(targets.raw, u64::MAX, s.image_available, vk::Fence::null()) }
        {
            Ok((index, _)) => index as usize,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => return Ok(false),
            Err(e) => return Err(e.into()),
        };
    // SAFETY: the slot's fence was waited: its command buffer is no longer in use.
    unsafe { host.device.reset_fences(&[s.fence]) }?;
    let cmd = s.cmd;
    // SAFETY: the command buffer is idle (fence waited) and its pool resets buffers one by one.
    unsafe {
        host.device.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())?;
        host.device.begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())?;
    }
    let (hdr, depth) = (s.hdr.image, s.depth.image);
    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
    let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
    // Last frame's use of this slot's targets (the ocean's exit states) to this frame's drawing.
    host.barrier(
        cmd,
        &hdr,
        (L::UNDEFINED, S::FRAGMENT_SHADER, A::NONE),
        (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
    );
    host.barrier(
        cmd,
        &depth,
        (L::UNDEFINED, tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
        (L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL, tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
    );
    // Lit by the frame's own sun and sky, as the ocean lights the sea.
    let light = ocean.light().expect("the update above set the frame's light");
    buoy.record(host, cmd, &hdr, &depth, projection * view, &light);
    let swap_image = targets.images[index];
    ocean.record(
        cmd,
        slot,
        &Targets {
            colour: hdr,
            colour_entry: ImageState::COLOR_ATTACHMENT,
            depth: Some((depth, ImageState::DEPTH_ATTACHMENT)),
            ldr: Some((swap_image, ImageState::ACQUIRED)),
        },
    )?;
    let written = (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    let readback = screenshot.map(|_| host.copy_out(cmd, &swap_image, written));
    let from = if readback.is_some() { (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::NONE) } else { written };
    host.barrier(cmd, &swap_image, from, (L::PRESENT_SRC_KHR, S::NONE, A::NONE));
    let render_finished = targets.render_finished[index];
    // SAFETY: the command buffer recorded the whole frame; the semaphores and fence are ours.
    unsafe {
        host.device.end_command_buffer(cmd)?;
        let waits =
            [vk::SemaphoreSubmitInfo::default().semaphore(s.image_available).stage_mask(S::COLOR_ATTACHMENT_OUTPUT)];
        let signals = [vk::SemaphoreSubmitInfo::default().semaphore(render_finished).stage_mask(S::ALL_COMMANDS)];
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let submit = vk::SubmitInfo2::default()
            .wait_semaphore_infos(&waits)
            .command_buffer_infos(&cmds)
            .signal_semaphore_infos(&signals);
        host.device.queue_submit2(host.queue, &[submit], s.fence)?;
    }
    if let (Some(path), Some(buffer)) = (screenshot, readback) {
        // SAFETY: waits for this frame, then reads the buffer it copied into.
        unsafe { host.device.wait_for_fences(&[s.fence], true, u64::MAX) }?;
        let mut rgba = host.read_and_free(buffer, targets.extent);
        if matches!(targets.format, vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM) {
            rgba.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        ocean::output::write_png(path, targets.extent.width, targets.extent.height, &rgba)?;
        println!("screenshot: {}", path.display());
    }
    let swapchains = [targets.raw];
    let indices = [index as u32];
    let waits = [render_finished];
    let present = vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
    // SAFETY: the image was acquired and its frame signals `render_finished`.
    match unsafe { host.swapchain.queue_present(host.queue, &present) } {
        Ok(false) => Ok(true),
        Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
        Err(e) => Err(e.into()),
    }
}

/// A walking camera over the sea (the ocean's world: z up).
struct Camera {
    eye: Vec3,
    yaw: f32,
    pitch: f32,
}

impl Camera {
    fn forward(&self) -> Vec3 {
        Vec3::new(self.pitch.cos() * self.yaw.cos(), self.pitch.cos() * self.yaw.sin(), self.pitch.sin())
    }
    fn view(&self) -> Mat4 {
        Mat4::look_to_rh(self.eye, self.forward(), Vec3::Z)
    }
    fn turn(&mut self, yaw: f32, pitch: f32) {
        self.yaw += yaw;
        self.pitch = (self.pitch + pitch).clamp(-1.5, 1.5);
    }
    fn drive(&mut self, held: &[KeyCode], dt: f32) {
        let (forward, right) =
            (Vec3::new(self.yaw.cos(), self.yaw.sin(), 0.0), Vec3::new(self.yaw.sin(), -self.yaw.cos(), 0.0));
        let speed = 10.0 * dt;
        for key in held {
            match key {
                KeyCode::KeyW => self.eye += forward * speed,
                KeyCode::KeyS => self.eye -= forward * speed,
                KeyCode::KeyD => self.eye += right * speed,
                KeyCode::KeyA => self.eye -= right * speed,
                KeyCode::KeyE => self.eye.z += speed,
                KeyCode::KeyQ => self.eye.z = (self.eye.z - speed).max(1.0), // stay above the crests
                KeyCode::ArrowLeft => self.turn(dt, 0.0),
                KeyCode::ArrowRight => self.turn(-dt, 0.0),
                KeyCode::ArrowUp => self.turn(0.0, dt * 0.5),
                KeyCode::ArrowDown => self.turn(0.0, -dt * 0.5),
                _ => {}
            }
        }
    }
}
