//! The light around an object on the sea, for its diffuse and rough-specular shading: the sky
//! above and the sea below, projected on the nine real spherical harmonics of order ≤ 2. A
//! Lambertian surface's irradiance is a convolution of that light with the clamped cosine, which
//! the first three bands hold to within about 3% (Ramamoorthi & Hanrahan, "An Efficient
//! Representation for Irradiance Environment Maps", SIGGRAPH 2001: the convolution's band
//! weights are π, 2π/3 and π/4, and the rest of the kernel's energy is under 1%).
//!
//! Below the horizon the sea is the environment: the sky mirrored in a level sea times its exact
//! Fresnel (model::fresnel), plus the light the sea scatters back up through the surface, the
//! paper's refracted term (the sea's albedo times the irradiance entering, over π).

use crate::model::fresnel::fresnel_exact;
use glam::DVec3;
use std::f64::consts::PI;

/// Sea water's refractive index (model::fresnel's).
const WATER_ETA: f64 = 1.333;

/// Nine coefficients per colour channel: Y₀₀, Y₁₋₁, Y₁₀, Y₁₁, Y₂₋₂, Y₂₋₁, Y₂₀, Y₂₁, Y₂₂.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sh9(pub [[f64; 3]; 9]);

/// The real spherical harmonics of order ≤ 2 at unit `d` (z up).
pub fn basis(d: DVec3) -> [f64; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        0.282_094_791_773_878_14,
        0.488_602_511_902_919_9 * y,
        0.488_602_511_902_919_9 * z,
        0.488_602_511_902_919_9 * x,
        1.092_548_430_592_079_2 * x * y,
        1.092_548_430_592_079_2 * y * z,
        0.315_391_565_252_520_05 * (3.0 * z * z - 1.0),
        1.092_548_430_592_079_2 * x * z,
        0.546_274_215_296_039_6 * (x * x - y * y),
    ]
}

/// The clamped cosine's weight on each band (Ramamoorthi & Hanrahan's Â_l).
const BAND_WEIGHTS: [f64; 9] =
    [PI, 2.0 * PI / 3.0, 2.0 * PI / 3.0, 2.0 * PI / 3.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0, PI / 4.0];

impl Sh9 {
    /// Projects `radiance` over the sphere by the midpoint rule on `rows` bands of equal z (equal
    /// solid angle) times `2 rows` columns.
    pub fn project(rows: usize, radiance: impl Fn(DVec3) -> [f64; 3]) -> Sh9 {
        let columns = 2 * rows;
        let weight = 4.0 * PI / (rows * columns) as f64;
        let mut sh = [[0.0; 3]; 9];
        for i in 0..rows {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / rows as f64;
            let r = (1.0 - z * z).sqrt();
            for j in 0..columns {
                let phi = 2.0 * PI * (j as f64 + 0.5) / columns as f64;
                let d = DVec3::new(r * phi.cos(), r * phi.sin(), z);
                let l = radiance(d);
                for (coefficient, y) in sh.iter_mut().zip(basis(d)) {
                    for c in 0..3 {
                        coefficient[c] += l[c] * y * weight;
                    }
                }
            }
        }
        Sh9(sh)
    }

    /// The irradiance on a surface of unit normal `n`.
    pub fn irradiance(&self, n: DVec3) -> [f64; 3] {
        let y = basis(n);
        std::array::from_fn(|c| (0..9).map(|i| BAND_WEIGHTS[i] * self.0[i][c] * y[i]).sum::<f64>().max(0.0))
    }

    /// The coefficients convolved with the clamped cosine, as a shader evaluates irradiance:
    /// E(n) = Σ c_i Y_i(n).
    pub fn irradiance_coefficients(&self) -> [[f64; 3]; 9] {
        std::array::from_fn(|i| self.0[i].map(|v| v * BAND_WEIGHTS[i]))
    }
}

/// The light at sea level: `sky` above the horizon (kcd/m², the sun's disc apart) and the sea
/// below it, under the sun at unit `sun` of irradiance `sun_irradiance` normal to it, the sky's
/// irradiance on the level sea being `sky_irradiance` (klux), the sea's albedo `sea_albedo`.
pub fn sea_level_light(
    sky: &dyn Fn(DVec3) -> [f64; 3],
    sun: DVec3,
    sun_irradiance: [f64; 3],
    sky_irradiance: [f64; 3],
    sea_albedo: [f64; 3],
) -> impl Fn(DVec3) -> [f64; 3] + '_ {
    // The irradiance entering a level sea: the sun's at its height, the sky's whole.
    let entering: [f64; 3] = std::array::from_fn(|c| sun_irradiance[c] * sun.z.max(0.0) + sky_irradiance[c]);
    move |d: DVec3| {
        if d.z >= 0.0 {
            return sky(d);
        }
        let cos = -d.z;
        let f = fresnel_exact(cos, WATER_ETA);
        let mirrored = sky(DVec3::new(d.x, d.y, cos));
        std::array::from_fn(|c| f * mirrored[c] + (1.0 - f) * sea_albedo[c] * entering[c] / PI)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_uniform_sky_gives_pi_l_upwards() {
        // A sky of uniform radiance 1 over a black ground: E = pi upwards, 0 downwards, pi / 2 on
        // a wall; order 2 holds these within Ramamoorthi & Hanrahan's few percent.
        let sh = Sh9::project(64, |d| if d.z > 0.0 { [1.0; 3] } else { [0.0; 3] });
        let e = |n: DVec3| sh.irradiance(n)[0];
        assert!((e(DVec3::Z) / PI - 1.0).abs() < 0.05, "{}", e(DVec3::Z));
        assert!(e(-DVec3::Z) < 0.05 * PI, "{}", e(-DVec3::Z));
        assert!((e(DVec3::X) / (PI / 2.0) - 1.0).abs() < 0.01, "{}", e(DVec3::X));
    }

    #[test]
    fn the_sea_below_reflects_the_sky_and_scatters_its_albedo() {
        let sky = |_: DVec3| [2.0, 2.0, 2.0];
        let light = sea_level_light(&sky, DVec3::Z, [0.0; 3], [2.0 * PI; 3], [0.1; 3]);
        // Straight down: Fresnel 2%, then the albedo's share of the sky's irradiance over pi.
        let f = fresnel_exact(1.0, WATER_ETA);
        let down = light(-DVec3::Z)[0];
        assert!((down - (f * 2.0 + (1.0 - f) * 0.1 * 2.0)).abs() < 1e-12, "{down}");
        // Grazing: the sea mirrors the sky almost whole.
        let grazing = light(DVec3::new(1.0, 0.0, -1e-3).normalize())[0];
        assert!(grazing > 1.9, "{grazing}");
    }
}
