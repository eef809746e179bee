//! The shading loop's two ways of reading the wave table (in blocks shared by subgroup
//! broadcasts, or per train) give the same picture, on views whose loops end at every block
//! position, at sizes that leave subgroups partly outside the image, and for every method.

mod common;

use common::{assert_clean, gpu};
use ocean::app::{render_on, RenderRequest};
use ocean::embed::Shading;
use ocean::model::scene::Scene;
use ocean::render::passes::ocean::{Method, ShaderConfig, TrainReads};
use ocean::render::passes::shade::train_reads_on;
use ocean::render::renderer::RenderedFrame;
use ocean::vk::gpu::Gpu;
use std::path::Path;

fn render(
    gpu: &Gpu,
    scene: &Scene,
    size: (u32, u32),
    method: Method,
    reads: TrainReads,
) -> (Vec<String>, RenderedFrame) {
    let shader = ShaderConfig { method, train_reads: reads, ..ShaderConfig::default() };
    let options = Shading { shader, ..Shading::default() };
    let request =
        RenderRequest { validation: true, shading: options, ..RenderRequest::new(scene.clone(), size.0, size.1) };
    let (report, frame) = render_on(gpu, &request).unwrap();
    assert_clean(&report, &format!("{reads:?}"));
    (report.pipelines, frame)
}

#[test]
fn blocks_and_per_train_reads_agree() {
    let gpu = gpu();
    let blocks = train_reads_on(&gpu.device, TrainReads::Blocks);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    // 60 trains (a partial last block), 1, 256; near, far and straight-down views.
    let cases = [
        ("default.toml", (97, 61), Method::Full),
        ("default.toml", (1, 1), Method::Full),
        ("default.toml", (64, 40), Method::ConstantBrdf),
        ("default.toml", (64, 40), Method::NoFilter),
        ("default.toml", (64, 40), Method::Paper),
        ("extreme/one_wave.toml", (40, 30), Method::Full),
        ("extreme/waves_256.toml", (40, 30), Method::Full),
        ("extreme/look_down.toml", (33, 17), Method::Full),
        ("extreme/camera_5cm.toml", (64, 40), Method::Full),
        ("noon.toml", (64, 40), Method::Full),
    ];
    for (file, size, method) in cases {
        let scene = Scene::load(&dir.join(file)).unwrap();
        let (pipelines, a) = render(&gpu, &scene, size, method, TrainReads::Blocks);
        let (_, b) = render(&gpu, &scene, size, method, TrainReads::PerTrain);
        let named = if blocks == TrainReads::Blocks { "read in blocks" } else { "read per train" };
        assert!(pipelines.iter().any(|p| p.contains(named)), "{file}: the report says {pipelines:?}");
        // The same sums to f32 rounding (trains past a pixel's cut are summed in the loop rather
        // than taken from the CPU's prefix): equal to binary16 rounding of the brightest value.
        let peak = b.hdr.iter().flat_map(|p| p[..3].iter().copied()).fold(0.0f32, f32::max).max(1e-6);
        let d =
            a.hdr.iter().zip(&b.hdr).flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs())).fold(0.0, f32::max);
        assert!(d <= 1e-3 * peak, "{file} {size:?} {method:?}: blocks and per-train reads differ by {d} (peak {peak})");
    }
}
