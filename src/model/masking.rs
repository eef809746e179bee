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
    let profiles = Profiles::new(waves, t, azimuth_deg, step, PROFILES);
    let model_table = MeanFresnelTable::sea_water();
    depressions_deg
        .iter()
        .map(|&depression_deg| {
            let e = depression_deg.to_radians();
            Masking {
                model: model_table.lookup(e.sin(), profiles.variance.sqrt()),
                ..visible_facets(&profiles, step, e)
            }
        })
        .collect()
}

/// The facets seen from an eye at depression e looking along the profiles, and every facet
/// facing it, on the profiles sampled every `step` m (`Masking`, its `model` left 0).
fn visible_facets(profiles: &Profiles, step: f64, e: f64) -> Masking {
    let along = profiles.along;
    // Towards the eye, which lies back along the profile.
    let v = DVec3::new(-along.x * e.cos(), -along.y * e.cos(), e.sin());
    let (mut visible, mut visible_w, mut facing, mut facing_w) = (0.0, 0.0, 0.0, 0.0);
    let (mut visible_tilt, mut facing_tilt) = (0.0, 0.0);
    for samples in &profiles.samples {
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
        model: 0.0,
        visible_share: visible_w / facing_w,
        visible_tilt: visible_tilt / visible_w,
        facing_tilt: facing_tilt / facing_w,
    }
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
    /// Smith's height-correlated masking at each facet's own height (Smith 1967; Heitz 2014): the
    /// facet seen and lit with probability C(h)^(Lambda_v + Lambda_l), C the heights' distribution
    /// (Gaussian of the profiles' own variance), averaged over the mirror facets. It keeps the
    /// correlation of a facet's slope with its height but not with its neighbours' heights: on
    /// the default sea it stays near Smith's mean (docs/results.md, "The sun's masking").
    pub smith_at_height: f64,
    /// The mirror facets' projected area per unit length of the profile over the Gaussian
    /// slopes' (the model's p(zeta_h), of the profiles' slope variance): whether the sea holds as
    /// many mirror facets as the model draws, before any masking.
    pub density_over_gaussian: f64,
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
    let Profiles { along, samples: profiles, variance } = Profiles::new(waves, t, azimuth_deg, step, PROFILES);
    let sigma = variance.sqrt();
    let a = sun_elevation_deg.to_radians();
    let l = DVec3::new(along.x * a.cos(), along.y * a.cos(), a.sin());
    // Smith's Lambda at elevation e for the slopes along the profile: a = tan(e) / (sqrt(2) sigma).
    let lambda = |e: f64| crate::measure::reference::smith_lambda(e.tan() / (std::f64::consts::SQRT_2 * sigma));
    let heights = profiles.iter().flatten().map(|(z, _)| *z);
    let count = profiles.iter().map(Vec::len).sum::<usize>() as f64;
    let mean_height = heights.clone().sum::<f64>() / count;
    let height_sigma = (heights.map(|z| (z - mean_height).powi(2)).sum::<f64>() / count).sqrt();
    depressions_deg
        .iter()
        .map(|&depression_deg| {
            let e = depression_deg.to_radians();
            let v = DVec3::new(-along.x * e.cos(), -along.y * e.cos(), e.sin());
            let h = (v + l).normalize();
            // The mirror facet's slope towards the eye: its normal h leans back along the profile.
            let mirror_slope = -DVec2::new(h.x, h.y).dot(along) / h.z;
            let (lv, ll) = (lambda(e), lambda(a));
            let (mut all, mut seen, mut lit, mut both, mut at_height) = (0.0, 0.0, 0.0, 0.0, 0.0);
            let mut length = 0.0;
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
                    length += if inside { 1.0 } else { 0.0 };
                    if inside && projected > 0.0 && (slope - mirror_slope).abs() < 0.2 * sigma {
                        let (is_seen, is_lit) = (seen_here[i], lit_here[i]);
                        all += projected;
                        seen += if is_seen { projected } else { 0.0 };
                        lit += if is_lit { projected } else { 0.0 };
                        both += if is_seen && is_lit { projected } else { 0.0 };
                        at_height += projected * normal_cdf((samples[i].0 - mean_height) / height_sigma).powf(lv + ll);
                    }
                }
            }
            GlintMasking {
                mirror_slope,
                seen: seen / all,
                lit: lit / all,
                seen_and_lit: both / all,
                smith_seen: 1.0 / (1.0 + lv),
                smith_lit: 1.0 / (1.0 + ll),
                smith_seen_and_lit: 1.0 / (1.0 + lv + ll),
                smith_at_height: at_height / all,
                density_over_gaussian: all / length / gaussian_window(mirror_slope, 0.2 * sigma, sigma, e),
            }
        })
        .collect()
}

/// The projected area towards an eye at depression e, per unit horizontal length, of Gaussian
/// slopes (standard deviation sigma) within half_width of centre: the integral of
/// (sin e + zeta cos e)^+ N(zeta; 0, sigma^2), by the midpoint rule.
fn gaussian_window(centre: f64, half_width: f64, sigma: f64, e: f64) -> f64 {
    const NODES: usize = 64;
    let dz = 2.0 * half_width / NODES as f64;
    (0..NODES)
        .map(|i| {
            let zeta = centre - half_width + (i as f64 + 0.5) * dz;
            let density = (-0.5 * (zeta / sigma).powi(2)).exp() / (sigma * (std::f64::consts::TAU).sqrt());
            (e.sin() + zeta * e.cos()).max(0.0) * density * dz
        })
        .sum()
}

/// Depressions of the glint's masking table (`GlintMaskingTable`); its two configurations are
/// the eye looking towards the sun's azimuth (0) and away from it (1).
pub const GLINT_DEPRESSIONS: usize = 32;
/// Depression j of the table is GLINT_DEPRESSION_MAX_DEG (j / (GLINT_DEPRESSIONS - 1))^2: dense
/// at grazing view, where the correction changes fastest. Beyond it the table's last entry holds.
pub const GLINT_DEPRESSION_MAX_DEG: f64 = 30.0;
/// The profiles' sampling: the shortest train's wavelength, within these bounds (m). Coarser
/// sampling misses the short waves' own crests that hide a grazing facet: on the default sea
/// the share at 1-3 degrees down reads 1.2-1.3 times as high at 2 cm as at 1 cm, 1.5 times at
/// 4 cm. 1 cm would cost four times 2 cm's time.
const TABLE_STEP_M: [f64; 2] = [0.02, 0.1];
/// The table's profiles: fewer than the bench's, it is measured whenever the sea or sun change.
const TABLE_PROFILES: usize = 2;
/// Sampled facets both seen and lit below which a depression's share is not measured.
const TABLE_MIN_HITS: usize = 20;
/// The mirror facets: slopes within this many standard deviations of the mirror slope.
const MIRROR_WINDOW_SIGMAS: f64 = 0.2;

/// The sun term's masking on the sea's own profiles over Smith's: among the facets that mirror an
/// eye at a given depression into the sun, in the vertical plane of the sun, the share both seen
/// and lit over Smith's height-correlated 1 / (1 + Lambda_v + Lambda_l) for the same directions,
/// which takes visibility as independent of the facet's slope. At grazing view it is not: a level
/// facet is seen and lit only near a long wave's crest, while one leaning towards the eye is also
/// seen down the near face (docs/results.md, "The sun's masking"). glsl/masking.glsl reads it at
/// each pixel's depression.
#[derive(Debug, Clone, PartialEq)]
pub struct GlintMaskingTable {
    /// Indexed by configuration * GLINT_DEPRESSIONS + depression.
    pub ratio: Vec<f64>,
}

impl GlintMaskingTable {
    /// Every ratio 1: Smith's masking unchanged (the sun below the horizon, or no slopes).
    pub fn smith() -> GlintMaskingTable {
        GlintMaskingTable { ratio: vec![1.0; 2 * GLINT_DEPRESSIONS] }
    }

    pub fn depression_deg(j: usize) -> f64 {
        GLINT_DEPRESSION_MAX_DEG * (j as f64 / (GLINT_DEPRESSIONS - 1) as f64).powi(2)
    }

    pub fn at(&self, configuration: usize, depression: usize) -> f64 {
        self.ratio[configuration * GLINT_DEPRESSIONS + depression]
    }

    /// `measure`, remembered for the last few seas and suns of this process: renderers made for
    /// the same scene (tests, benches, a window's resize) measure it once.
    pub fn cached(waves: &WaveSet, t: f64, sun_azimuth_deg: f64, sun_elevation_deg: f64) -> GlintMaskingTable {
        type Entry = ((WaveSet, [u64; 3]), GlintMaskingTable);
        static CACHE: std::sync::Mutex<Vec<Entry>> = std::sync::Mutex::new(Vec::new());
        let key = (waves.clone(), [t.to_bits(), sun_azimuth_deg.to_bits(), sun_elevation_deg.to_bits()]);
        remembered(&CACHE, key, || Self::measure(waves, t, sun_azimuth_deg, sun_elevation_deg))
    }

    /// Measured on the profiles along the sun's azimuth (`sun_azimuth_deg` from the wind) at time
    /// t, with the eye before them looking along (towards the sun) and after them looking back
    /// (the sun behind it); `glint` measures the first configuration alone.
    pub fn measure(waves: &WaveSet, t: f64, sun_azimuth_deg: f64, sun_elevation_deg: f64) -> GlintMaskingTable {
        let shortest = waves.trains.first().map_or(TABLE_STEP_M[1], |t| t.wavelength);
        let step = shortest.clamp(TABLE_STEP_M[0], TABLE_STEP_M[1]);
        if sun_elevation_deg <= 0.0 || waves.trains.is_empty() {
            return GlintMaskingTable::smith();
        }
        let Profiles { along, samples: profiles, variance } =
            Profiles::new(waves, t, sun_azimuth_deg, step, TABLE_PROFILES);
        if variance <= 0.0 {
            return GlintMaskingTable::smith();
        }
        let sigma = variance.sqrt();
        let a = sun_elevation_deg.to_radians();
        let l = DVec3::new(along.x * a.cos(), along.y * a.cos(), a.sin());
        let lambda = |e: f64| crate::measure::reference::smith_lambda(e.tan() / (std::f64::consts::SQRT_2 * sigma));
        let reach = |samples: &[(f64, DVec3)], i: usize| samples[i].0 - i as f64 * step * a.tan();
        let lit: Vec<Vec<bool>> = profiles
            .iter()
            .map(|samples| {
                let mut lit = unblocked((0..samples.len()).rev().map(|i| reach(samples, i)));
                lit.reverse();
                lit
            })
            .collect();
        let mut ratio: Vec<Option<f64>> = Vec::with_capacity(2 * GLINT_DEPRESSIONS);
        for towards in [true, false] {
            // The eye before the profiles (towards the sun) or after them (the sun behind it).
            let eye_side = if towards { -1.0 } else { 1.0 };
            for j in 0..GLINT_DEPRESSIONS {
                // Depression 0 stands for its limit: Smith's share vanishes there.
                let e = Self::depression_deg(j).max(0.05).to_radians();
                let v = DVec3::new(eye_side * along.x * e.cos(), eye_side * along.y * e.cos(), e.sin());
                let h = (v + l).normalize();
                let mirror_rise = -DVec2::new(h.x, h.y).dot(along) / h.z;
                let (mut all, mut both, mut hits) = (0.0, 0.0, 0usize);
                for (samples, lit) in profiles.iter().zip(&lit) {
                    let n = samples.len();
                    let seen = if towards {
                        unblocked((0..n).map(|i| samples[i].0 + i as f64 * step * e.tan()))
                    } else {
                        let mut seen = unblocked((0..n).rev().map(|i| samples[i].0 - i as f64 * step * e.tan()));
                        seen.reverse();
                        seen
                    };
                    for (i, (_, area)) in samples.iter().enumerate() {
                        let s = i as f64 * step;
                        let rise = -DVec2::new(area.x, area.y).dot(along) / area.z;
                        let projected = v.dot(*area) / area.z;
                        let inside = s > LEAD_M && s < n as f64 * step - LEAD_M;
                        if inside && projected > 0.0 && (rise - mirror_rise).abs() < MIRROR_WINDOW_SIGMAS * sigma {
                            all += projected;
                            both += if seen[i] && lit[i] { projected } else { 0.0 };
                            hits += usize::from(seen[i] && lit[i]);
                        }
                    }
                }
                let smith = 1.0 / (1.0 + lambda(e) + lambda(a));
                ratio.push((hits >= TABLE_MIN_HITS && all > 0.0).then(|| both / all / smith));
            }
        }
        // A depression with too few facets both seen and lit to measure takes the next steeper
        // one's ratio (the share grows with the depression: this errs bright, never to 0).
        let ratio = ratio
            .chunks(GLINT_DEPRESSIONS)
            .flat_map(|row| {
                let mut next = 1.0;
                let mut filled: Vec<f64> = row
                    .iter()
                    .rev()
                    .map(|r| {
                        next = r.unwrap_or(next);
                        next
                    })
                    .collect();
                filled.reverse();
                filled
            })
            .collect();
        GlintMaskingTable { ratio }
    }
}

impl GlintMaskingTable {
    /// The table at a depression (radians) in configuration 0 or 1, as glsl/masking.glsl reads
    /// it: linearly in sqrt(depression / max), clamped to its domain.
    pub fn lookup(&self, configuration: usize, depression: f64) -> f64 {
        let (j, f) = depression_node(depression);
        self.at(configuration, j) * (1.0 - f) + self.at(configuration, j + 1) * f
    }

    /// The factor glsl/masking.glsl's `sea_masking` puts on the full method's sun term, in f64,
    /// on a level sea (z up): v, l unit directions to the eye and the sun, `wind` the unit wind
    /// direction, slope variances along and across it of the BRDF's slopes and of the whole sea's.
    pub fn sea_masking(&self, v: DVec3, l: DVec3, wind: DVec2, unresolved: [f64; 2], whole: [f64; 2]) -> f64 {
        let local = |d: DVec3| DVec3::new(d.x * wind.x + d.y * wind.y, d.y * wind.x - d.x * wind.y, d.z);
        let (vs, ls) = (local(v), local(l));
        if vs.z <= 0.0 || ls.z <= 0.0 {
            return 1.0;
        }
        let lambda = |d: DVec3, sigma2: [f64; 2]| {
            let spread = (2.0 * (sigma2[0] * d.x * d.x + sigma2[1] * d.y * d.y)).sqrt();
            if spread > 0.0 {
                crate::measure::reference::smith_lambda(d.z / spread)
            } else {
                0.0
            }
        };
        let smith = |sigma2| 1.0 / (1.0 + lambda(vs, sigma2) + lambda(ls, sigma2));
        let smith_ratio = (smith(whole) / smith(unresolved)).min(1.0);
        let (vh, lh) = (DVec2::new(vs.x, vs.y), DVec2::new(ls.x, ls.y));
        let towards_sun = match (vh.try_normalize(), lh.try_normalize()) {
            (Some(a), Some(b)) => 0.5 * (1.0 - a.dot(b)),
            _ => 0.5,
        };
        let depression = vs.z.clamp(0.0, 1.0).asin();
        let exact_over_smith =
            self.lookup(1, depression) * (1.0 - towards_sun) + self.lookup(0, depression) * towards_sun;
        smith_ratio * exact_over_smith.max(0.0)
    }
}

/// The facets the eye sees on the sea's own profiles against the model's, per depression of the
/// view (the glint table's nodes) with the eye looking along the wind (configuration 0) and
/// across it (1). The full method weighs the facets facing the eye by their projected area and
/// lets Smith's masking, which does not see a facet's slope, cancel; at grazing view the facets a
/// ray reaches first lean further towards the eye (they mirror the sky from higher up) and their
/// mean Fresnel is lower. `lean`: the visible facets' mean slope towards the eye less the facing
/// ones'; `fresnel_ratio`: their mean Fresnel over the facing ones' (docs/results.md, "The facets
/// the eye sees"). glsl/masking.glsl reads both at each pixel's depression.
#[derive(Debug, Clone, PartialEq)]
pub struct VisibleFacetTable {
    /// Indexed by configuration * GLINT_DEPRESSIONS + depression.
    pub lean: Vec<f64>,
    pub fresnel_ratio: Vec<f64>,
}

impl VisibleFacetTable {
    /// The model's own: no further lean, its Fresnel (no slopes, or a glassy sea).
    pub fn model() -> VisibleFacetTable {
        VisibleFacetTable { lean: vec![0.0; 2 * GLINT_DEPRESSIONS], fresnel_ratio: vec![1.0; 2 * GLINT_DEPRESSIONS] }
    }

    /// `measure`, remembered for the last few seas of this process.
    pub fn cached(waves: &WaveSet, t: f64) -> VisibleFacetTable {
        type Entry = ((WaveSet, u64), VisibleFacetTable);
        static CACHE: std::sync::Mutex<Vec<Entry>> = std::sync::Mutex::new(Vec::new());
        remembered(&CACHE, (waves.clone(), t.to_bits()), || Self::measure(waves, t))
    }

    /// Measured on TABLE_PROFILES profiles along the wind and across it at time t, sampled as the
    /// glint table's.
    pub fn measure(waves: &WaveSet, t: f64) -> VisibleFacetTable {
        let shortest = waves.trains.first().map_or(TABLE_STEP_M[1], |t| t.wavelength);
        let step = shortest.clamp(TABLE_STEP_M[0], TABLE_STEP_M[1]);
        if waves.trains.is_empty() {
            return VisibleFacetTable::model();
        }
        let mut table = VisibleFacetTable::model();
        for (configuration, azimuth_deg) in [0.0, 90.0].into_iter().enumerate() {
            let profiles = Profiles::new(waves, t, azimuth_deg, step, TABLE_PROFILES);
            if profiles.variance <= 0.0 {
                continue;
            }
            // From the steepest node down: a depression where no facet is seen (a glassy crest
            // line at 0) keeps the next steeper one's values.
            let (mut lean, mut ratio) = (0.0, 1.0);
            for j in (0..GLINT_DEPRESSIONS).rev() {
                // Depression 0 stands for its limit.
                let e = GlintMaskingTable::depression_deg(j).max(0.05).to_radians();
                let m = visible_facets(&profiles, step, e);
                if m.visible_share > 0.0 && m.visible.is_finite() && m.facing > 0.0 {
                    (lean, ratio) = (m.visible_tilt - m.facing_tilt, m.visible / m.facing);
                }
                table.lean[configuration * GLINT_DEPRESSIONS + j] = lean;
                table.fresnel_ratio[configuration * GLINT_DEPRESSIONS + j] = ratio;
            }
        }
        table
    }

    /// (lean, Fresnel ratio) for an eye at depression (radians) looking at `along_share` =
    /// cos^2 of its azimuth from the wind, as glsl/masking.glsl reads them: each configuration
    /// linearly in sqrt(depression / max), then blended by the share.
    pub fn lookup(&self, along_share: f64, depression: f64) -> (f64, f64) {
        self.lookup_steeper(along_share, depression, 1.0)
    }

    /// The same for a sea `steeper` >= 1 times as steep along the view as the one measured (wave
    /// packets' slopes added to the trains'), as glsl/masking.glsl reads it: the measured sea with
    /// every height scaled by s hides from a ray at depression e exactly the facets it hides
    /// unscaled from one at atan(tan(e) / s), its slopes s times as steep (e / s here). So the lean
    /// is read there and scaled by s. The Fresnel is not scaled with the heights: its ratio's departure
    /// from 1, first order in the further lean, is read there and scaled by s as well (held at 0).
    pub fn lookup_steeper(&self, along_share: f64, depression: f64, steeper: f64) -> (f64, f64) {
        // atan(tan(e) / s) as e / s, as the shader takes it: within 1% below 10 degrees, and from
        // 20 degrees on the table is the model's own at either.
        let depression = depression / steeper;
        let (j, f) = depression_node(depression);
        let at = |values: &[f64], c: usize| {
            values[c * GLINT_DEPRESSIONS + j] * (1.0 - f) + values[c * GLINT_DEPRESSIONS + j + 1] * f
        };
        let blend = |values: &[f64]| at(values, 0) * along_share + at(values, 1) * (1.0 - along_share);
        (steeper * blend(&self.lean), (1.0 - steeper * (1.0 - blend(&self.fresnel_ratio))).max(0.0))
    }
}

/// Where a depression (radians) falls among the tables' nodes, which are spaced linearly in
/// sqrt(depression / max): the node below it and the fraction towards the next, clamped to the
/// domain (glsl/masking.glsl, masking_node).
fn depression_node(depression: f64) -> (usize, f64) {
    let max = GLINT_DEPRESSION_MAX_DEG.to_radians();
    let u = (depression / max).clamp(0.0, 1.0).sqrt() * (GLINT_DEPRESSIONS - 1) as f64;
    let j = (u as usize).min(GLINT_DEPRESSIONS - 2);
    (j, u - j as f64)
}

/// A table measured for `key`, remembered for the last few keys of this process: renderers made
/// for the same sea (tests, benches, a window's resize) measure it once.
fn remembered<K: PartialEq, V: Clone>(cache: &std::sync::Mutex<Vec<(K, V)>>, key: K, measure: impl FnOnce() -> V) -> V {
    const KEPT: usize = 8;
    let lock = || cache.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, table)) = lock().iter().find(|(k, _)| *k == key) {
        return table.clone();
    }
    let table = measure();
    let mut entries = lock();
    if entries.len() >= KEPT {
        entries.remove(0);
    }
    entries.push((key, table.clone()));
    table
}

/// The standard normal distribution function (by erfc_approx, the shaders' rational approximation).
pub(crate) fn normal_cdf(x: f64) -> f64 {
    let e = crate::measure::reference::erfc_approx(x.abs() / std::f64::consts::SQRT_2);
    if x >= 0.0 {
        1.0 - 0.5 * e
    } else {
        0.5 * e
    }
}

/// The sea's profiles at one azimuth: their direction, PROFILES parallel lines 37 m apart of
/// (height, area vector) every `step` m (`profile`), and the slopes' variance along them.
struct Profiles {
    along: DVec2,
    samples: Vec<Vec<(f64, DVec3)>>,
    variance: f64,
}

impl Profiles {
    fn new(waves: &WaveSet, t: f64, azimuth_deg: f64, step: f64, count: usize) -> Profiles {
        let wind = DVec2::from(waves.wind_direction);
        let along = DVec2::from_angle(azimuth_deg.to_radians()).rotate(wind);
        // One thread a profile: each is tens of thousands of Newton solves over every train.
        let samples = std::thread::scope(|scope| {
            let lines: Vec<_> = (0..count)
                .map(|line| scope.spawn(move || profile(waves, t, along.perp() * (37.0 * line as f64), along, step)))
                .collect();
            lines.into_iter().map(|line| line.join().expect("a profile's thread does not panic")).collect()
        });
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
        super::waves::add_tangents(&mut tx, &mut ty, d, tr.k * tr.amplitude * c, tr.k * tr.amplitude * s);
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

    /// The table the sun term reads: towards a low sun at grazing view the mirror facets are
    /// seen and lit a fraction of Smith's share, from 20 degrees down about Smith's; away from
    /// the sun no facet mirrors a low sun and Smith's stands.
    #[test]
    fn the_glint_masking_table_hides_grazing_mirror_facets_and_leaves_steep_views_to_smith() {
        let waves = coarse_sea();
        let table = GlintMaskingTable::measure(&waves, 0.0, 0.0, 3.0);
        let node = |deg: f64| {
            (0..GLINT_DEPRESSIONS)
                .min_by(|&a, &b| {
                    let d = |j| (GlintMaskingTable::depression_deg(j) - deg).abs();
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0)
        };
        let row: Vec<f64> = (0..GLINT_DEPRESSIONS).map(|j| table.at(0, j)).collect();
        eprintln!("towards the sun: {row:.3?}");
        assert!(row.iter().all(|r| r.is_finite() && *r >= 0.0));
        assert!(table.at(0, node(1.0)) < 0.5, "{row:?}");
        assert!((0.7..1.4).contains(&table.at(0, node(20.0))), "{row:?}");
        assert!(table.at(0, node(1.0)) < table.at(0, node(5.0)) && table.at(0, node(5.0)) < table.at(0, node(15.0)));
        assert!((0..GLINT_DEPRESSIONS).all(|j| table.at(1, j) == 1.0), "no mirror facets with the sun behind");
        assert_eq!(GlintMaskingTable::measure(&waves, 0.0, 0.0, -1.0), GlintMaskingTable::smith());
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

    /// The table the sky and refracted terms read: at grazing view the facets a ray reaches first
    /// lean further towards the eye than the facing ones and mirror less, most along the wind
    /// (its slopes are the larger); from 20 degrees down they are the facing ones.
    #[test]
    fn the_visible_facets_lean_towards_a_grazing_eye_and_match_the_model_from_above() {
        let waves = coarse_sea();
        let table = VisibleFacetTable::measure(&waves, 0.0);
        let at = |along_share: f64, deg: f64| table.lookup(along_share, f64::to_radians(deg));
        let ((lean_1, ratio_1), (lean_3, _), (lean_20, ratio_20)) = (at(1.0, 1.0), at(1.0, 3.0), at(1.0, 20.0));
        let (across_1, _) = at(0.0, 1.0);
        eprintln!("along the wind: 1 degree {lean_1:.4} {ratio_1:.3}, 3 degrees {lean_3:.4}, 20 degrees {lean_20:.5} {ratio_20:.4}; across at 1 degree {across_1:.4}");
        assert!(lean_1 > 0.02 && lean_1 > lean_3 && lean_3 > lean_20, "{:?}", &table.lean[..GLINT_DEPRESSIONS]);
        assert!(across_1 > 0.0 && across_1 < lean_1, "across the wind {across_1}, along {lean_1}");
        assert!(ratio_1 < 0.9, "the visible facets' Fresnel ratio at 1 degree: {ratio_1}");
        assert!(lean_20.abs() < 0.002 && (ratio_20 - 1.0).abs() < 0.01, "20 degrees: {lean_20} {ratio_20}");
        assert!(table.lean.iter().chain(&table.fresnel_ratio).all(|x| x.is_finite()));
    }

    /// A sea whose every height is s times the measured one's hides from a ray at depression e
    /// what the measured sea hides from atan(tan(e) / s): its table is the measured one read
    /// there, the lean and the Fresnel ratio's departure from 1 scaled by s (`lookup_steeper`,
    /// which the wave packets' steeper sea reads). Checked on the trains with their amplitudes 1.5
    /// times (their trochoids' crests sharpen too, so it is not exact): from 1 to 8 degrees down,
    /// along and across the wind, the lean and the Fresnel ratio read so go from the measured
    /// sea's at least half the way to the steeper sea's own and not past it by more than a tenth.
    /// Measured: the lean 0.55-1.01 of the way (the least at 1 degree along the wind), the ratio
    /// 0.78-1.02; at 0.5 degrees along the wind 0.23 and 0.44, not asserted. Reading the ratio at
    /// atan(tan(e) / s) unscaled went 0.02-0.63 of the way.
    #[test]
    fn a_steeper_sea_s_visible_facets_are_the_measured_ones_seen_from_a_steeper_view() {
        let waves = coarse_sea();
        let scale = 1.5;
        let mut steeper = waves.clone();
        for t in &mut steeper.trains {
            t.amplitude *= scale;
        }
        let along_variance = |w: &WaveSet, along_share: f64| {
            w.trains
                .iter()
                .map(|t| {
                    let c2 = t.angle_from_wind.cos().powi(2);
                    let v = crate::model::waves::trochoid_slope_variance((t.k * t.amplitude).powi(2));
                    v * (c2 * along_share + (1.0 - c2) * (1.0 - along_share))
                })
                .sum::<f64>()
        };
        let (measured, scaled) = (VisibleFacetTable::measure(&waves, 0.0), VisibleFacetTable::measure(&steeper, 0.0));
        for along_share in [1.0, 0.0] {
            let s = (along_variance(&steeper, along_share) / along_variance(&waves, along_share)).sqrt();
            for deg in [1.0, 2.0, 3.0, 5.0, 8.0] {
                let e = f64::to_radians(deg);
                let (lean, ratio) = scaled.lookup(along_share, e);
                let (read, read_ratio) = measured.lookup_steeper(along_share, e, s);
                let (before, before_ratio) = measured.lookup(along_share, e);
                let way = |from: f64, to: f64, read: f64| (read - from) / (to - from);
                let (lean_way, ratio_way) = (way(before, lean, read), way(before_ratio, ratio, read_ratio));
                eprintln!("share {along_share}, {deg} deg, s {s:.3}: lean {before:.4} -> {lean:.4}, read {read:.4} ({lean_way:.2} of the way); Fresnel ratio {before_ratio:.3} -> {ratio:.3}, read {read_ratio:.3} ({ratio_way:.2})");
                if lean - before > 0.002 {
                    assert!(
                        (0.5..=1.1).contains(&lean_way),
                        "{deg} deg, share {along_share}: lean {lean_way} of the way"
                    );
                }
                if before_ratio - ratio > 0.01 {
                    assert!(
                        (0.5..=1.1).contains(&ratio_way),
                        "{deg} deg, share {along_share}: ratio {ratio_way} of the way"
                    );
                }
            }
        }
    }
}
