//! The part of the rest plane a frame evaluates its wave packets at, and the perspective its
//! packet cells are laid out in (model::packets::grid::CellMap): cells the size of a screen's
//! tiles, and none where the frame cannot look.
//!
//! A rest position x is evaluated by a grid vertex (the projected grid reaches past the screen by
//! GridLayout's margins), by a pixel at the rest position the grid left it, moved by the full
//! method's step to where its ray meets the waves, or by a pixel the grid left uncovered (its
//! ray's point on the rest sphere, or on its limb above it). Each lies within the waves' largest
//! horizontal displacement of a point on one of the (extended) frustum's rays at most the waves'
//! crest above or below the rest sphere. On a ray those points run from where it enters the
//! sphere one crest up (the eye, below that) to where it meets the sphere one crest down, or
//! leaves the upper one: q is monotonic along the ray's horizontal trace, so the ends bound it.

use crate::model::packets::grid::CellMap;
use crate::model::scene::Scene;
use crate::model::waves::WaveSet;
use crate::render::frame::{CameraFrame, GridLayout};
use glam::{DVec2, DVec3};

/// Rays sampled across the extended frustum, per side (its corners and edges among them), and
/// along each edge besides: q's extremes lie on the edges, or at the limb.
const INTERIOR_RAYS: u32 = 33;
const EDGE_RAYS: u32 = 257;
/// The view's box in q widened by this share of its size on each side, for the extremes between
/// the sampled rays (ours: rays 1/256 of an edge apart move q by far less).
const BOX_MARGIN: f64 = 0.01;

/// The perspective cells' map for `scene` drawn at `width` x `height` with the projected grid's
/// cells `cell_px` wide, the packets' crests at most `packet_crest_m` over the rest plane; None
/// where no ray of the view meets the sea.
pub fn cell_map(
    scene: &Scene,
    waves: &WaveSet,
    packet_crest_m: f64,
    width: u32,
    height: u32,
    cell_px: f64,
) -> Option<CellMap> {
    let waves = WaveSet { packet_crest_m, ..waves.clone() };
    let camera = CameraFrame::new(scene, &waves, width, height);
    let layout = GridLayout::new(&camera, &waves, cell_px, width, height);
    // A trochoid moves a point horizontally by its amplitude, a packet by its amplitude times its
    // envelope: the crest bounds both the height and the horizontal reach.
    let crest = waves.highest_crest();
    let forward = DVec2::new(-camera.right.y, camera.right.x);
    let points = rest_extent(&camera, &layout, crest);
    if points.is_empty() {
        return None;
    }
    // Each point's box of the horizontal reach, in (along forward, along left).
    let corners: Vec<DVec2> = points
        .iter()
        .flat_map(|p| {
            let (f, l) = (p.dot(forward), p.dot(forward.perp()));
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)].map(|(a, b)| DVec2::new(f + a * crest, l + b * crest))
        })
        .collect();
    // The perspective's centre behind every one of them by the eye's height at least, so that
    // cells grow as the sea's pixels do, with the distance squared over the height; and by the
    // reach over the view's half-width's tangent at least, so that the reach about the nearest
    // points widens the box in q.x no more than the view itself does.
    let nearest = corners.iter().map(|c| c.x).fold(f64::INFINITY, f64::min);
    let clear = camera.plane_height.max(crest / camera.tan_half_x).max(f64::MIN_POSITIVE);
    let offset = clear + (-nearest).max(0.0);
    let q: Vec<DVec2> = corners.iter().map(|c| DVec2::new(c.y, 1.0) / (c.x + offset)).collect();
    let lo = q.iter().fold(DVec2::INFINITY, |lo, &v| lo.min(v));
    let hi = q.iter().fold(DVec2::NEG_INFINITY, |hi, &v| hi.max(v));
    let pad = (hi - lo) * BOX_MARGIN;
    let view = [DVec2::new(lo.x - pad.x, (lo.y - pad.y).max(0.5 * lo.y)), hi + pad];
    Some(CellMap::Perspective { forward, offset, view })
}

/// The horizontal ends (eye-relative) of every sampled ray's stretch within the waves' slab,
/// and the limb's point under each ray that passes over the sea; empty where no ray meets it.
fn rest_extent(camera: &CameraFrame, layout: &GridLayout, crest: f64) -> Vec<DVec2> {
    let (x0, x1) = (-1.0 - layout.margin_x, 1.0 + layout.margin_x);
    // From the screen's top (rays over the limb take the limb's point) to past its bottom.
    let (y0, y1) = (-1.0 - layout.margin_y, 1.0 + layout.margin_y);
    if layout.rows == 0 {
        return Vec::new();
    }
    let at = |i: u32, n: u32, a: f64, b: f64| a + (b - a) * i as f64 / (n - 1) as f64;
    let mut ndc: Vec<[f64; 2]> = Vec::new();
    for i in 0..INTERIOR_RAYS {
        for j in 0..INTERIOR_RAYS {
            ndc.push([at(i, INTERIOR_RAYS, x0, x1), at(j, INTERIOR_RAYS, y0, y1)]);
        }
    }
    for i in 0..EDGE_RAYS {
        let (x, y) = (at(i, EDGE_RAYS, x0, x1), at(i, EDGE_RAYS, y0, y1));
        ndc.extend([[x, y0], [x, y1], [x0, y], [x1, y]]);
    }
    let (r, h) = (camera.planet_radius, camera.plane_height);
    let centre_to_eye = DVec3::new(0.0, 0.0, r + h);
    let mut points = Vec::new();
    for n in ndc {
        let ray = camera.ray(n).normalize();
        let horizontal = ray.truncate();
        let top = sphere_roots(centre_to_eye, ray, r + crest);
        let bottom = sphere_roots(centre_to_eye, ray, (r - crest).max(0.0));
        if let Some((enter, leave)) = top {
            let near = if h <= crest { 0.0 } else { enter.max(0.0) };
            let far = bottom.map_or(leave, |(enter, _)| enter);
            if far >= 0.0 {
                points.extend([horizontal * near, horizontal * far.max(near)]);
            }
        }
        // A ray over the limb shades the limb's point below it, where the grid covers it.
        if camera.sea_hit(ray).is_none() && horizontal.length_squared() > 0.0 {
            let limb = r * camera.limb_c().sqrt() / (r + h);
            points.push(horizontal.normalize() * limb);
        }
    }
    points.retain(|p| p.is_finite());
    points
}

/// The ray's distances (unit `dir` from `origin`, centre-relative) to where it enters and leaves
/// the sphere of `radius` about the centre; None where it misses.
fn sphere_roots(origin: DVec3, dir: DVec3, radius: f64) -> Option<(f64, f64)> {
    let b = origin.dot(dir);
    // |o|^2 - rho^2 as a product: no cancellation for an eye just above the sphere.
    let (len, rho) = (origin.length(), radius);
    let c = (len - rho) * (len + rho);
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    Some((-b - root, -b + root))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::waves;

    fn scene(text: &str) -> Scene {
        Scene::parse(text, "test").unwrap()
    }

    /// Every pixel's point on the rest sphere, shifted by the waves' reach each way, maps inside
    /// the view's box: looking ahead, straight down, from 5 cm and from orbit.
    #[test]
    fn every_pixel_of_the_view_lies_in_the_box() {
        let views = [
            "[camera]\nheight_m = 20.0\npitch_deg = -25.0\nfov_y_deg = 45.0",
            "[camera]\nheight_m = 30.0\npitch_deg = -90.0\nfov_y_deg = 60.0",
            "[camera]\nheight_m = 0.05\npitch_deg = -10.0\nfov_y_deg = 90.0",
            "[camera]\nheight_m = 400000.0\npitch_deg = -60.0\nfov_y_deg = 40.0",
            "[camera]\nheight_m = 2.0\npitch_deg = 5.0\nfov_y_deg = 60.0\nyaw_deg = 130.0",
        ];
        for text in views {
            let scene = scene(&format!("{text}\n[wind]\nspeed_mps = 8.0"));
            let waves = waves::generate(&scene);
            let (w, h) = (160, 120);
            let map = cell_map(&scene, &waves, 0.3, w, h, 8.0).expect("the view holds sea");
            let CellMap::Perspective { view, .. } = map else { panic!("{map:?}") };
            let camera = CameraFrame::new(&scene, &WaveSet { packet_crest_m: 0.3, ..waves.clone() }, w, h);
            let reach = waves.highest_crest() + 0.3;
            let mut seen = 0;
            for py in 0..h {
                for px in 0..w {
                    let ndc = [(px as f64 + 0.5) / w as f64 * 2.0 - 1.0, (py as f64 + 0.5) / h as f64 * 2.0 - 1.0];
                    let Some(hit) = camera.sea_hit(camera.ray(ndc)) else { continue };
                    for shift in [DVec2::ZERO, DVec2::X, -DVec2::X, DVec2::Y, -DVec2::Y] {
                        let q = map.apply(hit.point.truncate() + shift * reach).expect("in front");
                        assert!(q.cmpge(view[0]).all() && q.cmple(view[1]).all(), "{text}: {q} outside {view:?}");
                    }
                    seen += 1;
                }
            }
            assert!(seen > 1000, "{text}: {seen}");
        }
    }

    /// A view of the sky alone bins nothing.
    #[test]
    fn a_view_without_sea_has_no_cells() {
        let scene = scene("[camera]\nheight_m = 10.0\npitch_deg = 60.0\nfov_y_deg = 30.0");
        let waves = waves::generate(&scene);
        assert_eq!(cell_map(&scene, &waves, 0.0, 160, 120, 8.0), None);
    }
}
