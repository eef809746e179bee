//! Profiling under validation: pipeline statistics against what the frame must do, the trace's
//! spans nested and on one clock, the shader's train counts, and the CLI's refusals.

mod common;

use common::{assert_clean, gpu, render_with};
use ocean::app::profile::{check, profile_on, ProfileRequest, CPU_TRACK, GPU_TRACK};
use ocean::embed::Shading;
use ocean::model::scene::Scene;
use ocean::render::renderer::{Options, Renderer};
use ocean::render::timeline::CpuSpans;
use ocean::vk::clock::host_now_ns;
use serde_json::Value;
use std::path::PathBuf;

fn request(scene: Scene, trace: Option<PathBuf>, frames: u32, warmup: u32) -> ProfileRequest {
    ProfileRequest {
        scene,
        scene_name: "default".into(),
        width: 128,
        height: 96,
        frames,
        warmup,
        trace,
        report: None,
        png: None,
        shading: Shading::default(),
        specialize: true,
        validation: true,
        device: None,
    }
}

#[test]
fn pipeline_statistics_match_the_frame_s_geometry_and_dispatches() {
    let gpu = gpu();
    let (w, h) = (256, 192);
    let options = Shading { statistics: true, ..Shading::default() };
    let (report, frame) = render_with(&gpu, &Scene::default(), w, h, options);
    assert_clean(&report, "statistics");
    let stats = report.pipeline_statistics.expect("lavapipe has pipeline statistics");
    // Compute passes: one invocation per texel, in 8x8 groups.
    let groups = |w: u32, h: u32| (w.div_ceil(8) * h.div_ceil(8) * 64) as u64;
    // The tone mapping into the host's LDR image: a full-screen triangle, a fragment a pixel and
    // at most the 2x2 quads' helpers along the image's edges.
    let fragments = stats["host tonemap"].fragment_shader_invocations;
    assert!((w as u64 * h as u64..=(w as u64 + 4) * (h as u64 + 4)).contains(&fragments), "{fragments} fragments");
    // The physical sky's sky-view table, then the 512 x 512 map resampled from it.
    let (vw, vh) = ocean::model::atmosphere::SKY_VIEW_SIZE;
    assert_eq!(stats["sky_map"].compute_shader_invocations, 512 * 512 + (vw * vh) as u64);
    assert!(stats["shade"].compute_shader_invocations <= groups(w, h));
    assert_eq!(stats["shade"].vertex_shader_invocations, 0);
    // The ocean pass: the grid's triangle list, and the sky rows' one triangle.
    let (c, r) = (report.grid.columns as u64, report.grid.rows as u64);
    let sky = if frame.frame.sky_rows > 0 { 3 } else { 0 };
    let ocean = stats["ocean"];
    assert_eq!(ocean.input_assembly_vertices, 6 * (c - 1) * (r - 1) + sky);
    assert_eq!(ocean.input_assembly_primitives, ocean.input_assembly_vertices / 3);
    // Each grid node is shaded at least once, at most once per index.
    assert!(
        (c * r + sky..=ocean.input_assembly_vertices).contains(&ocean.vertex_shader_invocations),
        "{} vertex invocations for {} nodes and {} indices",
        ocean.vertex_shader_invocations,
        c * r,
        ocean.input_assembly_vertices
    );
    assert!(ocean.fragment_shader_invocations >= (w * h) as u64, "every pixel is covered by the sea or the sky rows");
}

#[test]
fn a_full_screen_sky_shades_each_pixel_about_once() {
    let gpu = gpu();
    let scene = Scene::load(std::path::Path::new("scenes/extreme/look_up.toml")).unwrap();
    let (w, h) = (256, 192);
    let options = Shading { statistics: true, ..Shading::default() };
    let (report, _) = render_with(&gpu, &scene, w, h, options);
    assert_clean(&report, "look_up statistics");
    let ocean = report.pipeline_statistics.unwrap()["ocean"];
    let pixels = (w * h) as u64;
    // One triangle over the whole image: every pixel once, plus at most the rasterizer's partial
    // blocks along its edges (llvmpipe shades 4x4 blocks, GPUs 2x2 quads).
    assert_eq!(ocean.input_assembly_primitives, 1);
    assert!(
        (pixels..=pixels + pixels / 10).contains(&ocean.fragment_shader_invocations),
        "{} fragment invocations for {pixels} pixels",
        ocean.fragment_shader_invocations
    );
}

#[test]
fn the_trace_nests_each_track_and_puts_gpu_passes_inside_their_submit_to_fence_window() {
    let gpu = gpu();
    let path = std::env::temp_dir().join(format!("ocean-trace-{}.json", std::process::id()));
    let req = request(Scene::default(), Some(path.clone()), 4, 1);
    let report = profile_on(&gpu, &req, CpuSpans::default(), host_now_ns()).unwrap();
    assert_eq!(report.validation_errors, 0);
    let trace: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    std::fs::remove_file(&path).ok();
    let events = trace["traceEvents"].as_array().unwrap();
    let spans: Vec<&Value> = events.iter().filter(|e| e["ph"] == "X").collect();
    let (cpu, gpu_track) = (CPU_TRACK.0 as u64, GPU_TRACK.0 as u64);
    // Every track's spans nest: sorted by start, each lies within the open span that contains it.
    for track in [cpu, gpu_track] {
        let mut on: Vec<(f64, f64)> = spans
            .iter()
            .filter(|e| e["tid"] == track)
            .map(|e| (e["ts"].as_f64().unwrap(), e["ts"].as_f64().unwrap() + e["dur"].as_f64().unwrap()))
            .collect();
        on.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
        let mut stack: Vec<(f64, f64)> = Vec::new();
        for (begin, end) in on {
            assert!(end >= begin);
            while stack.last().is_some_and(|&(_, e)| e <= begin) {
                stack.pop();
            }
            if let Some(&(_, parent_end)) = stack.last() {
                assert!(end <= parent_end + 1e-3, "span [{begin}, {end}] overlaps its parent's end {parent_end}");
            }
            stack.push((begin, end));
        }
    }
    let span = |tid: u64, name: &str, frame: u64| {
        spans.iter().find(|e| e["tid"] == tid && e["name"] == name && e["args"]["frame"] == frame).copied()
    };
    for frame in 0..4u64 {
        let submit = span(cpu, "submit", frame).expect("a submit span");
        let fence = span(cpu, "wait for fence", frame).expect("a fence span");
        let window = (submit["ts"].as_f64().unwrap(), fence["ts"].as_f64().unwrap() + fence["dur"].as_f64().unwrap());
        let gpu_frame = span(gpu_track, &format!("frame {frame}"), frame).expect("a GPU frame");
        let (begin, end) =
            (gpu_frame["ts"].as_f64().unwrap(), gpu_frame["ts"].as_f64().unwrap() + gpu_frame["dur"].as_f64().unwrap());
        // Calibrated on lavapipe: within a microsecond of the window.
        assert!(begin >= window.0 - 1.0 && end <= window.1 + 1.0, "GPU frame [{begin}, {end}] outside {window:?}");
        assert_eq!(gpu_frame["args"]["warmup"], frame == 0);
    }
    // The trace's pass names are the report's.
    let mut traced: Vec<String> = spans
        .iter()
        .filter(|e| e["tid"] == gpu_track && e["cat"] == "gpu" && e["args"]["warmup"] == false)
        .map(|e| e["name"].as_str().unwrap().to_owned())
        .collect();
    traced.sort();
    traced.dedup();
    let mut reported: Vec<String> = report.passes.iter().map(|p| p.name.clone()).collect();
    reported.sort();
    assert_eq!(traced, reported);
    assert!(events.iter().any(|e| e["ph"] == "C" && e["name"] == "GPU ms per frame"));
    assert!(trace["otherData"]["clock"].as_str().unwrap().contains("calibrated"), "{}", trace["otherData"]["clock"]);
    assert_eq!(report.timings[0].round.len(), 3, "the warm-up frame is not timed");
    let shade = report.passes.iter().find(|p| p.name == "shade").unwrap();
    assert!(shade.ns_per_invocation.is_some_and(|ns| ns > 0.0));
}

#[test]
fn counting_trains_leaves_the_picture_alone_and_counts_what_the_pixels_resolve() {
    let gpu = gpu();
    let scene = Scene::default();
    let mut counting = Options::default();
    counting.shader.count_trains = true;
    let mut plain = Renderer::new(&gpu, &scene, 128, 96, Options::default()).unwrap();
    let mut counted = Renderer::new(&gpu, &scene, 128, 96, counting).unwrap();
    let a = plain.render(&scene).unwrap();
    let b = counted.render(&scene).unwrap();
    assert_eq!(a.ldr, b.ldr, "counting changes no pixel");
    assert!(plain.train_counts().unwrap().is_none());
    let counts = counted.train_counts().unwrap().expect("a counting renderer");
    let waves = ocean::model::waves::generate(&scene).trains.len() as f64;
    assert!(counts.sea_pixels > 128 * 96 / 4 && counts.sea_pixels <= 128 * 96, "{counts:?}");
    let (evaluated, weighted) = (counts.evaluated_per_sea_pixel(), counts.weighted_per_sea_pixel());
    assert!(weighted > 1.0 && weighted <= evaluated && evaluated <= waves, "{counts:?} of {waves} trains");
    // A second frame counts afresh (the host zeroes the counters).
    counted.render(&scene).unwrap();
    assert_eq!(counted.train_counts().unwrap(), Some(counts));
    assert_eq!(counts.packet_terms, 0, "no local waves, no packet terms");
    // A splash's rings: each pixel they reach counts the packets whose reach holds it, at most
    // every packet alive; the picture is again the same.
    let mut splash = scene.clone();
    splash.splashes = Scene::parse("[[splash]]\nposition_m = [30.0, 0.0]\ntime_s = 0.0\nradius_m = 1.0\n", "splash")
        .unwrap()
        .splashes;
    splash.render.time_s = 4.0;
    let mut plain = Renderer::new(&gpu, &splash, 128, 96, Options::default()).unwrap();
    let mut counted = Renderer::new(&gpu, &splash, 128, 96, counting).unwrap();
    assert_eq!(plain.render(&splash).unwrap().ldr, counted.render(&splash).unwrap().ldr, "counting changes no pixel");
    let counts = counted.train_counts().unwrap().unwrap();
    let alive = counted.packet_stats().expect("the splash's packets").alive as u64;
    assert!(counts.packet_terms > 0 && counts.packet_terms < counts.sea_pixels * alive, "{counts:?}, {alive} packets");
    assert_eq!(gpu.validation_counts().error_total(), 0);
}

#[test]
fn bad_profile_arguments_are_refused_in_one_line() {
    let e = check(&request(Scene::default(), None, 0, 0)).unwrap_err().to_string();
    assert!(e.contains("--frames 0"), "{e}");
    let e = check(&request(Scene::default(), None, 3, 3)).unwrap_err().to_string();
    assert!(e.contains("--warmup 3 must be less than --frames 3"), "{e}");
    let e =
        check(&request(Scene::default(), Some("/nonexistent-folder/trace.json".into()), 3, 1)).unwrap_err().to_string();
    assert!(e.contains("/nonexistent-folder/trace.json") && !e.contains('\n'), "{e}");
}
