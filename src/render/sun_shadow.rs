//! The sun's view of the displaced grid (passes/shadow.rs): an orthographic projection along the
//! sunlight fitted to the sea the grid displaces in view, and the probes that find it.
//! Only the grid's trains cast shadows here; the BRDF's unresolved slopes keep their statistical
//! (Smith) shadowing, so no train is counted by both (docs/architecture.md, "Sun shadows").

use crate::model::waves::WaveSet;
use crate::render::frame::{CameraFrame, GEOMETRY_STEPS};
use glam::{DMat4, DVec2, DVec3, DVec4};

/// Screen positions per axis (NDC over [-2, 2], the grid's margins included) where the grid's
/// resolution is probed.
pub const PROBES: usize = 41;

/// The rest positions (camera-relative, m) of the probes at which the grid displaces some train:
/// glsl/waves.glsl `sample_scale`'s test (the longest train against the footprint's smallest
/// phase step), with the longest train's step `margin` times finer than the shader needs.
pub fn displaced_probes(
    camera: &CameraFrame,
    waves: &WaveSet,
    cell_px: f64,
    size: (u32, u32),
    margin: f64,
) -> Vec<DVec2> {
    resolving_probes(camera, waves, cell_px, GEOMETRY_STEPS[1] as f64, size, margin)
}

/// The rest positions of the probes at which samples `cells` pixels apart resolve some train to
/// less than the phase step `unresolved` (turns), with `margin` as in `displaced_probes`.
pub fn resolving_probes(
    camera: &CameraFrame,
    waves: &WaveSet,
    cells: f64,
    unresolved: f64,
    size: (u32, u32),
    margin: f64,
) -> Vec<DVec2> {
    let longest = waves.longest_wavelength();
    if longest <= 0.0 {
        return Vec::new();
    }
    probe_steps(camera, size, 2.0)
        .filter_map(|(rest, q_min)| (longest * unresolved > margin * q_min * cells).then_some(rest))
        .collect()
}

/// The smallest phase step (m) of samples one pixel apart at any probe on the screen that meets
/// the sea: the finest footprint any pixel has. None where no probe meets the sea.
pub fn finest_pixel_step(camera: &CameraFrame, size: (u32, u32)) -> Option<f64> {
    probe_steps(camera, size, 1.0).map(|(_, q_min)| q_min).reduce(f64::min)
}

/// Each probe over NDC [-extent, extent] whose ray meets the sea: its rest position and the
/// smallest phase step (m) of samples one pixel apart there (footprint::smallest_step).
fn probe_steps(camera: &CameraFrame, size: (u32, u32), extent: f64) -> impl Iterator<Item = (DVec2, f64)> + '_ {
    let dr_du = camera.right * camera.tan_half_x * (2.0 / size.0 as f64);
    let dr_dv = -camera.up * camera.tan_half_y * (2.0 / size.1 as f64);
    let at = move |j: usize| -extent + 2.0 * extent * j as f64 / (PROBES - 1) as f64;
    (0..PROBES * PROBES).filter_map(move |i| {
        let ndc = [at(i % PROBES), at(i / PROBES)];
        let r = camera.ray(ndc);
        let hit = camera.sea_hit(r)?;
        let (qu, qv) = (CameraFrame::rest_derivative(&hit, r, dr_du), CameraFrame::rest_derivative(&hit, r, dr_dv));
        Some((hit.point.truncate(), super::footprint::smallest_step(qu, qv)))
    })
}

/// The sun's orthographic view of the displaced sea.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunView {
    /// Camera-relative world (z up, m) to the shadow map's clip space: x, y over the map, z = 0
    /// nearest the sun, 1 farthest.
    pub view_proj: DMat4,
    /// A texel's sides (m): across the sunlight (level), and across it in its vertical plane
    /// (a low sun's map spans a thin slab there, seen at a slant: a texel covers that side over
    /// the sine of the elevation on the sea).
    pub texel_m: [f64; 2],
}

/// The box (camera-relative world, m) holding the shadow casters a host draws into the sun's map
/// (embed::Ocean::record_shadows): the map then covers them and the sea their shadows fall on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CasterBox {
    pub min: DVec3,
    pub max: DVec3,
}

impl CasterBox {
    pub fn corners(&self) -> impl Iterator<Item = DVec3> + '_ {
        (0..8).map(|i| DVec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), self.max, self.min))
    }
}

/// Texel sides are snapped to quarter octaves, and the map's centre to whole texels of the
/// world (not of the eye), so that a moving eye or a turning view does not crawl the shadows'
/// edges across texels frame by frame.
const TEXEL_STEPS_PER_OCTAVE: f64 = 4.0;

/// Fits the sun's view to the sea the grid displaces (`probes`, rest positions) and to the
/// waves that can shadow it from towards the sun, and to a host's `casters` and the sea below
/// them; None with the sun at or below the horizon or nothing displaced and no casters. `eye`
/// is the eye's world position (m), `size` the map's texels per side.
pub fn fit(
    probes: &[DVec2],
    waves: &WaveSet,
    camera: &CameraFrame,
    sun_dir: DVec3,
    eye: DVec3,
    size: u32,
    casters: Option<CasterBox>,
) -> Option<SunView> {
    if sun_dir.z <= 0.0 || (probes.is_empty() && casters.is_none()) {
        return None;
    }
    // Light axes: `across` horizontal, `up` across the sunlight in its vertical plane.
    let toward_sun = sun_dir.normalize();
    let level = DVec3::new(toward_sun.x, toward_sun.y, 0.0);
    let across = if level.length_squared() > 1e-12 { DVec3::Z.cross(level).normalize() } else { DVec3::X };
    let up = toward_sun.cross(across);
    // Every point of the surface lies within the trains' summed amplitude of its rest position
    // (horizontally and vertically); a crest that shadows a rest position lies at most
    // 2 A / tan(elevation) towards the sun (a crest A above the rest plane over a trough A below).
    let amplitude = waves.highest_crest();
    let tan_elevation = toward_sun.z / level.length().max(f64::MIN_POSITIVE);
    let farthest = probes.iter().map(|p| p.length()).fold(0.0, f64::max);
    let shadow_reach = (2.0 * amplitude / tan_elevation).min(farthest);
    let towards = if level.length_squared() > 0.0 { level.normalize().truncate() } else { DVec2::ZERO };
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for p in probes {
        for shift in [0.0, shadow_reach] {
            for corner in 0..8 {
                let sign = |bit: u32| if corner & (1 << bit) != 0 { 1.0 } else { -1.0 };
                let x = *p + towards * shift + DVec2::new(sign(0), sign(1)) * amplitude;
                let world = camera.sea_point(x) + DVec3::Z * (sign(2) * amplitude);
                let light = DVec3::new(world.dot(across), world.dot(up), world.dot(toward_sun));
                lo = lo.min(light);
                hi = hi.max(light);
            }
        }
    }
    // A caster's corners, and where the sunlight through each meets the lowest trough below it
    // (the same texel across the light, farther along it): its shadow on the sea.
    for corner in casters.iter().flat_map(|c| c.corners().collect::<Vec<_>>()) {
        let trough = camera.sea_point(corner.truncate()).z - amplitude;
        let down = ((corner.z - trough) / toward_sun.z).max(0.0);
        for world in [corner, corner - toward_sun * down] {
            let light = DVec3::new(world.dot(across), world.dot(up), world.dot(toward_sun));
            lo = lo.min(light);
            hi = hi.max(light);
        }
    }
    // The probes are a sample: a probe's spacing more on every side.
    let pad = (hi - lo) * (1.0 / (PROBES - 1) as f64) + DVec3::splat(amplitude.max(0.01));
    let (lo, hi) = (lo - pad, hi + pad);
    let texel =
        |side: f64| 2f64.powf((TEXEL_STEPS_PER_OCTAVE * (side / size as f64).log2()).ceil() / TEXEL_STEPS_PER_OCTAVE);
    let texel = [texel(hi.x - lo.x), texel(hi.y - lo.y)];
    let eye_light = [eye.dot(across), eye.dot(up)];
    let snap = |mid: f64, axis: usize| ((mid + eye_light[axis]) / texel[axis]).round() * texel[axis] - eye_light[axis];
    let centre = DVec2::new(snap(0.5 * (lo.x + hi.x), 0), snap(0.5 * (lo.y + hi.y), 1));
    let scale = texel.map(|t| 2.0 / (t * size as f64));
    let depth = hi.z - lo.z;
    // clip = (scale (p.across - c.x), scale (p.up - c.y), (hi.z - p.toward_sun) / depth, 1)
    let row_x = DVec4::new(across.x * scale[0], across.y * scale[0], across.z * scale[0], -centre.x * scale[0]);
    let row_y = DVec4::new(up.x * scale[1], up.y * scale[1], up.z * scale[1], -centre.y * scale[1]);
    let row_z = DVec4::new(-toward_sun.x / depth, -toward_sun.y / depth, -toward_sun.z / depth, hi.z / depth);
    let view_proj = DMat4::from_cols_array_2d(&[
        [row_x.x, row_y.x, row_z.x, 0.0],
        [row_x.y, row_y.y, row_z.y, 0.0],
        [row_x.z, row_y.z, row_z.z, 0.0],
        [row_x.w, row_y.w, row_z.w, 1.0],
    ]);
    Some(SunView { view_proj, texel_m: texel })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{scene::Scene, waves};
    use crate::render::footprint::{smallest_step, Footprint};

    /// specialize::plan leaves the ray-hit step out by the probes' finest footprint, its cut taken
    /// twice finer: every pixel's own footprint must then be no finer than half of it. Checked
    /// on every fourth pixel of views that look ahead, down and up at the sky.
    #[test]
    fn no_pixel_is_finer_than_the_probes_find() {
        let (w, h) = (160u32, 120u32);
        for (pitch, expect_sea) in [(0.0, true), (-60.0, true), (50.0, false)] {
            let mut scene = Scene::default();
            scene.camera.pitch_deg = pitch;
            let wave_set = waves::generate(&scene);
            let camera = CameraFrame::new(&scene, &wave_set, w, h);
            let finest = finest_pixel_step(&camera, (w, h));
            assert_eq!(finest.is_some(), expect_sea, "pitch {pitch}: {finest:?}");
            let footprint =
                Footprint { camera: &camera, waves: &wave_set, time_s: 0.0, width: w, height: h, packets: None };
            let mut pixels = 0;
            for py in (0..h).step_by(4) {
                for px in (0..w).step_by(4) {
                    let Some((_, a_u, a_v)) = footprint.rest_hit(footprint.pixel_ray(px as f64, py as f64)) else {
                        continue;
                    };
                    pixels += 1;
                    let step = smallest_step(a_u, a_v);
                    let finest = finest.unwrap_or(f64::INFINITY);
                    assert!(step >= 0.5 * finest, "pitch {pitch}, pixel ({px}, {py}): {step} m against {finest} m");
                }
            }
            assert_eq!(pixels > 0, expect_sea, "pitch {pitch}: {pixels} sea pixels");
        }
    }
}
