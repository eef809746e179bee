//! The ocean inside a host's frame (embed::Ocean): a headless host (tests/common/host.rs) draws
//! occluders at known depths, then the ocean; the host's pixels in front of the sea are kept, the
//! sea hides what lies behind its surface, its depth in the host's projection matches the f64
//! sphere, the sky fills only what the host left empty, and validation with synchronization
//! validation stays clean, with standard and reversed depth, finite and infinite far planes.

mod common;

use ash::vk;
use common::host::{Host, COLOUR_FORMAT, DEPTH_FORMAT};
use glam::{DMat4, DVec3, DVec4};
use ocean::embed::{
    FrameInput, Gpu, HostFormats, HostImage, ImageState, MirrorCover, Ocean, OceanDesc, Targets, HOST_PASSES,
};
use ocean::model::scene::Scene;

const W: u32 = 160;
const H: u32 = 120;
const EYE_HEIGHT: f64 = 6.0;
const FOV_Y: f64 = 60.0;
const PITCH: f64 = -10.0;
const FAR_M: f64 = 2000.0;
/// How far (m) the sea's depth may place its surface above or below the f64 sphere: where the
/// grid is undisplaced the depth is the pixel's own ray's (glsl/ocean.frag), and the fully
/// displaced cells are small enough that their flat triangles sag by millimetres; f32 depth
/// rounds to millimetres at a few hundred metres.
const SAG_M: f64 = 0.01;

/// Vulkan's clip y points down: glam's right-handed projections with y negated.
fn flip_y(p: DMat4) -> DMat4 {
    DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0)) * p
}

fn projection(reversed: bool, infinite: bool) -> DMat4 {
    let (fov, aspect, near) = (FOV_Y.to_radians(), W as f64 / H as f64, 0.1);
    flip_y(match (reversed, infinite) {
        (true, true) => DMat4::perspective_infinite_reverse_rh(fov, aspect, near),
        (false, true) => DMat4::perspective_infinite_rh(fov, aspect, near),
        (false, false) => DMat4::perspective_rh(fov, aspect, near, FAR_M),
        // Depth 1 - z of the standard one.
        (true, false) => {
            let reverse = DMat4::from_cols(DVec4::X, DVec4::Y, DVec4::new(0.0, 0.0, -1.0, 0.0), DVec4::W + DVec4::Z);
            reverse * DMat4::perspective_rh(fov, aspect, near, FAR_M)
        }
    })
}

fn view() -> DMat4 {
    let p = PITCH.to_radians();
    DMat4::look_to_rh(DVec3::new(0.0, 0.0, EYE_HEIGHT), DVec3::new(p.cos(), 0.0, p.sin()), DVec3::Z)
}

/// The clip depth of view depth `t` (m) under `projection` (view space looks down -z).
fn depth_of(projection: DMat4, t: f64) -> f64 {
    let c = projection * DVec4::new(0.0, 0.0, -t, 1.0);
    c.z / c.w
}

/// The view depth of clip depth `d`: the inverse of `depth_of`.
fn view_depth(projection: DMat4, d: f64) -> f64 {
    let (zz, zw, wz, ww) = (projection.z_axis.z, projection.z_axis.w, projection.w_axis.z, projection.w_axis.w);
    (d * ww - wz) / (d * zw - zz)
}

/// An occluder the host draws: a screen rectangle at one view depth, in one colour.
struct Occluder {
    rect: (u32, u32, u32, u32),
    depth_m: f64,
    colour: [f32; 4],
}

impl Occluder {
    fn contains(&self, x: u32, y: u32) -> bool {
        let (x0, y0, w, h) = self.rect;
        x >= x0 && x < x0 + w && y >= y0 && y < y0 + h
    }
}

const BACKGROUND: [f32; 4] = [0.5, 0.0, 0.5, 1.0];

/// What the host reads back of a frame: its colour (RGBA16F as f32), depth, and the LDR target
/// (RGBA8) where the ocean tone-mapped into one.
struct Readback {
    colour: Vec<[f32; 4]>,
    depth: Vec<f32>,
    ldr: Option<Vec<u8>>,
}

/// Draws the occluders (cleared rectangles at their depths), then the ocean (tone-mapping into an
/// LDR target where the ocean was made with its format), and reads back what it drew.
/// The name the test host's own pass is timed under in the ocean's profile.
const HOST_PASS: &str = "host occluders";

fn frame(host: &Host, ocean: &mut Ocean, projection: DMat4, reversed: bool, occluders: &[Occluder]) -> Readback {
    use vk::{AccessFlags2 as A, ImageLayout as L, ImageUsageFlags as U, PipelineStageFlags2 as S};
    let ldr_format = ocean.desc().formats.ldr;
    let colour = host.image(COLOUR_FORMAT, W, H, U::COLOR_ATTACHMENT | U::TRANSFER_SRC | U::SAMPLED);
    let ldr = ldr_format.map(|f| host.image(f, W, H, U::COLOR_ATTACHMENT | U::TRANSFER_SRC));
    let ldr_out = ldr.as_ref().map(|_| host.readback(4 * (W * H) as u64));
    let depth = host.image(DEPTH_FORMAT, W, H, U::DEPTH_STENCIL_ATTACHMENT | U::TRANSFER_SRC | U::SAMPLED);
    let pixels = (W * H) as usize;
    let colour_out = host.readback(8 * pixels as u64);
    let depth_out = host.readback(4 * pixels as u64);
    let (c, d) = (colour.image, depth.image);
    let tests = S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS;
    let far = if reversed { 0.0 } else { 1.0 };

    ocean.update(0, &FrameInput { time_s: 0.0, view: view(), projection }).unwrap();
    host.begin();
    host.barrier(
        &c,
        (L::UNDEFINED, S::NONE, A::NONE),
        (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
    );
    host.barrier(
        &d,
        (L::UNDEFINED, S::NONE, A::NONE),
        (L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL, tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
    );
    let colour_attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(c.view)
        .image_layout(L::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: BACKGROUND } })];
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(d.view)
        .image_layout(L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: far, stencil: 0 } });
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: c.extent };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&colour_attachment)
        .depth_attachment(&depth_attachment);
    // The host's draws, timed in the ocean's profile (embed::Ocean::record_host_pass).
    let mut draw = |cmd: vk::CommandBuffer| unsafe {
        // SAFETY (test host): the attachments are in the layouts the barriers above moved them to.
        host.device.cmd_begin_rendering(cmd, &info);
        for o in occluders {
            let clears = [
                vk::ClearAttachment {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    color_attachment: 0,
                    clear_value: vk::ClearValue { color: vk::ClearColorValue { float32: o.colour } },
                },
                vk::ClearAttachment {
                    aspect_mask: vk::ImageAspectFlags::DEPTH,
                    color_attachment: 0,
                    clear_value: vk::ClearValue {
                        depth_stencil: vk::ClearDepthStencilValue {
                            depth: depth_of(projection, o.depth_m) as f32,
                            stencil: 0,
                        },
                    },
                },
            ];
            let (x, y, w, h) = o.rect;
            let rect = vk::ClearRect {
                rect: vk::Rect2D {
                    offset: vk::Offset2D { x: x as i32, y: y as i32 },
                    extent: vk::Extent2D { width: w, height: h },
                },
                base_array_layer: 0,
                layer_count: 1,
            };
            host.device.cmd_clear_attachments(cmd, &clears, &[rect]);
        }
        host.device.cmd_end_rendering(cmd);
    };
    ocean.record_host_pass(host.cmd, 0, HOST_PASS, &mut draw).unwrap();
    let targets = Targets {
        colour: c,
        colour_entry: ImageState::COLOR_ATTACHMENT,
        depth: Some((d, ImageState::DEPTH_ATTACHMENT)),
        ldr: ldr.as_ref().map(|l| (l.image, ImageState { layout: L::UNDEFINED, stage: S::NONE, access: A::NONE })),
    };
    ocean.record(host.cmd, 0, &targets).unwrap();
    // The ocean's exit states (embed::Ocean::record), then the host's copies.
    let colour_exit = match &ldr {
        Some(_) => (L::SHADER_READ_ONLY_OPTIMAL, S::FRAGMENT_SHADER, A::NONE),
        None => (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE),
    };
    host.barrier(&c, colour_exit, (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ));
    if let Some(l) = &ldr {
        let written = (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
        host.barrier(&l.image, written, (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ));
    }
    host.barrier(
        &d,
        (L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL, tests, A::DEPTH_STENCIL_ATTACHMENT_WRITE),
        (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ),
    );
    let ldr_copy = ldr.as_ref().zip(ldr_out.as_ref()).map(|(l, out)| (l.image, vk::ImageAspectFlags::COLOR, out.0));
    let copies = [(c, vk::ImageAspectFlags::COLOR, colour_out.0), (d, vk::ImageAspectFlags::DEPTH, depth_out.0)];
    for (image, aspect, buffer) in copies.into_iter().chain(ldr_copy) {
        let region = vk::BufferImageCopy {
            image_subresource: vk::ImageSubresourceLayers {
                aspect_mask: aspect,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 1,
            },
            image_extent: vk::Extent3D { width: W, height: H, depth: 1 },
            ..Default::default()
        };
        // SAFETY (test host): the image is in TRANSFER_SRC_OPTIMAL and the buffer holds it.
        unsafe {
            host.device.cmd_copy_image_to_buffer(host.cmd, image.raw, L::TRANSFER_SRC_OPTIMAL, buffer, &[region])
        };
    }
    host.submit_and_wait();
    let colour_bits: Vec<u16> = host.read(colour_out.1, 4 * pixels);
    let colour_values =
        colour_bits.chunks_exact(4).map(|p| std::array::from_fn(|i| half::f16::from_bits(p[i]).to_f32())).collect();
    let depth_values: Vec<f32> = host.read(depth_out.1, pixels);
    let ldr_values = ldr_out.map(|out| {
        let values = host.read(out.1, 4 * pixels);
        host.destroy_buffer(out);
        values
    });
    host.destroy_buffer(colour_out);
    host.destroy_buffer(depth_out);
    for image in [Some(colour), Some(depth), ldr].into_iter().flatten() {
        host.destroy_image(image);
    }
    Readback { colour: colour_values, depth: depth_values, ldr: ldr_values }
}

fn desc(scene: Scene, reversed: bool) -> OceanDesc {
    OceanDesc {
        scene,
        width: W,
        height: H,
        formats: HostFormats { colour: COLOUR_FORMAT, depth: Some(DEPTH_FORMAT), reversed_z: reversed, ldr: None },
        frames_in_flight: 2,
        sky: true,
        radiance_scale: 1.0,
        shading: Default::default(),
        in_place: None,
        shadow_casters: false,
    }
}

/// The f64 view depth where the ray through pixel (x, y)'s centre meets the glassy sea (the
/// sphere of the planet's radius at sea level), and the height the ray falls per metre of view
/// depth; None above the limb.
fn sea_view_depth(scene: &Scene, projection: DMat4, x: u32, y: u32) -> Option<(f64, f64)> {
    let ndc = DVec4::new((x as f64 + 0.5) / W as f64 * 2.0 - 1.0, (y as f64 + 0.5) / H as f64 * 2.0 - 1.0, 0.5, 1.0);
    let v = view();
    let p = (projection * v).inverse() * ndc;
    let eye = DVec3::new(0.0, 0.0, EYE_HEIGHT);
    let dir = (p.truncate() / p.w - eye).normalize();
    let r = scene.planet.radius_m;
    let b = dir.z * (r + EYE_HEIGHT);
    let c = EYE_HEIGHT * (2.0 * r + EYE_HEIGHT);
    let disc = b * b - c;
    if b >= 0.0 || disc <= 0.0 {
        return None;
    }
    let s = c / (-b + disc.sqrt());
    let forward = -v.row(2).truncate();
    Some((s * dir.dot(forward), -dir.z / dir.dot(forward)))
}

#[test]
fn ocean_in_a_host_frame_keeps_the_host_in_front_and_hides_what_is_under_the_sea() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let glassy = Scene::load(std::path::Path::new("scenes/extreme/wind_0.toml")).unwrap();
    // In front of the sea (the bottom rows see it 25-40 m away), behind it, and in the sky.
    let green = [0.0, 3.0, 0.0, 1.0];
    let blue = [0.0, 0.0, 4.0, 1.0];
    let red = [2.0, 0.0, 0.0, 1.0];
    let occluders = [
        Occluder { rect: (10, 95, 40, 20), depth_m: 3.0, colour: green },
        Occluder { rect: (100, 95, 40, 20), depth_m: 900.0, colour: blue },
        Occluder { rect: (60, 4, 30, 10), depth_m: 1500.0, colour: red },
    ];
    for (reversed, infinite) in [(true, true), (false, false), (false, true), (true, false)] {
        let what = format!("reversed {reversed}, infinite far {infinite}");
        let p = projection(reversed, infinite);
        let mut ocean = Ocean::new(&gpu, desc(glassy.clone(), reversed)).unwrap();
        let Readback { colour, depth, .. } = frame(&host, &mut ocean, p, reversed, &occluders);
        let far = if reversed { 0.0 } else { 1.0 };
        let (mut sea, mut sky) = (0, 0);
        let mut worst: f64 = 0.0;
        for y in 0..H {
            for x in 0..W {
                let i = (y * W + x) as usize;
                let (c, d) = (colour[i], depth[i] as f64);
                assert!(c.iter().all(|v| v.is_finite()), "{what}: non-finite pixel at ({x}, {y})");
                let truth = sea_view_depth(&glassy, p, x, y);
                if let Some(o) = occluders.iter().find(|o| o.contains(x, y)) {
                    let in_front = truth.is_none_or(|(t, _)| o.depth_m < t);
                    if in_front {
                        assert_eq!(
                            c, o.colour,
                            "{what}: the host's pixel at ({x}, {y}) in front of the sea was overwritten"
                        );
                        assert!(
                            (d - depth_of(p, o.depth_m)).abs() < 1e-6,
                            "{what}: the host's depth at ({x}, {y}) changed"
                        );
                        continue;
                    }
                    assert_ne!(c, o.colour, "{what}: the occluder under the sea at ({x}, {y}) shows through");
                }
                match truth {
                    // Past a finite far plane the sea lies on it; near the limb the grid's
                    // triangles chord the sphere.
                    Some((t, sine)) if (infinite || t < 0.9 * FAR_M) && t < 500.0 => {
                        // How far above or below the sphere the host's depth puts the sea: the
                        // error along the ray times the ray's depression.
                        let vertical = (view_depth(p, d) - t).abs() * sine;
                        worst = worst.max(vertical);
                        assert!(vertical < SAG_M, "{what}: sea at ({x}, {y}) {vertical} m off the f64 sphere");
                        sea += 1;
                    }
                    Some(_) => {}
                    None => {
                        assert_eq!(d, far, "{what}: the sky at ({x}, {y}) is not at the far plane");
                        assert_ne!(c, BACKGROUND, "{what}: the host's empty pixel at ({x}, {y}) did not get the sky");
                        sky += 1;
                    }
                }
            }
        }
        assert!(sea > 5000 && sky > 2000, "{what}: {sea} sea and {sky} sky pixels checked");
        eprintln!("{what}: {sea} sea pixels within {worst:.1e} m of the f64 sphere; {sky} sky pixels");
        host.assert_clean(&what);
    }
}

#[test]
fn a_wavy_sea_in_a_host_frame_stays_within_its_crests_and_validation_clean() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::default();
    let crest = ocean::model::waves::generate(&scene).highest_crest();
    let p = projection(true, true);
    let mut ocean = Ocean::new(&gpu, desc(scene.clone(), true)).unwrap();
    let under = Occluder { rect: (60, 100, 40, 15), depth_m: 900.0, colour: [0.0, 0.0, 4.0, 1.0] };
    let Readback { colour, depth, .. } = frame(&host, &mut ocean, p, true, std::slice::from_ref(&under));
    let mut checked = 0;
    for y in 0..H {
        for x in 0..W {
            let i = (y * W + x) as usize;
            assert!(colour[i].iter().all(|v| v.is_finite() && *v >= 0.0), "non-finite or negative pixel at ({x}, {y})");
            assert_ne!(colour[i], BACKGROUND, "the host's empty pixel at ({x}, {y}) got neither sea nor sky");
            assert_ne!(colour[i], under.colour, "the occluder under the sea at ({x}, {y}) shows through");
            // The displaced surface lies within the highest crest of the mean sphere (and the
            // grid's sag); the crest's slope stretches that along a grazing ray.
            if let Some((t, sine)) = sea_view_depth(&scene, p, x, y).filter(|&(t, _)| t < 200.0) {
                let vertical = (view_depth(p, depth[i] as f64) - t).abs() * sine;
                assert!(vertical < 2.0 * crest + SAG_M, "sea at ({x}, {y}) {vertical} m off the mean sphere");
                checked += 1;
            }
        }
    }
    assert!(checked > 5000, "{checked} sea pixels checked");
    host.assert_clean("the host's frames");
}

/// A host's pass is timed with the ocean's, under its own name, and a frame holds a stated
/// number of them: the next is refused by name, not a panic.
#[test]
fn host_passes_are_timed_in_the_ocean_s_frame() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::load(std::path::Path::new("scenes/extreme/wind_0.toml")).unwrap();
    let p = projection(true, true);
    let mut ocean = Ocean::new(&gpu, desc(scene, true)).unwrap();
    let occluder = Occluder { rect: (10, 95, 40, 20), depth_m: 3.0, colour: [0.0, 3.0, 0.0, 1.0] };
    frame(&host, &mut ocean, p, true, &[occluder]);
    ocean.finished(0).unwrap();
    let names: Vec<&str> = ocean.pass_ms().iter().map(|(n, _)| *n).collect();
    if !names.is_empty() {
        // Timed ahead of the ocean's own passes, as recorded.
        assert_eq!(names.iter().position(|&n| n == HOST_PASS), Some(0), "{names:?}");
        assert!(names.len() > 1, "{names:?}");
    }
    ocean.update(0, &FrameInput { time_s: 0.0, view: view(), projection: p }).unwrap();
    host.begin();
    for _ in 0..HOST_PASSES {
        ocean.record_host_pass(host.cmd, 0, "a host pass", &mut |_| {}).unwrap();
    }
    let e = ocean.record_host_pass(host.cmd, 0, "one too many", &mut |_| {}).unwrap_err().to_string();
    assert!(e.contains("one too many") && e.contains(&format!("at most {HOST_PASSES}")), "{e}");
    let out_of_range = ocean.record_host_pass(host.cmd, 2, "a host pass", &mut |_| {}).unwrap_err().to_string();
    assert!(out_of_range.contains('2'), "{out_of_range}");
    host.submit_and_wait();
}

#[test]
fn misuse_gets_an_error_not_a_crash() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::default();
    let error = |d: OceanDesc| Ocean::new(&gpu, d).err().map(|e| e.to_string()).unwrap_or_default();
    let mut d = desc(scene.clone(), true);
    d.formats.colour = vk::Format::R8G8B8A8_UNORM;
    assert!(error(d).contains("colour format R8G8B8A8_UNORM"));
    let mut d = desc(scene.clone(), true);
    d.formats.depth = Some(vk::Format::R32_SFLOAT);
    assert!(error(d).contains("depth format R32_SFLOAT"));
    let mut d = desc(scene.clone(), true);
    d.frames_in_flight = 0;
    assert!(error(d).contains("frames_in_flight = 0"));
    let mut d = desc(scene.clone(), true);
    d.radiance_scale = f32::NAN;
    assert!(error(d).contains("radiance_scale"));
    let mut d = desc(scene.clone(), true);
    d.shading.ssaa = 2;
    assert!(error(d).contains("shading.ssaa = 2 needs a frame wholly the ocean's"));
    let mut d = desc(scene.clone(), true);
    d.shading.ssaa = 17;
    assert!(error(d).contains("out of range"));
    let mut d = desc(scene.clone(), true);
    d.shading.specialize_for_scene_camera = true;
    let mut specialized = Ocean::new(&gpu, d).unwrap();
    let elsewhere = FrameInput { time_s: 0.0, view: view(), projection: projection(true, true) };
    let moved = specialized.update(0, &elsewhere).unwrap_err().to_string();
    assert!(moved.contains("specialized for the scene's camera"), "{moved}");
    drop(specialized);

    let mut ocean = Ocean::new(&gpu, desc(scene, true)).unwrap();
    let input = FrameInput { time_s: 0.0, view: view(), projection: projection(true, true) };
    let message = |r: ocean::Result<()>| r.unwrap_err().to_string();
    assert!(message(ocean.update(2, &input)).contains("frame slot 2 is out of range"));
    let standard = FrameInput { projection: projection(false, true), ..input };
    assert!(message(ocean.update(0, &standard)).contains("made for reversed depth"));
    let nan = FrameInput { view: DMat4::from_cols_array(&[f64::NAN; 16]), ..input };
    assert!(message(ocean.update(0, &nan)).contains("NaN"));
    let under_water = FrameInput { view: DMat4::look_to_rh(DVec3::new(0.0, 0.0, -1.0), DVec3::X, DVec3::Z), ..input };
    assert!(message(ocean.update(0, &under_water)).contains("not above the water"));
    // Shadow casters: a box that is not one, and a map asked of an ocean made without casters.
    let nan_box = Some((DVec3::new(f64::NAN, 0.0, 0.0), DVec3::ONE));
    assert!(message(ocean.set_shadow_casters(nan_box)).contains("not finite"));
    let inside_out = Some((DVec3::ONE, DVec3::ZERO));
    assert!(message(ocean.set_shadow_casters(inside_out)).contains("least corner above its greatest"));
    ocean.update(0, &input).unwrap();
    let drawn = ocean.record_shadows(vk::CommandBuffer::null(), 0, &mut |_, _| {});
    assert!(drawn.unwrap_err().to_string().contains("made without shadow_casters"));
    // A mirror pass asked of an ocean that reads no planar reflections: none drawn, no error; a
    // slot out of range: an error.
    assert!(ocean.mirror_view().is_none());
    let mut called = false;
    assert_eq!(
        ocean.record_planar(vk::CommandBuffer::null(), 0, MirrorCover::Whole, &mut |_, _| called = true).ok(),
        Some(false)
    );
    assert!(!called);
    let out_of_range =
        ocean.record_planar(vk::CommandBuffer::null(), 2, MirrorCover::Whole, &mut |_, _| {}).map(|_| ());
    assert!(message(out_of_range).contains("frame slot 2 is out of range"));
    let colour = host.image(COLOUR_FORMAT, W, H, vk::ImageUsageFlags::COLOR_ATTACHMENT);
    let depth = host.image(
        DEPTH_FORMAT,
        W / 2,
        H,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
    );
    let targets = Targets {
        colour: colour.image,
        colour_entry: ImageState::COLOR_ATTACHMENT,
        depth: Some((depth.image, ImageState::DEPTH_ATTACHMENT)),
        ldr: None,
    };
    assert!(message(ocean.record(host.cmd, 1, &targets)).contains("depth target is 80x120"));
    let full_depth =
        host.image(DEPTH_FORMAT, W, H, vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED);
    let targets = Targets { depth: Some((full_depth.image, ImageState::DEPTH_ATTACHMENT)), ..targets };
    assert!(message(ocean.record(host.cmd, 1, &targets)).contains("frame slot 1 was not updated"));
    // A size the device cannot hold: an error, and the ocean says so until a resize succeeds.
    assert!(ocean.resize(100_000, 10).is_err());
    assert!(message(ocean.update(0, &input)).contains("no pipelines"));
    ocean.resize(W, H).unwrap();
    ocean.update(0, &input).unwrap();
    // Resized to nothing: paused, every call a no-op until it has pixels again.
    ocean.resize(0, 0).unwrap();
    assert!(ocean.paused());
    ocean.update(0, &input).unwrap();
    ocean.record(host.cmd, 0, &targets).unwrap();
    ocean.resize(W, H).unwrap();
    assert!(!ocean.paused());
    for image in [colour, depth, full_depth] {
        host.destroy_image(image);
    }
    host.assert_clean("the host's frames");
}

#[test]
fn the_ocean_tone_maps_the_host_frame_in_the_host_unit() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let mut scene = Scene::default();
    scene.render.exposure = Some(0.4);
    // The host works in cd/m^2: the ocean writes 1000 times its own kcd/m^2, held to binary16.
    let mut d = desc(scene.clone(), true);
    d.radiance_scale = 1000.0;
    d.formats.ldr = Some(vk::Format::R8G8B8A8_UNORM);
    let mut ocean = Ocean::new(&gpu, d).unwrap();
    let box_in_front = Occluder { rect: (20, 90, 30, 20), depth_m: 4.0, colour: [900.0, 300.0, 100.0, 1.0] };
    let shot = frame(&host, &mut ocean, projection(true, true), true, std::slice::from_ref(&box_in_front));
    assert!(shot.colour.iter().flatten().all(|v| v.is_finite() && *v <= 65504.0));
    // The CPU twin of the tone mapping, on the host's frame in kcd/m^2.
    let kcd: Vec<[f32; 4]> = shot.colour.iter().map(|p| [p[0] / 1000.0, p[1] / 1000.0, p[2] / 1000.0, 1.0]).collect();
    let expected = ocean::output::tonemap(&kcd, W, &scene.render);
    let ldr = shot.ldr.expect("an LDR target");
    let worst = ldr.iter().zip(&expected).map(|(a, b)| (*a as i32 - *b as i32).abs()).max().unwrap();
    assert!(worst <= 1, "the LDR target differs from the CPU tone mapping by {worst} levels");
    // The host's object is in the tone-mapped picture, warm as the host drew it.
    let at = |x: u32, y: u32| &ldr[4 * (y * W + x) as usize..][..3];
    assert!(at(30, 100)[0] > at(30, 100)[2] + 50, "the box's pixel {:?}", at(30, 100));
    host.assert_clean("the host's frames");
}

/// `ocean bench embed`'s two frames (render's own and a host's through the API) on one device,
/// validation-clean, with every pass of each timed.
#[test]
fn the_embed_bench_times_both_frames_validation_clean() {
    let gpu = common::gpu();
    let out = std::env::temp_dir().join(format!("ocean-embed-bench-{}", std::process::id()));
    let t = ocean::measure::bench::embed::run(&gpu, &Scene::default(), "default", 96, 64, 1, &out).unwrap();
    for pass in ["ocean", "shade", "composite", "host tonemap"] {
        assert!(t.embedded_ms.get(pass).is_some_and(|ms| *ms > 0.0), "embedded {pass}: {:?}", t.embedded_ms);
    }
    // `ocean render`'s frame: a host without objects, drawn in its colour in place, not composited.
    let composited = ["host copy", "composite"].iter().any(|p| t.render_ms.contains_key(*p));
    assert!(t.render_ms.contains_key("host tonemap") && !composited, "{:?}", t.render_ms);
    assert!(t.ratio.iter().all(|r| r.is_finite() && *r > 0.0), "{:?}", t.ratio);
    let md = std::fs::read_to_string(out.join("embed.md")).unwrap();
    assert!(md.contains("| composite |") && md.contains("Embedded over render"), "{md}");
    let counts = gpu.validation_counts();
    assert_eq!(counts.error_total(), 0, "validation errors {:?}", counts.errors);
    let _ = std::fs::remove_dir_all(&out);
}

/// A host changes the scene between frames: a new sun takes effect at the next update, a new sky
/// model rebuilds the pipelines, both validation-clean.
#[test]
fn scene_changes_between_host_frames() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::default();
    let mut ocean = Ocean::new(&gpu, desc(scene.clone(), true)).unwrap();
    let p = projection(true, true);
    let sea_mean = |shot: &Readback| {
        let rows = (H * 3 / 4)..H;
        let pixels: Vec<f64> = rows
            .flat_map(|y| (0..W).map(move |x| (y * W + x) as usize))
            .map(|i| common::luminance(shot.colour[i]))
            .collect();
        pixels.iter().sum::<f64>() / pixels.len() as f64
    };
    let low_sun = sea_mean(&frame(&host, &mut ocean, p, true, &[]));
    let mut noon = scene.clone();
    noon.sun.elevation_deg = 60.0;
    ocean.set_scene(noon.clone()).unwrap();
    let high_sun = sea_mean(&frame(&host, &mut ocean, p, true, &[]));
    assert!(high_sun > 2.0 * low_sun, "the sea under a 60-degree sun {high_sun} against 3 degrees {low_sun}");
    let mut preetham = noon;
    preetham.sky.model = ocean::model::scene::SkyKind::Preetham;
    ocean.set_scene(preetham).unwrap();
    let shot = frame(&host, &mut ocean, p, true, &[]);
    assert!(shot.colour.iter().flatten().all(|v| v.is_finite()) && sea_mean(&shot) > 0.0);
    let mut bad = scene;
    bad.sun.elevation_deg = f64::NAN;
    assert!(ocean.set_scene(bad).unwrap_err().to_string().contains("sun.elevation_deg"));
    host.assert_clean("the host's frames");
}

/// A host without depth's frame: its colour (`in_place`, else an image of its own), cleared to
/// `BACKGROUND` (RGBA16F), after the ocean.
fn depthless_frame(host: &Host, ocean: &mut Ocean, input: &FrameInput, in_place: Option<HostImage>) -> Vec<[f32; 4]> {
    use vk::{AccessFlags2 as A, ImageLayout as L, ImageUsageFlags as U, PipelineStageFlags2 as S};
    let usage = U::COLOR_ATTACHMENT | U::TRANSFER_SRC | U::TRANSFER_DST;
    let own = in_place.is_none().then(|| host.image(COLOUR_FORMAT, W, H, usage));
    let pixels = (W * H) as usize;
    let out = host.readback(8 * pixels as u64);
    let c = own.as_ref().map_or_else(|| in_place.unwrap(), |i| i.image);
    ocean.update(0, input).unwrap();
    host.begin();
    let cleared = (L::TRANSFER_DST_OPTIMAL, S::CLEAR, A::TRANSFER_WRITE);
    host.barrier(&c, (L::UNDEFINED, S::NONE, A::NONE), cleared);
    let range =
        vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1);
    // SAFETY (test host): the image is in TRANSFER_DST_OPTIMAL.
    unsafe {
        let colour = vk::ClearColorValue { float32: BACKGROUND };
        host.device.cmd_clear_color_image(host.cmd, c.raw, L::TRANSFER_DST_OPTIMAL, &colour, &[range])
    };
    let entry = ImageState::new(cleared.0, cleared.1, cleared.2);
    ocean.record(host.cmd, 0, &Targets { colour: c, colour_entry: entry, depth: None, ldr: None }).unwrap();
    let exit = (L::COLOR_ATTACHMENT_OPTIMAL, S::COLOR_ATTACHMENT_OUTPUT, A::COLOR_ATTACHMENT_WRITE);
    host.barrier(&c, exit, (L::TRANSFER_SRC_OPTIMAL, S::COPY, A::TRANSFER_READ));
    let region = vk::BufferImageCopy {
        image_subresource: vk::ImageSubresourceLayers::default()
            .aspect_mask(vk::ImageAspectFlags::COLOR)
            .layer_count(1),
        image_extent: vk::Extent3D { width: W, height: H, depth: 1 },
        ..Default::default()
    };
    // SAFETY (test host): the image is in TRANSFER_SRC_OPTIMAL and the buffer holds it.
    unsafe { host.device.cmd_copy_image_to_buffer(host.cmd, c.raw, L::TRANSFER_SRC_OPTIMAL, out.0, &[region]) };
    host.submit_and_wait();
    let bits: Vec<u16> = host.read(out.1, 4 * pixels);
    host.destroy_buffer(out);
    if let Some(image) = own {
        host.destroy_image(image);
    }
    bits.chunks_exact(4).map(|p| std::array::from_fn(|i| half::f16::from_bits(p[i]).to_f32())).collect()
}

#[test]
fn a_host_without_depth_gets_the_sea_everywhere_and_keeps_its_own_sky_when_asked() {
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::default();
    let (view, projection) = ocean::embed::camera::scene_view(&scene, W as f64 / H as f64, true);
    let input = FrameInput { time_s: 0.0, view, projection };
    let depthless = |sky: bool, radiance_scale: f32| OceanDesc {
        formats: HostFormats { colour: COLOUR_FORMAT, depth: None, reversed_z: true, ldr: None },
        sky,
        radiance_scale,
        ..desc(scene.clone(), true)
    };
    // The whole frame the ocean's: a copy of its radiance.
    let mut whole = Ocean::new(&gpu, depthless(true, 1.0)).unwrap();
    assert!(whole.pass_names().contains(&"host copy") && !whole.pass_names().contains(&"composite"));
    let copied = depthless_frame(&host, &mut whole, &input, None);
    drop(whole);
    // The same drawn in the host's image in place (`ocean render`'s frame): the same bits.
    let image = host.in_place_image(W, H);
    let mut in_place = Ocean::new(&gpu, OceanDesc { in_place: Some(image.image), ..depthless(true, 1.0) }).unwrap();
    assert!(!in_place.pass_names().iter().any(|p| *p == "host copy" || *p == "composite"));
    let other = host.image(COLOUR_FORMAT, W, H, vk::ImageUsageFlags::COLOR_ATTACHMENT);
    let wrong = Targets { colour: other.image, colour_entry: ImageState::COLOR_ATTACHMENT, depth: None, ldr: None };
    in_place.update(0, &input).unwrap();
    let error = in_place.record(host.cmd, 0, &wrong).unwrap_err().to_string();
    assert!(error.contains("in place"), "{error}");
    assert!(in_place.resize(W / 2, H / 2).unwrap_err().to_string().contains("made again"));
    assert!(depthless_frame(&host, &mut in_place, &input, Some(image.image)) == copied, "in place against the copy");
    drop(in_place);
    host.destroy_image(other);
    host.destroy_image(image);
    let spare = host.in_place_image(W, H);
    let with_depth = OceanDesc { in_place: Some(spare.image), ..desc(scene.clone(), true) };
    let error = Ocean::new(&gpu, with_depth).err().expect("a host with depth composites").to_string();
    assert!(error.contains("in_place"), "{error}");
    host.destroy_image(spare);
    // A host with its own sky, in cd/m²: drawn, the sky's pixels kept.
    let mut own_sky = Ocean::new(&gpu, depthless(false, 1000.0)).unwrap();
    assert!(own_sky.pass_names().contains(&"composite"));
    let drawn = depthless_frame(&host, &mut own_sky, &input, None);
    let (mut sea, mut kept) = (0, 0);
    for (i, (a, b)) in copied.iter().zip(&drawn).enumerate() {
        if *b == BACKGROUND {
            kept += 1;
            // Only the sky's rows: above the horizon, which the default view puts in the top half.
            assert!(i < (W * H / 2) as usize, "pixel {i} of the sea kept the host's colour");
        } else {
            sea += 1;
            for c in 0..3 {
                // Both RGBA16F: one binary16 rounding of each (2^-11 relative), then the scale.
                let expected = (a[c] * 1000.0).min(65504.0);
                assert!((b[c] - expected).abs() <= 2e-3 * expected + 1e-3, "pixel {i}: {b:?} against {a:?} x 1000");
            }
        }
    }
    assert!(sea > (W * H / 3) as usize && kept > (W * H / 4) as usize, "{sea} sea pixels, {kept} kept");
    assert!(copied.iter().all(|p| p.iter().all(|v| v.is_finite()) && *p != BACKGROUND));
    drop(own_sky);
    host.assert_clean("hosts without depth");
}

/// The frame's light for the host's objects (embed::Ocean::light) is the f64 model's sun and sky
/// at sea level under the scene's sun, in the host's radiance unit.
#[test]
fn the_host_gets_the_frame_s_light_in_its_unit() {
    use ocean::model::atmosphere::sun_and_sky;
    use ocean::model::sky::SkyModel;
    let host = Host::new();
    let gpu = Gpu::from_host(&host.borrowed(), None).unwrap();
    let scene = Scene::default();
    let mut ocean = Ocean::new(&gpu, OceanDesc { radiance_scale: 1000.0, ..desc(scene.clone(), true) }).unwrap();
    assert!(ocean.light().is_none(), "no light before the first update");
    ocean.update(0, &FrameInput { time_s: 0.0, view: view(), projection: projection(true, true) }).unwrap();
    let light = ocean.light().unwrap();
    let (e, a) = (scene.sun.elevation_deg.to_radians(), scene.sun.azimuth_deg.to_radians());
    let sun = [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()];
    assert!((light.sun_direction - DVec3::from(sun)).length() < 1e-12, "{light:?}");
    let (sun_radiance, sky_irradiance) = sun_and_sky(&scene.atmosphere(), 0.0, sun);
    for c in 0..3 {
        let expected = [sun_radiance[c] * SkyModel::sun_solid_angle() * 1000.0, sky_irradiance[c] * 1000.0];
        for (got, want) in [light.sun_illuminance[c], light.sky_illuminance[c]].iter().zip(expected) {
            assert!(want > 0.0 && (*got as f64 / want - 1.0).abs() < 1e-5, "{light:?}: {got} against {want}");
        }
    }
    drop(ocean);
    host.assert_clean("the frame's light");
}
