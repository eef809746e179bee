//! The light on objects, on the CPU in f64: the environment's irradiance table (sky above, sea
//! below; model::environment), rebuilt only when the sun or the sky changes, and the air between
//! the eye and each object.

use crate::embed::Light;
use crate::model::atmosphere;
use crate::model::environment::Environment;
use crate::model::scene::{Scene, SkyKind};
use crate::model::sky::SkyModel;
use crate::render::frame::SEA_ALBEDO;
use glam::DVec3;

/// Bands of the environment's grid (times twice as many azimuths): 2048 directions, half of them
/// sky raymarches; a level surface's irradiance is then within 1% of the sky's own quadrature.
const ENVIRONMENT_ROWS: usize = 32;
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
    environment: Option<(EnvironmentKey, Vec<[f32; 4]>)>,
}

impl ObjectLight {
    /// The environment's irradiance table (model::environment, host unit) under `scene`'s sky
    /// and `light`, the frame's.
    pub fn environment(&mut self, scene: &Scene, light: &Light, radiance_scale: f64) -> &[[f32; 4]] {
        let sun = light.sun_direction;
        let key = EnvironmentKey {
            sun: sun.to_array().map(f64::to_bits),
            sky: scene.sky.clone(),
            planet_radius: scene.planet.radius_m.to_bits(),
            radiance_scale: radiance_scale.to_bits(),
        };
        if self.environment.as_ref().is_some_and(|(k, _)| *k == key) {
            return &self.environment.as_ref().expect("checked").1;
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
        let environment = Environment::sea_level(ENVIRONMENT_ROWS, scaled, f64s(light.sky_illuminance), SEA_ALBEDO);
        &self.environment.insert((key, environment.irradiance_table())).1
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::environment::table_lookup;

    #[test]
    fn a_level_surface_takes_the_skys_irradiance_and_a_downward_one_the_seas() {
        for (model, elevation) in [(SkyKind::Physical, 30.0), (SkyKind::Physical, 3.0), (SkyKind::Preetham, 45.0)] {
            let mut scene = Scene::default();
            scene.sky.model = model;
            scene.sun.elevation_deg = elevation;
            let e = f64::to_radians(elevation);
            let sun = DVec3::new(e.cos(), 0.0, e.sin());
            let (sun_irradiance, sky_irradiance) = match model {
                SkyKind::Physical => {
                    let (radiance, sky) = atmosphere::sun_and_sky(&scene.atmosphere(), 0.0, sun.to_array());
                    (radiance.map(|l| l * SkyModel::sun_solid_angle()), sky)
                }
                SkyKind::Preetham => {
                    let sky = SkyModel::new(elevation, 0.0, scene.sky.turbidity);
                    (sky.sun_irradiance(), sky.sky_irradiance())
                }
            };
            let f32s = |v: [f64; 3]| v.map(|x| x as f32);
            let light = Light {
                sun_direction: sun,
                sun_illuminance: f32s(sun_irradiance),
                sky_illuminance: f32s(sky_irradiance),
                sun_radiance: [0.0; 3],
            };
            let mut objects_light = ObjectLight::default();
            let table = objects_light.environment(&scene, &light, 1.0);
            let up = table_lookup(table, DVec3::Z);
            let down = table_lookup(table, -DVec3::Z);
            for c in 0..3 {
                let ratio = up[c] / sky_irradiance[c];
                assert!((ratio - 1.0).abs() < 0.01, "{model:?} at {elevation}: up {ratio:.4} of the sky's");
                // Facing down, the sea alone: the sky it mirrors (water's Fresnel over a uniform
                // sky is 6.6%, more where the bright horizon meets the grazing Fresnel) and what
                // its albedo scatters up of the sky's light.
                let share = down[c] / sky_irradiance[c];
                assert!(share > 0.03 && share < 0.35, "{model:?} at {elevation}: down {share:.3} of the sky's");
            }
        }
    }

    #[test]
    fn sixteen_steps_hold_the_air_to_a_percent() {
        let scene = Scene::default();
        let a = atmosphere::shared(&scene.atmosphere());
        let sun = DVec3::new(0.8, 0.3, 0.52).normalize();
        // From a deck to a boat, from an aircraft to a ship, and 100 km to a ship from 3 km up.
        for (h, relative) in [
            (3.0, DVec3::new(25.0, 0.0, -3.0)),
            (1000.0, DVec3::new(2100.0, 0.0, -1000.0)),
            (3000.0, DVec3::new(1e5, 0.0, -3785.0)),
        ] {
            let d = relative.length();
            let dir = relative / d;
            let cosines = (dir.z, sun.z, dir.dot(sun));
            let (l, t) = a.aerial_perspective(h, cosines, d, AERIAL_STEPS);
            let (l_fine, t_fine) = a.aerial_perspective(h, cosines, d, 256);
            for c in 0..3 {
                assert!((l[c] / l_fine[c] - 1.0).abs() < 0.01, "{relative}: in-scatter {} against {}", l[c], l_fine[c]);
                assert!(
                    (t[c] / t_fine[c] - 1.0).abs() < 0.01,
                    "{relative}: transmittance {} against {}",
                    t[c],
                    t_fine[c]
                );
            }
        }
    }
}
