//! The physical sky seen from sea level, tabulated in f64 for the CPU's evaluation of the methods'
//! models (measure::reference, `bench sky-model`): what the sea reflects, under one sun, over
//! elevation and azimuth from the sun. The atmosphere is spherically symmetric, so these two
//! angles are all a direction's radiance depends on at a given sun.

use crate::model::atmosphere::{self, AtmosphereParams};
use std::f64::consts::PI;

/// Rows over elevation (denser at the horizon, where the sky changes fastest: elevation =
/// 90 degrees x^2 for x uniform) and columns over the azimuth from the sun, 0 to 180 degrees (the
/// sky is symmetric about the sun's vertical plane).
const ROWS: usize = 96;
const COLUMNS: usize = 96;
/// Samples per sky ray: the ground truth's (measure::truth_sky::SKY_STEPS).
const STEPS: usize = 128;

/// The table and the light at sea level under its sun.
#[derive(Debug, PartialEq)]
pub struct SeaLevelSky {
    radiance: Vec<[f64; 3]>,
    sun_dir: [f64; 3],
    /// The sun disc's mean radiance at sea level (kcd/m^2) and the sky's irradiance there (klux).
    pub sun_radiance: [f64; 3],
    pub sky_irradiance: [f64; 3],
}

impl SeaLevelSky {
    pub fn new(params: &AtmosphereParams, sun_dir: [f64; 3]) -> SeaLevelSky {
        let a = atmosphere::shared(params);
        let radiance = (0..ROWS * COLUMNS)
            .map(|i| {
                let (elevation, azimuth) = (row_elevation(i / COLUMNS), column_azimuth(i % COLUMNS));
                let mu = elevation.sin();
                let mu_s = sun_dir[2];
                let nu = mu * mu_s + elevation.cos() * (1.0 - mu_s * mu_s).max(0.0).sqrt() * azimuth.cos();
                a.sky_radiance_cosines(0.0, mu, mu_s, nu, STEPS)
            })
            .collect();
        let (sun_radiance, sky_irradiance) = atmosphere::sun_and_sky(params, 0.0, sun_dir);
        SeaLevelSky { radiance, sun_dir, sun_radiance, sky_irradiance }
    }

    /// Radiance (kcd/m^2) towards unit `dir` (z up; directions below the horizon see the
    /// horizon's), bilinear in the table.
    pub fn radiance(&self, dir: [f64; 3]) -> [f64; 3] {
        let elevation = dir[2].clamp(0.0, 1.0).asin();
        let s = self.sun_dir;
        // The azimuth from the sun's: the angle between the horizontal projections.
        let (sx, sy) = (s[0], s[1]);
        let sun_len = (sx * sx + sy * sy).sqrt();
        let azimuth = if sun_len > 0.0 {
            let (c, d) = (dir[0] * sx + dir[1] * sy, (dir[0] * sy - dir[1] * sx).abs());
            d.atan2(c)
        } else {
            0.0
        };
        let y = (elevation / (PI / 2.0)).sqrt() * (ROWS - 1) as f64;
        let x = azimuth / PI * (COLUMNS - 1) as f64;
        let (y0, x0) = ((y.floor() as usize).min(ROWS - 2), (x.floor() as usize).min(COLUMNS - 2));
        let (fy, fx) = (y - y0 as f64, x - x0 as f64);
        let at = |r: usize, c: usize| self.radiance[r * COLUMNS + c];
        std::array::from_fn(|k| {
            let top = at(y0, x0)[k] * (1.0 - fx) + at(y0, x0 + 1)[k] * fx;
            let bottom = at(y0 + 1, x0)[k] * (1.0 - fx) + at(y0 + 1, x0 + 1)[k] * fx;
            top * (1.0 - fy) + bottom * fy
        })
    }
}

impl crate::model::sky::SkyLight for SeaLevelSky {
    fn sun_dir(&self) -> [f64; 3] {
        self.sun_dir
    }
    fn sun_irradiance(&self) -> [f64; 3] {
        self.sun_radiance.map(|l| l * crate::model::sky::SkyModel::sun_solid_angle())
    }
    fn sky_irradiance(&self) -> [f64; 3] {
        self.sky_irradiance
    }
    fn radiance(&self, dir: [f64; 3]) -> [f64; 3] {
        SeaLevelSky::radiance(self, dir)
    }
}

fn row_elevation(row: usize) -> f64 {
    let x = row as f64 / (ROWS - 1) as f64;
    PI / 2.0 * x * x
}

fn column_azimuth(column: usize) -> f64 {
    PI * column as f64 / (COLUMNS - 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_matches_the_model_away_from_the_sun() {
        let params = AtmosphereParams::default();
        let el = 20f64.to_radians();
        let sun = [el.cos(), 0.0, el.sin()];
        let sky = SeaLevelSky::new(&params, sun);
        let a = atmosphere::shared(&params);
        let mut worst: f64 = 0.0;
        for (e, az) in [(2.0, 150.0), (7.0, 60.0), (15.0, 100.0), (45.0, 170.0), (80.0, 30.0), (0.5, 90.0)] {
            let (e, az) = (f64::to_radians(e), f64::to_radians(az));
            let dir = [e.cos() * az.cos(), e.cos() * az.sin(), e.sin()];
            let exact = a.sky_radiance(0.0, dir, sun, STEPS);
            let table = sky.radiance(dir);
            for c in 0..3 {
                worst = worst.max((table[c] - exact[c]).abs() / exact[c]);
            }
        }
        // Measured 0.5%.
        assert!(worst < 0.01, "table within {:.3}% of the model", 100.0 * worst);
    }
}
