//! The sea's own masking at grazing view. Smith's masking, the microfacet model's, hides a facet
//! independently of its slope, so the mean Fresnel of the facets seen is the mean over every facet
//! facing the eye by its projected area (src/model/fresnel.rs). On the sea a grazing ray reaches
//! first the steeper facets facing it, whose Fresnel is lower. This module measures that on the
//! sea's exact surface, along vertical profiles (`ocean bench sky-model`, docs/results.md).
//! The same holds for the sun's glint: the facets that mirror a low sun to a grazing eye are
//! nearly level, and a level facet is seen, and lit, only near a long wave's crest (`glint`).

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
    let Profiles { along, samples: profiles, variance } = Profiles::new(waves, t, azimuth_deg, step);
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
                let seen = unblocked(samples.iter().enumerate().map(|(i, (z, _))| z + i as f64 * step * e.tan()));
                for (i, (_, area)) in samples.iter().enumerate() {
                    let projected = v.dot(*area) / area.z; // per unit of horizontal length
                    if i as f64 * step > LEAD_M && projected > 0.0 {
                        let f = fresnel_exact(v.dot(*area) / area.length(), SEA_WATER_IOR);
                        let tilt = -DVec2::new(area.x, area.y).dot(along) / area.z;
                        facing += projected * f;
                        facing_w += projected;
                        facing_tilt += projected * tilt;
                        if seen[i] {
                            visible += projected * f;
                            visible_w += projected;
                            visible_tilt += projected * tilt;
                        }
                    }
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

/// Where the sun's glint meets the sea's own masking, at one depression of the view: among the
/// facets whose slope along the profile mirrors the eye into the sun (within a fifth of the slopes'
/// standard deviation, by projected area towards the eye), the shares seen from the eye, lit by
/// the sun and both, on the sea's exact profiles; and Smith's for the same directions, which do
/// not depend on the facet: 1 / (1 + Lambda_v), 1 / (1 + Lambda_l) and the height-correlated
/// 1 / (1 + Lambda_v + Lambda_l) the sun term takes (glsl/brdf.glsl).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct GlintMasking {
    /// The mirror slope along the profile (towards the eye positive).
    pub mirror_slope: f64,
    pub seen: f64,
    pub lit: f64,
    pub seen_and_lit: f64,
    pub smith_seen: f64,
    pub smith_lit: f64,
    pub smith_seen_and_lit: f64,
}

/// The glint's masking (`GlintMasking`) looking along `azimuth_deg` from the wind towards a sun
/// `sun_elevation_deg` up at that azimuth, at each depression (degrees), profiles sampled every
/// `step` m at time t. Points within LEAD_M of either end are left out: what hides them from
/// the eye (before) or from the sun (after) could lie past the profile.
pub fn glint(
    waves: &WaveSet,
    t: f64,
    azimuth_deg: f64,
    sun_elevation_deg: f64,
    depressions_deg: &[f64],
    step: f64,
) -> Vec<GlintMasking> {
    let Profiles { along, samples: profiles, variance } = Profiles::new(waves, t, azimuth_deg, step);
    let sigma = variance.sqrt();
    let a = sun_elevation_deg.to_radians();
    let l = DVec3::new(along.x * a.cos(), along.y * a.cos(), a.sin());
    // Smith's Lambda at elevation e for the slopes along the profile: a = tan(e) / (sqrt(2) sigma).
    let lambda = |e: f64| crate::measure::reference::smith_lambda(e.tan() / (std::f64::consts::SQRT_2 * sigma));
    depressions_deg
        .iter()
        .map(|&depression_deg| {
            let e = depression_deg.to_radians();
            let v = DVec3::new(-along.x * e.cos(), -along.y * e.cos(), e.sin());
            let h = (v + l).normalize();
            // The mirror facet's slope towards the eye: its normal h leans back along the profile.
            let mirror_slope = -DVec2::new(h.x, h.y).dot(along) / h.z;
            let (mut all, mut seen, mut lit, mut both) = (0.0, 0.0, 0.0, 0.0);
            for samples in &profiles {
                let n = samples.len();
                // Seen: z + s tan(e) at least its running maximum nearer the eye; lit: z - s tan(a)
                // at least its running maximum further towards the sun.
                let seen_here = unblocked((0..n).map(|i| samples[i].0 + i as f64 * step * e.tan()));
                let mut lit_here = unblocked((0..n).rev().map(|i| samples[i].0 - i as f64 * step * a.tan()));
                lit_here.reverse();
                for (i, (_, area)) in samples.iter().enumerate() {
                    let s = i as f64 * step;
                    let slope = -DVec2::new(area.x, area.y).dot(along) / area.z;
                    let projected = v.dot(*area) / area.z;
                    let inside = s > LEAD_M && s < (n as f64 * step - LEAD_M);
                    if inside && projected > 0.0 && (slope - mirror_slope).abs() < 0.2 * sigma {
                        let (is_seen, is_lit) = (seen_here[i], lit_here[i]);
                        all += projected;
                        seen += if is_seen { projected } else { 0.0 };
                        lit += if is_lit { projected } else { 0.0 };
                        both += if is_seen && is_lit { projected } else { 0.0 };
                    }
                }
            }
            let (lv, ll) = (lambda(e), lambda(a));
            GlintMasking {
                mirror_slope,
                seen: seen / all,
                lit: lit / all,
                seen_and_lit: both / all,
                smith_seen: 1.0 / (1.0 + lv),
                smith_lit: 1.0 / (1.0 + ll),
                smith_seen_and_lit: 1.0 / (1.0 + lv + ll),
            }
        })
        .collect()
}

/// The sea's profiles at one azimuth: their direction, PROFILES parallel lines 37 m apart of
/// (height, area vector) every `step` m (`profile`), and the slopes' variance along them.
struct Profiles {
    along: DVec2,
    samples: Vec<Vec<(f64, DVec3)>>,
    variance: f64,
}

impl Profiles {
    fn new(waves: &WaveSet, t: f64, azimuth_deg: f64, step: f64) -> Profiles {
        let wind = DVec2::from(waves.wind_direction);
        let along = DVec2::from_angle(azimuth_deg.to_radians()).rotate(wind);
        let samples =
            (0..PROFILES).map(|line| profile(waves, t, along.perp() * (37.0 * line as f64), along, step)).collect();
        let variance = waves.sigma2[0] * along.dot(wind).powi(2) + waves.sigma2[1] * along.perp_dot(wind).powi(2);
        Profiles { along, samples, variance }
    }
}

/// Whether each point of a sequence of ray heights is at least the running maximum of the ones
/// before it: nothing earlier on the line rises above its ray.
fn unblocked(reach: impl Iterator<Item = f64>) -> Vec<bool> {
    let mut horizon = f64::NEG_INFINITY;
    reach
        .map(|r| {
            let clear = r >= horizon;
            horizon = horizon.max(r);
            clear
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
pub(crate) fn surface(waves: &WaveSet, t: f64, x: DVec2) -> (DVec3, DVec3, DVec3) {
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

    /// 20 trains from 0.5 m: the default's sea, coarse enough to march quickly.
    fn coarse_sea() -> WaveSet {
        let mut scene = Scene::default();
        scene.waves.count = 20;
        scene.waves.lambda_min_m = 0.5;
        waves::generate(&scene)
    }

    /// A low sun's glint seen at grazing view: the level facets that mirror it are seen and lit
    /// far less often than Smith's masking, which ignores the facet's slope, says; from high up
    /// the two agree.
    #[test]
    fn the_glints_facets_are_hidden_at_grazing_view_more_than_smiths_masking_says() {
        let waves = coarse_sea();
        let m = glint(&waves, 0.0, 0.0, 3.0, &[1.0, 30.0], 0.05);
        let (grazing, steep) = (&m[0], &m[1]);
        eprintln!("1 degree down: {grazing:?}\n30 degrees down: {steep:?}");
        assert!(grazing.seen_and_lit < 0.5 * grazing.smith_seen_and_lit, "{grazing:?}");
        assert!(
            grazing.seen < grazing.smith_seen && grazing.seen_and_lit <= grazing.seen.min(grazing.lit),
            "{grazing:?}"
        );
        assert!((steep.seen - steep.smith_seen).abs() < 0.05, "{steep:?}");
    }

    /// Seen from high up nothing hides a facet; at grazing view the profiles hide most of them,
    /// and the ones left face the eye more steeply: a lower Fresnel than Smith's model keeps.
    #[test]
    fn the_seas_own_masking_hides_grazing_facets_and_leaves_the_steeper_ones() {
        let waves = coarse_sea();
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
