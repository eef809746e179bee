//! Clear-sky model on the CPU in f64: Preetham, Shirley & Smits, "A Practical Analytic Model for
//! Daylight" (SIGGRAPH 1999), and the sun through the same atmosphere. The GPU evaluates the same
//! Perez formula (glsl/sky.glsl) from the coefficients computed here; `radiance` is its f64 twin.
//! Radiance in kcd/m^2 (Preetham's zenith luminance unit), irradiance in klux.

use std::f64::consts::{FRAC_PI_2, PI};

/// Sun angular radius: 0.2666 degrees (mean apparent solar radius).
pub const SUN_ANGULAR_RADIUS: f64 = 0.2666 * PI / 180.0;
/// Solar illuminance outside the atmosphere, 128 klux (the "solar illuminance constant").
pub const SOLAR_ILLUMINANCE_KLUX: f64 = 128.0;
/// Solar depression below which the sky is dark: 18 degrees (end of astronomical twilight).
const TWILIGHT_END: f64 = 18.0 * PI / 180.0;
/// Wavelengths (micrometres) standing for the linear sRGB primaries in the sun's extinction.
const RGB_WAVELENGTHS_UM: [f64; 3] = [0.65, 0.55, 0.45];

#[derive(Debug, Clone, PartialEq)]
pub struct SkyModel {
    /// Unit vector towards the sun (z up). May point below the horizon.
    pub sun_dir: [f64; 3],
    /// Perez coefficients A..E for the channels (Y, x, y).
    pub perez: [[f64; 3]; 5],
    /// Zenith (Y, x, y), Y and x, y divided by F(0, theta_s) of their channel.
    pub zenith_over_f0: [f64; 3],
    /// Overall scale of the sky (1 by day, fading to 0 through twilight).
    pub sky_scale: f64,
    /// Sun disc radiance (kcd/m^2, linear sRGB) after atmospheric extinction; 0 below the horizon.
    pub sun_radiance: [f64; 3],
}

impl SkyModel {
    pub fn new(sun_elevation_deg: f64, sun_azimuth_deg: f64, turbidity: f64) -> SkyModel {
        let elevation = sun_elevation_deg.to_radians();
        let azimuth = sun_azimuth_deg.to_radians();
        let sun_dir = [elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin()];
        // Preetham's fit holds for the sun above the horizon; below it, the sky keeps its shape at
        // theta_s = 90 degrees and fades linearly to night at the end of astronomical twilight.
        let theta_s = (FRAC_PI_2 - elevation).min(FRAC_PI_2);
        let sky_scale = if elevation >= 0.0 { 1.0 } else { (1.0 + elevation / TWILIGHT_END).max(0.0) };
        let t = turbidity;
        let perez = [
            [0.1787 * t - 1.4630, -0.0193 * t - 0.2592, -0.0167 * t - 0.2608],
            [-0.3554 * t + 0.4275, -0.0665 * t + 0.0008, -0.0950 * t + 0.0092],
            [-0.0227 * t + 5.3251, -0.0004 * t + 0.2125, -0.0079 * t + 0.2102],
            [0.1206 * t - 2.5771, -0.0641 * t - 0.8989, -0.0441 * t - 1.6537],
            [-0.0670 * t + 0.3703, -0.0033 * t + 0.0452, -0.0109 * t + 0.0529],
        ];
        let chi = (4.0 / 9.0 - t / 120.0) * (PI - 2.0 * theta_s);
        let zenith_luminance = (4.0453 * t - 4.9710) * chi.tan() - 0.2155 * t + 2.4192;
        let th = theta_s;
        let (th2, th3) = (th * th, th * th * th);
        let zx = t * t * (0.00166 * th3 - 0.00375 * th2 + 0.00209 * th)
            + t * (-0.02903 * th3 + 0.06377 * th2 - 0.03202 * th + 0.00394)
            + (0.11693 * th3 - 0.21196 * th2 + 0.06052 * th + 0.25886);
        let zy = t * t * (0.00275 * th3 - 0.00610 * th2 + 0.00317 * th)
            + t * (-0.04214 * th3 + 0.08970 * th2 - 0.04153 * th + 0.00516)
            + (0.15346 * th3 - 0.26756 * th2 + 0.06670 * th + 0.26688);
        let zenith = [zenith_luminance, zx, zy];
        let mut zenith_over_f0 = [0.0; 3];
        for (c, z) in zenith_over_f0.iter_mut().enumerate() {
            let coeff = [perez[0][c], perez[1][c], perez[2][c], perez[3][c], perez[4][c]];
            *z = zenith[c] / perez_f(coeff, 1.0, theta_s, theta_s.cos());
        }
        let sun_radiance = if elevation > -SUN_ANGULAR_RADIUS {
            sun_transmittance(elevation, turbidity).map(|tr| tr * sun_luminance_outside_atmosphere())
        } else {
            [0.0; 3]
        };
        SkyModel { sun_dir, perez, zenith_over_f0, sky_scale, sun_radiance }
    }

    /// Sky radiance towards unit direction `dir` (linear sRGB, kcd/m^2), like glsl/sky.glsl.
    pub fn radiance(&self, dir: [f64; 3]) -> [f64; 3] {
        let cos_theta = dir[2].max(0.0);
        let cos_gamma =
            (dir[0] * self.sun_dir[0] + dir[1] * self.sun_dir[1] + dir[2] * self.sun_dir[2]).clamp(-1.0, 1.0);
        let gamma = cos_gamma.acos();
        let mut yxy = [0.0; 3];
        for (c, v) in yxy.iter_mut().enumerate() {
            let coeff = [self.perez[0][c], self.perez[1][c], self.perez[2][c], self.perez[3][c], self.perez[4][c]];
            *v = self.zenith_over_f0[c] * perez_f(coeff, cos_theta, gamma, cos_gamma);
        }
        xyy_to_linear_srgb(yxy[1], yxy[2], yxy[0]).map(|v| (v * self.sky_scale).max(0.0))
    }

    /// Irradiance on a horizontal plane from the sky dome (klux per channel); the integrand is
    /// smooth, 64 x 128 cells give < 1e-3.
    pub fn sky_irradiance(&self) -> [f64; 3] {
        horizontal_irradiance(64, 128, |dir| self.radiance(dir))
    }

    /// Solid angle of the sun disc.
    pub fn sun_solid_angle() -> f64 {
        2.0 * PI * (1.0 - SUN_ANGULAR_RADIUS.cos())
    }

    /// Irradiance normal to the sun's direction (klux per channel).
    pub fn sun_irradiance(&self) -> [f64; 3] {
        self.sun_radiance.map(|l| l * Self::sun_solid_angle())
    }

    /// Slope variance per axis that the sun disc adds to a mirror's reflection: a uniform disc of
    /// angular radius a seen through a half vector spans slopes of radius a/2, variance (a/2)^2 / 4.
    pub fn sun_slope_variance() -> f64 {
        (SUN_ANGULAR_RADIUS / 2.0).powi(2) / 4.0
    }
}

/// What a sea point is lit by, as the CPU's evaluation of the methods' models reads it: Preetham's
/// sky (SkyModel) or the physical one seen from sea level (sky_table::SeaLevelSky).
pub trait SkyLight {
    /// Unit vector towards the sun (z up).
    fn sun_dir(&self) -> [f64; 3];
    /// Irradiance normal to the sun at the sea (klux).
    fn sun_irradiance(&self) -> [f64; 3];
    /// The sky's irradiance on the level sea (klux).
    fn sky_irradiance(&self) -> [f64; 3];
    /// Sky radiance towards unit `dir` (kcd/m^2), the sun disc apart.
    fn radiance(&self, dir: [f64; 3]) -> [f64; 3];
}

impl SkyLight for SkyModel {
    fn sun_dir(&self) -> [f64; 3] {
        self.sun_dir
    }
    fn sun_irradiance(&self) -> [f64; 3] {
        SkyModel::sun_irradiance(self)
    }
    fn sky_irradiance(&self) -> [f64; 3] {
        SkyModel::sky_irradiance(self)
    }
    fn radiance(&self, dir: [f64; 3]) -> [f64; 3] {
        SkyModel::radiance(self, dir)
    }
}

/// Irradiance on a horizontal plane from the radiance of the upper hemisphere, by midpoint
/// quadrature over `nu` cells in cos theta and `nphi` in phi (cos theta dOmega = mu dmu dphi).
pub fn horizontal_irradiance(nu: usize, nphi: usize, radiance: impl Fn([f64; 3]) -> [f64; 3]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for i in 0..nu {
        let mu = (i as f64 + 0.5) / nu as f64;
        let sin_t = (1.0 - mu * mu).sqrt();
        for j in 0..nphi {
            let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * PI;
            let l = radiance([sin_t * phi.cos(), sin_t * phi.sin(), mu]);
            for c in 0..3 {
                e[c] += l[c] * mu;
            }
        }
    }
    e.map(|v| v * (1.0 / nu as f64) * (2.0 * PI / nphi as f64))
}

/// Perez et al. (1993): F = (1 + A exp(B / cos theta)) (1 + C exp(D gamma) + E cos^2 gamma).
/// exp(B / cos theta) with B < 0 tends to 0 as cos theta -> 0+.
fn perez_f(c: [f64; 5], cos_theta: f64, gamma: f64, cos_gamma: f64) -> f64 {
    let horizon = if cos_theta > 0.0 { (c[1] / cos_theta).exp() } else { 0.0 };
    (1.0 + c[0] * horizon) * (1.0 + c[2] * (c[3] * gamma).exp() + c[4] * cos_gamma * cos_gamma)
}

/// CIE xyY -> linear sRGB (D65, IEC 61966-2-1).
pub fn xyy_to_linear_srgb(x: f64, y: f64, big_y: f64) -> [f64; 3] {
    let big_x = x * big_y / y;
    let big_z = (1.0 - x - y) * big_y / y;
    [
        3.2406 * big_x - 1.5372 * big_y - 0.4986 * big_z,
        -0.9689 * big_x + 1.8758 * big_y + 0.0415 * big_z,
        0.0557 * big_x - 0.2040 * big_y + 1.0570 * big_z,
    ]
}

/// Sun disc luminance outside the atmosphere: illuminance constant over the disc's solid angle.
fn sun_luminance_outside_atmosphere() -> f64 {
    SOLAR_ILLUMINANCE_KLUX / SkyModel::sun_solid_angle()
}

/// Direct-sun transmittance per channel: Rayleigh (0.008735 lambda^-4.08) and aerosol
/// (beta lambda^-1.3, beta = 0.04608 T - 0.04586) optical depths from Preetham's appendix,
/// times the Kasten & Young (1989) relative air mass.
pub fn sun_transmittance(elevation: f64, turbidity: f64) -> [f64; 3] {
    let zenith_deg = 90.0 - elevation.to_degrees().max(0.0);
    let air_mass = 1.0 / (zenith_deg.to_radians().cos() + 0.50572 * (96.07995 - zenith_deg).powf(-1.6364));
    let beta = 0.04608 * turbidity - 0.04586;
    RGB_WAVELENGTHS_UM.map(|l| {
        let tau = 0.008735 * l.powf(-4.08) + beta * l.powf(-1.3);
        (-tau * air_mass).exp()
    })
}
