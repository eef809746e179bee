//! A splash's rings as wave packets, a function of the time alone: the Cauchy-Poisson problem of
//! deep water (Lamb, Hydrodynamics, 1932, sections 238 and 255). The splash leaves a crater at
//! its time, the surface lowered by depth_m exp(-r^2 / R^2) (R its radius; ours, depth R / 4),
//! and lets go: each wavenumber k of the crater's spectrum, eta(k) = -depth pi R^2 exp(-k^2 R^2 / 4),
//! leaves its centre in every direction at the group velocity sqrt(g / k) / 2, longer waves first,
//! so that a ring of age t at radius r holds the wavenumber g t^2 / (4 r^2). Each band of k and of
//! direction is a packet; its amplitude carries the band's share of the crater's energy, the
//! phase average of eta^2 integrated over the sea, conserved: (1 / 2) (1 / 2 pi)^2 |eta(k)|^2 k dk
//! dphi, spread over the band's radial width (its group velocities' spread, times the age) and
//! its arc of the ring. Neighbouring directions share a wavenumber and a phase: their packets
//! overlap along the ring into one wave front.

use super::{comb_share, envelope_at, row_sum, Packet, STEEPEST_KA, VISCOSITY};
use crate::model::waves::G;
use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// The crater's depth over its radius (ours: a quarter).
pub const DEPTH_PER_RADIUS: f64 = 0.25;

/// The wavenumbers a splash's packets span, in k R: the crater's energy per unit k,
/// k exp(-k^2 R^2 / 2), peaks at k R = 1 and holds 99.97% of itself between these.
const K_R_RANGE: (f64, f64) = (0.05, 4.0);

/// The largest sum of a row of windows (packets::envelope_at along one axis), centred at
/// `centres` with half-widths `sigmas`, between its first and last centres, sampled 32 times
/// between neighbours (the sum is smooth; a quarter of a percent finer changes it by under
/// 1e-4), and no less than 1. Windows two sigmas apart sum to exactly 1; the bands' radial
/// widths grow outwards, and their sum overshoots between them (2.7% for 24 bands).
fn row_peak(centres: &[f64], sigmas: &[f64]) -> f64 {
    let sum = |r: f64| centres.iter().zip(sigmas).map(|(c, s)| envelope_at((r - c) / s, 0.0).0).sum::<f64>();
    centres
        .windows(2)
        .flat_map(|pair| (0..32).map(move |i| pair[0] + (pair[1] - pair[0]) * i as f64 / 32.0))
        .map(sum)
        .fold(1.0, f64::max)
}

/// A splash: a crater of `radius_m` at `position` at `time_s`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splash {
    pub position: DVec2,
    pub time_s: f64,
    pub radius_m: f64,
}

/// How finely a splash is cut into packets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplashSampling {
    /// Wavenumber bands, spaced evenly in log k over K_R_RANGE.
    pub bands: usize,
    /// Directions around the ring.
    pub directions: usize,
}

impl Splash {
    /// The crater's depth (m).
    pub fn depth_m(&self) -> f64 {
        DEPTH_PER_RADIUS * self.radius_m
    }

    /// The phase average of eta^2 integrated over the sea (m^4), which the rings carry away:
    /// half the crater's integral of eta^2, pi depth^2 R^2 / 2.
    pub fn energy(&self) -> f64 {
        0.25 * PI * (self.depth_m() * self.radius_m).powi(2)
    }

    /// The packets alive at time t: none before the splash.
    pub fn packets(&self, t: f64, sampling: &SplashSampling) -> Vec<Packet> {
        let age = t - self.time_s;
        let (n_k, n_phi) = (sampling.bands, sampling.directions);
        // Also where the time or the radius is NaN: none of the comparisons holds.
        let valid = age >= 0.0 && age.is_finite() && self.radius_m > 0.0 && self.radius_m.is_finite();
        if !valid || n_k == 0 || n_phi == 0 {
            return Vec::new();
        }
        let r_crater = self.radius_m;
        let spectrum = |k: f64| self.depth_m() * PI * r_crater * r_crater * (-0.25 * (k * r_crater).powi(2)).exp();
        let (lo, hi) = ((K_R_RANGE.0 / r_crater).ln(), (K_R_RANGE.1 / r_crater).ln());
        let d_phi = TAU / n_phi as f64;
        // Band j's edges, evenly spaced in log k.
        let edge = |j: usize| (lo + (hi - lo) * j as f64 / n_k as f64).exp();
        let group = |k: f64| 0.5 * (G / k).sqrt();
        // Band j's wavenumber and radial extent (see below), and the height its rows can sum to
        // along a ray, for the crater's bound: their radial windows' overshoot (row_peak), and
        // along the ring the packets' crests are straight where it curves, which brings its
        // neighbours closer by at most 1 - cos of half the angle between them (a window's
        // steepest slope, 3/4 a sigma, over that): 1 + d_phi^2 / 2 bounds it.
        let band_at = |j: usize| {
            let (k_lo, k_hi) = (edge(j), edge(j + 1));
            let k = (k_lo * k_hi).sqrt();
            (k_lo, k_hi, k, ((group(k_lo) - group(k_hi)) * age).max(1e-6 * TAU / k))
        };
        let (centres, radials): (Vec<f64>, Vec<f64>) =
            (0..n_k).map(band_at).map(|(_, _, k, spread)| (group(k) * age, 0.5 * spread)).unzip();
        let peak = row_peak(&centres, &radials) * (1.0 + 0.5 * d_phi * d_phi);
        let mut packets = Vec::with_capacity(n_k * n_phi);
        for j in 0..n_k {
            let (k_lo, k_hi, k, spread) = band_at(j);
            let dk = k_hi - k_lo;
            let r = group(k) * age;
            let lambda = TAU / k;
            // Where the band lies: its group velocities' spread times the age, which the
            // stationary phase maps it onto, and its packets' radial sigma half that: the
            // neighbouring bands meet there in phase, and sum to a chirp whose wavenumber falls
            // outwards. Wider, they would overlap bands whose phases have drifted apart and
            // cancel. Along the ring, half its arc: each packet's crests are straight, the ring's
            // curved, and a packet wider than its arc would reach its neighbours' with its phase
            // off by k x^2 / 2 r at x from its centre.
            let radial = 0.5 * spread;
            let arc = (0.5 * r * d_phi).max(1e-6 * lambda);
            // The band's share of the energy, 2 pi (1/2)(1/2 pi)^2 |eta|^2 k dk over the ring,
            // is (A^2 / 2) over its area, 2 pi r times its width.
            let band = 0.5 * spectrum(k).powi(2) * k * dk / TAU;
            // Near the centre, early (k r small), the stationary phase no longer holds and the
            // energy would pile into a ring of no width: the field is held to the crater's depth,
            // the linear solution's own bound (|eta| <= the Hankel integral of |eta(k)| k / 2 pi,
            // the depth). At a point the bands that meet in phase are the neighbours the shares
            // below divide the field among: rows about two sigmas apart radially and along the
            // ring, summing to at most `peak` times it.
            let field = (2.0 * band / (TAU * r.max(radial) * spread)).sqrt().min(self.depth_m() / peak);
            // Each packet's share of the field, radially (the bands) and along the ring.
            let (radial_share, ring_share) = (comb_share(spread, radial), comb_share(r * d_phi, arc));
            let amplitude_share = radial_share * ring_share;
            let damping = (-2.0 * VISCOSITY * k * k * age).exp();
            let amplitude = (field * amplitude_share * damping).min(STEEPEST_KA / k);
            for m in 0..n_phi {
                let phi = (m as f64 + 0.5) * d_phi;
                let direction = DVec2::new(phi.cos(), phi.sin());
                let centre = self.position + direction * r;
                packets.push(Packet {
                    centre,
                    direction,
                    k,
                    amplitude,
                    axis: direction,
                    sigma: [radial, arc],
                    // The crater at its centre at the start (cos = -1), the wave's phase
                    // omega t - k . (x - position) since.
                    phase: PI + (G * k).sqrt() * age - k * r,
                    // The ring's packets share its phase, and the neighbouring bands meet it
                    // in phase (the chirp): each its share of their sum.
                    in_phase: [Some(row_sum(radial_share)), Some(row_sum(ring_share))],
                });
            }
        }
        packets
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::packets::test_support::zero_crossings;
    use crate::model::packets::PacketField;

    fn splash() -> Splash {
        Splash { position: DVec2::new(5.0, -3.0), time_s: 2.0, radius_m: 1.0 }
    }

    const SAMPLING: SplashSampling = SplashSampling { bands: 48, directions: 96 };

    /// The rings' height squared summed over the sea: the field is a ring about the splash, so
    /// along three rays from its centre, each point weighted by its circle, 2 pi rho d rho.
    fn integral_of_height_squared(field: &PacketField, centre: DVec2, reach: f64) -> f64 {
        let n = 400;
        let step = reach / n as f64;
        let rays = [DVec2::X, DVec2::Y, DVec2::new(-0.6, -0.8)];
        (0..n)
            .map(|i| (i as f64 + 0.5) * step)
            .map(|rho| {
                rays.iter().map(|d| field.height(centre + *d * rho).powi(2)).sum::<f64>() / 3.0 * TAU * rho * step
            })
            .sum()
    }

    /// The rings carry away the crater's energy: the phase average of eta^2 over the sea is half
    /// the crater's integral of eta^2, at every age.
    #[test]
    fn a_splash_s_rings_carry_its_crater_s_energy_away() {
        let s = splash();
        for age in [3.0, 6.0, 12.0] {
            let field = PacketField::bounded(s.packets(s.time_s + age, &SAMPLING), usize::MAX);
            // The longest waves, k R = 0.05, run ahead at sqrt(g R / 0.05) / 2 = 7 m/s.
            let reach = 0.5 * (G * s.radius_m / K_R_RANGE.0).sqrt() * age + 10.0;
            let measured = integral_of_height_squared(&field, s.position, reach);
            let expected = s.energy();
            assert!((measured / expected - 1.0).abs() < 0.05, "age {age}: {measured} against {expected}");
        }
    }

    /// Early, before its rings leave the crater, the sea is nowhere deeper or higher than the
    /// crater was deep: the linear solution's bound, the crater's depth.
    #[test]
    fn a_splash_never_rises_above_its_crater_s_depth() {
        let s = splash();
        for age in [0.0, 0.02, 0.1, 0.3, 1.0, 3.0] {
            let field = PacketField::bounded(s.packets(s.time_s + age, &SAMPLING), usize::MAX);
            let highest = (0..400)
                .map(|i| s.position + DVec2::new(0.03 * i as f64, 0.011 * i as f64))
                .map(|x| field.height(x).abs())
                .fold(0.0, f64::max);
            assert!(highest <= s.depth_m() * (1.0 + 1e-9), "age {age}: {highest} m against {}", s.depth_m());
        }
    }

    /// Nothing before the splash; after it, the rings' local wavelength at radius r and age t is
    /// the stationary phase's, 2 pi / (g t^2 / 4 r^2): longer waves farther out. Measured on the
    /// height field, each half wavelength from two neighbouring zero crossings.
    #[test]
    fn a_splash_s_rings_spread_out_longest_first_and_nothing_comes_before_it() {
        let s = splash();
        assert!(s.packets(s.time_s - 1e-6, &SAMPLING).is_empty());
        assert!(s.packets(f64::NAN, &SAMPLING).is_empty());
        let age = 10.0;
        let field = PacketField::bounded(s.packets(s.time_s + age, &SAMPLING), usize::MAX);
        let direction = DVec2::new(0.6, 0.8);
        // Where the crater's spectrum holds its energy, k R from 0.5 to 2 (r from 22 to 11 m).
        for radius in [12.0, 15.0, 18.0, 21.0] {
            let expected = TAU / (G * age * age / (4.0 * radius * radius));
            let (from, to) = (radius - 1.5 * expected, radius + 1.5 * expected);
            let crossings = zero_crossings(&field, s.position, direction, from, to, 2000);
            assert!(crossings.len() >= 4, "r {radius}: {} crossings", crossings.len());
            // Each half wavelength against the stationary phase's at its middle (the rings chirp:
            // the wavelength grows as r^2).
            for pair in crossings.windows(2) {
                let middle = 0.5 * (pair[0] + pair[1]);
                let local = TAU / (G * age * age / (4.0 * middle * middle));
                let measured = 2.0 * (pair[1] - pair[0]);
                assert!((measured / local - 1.0).abs() < 0.1, "r {middle}: {measured} m against {local} m");
            }
        }
    }
}
