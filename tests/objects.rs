//! Objects on the sea (`[[object]]`): every preset and extreme placement renders clean under
//! validation; the objects occlude the sea and the sea hides what is under water, found at the
//! pixels the f64 placement projects to; bad input gets one line naming the file and the key.

mod common;

use common::{assert_clean, gpu, render};
use glam::DVec3;
use ocean::app::{render_on, RenderRequest};
use ocean::embed::camera::scene_view;
use ocean::model::placement::{place, waterplane};
use ocean::model::scene::{Reflections, Scene};
use ocean::render::renderer::{Options, RenderedFrame, Renderer};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn scenes_in(dir: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    found.sort();
    found
}

#[test]
fn every_object_scene_renders_clean() {
    let gpu = gpu();
    let mut paths = scenes_in(&root().join("scenes/objects"));
    paths.extend(scenes_in(&root().join("scenes/extreme/objects")));
    let names: Vec<String> = paths.iter().map(|p| p.file_stem().unwrap().to_string_lossy().into_owned()).collect();
    for wanted in
        ["boat_sunset", "pier_noon", "buoys_storm", "ship_aircraft", "behind_eye", "eye_inside", "harbour_200"]
    {
        assert!(names.iter().any(|n| n == wanted), "missing scene {wanted}");
    }
    for path in &paths {
        let scene = Scene::load(path).unwrap_or_else(|e| panic!("{e}"));
        assert!(!scene.objects.is_empty(), "{}: places no object", path.display());
        // Both reflection methods: the screen's trace, and the mirror pass, drawn or (no mirror
        // image in view) not.
        let (report, frame) = common::render_with(&gpu, &scene, 256, 192, reflecting(Reflections::Both));
        assert_clean(&report, &path.display().to_string());
        assert!(frame.hdr.iter().all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)), "{}", path.display());
        assert!(frame.pass_ms.is_empty() || frame.pass_ms.iter().any(|(n, _)| n == "objects"), "{:?}", frame.pass_ms);
    }
}

/// The pixel (column, row) a world point projects to in a `width` x `height` frame of `scene`,
/// None behind the eye or off the picture.
fn project(scene: &Scene, width: u32, height: u32, world: DVec3) -> Option<(usize, usize)> {
    let (view, projection) = scene_view(scene, width as f64 / height as f64, true);
    let clip = projection * view * world.extend(1.0);
    if clip.w <= 0.0 {
        return None;
    }
    let (x, y) = ((clip.x / clip.w * 0.5 + 0.5) * width as f64, (clip.y / clip.w * 0.5 + 0.5) * height as f64);
    ((0.0..width as f64).contains(&x) && (0.0..height as f64).contains(&y)).then_some((x as usize, y as usize))
}

/// Where a point of the scene's first object's model stands in the world at time 0, for a
/// `width` x `height` frame of the scene's camera (the f64 placement the commands draw with).
fn first_object_in_world(scene: &Scene, width: u32, height: u32) -> impl Fn([f64; 3]) -> DVec3 {
    let waves = ocean::model::waves::generate(scene);
    let (view, _) = scene_view(scene, width as f64 / height as f64, true);
    let eye = view.inverse().w_axis.truncate();
    let object = &scene.objects[0];
    let model = ocean::model::gltf::load(&object.file).unwrap();
    let placement = place(scene, &waves, None, object, waterplane(model.bounds, object.scale), eye.z, 0.0);
    move |model_point| eye + placement.relative_from_model.transform_point3(DVec3::from(model_point))
}

/// `settings` (scene keys) with the boat `ahead_m` in front of the eye, bow north, fixed.
fn boat_scene(settings: &str, ahead_m: f64, name: &str) -> Scene {
    let boat = root().join("scenes/models/boat.gltf");
    let object =
        format!("[[object]]\nfile = \"{}\"\nposition_m = [{ahead_m}, 0.0, 0.0]\nheading_deg = 90.0\n", boat.display());
    Scene::parse(&format!("{settings}\n{object}"), name).unwrap()
}

/// A calm sea with the boat beam-on 20 m ahead, its waterline at mean sea level.
fn calm_boat() -> Scene {
    let settings = r#"
        [camera]
        height_m = 3.0
        pitch_deg = -8.0
        fov_y_deg = 40.0
        [wind]
        speed_mps = 3.0
        [sun]
        elevation_deg = 40.0
        azimuth_deg = 180.0
        "#;
    boat_scene(settings, 20.0, "calm_boat.toml")
}

/// The calm boat on a sea without wind: a mirror.
fn mirror_calm_boat() -> Scene {
    let mut scene = calm_boat();
    scene.wind.speed_mps = 0.0;
    scene
}

/// Shading without the sea's reflections of the objects: what occlusion alone leaves.
fn without_reflections() -> ocean::embed::Shading {
    ocean::embed::Shading {
        shader: ocean::embed::ShaderConfig { reflections: Reflections::None, ..Default::default() },
        ..Default::default()
    }
}

#[test]
fn objects_occlude_the_sea_and_the_sea_hides_their_keels() {
    let gpu = gpu();
    let scene = calm_boat();
    let (w, h) = (320, 240);
    let (report, with) = common::render_with(&gpu, &scene, w, h, without_reflections());
    assert_clean(&report, "calm boat");
    let mut bare = scene.clone();
    bare.objects.clear();
    let (bare_report, without) = render(&gpu, &bare, w, h);
    // Without objects nothing is reflected, and the report says what was left out and why.
    let omitted = bare_report.omitted.iter().find(|o| o.what.starts_with("local reflections"));
    assert!(omitted.is_some_and(|o| o.why.contains("no objects")), "{:?}", bare_report.omitted);
    assert!(!bare_report.pipelines.iter().any(|p| p == "reflection sources"), "{:?}", bare_report.pipelines);
    let (both, _) = common::render_with(&gpu, &bare, w, h, reflecting(Reflections::Both));
    let omitted = both.omitted.iter().find(|o| o.what.contains("planar reflections"));
    assert!(omitted.is_some_and(|o| o.why.contains("no objects")), "{:?}", both.omitted);
    assert!(!both.pipelines.iter().any(|p| p == "planar reflection"), "{:?}", both.pipelines);

    let world = first_object_in_world(&scene, w, h);
    let at = |frame: &RenderedFrame, (x, y): (usize, usize)| frame.hdr[y * w as usize + x];
    let differs = |a: [f32; 4], b: [f32; 4]| (0..3).map(|c| (a[c] - b[c]).abs() / b[c].max(1e-3)).fold(0.0, f32::max);

    // Half way up the mast, the cabin's side and the hull's above the water, facing the eye
    // (the port side: the bow points north, the eye looks east): the object.
    let points = [("the mast", [0.4, 5.0, 0.0]), ("the cabin", [-0.3, 1.0, -0.6]), ("the topsides", [0.0, 0.45, -1.0])];
    for (what, point) in points {
        let pixel = project(&scene, w, h, world(point)).unwrap_or_else(|| panic!("{what} is off the picture"));
        let (a, b) = (at(&with, pixel), at(&without, pixel));
        assert!(differs(a, b) > 0.1, "{what} at {pixel:?}: {a:?} is the bare sea's {b:?}");
    }
    // The keel, 0.8 m under water behind the near side's waterline: the sea in front hides it.
    let keel = project(&scene, w, h, world([0.0, -0.8, 0.0])).expect("the keel's pixel");
    let (a, b) = (at(&with, keel), at(&without, keel));
    assert!(differs(a, b) < 1e-3, "the keel at {keel:?} shows through the sea: {a:?} against {b:?}");
    // Far from the boat the frame is the bare sea's, the sky's included.
    for pixel in [(5, 5), (5, h as usize - 5), (w as usize - 5, h as usize - 5), (w as usize - 5, 60)] {
        let (a, b) = (at(&with, pixel), at(&without, pixel));
        assert!(differs(a, b) < 1e-3, "{pixel:?}: {a:?} against {b:?}");
    }
}

fn render_error(scene: Scene) -> String {
    let gpu = gpu();
    let request = RenderRequest { validation: true, ..RenderRequest::new(scene, 64, 48) };
    match render_on(&gpu, &request) {
        Ok(_) => panic!("expected an error"),
        Err(e) => e.to_string(),
    }
}

fn scene_with(object: &str) -> std::result::Result<Scene, String> {
    Scene::parse(&format!("[[object]]\n{object}\n"), "objects.toml").map_err(|e| e.to_string())
}

#[test]
fn bad_objects_get_one_line_naming_the_file_and_the_key() {
    let tmp = std::env::temp_dir().join(format!("ocean-objects-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();

    // Scene keys: an unknown key, a scale out of range, a position that is not finite.
    let e = scene_with("file = \"a.gltf\"\ncolour = 3").unwrap_err();
    assert!(e.contains("objects.toml") && e.contains("unknown field `colour`"), "{e}");
    let e = scene_with("file = \"a.gltf\"\nscale = 0.0").unwrap_err();
    assert!(e.contains("object 1 (a.gltf): scale = 0 is out of range"), "{e}");
    let e = scene_with("file = \"a.gltf\"\nposition_m = [nan, 0.0, 0.0]").unwrap_err();
    assert!(e.contains("position_m.x = NaN is out of range"), "{e}");
    let e = scene_with("position_m = [1.0, 0.0, 0.0]").unwrap_err();
    assert!(e.contains("missing field `file`"), "{e}");
    let e = scene_with("file = \"a.gltf\"\nmotion = \"sinking\"").unwrap_err();
    assert!(e.contains("unknown variant `sinking`"), "{e}");

    // Files: missing, not glTF, a valid file with a skin.
    let missing = tmp.join("missing.gltf");
    let e = render_error(scene_with(&format!("file = {:?}", missing.display().to_string())).unwrap());
    assert!(e.contains("missing.gltf") && e.contains("no such glTF file") && !e.contains('\n'), "{e}");
    let broken = tmp.join("broken.gltf");
    std::fs::write(&broken, "{ this is not json").unwrap();
    let e = render_error(scene_with(&format!("file = {:?}", broken.display().to_string())).unwrap());
    assert!(e.contains("broken.gltf") && e.contains("not a readable glTF 2.0 file") && !e.contains('\n'), "{e}");

    // A scene file names its objects relative to itself.
    let scene_file = tmp.join("relative.toml");
    std::fs::write(&scene_file, "[[object]]\nfile = \"models/boat.gltf\"\n").unwrap();
    let scene = Scene::load(&scene_file).unwrap();
    assert_eq!(scene.objects[0].file, tmp.join("models/boat.gltf"));
    let _ = std::fs::remove_dir_all(&tmp);
}

/// The ground truth traces the objects: the boat's mast, cabin and topsides where the f64
/// placement projects them, in the raster's light (the same material model: within a quarter,
/// the truth's environment traced where the raster's is tabulated and unoccluded), and on a
/// mirror-calm sea the cabin's reflection below it, in the reflected sky's place.
#[test]
fn the_ground_truth_traces_the_objects() {
    use ocean::measure::groundtruth::{self, Sampling};
    let gpu = gpu();
    let scene = mirror_calm_boat();
    let (w, h) = (160, 120);
    let truth = groundtruth::render(&gpu, &scene, w, h, &Sampling::new(4), |_, _| {}).unwrap();
    assert_eq!(truth.report.validation_errors, 0);
    assert!(truth.radiance.iter().all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)));
    let (_, raster) = common::render_with(&gpu, &scene, w, h, without_reflections());
    let world = first_object_in_world(&scene, w, h);
    let luminance = |p: [f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    let points = [("the mast", [0.4, 5.0, 0.0]), ("the cabin", [-0.3, 1.0, -0.6]), ("the topsides", [0.0, 0.45, -1.0])];
    for (what, point) in points {
        let (x, y) = project(&scene, w, h, world(point)).unwrap_or_else(|| panic!("{what} is off the picture"));
        let i = y * w as usize + x;
        let (traced, drawn) = (luminance(truth.radiance[i]), luminance(raster.hdr[i]));
        assert!((traced / drawn - 1.0).abs() < 0.25, "{what} at ({x}, {y}): traced {traced}, drawn {drawn}");
    }
    // The cabin's image in the mirror-calm sea: its teak's warmth in the reflected sky.
    let side = world([-0.3, 1.0, -0.6]);
    let (x, y) = project(&scene, w, h, DVec3::new(side.x, side.y, -side.z)).expect("the image is on the picture");
    let p = truth.sky[y * w as usize + x];
    assert!(p[0] > 1.3 * p[2], "the cabin's image at ({x}, {y}) in the truth's reflected sky: {p:?}");
}

#[test]
fn measurements_of_the_oceans_own_frame_refuse_objects() {
    let gpu = gpu();
    let scene = calm_boat();
    let e = Renderer::new(&gpu, &scene, 64, 48, Options::default()).err().expect("refused").to_string();
    assert!(e.contains("draws no objects") && e.contains("boat.gltf"), "{e}");
}

/// From inside a hull the walls around the eye face away from it: culled, so the sea outside
/// shows where they stand (the winding glTF states and Vulkan's rule for it agree). Culling the
/// wrong side would show the hull's inner walls instead.
#[test]
fn from_inside_a_hull_the_eye_sees_the_sea_through_its_walls() {
    let gpu = gpu();
    let mut scene = Scene::load(&root().join("scenes/extreme/objects/eye_inside.toml")).unwrap();
    // The walls alone: the ship's shadow on the sea around it is not what is looked for here.
    scene.render.shadow_map = ocean::model::scene::ShadowMapMode::Off;
    let (w, h) = (256, 192);
    let (report, inside) = common::render_with(&gpu, &scene, w, h, without_reflections());
    assert_clean(&report, "eye inside");
    let mut bare = scene.clone();
    bare.objects.clear();
    let (_, sea) = render(&gpu, &bare, w, h);
    // Below the horizon (the view pitches down 5 degrees) the walls would fill the sides.
    let rows = (h as usize * 3 / 4)..h as usize;
    let pixels: Vec<usize> = rows.flat_map(|y| (0..w as usize).map(move |x| y * w as usize + x)).collect();
    let same = pixels
        .iter()
        .filter(|&&i| (0..3).all(|c| (inside.hdr[i][c] - sea.hdr[i][c]).abs() <= 1e-3 * sea.hdr[i][c].max(1e-3)))
        .count();
    assert!(same == pixels.len(), "{} of {} pixels below are the sea's", same, pixels.len());
    // Above, the deckhouses' undersides face the eye: drawn.
    let top = (0..w as usize).filter(|&x| (inside.hdr[x][2] - sea.hdr[x][2]).abs() > 0.1 * sea.hdr[x][2]).count();
    assert!(top > w as usize / 2, "{top} of the top row's pixels show the ship");
}

/// Shading with the sea's reflections of the objects by `reflections`.
fn reflecting(reflections: Reflections) -> ocean::embed::Shading {
    ocean::embed::Shading {
        shader: ocean::embed::ShaderConfig { reflections, ..Default::default() },
        ..Default::default()
    }
}

/// The sky term alone (where the objects' reflections are), reflected by `reflections`.
fn sky_term(reflections: Reflections) -> ocean::embed::Shading {
    ocean::embed::Shading {
        shader: ocean::embed::ShaderConfig {
            reflections,
            terms: ocean::embed::Terms { sun: false, sky: true, sea: false },
            ..Default::default()
        },
        ..Default::default()
    }
}

/// On a mirror-calm sea the objects' reflections stand where a plane mirror puts them, traced in
/// screen space or read from the mirror pass, or both: the cabin's side reflected at the pixel
/// its image below the waterline projects to (within a pixel), its paint's hue in place of the
/// sky's, and nothing there without reflections.
#[test]
fn a_calm_sea_mirrors_the_boat_at_the_mirror_image() {
    let gpu = gpu();
    let scene = mirror_calm_boat();
    let (w, h) = (320, 240);
    let (_, plain) = common::render_with(&gpu, &scene, w, h, without_reflections());
    // The cabin's side facing the eye, and its image in the mean sea (z = 0 in the world).
    let side = first_object_in_world(&scene, w, h)([-0.3, 1.0, -0.6]);
    let image = DVec3::new(side.x, side.y, -side.z);
    let pixel = project(&scene, w, h, image).expect("the mirror image is on screen");
    let at = |frame: &RenderedFrame, (x, y): (usize, usize)| frame.hdr[y * w as usize + x];
    // The teak's red over blue, against the sea's, within a pixel of the image.
    let warmth = |p: [f32; 4]| p[0] / p[2].max(1e-6);
    let sea = warmth(at(&plain, pixel));
    for method in [Reflections::Screen, Reflections::Planar, Reflections::Both] {
        let (report, mirrored) = common::render_with(&gpu, &scene, w, h, reflecting(method));
        assert_clean(&report, &format!("mirror-calm boat, {} reflections", method.name()));
        let best = (-1i64..=1)
            .flat_map(|dy| (-1i64..=1).map(move |dx| (dx, dy)))
            .map(|(dx, dy)| ((pixel.0 as i64 + dx) as usize, (pixel.1 as i64 + dy) as usize))
            .map(|p| warmth(at(&mirrored, p)))
            .fold(0.0, f32::max);
        assert!(
            best > 1.5 * sea && best > 0.5,
            "{} reflections: the cabin's image at {pixel:?}: warmth {best} against the sea's {sea}",
            method.name()
        );
    }
}

/// The mirror pass reflects what the screen does not hold: with the eye looking down, the mast's
/// upper part is above the picture's top edge, and its image in a mirror-calm sea below the
/// boat is in the picture. The planar reflection draws it there; the screen-space trace, whose
/// ray leaves the screen, cannot, and leaves the sky's reflection.
#[test]
fn planar_reflections_hold_what_the_screen_does_not() {
    let gpu = gpu();
    let mut scene = mirror_calm_boat();
    scene.camera.pitch_deg = -14.0;
    let (w, h) = (320, 240);
    let mast = first_object_in_world(&scene, w, h)([0.4, 7.5, 0.0]);
    assert!(project(&scene, w, h, mast).is_none(), "the mast's top is in the picture");
    let pixel = project(&scene, w, h, DVec3::new(mast.x, mast.y, -mast.z)).expect("its image is in the picture");
    let luminance_at = |frame: &RenderedFrame| {
        // The brightest within a pixel of the image, against the plain sea's.
        (-1i64..=1)
            .map(|dx| frame.hdr[pixel.1 * w as usize + (pixel.0 as i64 + dx) as usize])
            .map(common::luminance)
            .fold(0.0, f64::max)
    };
    let (_, plain) = common::render_with(&gpu, &scene, w, h, without_reflections());
    let sea = luminance_at(&plain);
    let mut seen = Vec::new();
    for method in [Reflections::Screen, Reflections::Planar, Reflections::Both] {
        let (report, frame) = common::render_with(&gpu, &scene, w, h, reflecting(method));
        assert_clean(&report, &format!("boat seen from above, {} reflections", method.name()));
        seen.push((method, luminance_at(&frame) / sea));
    }
    let ratio = |m: Reflections| seen.iter().find(|(k, _)| *k == m).map(|(_, r)| *r).unwrap();
    assert!((ratio(Reflections::Screen) - 1.0).abs() < 0.02, "{seen:?}");
    // The grey mast in place of the darker sky the calm sea mirrors there (about 1.25 times the
    // plain sea's radiance); the screen's trace leaves the plain sea to within rounding.
    assert!(ratio(Reflections::Planar) > 1.15, "{seen:?}");
    assert!(ratio(Reflections::Both) > 1.15, "{seen:?}");
}

/// The boat's preset with planar reflections at w x h, rendered with two variants of the shading
/// (`variant(true)`, `variant(false)`, labelled): both clean, the same within a half float's
/// rounding, and the boat's reflection in the picture. Their reports, in that order.
fn planar_variants_agree(
    w: u32,
    h: u32,
    variant: impl Fn(bool) -> ocean::embed::ShaderConfig,
    labels: [&str; 2],
) -> [ocean::app::report::Report; 2] {
    let gpu = gpu();
    let scene = Scene::load(&root().join("scenes/objects/boat_sunset.toml")).unwrap();
    let planar = |on: bool| ocean::embed::Shading {
        shader: ocean::embed::ShaderConfig { reflections: Reflections::Planar, ..variant(on) },
        ..Default::default()
    };
    let (report_on, on) = common::render_with(&gpu, &scene, w, h, planar(true));
    assert_clean(&report_on, labels[0]);
    let (report_off, off) = common::render_with(&gpu, &scene, w, h, planar(false));
    assert_clean(&report_off, labels[1]);
    let (_, plain) = common::render_with(&gpu, &scene, w, h, without_reflections());
    let mut reflected = 0;
    for ((a, b), c) in on.hdr.iter().zip(&off.hdr).zip(&plain.hdr) {
        for k in 0..3 {
            // binary16 keeps 11 significant bits: one rounding is within 2^-11 of the value.
            let tolerance = 2.0 * (a[k].abs().max(b[k].abs()) / 2048.0).max(6.0e-8);
            assert!((a[k] - b[k]).abs() <= tolerance, "{a:?} against {b:?}");
        }
        if (common::luminance(*a) - common::luminance(*c)).abs() > 0.02 * common::luminance(*c) {
            reflected += 1;
        }
    }
    assert!(reflected > 100, "the boat's reflection changes only {reflected} pixels");
    [report_on, report_off]
}

/// The sea's tiles sorted by whether they may read the mirror (passes/planar_tiles.rs) shade as
/// the unsorted pass does: a tile the sort leaves without the mirror's code holds no pixel that
/// would have read it. The boat's preset, its reflection across many tiles of the sea-only rows
/// and the rest of them far from it; the same within a half float's rounding (the two pipelines
/// are compiled apart), and the reflection there in both.
#[test]
fn sorting_the_tiles_by_the_mirror_changes_no_pixel() {
    let tiles = |on: bool| ocean::embed::ShaderConfig { planar_tiles: on, ..Default::default() };
    let [sorted, unsorted] = planar_variants_agree(320, 240, tiles, ["boat, tiles sorted", "boat, tiles unsorted"]);
    assert!(sorted.pipelines.iter().any(|p| p == "planar tiles"), "{:?}", sorted.pipelines);
    assert!(!unsorted.pipelines.iter().any(|p| p == "planar tiles"), "{:?}", unsorted.pipelines);
}

/// The mirror pass builds its images only where the host says its mirrored objects may lie (the
/// boat's mirrored box covers a small part of the view): the same picture as built over the whole
/// images, within a half float's rounding, with the boat's reflection in it. A cover that cut
/// into the mirror image would crop the reflection and fail it. The view's sides are powers of
/// two: a level of odd size is blitted from exact 2 x 2 blocks within a cover and at the level's
/// own scale (W / floor(W / 2)) over the whole, which differ there by a fraction of a texel.
#[test]
fn building_the_mirror_within_its_cover_changes_no_pixel() {
    let cover = |on: bool| ocean::embed::ShaderConfig { planar_cover: on, ..Default::default() };
    let [within, whole] =
        planar_variants_agree(256, 256, cover, ["boat, mirror within its cover", "boat, mirror over the whole view"]);
    // The boat's mirror image is a small part of the view, and the pass built only that.
    let share = within.planar_cover_share.expect("the mirror pass ran");
    assert!(share > 0.0 && share < 0.25, "the cover is {share} of the images");
    assert_eq!(whole.planar_cover_share, Some(1.0));
}

/// The mirror image shows what a mirror below the objects sees, as the exact tracer sees it on a
/// calm sea: a pier deck's side facing the eye sunlit (the sun is behind the eye), its underside
/// in shade. The mirror reverses every face's winding on screen; culled as the eye's pass culls,
/// the image showed each solid's far faces from inside, shaded, and the side's image came out
/// dark where the truth's is bright.
#[test]
fn planar_reflections_show_the_near_faces() {
    use ocean::measure::{
        groundtruth::{self, Sampling},
        region::Region,
    };
    let gpu = gpu();
    let mut scene = Scene::load(&root().join("scenes/objects/pier_noon.toml")).unwrap();
    scene.wind.speed_mps = 0.0;
    scene.waves.lambda_max_m = ocean::model::scene::LongestWave::Metres(30.0);
    let (w, h) = (640, 480);
    // The deck's side facing the eye and its underside (model: x along the pier, y up, z across;
    // -z faces the eye), between two piles, and their images in the mean sea.
    let world = first_object_in_world(&scene, w, h);
    let image = |p: [f64; 3]| {
        let q = world(p);
        project(&scene, w, h, DVec3::new(q.x, q.y, -q.z)).expect("the deck's image is seen")
    };
    let (side_top, side_bottom, far_bottom) =
        (image([13.0, 2.0, -1.5]), image([13.0, 1.8, -1.5]), image([13.0, 1.8, 1.5]));
    let x = side_top.0;
    // The image is upside down: the underside's between the far and the near lower edges, the
    // side's below that. A pixel's row either side of an edge is left out (it holds both).
    let underside = far_bottom.1 + 1..side_bottom.1;
    let side = side_bottom.1 + 1..side_top.1;
    assert!(!underside.is_empty() && !side.is_empty(), "underside rows {underside:?}, side rows {side:?}");
    let region =
        Region { x: x as u32, y: far_bottom.1 as u32, width: 1, height: (side_top.1 - far_bottom.1 + 1) as u32 };
    let sampling = Sampling { region: Some(region), ..Sampling::new(2) };
    let truth = groundtruth::render(&gpu, &scene, w, h, &sampling, |_, _| {}).unwrap();
    let (report, planar) = common::render_with(&gpu, &scene, w, h, reflecting(Reflections::Planar));
    assert_clean(&report, "pier on a calm sea, planar reflections");
    let traced = |y: usize| common::luminance(truth.radiance[y - far_bottom.1]);
    let drawn = |y: usize| common::luminance(planar.hdr[y * w as usize + x]);
    let ratio = |rows: std::ops::Range<usize>| rows.clone().map(drawn).sum::<f64>() / rows.map(traced).sum::<f64>();
    let mean = |rows: std::ops::Range<usize>| rows.clone().map(drawn).sum::<f64>() / rows.len() as f64;
    let sunlit = ratio(side.clone());
    let contrast = mean(side.clone()) / mean(underside.clone());
    // 1.06 and 25 here (the truth's contrast is 50: the raster lights the underside by the
    // environment unoccluded, the truth's piles and deck stop some of the sea below it); 15 when
    // the objects' sea below scattered the sun up, which the drawn sea does not; culled as the
    // eye's pass, the side's image is 0.07 of the truth's and darker than the underside's.
    assert!((sunlit - 1.0).abs() < 0.25, "the sunlit side's image (rows {side:?}): {sunlit} of the truth's");
    assert!(contrast > 20.0, "the sunlit side's image against the underside's (rows {underside:?}): {contrast}");
}

/// Through a rough sea a pier's piles darken the sea before them as the exact tracer's do: the
/// reflection's energy there, the scene's sky term less that of the scene without the pier, over
/// the latter, against the same of the tracer's. The low reflections, which meet the piles, mirror about
/// three times as much as the steep ones (their Fresnel), and hide the horizon's bright sky;
/// the taps tile the footprint's length without blurring the thin piles across its width.
#[test]
fn a_rough_sea_mirrors_a_pier_s_piles_as_the_truth_does() {
    use ocean::measure::{
        groundtruth::{self, Sampling},
        region::Region,
    };
    let gpu = gpu();
    let scene = Scene::load(&root().join("scenes/objects/pier_noon.toml")).unwrap();
    let mut bare = scene.clone();
    bare.objects.clear();
    let (w, h) = (240, 180);
    // The near piles' waterline (model: x along the pier, y up, -z faces the eye) at the middle
    // of the pier, and the sea below it: the rows where the piles' reflection lies, past the
    // pixel row the waterline crosses.
    let world = first_object_in_world(&scene, w, h);
    let (left, waterline) = project(&scene, w, h, world([7.0, 0.0, -1.3])).expect("the piles are in view");
    let (right, _) = project(&scene, w, h, world([23.0, 0.0, -1.3])).expect("the piles are in view");
    let (x0, x1) = (left.min(right), left.max(right));
    let region = Region { x: x0 as u32, y: waterline as u32 + 2, width: (x1 - x0) as u32, height: 6 };
    let sampling = Sampling { region: Some(region), ..Sampling::new(3) };
    let (report, with) = common::render_with(&gpu, &scene, w, h, sky_term(Reflections::Planar));
    assert_clean(&report, "pier through a rough sea, planar reflections");
    let (_, without) = common::render_with(&gpu, &bare, w, h, sky_term(Reflections::None));
    let traced = groundtruth::render(&gpu, &scene, w, h, &sampling, |_, _| {}).unwrap();
    let traced_bare = groundtruth::render(&gpu, &bare, w, h, &sampling, |_, _| {}).unwrap();
    let (mut drawn, mut truth, mut drawn_sea, mut truth_sea) = (0.0, 0.0, 0.0, 0.0);
    for y in 0..region.height as usize {
        for x in 0..region.width as usize {
            let i = (region.y as usize + y) * w as usize + region.x as usize + x;
            let k = y * region.width as usize + x;
            drawn += common::luminance(with.hdr[i]) - common::luminance(without.hdr[i]);
            truth += common::luminance(traced.sky[k]) - common::luminance(traced_bare.sky[k]);
            drawn_sea += common::luminance(without.hdr[i]);
            truth_sea += common::luminance(traced_bare.sky[k]);
        }
    }
    assert!(truth < 0.0, "the tracer's piles darken the sea: {truth}");
    // Each against its own sea: the reflection takes the place of a share of the sky the sea
    // reflects, and this sea's sky term is 1.49 times the tracer's here (a low eye over long
    // waves, docs/bench/objects.md), which the absolute ratio (1.31) carries. 0.88 here; 0.66
    // with each tap hiding the sky lookup's pair, interpolated and held beyond it; 0.33 with four
    // taps, each weighted alike and hiding the footprint's mean sky.
    let ratio = (drawn / drawn_sea) / (truth / truth_sea);
    assert!(
        (ratio - 1.0).abs() < 0.15,
        "the piles' reflection over {region:?}, each over its sea: {ratio} of the truth's"
    );
}

/// `both` reads the mirror's images first and traces the screen only where they hold nothing:
/// where the mirror holds the boat (every reflection of it here), `both` reflects it as `planar`
/// does. Adding the mirror's coverage over the rest of a footprint the screen's trace had
/// partly covered counted the boat twice: 7% more reflection than `planar`'s over the picture
/// (19% over the blocks where bench reflections resolves the truth's).
#[test]
fn both_methods_count_an_object_once() {
    let gpu = gpu();
    let scene = Scene::load(&root().join("scenes/objects/boat_sunset.toml")).unwrap();
    let (w, h) = (240, 180);
    let (_, none) = common::render_with(&gpu, &scene, w, h, sky_term(Reflections::None));
    let (_, planar) = common::render_with(&gpu, &scene, w, h, sky_term(Reflections::Planar));
    let (report, both) = common::render_with(&gpu, &scene, w, h, sky_term(Reflections::Both));
    assert_clean(&report, "boat at sunset, both reflections");
    let reflection = |frame: &RenderedFrame| -> f64 {
        frame.hdr.iter().zip(&none.hdr).map(|(&p, &q)| common::luminance(p) - common::luminance(q)).sum()
    };
    let (by_planar, by_both) = (reflection(&planar), reflection(&both));
    assert!(by_planar < 0.0, "the boat darkens the sunset's sea: {by_planar}");
    assert!((by_both / by_planar - 1.0).abs() < 0.02, "both {by_both} against planar {by_planar}");
}

/// The boat 52 m ahead with the sun low behind it, seen from 25 m up: its hull's shadow falls
/// towards the eye across the sun's glitter, which reaches it on a 3 m/s sea.
fn boat_against_the_sun(shadow_map: &str) -> Scene {
    let settings = format!(
        r#"
        [camera]
        height_m = 25.0
        pitch_deg = -35.0
        fov_y_deg = 50.0
        [wind]
        speed_mps = 3.0
        [sun]
        elevation_deg = 15.0
        azimuth_deg = 5.0
        [render]
        shadow_map = "{shadow_map}"
        "#
    );
    boat_scene(&settings, 52.0, "boat_against_the_sun.toml")
}

/// The objects are in the sun's shadow map: the sea's reflected sun goes where the sunlight
/// through the hull's box meets the sea (its corners carried along the sunlight onto the mean
/// sea, projected), and nowhere else; beside that region, at the same distance, the glitter
/// stays. Only the sun term: the shadow takes nothing else.
#[test]
fn the_objects_shadow_the_sea() {
    let gpu = gpu();
    let (w, h) = (480, 360);
    let sun_only = ocean::embed::Shading {
        shader: ocean::embed::ShaderConfig {
            reflections: Reflections::None,
            terms: ocean::embed::Terms { sun: true, sky: false, sea: false },
            ..Default::default()
        },
        ..Default::default()
    };
    let scene = boat_against_the_sun("auto");
    let (report, shadowed) = common::render_with(&gpu, &scene, w, h, sun_only);
    assert_clean(&report, "boat against the sun");
    let (_, unshadowed) = common::render_with(&gpu, &boat_against_the_sun("off"), w, h, sun_only);
    // A box inside the hull above the water (model space: x along, y up, z across), and its
    // shadow.
    let world = first_object_in_world(&scene, w, h);
    let (e, a) = (scene.sun.elevation_deg.to_radians(), scene.sun.azimuth_deg.to_radians());
    let sun = DVec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin());
    let mut shadow = (usize::MAX, usize::MAX, 0, 0);
    let mut hull = shadow;
    for corner in 0..8 {
        let pick = |bit: u32, lo: f64, hi: f64| if corner & (1 << bit) != 0 { hi } else { lo };
        let p = world([pick(0, -2.0, 2.0), pick(1, 0.0, 0.7), pick(2, -0.7, 0.7)]);
        let on_sea = p - sun * (p.z / sun.z);
        for (rect, q) in [(&mut shadow, on_sea), (&mut hull, p)] {
            let (x, y) = project(&scene, w, h, q).expect("on the picture");
            *rect = (rect.0.min(x), rect.1.min(y), rect.2.max(x), rect.3.max(y));
        }
    }
    let luminance = |p: [f32; 4]| 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    // The mean sun term over the rows of the shadow below the hull, in columns `cols`.
    let rows = (hull.3 + 2)..=shadow.3;
    assert!(!rows.is_empty(), "the shadow {shadow:?} reaches below the hull {hull:?}");
    let mean = |frame: &RenderedFrame, cols: std::ops::RangeInclusive<usize>| {
        let (mut sum, mut n) = (0.0, 0);
        for y in rows.clone() {
            for x in cols.clone() {
                sum += luminance(frame.hdr[y * w as usize + x]) as f64;
                n += 1;
            }
        }
        sum / n as f64
    };
    let inside = shadow.0..=shadow.2;
    let width = shadow.2 - shadow.0;
    let beside = (shadow.2 + width)..=(shadow.2 + 2 * width);
    let (lit, dark) = (mean(&unshadowed, inside.clone()), mean(&shadowed, inside));
    assert!(lit > 0.0 && dark < 0.5 * lit, "in the hull's shadow {shadow:?}: {dark} against {lit} unshadowed");
    let (lit, kept) = (mean(&unshadowed, beside.clone()), mean(&shadowed, beside));
    assert!(kept > 0.85 * lit, "beside the shadow: {kept} against {lit} unshadowed");
}

/// The pier seen along its side with the sun behind the eye: its deck shadows the far row of
/// piles (the sunlight to them crosses the deck), not the near row facing the sun.
fn pier_across_the_sun(shadow_map: &str) -> Scene {
    let pier = root().join("scenes/models/pier.gltf");
    let text = format!(
        r#"
        [camera]
        height_m = 4.0
        pitch_deg = -5.0
        yaw_deg = 80.0
        fov_y_deg = 50.0
        [sun]
        elevation_deg = 35.0
        azimuth_deg = -60.0
        [wind]
        speed_mps = 3.0
        [render]
        shadow_map = "{shadow_map}"
        [[object]]
        file = "{}"
        position_m = [-5.0, 12.0, 0.0]
        "#,
        pier.display()
    );
    Scene::parse(&text, "pier_across_the_sun.toml").unwrap()
}

/// The objects receive the shadows of the sun's map: the far piles darken under the deck's
/// shadow, the near ones keep their sunlight.
#[test]
fn the_objects_shadow_each_other() {
    let gpu = gpu();
    let (w, h) = (640, 400);
    let scene = pier_across_the_sun("auto");
    let (report, shadowed) = common::render_with(&gpu, &scene, w, h, without_reflections());
    assert_clean(&report, "pier across the sun");
    let (_, unshadowed) = common::render_with(&gpu, &pier_across_the_sun("off"), w, h, without_reflections());
    let world = first_object_in_world(&scene, w, h);
    let eye = scene_view(&scene, w as f64 / h as f64, true).0.inverse().w_axis.truncate();
    let luminance = |frame: &RenderedFrame, (x, y): (usize, usize)| {
        let p = frame.hdr[y * w as usize + x];
        0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
    };
    // The piles' centres half way between the water and the deck (model: x along, y up, z
    // across), where both rows are on the picture.
    let mut seen = 0;
    for k in 0..11 {
        let x = 0.3 + 2.94 * k as f64;
        let mut rows = [world([x, 1.0, -1.3]), world([x, 1.0, 1.3])];
        rows.sort_by(|a, b| (*a - eye).length().total_cmp(&(*b - eye).length()));
        let (Some(near), Some(far)) = (project(&scene, w, h, rows[0]), project(&scene, w, h, rows[1])) else {
            continue;
        };
        seen += 1;
        let (lit, dark) = (luminance(&unshadowed, far), luminance(&shadowed, far));
        assert!(dark < 0.6 * lit, "far pile {k} at {far:?}: {dark} against {lit} unshadowed");
        let (lit, kept) = (luminance(&unshadowed, near), luminance(&shadowed, near));
        assert!(kept > 0.9 * lit, "near pile {k} at {near:?}: {kept} against {lit} unshadowed");
    }
    assert!(seen >= 4, "{seen} pairs of piles on the picture");
}

/// The scene at `path` (from the repository's root) on a sea without wind, without the sun's
/// shadows: its objects' images in a mirror.
fn mirror_calm(path: &str) -> Scene {
    let mut scene = Scene::load(&root().join(path)).unwrap();
    scene.wind.speed_mps = 0.0;
    scene.waves.lambda_max_m = ocean::model::scene::LongestWave::Metres(30.0);
    scene.render.shadow_map = ocean::model::scene::ShadowMapMode::Off;
    scene
}

/// The classic screen-space error: the sea seen under a pier's deck lies behind the pier, and its
/// reflected rays, going on away from the eye, never meet the deck, though on screen they run up
/// across the deck's image (nearer the eye by 70 m). The trace must leave that sea its sky's
/// reflection, while the calm sea before the pier, in the same frame, shows the deck's image.
#[test]
fn the_sea_behind_an_object_does_not_reflect_it() {
    let gpu = gpu();
    let scene = mirror_calm("scenes/objects/pier_noon.toml");
    let (w, h) = (320, 240);
    let world = first_object_in_world(&scene, w, h);
    let (_, plain) = common::render_with(&gpu, &scene, w, h, without_reflections());
    let (report, traced) = common::render_with(&gpu, &scene, w, h, reflecting(Reflections::Screen));
    assert_clean(&report, "pier on a calm sea, screen reflections");
    let luminance = |frame: &RenderedFrame, (x, y): (usize, usize)| common::luminance(frame.hdr[y * w as usize + x]);
    // Between two piles, two pixels under the deck's near edge: the sea 100 m off, behind the
    // pier (the eye 2.5 m up sees past the deck's underside at 1.8 m, 30 m ahead).
    let edge = project(&scene, w, h, world([13.0, 1.8, -1.5])).expect("the deck's edge is seen");
    let mut checked = 0;
    for dy in 2..=3 {
        let p = (edge.0, edge.1 + dy);
        let (before, after) = (luminance(&plain, p), luminance(&traced, p));
        assert!((after / before - 1.0).abs() < 0.01, "the sea behind the pier at {p:?}: {after} against {before}");
        checked += 1;
    }
    assert_eq!(checked, 2);
    // The deck's image before the pier, from its top rail to its planking (the sky between),
    // shows the screen's reflection: the deck's sunlit near side, 5% over the sky's there.
    let image = |p: [f64; 3]| {
        let q = world(p);
        project(&scene, w, h, DVec3::new(q.x, q.y, -q.z)).expect("the deck's image is seen")
    };
    let (top, bottom) = (image([13.0, 2.9, -1.5]), image([13.0, 1.9, -1.5]));
    let rows = top.1.min(bottom.1)..=top.1.max(bottom.1);
    let sum = |frame: &RenderedFrame| rows.clone().map(|y| luminance(frame, (top.0, y))).sum::<f64>();
    let change = sum(&traced) / sum(&plain);
    assert!(change > 1.03, "the deck's image at {top:?} .. {bottom:?}: {change} of the sky's reflection");
}

/// At the screen's edge the screen's trace loses what lies beyond it: its reflection fades out
/// over the last pixels instead of ending in a hard line where the picture ends. The pier runs out
/// of the left of the picture, its image in the calm sea with it.
#[test]
fn reflections_fade_out_at_the_screen_s_edge() {
    let gpu = gpu();
    let scene = mirror_calm("scenes/extreme/objects/screen_edge.toml");
    let (w, h) = (320, 240);
    let (_, plain) = common::render_with(&gpu, &scene, w, h, without_reflections());
    let (report, traced) = common::render_with(&gpu, &scene, w, h, reflecting(Reflections::Screen));
    assert_clean(&report, "pier at the screen's edge, screen reflections");
    // The reflection alone, summed down each column over the rows below the horizon.
    let column = |x: usize| -> f64 {
        (h as usize / 2..h as usize)
            .map(|y| {
                let i = y * w as usize + x;
                (common::luminance(traced.hdr[i]) - common::luminance(plain.hdr[i])).abs()
            })
            .sum()
    };
    let at_edge = (0..2).map(column).sum::<f64>() / 2.0;
    let inside = (24..40).map(column).sum::<f64>() / 16.0;
    assert!(inside > 0.0, "the pier's image is reflected inside the picture");
    assert!(at_edge < 0.25 * inside, "at the edge {at_edge} against {inside} inside: a hard edge");
}

/// As the waves move, the objects' reflection moves with them and no more: between two frames a
/// thirtieth of a second apart, where the boat is reflected, each method's picture changes about
/// as much as the sea's without the reflection does there (a trace that found and lost its hit
/// from frame to frame, or lookups not filtered over the footprint, change it more).
#[test]
fn reflections_move_with_the_waves_without_flicker() {
    let gpu = gpu();
    let scene = Scene::load(&root().join("scenes/objects/boat_sunset.toml")).unwrap();
    let (w, h) = (256, 192);
    let at = |t: f64, reflections: Reflections| {
        let mut moved = scene.clone();
        moved.render.time_s = t;
        let shading = if reflections == Reflections::None { without_reflections() } else { reflecting(reflections) };
        let (report, frame) = common::render_with(&gpu, &moved, w, h, shading);
        assert_clean(&report, &format!("boat at sunset at {t} s, {} reflections", reflections.name()));
        frame.hdr.iter().map(|&p| common::luminance(p)).collect::<Vec<f64>>()
    };
    let plain = [at(0.0, Reflections::None), at(1.0 / 30.0, Reflections::None)];
    let mut report = Vec::new();
    for method in [Reflections::Screen, Reflections::Planar, Reflections::Both] {
        let frames = [at(0.0, method), at(1.0 / 30.0, method)];
        // Where the boat is reflected in both frames (a tenth of the plain sea's radiance or more).
        let reflected: Vec<usize> = (0..frames[0].len())
            .filter(|&i| (0..2).all(|k| (frames[k][i] - plain[k][i]).abs() > 0.1 * plain[k][i]))
            .collect();
        assert!(reflected.len() > 50, "{}: the boat's reflection, {} pixels", method.name(), reflected.len());
        let change = |f: &[Vec<f64>; 2]| reflected.iter().map(|&i| (f[1][i] - f[0][i]).abs()).sum::<f64>();
        let ratio = change(&frames) / change(&plain);
        report.push((method.name(), reflected.len(), ratio));
    }
    // 1.20 (screen), 0.75 (planar), 0.79 (both); read unfiltered (every lookup at the images'
    // finest level) 1.46, 1.75, 1.63.
    assert!(report.iter().all(|&(_, _, ratio)| ratio < 1.5), "change against the plain sea's: {report:?}");
}
