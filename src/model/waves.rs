//! Wave trains on the CPU, in f64: wavelengths, directions, amplitudes from a wind spectrum,
//! total slope variances and the mean-height offset. Deterministic from the scene's seed.

use crate::model::scene::Scene;
use glam::{DVec2, DVec3};
use std::f64::consts::{PI, TAU};

/// Standard gravity (m/s^2).
pub const G: f64 = 9.81;
/// Pierson-Moskowitz constants (Pierson & Moskowitz 1964): alpha (Phillips) and beta.
const PM_ALPHA: f64 = 8.1e-3;
const PM_BETA: f64 = 0.74;
/// Directional spread narrowing for long waves: angle / (1 + 40 (omega0/omega)^4) (authors' demo).
const SPREAD_NARROWING: f64 = 40.0;

/// One trochoid train. Directions are unit vectors in the world frame (x east, y north).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Train {
    pub wavelength: f64,
    pub k: f64,
    pub direction: [f64; 2],
    /// Angle from the wind direction (rad).
    pub angle_from_wind: f64,
    pub amplitude: f64,
    pub omega: f64,
    /// Initial phase (rad); phase(x, t) = omega t - k.x + phase0.
    pub phase0: f64,
}

impl Train {
    /// Phase at the origin and time t, reduced to [0, 2 pi) in f64 so f32 shaders keep precision.
    pub fn phase_at(&self, t: f64) -> f64 {
        (self.omega * t + self.phase0).rem_euclid(TAU)
    }

    /// This train's slope variance along and across the wind: (cos^2, sin^2) (1 - sqrt(1 - (k h)^2)).
    pub fn slope_variance(&self) -> [f64; 2] {
        let v = trochoid_slope_variance((self.k * self.amplitude).powi(2));
        let (s, c) = self.angle_from_wind.sin_cos();
        [c * c * v, s * s * v]
    }

    /// This train's curvature power (1/m^2), as a sinusoid's: its curvature k (k h) along the
    /// train has variance (k^2 h)^2 / 2 (the glints' facet scale, glsl/glints.glsl;
    /// glsl/waves.glsl adds the same in its loop).
    pub fn curvature_power(&self) -> f64 {
        0.5 * (self.k * self.k * self.amplitude).powi(2)
    }
}

/// Adds a train's share of the surface's tangents d p / d x (tx) and d p / d y (ty): d/dx of
/// (dir h sin(theta), h cos(theta)) with d theta / dx = -k dir, from the train's slope k h (at
/// its weight) times the cosine and sine of its phase (glsl/waves.glsl add_tangents).
pub fn add_tangents(tx: &mut DVec3, ty: &mut DVec3, dir: DVec2, slope_cos: f64, slope_sin: f64) {
    *tx += DVec3::new(-dir.x * dir.x * slope_cos, -dir.y * dir.x * slope_cos, dir.x * slope_sin);
    *ty += DVec3::new(-dir.x * dir.y * slope_cos, -dir.y * dir.y * slope_cos, dir.y * slope_sin);
}

/// 1 - sqrt(1 - a^2) in the cancellation-free form a^2 / (1 + sqrt(1 - a^2)), for 0 <= a <= 1,
/// from a2 = a^2 (glsl/waves.glsl trochoid_slope_variance takes the same: a weighted train's
/// unresolved amplitude is at hand only as its square).
pub fn trochoid_slope_variance(a2: f64) -> f64 {
    a2 / (1.0 + (1.0 - a2).max(0.0).sqrt())
}

#[derive(Debug, Clone, PartialEq)]
pub struct WaveSet {
    /// Sorted by increasing wavelength.
    pub trains: Vec<Train>,
    pub wind_direction: [f64; 2],
    /// Total slope variance along and across the wind.
    pub sigma2: [f64; 2],
    /// Mean height of the trochoid surface below the rest plane: sum k h^2 / 2.
    pub mean_height_offset: f64,
    /// The highest crest the frame's wave packets add at any one place (m; 0 without them, as
    /// `generate` leaves it): render::packets sets it for a frame.
    pub packet_crest_m: f64,
    /// The longest of the frame's wave packets (m; 0 without them), set with packet_crest_m.
    pub packet_longest_m: f64,
}

/// Pierson-Moskowitz spectrum S(omega) for wind speed u (m^2 s).
pub fn pierson_moskowitz(omega: f64, wind_speed: f64) -> f64 {
    if wind_speed <= 0.0 || omega <= 0.0 {
        return 0.0; // no wind, no waves: the limit of exp(-beta (g/(U w))^4)
    }
    let omega0 = G / wind_speed;
    PM_ALPHA * G * G / omega.powi(5) * (-PM_BETA * (omega0 / omega).powi(4)).exp()
}

/// Angular frequency of the Pierson-Moskowitz spectrum's peak: dS/domega = 0 at
/// omega_p^4 = (4 beta / 5) (g/U)^4, so omega_p = 0.877 g/U (zero without wind).
pub fn peak_omega(wind_speed: f64) -> f64 {
    (4.0 * PM_BETA / 5.0).powf(0.25) * G / wind_speed.max(0.0)
}

/// Wavelength at the spectrum's peak, by the deep-water dispersion omega^2 = g k: 2 pi g / omega_p^2
/// (83 m at 10 m/s, 333 m at 20 m/s). Longer waves hold exp(-5/4) = 29% of the height variance
/// (the cumulative spectrum is exp(-beta (g/(U omega))^4)) but little of the slope variance.
pub fn peak_wavelength(wind_speed: f64) -> f64 {
    TAU * G / peak_omega(wind_speed).powi(2)
}

/// Integral of S over [lo, hi] by composite Simpson's rule in log(omega), where S is smooth.
fn band_energy(lo: f64, hi: f64, wind_speed: f64) -> f64 {
    const STEPS: usize = 64;
    let (a, b) = (lo.ln(), hi.ln());
    let dx = (b - a) / STEPS as f64;
    let f = |x: f64| {
        let w = x.exp();
        pierson_moskowitz(w, wind_speed) * w
    };
    let mut sum = f(a) + f(b);
    for i in 1..STEPS {
        sum += f(a + i as f64 * dx) * if i % 2 == 1 { 4.0 } else { 2.0 };
    }
    sum * dx / 3.0
}

/// splitmix64 (Steele, Lea & Flood 2014): a small, well-mixed deterministic generator.
struct SplitMix64(u64);
impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The wave vector of wavelength `lambda` (m) along `angle` (rad), moved to the nearest one whose
/// components in turns per metre are binary16 values: the shaders read a train's wave vector as
/// two halves of one word (one gather less per train and pixel on CPU drivers), and every f64
/// evaluation then sees exactly the waves the GPU draws. The move is below 2^-11 relative (the
/// half's precision) for a normal half; a component below the smallest normal half (2^-14 turns
/// per metre) goes to 0 or to it instead, since a device may flush half subnormals to zero when
/// it unpacks them. That turns the direction of a train within 2^-14 turns/m of an axis onto the
/// axis or away from it by at most that much: under 0.4 degrees up to 100 m waves, a few degrees
/// for kilometre waves (a random draw either way). Returns the wavelength and direction.
pub fn binary16_wave_vector(lambda: f64, angle: f64) -> (f64, f64) {
    const SMALLEST_NORMAL: f64 = 1.0 / 16384.0; // 2^-14
    let snap = |v: f64| {
        if v.abs() >= SMALLEST_NORMAL {
            half::f16::from_f64(v).to_f64()
        } else if v.abs() >= SMALLEST_NORMAL / 2.0 {
            SMALLEST_NORMAL.copysign(v)
        } else {
            0.0
        }
    };
    let (kx, ky) = (snap(angle.cos() / lambda), snap(angle.sin() / lambda));
    (1.0 / kx.hypot(ky), ky.atan2(kx))
}

fn omega_of_wavelength(lambda: f64) -> f64 {
    (G * TAU / lambda).sqrt()
}

pub fn generate(scene: &Scene) -> WaveSet {
    let w = &scene.waves;
    let n = w.count as usize;
    let wind_angle = scene.wind.direction_deg.to_radians();
    let wind_direction = [wind_angle.cos(), wind_angle.sin()];
    let wind_speed = scene.wind.speed_mps;
    let omega0 = if wind_speed > 0.0 { G / wind_speed } else { 0.0 };
    let (log_min, log_max) = (w.lambda_min_m.log2(), scene.lambda_max_m().log2());
    let wavelength = |x: f64| 2f64.powf((1.0 - x) * log_min + x * log_max);
    let position = |i: f64| if n > 1 { i / (n - 1) as f64 } else { 1.0 };
    let mut rng = SplitMix64(w.seed);

    let mut trains = Vec::with_capacity(n);
    for i in 0..n {
        let nominal = wavelength(position(i as f64));
        // The band this train stands for: half a step either side on the geometric progression.
        let (lambda_hi, lambda_lo) = (wavelength(position(i as f64 - 0.5)), wavelength(position(i as f64 + 0.5)));
        let (omega_lo, omega_hi) =
            (omega_of_wavelength(lambda_lo.max(lambda_hi)), omega_of_wavelength(lambda_lo.min(lambda_hi)));
        let energy = band_energy(omega_lo, omega_hi, wind_speed);
        let spread = (rng.next_f64() * 2.0 - 1.0) * PI / 2.0;
        let narrowing = 1.0 + SPREAD_NARROWING * (omega0 / omega_of_wavelength(nominal)).powi(4);
        let (lambda, angle) = binary16_wave_vector(nominal, wind_angle + spread / narrowing);
        let angle_from_wind = (angle - wind_angle + PI).rem_euclid(TAU) - PI;
        let k = TAU / lambda;
        let omega = omega_of_wavelength(lambda);
        // A sinusoid of amplitude h carries variance h^2 / 2; clamp k h <= 1 so no trochoid loops.
        let amplitude = (2.0 * energy).sqrt().min(1.0 / k);
        // The world frame's origin is the eye: a train's phase there is its phase at (x_m, y_m).
        let eye = [scene.camera.x_m, scene.camera.y_m];
        let phase0 = (rng.next_f64() * TAU - k * (angle.cos() * eye[0] + angle.sin() * eye[1])).rem_euclid(TAU);
        trains.push(Train {
            wavelength: lambda,
            k,
            direction: [angle.cos(), angle.sin()],
            angle_from_wind,
            amplitude,
            omega,
            phase0,
        });
    }
    trains.sort_by(|a, b| a.wavelength.total_cmp(&b.wavelength));
    let sigma2 = trains.iter().fold([0.0; 2], |acc, t| {
        let v = t.slope_variance();
        [acc[0] + v[0], acc[1] + v[1]]
    });
    let mean_height_offset = trains.iter().map(|t| t.k * t.amplitude * t.amplitude / 2.0).sum();
    WaveSet { trains, wind_direction, sigma2, mean_height_offset, packet_crest_m: 0.0, packet_longest_m: 0.0 }
}

/// Cox & Munk (1954), clean sea: total slope variance 0.003 + 5.12e-3 U (U in m/s at 12.5 m).
pub fn cox_munk_total_variance(wind_speed: f64) -> f64 {
    0.003 + 5.12e-3 * wind_speed
}

impl WaveSet {
    /// The share of the sea's slope variance in the trains longer than `lambda_cut` (m), the ones
    /// a pixel whose cut it is can resolve into its normal at all (glsl/shade.glsl
    /// resolvable_slope_share: the shader sums the same trains' variance from its prefix table).
    pub fn resolvable_slope_share(&self, lambda_cut: f64) -> f64 {
        let unresolved: f64 = self
            .trains
            .iter()
            .filter(|t| t.wavelength <= lambda_cut)
            .map(|t| trochoid_slope_variance((t.k * t.amplitude).powi(2)))
            .sum();
        let total = self.sigma2[0] + self.sigma2[1];
        if total > 0.0 {
            (1.0 - unresolved / total).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    /// The longest wave of the trains and the frame's packets (m; 0 without either): what any
    /// scale may resolve first.
    pub fn longest_wavelength(&self) -> f64 {
        self.trains.last().map_or(0.0, |t| t.wavelength).max(self.packet_longest_m)
    }

    /// The summed amplitude, with the packets' crest: no point of the surface rises higher above
    /// its rest plane (or sinks lower below it), whatever the phases.
    pub fn highest_crest(&self) -> f64 {
        self.trains_highest_crest() + self.packet_crest_m
    }

    /// `highest_crest` of the trains alone: the surface's where no packet reaches.
    pub fn trains_highest_crest(&self) -> f64 {
        self.trains.iter().map(|t| t.amplitude).sum()
    }

    /// Height above mean sea level of the water directly below the origin (the eye) at time t.
    pub fn water_height_at_origin(&self, t: f64) -> f64 {
        self.water_under([0.0, 0.0], t).1
    }

    /// The rest position whose displaced point lies over `p` (m, from the eye) at time t, and
    /// the water's height there above mean sea level: x + D_xy(x) = p by Newton's method in f64
    /// over every train, then the rest plane's offset plus D_z(x).
    pub fn water_under(&self, p: [f64; 2], t: f64) -> ([f64; 2], f64) {
        let mut x = p;
        let mut height = 0.0;
        for _ in 0..32 {
            let (mut f, mut jac, mut dz) = ([x[0] - p[0], x[1] - p[1]], [[1.0, 0.0], [0.0, 1.0]], 0.0);
            for tr in &self.trains {
                let (d, k) = (tr.direction, tr.k);
                let (s, c) = (tr.phase_at(t) - k * (d[0] * x[0] + d[1] * x[1])).sin_cos();
                let h = tr.amplitude;
                f[0] += d[0] * h * s;
                f[1] += d[1] * h * s;
                dz += h * c;
                for (r, row) in jac.iter_mut().enumerate() {
                    for (col, entry) in row.iter_mut().enumerate() {
                        *entry -= h * c * k * d[r] * d[col];
                    }
                }
            }
            height = self.mean_height_offset + dz;
            if f[0].hypot(f[1]) < 1e-9 {
                break;
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            // Where the surface folds, Newton has no direction: step by the residual instead.
            let step = if det > 0.0 {
                [(jac[1][1] * f[0] - jac[0][1] * f[1]) / det, (jac[0][0] * f[1] - jac[1][0] * f[0]) / det]
            } else {
                f
            };
            x = [x[0] - step[0], x[1] - step[1]];
        }
        (x, height)
    }
}
