//! `ocean view` under X11 with lavapipe and validation (synchronization validation included):
//! a scripted session with a resize and a minimize, and a paused frame against `ocean render`.
//! Without DISPLAY each test starts its own Xvfb and a window manager (an X server alone ignores
//! minimize requests); when neither a display nor Xvfb can be had, the test fails and says so.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// An X display for one test: the user's (DISPLAY) or our own Xvfb with openbox, killed on drop.
struct Display {
    name: String,
    children: Vec<Child>,
    /// Released after `drop` has killed the children.
    _one_at_a_time: std::sync::MutexGuard<'static, ()>,
}

/// One display at a time: the two display tests would otherwise start their servers and their
/// lavapipe sessions together and contend for two cores.
static DISPLAYS: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// How long a window manager may take to announce itself, per attempt, and how many attempts.
const WM_WAIT: Duration = Duration::from_secs(20);
const WM_ATTEMPTS: usize = 3;

impl Display {
    fn open() -> Display {
        let guard = DISPLAYS.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Ok(name) = std::env::var("DISPLAY") {
            if !name.is_empty() {
                return Display { name, children: Vec::new(), _one_at_a_time: guard };
            }
        }
        let mut xvfb = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap_or_else(|e| {
                panic!("no X display: DISPLAY is unset and Xvfb cannot start ({e}); run scripts/setup.sh")
            });
        let mut line = String::new();
        BufReader::new(xvfb.stdout.take().expect("piped")).read_line(&mut line).expect("Xvfb prints its display");
        let name = format!(":{}", line.trim());
        let mut display = Display { name, children: vec![xvfb], _one_at_a_time: guard };
        display.start_window_manager();
        display
    }

    /// Starts openbox and waits until it announces itself with _NET_SUPPORTING_WM_CHECK on the
    /// root window; one that exits or stays silent is replaced, and the last one's words are
    /// in the failure.
    fn start_window_manager(&mut self) {
        let log = std::env::temp_dir().join(format!("ocean-view-{}-openbox.log", std::process::id()));
        let mut history = Vec::new();
        for attempt in 1..=WM_ATTEMPTS {
            let mut wm = Command::new("openbox")
                .env("DISPLAY", &self.name)
                .stdout(Stdio::null())
                .stderr(std::fs::File::create(&log).expect("openbox's log in the temp dir"))
                .spawn()
                .unwrap_or_else(|e| {
                    panic!("the minimize test needs a window manager: openbox cannot start ({e}); run scripts/setup.sh")
                });
            let start = Instant::now();
            let mut exited = None;
            while start.elapsed() < WM_WAIT && exited.is_none() {
                if self.window_manager_announced() {
                    self.children.push(wm);
                    return;
                }
                exited = wm.try_wait().expect("openbox's status");
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = wm.kill();
            let _ = wm.wait();
            let said = std::fs::read_to_string(&log).unwrap_or_default();
            let how = exited.map_or(format!("silent for {} s", WM_WAIT.as_secs()), |s| format!("exited ({s})"));
            history.push(format!("attempt {attempt}: {how}; said: {}", said.trim()));
        }
        let xvfb = self.children[0].try_wait().ok().flatten().map_or("running".into(), |s| format!("exited ({s})"));
        panic!("openbox did not start on {} (Xvfb {xvfb}):\n{}", self.name, history.join("\n"));
    }

    fn window_manager_announced(&self) -> bool {
        let out = Command::new("xprop")
            .args(["-display", &self.name, "-root", "_NET_SUPPORTING_WM_CHECK"])
            .output()
            .unwrap_or_else(|e| panic!("xprop (x11-utils) is needed to wait for the window manager: {e}"));
        String::from_utf8_lossy(&out.stdout).contains("window id")
    }
}

impl Drop for Display {
    fn drop(&mut self) {
        for child in self.children.iter_mut().rev() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ocean-view-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn ocean(display: Option<&Display>, args: &[&str]) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_ocean"));
    command.args(args).env("OCEAN_CACHE_DIR", "");
    match display {
        Some(d) => command.env("DISPLAY", &d.name).env_remove("WAYLAND_DISPLAY"),
        None => command.env_remove("DISPLAY").env_remove("WAYLAND_DISPLAY"),
    };
    command.output().unwrap()
}

fn succeed(out: &std::process::Output, what: &str) {
    assert!(
        out.status.success(),
        "{what} failed:\n{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn report(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn rgb(path: &Path) -> image::RgbImage {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8()
}

fn mean_rows(img: &image::RgbImage, rows: std::ops::Range<u32>) -> [f64; 3] {
    let mut sum = [0.0; 3];
    let mut n = 0.0;
    for y in rows {
        for x in 0..img.width() {
            let p = img.get_pixel(x, y);
            (0..3).for_each(|c| sum[c] += p[c] as f64);
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

#[test]
fn a_session_with_a_resize_and_a_minimize_is_validation_clean() {
    let display = Display::open();
    let dir = scratch("session");
    let (shot, json, trace) = (dir.join("last.png"), dir.join("report.json"), dir.join("trace.json"));
    let out = ocean(
        Some(&display),
        &[
            "view",
            "--validation",
            "--frames",
            "60",
            "--width",
            "320",
            "--height",
            "200",
            "--resize-at",
            "10:400x240",
            "--minimize-at",
            "25:5",
            "--screenshot",
            shot.to_str().unwrap(),
            "--report",
            json.to_str().unwrap(),
            "--trace",
            trace.to_str().unwrap(),
        ],
    );
    succeed(&out, "ocean view");
    let r = report(&json);
    assert_eq!(r["frames"], 60);
    // The timeline: a CPU span per presented frame, the GPU's passes of the frames it finished.
    let t = report(&trace);
    let events = t["traceEvents"].as_array().unwrap();
    let count = |tid: u64, name: &str| events.iter().filter(|e| e["tid"] == tid && e["name"] == name).count();
    let cpu_frames = events.iter().filter(|e| e["tid"] == 1 && e["cat"] == "frame").count();
    let gpu_frames = events.iter().filter(|e| e["tid"] == 2 && e["cat"] == "frame").count();
    assert_eq!(cpu_frames, 60, "a CPU span per presented frame");
    assert!((50..=60).contains(&gpu_frames), "{gpu_frames} GPU frames of 60");
    assert_eq!(
        count(2, "host tonemap"),
        gpu_frames,
        "each GPU frame ends with the tone mapping into the swapchain image"
    );
    assert!(events.iter().filter(|e| e["name"] == "frame interval ms").count() >= 50);
    assert_eq!(r["validation_errors"], 0, "{}", r["validation_messages"]);
    assert!(r["swapchain_recreations"].as_u64().unwrap() >= 1, "the resize recreates the swapchain: {r}");
    assert!(r["minimized_seen"].as_u64().unwrap() >= 1, "the window manager minimized the window: {r}");
    assert_eq!((r["width"].as_u64(), r["height"].as_u64()), (Some(400), Some(240)), "the window took the new size");
    assert!(r["fps"].as_f64().unwrap() > 0.0 && r["gpu_ms"]["shade"].as_f64().unwrap() > 0.0, "{r}");
    for key in ["device", "present_mode", "surface_format", "cpu_frame_ms", "validation_warnings"] {
        assert!(!r[key].is_null(), "report lacks {key}");
    }
    // The last frame, as shown at the new size: the sky above the sea, neither black.
    let img = rgb(&shot);
    assert_eq!(img.dimensions(), (400, 240));
    let (sky, sea) = (mean_rows(&img, 0..60), mean_rows(&img, 180..240));
    let luma = ocean::output::luminance_rgb;
    assert!(luma(sky) > 100.0, "the default scene's sky is bright: {sky:?}");
    assert!(luma(sea) > 20.0, "the sea is not black: {sea:?}");
    assert!(luma(sky) > luma(sea) + 20.0, "the sky above is brighter than the sea below: {sky:?} {sea:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_paused_frame_matches_ocean_render() {
    let display = Display::open();
    let dir = scratch("paused");
    let (shown, rendered) = (dir.join("shown.png"), dir.join("rendered.png"));
    let size = ["--width", "320", "--height", "200"];
    let mut view = vec!["view", "--validation", "--time-scale", "0", "--frames", "3", "--screenshot"];
    view.push(shown.to_str().unwrap());
    view.extend(size);
    succeed(&ocean(Some(&display), &view), "ocean view");
    let mut render = vec!["render", "--out", rendered.to_str().unwrap()];
    render.extend(size);
    succeed(&ocean(None, &render), "ocean render");
    let (a, b) = (rgb(&shown), rgb(&rendered));
    assert_eq!(a.dimensions(), b.dimensions());
    // The same passes and tone curve; an sRGB swapchain encodes on store and `render` in the
    // shader, which round differently by at most one level.
    let worst = a.pixels().zip(b.pixels()).flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c]))).max();
    assert!(worst <= Some(2), "largest difference {worst:?} levels of 255");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_view_input_is_one_clear_line() {
    let cases: [(&[&str], &str); 4] = [
        (&["view", "--resize-at", "10:0x360"], "[1, 16384]"),
        (&["view", "--minimize-at", "20"], "FRAME:FRAMES"),
        (&["view", "--present", "sometimes"], "sometimes"),
        (&["view", "--time-scale", "inf"], "time scale"),
    ];
    for (args, needle) in cases {
        let out = ocean(None, args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains(needle), "{args:?}: {err}");
    }
    // No display at all: one line that says so, no panic.
    let out = ocean(None, &["view", "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "a view without a display must fail");
    assert!(err.contains("display") && !err.contains("panicked"), "{err}");
}

/// The example host (examples/host): its own window, swapchain, buoy and frame loop with the
/// ocean embedded, resized half way, validation-clean; its last frame shows the buoy in the sea.
#[test]
fn the_example_host_draws_its_buoy_in_the_sea_through_a_resize() {
    let display = Display::open();
    // Built by `cargo test` beside the program: target/<profile>/examples/host.
    let bin = Path::new(env!("CARGO_BIN_EXE_ocean")).with_file_name("examples").join("host");
    let shot = scratch("example-host").join("host.png");
    let out = Command::new(&bin)
        .env("DISPLAY", &display.name)
        .args(["--frames", "8", "--resize", "480x360", "--validation", "--width", "320", "--height", "240"])
        .arg("--screenshot")
        .arg(&shot)
        .output()
        .unwrap_or_else(|e| panic!("{}: {e}", bin.display()));
    succeed(&out, "the example host");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("validation errors: 0"), "{stdout}");
    let img = rgb(&shot);
    assert_eq!(img.dimensions(), (480, 360), "the last frame after the resize");
    // The buoy's paint in the ocean's light, below the horizon: the face towards the eye is
    // backlit at sunset (the sun behind the buoy), a dark red with the paint's hue, red over
    // twice the green, where the sea is blue-grey and its glitter white to pale gold.
    let (w, h) = img.dimensions();
    let paint = (h / 2..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| img.get_pixel(x, y))
        .filter(|p| p[0] as i32 > 2 * p[1] as i32 + 8 && p[0] as i32 > p[2] as i32 + 10)
        .count();
    assert!(paint > 30, "{paint} buoy pixels");
}
