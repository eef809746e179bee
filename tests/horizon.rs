//! The horizon's row: the pixel the mean sea's horizon crosses is split between the sea and the
//! sky by the share of it below the horizon, so a camera tilting by a fraction of a pixel moves
//! the horizon by that fraction (no row pops from sky to sea), and the share is right.

mod common;

use common::{assert_clean, gpu, luminance, render};
use ocean::model::scene::{Scene, SkyKind};

const SIZE: (u32, u32) = (32, 48);
const FOV_Y_DEG: f64 = 60.0;

/// 10 m above the default sea, the sun behind the eye (its glints out of view), Preetham's sky.
fn looking_at_the_horizon(pitch_deg: f64) -> Scene {
    let mut scene = Scene::default();
    scene.sky.model = SkyKind::Preetham;
    scene.camera.height_m = 10.0;
    scene.camera.pitch_deg = pitch_deg;
    scene.camera.fov_y_deg = FOV_Y_DEG;
    scene.sun.elevation_deg = 30.0;
    scene.sun.azimuth_deg = 180.0;
    scene
}

/// Summed luminance of the rows within four of the image's centre line.
fn middle_rows(pitch_deg: f64) -> f64 {
    let gpu = gpu();
    let (w, h) = SIZE;
    let (report, frame) = render(&gpu, &looking_at_the_horizon(pitch_deg), w, h);
    assert_clean(&report, "the horizon's rows");
    (h / 2 - 4..h / 2 + 4)
        .flat_map(|y| (0..w).map(move |x| (y * w + x) as usize))
        .map(|i| luminance(frame.hdr[i]))
        .sum()
}

#[test]
fn the_horizon_moves_by_fractions_of_a_pixel() {
    // Level, the horizon lies on the boundary between the two middle rows; each step tilts the
    // camera up by a quarter of a pixel there (the angle of one pixel at the centre), so the
    // horizon enters the row below by a quarter each time. Rounded to whole pixels, the four
    // steps would change nothing, then everything, then nothing twice.
    let pixel_deg = (2.0 * (FOV_Y_DEG.to_radians() / 2.0).tan() / SIZE.1 as f64).atan().to_degrees();
    let sums: Vec<f64> = (0..=4).map(|i| middle_rows(i as f64 * pixel_deg / 4.0)).collect();
    let whole = sums[4] - sums[0];
    assert!(whole.abs() > 0.05 * sums[0], "a pixel's tilt hardly changes the rows: {sums:?}");
    for (i, step) in sums.windows(2).map(|s| s[1] - s[0]).enumerate() {
        let share = step / whole;
        assert!((0.1..=0.4).contains(&share), "quarter step {i} moves {share:.3} of a whole pixel's change: {sums:?}");
    }
}
