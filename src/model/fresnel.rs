//! Fresnel reflectance of sea water, exact (unpolarized, air into water) and averaged over the
//! facets a view sees on Gaussian slopes, the average the sky and refracted terms need.
//!
//! The paper fits that average with Schlick's approximation inside a closed form; against the
//! exact average over the visible slopes (below) the fit is 10-16% high towards the horizon
//! (cos_v < 0.05, sigma 0.05-0.2), where (1 - F) is then up to 30% low: the far field's sky
//! excess and refracted deficit in docs/results.md. The full method reads a table of the exact
//! average instead (`MeanFresnelTable`, glsl/slopes.glsl), and the exact Fresnel at the sun's
//! half vector where the paper uses Schlick's.

use std::sync::OnceLock;

/// Refractive index of sea water for visible light (about 1.34; 1.333 for pure water at 20 C).
pub const SEA_WATER_IOR: f64 = 1.34;

/// Unpolarized Fresnel reflectance from air into a medium of index `eta` at cos(incidence) `c`
/// (the mean of the s and p reflectances). Both denominators are at least eta cos_t >= 0, and zero
/// only at grazing (c = 0, cos_t = 0 needs eta <= 1), where the limit 1 is returned.
pub fn fresnel_exact(c: f64, eta: f64) -> f64 {
    let c = c.clamp(0.0, 1.0);
    let cos_t = (1.0 - (1.0 - c * c) / (eta * eta)).max(0.0).sqrt();
    let (s_den, p_den) = (c + eta * cos_t, eta * c + cos_t);
    if s_den <= 0.0 || p_den <= 0.0 {
        return 1.0;
    }
    let rs = (c - eta * cos_t) / s_den;
    let rp = (eta * c - cos_t) / p_den;
    0.5 * (rs * rs + rp * rp)
}

/// Whitened slopes beyond this many standard deviations carry under 1e-14 of the weight.
const SLOPE_RANGE: f64 = 8.0;
/// Intervals along the view's azimuth (Simpson) and across it (trapezoid over the half range: the
/// integrand is even and smooth there, where the trapezoid converges faster than any power).
const ALONG_INTERVALS: usize = 256;
const ACROSS_INTERVALS: usize = 16;

/// The exact Fresnel averaged over the facets seen from a view at cos(theta_v) = `cos_v` above
/// Gaussian slopes of standard deviation `sigma_v` (isotropic), each facet weighted by its
/// projected area towards the eye, (v_z - zeta . v_xy)^+ per unit horizontal area (the weight
/// glsl/slopes.glsl's visible slopes use; Smith's masking does not depend on the facet, so it
/// cancels from the average). In whitened slopes x along the view's azimuth and y across it, the
/// facet's cos(incidence) is (c - sigma s x) / sqrt(1 + sigma^2 (x^2 + y^2)), s = sin(theta_v):
/// the trapezoid over y in [0, 8] and composite Simpson over x from -8 up to the weight's zero
/// c / (sigma s), where the integrand vanishes linearly, so the rule keeps its order at the cut.
pub fn visible_mean_fresnel(cos_v: f64, sigma_v: f64, eta: f64) -> f64 {
    let c = cos_v.clamp(0.0, 1.0);
    let s = (1.0 - c * c).sqrt();
    if sigma_v <= 0.0 {
        return fresnel_exact(c, eta);
    }
    let cut = if s > 0.0 { (c / (sigma_v * s)).min(SLOPE_RANGE) } else { SLOPE_RANGE };
    let simpson = |i: usize, n: usize| {
        if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        }
    };
    let (dx, dy) = ((cut + SLOPE_RANGE) / ALONG_INTERVALS as f64, SLOPE_RANGE / ACROSS_INTERVALS as f64);
    // The Gaussian factors apart, the one across with its trapezoid weight: one exp per node.
    let across: [(f64, f64); ACROSS_INTERVALS + 1] = std::array::from_fn(|j| {
        let y = j as f64 * dy;
        let end = if j == 0 || j == ACROSS_INTERVALS { 0.5 } else { 1.0 };
        (y * y, end * (-0.5 * y * y).exp())
    });
    let (mut weighted, mut total) = (0.0, 0.0);
    for i in 0..=ALONG_INTERVALS {
        let x = -SLOPE_RANGE + i as f64 * dx;
        let ramp = (c - sigma_v * s * x).max(0.0);
        if ramp == 0.0 {
            continue;
        }
        let along = simpson(i, ALONG_INTERVALS) * ramp * (-0.5 * x * x).exp();
        for &(y2, across_weight) in &across {
            let w = along * across_weight;
            let cos_i = ramp / (1.0 + sigma_v * sigma_v * (x * x + y2)).sqrt();
            weighted += w * fresnel_exact(cos_i, eta);
            total += w;
        }
    }
    // total > 0: the x = -8 node always has a positive ramp (c + 8 sigma s > 0 unless c = s = 0).
    if total > 0.0 {
        weighted / total
    } else {
        fresnel_exact(c, eta)
    }
}

/// `visible_mean_fresnel` tabulated for the shaders: COS_SIZE x SIGMA_SIZE values at
/// cos_v = u^2 and sigma_v = SIGMA_MAX t^2 for u, t on uniform grids over [0, 1] (both squares put
/// the nodes where the average bends fastest: grazing views, smooth seas). Bilinear between nodes
/// is within 0.35% of the quadrature everywhere (tests/numerics.rs), the quadrature itself within
/// 1e-6 of an independent midpoint rule on a finer grid.
pub struct MeanFresnelTable {
    /// Row-major by sigma: values[j * COS_SIZE + i].
    pub values: Vec<f32>,
    pub eta: f64,
}

impl MeanFresnelTable {
    pub const COS_SIZE: usize = 64;
    pub const SIGMA_SIZE: usize = 32;
    /// Slopes beyond a standard deviation of 1 (45 degrees) are outside any wind sea's spectrum
    /// (Cox-Munk give 0.3 at 20 m/s); lookups clamp there.
    pub const SIGMA_MAX: f64 = 1.0;

    /// The table for sea water, built once per process (2048 quadratures, 9 10^6 Fresnel
    /// evaluations).
    pub fn sea_water() -> &'static MeanFresnelTable {
        static TABLE: OnceLock<MeanFresnelTable> = OnceLock::new();
        TABLE.get_or_init(|| MeanFresnelTable::new(SEA_WATER_IOR))
    }

    /// Every process builds the table once, at start-up: its rows are shared out among the
    /// cores (each node is its own quadrature, so the values do not depend on the split).
    pub fn new(eta: f64) -> MeanFresnelTable {
        let mut values = vec![0.0f32; Self::COS_SIZE * Self::SIGMA_SIZE];
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).min(Self::SIGMA_SIZE);
        let rows_per_thread = Self::SIGMA_SIZE.div_ceil(threads);
        std::thread::scope(|scope| {
            for (chunk, rows) in values.chunks_mut(rows_per_thread * Self::COS_SIZE).enumerate() {
                scope.spawn(move || {
                    for (k, value) in rows.iter_mut().enumerate() {
                        let (j, i) = (chunk * rows_per_thread + k / Self::COS_SIZE, k % Self::COS_SIZE);
                        let t = j as f64 / (Self::SIGMA_SIZE - 1) as f64;
                        let u = i as f64 / (Self::COS_SIZE - 1) as f64;
                        *value = visible_mean_fresnel(u * u, Self::SIGMA_MAX * t * t, eta) as f32;
                    }
                });
            }
        });
        MeanFresnelTable { values, eta }
    }

    /// Bilinear lookup as glsl/slopes.glsl does it (in f64), for tests and the CPU mirror.
    pub fn lookup(&self, cos_v: f64, sigma_v: f64) -> f64 {
        let u = cos_v.clamp(0.0, 1.0).sqrt() * (Self::COS_SIZE - 1) as f64;
        let t = (sigma_v.max(0.0) / Self::SIGMA_MAX).min(1.0).sqrt() * (Self::SIGMA_SIZE - 1) as f64;
        let (i, j) = ((u as usize).min(Self::COS_SIZE - 2), (t as usize).min(Self::SIGMA_SIZE - 2));
        let (fu, ft) = (u - i as f64, t - j as f64);
        let at = |i: usize, j: usize| self.values[j * Self::COS_SIZE + i] as f64;
        let low = at(i, j) * (1.0 - fu) + at(i + 1, j) * fu;
        let high = at(i, j + 1) * (1.0 - fu) + at(i + 1, j + 1) * fu;
        low * (1.0 - ft) + high * ft
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_fresnel_at_its_limits() {
        // Normal incidence: ((eta - 1) / (eta + 1))^2; grazing: total reflection.
        let r0 = ((SEA_WATER_IOR - 1.0) / (SEA_WATER_IOR + 1.0)).powi(2);
        assert!((fresnel_exact(1.0, SEA_WATER_IOR) - r0).abs() < 1e-15);
        assert!((fresnel_exact(0.0, SEA_WATER_IOR) - 1.0).abs() < 1e-15);
        // Brewster's angle: tan = eta, where p vanishes and F = rs^2 / 2.
        let brewster = (1.0 / (1.0 + SEA_WATER_IOR * SEA_WATER_IOR)).sqrt();
        let cos_t = (1.0 - (1.0 - brewster * brewster) / SEA_WATER_IOR.powi(2)).sqrt();
        let rs = (brewster - SEA_WATER_IOR * cos_t) / (brewster + SEA_WATER_IOR * cos_t);
        assert!((fresnel_exact(brewster, SEA_WATER_IOR) - 0.5 * rs * rs).abs() < 1e-15);
    }

    #[test]
    fn the_visible_average_converges_and_meets_its_limits() {
        for &(c, sigma) in &[(0.01, 0.05), (0.02, 0.1), (0.2, 0.15), (0.5, 0.3), (0.9, 0.02), (0.001, 0.6)] {
            let f = visible_mean_fresnel(c, sigma, SEA_WATER_IOR);
            // Against an independent midpoint rule on a much finer grid.
            let fine = fine_quadrature(c, sigma);
            assert!((f - fine).abs() < 1e-6, "cos {c} sigma {sigma}: {f} against {fine}");
        }
        // No slopes: the exact Fresnel itself; a tiny spread moves it continuously.
        for &c in &[0.0, 0.05, 0.3, 1.0] {
            let f0 = fresnel_exact(c, SEA_WATER_IOR);
            assert_eq!(visible_mean_fresnel(c, 0.0, SEA_WATER_IOR), f0);
            assert!((visible_mean_fresnel(c, 1e-4, SEA_WATER_IOR) - f0).abs() < 2e-3);
        }
    }

    /// An independent midpoint rule over the whole plane where the weight is positive.
    fn fine_quadrature(c: f64, sigma: f64) -> f64 {
        let s = (1.0 - c * c).sqrt();
        let cut = if s > 0.0 { (c / (sigma * s)).min(8.0) } else { 8.0 };
        let (n, m) = (4096, 256);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..n {
            let x = -8.0 + (i as f64 + 0.5) * (cut + 8.0) / n as f64;
            let ramp = (c - sigma * s * x).max(0.0);
            for j in 0..m {
                let y = -8.0 + (j as f64 + 0.5) * 16.0 / m as f64;
                let w = ramp * (-0.5 * (x * x + y * y)).exp();
                num += w * fresnel_exact(ramp / (1.0 + sigma * sigma * (x * x + y * y)).sqrt(), SEA_WATER_IOR);
                den += w;
            }
        }
        num / den
    }
}
