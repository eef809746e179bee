//! A moving object's Kelvin wake as wave packets, a function of the time alone.
//!
//! In the object's frame the wake is steady: each component of wave vector k at angle theta to
//! the track keeps pace with the object where its phase speed sqrt(g / k) equals U cos(theta), so
//! k(theta) = k0 / cos^2(theta), k0 = g / U^2 (the transverse waves' wavelength 2 pi U^2 / g at
//! theta = 0). Its energy leaves at the group velocity, half the phase speed along the wave
//! vector, which in the object's frame is v(theta) = U (cos^2(theta) / 2 - 1, cos(theta) sin(theta) / 2):
//! a ray behind the object at alpha(theta) = atan(sin cos / (1 + sin^2)) to the track, at most
//! arcsin(1/3) = 19.47 deg where tan(theta) = 1 / sqrt(2) (Kelvin 1887; Lighthill, Waves in Fluids,
//! 1978, section 3.10). Each component is a chain of packets along its ray, one emitted from the
//! object's path at each time of the component's own fixed grid (a few of its wavelengths apart
//! along the chain), so that the packets alive at t are those emitted before t, wherever the
//! clock started.
//!
//! The amplitude: the energy a component band d theta carries per unit time, F(theta) d theta,
//! spreads over the band's width r |alpha'| d theta at distance r along its ray while it moves at
//! |v|: A^2 = F / (|v| r |alpha'|), the far field's r^(-1/2). At the cusp, alpha' = 0, the width is
//! held at the caustic's own, where the field falls as r^(-1/3) (Airy): |alpha'| is taken no less
//! than (k r)^(-1/3). F is the spectrum of the pressure the hull puts on the water, a patch of
//! half-width b = L / 2 (L its waterline length): ours, F proportional to
//! (k b)^4 / (1 + (k b)^2)^3, rising as k^4 (a displacement's pressure radiates nothing at k = 0)
//! and falling as k^-2 beyond the patch's size (a hull's sharp bow and stern: a Gaussian patch,
//! whose spectrum falls as exp(-(k b)^2), leaves a slow hull no wake at all). It peaks at
//! k b = sqrt(2): on the transverse waves below a hull Froude number U / sqrt(g L) of
//! 2^(-3/4) = 0.59, the threshold Noblesse et al. (Eur. J. Mech. B 46, 2014) find, and above it
//! at cos^2(theta) = 1 / (2 sqrt(2) Fr^2), where the brightest ray's angle falls as 1 / Fr
//! (Rabaud & Moisy, Phys. Rev. Lett. 110, 2013; Darmon, Benzaquen & Raphael, J. Fluid Mech. 738,
//! 2014, with a Gaussian patch).

use super::{comb_share, row_sum, Packet, STEEPEST_KA, VISCOSITY};
use crate::model::waves::G;
use glam::DVec2;
use std::f64::consts::{FRAC_PI_4, TAU};

/// The shortest component: k b at most this. There F's amplitude, sqrt(F), is a tenth of its
/// peak's, and the wavelength 2 pi b / 30, a fifth of the patch's half-width.
const SOURCE_K_B_MAX: f64 = 30.0;

/// The source's largest value, (k b)^4 / (1 + (k b)^2)^3 at k b = sqrt(2).
const SOURCE_PEAK: f64 = 4.0 / 27.0;

/// The shortest wavelength a component may have (m): the trains' shortest (waves::generate).
const SHORTEST_WAVELENGTH_M: f64 = 0.02;

/// An object moving in a straight line, and the wake it sheds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wake {
    /// Where the object is at t = 0 (m, the trains' horizontal frame).
    pub origin: DVec2,
    /// Its velocity (m/s): at time t it is at origin + velocity t.
    pub velocity: DVec2,
    /// Since when it has moved (s); None: forever, a steady wake.
    pub start_s: Option<f64>,
    /// Its waterline length (m).
    pub hull_length_m: f64,
    /// The wake's amplitude scale (m): its brightest component's far field, A ∝ r^(-1/2) along
    /// its ray, taken back to one waterline length behind, where that component is at the hull's
    /// source's peak (Fr >= 0.59); a slower hull's is lower by the square root of its source's
    /// share of the peak, which falls as Fr^2. Nearer than a few wavelengths the
    /// far-field law does not hold, and the drawn waves there are lower.
    pub amplitude_m: f64,
}

/// How finely a wake is cut into packets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WakeSampling {
    /// Components on each side of the track.
    pub components: usize,
    /// A component's packets are emitted this many of its wavelengths apart along its chain
    /// (each half as long, one sigma, as the spacing): the time between two emissions is this
    /// times its wavelength over its speed along the ray.
    pub spacing_wavelengths: f64,
    /// ...and no less than this far apart (m): a short component's packets many of its
    /// wavelengths long (a packet may be, its wavenumber is one), fewer of them. Its waves then
    /// rise over that length behind the object.
    pub min_spacing_m: f64,
    /// The oldest packet's age (s): the wake's length behind the object is about U times it.
    pub max_age_s: f64,
}

/// One component of a wake: its wavenumber, the direction it travels, its speed along its ray
/// in the object's frame, |v(theta)|, and the ray angle's derivative alpha'(theta).
struct Component {
    k: f64,
    direction: DVec2,
    speed: f64,
    alpha_prime: f64,
}

/// alpha'(theta): how fast a component's ray turns with theta, its angle to the track being
/// alpha = atan(f), f = sin cos / (1 + sin^2).
fn ray_turn(theta: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    let f = s * c / (1.0 + s * s);
    // d/dtheta of sin cos / (1 + sin^2): (cos 2theta (1 + sin^2) - sin^2 2theta / 2) / (1 + sin^2)^2.
    let df = ((2.0 * theta).cos() * (1.0 + s * s) - 0.5 * (2.0 * theta).sin().powi(2)) / (1.0 + s * s).powi(2);
    df / (1.0 + f * f)
}

impl Wake {
    /// The object's position at time t.
    pub fn position(&self, t: f64) -> DVec2 {
        self.origin + self.velocity * t
    }

    /// The largest angle to the track a component reaches: where its wavenumber k0 / cos^2
    /// reaches the shortest component's.
    fn theta_max(&self, k0: f64) -> f64 {
        let b = 0.5 * self.hull_length_m;
        let k_max = (SOURCE_K_B_MAX / b).min(TAU / SHORTEST_WAVELENGTH_M);
        let ratio = k0 / k_max;
        if ratio >= 1.0 {
            0.0
        } else {
            ratio.sqrt().acos()
        }
    }

    /// The packets alive at time t.
    pub fn packets(&self, t: f64, sampling: &WakeSampling) -> Vec<Packet> {
        let u = self.velocity.length();
        // Also where a value is NaN or infinite: none of the comparisons holds.
        let moving = u > 0.0 && u.is_finite() && self.hull_length_m > 0.0 && self.hull_length_m.is_finite();
        let sampled = sampling.components > 0
            && sampling.spacing_wavelengths > 0.0
            && sampling.spacing_wavelengths.is_finite()
            && sampling.min_spacing_m >= 0.0
            && sampling.min_spacing_m.is_finite()
            && sampling.max_age_s >= 0.0
            && sampling.max_age_s.is_finite()
            && t.is_finite();
        if !(moving && sampled) {
            return Vec::new();
        }
        let track = self.velocity / u;
        let k0 = G / (u * u);
        let b = 0.5 * self.hull_length_m;
        let theta_max = self.theta_max(k0);
        if theta_max <= 0.0 {
            return Vec::new();
        }
        let m = sampling.components;
        let d_theta = theta_max / m as f64;
        let source = |k: f64| (k * b).powi(4) / (1.0 + (k * b).powi(2)).powi(3);
        // |alpha'| no less than the caustic's (k r)^(-1/3).
        let spread = |alpha_prime: f64, k: f64, r: f64| alpha_prime.hypot((k * r).powf(-1.0 / 3.0));
        // A component's field squared at r along its ray, over F's scale.
        let field2 = |c: &Component, r: f64| source(c.k) / (c.speed * r * spread(c.alpha_prime, c.k, r));
        let components: Vec<Component> = (0..2 * m)
            .map(|i| {
                let theta = (i as f64 + 0.5) * d_theta - theta_max;
                let (sin, cos) = theta.sin_cos();
                Component {
                    k: k0 / (cos * cos),
                    direction: DVec2::new(track.x * cos - track.y * sin, track.x * sin + track.y * cos),
                    speed: u * DVec2::new(0.5 * cos * cos - 1.0, 0.5 * cos * sin).length(),
                    alpha_prime: ray_turn(theta),
                }
            })
            .collect();
        // F's scale: the brightest component's field one waterline length behind is amplitude_m
        // times the square root of its source over the source's peak (4/27 at k b = sqrt(2)): a
        // hull whose brightest component is off the peak (slow, below Fr 0.59) radiates less.
        let (brightest, its_source) = components
            .iter()
            .map(|c| (field2(c, self.hull_length_m), source(c.k)))
            .fold((0.0, 0.0), |best, f| if f.0 > best.0 { f } else { best });
        if brightest.is_nan() || brightest <= 0.0 {
            return Vec::new();
        }
        let f0 = self.amplitude_m * self.amplitude_m / brightest * (its_source / SOURCE_PEAK).min(1.0);
        let fade = |x: f64| {
            let x = x.clamp(0.0, 1.0);
            x * x * (3.0 - 2.0 * x)
        };
        let here = self.position(t);
        let mut packets = Vec::new();
        for c in &components {
            let (k, direction, v, alpha_prime) = (c.k, c.direction, c.speed, c.alpha_prime);
            let lambda = TAU / k;
            let group = 0.5 * (G / k).sqrt();
            // Each component's own grid of emission times, n dt for whole n: the packets alive at
            // t are those emitted in (t - max_age, t], since the start, whatever the clock.
            let dt = (sampling.spacing_wavelengths * lambda).max(sampling.min_spacing_m) / v;
            let oldest = (t - sampling.max_age_s) / dt;
            let first = self.start_s.map_or(oldest, |start| oldest.max(start / dt)).ceil() as i64;
            let newest = (t / dt).floor() as i64;
            for n in first..=newest {
                let tau = n as f64 * dt;
                let age = t - tau;
                // Faded in over its first interval and out over its last: no packet appears or
                // vanishes whole as t crosses an emission.
                let weight = fade(age / dt) * fade((sampling.max_age_s - age) / dt);
                // (A NaN weight is not above zero either.)
                if weight.is_nan() || weight <= 0.0 {
                    continue;
                }
                let centre = self.position(tau) + direction * group * age;
                let chain = centre - here; // along the ray, |v| age long
                let r = chain.length();
                let lateral = r * alpha_prime.abs() * d_theta;
                let caustic = r.powf(1.0 / 3.0) * k.powf(-2.0 / 3.0);
                // Half the band's width, and no less than half the cusp's: narrower than a
                // wavelength where need be (wider, a packet would overlap components whose phases
                // have drifted apart). Never zero: an envelope divides by it.
                let across = (0.5 * lateral).max(0.5 * caustic).max(1e-6 * lambda);
                let field = if r > 0.0 { (f0 * field2(c, r)).sqrt() } else { f64::INFINITY };
                // The chain's windows, two sigmas apart (a partition of unity), and the neighbouring
                // components' `lateral` apart. Two sigmas, not one: a packet near the object
                // reaches half as far ahead of it.
                let along = 0.5 * v * dt;
                let (along_share, across_share) = (comb_share(v * dt, along), comb_share(lateral.max(1e-12), across));
                let share = along_share * across_share;
                let damping = (-2.0 * VISCOSITY * k * k * age).exp();
                let amplitude = (field * share * damping * weight).min(STEEPEST_KA / k);
                // The stationary phase's quarter turn, by the sign of alpha' (held smooth across
                // the cusp).
                let turn = FRAC_PI_4 * (alpha_prime * (k * r).powf(1.0 / 3.0)).clamp(-1.0, 1.0);
                let axis = if r > 0.0 { chain / r } else { -track };
                packets.push(Packet {
                    centre,
                    direction,
                    k,
                    amplitude,
                    axis,
                    sigma: [along, across],
                    phase: -turn - k * direction.dot(centre - here),
                    // The chain's packets share its carrier. The neighbouring components do not,
                    // but across a band they overlap where their phases have not drifted apart
                    // (its width is chosen so): near its ray's stationary phase a component adds in
                    // phase with its neighbours, the crest lines being that sum. So the variance
                    // takes both rows' sums, each the reciprocal of the packet's share of it
                    // (measured against the wake's own surface:
                    // `a_wake_s_slope_variance_is_its_surface_s`).
                    in_phase: [Some(row_sum(along_share)), Some(row_sum(across_share))],
                });
            }
        }
        packets
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::packets::PacketField;

    const LENGTH_M: f64 = 20.0;
    /// A short component's packets at least a hull length apart.
    const MIN_SPACING_M: f64 = LENGTH_M;

    /// An object moving along +x at hull Froude number `froude`, forever.
    fn wake(froude: f64) -> Wake {
        Wake {
            origin: DVec2::ZERO,
            velocity: DVec2::new(froude * (G * LENGTH_M).sqrt(), 0.0),
            start_s: None,
            hull_length_m: LENGTH_M,
            amplitude_m: 0.2,
        }
    }

    /// The field of `wake` at t = 0, long enough to reach `reach_m` behind it on every ray.
    fn field(wake: &Wake, reach_m: f64) -> PacketField {
        // The slowest ray, the transverse one, moves at U / 2 in the object's frame.
        let max_age = 2.2 * reach_m / wake.velocity.length();
        let sampling =
            WakeSampling { components: 64, spacing_wavelengths: 2.0, min_spacing_m: MIN_SPACING_M, max_age_s: max_age };
        PacketField::bounded(wake.packets(0.0, &sampling), usize::MAX)
    }

    /// The root mean square height on the ray at `angle_deg` to the track behind the object,
    /// between r0 and r1 metres from it.
    fn rms_on_ray(field: &PacketField, angle_deg: f64, r0: f64, r1: f64) -> f64 {
        let dir = DVec2::new(-angle_deg.to_radians().cos(), angle_deg.to_radians().sin());
        let n = 400;
        let sum: f64 = (0..n).map(|i| field.height(dir * (r0 + (r1 - r0) * (i as f64 + 0.5) / n as f64)).powi(2)).sum();
        (sum / n as f64).sqrt()
    }

    /// The angle (deg) of the largest rms between `from` and `to`, in steps of `step`.
    fn brightest_angle(field: &PacketField, from: f64, to: f64, step: f64, r0: f64, r1: f64) -> (f64, Vec<(f64, f64)>) {
        let profile: Vec<(f64, f64)> = (0..=((to - from) / step).round() as usize)
            .map(|i| from + step * i as f64)
            .map(|a| (a, rms_on_ray(field, a, r0, r1)))
            .collect();
        let best = profile.iter().copied().fold((0.0, 0.0), |b, p| if p.1 > b.1 { p } else { b });
        (best.0, profile)
    }

    /// The wake's outer edge, where the waves' rms falls to a quarter of its largest, lies at
    /// arcsin(1/3) = 19.47 deg at a low Froude number: measured on the height field 30 to 36 hull
    /// lengths behind, where the cusp's own width (r^(1/3) k^(-2/3)) is a third of a degree.
    #[test]
    fn a_slow_hull_s_wake_fills_a_wedge_of_arcsin_one_third() {
        let w = wake(0.3);
        let (r0, r1) = (30.0 * LENGTH_M, 36.0 * LENGTH_M);
        let f = field(&w, r1 * 1.05);
        let (best, profile) = brightest_angle(&f, 12.0, 24.0, 0.25, r0, r1);
        let peak = profile.iter().map(|p| p.1).fold(0.0, f64::max);
        let edge = profile.iter().filter(|p| p.0 > best && p.1 >= 0.25 * peak).map(|p| p.0).fold(best, f64::max);
        let kelvin = (1.0f64 / 3.0).asin().to_degrees();
        assert!((edge - kelvin).abs() <= 1.0, "edge {edge} deg, brightest {best}: {profile:?}");
        // Nothing beyond it.
        assert!(profile.iter().filter(|p| p.0 >= kelvin + 2.0).all(|p| p.1 < 0.05 * peak), "{profile:?}");
    }

    /// Along the track behind a slow hull the transverse waves keep pace with it: their
    /// wavelength is 2 pi U^2 / g, measured on the height field as the wavelength of the largest
    /// Fourier amplitude over 4 to 12 hull lengths behind.
    #[test]
    fn the_transverse_waves_are_two_pi_u_squared_over_g_long() {
        let w = wake(0.3);
        let u = w.velocity.length();
        let expected = TAU * u * u / G;
        let f = field(&w, 13.0 * LENGTH_M);
        let n = 1200;
        let (x0, x1) = (-4.0 * LENGTH_M, -12.0 * LENGTH_M);
        let heights: Vec<(f64, f64)> = (0..n)
            .map(|i| x0 + (x1 - x0) * i as f64 / (n - 1) as f64)
            .map(|x| (x, f.height(DVec2::new(x, 0.0))))
            .collect();
        let power = |lambda: f64| {
            let k = TAU / lambda;
            let (c, s) =
                heights.iter().fold((0.0, 0.0), |(c, s), &(x, h)| (c + h * (k * x).cos(), s + h * (k * x).sin()));
            c * c + s * s
        };
        let measured = (0..=400)
            .map(|i| expected * (0.7 + 0.6 * i as f64 / 400.0))
            .max_by(|a, b| power(*a).total_cmp(&power(*b)))
            .unwrap();
        assert!((measured / expected - 1.0).abs() <= 0.05, "{measured} m against 2 pi U^2 / g = {expected} m");
    }

    /// Above a hull Froude number of about 0.6 the brightest waves lie on a ray nearer the track
    /// than the wedge's edge, at an angle that falls roughly as 1 / Fr.
    #[test]
    fn a_fast_hull_s_wake_narrows_as_one_over_its_froude_number() {
        let angles: Vec<(f64, f64)> = [1.0, 1.5, 2.0]
            .iter()
            .map(|&fr| {
                let f = field(&wake(fr), 13.0 * LENGTH_M);
                (fr, brightest_angle(&f, 1.0, 24.0, 0.5, 8.0 * LENGTH_M, 12.0 * LENGTH_M).0)
            })
            .collect();
        let kelvin = (1.0f64 / 3.0).asin().to_degrees();
        let products: Vec<f64> = angles.iter().map(|(fr, a)| fr * a).collect();
        let mean = products.iter().sum::<f64>() / products.len() as f64;
        for (&(fr, a), p) in angles.iter().zip(&products) {
            assert!(a < kelvin - 3.0, "Fr {fr}: brightest at {a} deg: {angles:?}");
            assert!((p / mean - 1.0).abs() < 0.25, "Fr times angle {products:?} ({angles:?})");
        }
    }

    /// The field is a function of the time alone: as t crosses any component's emission, no
    /// packet appears or vanishes whole, and a wake that began at start_s has left nothing
    /// behind where the object then was.
    #[test]
    fn the_wake_changes_smoothly_with_time_and_begins_where_the_object_started() {
        let w = wake(0.3);
        let sampling =
            WakeSampling { components: 32, spacing_wavelengths: 2.0, min_spacing_m: MIN_SPACING_M, max_age_s: 40.0 };
        let at = |t: f64, x: DVec2| PacketField::bounded(w.packets(t, &sampling), usize::MAX).height(x);
        let points = [DVec2::new(-15.0, 3.0), DVec2::new(-40.0, 10.0), DVec2::new(-70.0, -20.0)];
        let u = w.velocity.length();
        // The fastest change a wave of the field can make: omega a, for the steepest packet.
        let dt = 1e-3;
        for x in points {
            let (mut previous, mut largest) = (at(0.0, x), 0.0f64);
            for i in 1..=2000 {
                let h = at(i as f64 * dt * 5.0, x);
                largest = largest.max((h - previous).abs());
                previous = h;
            }
            // Between samples 5 ms apart, a wave of amplitude 0.2 m and omega = g / U changes by at
            // most 0.2 (g / U) 5e-3; a packet appearing whole would jump by its amplitude.
            let bound = 2.0 * w.amplitude_m * (G / u) * 5.0 * dt;
            assert!(largest <= bound, "{x}: a jump of {largest} m in 5 ms (bound {bound})");
        }
        let started = Wake { start_s: Some(10.0), ..w };
        let field = PacketField::bounded(started.packets(20.0, &sampling), usize::MAX);
        assert!(!field.packets.is_empty());
        // Its wake lies between its start and where it is: every packet's centre, and so the sea
        // on its track behind the start beyond the packets' reach (their envelopes' tails) is
        // still.
        let reach = field.packets.iter().map(|p| p.sigma[0].max(p.sigma[1])).fold(0.0, f64::max);
        // (Its rectangle, ENVELOPE_SIGMAS sigmas along each axis, reaches sqrt(2) times that at a corner.)
        let reach = crate::model::packets::ENVELOPE_SIGMAS * std::f64::consts::SQRT_2 * reach;
        let before = started.position(10.0) - DVec2::new(reach + 1.0, 0.0);
        assert!(field.height(before).abs() < 1e-6 * w.amplitude_m, "{}", field.height(before));
        assert!(field.packets.iter().all(|p| p.centre.x >= started.position(10.0).x - 1e-9));
    }

    /// The slope variance a wake leaves to the BRDF where nothing resolves it
    /// (`Packet::slope_variance`, summed over the packets reaching a point) is its surface's
    /// own: over 12 m squares within the wedge 3 to 12 hull lengths behind, the mean square of
    /// the f64 surface's slope (its tangents, every packet summed) over the model's, the median
    /// square within 15% of 1. The components taken as adding their variances across their bands
    /// (each packet's window squared across) left it 1.3 times the model's.
    #[test]
    fn a_wake_s_slope_variance_is_its_surface_s() {
        let w = wake(0.3);
        let f = field(&w, 13.0 * LENGTH_M);
        let shortest = f.packets.iter().map(Packet::wavelength).fold(f64::INFINITY, f64::min);
        let step = shortest / 6.0;
        let side = 12.0;
        let per_side = (side / step).ceil() as usize;
        let half_angle = (1.0f64 / 3.0).asin();
        let mut ratios = Vec::new();
        for i in 0..((9.0 * LENGTH_M / side) as usize) {
            let x0 = -3.0 * LENGTH_M - (i as f64 + 1.0) * side;
            let reach = -x0 * half_angle.tan();
            for j in 0..((2.0 * reach / side) as usize) {
                let corner = DVec2::new(x0, -reach + j as f64 * side);
                let (surface, model) = f.slope_variance_over(corner, side, per_side);
                if model > 0.0 {
                    ratios.push(surface / model);
                }
            }
        }
        assert!(ratios.len() >= 20, "{} squares", ratios.len());
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        assert!((median - 1.0).abs() <= 0.15, "median {median} of {} squares: {ratios:?}", ratios.len());
    }
}
