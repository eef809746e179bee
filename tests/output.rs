//! Where outputs go: regular files atomically, devices, pipes and symlinks in place, `-` to
//! standard output, failed writes as errors; and the progress lines of long commands.

mod common;

use common::ocean_cli;
use ocean::output::progress::{seconds, time_left, Progress, Style};
use ocean::output::target::Target;
use ocean::output::write_text;
use std::io::{Read, Write};
use std::os::unix::fs::{FileTypeExt, PermissionsExt};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ocean-output-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::canonicalize(&dir).unwrap() // targets are named by their real folders
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo").arg(path).status().expect("mkfifo runs");
    assert!(status.success());
}

/// Files in `dir` whose names mark a partial write.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("partial"))
        .collect()
}

#[test]
fn targets_are_classified_by_what_the_path_names() {
    let dir = scratch("classify");
    let file = dir.join("a.png");
    std::fs::write(&file, b"old").unwrap();
    assert_eq!(Target::of(Path::new("-")).unwrap(), Target::Stdout);
    assert_eq!(Target::of(&file).unwrap(), Target::Replace(file.clone()));
    assert_eq!(Target::of(&dir.join("new.png")).unwrap(), Target::Replace(dir.join("new.png")));
    // A relative symlink to a relative symlink to the file: the file, found from each link's folder.
    std::fs::create_dir(dir.join("sub")).unwrap();
    std::os::unix::fs::symlink("../a.png", dir.join("sub/link1")).unwrap();
    std::os::unix::fs::symlink("sub/link1", dir.join("link2")).unwrap();
    assert_eq!(Target::of(&dir.join("link2")).unwrap(), Target::Replace(file.clone()));
    // A dangling symlink: the file it names will be created.
    std::os::unix::fs::symlink("later.png", dir.join("dangling")).unwrap();
    assert_eq!(Target::of(&dir.join("dangling")).unwrap(), Target::Replace(dir.join("later.png")));
    assert_eq!(Target::of(Path::new("/dev/null")).unwrap(), Target::InPlace("/dev/null".into()));
    // Links to open descriptors are the kernel's to follow: written where they are.
    for fd in ["/dev/stdout", "/dev/fd/2"] {
        assert_eq!(Target::of(Path::new(fd)).unwrap(), Target::InPlace(fd.into()), "{fd}");
    }
    mkfifo(&dir.join("fifo"));
    assert_eq!(Target::of(&dir.join("fifo")).unwrap(), Target::InPlace(dir.join("fifo")));
    let e = Target::of(&dir).unwrap_err().to_string();
    assert!(e.contains("is a directory"), "{e}");
    std::os::unix::fs::symlink("loop_b", dir.join("loop_a")).unwrap();
    std::os::unix::fs::symlink("loop_a", dir.join("loop_b")).unwrap();
    let e = Target::of(&dir.join("loop_a")).unwrap_err().to_string();
    assert!(e.contains("loop_a") && e.contains("symbolic links"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn symlinks_pipes_and_permissions_survive_a_write() {
    let dir = scratch("write");
    // A regular file keeps its permissions and is replaced whole.
    let file = dir.join("report.json");
    std::fs::write(&file, "old and longer than the new text").unwrap();
    std::fs::set_permissions(&file, std::fs::Permissions::from_mode(0o640)).unwrap();
    write_text(&file, "new").unwrap();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
    assert_eq!(std::fs::metadata(&file).unwrap().permissions().mode() & 0o777, 0o640);
    // A symlink stays a symlink; the file it names gets the bytes.
    let link = dir.join("link.json");
    std::os::unix::fs::symlink("report.json", &link).unwrap();
    write_text(&link, "through the link").unwrap();
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "through the link");
    // A named pipe is written, not replaced by a file.
    let fifo = dir.join("fifo");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut text = String::new();
            std::fs::File::open(&fifo).unwrap().read_to_string(&mut text).unwrap();
            text
        })
    };
    write_text(&fifo, "down the pipe").unwrap();
    assert_eq!(reader.join().unwrap(), "down the pipe");
    assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failed_writes_are_errors_naming_the_path() {
    let e = write_text(Path::new("/dev/full"), "x").unwrap_err().to_string();
    assert!(e.contains("/dev/full") && e.contains("space"), "{e}");
    assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device());
    let dir = scratch("fail");
    let missing = dir.join("no/such/folder/out.png");
    let e = write_text(&missing, "x").unwrap_err().to_string();
    assert!(e.contains("no/such/folder/out.png"), "{e}");
    assert!(leftovers(&dir).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_cli_writes_to_standard_output_and_reports_failed_writes() {
    let dir = scratch("cli");
    let report = dir.join("r.json");
    let report_arg = report.display().to_string();
    // The PNG on standard output, the status line on standard error.
    let out = ocean_cli(&["render", "--width", "16", "--height", "12", "--out", "-", "--report", &report_arg]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG on standard output");
    let png = image::load_from_memory(&out.stdout).unwrap();
    assert_eq!((png.width(), png.height()), (16, 12));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.starts_with("standard output: 16x12"), "{stderr}");
    assert!(report.exists());
    // /dev/stdout is standard output too: the PNG there, the status line off it.
    let out = ocean_cli(&["render", "--width", "16", "--height", "12", "--out", "/dev/stdout"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.starts_with(b"\x89PNG\r\n\x1a\n"), "a PNG through /dev/stdout");
    assert!(String::from_utf8_lossy(&out.stderr).starts_with("/dev/stdout: 16x12"));
    image::load_from_memory(&out.stdout).expect("nothing but the PNG on standard output");
    // The report as JSON on standard output.
    let png_path = dir.join("o.png");
    let out =
        ocean_cli(&["render", "--width", "16", "--height", "12", "--out", png_path.to_str().unwrap(), "--report", "-"]);
    assert!(out.status.success());
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on standard output");
    assert_eq!(json["width"], 16);
    // A device is written in place and a failed write fails the run, in one line.
    let out = ocean_cli(&["render", "--width", "16", "--height", "12", "--out", "/dev/full"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "writing to /dev/full must fail");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: /dev/full:"), "{stderr}");
    assert!(std::fs::metadata("/dev/full").unwrap().file_type().is_char_device(), "the device node stays");
    // Two outputs cannot share standard output; the reference's sibling files need a name.
    for args in [
        vec!["render", "--out", "-", "--report", "-"],
        vec!["render", "--exr", "-", "--out", "-"],
        vec!["render", "--out", "-", "--report", "/dev/stdout"],
        vec!["reference", "--out", "-"],
        vec!["reference", "--png", "-"],
    ] {
        let out = ocean_cli(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{args:?}");
        assert!(stderr.starts_with("error: ") && stderr.contains('-'), "{args:?}: {stderr}");
        assert_eq!(stderr.trim_end().lines().count(), 1, "{args:?}: {stderr}");
        assert!(out.stdout.is_empty(), "{args:?}: nothing on standard output");
    }
    // A ground truth into a folder that does not exist fails before it traces anything: in one
    // line naming the path, and at once (a 512 x 512 trace at 64 x 64 samples takes hours).
    let missing = dir.join("no/such/folder/ref.exr");
    let started = std::time::Instant::now();
    let out = ocean_cli(&[
        "reference",
        "--width",
        "512",
        "--height",
        "512",
        "--samples",
        "64",
        "--out",
        missing.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("no/such/folder"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(started.elapsed().as_secs() < 30, "refused only after {:?}", started.elapsed());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_reference_reports_its_progress_on_standard_error() {
    let dir = scratch("progress");
    let out = dir.join("ref.exr");
    let out_arg = out.display().to_string();
    // A scene the ground truth traces (Preetham's sky).
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/figure/calm.toml");
    let run = ocean_cli(&[
        "reference",
        "--scene",
        scene,
        "--width",
        "40",
        "--height",
        "30",
        "--samples",
        "1",
        "--out",
        &out_arg,
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stderr = String::from_utf8_lossy(&run.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    // Not a terminal: plain lines, the last at 100%, and nothing but progress there.
    assert!(!stderr.contains('\r'), "no bar outside a terminal: {stderr:?}");
    assert!(lines.iter().all(|l| l.starts_with("ground truth 40x30, 1x1 samples per pixel: ")), "{stderr}");
    assert!(lines.last().is_some_and(|l| l.contains("100%")), "{stderr}");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("40x30 with 1x1 samples per pixel"), "the summary on standard output: {stdout}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A writer the test can read back.
#[derive(Clone, Default)]
struct Captured(Arc<Mutex<Vec<u8>>>);
impl Write for Captured {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(bytes);
        Ok(bytes.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
impl Captured {
    fn text(&self) -> String {
        String::from_utf8(self.0.lock().unwrap().clone()).unwrap()
    }
}

#[test]
fn progress_lines_say_how_far_and_how_long() {
    let sink = Captured::default();
    let mut p = Progress::to(Box::new(sink.clone()), Style::Lines, "ground truth", 200, "tiles", true);
    for done in 1..=200 {
        p.set(done, None);
    }
    let text = sink.text();
    let lines: Vec<&str> = text.lines().collect();
    // One line per tenth, the last at 100%, each with the count and the elapsed time.
    assert_eq!(lines.len(), 10, "{text}");
    assert!(lines[0].starts_with("ground truth: 20/200 tiles (10%), "), "{text}");
    assert!(lines[0].contains("left"), "an estimate of the time left: {text}");
    assert!(lines[9].starts_with("ground truth: 200/200 tiles (100%), ") && !lines[9].contains("left"), "{text}");
    // Named steps are each shown; without a unit only the percentage is.
    let sink = Captured::default();
    let mut p = Progress::to(Box::new(sink.clone()), Style::Lines, "bench", 4, "", false);
    p.set(1, Some("timing storm"));
    p.set(2, Some("timing calm"));
    assert_eq!(sink.text(), format!("bench: 25%, {0}: timing storm\nbench: 50%, {0}: timing calm\n", seconds(0.0)));
    // A bar redraws in place and ends its line when done.
    let sink = Captured::default();
    let mut p = Progress::to(Box::new(sink.clone()), Style::Bar, "speed", 3, "scenes", true);
    p.set(1, None);
    p.set(3, None);
    let text = sink.text();
    assert!(text.starts_with("\rspeed [##########") && text.ends_with("3/3 scenes (100%), 0.0 s\x1b[K\n"), "{text:?}");
}

#[test]
fn time_left_and_durations() {
    assert_eq!(time_left(10.0, 0, 100), None, "no estimate before the first unit");
    assert_eq!(time_left(10.0, 25, 100), Some(30.0));
    assert_eq!(time_left(10.0, 100, 100), Some(0.0));
    assert_eq!(seconds(0.42), "0.4 s");
    assert_eq!(seconds(42.4), "42 s");
    assert_eq!(seconds(185.0), "3 min 05 s");
    assert_eq!(seconds(7440.0), "2 h 04 min");
}
