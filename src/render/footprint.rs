//! The method's split of the trains at one pixel, in f64 on the CPU: the rest point a
//! pixel sees and its footprint (derivatives per pixel), each train's weight in the per-pixel
//! normal, the resolved normal and the residual slope variance left to the BRDF (paper, sections
//! 4-5; glsl/waves.glsl does the same on the GPU). The frame uses it for the baseline's roughness,
//! the f64 reference (`measure::reference`) to shade a pixel.
//!
//! Only valid where the grid is not displaced: the visible point is the ray's intersection with
//! the rest sphere, moved for the full method to where the ray meets the trains the pixel
//! resolves. The normal is in the tangent frame of the point below the eye, as the waves;
//! `resolved_surface` tilts it by the sphere's normal there, as glsl/shade.glsl.

use super::frame::CameraFrame;
use crate::model::packets::{PacketField, SurfaceSum};
use crate::model::waves::{add_tangents, trochoid_slope_variance, WaveSet};
use glam::{DVec2, DVec3};
use std::f64::consts::{PI, TAU};

/// A pixel's box filter's transfer of a sinusoid advancing `s` turns across it: sinc(pi s), 0 past
/// its first zero, as the polynomial (1 - s^2)(1 + a s^2 + b s^4) with a = 1 - pi^2 / 6 (sinc's
/// curvature at 0) and b = -1/2 - a (its slope at the zero): within 1.4e-3 of sinc, with no sine
/// (glsl/waves.glsl box_transfer, the same).
pub fn box_transfer(s: f64) -> f64 {
    let a = 1.0 - PI * PI / 6.0;
    let b = -0.5 - a;
    let s2 = (s * s).min(1.0);
    (1.0 - s2) * (1.0 + s2 * (a + s2 * b))
}

/// Weight of a train in the per-pixel normal: what the pixel's box filter keeps of it, the
/// product of the transfers along the footprint's sides a_u and a_v (rest-position change per
/// pixel), as the ground truth's pixel keeps it (glsl/waves.glsl normal_weight).
pub fn normal_weight(k_turns: DVec2, a_u: DVec2, a_v: DVec2) -> f64 {
    box_transfer(k_turns.dot(a_u).abs()) * box_transfer(k_turns.dot(a_v).abs())
}

/// The smallest phase step any direction has across a footprint with sides a_u and a_v: the
/// minimum over unit k of max(|k.a_u|, |k.a_v|), |a_u x a_v| over the longer of the diagonals
/// a_u -+ a_v (glsl/waves.glsl sample_scale's q_min, which explains why).
pub fn smallest_step(a_u: DVec2, a_v: DVec2) -> f64 {
    let diagonal = (a_u - a_v).length().max((a_u + a_v).length());
    if diagonal > 0.0 {
        a_u.perp_dot(a_v).abs() / diagonal
    } else {
        0.0
    }
}

/// A frame's camera and waves at one time, on an image of `width` x `height` pixels.
pub struct Footprint<'a> {
    pub camera: &'a CameraFrame,
    pub waves: &'a WaveSet,
    pub time_s: f64,
    pub width: u32,
    pub height: u32,
    /// The wave packets alive at time_s, in the eye's frame (PacketField::relative_to), where
    /// there are any: added to the resolved surface as glsl/packets.glsl adds them.
    pub packets: Option<&'a PacketField>,
}

impl Footprint<'_> {
    /// Camera ray through the centre of pixel (px, py), y down.
    pub fn pixel_ray(&self, px: f64, py: f64) -> DVec3 {
        let ndc = [(px + 0.5) / self.width as f64 * 2.0 - 1.0, (py + 0.5) / self.height as f64 * 2.0 - 1.0];
        self.camera.ray(ndc)
    }

    /// Rest position hit by `ray` on the rest sphere, and its derivatives per pixel along
    /// screen u and v (`CameraFrame::rest_derivative`, r linear in pixels).
    pub fn rest_hit(&self, ray: DVec3) -> Option<(DVec2, DVec2, DVec2)> {
        let hit = self.camera.sea_hit(ray)?;
        let dr_du = self.camera.right * self.camera.tan_half_x * (2.0 / self.width as f64);
        let dr_dv = -self.camera.up * self.camera.tan_half_y * (2.0 / self.height as f64);
        let derivative = |dr: DVec3| CameraFrame::rest_derivative(&hit, ray, dr);
        Some((hit.point.truncate(), derivative(dr_du), derivative(dr_dv)))
    }

    /// Resolved normal, view direction and residual slope variance at a pixel's centre; None
    /// where the pixel sees no sea. `ray_hit_strength`: for the full method, the strength of the
    /// step to where the pixel's ray meets the surface it resolves (`ray_hit`) for the view v, the
    /// sphere's normal up at the rest sphere's point and the footprint a_u, a_v; None for that
    /// point.
    pub fn resolved_surface(
        &self,
        px: f64,
        py: f64,
        ray_hit_strength: Option<&dyn Fn(DVec3, DVec3, DVec2, DVec2) -> f64>,
    ) -> Option<(DVec3, DVec3, [f64; 2])> {
        let ray = self.pixel_ray(px, py);
        let (x, a_u, a_v) = self.rest_hit(ray)?;
        let v = -ray.normalize();
        let grid_up = self.camera.sea_normal(x);
        // The step only where the eye sees the rest point from above (the shader's v_up > 0).
        let x = match ray_hit_strength {
            Some(strength) if v.dot(grid_up) > 0.0 => self.ray_hit(x, ray, a_u, a_v, strength(v, grid_up, a_u, a_v)),
            _ => x,
        };
        let up = self.camera.sea_normal(x);
        let v_up = v.dot(up);
        let wind = DVec2::from(self.waves.wind_direction);
        let mut tx = DVec3::X;
        let mut ty = DVec3::Y;
        let mut sigma2 = [0.0; 2];
        for t in &self.waves.trains {
            let dir = DVec2::from(t.direction);
            let k_turns = dir / t.wavelength;
            let kh = t.k * t.amplitude;
            let wn = if v_up > 0.0 { normal_weight(k_turns, a_u, a_v) } else { 0.0 };
            let theta = t.omega * self.time_s + t.phase0 - t.k * dir.dot(x);
            let (s, c) = theta.sin_cos();
            add_tangents(&mut tx, &mut ty, dir, wn * kh * c, wn * kh * s);
            let (along, across) = (dir.dot(wind), dir.perp_dot(wind));
            // The variance the normal does not hold: of the amplitude sqrt(1 - wn^2) k h, from its
            // square as the shader forms it.
            let residual = trochoid_slope_variance((1.0 - wn * wn) * (kh * kh));
            sigma2[0] += along * along * residual;
            sigma2[1] += across * across * residual;
        }
        for p in self.packets.iter().flat_map(|f| &f.packets).filter(|p| p.reaches(x)) {
            let wn = if v_up > 0.0 { normal_weight(p.direction * (p.k / TAU), a_u, a_v) } else { 0.0 };
            let mut surface = SurfaceSum::default();
            p.add_to(x, &mut surface);
            tx += wn * surface.tx;
            ty += wn * surface.ty;
            let residual = trochoid_slope_variance((1.0 - wn * wn) * p.unresolved_slope2(x));
            let (along, across) = (p.direction.dot(wind), p.direction.perp_dot(wind));
            sigma2[0] += along * along * residual;
            sigma2[1] += across * across * residual;
        }
        let n = tx.cross(ty).try_normalize().unwrap_or(DVec3::Z);
        Some((super::frame::tilt_to(n, up), v, sigma2))
    }

    /// The rest position whose displaced point `ray` meets, from x on the rest sphere: the trains
    /// at their normal weights, one Newton step across the ray, taken where the surface faces the
    /// ray and the step stays within the waves' slab, scaled by `strength` (glsl/waves.glsl
    /// ray_hit_rest_position, the same).
    pub fn ray_hit(&self, x: DVec2, ray: DVec3, a_u: DVec2, a_v: DVec2, strength: f64) -> DVec2 {
        if strength <= 0.0 {
            return x;
        }
        let u = ray.normalize();
        let e1 = u.cross(DVec3::Z).try_normalize().unwrap_or(DVec3::X);
        let e2 = e1.cross(u);
        let FilteredPoint { point: p, tangent_x: tx, tangent_y: ty, slab } = self.filtered_point(x, a_u, a_v);
        let (j00, j01, j10, j11) = (tx.dot(e1), ty.dot(e1), tx.dot(e2), ty.dot(e2));
        let det = j00 * j11 - j01 * j10;
        let f = DVec2::new(p.dot(e1), p.dot(e2));
        let step = DVec2::new(j11 * f.x - j01 * f.y, j00 * f.y - j10 * f.x) / det;
        let within = step.length() * u.z.abs() <= slab * (u.z.abs() + u.truncate().length());
        if det > 0.0 && within {
            x - strength * step
        } else {
            x
        }
    }

    /// The surface of the trains at their normal weights for a footprint a_u, a_v: the point
    /// displaced from rest position x, its tangents, and the sum of the weighted amplitudes.
    pub fn filtered_point(&self, x: DVec2, a_u: DVec2, a_v: DVec2) -> FilteredPoint {
        let (mut d, mut tx, mut ty, mut slab) = (DVec3::ZERO, DVec3::X, DVec3::Y, 0.0);
        for t in &self.waves.trains {
            let dir = DVec2::from(t.direction);
            let wn = normal_weight(dir / t.wavelength, a_u, a_v);
            let theta = t.omega * self.time_s + t.phase0 - t.k * dir.dot(x);
            let (s, c) = theta.sin_cos();
            let h = wn * t.amplitude;
            slab += h;
            d += DVec3::new(dir.x * h * s, dir.y * h * s, h * c);
            add_tangents(&mut tx, &mut ty, dir, wn * t.k * t.amplitude * c, wn * t.k * t.amplitude * s);
        }
        FilteredPoint { point: self.camera.sea_point(x) + d, tangent_x: tx, tangent_y: ty, slab }
    }
}

/// A point of the surface a pixel resolves (`Footprint::filtered_point`).
pub struct FilteredPoint {
    /// Eye-relative, on the rest sphere's point displaced.
    pub point: DVec3,
    pub tangent_x: DVec3,
    pub tangent_y: DVec3,
    /// The sum of the weighted amplitudes (m): the surface lies within it of the rest sphere.
    pub slab: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_box_transfer_is_sinc_to_its_first_zero() {
        let mut worst: f64 = 0.0;
        for i in 0..=1000 {
            let s = i as f64 / 1000.0;
            let x = PI * s;
            let sinc = if x > 0.0 { x.sin() / x } else { 1.0 };
            worst = worst.max((box_transfer(s) - sinc).abs());
        }
        assert!(worst < 1.4e-3, "{worst}");
        assert_eq!(box_transfer(1.0), 0.0);
        assert_eq!(box_transfer(3.7), 0.0, "past the first zero: nothing");
        // A quarter turn across the pixel keeps 90%, half a turn 64% (sinc(pi/4), sinc(pi/2) = 2/pi).
        let quarter = (PI / 4.0).sin() / (PI / 4.0);
        assert!((box_transfer(0.25) - quarter).abs() < 1e-3);
        assert!((box_transfer(0.5) - std::f64::consts::FRAC_2_PI).abs() < 1e-3);
    }

    /// The Newton step brings the shaded point onto the pixel's ray: on the default scene at
    /// 160x120, from the bottom row to 6 rows below the horizon, the displaced point's distance
    /// from the ray falls several times over (measured: 11x in the median, 2.3x at the 90th
    /// percentile), and with no strength the point is left as it was.
    #[test]
    fn the_ray_hit_step_lands_on_the_ray() {
        use crate::model::{scene::Scene, waves};
        let scene = Scene::default();
        let wave_set = waves::generate(&scene);
        let (w, h) = (160, 120);
        let camera = CameraFrame::new(&scene, &wave_set, w, h);
        let footprint =
            Footprint { camera: &camera, waves: &wave_set, time_s: 0.0, width: w, height: h, packets: None };
        let off_ray = |x: DVec2, ray: DVec3, a_u, a_v| {
            let p = footprint.filtered_point(x, a_u, a_v).point;
            (p - ray.normalize() * p.dot(ray.normalize())).length()
        };
        let (mut before, mut after) = (Vec::new(), Vec::new());
        for py in (66..h).step_by(3) {
            for px in (0..w).step_by(7) {
                let ray = footprint.pixel_ray(px as f64, py as f64);
                let Some((x, a_u, a_v)) = footprint.rest_hit(ray) else { continue };
                let moved = footprint.ray_hit(x, ray, a_u, a_v, 1.0);
                assert_eq!(footprint.ray_hit(x, ray, a_u, a_v, 0.0), x, "strength 0 leaves the point");
                before.push(off_ray(x, ray, a_u, a_v));
                after.push(off_ray(moved, ray, a_u, a_v));
            }
        }
        let ratios: Vec<f64> = {
            let mut r: Vec<f64> = before.iter().zip(&after).map(|(b, a)| a / b.max(1e-12)).collect();
            r.sort_by(f64::total_cmp);
            r
        };
        let (median, p90) = (ratios[ratios.len() / 2], ratios[ratios.len() * 9 / 10]);
        assert!(ratios.len() > 300, "{} pixels", ratios.len());
        assert!(
            median < 0.15 && p90 < 0.6,
            "off the ray after the step over before: median {median}, 90th percentile {p90}"
        );
    }
}
