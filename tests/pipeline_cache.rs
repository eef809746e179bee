//! The pipeline cache on disk: one file per device and driver, loaded when valid, ignored (and
//! replaced) when corrupt or from another device, and never a validation error either way.

mod common;

use ocean::app::{render_on, RenderRequest};
use ocean::model::scene::Scene;
use ocean::vk::gpu::Gpu;
use ocean::vk::pipeline_cache::{check_header, file_name};
use std::path::{Path, PathBuf};

fn gpu_with_cache(dir: &Path) -> Gpu {
    let filter = std::env::var("OCEAN_TEST_DEVICE").ok();
    Gpu::with_cache_dir(true, filter.as_deref(), Some(dir)).expect("a validated context")
}

/// A validated 32x24 frame; returns the cache status the run started from.
fn render_once(dir: &Path) -> (String, u64, PathBuf) {
    let gpu = gpu_with_cache(dir);
    let request = RenderRequest { validation: true, ..RenderRequest::new(Scene::default(), 32, 24) };
    let (report, _) = render_on(&gpu, &request).unwrap();
    common::assert_clean(&report, "render with the pipeline cache");
    let cache = report.pipeline_cache;
    (cache.status, cache.loaded_bytes, cache.file.expect("a disk cache"))
    // `gpu` drops here and saves the cache.
}

#[test]
fn the_cache_file_is_kept_checked_and_replaced() {
    let dir = std::env::temp_dir().join(format!("ocean-pipeline-cache-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    // First run: no file yet; the run leaves one named after the device and driver.
    let (status, loaded, file) = render_once(&dir);
    assert_eq!((status.as_str(), loaded), ("none yet", 0));
    let gpu = gpu_with_cache(&dir);
    let properties = gpu.device.properties;
    drop(gpu);
    assert_eq!(file, dir.join(file_name(&properties)));
    let name = file_name(&properties);
    assert!(
        name.contains(&format!(
            "{:04x}-{:04x}-{:08x}",
            properties.vendor_id, properties.device_id, properties.driver_version
        )),
        "{name}"
    );
    let saved = std::fs::read(&file).expect("the cache file");
    check_header(&saved, &properties).expect("the saved file starts with this device's header");
    // Second run: loaded whole.
    let (status, loaded, _) = render_once(&dir);
    assert_eq!((status.as_str(), loaded), ("loaded", saved.len() as u64));
    // A file from another device, a truncated one and an unreadable one are ignored, and
    // replaced by a valid one when the run ends.
    let mut foreign = saved.clone();
    foreign[8] ^= 0xff; // vendor id
    let mut other_driver = saved.clone();
    other_driver[20] ^= 0xff; // pipeline cache UUID
    let cases: [(&[u8], &str); 4] = [
        (&foreign, "made by device"),
        (&other_driver, "another driver"),
        (&saved[..20], "shorter than a cache header"),
        (b"not a pipeline cache, but longer than a header is", "not valid"),
    ];
    for (bytes, why) in cases {
        std::fs::write(&file, bytes).unwrap();
        let (status, loaded, _) = render_once(&dir);
        assert!(status.starts_with("ignored") && status.contains(why), "{why}: {status}");
        assert_eq!(loaded, 0);
        check_header(&std::fs::read(&file).unwrap(), &properties).expect("replaced by a valid file");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn headers_are_checked_field_by_field() {
    let gpu = common::gpu();
    let p = gpu.device.properties;
    let mut header = Vec::new();
    for word in [32u32, 1, p.vendor_id, p.device_id] {
        header.extend_from_slice(&word.to_le_bytes());
    }
    header.extend_from_slice(&p.pipeline_cache_uuid);
    check_header(&header, &p).expect("a bare header of this device");
    let with = |i: usize, word: u32| {
        let mut h = header.clone();
        h[4 * i..4 * i + 4].copy_from_slice(&word.to_le_bytes());
        check_header(&h, &p).unwrap_err()
    };
    assert!(with(0, 16).contains("header size"));
    assert!(with(0, 64).contains("header size"), "a size past the data");
    assert!(with(1, 2).contains("version"));
    assert!(with(3, p.device_id ^ 1).contains("made by device"));
    assert!(check_header(&[], &p).unwrap_err().contains("shorter"));
}
