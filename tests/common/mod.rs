//! Shared helpers for GPU tests: a validated context on the test device, renders with reports,
//! and a headless host (host.rs).
#![allow(dead_code)]

pub mod host;

use ocean::app::report::Report;
use ocean::app::{render_on, RenderRequest};
use ocean::embed::Shading;
use ocean::model::scene::Scene;
use ocean::render::passes::ocean::{Method, ShaderConfig, Terms};
use ocean::render::renderer::{Options, RenderedFrame, Renderer};
use ocean::vk::gpu::Gpu;

/// A context with the validation layer and synchronization validation on, its pipeline cache in
/// memory only (the tests leave nothing in the user's cache folder). `OCEAN_TEST_DEVICE` picks a
/// device by name (CI sets VK_DRIVER_FILES to lavapipe instead).
pub fn gpu() -> Gpu {
    let filter = std::env::var("OCEAN_TEST_DEVICE").ok();
    Gpu::with_cache_dir(true, filter.as_deref(), None)
        .unwrap_or_else(|e| panic!("GPU tests need Vulkan with validation: {e}"))
}

pub fn render(gpu: &Gpu, scene: &Scene, width: u32, height: u32) -> (Report, RenderedFrame) {
    render_with(gpu, scene, width, height, Shading::default())
}

/// A validated single-frame render with the given method, terms and supersampling.
pub fn render_with(gpu: &Gpu, scene: &Scene, width: u32, height: u32, shading: Shading) -> (Report, RenderedFrame) {
    let request = RenderRequest { validation: true, shading, ..RenderRequest::new(scene.clone(), width, height) };
    render_on(gpu, &request).unwrap_or_else(|e| panic!("render failed: {e}"))
}

/// Renders with only some BRDF terms (specialization constants).
pub fn render_terms(gpu: &Gpu, scene: &Scene, width: u32, height: u32, terms: Terms) -> RenderedFrame {
    render_terms_by(gpu, scene, width, height, terms, Method::Full)
}

/// Renders with only some BRDF terms, by `method`, the reflected sun at its expected value (no
/// glints: the tests that use it compare pixels with f64 formulas of that value).
pub fn render_terms_by(
    gpu: &Gpu,
    scene: &Scene,
    width: u32,
    height: u32,
    terms: Terms,
    method: Method,
) -> RenderedFrame {
    render_shader(gpu, scene, width, height, ShaderConfig { glints: false, ..ShaderConfig::terms_only(terms, method) })
}

/// One frame with the given shader configuration and every other option at its default.
pub fn render_shader(gpu: &Gpu, scene: &Scene, width: u32, height: u32, shader: ShaderConfig) -> RenderedFrame {
    let mut renderer = Renderer::new(gpu, scene, width, height, Options { shader, ..Options::default() }).unwrap();
    renderer.render(scene).unwrap()
}

/// Runs the `ocean` program with `args`, its pipeline cache off the disk.
pub fn ocean_cli(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_ocean")).args(args).env("OCEAN_CACHE_DIR", "").output().unwrap()
}

/// Fails on any validation error or non-finite pixel, naming the message ids.
pub fn assert_clean(report: &Report, what: &str) {
    assert_eq!(report.validation_errors, 0, "{what}: validation errors {:?}", report.validation_messages);
    assert_eq!(report.nonfinite_pixels, 0, "{what}: non-finite pixels");
}

/// Rec. 709 luminance of a linear RGB pixel.
pub fn luminance(p: [f32; 4]) -> f64 {
    0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64
}
