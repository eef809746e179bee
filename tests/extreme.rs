//! Stiff and extreme scenes (scenes/extreme/): every one renders under validation with finite,
//! sane radiance and no seam along the horizon; so do extreme image sizes.

mod common;

use common::{assert_clean, gpu, luminance, render};
use ocean::measure::groundtruth::{self, Sampling};
use ocean::model::scene::Scene;
use ocean::render::renderer::RenderedFrame;
use std::path::Path;

fn extreme_scenes() -> Vec<(String, Scene)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/extreme");
    let mut scenes: Vec<(String, Scene)> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| (p.file_stem().unwrap().to_string_lossy().into_owned(), Scene::load(&p).unwrap()))
        .collect();
    scenes.sort_by(|a, b| a.0.cmp(&b.0));
    scenes
}

/// A row's level: the mean luminance of its pixels but the brightest and the darkest tenth. A seam
/// is a line across the row; the sun's glints are a few pixels of it, and where its path is a
/// pixel wide (an eye 5 cm above the sea) its rows hold a glint or none, by chance.
fn row_level(mut row: Vec<f64>) -> f64 {
    row.sort_by(f64::total_cmp);
    let cut = row.len() / 10;
    let kept = &row[cut..row.len() - cut];
    kept.iter().sum::<f64>() / kept.len() as f64
}

fn row_luminance(frame: &RenderedFrame, y: u32) -> f64 {
    row_level((0..frame.width).map(|x| luminance(frame.hdr[(y * frame.width + x) as usize])).collect())
}

/// The rows within `reach` of the horizon that stand out from both their neighbours (brighter or
/// darker than each by more than 15% of their difference plus 2%) and continue the trend of
/// neither side (off the line through the two rows there by more than half their step plus 2%):
/// lines, not transitions, and not the sky's own glow steepening towards the horizon above a
/// darker sea.
fn rows_standing_out(frame: &RenderedFrame, horizon_row: u32, reach: u32) -> Vec<(u32, String)> {
    let rows: Vec<f64> = (0..frame.height).map(|y| row_luminance(frame, y)).collect();
    lines_in(&rows, horizon_row, reach)
}

fn lines_in(rows: &[f64], horizon_row: u32, reach: u32) -> Vec<(u32, String)> {
    let lo = horizon_row.saturating_sub(reach).max(2);
    let hi = (horizon_row + reach).min(rows.len() as u32 - 3);
    (lo..=hi)
        .filter_map(|y| {
            let at = |dy: i32| rows[(y as i32 + dy) as usize];
            let (above, here, below) = (at(-1), at(0), at(1));
            let slack = 0.15 * (above - below).abs() + 0.02 * above.max(below);
            let stands_out = here > above.max(below) + slack || here < above.min(below) - slack;
            let off_trend = |near: f64, far: f64| {
                (here - (2.0 * near - far)).abs() > 0.5 * (near - far).abs() + 0.02 * near.max(here)
            };
            (stands_out && off_trend(above, at(-2)) && off_trend(below, at(2)))
                .then(|| (y, format!("row {y} ({here:.3}) stands out between {above:.3} and {below:.3}")))
        })
        .collect()
}

/// The detector itself: a one-row dip or spike at the sea's edge is a line; the sky brightening
/// ever faster down to the horizon above a dark sea, or a plain step, is not.
#[test]
fn the_seam_detector_tells_lines_from_gradients() {
    // The kilometre-wave scene's rows at the horizon under the full method (its sky glowing at
    // sunset): its last row of sky (5) stands out from both neighbours, and is on the sky's trend.
    let glow = [5.632, 6.066, 6.566, 7.162, 7.917, 8.953, 2.256, 2.124, 2.859, 5.103, 8.258];
    assert!(lines_in(&glow, 5, 3).is_empty(), "{:?}", lines_in(&glow, 5, 3));
    let step = [8.0, 8.0, 8.0, 8.0, 8.0, 8.0, 3.0, 3.0, 3.0, 3.0, 3.0];
    assert!(lines_in(&step, 5, 3).is_empty());
    let mut dark_edge = step;
    dark_edge[6] = 1.5;
    assert_eq!(lines_in(&dark_edge, 5, 3).iter().map(|l| l.0).collect::<Vec<_>>(), [6]);
    let mut bright_edge = glow;
    bright_edge[6] = 12.0;
    let mut dark_glow = glow;
    dark_glow[6] = 0.5;
    assert_eq!(lines_in(&dark_glow, 5, 3).iter().map(|l| l.0).collect::<Vec<_>>(), [6]);
    assert_eq!(lines_in(&bright_edge, 5, 3).iter().map(|l| l.0).collect::<Vec<_>>(), [6]);
}

/// A seam is a line fixed to the screen and one pixel thick at any resolution. The scene's own
/// features near the horizon are neither: the sky's glow just above it spans more rows as the image
/// grows, and a wave's crest (which an eye below the crests sees edge-on as a dark line) moves. So
/// a row that stands out at w x h is a suspect only if one of the rows it becomes at 2w x 2h stands
/// out too, and it still stands out later (`later`, the same view half the longest train's period
/// later, at least 1.3 s). Returns the suspects' descriptions.
fn seam_suspects(
    coarse: &RenderedFrame,
    fine: &RenderedFrame,
    later: &RenderedFrame,
    horizon_row: u32,
) -> Vec<(u32, String)> {
    let fine_rows = rows_standing_out(fine, 2 * horizon_row, 9);
    let later_rows = rows_standing_out(later, horizon_row, 4);
    rows_standing_out(coarse, horizon_row, 4)
        .into_iter()
        .filter_map(|(y, what)| {
            let thin = fine_rows.iter().find(|(z, _)| (2 * y).saturating_sub(1) <= *z && *z <= 2 * y + 2)?;
            later_rows
                .iter()
                .any(|(z, _)| *z == y)
                .then(|| (y, format!("{what}, at twice the resolution {}, and later", thin.1)))
        })
        .collect()
}

/// A suspect is a seam unless the ground truth of the same view has a line there too (within a
/// row): swell kilometres long, seen edge-on from a low eye, draws dark and bright lines along the
/// horizon in the truth itself, and barely moves between frames. Returns the seams: the suspects
/// the truth does not explain.
fn seams(gpu: &ocean::vk::gpu::Gpu, scene: &Scene, coarse: &RenderedFrame, suspects: &[(u32, String)]) -> Vec<String> {
    if suspects.is_empty() {
        return Vec::new();
    }
    let (w, h) = (coarse.width, coarse.height);
    let truth = groundtruth::render(gpu, scene, w, h, &Sampling::new(2), |_, _| {}).unwrap();
    let rows: Vec<f64> =
        (0..h).map(|y| row_level((0..w).map(|x| luminance(truth.radiance[(y * w + x) as usize])).collect())).collect();
    suspects
        .iter()
        .filter(|(y, _)| lines_in(&rows, *y, 1).is_empty())
        .map(|(_, what)| format!("{what}; the ground truth has no line there"))
        .collect()
}

/// Views whose horizon shows a line the ground truth does not: the method's own, measured and
/// open (docs/results.md, "The ground truth at grazing rays": since the truth's camera rays march
/// to their first crossing, its kilometre swell's rows at the horizon no longer match ours; the
/// storm's one-pixel dark crest lines, issue 25 item 6, are the same kind). The test asserts the
/// line is still there, so that a fix is noticed and the view returns to the strict check.
const KNOWN_SEAMS: &[&str] = &["kilometre_waves"];

#[test]
fn every_extreme_scene_renders_finite_and_sane() {
    let gpu = gpu();
    let scenes = extreme_scenes();
    assert!(scenes.len() >= 18, "the extreme suite is incomplete");
    for (name, scene) in &scenes {
        let (report, frame) = render(&gpu, scene, 64, 48);
        assert_clean(&report, name);
        let mean = report.mean_radiance;
        assert!(mean.iter().all(|&c| c.is_finite() && (0.0..1e5).contains(&c)), "{name}: mean radiance {mean:?}");
        if scene.sun.elevation_deg > -18.0 {
            assert!(mean.iter().all(|&c| c > 0.0), "{name}: black by day or twilight: {mean:?}");
        }
        assert!(
            frame.hdr.iter().all(|p| p[..3].iter().all(|&c| (0.0..=65504.0).contains(&c))),
            "{name}: radiance out of range"
        );
    }
}

#[test]
fn the_horizon_has_no_seam() {
    let gpu = gpu();
    let mut cases: Vec<(String, Scene)> = [("level", 0.0), ("slightly down", -5.0), ("slightly up", 5.0)]
        .into_iter()
        .map(|(name, pitch)| {
            let mut scene = Scene::default();
            scene.camera.pitch_deg = pitch;
            (name.to_owned(), scene)
        })
        .collect();
    cases.extend(extreme_scenes());
    let (w, h) = (128u32, 96u32);
    let mut checked = 0;
    for (name, scene) in &cases {
        // NDC y of the limb: tan(pitch + dip) / tan(fov/2), y pointing down.
        let tan_half = (scene.camera.fov_y_deg.to_radians() / 2.0).tan();
        let dip = scene.planet.dip(scene.camera.height_m);
        let ndc = (scene.camera.pitch_deg.to_radians() + dip).tan() / tan_half;
        let row = ((ndc + 1.0) / 2.0 * h as f64).round();
        if !(6.0..h as f64 - 6.0).contains(&row) {
            continue; // the horizon is off screen
        }
        // The physical sky peaks in a band a few degrees above the horizon (the low sun's glow
        // through the longest path in the air); rows wider than that band, at any resolution of
        // this test, take in its peak and stand out for the sky's own sake. Such coarse views
        // (a fov near 180 degrees) are checked under Preetham's sky, which has no band.
        let row_degrees = (2.0 * tan_half / h as f64 / (1.0 + ndc * ndc * tan_half * tan_half)).to_degrees();
        let mut scene = scene.clone();
        if row_degrees > 2.0 {
            scene.sky.model = ocean::model::scene::SkyKind::Preetham;
        }
        let (report, frame) = render(&gpu, &scene, w, h);
        assert_clean(&report, name);
        let (report_fine, fine) = render(&gpu, &scene, 2 * w, 2 * h);
        assert_clean(&report_fine, name);
        // Half the longest train's period later its crests have moved half a wavelength (deep
        // water: T = sqrt(2 pi lambda / g)); kilometre swell barely moves in 1.3 s, and its crests
        // seen edge-on are lines in the ground truth too (docs/results.md, "The detail a pixel can
        // see").
        let period = (std::f64::consts::TAU * scene.lambda_max_m() / 9.81).sqrt();
        let mut after = scene.clone();
        after.render.time_s += (0.5 * period).max(1.3);
        let (report_later, later) = render(&gpu, &after, w, h);
        assert_clean(&report_later, name);
        let suspects = seam_suspects(&frame, &fine, &later, row as u32);
        let found = seams(&gpu, &scene, &frame, &suspects);
        if KNOWN_SEAMS.contains(&name.as_str()) {
            assert!(!found.is_empty(), "{name}: its known seam is gone: take it off KNOWN_SEAMS");
        } else {
            assert!(found.is_empty(), "{name}: {}", found.join("; "));
        }
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} views had the horizon in view");
}

#[test]
fn extreme_sizes_render_clean() {
    let gpu = gpu();
    for (w, h) in [(1, 1), (7, 3), (4096, 16), (16, 4096)] {
        let (report, frame) = render(&gpu, &Scene::default(), w, h);
        assert_clean(&report, &format!("{w}x{h}"));
        assert_eq!(frame.hdr.len(), (w * h) as usize);
    }
}
