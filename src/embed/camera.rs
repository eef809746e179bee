//! A host's camera: its view and projection matrices read back into the ocean's camera (eye,
//! yaw, pitch, field of view) and the host's clip space, checked for what the ocean can draw.
//!
//! The world is the ocean's: x east, y north, z up, metres, z = 0 at mean sea level. The view
//! takes world points to the host's view space and the projection view space to Vulkan's clip
//! space (x right, y down, depth in [0, 1]), standard or reversed, with a finite or an infinite
//! far plane; a negative-height viewport is not supported.

use crate::error::{Error, Result};
use crate::model::scene::Scene;
use glam::{DMat4, DVec3, DVec4};

/// Largest |sin| of a roll the ocean accepts as level (the projected grid and its row splits
/// assume a level horizon): an engine's level camera carries f32 rounding, about 1e-7.
const LEVEL_TOLERANCE: f64 = 1e-4;
/// Largest relative mismatch between the projection's aspect and the targets' (a pixel is square).
const ASPECT_TOLERANCE: f64 = 1e-4;

/// The host's camera as the ocean draws it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostView {
    /// The eye in the ocean's world (m).
    pub eye: DVec3,
    /// The view's azimuth, counter-clockwise from +x (degrees).
    pub yaw_deg: f64,
    /// The view's elevation, negative looking down (degrees).
    pub pitch_deg: f64,
    /// The vertical field of view (degrees).
    pub fov_y_deg: f64,
    /// Camera-relative world (origin at the eye) to the host's clip space: what the host's
    /// projection and view do to world points, the eye's translation folded in.
    pub clip_from_relative: DMat4,
    /// Whether depth falls from 1 at the near plane to 0 at the far one.
    pub reversed_z: bool,
    /// The far plane's view depth (m); None: infinite.
    pub far_m: Option<f64>,
}

impl HostView {
    /// Reads `view` and `projection` (world to view, view to clip); `aspect` is the targets'
    /// width over height. Errors name what the ocean cannot draw.
    pub fn new(view: DMat4, projection: DMat4, aspect: f64) -> Result<HostView> {
        let bad = |what: String| Error::Argument(format!("camera: {what}"));
        if !view.is_finite() {
            return Err(bad("the view matrix has a NaN or infinite entry".into()));
        }
        if !projection.is_finite() {
            return Err(bad("the projection matrix has a NaN or infinite entry".into()));
        }
        let invertible = |m: DMat4| {
            let det = m.determinant();
            det.is_normal() && m.inverse().is_finite()
        };
        if !invertible(view) {
            return Err(bad("the view matrix is not invertible".into()));
        }
        if !invertible(projection) {
            return Err(bad("the projection matrix is not invertible".into()));
        }
        let eye = view.inverse().w_axis.truncate();
        // The view from the eye: an affine view's rotation alone, exactly (composing it with
        // the eye's translation would leave |eye| * 1e-16 of rounding in a column that should be
        // 0, rounding the rays near a far-off eye by as much).
        let relative = if view.row(3) == DVec4::W {
            DMat4::from_cols(view.x_axis, view.y_axis, view.z_axis, DVec4::W)
        } else {
            view * DMat4::from_translation(eye)
        };
        let clip = projection * relative;
        // A perspective projection through the eye: clip w vanishes at the eye, and is the view
        // depth along the principal axis (the gradient of w), up to scale.
        let w_row = clip.row(3);
        let axis = w_row.truncate();
        if axis.length() == 0.0 || w_row.w.abs() > 1e-9 * axis.length() {
            return Err(bad(
                "the projection is not a perspective one (its w row must be (0, 0, -1, 0) in view space)".into()
            ));
        }
        let forward = axis.normalize();
        let unclip = clip.inverse();
        // The camera-relative point on the ray through NDC (x, y) at depth z, scaled to unit
        // depth along the principal axis.
        let ray = |x: f64, y: f64, z: f64| -> Option<DVec3> {
            let p = unclip * DVec4::new(x, y, z, 1.0);
            let point = p.truncate() / p.w;
            let depth = point.dot(forward);
            (point.is_finite() && depth > 0.0).then(|| point / depth)
        };
        let rays = [(0.0, 0.0), (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)].map(|(x, y)| ray(x, y, 0.5));
        let [Some(centre), Some(right), Some(left), Some(down), Some(up)] = rays else {
            return Err(bad("the projection puts the middle of the depth range behind the eye".into()));
        };
        if ray(0.0, 0.0, 0.25).is_none_or(|r| (r - centre).length() > 1e-6) {
            return Err(bad("the projection's rays do not meet at the eye".into()));
        }
        if (centre - forward).length() > 1e-6 {
            return Err(bad("the projection is off-centre (asymmetric frustums are not supported)".into()));
        }
        let half_x = (right - left) / 2.0;
        let half_down = (down - up) / 2.0;
        let (tan_x, tan_y) = (half_x.length(), half_down.length());
        let (right, down) = (half_x / tan_x, half_down / tan_y);
        if right.dot(down).abs() > 1e-6 {
            return Err(bad("the projection skews its axes".into()));
        }
        if (tan_x / tan_y / aspect - 1.0).abs() > ASPECT_TOLERANCE {
            return Err(bad(format!(
                "the projection's aspect ratio {:.6} is not the targets' {:.6} (pixels must be square)",
                tan_x / tan_y,
                aspect
            )));
        }
        if right.z.abs() > LEVEL_TOLERANCE {
            return Err(bad(format!(
                "a roll of {:.4} degrees is not supported: the ocean draws a level horizon",
                right.z.asin().to_degrees()
            )));
        }
        let up = -down;
        if up.z < -LEVEL_TOLERANCE {
            return Err(bad(
                "the picture is upside down: Vulkan's clip y points down (negate the projection's y scale)".into(),
            ));
        }
        if right.cross(forward).dot(up) < 0.0 {
            return Err(bad("the picture is mirrored (x and y of the clip space must be right and down)".into()));
        }
        let (reversed_z, far_m) = depth_convention(clip, forward)?;
        Ok(HostView {
            eye,
            yaw_deg: right.x.atan2(-right.y).to_degrees(),
            pitch_deg: forward.z.clamp(-1.0, 1.0).asin().to_degrees(),
            fov_y_deg: 2.0 * tan_y.atan().to_degrees(),
            clip_from_relative: clip,
            reversed_z,
            far_m,
        })
    }
}

/// The view and projection that draw `scene` from its own camera, as a host would hand them:
/// the eye `camera.height_m` above the water under it at `render.time_s` (frame::CameraFrame's
/// rule), Vulkan's clip y down, `reversed_z` or standard depth, an infinite far plane. `aspect`
/// is the targets' width over height. The commands draw scene files through this.
pub fn scene_view(scene: &Scene, aspect: f64, reversed_z: bool) -> (DMat4, DMat4) {
    let c = &scene.camera;
    let water = crate::model::waves::generate(scene).water_height_at_origin(scene.render.time_s);
    let eye = DVec3::new(c.x_m, c.y_m, c.height_m + water.max(0.0));
    let (yaw, pitch) = (c.yaw_deg.to_radians(), c.pitch_deg.to_radians());
    // The basis HostView reads back: level right from the yaw alone, so that a view straight
    // down keeps its azimuth (look_to with +z up would have no right axis there).
    let right = DVec3::new(yaw.sin(), -yaw.cos(), 0.0);
    let forward = DVec3::new(pitch.cos() * yaw.cos(), pitch.cos() * yaw.sin(), pitch.sin());
    let up = right.cross(forward);
    let rotation = DMat4::from_cols(right.extend(0.0), up.extend(0.0), (-forward).extend(0.0), DVec4::W).transpose();
    let view = rotation * DMat4::from_translation(-eye);
    let fov = c.fov_y_deg.to_radians();
    // Near the eye, well inside the sea's nearest point (the eye is above the water).
    let near = 1e-3;
    let flip_y = DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0));
    let projection = if reversed_z {
        DMat4::perspective_infinite_reverse_rh(fov, aspect, near)
    } else {
        DMat4::perspective_infinite_rh(fov, aspect, near)
    };
    (view, flip_y * projection)
}

/// Whether depth is reversed, and the far plane's view depth (None: infinite), from how clip
/// depth runs along the principal axis: z(t) = (a t + b) / (c t) for a point at view depth t.
fn depth_convention(clip: DMat4, forward: DVec3) -> Result<(bool, Option<f64>)> {
    let depth_at = |t: f64| {
        let c = clip * (forward * t).extend(1.0);
        c.z / c.w
    };
    let reversed = depth_at(1e3) < depth_at(1.0);
    // At infinity: the direction's clip coordinates (w = 0 input).
    let c = clip * forward.extend(0.0);
    let at_infinity = c.z / c.w;
    let far_value = if reversed { 0.0 } else { 1.0 };
    if (at_infinity - far_value).abs() <= 1e-6 {
        return Ok((reversed, None));
    }
    // Finite: solve z(t) = far with z(t) = at_infinity + b' / t, b' from depth at 1 m.
    let b = depth_at(1.0) - at_infinity;
    let far = b / (far_value - at_infinity);
    if !(far.is_finite() && far > 0.0) {
        return Err(Error::Argument(format!(
            "camera: the projection's depth does not reach {far_value} in front of the eye (at infinity {at_infinity:.6})"
        )));
    }
    Ok((reversed, Some(far)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Vulkan's clip y points down: a right-handed GL-style projection with y negated.
    fn flip_y(p: DMat4) -> DMat4 {
        DMat4::from_diagonal(DVec4::new(1.0, -1.0, 1.0, 1.0)) * p
    }

    /// Depth 1 - z: a standard projection reversed.
    fn reverse(p: DMat4) -> DMat4 {
        DMat4::from_cols(DVec4::X, DVec4::Y, DVec4::new(0.0, 0.0, -1.0, 0.0), DVec4::new(0.0, 0.0, 1.0, 1.0)) * p
    }

    fn view(eye: DVec3, yaw_deg: f64, pitch_deg: f64) -> DMat4 {
        let (y, p) = (yaw_deg.to_radians(), pitch_deg.to_radians());
        let forward = DVec3::new(p.cos() * y.cos(), p.cos() * y.sin(), p.sin());
        DMat4::look_to_rh(eye, forward, DVec3::Z)
    }

    #[test]
    fn reads_back_every_depth_convention() {
        let eye = DVec3::new(12.0, -4.0, 7.5);
        let v = view(eye, 35.0, -12.0);
        let fov = 50f64.to_radians();
        let aspect = 16.0 / 9.0;
        let cases = [
            (flip_y(DMat4::perspective_rh(fov, aspect, 0.1, 5000.0)), false, Some(5000.0)),
            (flip_y(DMat4::perspective_infinite_rh(fov, aspect, 0.1)), false, None),
            (flip_y(reverse(DMat4::perspective_rh(fov, aspect, 0.1, 5000.0))), true, Some(5000.0)),
            (flip_y(DMat4::perspective_infinite_reverse_rh(fov, aspect, 0.1)), true, None),
        ];
        for (p, reversed, far) in cases {
            let h = HostView::new(v, p, aspect).unwrap();
            assert!((h.eye - eye).length() < 1e-9);
            assert!((h.yaw_deg - 35.0).abs() < 1e-9 && (h.pitch_deg + 12.0).abs() < 1e-9, "{h:?}");
            assert!((h.fov_y_deg - 50.0).abs() < 1e-9);
            assert_eq!(h.reversed_z, reversed);
            match (h.far_m, far) {
                (Some(a), Some(b)) => assert!((a / b - 1.0).abs() < 1e-6, "far {a} against {b}"),
                (a, b) => assert_eq!(a, b),
            }
            // The host's clip of a world point is the ocean's of the point relative to the eye.
            let world = DVec3::new(80.0, 40.0, -1.0);
            let host = p * v * world.extend(1.0);
            let ours = h.clip_from_relative * (world - eye).extend(1.0);
            assert!((host - ours).length() < 1e-9 * host.length());
        }
    }

    #[test]
    fn reads_back_a_scene_camera() {
        for (yaw, pitch) in [(0.0, -10.0), (135.0, -90.0), (-60.0, 30.0), (200.0, -45.5)] {
            let mut scene = Scene::default();
            (scene.camera.yaw_deg, scene.camera.pitch_deg, scene.camera.x_m) = (yaw, pitch, 1.0e5);
            for reversed in [false, true] {
                let (v, p) = scene_view(&scene, 4.0 / 3.0, reversed);
                let h = HostView::new(v, p, 4.0 / 3.0).unwrap();
                let wrapped = (h.yaw_deg - yaw).rem_euclid(360.0);
                assert!(wrapped.min(360.0 - wrapped) < 1e-9 && (h.pitch_deg - pitch).abs() < 1e-9, "{h:?}");
                assert!((h.fov_y_deg - scene.camera.fov_y_deg).abs() < 1e-9 && h.reversed_z == reversed);
                assert!((h.eye.x - 1.0e5).abs() < 1e-9 && h.far_m.is_none());
            }
        }
    }

    #[test]
    fn refuses_what_it_cannot_draw() {
        let v = view(DVec3::new(0.0, 0.0, 5.0), 0.0, -5.0);
        let p = flip_y(DMat4::perspective_infinite_reverse_rh(1.0, 1.5, 0.1));
        let error = |v: DMat4, p: DMat4, aspect: f64| HostView::new(v, p, aspect).unwrap_err().to_string();
        assert!(error(v, DMat4::from_cols_array(&[f64::NAN; 16]), 1.5).contains("NaN"));
        assert!(error(DMat4::ZERO, p, 1.5).contains("view matrix is not invertible"));
        assert!(error(v, p, 1.0).contains("aspect ratio"));
        let unflipped = DMat4::perspective_infinite_reverse_rh(1.0, 1.5, 0.1);
        assert!(error(v, unflipped, 1.5).contains("upside down"), "{}", error(v, unflipped, 1.5));
        let rolled = DMat4::from_rotation_z(0.1) * v;
        assert!(error(rolled, p, 1.5).contains("roll"));
        let ortho = DMat4::orthographic_rh(-1.0, 1.0, -1.0, 1.0, 0.1, 100.0);
        assert!(error(v, ortho, 1.0).contains("not a perspective"));
        let off_centre = DMat4::from_translation(DVec3::new(0.2, 0.0, 0.0)) * p;
        assert!(error(v, off_centre, 1.5).contains("off-centre"));
        let mirrored = DMat4::from_diagonal(DVec4::new(-1.0, 1.0, 1.0, 1.0)) * p;
        assert!(error(v, mirrored, 1.5).contains("mirrored"));
    }
}
