//! The light around an object on the sea, for its diffuse and rough-specular shading: the sky
//! above and the sea below on a grid of directions, and the irradiance it gives a surface of any
//! normal, tabulated over the normal's zenith and azimuth for the GPU to interpolate.
//!
//! A step between a bright sky and a dark sea at the horizon is what a low-order projection
//! holds worst: order-2 spherical harmonics (Ramamoorthi & Hanrahan 2001) put a level surface's
//! irradiance 2-7% high from the sky alone and 13% high with the sea below, measured on the
//! physical sky with the sun at 30°. The table is the irradiance integrated exactly over the
//! grid instead, and bilinear in it is within 0.5% of the brightest irradiance (it is smooth in
//! the normal: a convolution with the clamped cosine).
//!
//! Below the horizon the sea is the environment: the sky mirrored in a level sea times its exact
//! Fresnel (model::fresnel), plus the light the sea scatters back up through the surface: the
//! paper's refracted term, the sea's albedo times the sky's irradiance over π, the same sea the
//! shading draws (glsl/brdf.glsl `sea_radiance`) and the ground truth's objects see
//! (glsl/groundtruth_objects.glsl `environment`). The paper's sea scatters no sunlight up, and an
//! object must not see a brighter sea than the eye does: at noon that would light a pier deck's
//! underside by several times the sea beneath it.

use crate::model::fresnel::fresnel_exact;
use glam::DVec3;
use std::f64::consts::PI;

/// Sea water's refractive index (model::fresnel's).
const WATER_ETA: f64 = 1.333;

/// Rows of normals' zenith angles in the irradiance table, from the zenith (row 0) to the nadir,
/// and columns of their azimuths (from +x, counter-clockwise): glsl/object.frag's.
pub const IRRADIANCE_ROWS: usize = 17;
pub const IRRADIANCE_COLUMNS: usize = 32;

/// Radiance on a grid of equal solid angles: `rows` bands of equal z (symmetric about the
/// horizon) by twice as many azimuths.
pub struct Environment {
    rows: usize,
    radiance: Vec<[f64; 3]>,
}

impl Environment {
    fn columns(&self) -> usize {
        2 * self.rows
    }

    /// The centre of cell (row, column): row 0 nearest the zenith.
    pub fn direction(rows: usize, row: usize, column: usize) -> DVec3 {
        let z = 1.0 - 2.0 * (row as f64 + 0.5) / rows as f64;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * PI * (column as f64 + 0.5) / (2 * rows) as f64;
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// The light at sea level on `rows` (even) bands: `sky` above the horizon (radiance, the
    /// sun's disc apart), evaluated once per upper cell, and the sea below it, the sky's
    /// irradiance on the level sea being `sky_irradiance`, the sea's albedo `sea_albedo`.
    pub fn sea_level(
        rows: usize,
        sky: impl Fn(DVec3) -> [f64; 3],
        sky_irradiance: [f64; 3],
        sea_albedo: [f64; 3],
    ) -> Environment {
        assert!(rows % 2 == 0, "rows symmetric about the horizon");
        let columns = 2 * rows;
        let upper: Vec<[f64; 3]> =
            (0..rows / 2 * columns).map(|i| sky(Environment::direction(rows, i / columns, i % columns))).collect();
        let mut radiance = upper.clone();
        for row in rows / 2..rows {
            // The mirror direction is the upper row as far above the horizon.
            let mirror = rows - 1 - row;
            for column in 0..columns {
                let cos = -Environment::direction(rows, row, column).z;
                let f = fresnel_exact(cos, WATER_ETA);
                let sky = upper[mirror * columns + column];
                radiance.push(std::array::from_fn(|c| f * sky[c] + (1.0 - f) * sea_albedo[c] * sky_irradiance[c] / PI));
            }
        }
        Environment { rows, radiance }
    }

    /// The radiance of `rows` bands from any function (for tests and other environments).
    pub fn from_fn(rows: usize, radiance: impl Fn(DVec3) -> [f64; 3]) -> Environment {
        let columns = 2 * rows;
        let radiance =
            (0..rows * columns).map(|i| radiance(Environment::direction(rows, i / columns, i % columns))).collect();
        Environment { rows, radiance }
    }

    /// The irradiance on a surface of unit normal `n`: the cosine-weighted sum over the grid.
    pub fn irradiance(&self, n: DVec3) -> [f64; 3] {
        let columns = self.columns();
        let weight = 4.0 * PI / (self.rows * columns) as f64;
        let mut e = [0.0; 3];
        for (i, l) in self.radiance.iter().enumerate() {
            let cos = n.dot(Environment::direction(self.rows, i / columns, i % columns));
            if cos > 0.0 {
                for c in 0..3 {
                    e[c] += l[c] * cos * weight;
                }
            }
        }
        e
    }

    /// The irradiance table: rows of normals from the zenith to the nadir, columns of azimuths,
    /// row-major, rgb and 0.
    pub fn irradiance_table(&self) -> Vec<[f32; 4]> {
        (0..IRRADIANCE_ROWS * IRRADIANCE_COLUMNS)
            .map(|i| {
                let e = self.irradiance(table_normal(i / IRRADIANCE_COLUMNS, i % IRRADIANCE_COLUMNS));
                [e[0] as f32, e[1] as f32, e[2] as f32, 0.0]
            })
            .collect()
    }
}

/// The normal at table node (row, column).
pub fn table_normal(row: usize, column: usize) -> DVec3 {
    let theta = PI * row as f64 / (IRRADIANCE_ROWS - 1) as f64;
    let phi = 2.0 * PI * column as f64 / IRRADIANCE_COLUMNS as f64;
    DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

/// Bilinear in the table at unit `n`, as glsl/object.frag reads it.
pub fn table_lookup(table: &[[f32; 4]], n: DVec3) -> [f64; 3] {
    let theta = n.z.clamp(-1.0, 1.0).acos();
    let phi = if n.x == 0.0 && n.y == 0.0 { 0.0 } else { n.y.atan2(n.x) };
    let r = theta / PI * (IRRADIANCE_ROWS - 1) as f64;
    let r0 = (r.floor() as usize).min(IRRADIANCE_ROWS - 2);
    let fr = r - r0 as f64;
    let c = (phi / (2.0 * PI)).rem_euclid(1.0) * IRRADIANCE_COLUMNS as f64;
    let c0 = (c.floor() as usize) % IRRADIANCE_COLUMNS;
    let fc = c - c.floor();
    let c1 = (c0 + 1) % IRRADIANCE_COLUMNS;
    let at = |r: usize, c: usize| table[r * IRRADIANCE_COLUMNS + c];
    std::array::from_fn(|k| {
        let top = at(r0, c0)[k] as f64 * (1.0 - fc) + at(r0, c1)[k] as f64 * fc;
        let bottom = at(r0 + 1, c0)[k] as f64 * (1.0 - fc) + at(r0 + 1, c1)[k] as f64 * fc;
        top * (1.0 - fr) + bottom * fr
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_sky_gives_pi_l_upwards_and_half_on_a_wall() {
        let sky = Environment::from_fn(48, |d| if d.z > 0.0 { [1.0; 3] } else { [0.0; 3] });
        let e = |n: DVec3| sky.irradiance(n)[0];
        assert!((e(DVec3::Z) / PI - 1.0).abs() < 1e-3, "{}", e(DVec3::Z));
        assert!(e(-DVec3::Z) == 0.0);
        assert!((e(DVec3::X) / (PI / 2.0) - 1.0).abs() < 0.01, "{}", e(DVec3::X));
    }

    #[test]
    fn the_table_is_the_irradiance_to_half_a_percent_of_the_brightest() {
        // A sky brighter towards a sun at 20 degrees, a darker sea below.
        let sun = DVec3::new(0.94, 0.0, 0.342);
        let sky = |d: DVec3| {
            let glow = 1.0 + 4.0 * d.dot(sun).max(0.0).powi(8);
            [glow * 0.6, glow * 0.8, glow]
        };
        let env = Environment::sea_level(48, sky, [3.0; 3], [0.01, 0.03, 0.05]);
        let table = env.irradiance_table();
        let brightest: [f64; 3] = std::array::from_fn(|c| table.iter().map(|e| e[c] as f64).fold(0.0, f64::max));
        // Errors against the brightest irradiance: near the nadir, where the sea's light is a
        // tenth of the sky's, the table is 2-4% of its own value off, and that is what shows.
        let mut worst: f64 = 0.0;
        for i in 0..200 {
            let (u, v) = ((i as f64 * 0.618_034) % 1.0, (i as f64 + 0.5) / 200.0);
            let (z, phi) = (1.0 - 2.0 * v, 2.0 * PI * u);
            let n = DVec3::new((1.0 - z * z).sqrt() * phi.cos(), (1.0 - z * z).sqrt() * phi.sin(), z);
            let (exact, table) = (env.irradiance(n), table_lookup(&table, n));
            for c in 0..3 {
                worst = worst.max((table[c] - exact[c]).abs() / brightest[c]);
            }
        }
        assert!(worst < 0.005, "the table within {:.3}%", 100.0 * worst);
    }

    #[test]
    fn the_sea_below_reflects_the_sky_and_scatters_its_albedo() {
        let sky = |_: DVec3| [2.0, 2.0, 2.0];
        let env = Environment::sea_level(64, sky, [2.0 * PI; 3], [0.1; 3]);
        // The cell nearest the nadir: Fresnel 2%, then the albedo's share of the sky's
        // irradiance over pi.
        let down = env.radiance[env.radiance.len() - 1][0];
        let cos = -Environment::direction(64, 63, 127).z;
        let f = fresnel_exact(cos, WATER_ETA);
        assert!((down - (f * 2.0 + (1.0 - f) * 0.1 * 2.0)).abs() < 1e-12, "{down}");
        // Just below the horizon the sea mirrors the sky almost whole.
        let grazing = env.radiance[32 * 128][0];
        assert!(grazing > 1.8, "{grazing}");
    }
}
