//! The light on objects, on the CPU in f64: the environment (sky above, sea below) on spherical
//! harmonics, rebuilt only when the sun or the sky changes, and the air between the eye and each
//! object.

use crate::embed::Light;
use crate::model::atmosphere;
use crate::model::environment::{sea_level_light, Sh9};
use crate::model::scene::{Scene, SkyKind};
use crate::model::sky::SkyModel;
use crate::render::frame::SEA_ALBEDO;
use glam::DVec3;

/// Rows of the environment's projection (times twice as many columns): the order-2 projection
/// of a sky with a sharp horizon settles to 0.5% by 24 rows (1152 directions).
const ENVIRONMENT_ROWS: usize = 24;
/// Midpoint samples along the path to an object (the air changes slowly over it; 16 keep the
/// in-scatter within 1% of 256 on the presets' paths).
const AERIAL_STEPS: usize = 16;

/// What the environment was projected for: the sun and the sky's settings.
#[derive(Clone, PartialEq)]
struct EnvironmentKey {
    sun: [u64; 3],
    sky: crate::model::scene::Sky,
    planet_radius: u64,
    radiance_scale: u64,
}

#[derive(Default)]
pub struct ObjectLight {
    environment: Option<(EnvironmentKey, [[f64; 3]; 9])>,
}

impl ObjectLight {
    /// The environment's irradiance coefficients (E(n) = Σ c_i Y_i(n), host unit) under `scene`'s
    /// sky and `light`, the frame's.
    pub fn environment(&mut self, scene: &Scene, light: &Light, radiance_scale: f64) -> [[f64; 3]; 9] {
        let sun = light.sun_direction;
        let key = EnvironmentKey {
            sun: sun.to_array().map(f64::to_bits),
            sky: scene.sky.clone(),
            planet_radius: scene.planet.radius_m.to_bits(),
            radiance_scale: radiance_scale.to_bits(),
        };
        if let Some((k, sh)) = &self.environment {
            if *k == key {
                return *sh;
            }
        }
        let sky: Box<dyn Fn(DVec3) -> [f64; 3]> = match scene.sky.model {
            SkyKind::Physical => {
                let a = atmosphere::shared(&scene.atmosphere());
                let s = sun.to_array();
                Box::new(move |d: DVec3| a.sky_radiance(0.0, d.to_array(), s, atmosphere::SKY_STEPS))
            }
            SkyKind::Preetham => {
                let model = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
                Box::new(move |d: DVec3| model.radiance(d.to_array()))
            }
        };
        let scaled = |d: DVec3| sky(d).map(|l| l * radiance_scale);
        let f64s = |v: [f32; 3]| v.map(f64::from);
        let environment =
            sea_level_light(&scaled, sun, f64s(light.sun_illuminance), f64s(light.sky_illuminance), SEA_ALBEDO);
        let sh = Sh9::project(ENVIRONMENT_ROWS, environment).irradiance_coefficients();
        self.environment = Some((key, sh));
        sh
    }

    /// The air's in-scatter (host unit) and transmittance between an eye `eye_height` m above
    /// the sea and a point `relative` (eye-relative) under `scene`'s sky: none under Preetham's
    /// sky, which has no air to look through (as the sea's shading).
    pub fn air_between(
        &self,
        scene: &Scene,
        sun: DVec3,
        eye_height: f64,
        relative: DVec3,
        radiance_scale: f64,
    ) -> ([f64; 3], [f64; 3]) {
        if scene.sky.model != SkyKind::Physical {
            return ([0.0; 3], [1.0; 3]);
        }
        // The tables are built once per atmosphere in a process (atmosphere::shared).
        let a = atmosphere::shared(&scene.atmosphere());
        let d = relative.length();
        if d == 0.0 {
            return ([0.0; 3], [1.0; 3]);
        }
        let dir = relative / d;
        let (inscatter, transmittance) =
            a.aerial_perspective(eye_height, (dir.z, sun.z, dir.dot(sun)), d, AERIAL_STEPS);
        (inscatter.map(|l| l * radiance_scale), transmittance)
    }
}
