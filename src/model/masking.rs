//! The sea's own masking at grazing view. Smith's masking, the microfacet model's, hides a facet
//! independently of its slope, so the mean Fresnel of the facets seen is the mean over every facet
//! facing the eye by its projected area (src/model/fresnel.rs). On the sea a grazing ray reaches
//! first the steeper facets facing it, whose Fresnel is lower. This module measures that on the
//! sea's exact surface, along vertical profiles (`ocean bench sky-model`, docs/results.md).

use crate::model::fresnel::{fresnel_exact, MeanFresnelTable, SEA_WATER_IOR};
use crate::model::waves::WaveSet;
use glam::{DVec2, DVec3};

/// Profiles per azimuth, their length and the stretch at their start left out (m): a point there
/// could be hidden by waves before the profile begins (a crest 1 m high hides 60 m behind it at
/// 1 degree).
const PROFILES: usize = 4;
const PROFILE_M: f64 = 400.0;
const LEAD_M: f64 = 60.0;

/// The visible facets' mean Fresnel at one azimuth and depression of the view.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Masking {
    /// Over the facets a ray from the eye reaches first.
    pub visible: f64,
    /// Over every facet facing the eye, by its projected area (no masking).
    pub facing: f64,
    /// The model's (MeanFresnelTable at the sea's slope variance along the view).
    pub model: f64,
    /// Share of the facing projected area that stays visible.
    pub visible_share: f64,
    /// Mean slope towards the eye of the visible and of the facing facets.
    pub visible_tilt: f64,
    pub facing_tilt: f64,
}

/// The visible facets' mean Fresnel along profiles at `azimuth_deg` from the wind, at each
/// depression (degrees), sampled every `step` m at time t.
pub fn measure(waves: &WaveSet, t: f64, azimuth_deg: f64, depressions_deg: &[f64], step: f64) -> Vec<Masking> {
    let wind = DVec2::from(waves.wind_direction);
    let along = DVec2::from_angle(azimuth_deg.to_radians()).rotate(wind);
    let profiles: Vec<Vec<(f64, DVec3)>> =
        (0..PROFILES).map(|line| profile(waves, t, along.perp() * (37.0 * line as f64), along, step)).collect();
    let variance = waves.sigma2[0] * along.dot(wind).powi(2) + waves.sigma2[1] * along.perp_dot(wind).powi(2);
    let model_table = MeanFresnelTable::sea_water();
    depressions_deg
        .iter()
        .map(|&depression_deg| {
            let e = depression_deg.to_radians();
            // Towards the eye, which lies back along the profile.
            let v = DVec3::new(-along.x * e.cos(), -along.y * e.cos(), e.sin());
            let (mut visible, mut visible_w, mut facing, mut facing_w) = (0.0, 0.0, 0.0, 0.0);
            let (mut visible_tilt, mut facing_tilt) = (0.0, 0.0);
            for samples in &profiles {
                // Visible: z + s tan(e) at least its running maximum nearer the eye.
                let mut horizon = f64::NEG_INFINITY;
                for (i, (z, area)) in samples.iter().enumerate() {
                    let s = i as f64 * step;
                    let reach = z + s * e.tan();
                    let projected = v.dot(*area) / area.z; // per unit of horizontal length
                    if s > LEAD_M && projected > 0.0 {
                        let f = fresnel_exact(v.dot(*area) / area.length(), SEA_WATER_IOR);
                        let tilt = -DVec2::new(area.x, area.y).dot(along) / area.z;
                        facing += projected * f;
                        facing_w += projected;
                        facing_tilt += projected * tilt;
                        if reach >= horizon {
                            visible += projected * f;
                            visible_w += projected;
                            visible_tilt += projected * tilt;
                        }
                    }
                    horizon = horizon.max(reach);
                }
            }
            Masking {
                visible: visible / visible_w,
                facing: facing / facing_w,
                model: model_table.lookup(e.sin(), variance.sqrt()),
                visible_share: visible_w / facing_w,
                visible_tilt: visible_tilt / visible_w,
                facing_tilt: facing_tilt / facing_w,
            }
        })
        .collect()
}

/// (height, area vector dp/dx x dp/dy) at Eulerian positions offset + s along, s = 0, step, ...:
/// each point's rest position by Newton's method from the previous one's, a step away.
fn profile(waves: &WaveSet, t: f64, offset: DVec2, along: DVec2, step: f64) -> Vec<(f64, DVec3)> {
    let steps = (PROFILE_M / step) as usize;
    let mut rest = offset;
    let mut samples = Vec::with_capacity(steps);
    for i in 0..steps {
        let target = offset + along * (step * i as f64);
        for _ in 0..20 {
            let (p, tx, ty) = surface(waves, t, rest);
            let miss = DVec2::new(p.x, p.y) - target;
            if miss.abs().max_element() < 1e-9 {
                break;
            }
            let det = tx.x * ty.y - ty.x * tx.y; // > 0: no train loops (k h <= 1)
            rest -= DVec2::new(miss.x * ty.y - miss.y * ty.x, tx.x * miss.y - tx.y * miss.x) / det;
        }
        let (p, tx, ty) = surface(waves, t, rest);
        samples.push((p.z, tx.cross(ty)));
    }
    samples
}

/// The displaced point of rest position x and its tangents along x and y (glsl/waves.glsl).
fn surface(waves: &WaveSet, t: f64, x: DVec2) -> (DVec3, DVec3, DVec3) {
    let (mut p, mut tx, mut ty) = (DVec3::new(x.x, x.y, 0.0), DVec3::X, DVec3::Y);
    for tr in &waves.trains {
        let d = DVec2::from(tr.direction);
        let (s, c) = (tr.phase_at(t) - tr.k * d.dot(x)).sin_cos();
        p += DVec3::new(d.x * tr.amplitude * s, d.y * tr.amplitude * s, tr.amplitude * c);
        let (kc, ks) = (tr.k * tr.amplitude * c, tr.k * tr.amplitude * s);
        tx += DVec3::new(-d.x * d.x * kc, -d.y * d.x * kc, d.x * ks);
        ty += DVec3::new(-d.x * d.y * kc, -d.y * d.y * kc, d.y * ks);
    }
    (p, tx, ty)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::Scene;
    use crate::model::waves;

    /// Seen from high up nothing hides a facet; at grazing view the profiles hide most of them,
    /// and the ones left face the eye more steeply: a lower Fresnel than Smith's model keeps.
    #[test]
    fn the_seas_own_masking_hides_grazing_facets_and_leaves_the_steeper_ones() {
        let mut scene = Scene::default();
        scene.waves.count = 20;
        scene.waves.lambda_min_m = 0.5;
        let waves = waves::generate(&scene);
        for azimuth in [0.0, 90.0] {
            for (m, depression) in measure(&waves, 3.0, azimuth, &[1.0, 2.0, 20.0], 0.1).iter().zip([1.0, 2.0, 20.0]) {
                assert!(
                    m.visible.is_finite() && m.facing > 0.0 && m.visible_share > 0.0 && m.visible_share <= 1.0,
                    "{m:?}"
                );
                if depression >= 20.0 {
                    assert!(m.visible_share > 0.99 && (m.visible / m.facing - 1.0).abs() < 0.01, "{m:?}");
                    assert!((m.facing / m.model - 1.0).abs() < 0.03, "projected area alone is the model's: {m:?}");
                } else {
                    assert!(m.visible_share < 0.8 && m.visible < 0.97 * m.facing, "{m:?}");
                }
            }
        }
    }
}
