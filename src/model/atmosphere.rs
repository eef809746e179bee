//! A physical clear sky, in f64: the precomputed atmospheric scattering of Bruneton & Neyret,
//! "Precomputed Atmospheric Scattering" (EGSR 2008), in the parametrization of Bruneton's 2017
//! reimplementation, with the multiple-scattering approximation of Hillaire, "A Scalable and
//! Production Ready Sky and Atmosphere Rendering Technique" (EGSR 2020). A spherical planet
//! under a layer of air (Rayleigh scattering), aerosols (Mie scattering and absorption) and ozone
//! (absorption), lit by the sun. The GPU builds the same tables (glsl/atmosphere.glsl,
//! transmittance.comp, multiple_scattering.comp) and the sky map from them; this module is the
//! reference the tests hold them to, and gives the CPU what it needs per frame (the sun's
//! radiance and the sky's irradiance at the sea). Lengths in metres; radiance in kcd/m^2 for a
//! sun of SOLAR_ILLUMINANCE_KLUX outside the atmosphere, as the rest of the renderer.

use crate::model::sky::{SkyModel, SOLAR_ILLUMINANCE_KLUX, SUN_ANGULAR_RADIUS};
use std::f64::consts::PI;

/// Earth's mean radius as Bruneton's precomputed atmosphere takes it (m): the default planet.
pub const EARTH_RADIUS_M: f64 = 6_360e3;

/// The atmosphere's parameters (scene `[sky.atmosphere]`, on the scene's planet through
/// Scene::atmosphere); Earth's by default: Bruneton (2017)'s demo values, also Hillaire (2020),
/// table 1. Coefficients per metre for the linear sRGB primaries (680, 550, 440 nm).

#[derive(Debug, Clone, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct AtmosphereParams {
    /// The planet's radius (`[planet] radius_m`, the sea's mean level): set by Scene::atmosphere,
    /// not a key of its own, so that the sea and the air share one ground.
    #[serde(skip)]
    pub bottom_radius_m: f64,
    /// bottom_radius_m + thickness_m, likewise derived.
    #[serde(skip)]
    pub top_radius_m: f64,
    /// Height of the atmosphere's top above the sea.
    pub thickness_m: f64,
    pub rayleigh_scattering_per_m: [f64; 3],
    pub rayleigh_scale_height_m: f64,
    pub mie_scattering_per_m: f64,
    pub mie_absorption_per_m: f64,
    pub mie_scale_height_m: f64,
    /// Cornette-Shanks asymmetry of the aerosols' phase function, in (-1, 1).
    pub mie_g: f64,
    /// Ozone's absorption at its peak density; the density is a tent from 0 at
    /// center -/+ width/2 to 1 at its center.
    pub ozone_absorption_per_m: [f64; 3],
    pub ozone_center_m: f64,
    pub ozone_width_m: f64,
    /// Lambertian albedo of the ground (the sea, seen from the air) in the multiple scattering.
    pub ground_albedo: f64,
}

impl Default for AtmosphereParams {
    fn default() -> Self {
        AtmosphereParams {
            bottom_radius_m: EARTH_RADIUS_M,
            top_radius_m: EARTH_RADIUS_M + 60e3,
            thickness_m: 60e3,
            rayleigh_scattering_per_m: [5.802e-6, 13.558e-6, 33.1e-6],
            rayleigh_scale_height_m: 8_000.0,
            mie_scattering_per_m: 3.996e-6,
            mie_absorption_per_m: 0.444e-6,
            mie_scale_height_m: 1_200.0,
            mie_g: 0.8,
            ozone_absorption_per_m: [0.650e-6, 1.881e-6, 0.085e-6],
            ozone_center_m: 25_000.0,
            ozone_width_m: 30_000.0,
            // The open ocean's albedo (about 0.06) and a little for foam and haze above it.
            ground_albedo: 0.1,
        }
    }
}

impl AtmosphereParams {
    /// Checks every key against its physical range: "atmosphere.KEY = V is out of range ...".
    pub fn validate(&self) -> Result<(), String> {
        let positive = |key: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("atmosphere.{key} = {v} is out of range (0, inf): it must be positive and finite"))
            }
        };
        let non_negative = |key: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(format!(
                    "atmosphere.{key} = {v} is out of range [0, 1e-3]: a coefficient is finite and not negative"
                ))
            }
        };
        positive("thickness_m", self.thickness_m)?;
        if self.thickness_m > self.bottom_radius_m {
            return Err(format!(
                "atmosphere.thickness_m = {} is out of range (0, {}]: at most the planet's radius (planet.radius_m)",
                self.thickness_m, self.bottom_radius_m
            ));
        }
        for (i, &v) in self.rayleigh_scattering_per_m.iter().enumerate() {
            non_negative(&format!("rayleigh_scattering_per_m[{i}]"), v)?;
        }
        for (i, &v) in self.ozone_absorption_per_m.iter().enumerate() {
            non_negative(&format!("ozone_absorption_per_m[{i}]"), v)?;
        }
        non_negative("mie_scattering_per_m", self.mie_scattering_per_m)?;
        non_negative("mie_absorption_per_m", self.mie_absorption_per_m)?;
        let coefficients = self.rayleigh_scattering_per_m.iter().chain(&self.ozone_absorption_per_m);
        if let Some(v) =
            coefficients.chain([&self.mie_scattering_per_m, &self.mie_absorption_per_m]).find(|v| **v > 1e-3)
        {
            return Err(format!(
                "atmosphere coefficients: {v} per metre is out of range [0, 1e-3] (air is not that thick)"
            ));
        }
        positive("rayleigh_scale_height_m", self.rayleigh_scale_height_m)?;
        positive("mie_scale_height_m", self.mie_scale_height_m)?;
        positive("ozone_width_m", self.ozone_width_m)?;
        if !(self.ozone_center_m.is_finite() && self.ozone_center_m >= 0.0) {
            return Err(format!("atmosphere.ozone_center_m = {} is out of range [0, inf)", self.ozone_center_m));
        }
        if !(self.mie_g.is_finite() && self.mie_g.abs() < 1.0) {
            return Err(format!("atmosphere.mie_g = {} is out of range (-1, 1)", self.mie_g));
        }
        if !(self.ground_albedo.is_finite() && (0.0..=1.0).contains(&self.ground_albedo)) {
            return Err(format!("atmosphere.ground_albedo = {} is out of range [0, 1]", self.ground_albedo));
        }
        Ok(())
    }

    /// Scattering and extinction coefficients at altitude `h` (m above the ground).
    pub fn coefficients(&self, h: f64) -> Coefficients {
        let rayleigh = (-h / self.rayleigh_scale_height_m).exp();
        let mie = (-h / self.mie_scale_height_m).exp();
        let ozone = (1.0 - (h - self.ozone_center_m).abs() / (0.5 * self.ozone_width_m)).max(0.0);
        let rayleigh_s = self.rayleigh_scattering_per_m.map(|b| b * rayleigh);
        let mie_s = self.mie_scattering_per_m * mie;
        let mie_t = (self.mie_scattering_per_m + self.mie_absorption_per_m) * mie;
        let extinction = std::array::from_fn(|c| rayleigh_s[c] + mie_t + self.ozone_absorption_per_m[c] * ozone);
        Coefficients { rayleigh: rayleigh_s, mie: mie_s, extinction }
    }
}

#[derive(Debug, Clone, Copy)]
pub struct Coefficients {
    pub rayleigh: [f64; 3],
    pub mie: f64,
    pub extinction: [f64; 3],
}

impl Coefficients {
    fn scattering(&self) -> [f64; 3] {
        self.rayleigh.map(|r| r + self.mie)
    }
}

/// Rayleigh's phase function, 3 / (16 pi) (1 + nu^2).
pub fn rayleigh_phase(nu: f64) -> f64 {
    3.0 / (16.0 * PI) * (1.0 + nu * nu)
}

/// Cornette & Shanks (1992): 3 / (8 pi) (1 - g^2)(1 + nu^2) / ((2 + g^2)(1 + g^2 - 2 g nu)^1.5).
/// 1 + g^2 - 2 g nu >= (1 - |g|)^2 > 0 for |g| < 1.
pub fn mie_phase(g: f64, nu: f64) -> f64 {
    let g2 = g * g;
    3.0 / (8.0 * PI) * (1.0 - g2) * (1.0 + nu * nu) / ((2.0 + g2) * (1.0 + g2 - 2.0 * g * nu).powf(1.5))
}

/// Distance from radius r along zenith cosine mu to the top of the atmosphere.
pub fn distance_to_top(p: &AtmosphereParams, r: f64, mu: f64) -> f64 {
    let disc = r * r * (mu * mu - 1.0) + p.top_radius_m * p.top_radius_m;
    (-r * mu + disc.max(0.0).sqrt()).max(0.0)
}

/// Distance to the ground, where the ray meets it (mu < 0 and below the ground's horizon).
pub fn distance_to_ground(p: &AtmosphereParams, r: f64, mu: f64) -> Option<f64> {
    let disc = r * r * (mu * mu - 1.0) + p.bottom_radius_m * p.bottom_radius_m;
    // A ray along the tangent (disc = 0) only touches the ground.
    (mu < 0.0 && disc > 0.0).then(|| (-r * mu - disc.sqrt()).max(0.0))
}

/// Transmittance from radius r along mu to the top of the atmosphere, by the trapezoid rule over
/// `steps` intervals (Bruneton 2017 uses 500; the density's scale heights are resolved from 100).
pub fn transmittance_to_top(p: &AtmosphereParams, r: f64, mu: f64, steps: usize) -> [f64; 3] {
    let d = distance_to_top(p, r, mu);
    let dx = d / steps as f64;
    let mut depth = [0.0; 3];
    for i in 0..=steps {
        let t = i as f64 * dx;
        let h = (r * r + t * t + 2.0 * r * mu * t).sqrt() - p.bottom_radius_m;
        let w = if i == 0 || i == steps { 0.5 } else { 1.0 };
        let e = p.coefficients(h).extinction;
        for c in 0..3 {
            depth[c] += w * e[c] * dx;
        }
    }
    depth.map(|tau| (-tau).exp())
}

/// Texture size of the transmittance table (mu, r), as Bruneton (2017).
pub const TRANSMITTANCE_SIZE: (usize, usize) = (256, 64);
/// Texture size of the multiple-scattering table (mu_s, r), as Hillaire (2020).
pub const MULTIPLE_SCATTERING_SIZE: usize = 32;
/// Texture size of the GPU's sky-view table (azimuth from the sun, elevation; glsl/atmosphere.glsl).
pub const SKY_VIEW_SIZE: (usize, usize) = (256, 128);
/// Texels of the sea-level sky irradiance table over the sun's zenith cosine (glsl/atmosphere.glsl).
pub const SEA_IRRADIANCE_SIZE: usize = 256;

/// x in [0, 1] to a texture coordinate that puts 0 and 1 at the centres of the end texels.
pub fn unit_to_texcoord(x: f64, size: usize) -> f64 {
    0.5 / size as f64 + x * (1.0 - 1.0 / size as f64)
}

pub fn texcoord_to_unit(u: f64, size: usize) -> f64 {
    (u - 0.5 / size as f64) / (1.0 - 1.0 / size as f64)
}

/// Bruneton (2017)'s transmittance parametrization: (r, mu) -> uv, with the distance to the top
/// mapped linearly between its extremes so that the horizon gets as many texels as the zenith.
pub fn transmittance_uv(p: &AtmosphereParams, r: f64, mu: f64) -> (f64, f64) {
    let h = (p.top_radius_m.powi(2) - p.bottom_radius_m.powi(2)).sqrt();
    let rho = (r * r - p.bottom_radius_m.powi(2)).max(0.0).sqrt();
    let d = distance_to_top(p, r, mu);
    let (d_min, d_max) = (p.top_radius_m - r, rho + h);
    let x_mu = if d_max > d_min { (d - d_min) / (d_max - d_min) } else { 0.0 };
    (unit_to_texcoord(x_mu, TRANSMITTANCE_SIZE.0), unit_to_texcoord(rho / h, TRANSMITTANCE_SIZE.1))
}

/// The inverse of transmittance_uv: the (r, mu) a texel centre stands for.
pub fn transmittance_r_mu(p: &AtmosphereParams, u: f64, v: f64) -> (f64, f64) {
    let x_mu = texcoord_to_unit(u, TRANSMITTANCE_SIZE.0);
    let x_r = texcoord_to_unit(v, TRANSMITTANCE_SIZE.1);
    let h = (p.top_radius_m.powi(2) - p.bottom_radius_m.powi(2)).sqrt();
    let rho = h * x_r;
    let r = (rho * rho + p.bottom_radius_m.powi(2)).sqrt();
    let (d_min, d_max) = (p.top_radius_m - r, rho + h);
    let d = d_min + x_mu * (d_max - d_min);
    let mu = if d == 0.0 { 1.0 } else { ((h * h - rho * rho - d * d) / (2.0 * r * d)).clamp(-1.0, 1.0) };
    (r, mu)
}

/// The tables the sky is evaluated from, in f64: what the GPU's passes build.
pub struct Atmosphere {
    pub params: AtmosphereParams,
    transmittance: Vec<[f64; 3]>,
    multiple_scattering: Vec<[f64; 3]>,
}

/// Bilinear lookup of a row-major table at texture coordinates (u, v), clamped to the edges.
fn bilinear(table: &[[f64; 3]], width: usize, height: usize, u: f64, v: f64) -> [f64; 3] {
    let x = (u * width as f64 - 0.5).clamp(0.0, (width - 1) as f64);
    let y = (v * height as f64 - 0.5).clamp(0.0, (height - 1) as f64);
    let (x0, y0) = (x.floor() as usize, y.floor() as usize);
    let (x1, y1) = ((x0 + 1).min(width - 1), (y0 + 1).min(height - 1));
    let (fx, fy) = (x - x0 as f64, y - y0 as f64);
    let at = |i: usize, j: usize| table[j * width + i];
    std::array::from_fn(|c| {
        let top = at(x0, y0)[c] * (1.0 - fx) + at(x1, y0)[c] * fx;
        let bottom = at(x0, y1)[c] * (1.0 - fx) + at(x1, y1)[c] * fx;
        top * (1.0 - fy) + bottom * fy
    })
}

/// Points along a ray of length d for a raymarch of n samples: quadratic spacing, dense near the
/// start where a ray from the ground meets the densest air (Hillaire 2020 spaces samples too).
fn march(d: f64, n: usize) -> impl Iterator<Item = (f64, f64)> {
    (0..n).map(move |i| {
        let (a, b) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
        let (ta, tb) = (d * a * a, d * b * b);
        (0.5 * (ta + tb), tb - ta)
    })
}

/// A ray from altitude `h` as the air sees it (glsl/atmosphere.glsl `air_ray`): from where it
/// enters the air, since nothing happens in space before; its radius, zenith cosine and the
/// sun's zenith cosine there, and the distance skipped to get there.
struct AirRay {
    r: f64,
    mu: f64,
    mu_s: f64,
    skipped: f64,
}

impl AirRay {
    /// From altitude `h` (the ground's air below it); None where the ray passes the air by.
    fn new(p: &AtmosphereParams, h: f64, mu: f64, mu_s: f64, nu: f64) -> Option<AirRay> {
        AirRay::at_radius(p, p.bottom_radius_m + h.max(0.0), mu, mu_s, nu)
    }

    /// From radius `r`; None where the ray passes the air by.
    fn at_radius(p: &AtmosphereParams, r: f64, mu: f64, mu_s: f64, nu: f64) -> Option<AirRay> {
        let top = p.top_radius_m;
        if r <= top {
            return Some(AirRay { r, mu, mu_s, skipped: 0.0 });
        }
        // The top sphere's near root, r^2 - R_top^2 as a product of the altitudes' difference.
        let c = (r - top) * (r + top);
        let disc = r * r * mu * mu - c;
        if mu >= 0.0 || disc <= 0.0 {
            return None;
        }
        let t = c / (-r * mu + disc.sqrt());
        let clamp = |x: f64| x.clamp(-1.0, 1.0);
        Some(AirRay { r: top, mu: clamp((r * mu + t) / top), mu_s: clamp((r * mu_s + t * nu) / top), skipped: t })
    }
}

/// Samples per sky ray: the GPU's sky map uses the same (glsl/atmosphere.glsl, SKY_STEPS).
pub const SKY_STEPS: usize = 40;
/// Directions (in each of two angles) and samples per direction of the multiple-scattering table.
pub const MS_DIRECTIONS: usize = 8;
pub const MS_STEPS: usize = 20;

impl Atmosphere {
    /// Builds the transmittance and multiple-scattering tables.
    pub fn new(params: &AtmosphereParams) -> Atmosphere {
        let (tw, th) = TRANSMITTANCE_SIZE;
        let transmittance = (0..tw * th)
            .map(|i| {
                let (u, v) = (((i % tw) as f64 + 0.5) / tw as f64, ((i / tw) as f64 + 0.5) / th as f64);
                let (r, mu) = transmittance_r_mu(params, u, v);
                transmittance_to_top(params, r, mu, 500)
            })
            .collect();
        let mut atmosphere = Atmosphere { params: params.clone(), transmittance, multiple_scattering: Vec::new() };
        let n = MULTIPLE_SCATTERING_SIZE;
        atmosphere.multiple_scattering = (0..n * n)
            .map(|i| {
                let (u, v) = (((i % n) as f64 + 0.5) / n as f64, ((i / n) as f64 + 0.5) / n as f64);
                let mu_s = 2.0 * texcoord_to_unit(u, n) - 1.0;
                let r =
                    params.bottom_radius_m + texcoord_to_unit(v, n) * (params.top_radius_m - params.bottom_radius_m);
                atmosphere.multiple_scattering_at(r, mu_s.clamp(-1.0, 1.0))
            })
            .collect();
        atmosphere
    }

    /// The transmittance table, row-major (TRANSMITTANCE_SIZE; texel centres as `transmittance_uv`).
    pub fn transmittance_table(&self) -> &[[f64; 3]] {
        &self.transmittance
    }

    /// The multiple-scattering table, row-major (MULTIPLE_SCATTERING_SIZE squared; mu_s across).
    pub fn multiple_scattering_table(&self) -> &[[f64; 3]] {
        &self.multiple_scattering
    }

    /// Transmittance to the top of the atmosphere, from the table (what a shader samples).
    pub fn transmittance(&self, r: f64, mu: f64) -> [f64; 3] {
        let (u, v) = transmittance_uv(&self.params, r, mu);
        bilinear(&self.transmittance, TRANSMITTANCE_SIZE.0, TRANSMITTANCE_SIZE.1, u, v)
    }

    /// Transmittance to the sun from radius r (0 where the planet hides the sun's centre). From
    /// above the air, the path starts where the ray enters it (glsl/atmosphere.glsl `air_ray`), and
    /// a ray that never does is clear.
    pub fn sun_transmittance(&self, r: f64, mu_s: f64) -> [f64; 3] {
        if distance_to_ground(&self.params, r, mu_s).is_some() {
            return [0.0; 3];
        }
        match AirRay::at_radius(&self.params, r, mu_s, mu_s, 1.0) {
            Some(a) => self.transmittance(a.r, a.mu),
            None => [1.0; 3],
        }
    }

    /// Transmittance between the ray's origin (r, mu) and the point at distance d along it, as a
    /// ratio of transmittances to the top (Bruneton 2017, GetTransmittance); for a ray that meets
    /// the ground, both segments are taken pointing up (the reversed ray), which stays accurate.
    pub fn transmittance_between(&self, r: f64, mu: f64, d: f64) -> [f64; 3] {
        let r_d =
            (d * d + 2.0 * r * mu * d + r * r).sqrt().clamp(self.params.bottom_radius_m, self.params.top_radius_m);
        let mu_d = ((r * mu + d) / r_d).clamp(-1.0, 1.0);
        let (a, b) = if distance_to_ground(&self.params, r, mu).is_some() {
            (self.transmittance(r_d, -mu_d), self.transmittance(r, -mu))
        } else {
            (self.transmittance(r, mu), self.transmittance(r_d, mu_d))
        };
        std::array::from_fn(|c| if b[c] > 0.0 { (a[c] / b[c]).min(1.0) } else { 0.0 })
    }

    /// Hillaire (2020)'s psi_ms at (r, mu_s): the light scattered twice or more towards a point,
    /// per unit of sun illuminance, with isotropic phase; the sum of all orders of it is the
    /// second order over (1 - f_ms), f_ms the fraction a point's surroundings send back.
    fn multiple_scattering_at(&self, r: f64, mu_s: f64) -> [f64; 3] {
        let p = &self.params;
        let sun = [(1.0 - mu_s * mu_s).max(0.0).sqrt(), 0.0, mu_s];
        let (mut second, mut transfer) = ([0.0; 3], [0.0; 3]);
        let n = MS_DIRECTIONS;
        let weight = 1.0 / (n * n) as f64; // uniform over the sphere; times 4 pi sr and the phase 1 / (4 pi)
        for i in 0..n {
            let cos_theta = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
            for j in 0..n {
                let phi = 2.0 * PI * (j as f64 + 0.5) / n as f64;
                let dir = [sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta];
                let mu = dir[2];
                let ground = distance_to_ground(p, r, mu);
                let d = ground.unwrap_or_else(|| distance_to_top(p, r, mu));
                let (mut l, mut f) = ([0.0; 3], [0.0; 3]);
                for (t, dt) in march(d, MS_STEPS) {
                    let r_t = (r * r + t * t + 2.0 * r * mu * t).sqrt();
                    let c = p.coefficients(r_t - p.bottom_radius_m);
                    let tr = self.transmittance_between(r, mu, t);
                    let mu_s_t = (r * mu_s + t * (dir[0] * sun[0] + dir[2] * sun[2])) / r_t;
                    let ts = self.sun_transmittance(r_t, mu_s_t);
                    let s = c.scattering();
                    for k in 0..3 {
                        l[k] += tr[k] * s[k] * ts[k] / (4.0 * PI) * dt;
                        f[k] += tr[k] * s[k] * dt;
                    }
                }
                if ground.is_some() {
                    let t_last = self.transmittance_between(r, mu, d);
                    // The ground at the ray's end, lit by the sun, reflecting as a Lambertian.
                    let r_g = p.bottom_radius_m;
                    let up = [dir[0] * d, dir[1] * d, r + dir[2] * d];
                    let mu_s_g = ((up[0] * sun[0] + up[2] * sun[2]) / r_g).clamp(-1.0, 1.0);
                    let ts = self.sun_transmittance(r_g, mu_s_g);
                    for k in 0..3 {
                        l[k] += t_last[k] * ts[k] * mu_s_g.max(0.0) * p.ground_albedo / PI;
                    }
                }
                for k in 0..3 {
                    second[k] += l[k] * weight;
                    transfer[k] += f[k] * weight;
                }
            }
        }
        std::array::from_fn(|k| second[k] / (1.0 - transfer[k].min(0.999)))
    }

    /// The multiple-scattering table's psi_ms at (r, mu_s).
    pub fn multiple_scattering(&self, r: f64, mu_s: f64) -> [f64; 3] {
        let n = MULTIPLE_SCATTERING_SIZE;
        let u = unit_to_texcoord(0.5 * mu_s + 0.5, n);
        let v = unit_to_texcoord(
            (r - self.params.bottom_radius_m) / (self.params.top_radius_m - self.params.bottom_radius_m),
            n,
        );
        bilinear(&self.multiple_scattering, n, n, u, v)
    }

    /// Sky radiance (kcd/m^2) seen from altitude `eye_m` towards unit `dir` (z up) with the sun
    /// towards unit `sun`: `sky_radiance_cosines` with the ray's cosines.
    pub fn sky_radiance(&self, eye_m: f64, dir: [f64; 3], sun: [f64; 3], steps: usize) -> [f64; 3] {
        let nu = dir[0] * sun[0] + dir[1] * sun[1] + dir[2] * sun[2];
        self.sky_radiance_cosines(eye_m, dir[2], sun[2], nu, steps)
    }

    /// Sky radiance (kcd/m^2) from altitude `h` along the ray of zenith cosine `mu`, under the
    /// sun of zenith cosine `mu_s`, `nu` the cosine between ray and sun: single scattering plus
    /// psi_ms along the ray, `steps` quadratically spaced samples from where the ray enters the
    /// air (black where it never does); the sun disc itself not included. A ray below the
    /// horizon ends at the ground. Only the three cosines matter (the air is spherically
    /// symmetric), so a sea point's sky is this in its own zenith's frame.
    pub fn sky_radiance_cosines(&self, h: f64, mu: f64, mu_s: f64, nu: f64, steps: usize) -> [f64; 3] {
        let p = &self.params;
        let Some(a) = AirRay::new(p, h, mu, mu_s, nu) else { return [0.0; 3] };
        let (r, mu) = (a.r, a.mu);
        let d = distance_to_ground(p, r, mu).unwrap_or_else(|| distance_to_top(p, r, mu));
        let (phase_r, phase_m) = (rayleigh_phase(nu), mie_phase(p.mie_g, nu));
        let mut l = [0.0; 3];
        for (t, dt) in march(d, steps) {
            let r_t = (r * r + t * t + 2.0 * r * mu * t).sqrt();
            let c = p.coefficients(r_t - p.bottom_radius_m);
            let tr = self.transmittance_between(r, mu, t);
            let mu_s_t = (r * a.mu_s + t * nu) / r_t;
            let ts = self.sun_transmittance(r_t, mu_s_t);
            let ms = self.multiple_scattering(r_t, mu_s_t);
            let s = c.scattering();
            for k in 0..3 {
                let single = ts[k] * (c.rayleigh[k] * phase_r + c.mie * phase_m);
                l[k] += tr[k] * (single + s[k] * ms[k]) * dt;
            }
        }
        l.map(|v| v * SOLAR_ILLUMINANCE_KLUX)
    }

    /// The aerial perspective over the first `d` metres of a ray from altitude `h` (cosines as
    /// `sky_radiance_cosines`): the light the air scatters towards the ray's origin (kcd/m^2) and
    /// the transmittance over the path, by `steps` equal midpoint samples from where the ray
    /// enters the air, the optical depth integrated along the same samples (not a ratio of
    /// table values, which loses digits on paths that meet the ground). Altitudes below the
    /// ground (a path to a wave's trough) are held at the ground's air. The ground truth's
    /// (glsl/groundtruth_sky.glsl, truth_aerial) twin.
    pub fn aerial_perspective(
        &self,
        h: f64,
        (mu, mu_s, nu): (f64, f64, f64),
        d: f64,
        steps: usize,
    ) -> ([f64; 3], [f64; 3]) {
        let p = &self.params;
        let Some(a) = AirRay::new(p, h, mu, mu_s, nu) else { return ([0.0; 3], [1.0; 3]) };
        let length = (d - a.skipped).max(0.0);
        let (phase_r, phase_m) = (rayleigh_phase(nu), mie_phase(p.mie_g, nu));
        let dt = length / steps as f64;
        let (mut l, mut depth) = ([0.0; 3], [0.0; 3]);
        for i in 0..steps {
            let t = (i as f64 + 0.5) * dt;
            let r_t = (a.r * a.r + t * t + 2.0 * a.r * a.mu * t).sqrt().max(p.bottom_radius_m);
            let c = p.coefficients(r_t - p.bottom_radius_m);
            let mu_s_t = ((a.r * a.mu_s + t * nu) / r_t).clamp(-1.0, 1.0);
            let ts = self.sun_transmittance(r_t, mu_s_t);
            let ms = self.multiple_scattering(r_t, mu_s_t);
            let s = c.scattering();
            for k in 0..3 {
                // The transmittance to the sample's midpoint: the depth so far and half its own.
                let tr = (-(depth[k] + 0.5 * c.extinction[k] * dt)).exp();
                let single = ts[k] * (c.rayleigh[k] * phase_r + c.mie * phase_m);
                l[k] += tr * (single + s[k] * ms[k]) * dt;
                depth[k] += c.extinction[k] * dt;
            }
        }
        (l.map(|v| v * SOLAR_ILLUMINANCE_KLUX), depth.map(|tau| (-tau).exp()))
    }

    /// Radiance of the sun disc's centre at altitude `eye_m` (kcd/m^2) for a sun at zenith cosine
    /// mu_s: the disc's mean outside the atmosphere, over the limb darkening's mean, times the
    /// transmittance (0 once the planet hides the disc's centre).
    pub fn sun_radiance(&self, eye_m: f64, mu_s: f64) -> [f64; 3] {
        let r = self.params.bottom_radius_m + eye_m.max(0.0);
        let mean = SOLAR_ILLUMINANCE_KLUX / SkyModel::sun_solid_angle();
        self.sun_transmittance(r, mu_s).map(|t| t * mean)
    }

    /// Irradiance on a horizontal plane at altitude `eye_m` from the sky dome (klux), over the
    /// table-based radiance (16 x 32 cells: the sky's raymarches are the cost).
    pub fn sky_irradiance(&self, eye_m: f64, sun: [f64; 3]) -> [f64; 3] {
        crate::model::sky::horizontal_irradiance(16, 32, |dir| self.sky_radiance(eye_m, dir, sun, SKY_STEPS))
    }
}

/// The tables for `params`, built once per set of parameters in a process (about 0.3 s) and
/// shared: frames under the same atmosphere reuse them.
pub fn shared(params: &AtmosphereParams) -> std::sync::Arc<Atmosphere> {
    use std::sync::{Arc, Mutex};
    static CACHE: Mutex<Option<Arc<Atmosphere>>> = Mutex::new(None);
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    match cache.as_ref() {
        Some(a) if a.params == *params => a.clone(),
        _ => {
            let a = Arc::new(Atmosphere::new(params));
            *cache = Some(a.clone());
            a
        }
    }
}

/// What the shaders need from the physical sky for one sun and eye: the sun disc's mean radiance
/// and the sky's irradiance at the sea (kcd/m^2, klux), kept for the last sun and eye asked.
pub fn sun_and_sky(params: &AtmosphereParams, eye_m: f64, sun: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    use std::sync::Mutex;
    type Key = (AtmosphereParams, [u64; 4]);
    type SunAndSky = ([f64; 3], [f64; 3]);
    static LAST: Mutex<Option<(Key, SunAndSky)>> = Mutex::new(None);
    let key = (params.clone(), [eye_m.to_bits(), sun[0].to_bits(), sun[1].to_bits(), sun[2].to_bits()]);
    let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((k, v)) = last.as_ref() {
        if *k == key {
            return *v;
        }
    }
    let a = shared(params);
    let value = (a.sun_radiance(eye_m, sun[2]), a.sky_irradiance(eye_m, sun));
    *last = Some((key, value));
    value
}

/// The sea-level light table's lowest sun zenith cosine, sin(-18 degrees): astronomical twilight's
/// end, below which the sky is dark (glsl/atmosphere.glsl SEA_IRRADIANCE_MU_MIN).
pub const SEA_IRRADIANCE_MU_MIN: f64 = -0.309017;

/// The sea-level light table (glsl/sea_irradiance.comp: SEA_IRRADIANCE_SIZE nodes over the sun's
/// zenith cosine from SEA_IRRADIANCE_MU_MIN to 1) as the GPU's linear lookup reads it at `mu_s`,
/// from this model: the sky's irradiance on level sea and the sun's irradiance normal to it (klux).
/// Kept for the last atmosphere and cosine asked.
pub fn sea_light_table(params: &AtmosphereParams, mu_s: f64) -> ([f64; 3], [f64; 3]) {
    use std::sync::Mutex;
    type Key = (AtmosphereParams, u64);
    type SkyAndSun = ([f64; 3], [f64; 3]);
    static LAST: Mutex<Option<(Key, SkyAndSun)>> = Mutex::new(None);
    let key = (params.clone(), mu_s.to_bits());
    let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((k, v)) = last.as_ref() {
        if *k == key {
            return *v;
        }
    }
    let a = shared(params);
    let n = SEA_IRRADIANCE_SIZE - 1;
    let x = ((mu_s - SEA_IRRADIANCE_MU_MIN) / (1.0 - SEA_IRRADIANCE_MU_MIN)).clamp(0.0, 1.0) * n as f64;
    let i = (x.floor() as usize).min(n - 1);
    let f = x - i as f64;
    let node = |i: usize| {
        let mu = SEA_IRRADIANCE_MU_MIN + i as f64 / n as f64 * (1.0 - SEA_IRRADIANCE_MU_MIN);
        let sun = [(1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu];
        let sun_irradiance = a.sun_transmittance(params.bottom_radius_m, mu).map(|t| t * SOLAR_ILLUMINANCE_KLUX);
        (a.sky_irradiance(0.0, sun), sun_irradiance)
    };
    let ((sky0, sun0), (sky1, sun1)) = (node(i), node(i + 1));
    let lerp = |a: [f64; 3], b: [f64; 3]| std::array::from_fn(|c| a[c] + f * (b[c] - a[c]));
    let value = (lerp(sky0, sky1), lerp(sun0, sun1));
    *last = Some((key, value));
    value
}

/// Limb darkening of the sun disc: I(m) / I(centre) = 1 - u (1 - m), m the cosine at the disc's
/// surface (sqrt(1 - (angle / radius)^2)), u = 0.6 in the visible (a linear law of the fits in
/// Cox, Allen's Astrophysical Quantities, 2000). The disc's mean is 1 - u / 3 of its centre.
pub const LIMB_DARKENING_U: f64 = 0.6;

pub fn limb_darkening(angle: f64) -> f64 {
    let x = (angle / SUN_ANGULAR_RADIUS).min(1.0);
    let m = (1.0 - x * x).max(0.0).sqrt();
    (1.0 - LIMB_DARKENING_U * (1.0 - m)) / (1.0 - LIMB_DARKENING_U / 3.0)
}
