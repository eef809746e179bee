//! The ground truth's physical sky: the f64 atmosphere model's tables for
//! glsl/groundtruth_sky.glsl, and the error of what the ground truth takes from them, measured per
//! scene and reported beside its own noise:
//! - the GPU's f32 evaluation against the f64 model at the same arguments (`check`);
//! - the sky's quadrature (TRUTH_SKY_STEPS samples a ray) against a converged one;
//! - the transmittance table's bilinear lookup along the scene's sun against its integral;
//! - the sea-level sky irradiance's linear interpolation between its nodes against the model.

use crate::model::atmosphere::{self, transmittance_to_top, Atmosphere, MULTIPLE_SCATTERING_SIZE, TRANSMITTANCE_SIZE};
use crate::model::scene::Scene;

/// Nodes of the sea-level sky irradiance over the sun's zenith cosines the visible sea has
/// (glsl/groundtruth_sky.glsl TRUTH_SEA_LIGHT_NODES).
pub const SEA_LIGHT_NODES: usize = 129;
/// The irradiance is interpolated in its logarithm (it falls exponentially through twilight),
/// floored here (klux) where it is zero (night).
const SEA_LIGHT_FLOOR: f64 = 1e-30;
/// Samples per sky ray and per aerial-perspective path (TRUTH_SKY_STEPS, TRUTH_AERIAL_STEPS).
pub const SKY_STEPS: usize = 128;
pub const AERIAL_STEPS: usize = 64;
/// Evaluations the GPU check runs (glsl/groundtruth.comp `check`): a third each of the sea's sky,
/// the eye's sky and the aerial perspective.
pub const CHECKS: u32 = 96;

/// What the ground truth's sky is measured to carry of its own error, each as the largest
/// relative error over the probes (of the brightest channel; probes darker than a millionth of
/// the brightest are left out).
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub struct TruthSkyError {
    /// The GPU's f32 sky, eye sky and aerial perspective against the f64 model.
    pub gpu_against_f64: f64,
    /// The sky's SKY_STEPS-sample quadrature against 4096 samples, at the check's directions.
    pub quadrature: f64,
    /// The transmittance table's lookup against its integral along the sun, at sea level.
    pub sun_transmittance_table: f64,
    /// The sea-level sky irradiance between its nodes against the model there.
    pub sea_light_interpolation: f64,
}

impl TruthSkyError {
    /// The largest of the four: what the report compares with the ground truth's noise.
    pub fn largest(&self) -> f64 {
        [self.gpu_against_f64, self.quadrature, self.sun_transmittance_table, self.sea_light_interpolation]
            .into_iter()
            .fold(0.0, f64::max)
    }
}

/// The tables the ground truth's shader reads, as one buffer of vec4 words.
pub struct TruthSkyTables {
    pub words: Vec<[f32; 4]>,
    /// The sea-level irradiance's zenith cosines: lowest, highest.
    pub sea_light_range: (f64, f64),
    atmosphere: std::sync::Arc<Atmosphere>,
}

/// The sun's zenith cosines at the sea points the eye can see: the sun's below the eye, turned
/// by up to the limb's central angle acos(R / (R + H)) either way.
fn visible_sun_cosines(scene: &Scene, eye_height: f64, sun_z: f64) -> (f64, f64) {
    let reach = scene.planet.dip(eye_height);
    let zenith = sun_z.clamp(-1.0, 1.0).acos();
    let lo = (zenith + reach).min(std::f64::consts::PI).cos();
    let hi = (zenith - reach).max(0.0).cos();
    (lo, hi)
}

fn sun_at(mu: f64) -> [f64; 3] {
    [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu]
}

impl TruthSkyTables {
    /// Builds the tables for `scene` seen from `eye_height` m, the sun towards `sun_dir`.
    pub fn new(scene: &Scene, eye_height: f64, sun_dir: [f64; 3]) -> TruthSkyTables {
        let params = scene.atmosphere();
        let atmosphere = atmosphere::shared(&params);
        let (lo, hi) = visible_sun_cosines(scene, eye_height, sun_dir[2]);
        let span = hi - lo;
        let node_mu = |i: f64| lo + span * i / (SEA_LIGHT_NODES - 1) as f64;
        // A sea seen from low down spans no cosines worth a node: every node holds the one value.
        let irradiance: Vec<[f64; 3]> = if span > 0.0 {
            (0..SEA_LIGHT_NODES).map(|i| atmosphere.sky_irradiance(0.0, sun_at(node_mu(i as f64)))).collect()
        } else {
            vec![atmosphere.sky_irradiance(0.0, sun_at(lo)); SEA_LIGHT_NODES]
        };
        let mut words = Vec::with_capacity(1 + SEA_LIGHT_NODES + 256 * 64 + 32 * 32);
        let inverse_span = if span > 0.0 { 1.0 / span } else { 0.0 };
        words.push([lo as f32, inverse_span as f32, SEA_LIGHT_NODES as f32, SEA_LIGHT_FLOOR as f32]);
        words.extend(irradiance.iter().map(|e| rgb(e.map(|v| v.max(SEA_LIGHT_FLOOR).ln()))));
        words.extend(atmosphere.transmittance_table().iter().map(|t| rgb(*t)));
        words.extend(atmosphere.multiple_scattering_table().iter().map(|t| rgb(*t)));
        debug_assert_eq!(
            words.len(),
            1 + SEA_LIGHT_NODES
                + TRANSMITTANCE_SIZE.0 * TRANSMITTANCE_SIZE.1
                + MULTIPLE_SCATTERING_SIZE * MULTIPLE_SCATTERING_SIZE
        );
        TruthSkyTables { words, sea_light_range: (lo, hi), atmosphere }
    }

    /// The sea-level irradiance's largest relative error between nodes: the linear lookup at each
    /// interval's midpoint against the model there.
    fn sea_light_error(&self) -> f64 {
        let (lo, hi) = self.sea_light_range;
        if hi <= lo {
            return 0.0;
        }
        let step = (hi - lo) / (SEA_LIGHT_NODES - 1) as f64;
        let node = |i: usize| rgb_f64(self.words[1 + i]);
        (0..SEA_LIGHT_NODES - 1)
            .map(|i| {
                let exact = self.atmosphere.sky_irradiance(0.0, sun_at(lo + (i as f64 + 0.5) * step));
                let (a, b) = (node(i), node(i + 1));
                relative(std::array::from_fn(|c| unfloor((0.5 * (a[c] + b[c])).exp())), exact)
            })
            .fold(0.0, f64::max)
    }

    /// The check's arguments for evaluation i (glsl/groundtruth.comp `check_arguments`, the same
    /// formulas): (altitude, mu, mu_s, nu, path length) and which function.
    pub fn check_arguments(i: u32, eye_height: f64, sun_z: f64) -> (Check, f64, f64, f64, f64, f64) {
        let j = i % 32;
        let kind = match i / 32 {
            0 => Check::SeaSky,
            1 => Check::EyeSky,
            _ => Check::Aerial,
        };
        let azimuth = std::f64::consts::PI * ((j / 8) as f64) / 3.0;
        let mu = match kind {
            Check::Aerial => -0.001 - 0.3 * ((j % 8) as f64 / 7.0).powi(2),
            _ => 0.02 + 0.96 * (j % 8) as f64 / 7.0,
        };
        let mu = mu as f32 as f64;
        let mu_s = sun_z as f32 as f64;
        let nu = ((1.0 - mu * mu).max(0.0).sqrt() * (1.0 - mu_s * mu_s).max(0.0).sqrt() * azimuth.cos() + mu * mu_s)
            as f32 as f64;
        let h = match kind {
            Check::SeaSky => 0.0,
            _ => eye_height as f32 as f64,
        };
        let length = (50.0 * 10f64.powf((j % 8) as f64 * 0.5)) as f32 as f64;
        (kind, h, mu, mu_s, nu, length)
    }

    /// The f64 model's value of check i: radiance, and the transmittance for the aerial checks.
    fn check_value(&self, i: u32, eye_height: f64, sun_z: f64, steps: usize) -> ([f64; 3], [f64; 3]) {
        let (kind, h, mu, mu_s, nu, length) = Self::check_arguments(i, eye_height, sun_z);
        match kind {
            Check::Aerial => self.atmosphere.aerial_perspective(h, (mu, mu_s, nu), length, AERIAL_STEPS),
            _ => (self.atmosphere.sky_radiance_cosines(h, mu, mu_s, nu, steps), [1.0; 3]),
        }
    }

    /// Measures the errors, with the GPU's results of the CHECKS evaluations (two vec4 each:
    /// radiance, transmittance).
    pub fn errors(&self, gpu: &[[f32; 4]], eye_height: f64, sun_dir: [f64; 3]) -> TruthSkyError {
        let sun_z = sun_dir[2];
        let mut gpu_against_f64: f64 = 0.0;
        let mut quadrature: f64 = 0.0;
        let values: Vec<([f64; 3], [f64; 3])> =
            (0..CHECKS).map(|i| self.check_value(i, eye_height, sun_z, SKY_STEPS)).collect();
        let brightest = values.iter().map(|(l, _)| l.iter().copied().fold(0.0, f64::max)).fold(0.0, f64::max);
        for (i, &(l, t)) in (0..CHECKS).zip(&values) {
            if l.into_iter().fold(0.0, f64::max) <= 1e-6 * brightest {
                continue;
            }
            let (gl, gt) = (rgb_f64(gpu[2 * i as usize]), rgb_f64(gpu[2 * i as usize + 1]));
            gpu_against_f64 = gpu_against_f64.max(relative(gl, l)).max(relative(gt, t));
            if Self::check_arguments(i, eye_height, sun_z).0 != Check::Aerial {
                let converged = self.check_value(i, eye_height, sun_z, 4096).0;
                quadrature = quadrature.max(relative(l, converged));
            }
        }
        // The sun's transmittance at sea level through the table against its own integral.
        let params = &self.atmosphere.params;
        let r = params.bottom_radius_m;
        let mu_s = sun_z.max(0.0);
        let sun_transmittance_table = if sun_z > 0.0 {
            relative(self.atmosphere.transmittance(r, mu_s), transmittance_to_top(params, r, mu_s, 2000))
        } else {
            0.0
        };
        TruthSkyError {
            gpu_against_f64,
            quadrature,
            sun_transmittance_table,
            sea_light_interpolation: self.sea_light_error(),
        }
    }
}

/// Which function a check evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Check {
    SeaSky,
    EyeSky,
    Aerial,
}

/// An irradiance interpolated in its floored logarithm, less the floor: 0 stays 0 (the shader's
/// truth_sky_irradiance does the same).
fn unfloor(e: f64) -> f64 {
    (e - SEA_LIGHT_FLOOR).max(0.0)
}

/// |a - b| over b's brightest channel, the largest over the channels.
fn relative(a: [f64; 3], b: [f64; 3]) -> f64 {
    let scale = b.into_iter().fold(0.0, f64::max);
    if scale <= 0.0 {
        return a.into_iter().fold(0.0, |m, x| m.max(x.abs()));
    }
    (0..3).map(|c| (a[c] - b[c]).abs() / scale).fold(0.0, f64::max)
}

fn rgb(v: [f64; 3]) -> [f32; 4] {
    [v[0] as f32, v[1] as f32, v[2] as f32, 0.0]
}

fn rgb_f64(v: [f32; 4]) -> [f64; 3] {
    [v[0] as f64, v[1] as f64, v[2] as f64]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_visible_sun_cosines_widen_with_height_and_hold_the_suns_own() {
        let scene = Scene::default();
        let sun_z = 0.3f64;
        let (lo, hi) = visible_sun_cosines(&scene, 2.0, sun_z);
        // 2 m up the limb is 0.045 degrees off: the sun's cosine moves by sin(72.5 deg) times that.
        assert!(lo <= sun_z && sun_z <= hi && hi - lo < 2e-3, "{lo} {hi}");
        let (lo, hi) = visible_sun_cosines(&scene, 400e3, sun_z);
        assert!(lo < 0.0 && hi > 0.5, "from orbit the terminator is in view: {lo} {hi}");
    }

    #[test]
    fn the_sea_light_nodes_match_the_model_and_between_them_stay_close() {
        let mut scene = Scene::default();
        scene.camera.height_m = 400e3;
        let sun = sun_at(0.2);
        let tables = TruthSkyTables::new(&scene, 400e3, sun);
        let (lo, _) = tables.sea_light_range;
        let exact = tables.atmosphere.sky_irradiance(0.0, sun_at(lo));
        assert!(relative(rgb_f64(tables.words[1]).map(|l| unfloor(l.exp())), exact) < 1e-6);
        // Linear in the logarithm between the nodes over the orbit's whole range of suns.
        // Measured 2.1%, 5 degrees into twilight, where the irradiance is a thousandth of the
        // day's and its own quadrature wiggles between nodes; under 0.1% by day.
        let e = tables.sea_light_error();
        assert!(e < 0.03, "interpolation error {e}");
    }
}
