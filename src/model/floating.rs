//! How a floating object rides the waves: its heave, pitch and roll are the plane that best fits
//! the sea's surface over its waterplane, a rectangle of its length and beam turned to its
//! heading. A hull averages the sea under it, so a wave much shorter than the hull barely moves
//! it; the fit is taken per train in closed form over the whole rectangle, never from a few
//! sample points, which would alias short trains into a jitter.
//!
//! Per train of amplitude h and wavenumber k along d, the height is h cos(ψ − α u − β v) at
//! body coordinates (u along the heading, v to port), with α = k d·u, β = k d·v and ψ the phase
//! at the centre. Over |u| ≤ L/2, |v| ≤ B/2 the functions 1, u and v are orthogonal, so the
//! least-squares plane z = a₀ + a₁ u + a₂ v has
//!   a₀ = h cos ψ · S(αL/2) S(βB/2),
//!   a₁ = −(6/L) h sin ψ · S′(αL/2) S(βB/2),
//!   a₂ = −(6/B) h sin ψ · S(αL/2) S′(βB/2),
//! with S(x) = sin x / x. For a hull short against the wave, a₀ → the height at the centre and
//! a₁, a₂ → the slopes there. The trochoids move the water sideways too: the fit is centred on
//! the rest position whose displaced point lies under the hull's centre (waves::water_under), and
//! the heave adds the rest plane's offset above mean sea level (Σ k h²/2, a metre in a storm),
//! so that a point hull sits exactly on the drawn surface. Over the rectangle the sideways motion
//! is left to first order: it moves the plane by O(k h²) per train.
//!
//! A hull with a draft heaves as a damped oscillator driven by the water at its bottom (pitch and
//! roll stay the fitted plane's): per wave of wavenumber k, its heave is a₀ times
//! `Waterplane::heave_response`, which is 1 for a hull without draft and for waves long against
//! it, and rises near its natural period. What it moves against the water radiates rings
//! (packets::heave).

use crate::model::packets::PacketField;
use crate::model::waves::WaveSet;
use glam::DVec2;

/// A hull's waterplane: the rectangle over which the sea is averaged, and the hull's draft.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waterplane {
    pub length_m: f64,
    pub beam_m: f64,
    /// Depth of the hull's bottom below its waterline (m); 0 rides the fitted plane exactly.
    pub draft_m: f64,
}

/// A hull's heave damping beside its radiation's, as a ratio of the critical: ours, of the order
/// of the viscous and eddy damping of small buoys and boats in heave. It bounds the response at
/// the natural period where a long hull radiates little.
pub const VISCOUS_HEAVE_DAMPING: f64 = 0.1;

/// Directions over a quarter turn for the waterplane's mean squared directional factor (its
/// square is even about both axes): k times the longer side of them, about four a lobe of the
/// sinc, within these (a buoy on its waves takes the fewest; every hull on every train, every
/// frame, takes them).
const DIRECTIONS: (usize, usize) = (8, 64);

impl Waterplane {
    /// The rectangle's area (m²).
    pub fn area(&self) -> f64 {
        self.length_m.max(0.0) * self.beam_m.max(0.0)
    }

    /// The rectangle's average of cos(k d . x) for a wave along `angle_from_bow` (rad):
    /// S(k L cos / 2) S(k B sin / 2), the fit's factor on a₀ and, by reciprocity, the directional
    /// factor of the waves the hull radiates.
    pub fn directional(&self, k: f64, angle_from_bow: f64) -> f64 {
        let (s, c) = angle_from_bow.sin_cos();
        sinc(0.5 * k * self.length_m.max(0.0) * c) * sinc(0.5 * k * self.beam_m.max(0.0) * s)
    }

    /// The directional factor's square averaged over all directions, by the midpoint rule.
    pub fn mean_directional2(&self, k: f64) -> f64 {
        let longer = self.length_m.max(self.beam_m).max(0.0);
        let n = ((k * longer).ceil() as usize).clamp(DIRECTIONS.0, DIRECTIONS.1);
        let step = 0.5 * std::f64::consts::PI / n as f64;
        (0..n).map(|i| self.directional(k, (i as f64 + 0.5) * step).powi(2)).sum::<f64>() / n as f64
    }

    /// The heave's radiation damping over the stiffness times omega, B omega / (rho g A), at
    /// wavenumber k: k² A e^(−2kd) <S²> / 2, from Haskind's relation with the Froude-Krylov force
    /// rho g A e^(−kd) S on a wall-sided hull in deep water (Newman, Marine Hydrodynamics, 1977,
    /// section 6.18). For a small hull, rho omega³ A² / 2g.
    pub fn radiation_damping(&self, k: f64) -> f64 {
        0.5 * k * k * self.area() * (-2.0 * k * self.draft_m).exp() * self.mean_directional2(k)
    }

    /// The heave of a wall-sided hull of this draft (its mass rho A d, no added mass: natural
    /// frequency sqrt(g / d)) over the fitted a₀ of a wave of wavenumber k, as a complex factor
    /// (re, im) on a₀'s phasor: e^(−kd) (1 + i b) / (1 − kd + i b), b the damping's
    /// (radiation_damping plus VISCOUS_HEAVE_DAMPING's 2 zeta omega / omega₀), both acting on
    /// the heave against the water at its bottom, e^(−kd) a₀. Exactly 1 without draft; 1 for
    /// waves long against the draft.
    pub fn heave_response(&self, k: f64) -> DVec2 {
        if self.draft_m <= 0.0 {
            return DVec2::X;
        }
        let (kd, b) = (k * self.draft_m, self.damping(k));
        complex_quotient(DVec2::new(1.0, b), DVec2::new(1.0 - kd, b)) * (-kd).exp()
    }

    /// The heave against the water at the hull's bottom, over a₀, complex: heave_response − e^(−kd)
    /// = e^(−kd) kd / (1 − kd + i b). What radiates (packets::heave).
    pub fn relative_heave(&self, k: f64) -> DVec2 {
        if self.draft_m <= 0.0 {
            return DVec2::ZERO;
        }
        let (kd, b) = (k * self.draft_m, self.damping(k));
        complex_quotient(DVec2::new(kd, 0.0), DVec2::new(1.0 - kd, b)) * (-kd).exp()
    }

    /// The heave's whole damping term b: radiation's and the viscous 2 zeta sqrt(kd).
    fn damping(&self, k: f64) -> f64 {
        self.radiation_damping(k) + 2.0 * VISCOUS_HEAVE_DAMPING * (k * self.draft_m).sqrt()
    }
}

/// a / b for complex numbers as (re, im); b is never 0 here (its imaginary part is a damping > 0).
fn complex_quotient(a: DVec2, b: DVec2) -> DVec2 {
    let d = b.length_squared();
    DVec2::new(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) / d
}

/// The complex product of (re, im) pairs.
pub fn complex_product(a: DVec2, b: DVec2) -> DVec2 {
    DVec2::new(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x)
}

/// Where the sea puts a floating object, relative to its still-water pose.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The waterplane's centre above mean sea level (m).
    pub heave_m: f64,
    /// The bow raised (rad).
    pub pitch_rad: f64,
    /// The port side (+v, left of the heading) raised (rad).
    pub roll_rad: f64,
}

/// The pose of a hull whose waterplane is centred at `centre` (m, in the frame whose origin is
/// the eye, as the trains' phases are) and turned `heading_rad` counter-clockwise from +x, at
/// time `t`.
pub fn ride(waves: &WaveSet, t: f64, centre: [f64; 2], heading_rad: f64, plane: Waterplane) -> Pose {
    PlaneFit::of_trains(waves, t, centre, heading_rad, plane).pose(waves)
}

/// The same hull's pose on the trains and the wave packets of `field` (the packets alive at
/// `t`, in the trains' frame): a wake or a splash rocks it too. Each packet is fitted as a train
/// of amplitude a E with the envelope E and its gradient taken at the hull's centre, to first
/// order in the envelope's change across the hull (a packet is several wavelengths long).
pub fn ride_with_packets(
    waves: &WaveSet,
    field: &PacketField,
    t: f64,
    centre: [f64; 2],
    heading_rad: f64,
    plane: Waterplane,
) -> Pose {
    let mut fit = PlaneFit::of_trains(waves, t, centre, heading_rad, plane);
    fit.add_packets(field);
    fit.pose(waves)
}

/// The least-squares plane z = a0 + slope_u u + slope_v v over a waterplane, summed wave by wave.
struct PlaneFit {
    /// The rest position under the hull's centre, and its axes.
    centre: DVec2,
    along: DVec2,
    across: DVec2,
    half_l: f64,
    half_b: f64,
    plane: Waterplane,
    a0: f64,
    slope_u: f64,
    slope_v: f64,
}

impl PlaneFit {
    fn of_trains(waves: &WaveSet, t: f64, centre: [f64; 2], heading_rad: f64, plane: Waterplane) -> Self {
        let (sin_h, cos_h) = heading_rad.sin_cos();
        let mut fit = PlaneFit {
            centre: DVec2::from(waves.water_under(centre, t).0),
            along: DVec2::new(cos_h, sin_h),
            across: DVec2::new(-sin_h, cos_h),
            half_l: 0.5 * plane.length_m.max(0.0),
            half_b: 0.5 * plane.beam_m.max(0.0),
            plane,
            a0: 0.0,
            slope_u: 0.0,
            slope_v: 0.0,
        };
        for train in &waves.trains {
            let d = DVec2::from(train.direction);
            fit.add_wave(train.amplitude, train.k, d, train.phase_at(t) - train.k * d.dot(fit.centre), DVec2::ZERO);
        }
        fit
    }

    /// Adds (h + g . x) cos(psi - k d . x) over the rectangle (x from its centre): a wave, and a
    /// tilt g of its amplitude (a packet's envelope to first order). With alpha, beta = k d along
    /// and across and u, v the body coordinates, the plane's moments are products of
    /// <cos(alpha u)> = S, <u sin(alpha u)> = F alpha L^2 / 12 and <u^2 cos(alpha u)> = S2 L^2 / 12.
    fn add_wave(&mut self, h: f64, k: f64, d: DVec2, psi: f64, g: DVec2) {
        let (alpha, beta) = (k * d.dot(self.along), k * d.dot(self.across));
        let (x, y) = (alpha * self.half_l, beta * self.half_b);
        let (l2, b2) = ((2.0 * self.half_l).powi(2) / 12.0, (2.0 * self.half_b).powi(2) / 12.0);
        let (sin_psi, cos_psi) = psi.sin_cos();
        let (sx, sy, fx, fy) = (sinc(x), sinc(y), slope_factor(x), slope_factor(y));
        let (gu, gv) = (g.dot(self.along), g.dot(self.across));
        // a₀'s share is Re[(c − i s) e^(i psi)], s the tilt's: the hull heaves it times its
        // response, a complex factor (1 without draft).
        let (c, s) = (h * sx * sy, gu * alpha * l2 * fx * sy + gv * beta * b2 * sx * fy);
        let f = self.plane.heave_response(k);
        self.a0 += (f.x * c + f.y * s) * cos_psi + (f.x * s - f.y * c) * sin_psi;
        // −(6/L) S′(αL/2) = α F(αL/2), F = −3 S′(x)/x: so a point hull (L → 0) keeps the
        // slope at its centre, h α sin ψ, with no 0/0.
        self.slope_u += h * sin_psi * alpha * fx * sy
            + cos_psi * (gu * curvature_factor(x) * sy - gv * alpha * beta * b2 * fx * fy);
        self.slope_v +=
            h * sin_psi * beta * sx * fy + cos_psi * (gv * sx * curvature_factor(y) - gu * alpha * beta * l2 * fx * fy);
    }

    fn add_packets(&mut self, field: &PacketField) {
        let centre = self.centre;
        // The envelope's tilt is its first order over the hull: for a packet shorter than the
        // hull it would change sign across it, and only its value at the centre is kept.
        let half_size = self.half_l.max(self.half_b);
        for p in field.packets.iter().filter(|p| p.reaches(centre)) {
            let (e, grad) = p.envelope(self.centre);
            let grad = if p.sigma[0].min(p.sigma[1]) >= half_size { grad } else { DVec2::ZERO };
            let psi = p.phase - p.k * p.direction.dot(self.centre - p.centre);
            self.add_wave(p.amplitude * e, p.k, p.direction, psi, p.amplitude * grad);
        }
    }

    fn pose(&self, waves: &WaveSet) -> Pose {
        Pose {
            heave_m: waves.mean_height_offset + self.a0,
            pitch_rad: self.slope_u.atan(),
            roll_rad: self.slope_v.atan(),
        }
    }
}

/// S(x) = sin x / x, 1 at 0 (its series below 1e-4, where 1 − x²/6 is exact in f64).
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// −3 S′(x) / x = 3 (sin x − x cos x) / x³: the least-squares slope of cos over [−1, 1] scaled
/// by x, over the slope at the centre; 1 at 0 (its series below 1e-3, where cancellation in
/// sin x − x cos x would cost digits: 1 − x²/10 + x⁴/280).
fn slope_factor(x: f64) -> f64 {
    if x.abs() < 1e-3 {
        let x2 = x * x;
        1.0 - x2 / 10.0 + x2 * x2 / 280.0
    } else {
        3.0 * (x.sin() - x * x.cos()) / (x * x * x)
    }
}

/// −3 S″(x) = 3 sin x / x + 6 cos x / x² − 6 sin x / x³: the mean of u² cos(αu) over [−1, 1]
/// scaled, over u²'s own; 1 at 0 (its series below 1e-2, where the terms cancel:
/// 1 − 3x²/10 + x⁴/56).
fn curvature_factor(x: f64) -> f64 {
    if x.abs() < 1e-2 {
        let x2 = x * x;
        1.0 - 0.3 * x2 + x2 * x2 / 56.0
    } else {
        let (s, c) = x.sin_cos();
        3.0 * s / x + 6.0 * c / (x * x) - 6.0 * s / (x * x * x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::waves::Train;

    fn sea(trains: Vec<Train>) -> WaveSet {
        WaveSet {
            trains,
            wind_direction: [1.0, 0.0],
            sigma2: [0.0; 2],
            mean_height_offset: 0.0,
            packet_crest_m: 0.0,
            packet_longest_m: 0.0,
        }
    }

    fn train(wavelength: f64, angle: f64, amplitude: f64, phase0: f64) -> Train {
        let k = std::f64::consts::TAU / wavelength;
        Train {
            wavelength,
            k,
            direction: [angle.cos(), angle.sin()],
            angle_from_wind: angle,
            amplitude,
            omega: (9.81 * k).sqrt(),
            phase0,
        }
    }

    /// The least-squares plane over the rectangle by brute force: a fine midpoint grid.
    fn fitted(waves: &WaveSet, t: f64, centre: [f64; 2], heading: f64, plane: Waterplane) -> Pose {
        let n = 400;
        let (s, c) = heading.sin_cos();
        let (mut m0, mut mu, mut mv, mut uu, mut vv) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for i in 0..n {
            for j in 0..n {
                let u = ((i as f64 + 0.5) / n as f64 - 0.5) * plane.length_m;
                let v = ((j as f64 + 0.5) / n as f64 - 0.5) * plane.beam_m;
                let p = [centre[0] + u * c - v * s, centre[1] + u * s + v * c];
                let z: f64 = waves
                    .trains
                    .iter()
                    .map(|t_| {
                        let phase = t_.phase_at(t) - t_.k * (t_.direction[0] * p[0] + t_.direction[1] * p[1]);
                        t_.amplitude * phase.cos()
                    })
                    .sum();
                (m0, mu, mv, uu, vv) = (m0 + z, mu + u * z, mv + v * z, uu + u * u, vv + v * v);
            }
        }
        let count = (n * n) as f64;
        Pose { heave_m: m0 / count, pitch_rad: (mu / uu).atan(), roll_rad: (mv / vv).atan() }
    }

    #[test]
    fn the_closed_form_is_the_least_squares_plane() {
        let waves = sea(vec![train(40.0, 0.3, 0.5, 1.0), train(7.0, -1.2, 0.08, 2.5), train(2.1, 2.0, 0.02, 0.4)]);
        let plane = Waterplane { length_m: 6.0, beam_m: 2.2, draft_m: 0.0 };
        for (t, centre, heading) in [(0.0, [0.0, 0.0], 0.0), (3.7, [40.0, -12.0], 1.1), (11.0, [-5.0, 8.0], -2.6)] {
            let ours = ride(&waves, t, centre, heading, plane);
            // Fitted about the rest position under the centre, as ride centres it.
            let brute = fitted(&waves, t, waves.water_under(centre, t).0, heading, plane);
            // The midpoint grid's own error is O((k L / n)²): below 1e-5 relative here.
            assert!((ours.heave_m - brute.heave_m).abs() < 1e-5, "{ours:?} against {brute:?}");
            assert!((ours.pitch_rad - brute.pitch_rad).abs() < 1e-5, "{ours:?} against {brute:?}");
            assert!((ours.roll_rad - brute.roll_rad).abs() < 1e-5, "{ours:?} against {brute:?}");
        }
    }

    /// On a wave packet alone (no trains), many hulls long, the pose is the least-squares plane
    /// of the packet's surface over the waterplane, to first order in the envelope's change across
    /// the hull; a calm sea's, level.
    #[test]
    fn a_hull_rides_a_wave_packet_as_its_plane_fit() {
        use crate::model::packets::Packet;
        let calm = sea(vec![]);
        let packet = Packet {
            centre: DVec2::new(30.0, -4.0),
            direction: DVec2::new(0.8, 0.6),
            k: std::f64::consts::TAU / 9.0,
            amplitude: 0.3,
            axis: DVec2::new(0.8, 0.6),
            sigma: [60.0, 40.0],
            phase: 0.9,
            in_phase: [None, None],
        };
        let field = PacketField { packets: vec![packet], ..Default::default() };
        let plane = Waterplane { length_m: 6.0, beam_m: 2.2, draft_m: 0.0 };
        for (centre, heading) in [([30.0, -4.0], 0.3), ([10.0, 20.0], -1.9), ([70.0, -40.0], 2.5)] {
            let ours = ride_with_packets(&calm, &field, 0.0, centre, heading, plane);
            let n = 200;
            let (s, c) = f64::sin_cos(heading);
            let (mut m0, mut mu, mut mv, mut uu, mut vv) = (0.0, 0.0, 0.0, 0.0, 0.0);
            for i in 0..n {
                for j in 0..n {
                    let u = ((i as f64 + 0.5) / n as f64 - 0.5) * plane.length_m;
                    let v = ((j as f64 + 0.5) / n as f64 - 0.5) * plane.beam_m;
                    let z = field.height(DVec2::new(centre[0] + u * c - v * s, centre[1] + u * s + v * c));
                    (m0, mu, mv, uu, vv) = (m0 + z, mu + u * z, mv + v * z, uu + u * u, vv + v * v);
                }
            }
            let count = (n * n) as f64;
            let brute = Pose { heave_m: m0 / count, pitch_rad: (mu / uu).atan(), roll_rad: (mv / vv).atan() };
            // The envelope's second order over a 6 m hull, (3 / 40)^2 / 2 of an amplitude 0.3.
            assert!((ours.heave_m - brute.heave_m).abs() < 1e-3, "{ours:?} against {brute:?}");
            assert!((ours.pitch_rad - brute.pitch_rad).abs() < 1e-3, "{ours:?} against {brute:?}");
            assert!((ours.roll_rad - brute.roll_rad).abs() < 1e-3, "{ours:?} against {brute:?}");
            assert!(ours.heave_m.abs() + ours.pitch_rad.abs() > 1e-3, "the packet moves it: {ours:?}");
        }
        assert_eq!(
            ride_with_packets(&calm, &PacketField::default(), 0.0, [3.0, 4.0], 0.5, plane),
            ride(&calm, 0.0, [3.0, 4.0], 0.5, plane)
        );
    }

    #[test]
    fn a_point_hull_follows_the_surface_and_a_long_one_ignores_short_waves() {
        // A 100 m swell along +x, crest at the origin at t = 0 (phase 0), plus a 2 m chop.
        let swell = train(100.0, 0.0, 1.0, 0.0);
        let waves = sea(vec![swell, train(2.0, 0.0, 0.05, 0.7)]);
        let point = Waterplane { length_m: 0.0, beam_m: 0.0, draft_m: 0.0 };
        // A point hull sits on the drawn surface: the trochoid's height over its centre, the
        // rest plane's offset included.
        let mut swell_only = sea(vec![swell]);
        swell_only.mean_height_offset = swell.k * swell.amplitude * swell.amplitude / 2.0;
        for x in [0.0, 11.0, 25.0, 60.0] {
            let p = ride(&swell_only, 0.0, [x, 0.0], 0.0, point);
            let (rest, height) = swell_only.water_under([x, 0.0], 0.0);
            assert!((p.heave_m - height).abs() < 1e-12, "{p:?} against {height}");
            // Its slope: the rest position's first-order slope, d/dx of h cos(-k x).
            let slope = swell.k * swell.amplitude * (-swell.k * rest[0]).sin();
            assert!((p.pitch_rad - slope.atan()).abs() < 1e-12 && p.roll_rad.abs() < 1e-12, "{p:?}");
        }
        // A 20 m hull spans ten wavelengths of the chop: S(k L / 2) = S(10 pi) = 0.
        let hull = Waterplane { length_m: 20.0, beam_m: 4.0, draft_m: 0.0 };
        let with_chop = ride(&waves, 0.0, [0.0, 0.0], 0.0, hull);
        let without = ride(&sea(vec![swell]), 0.0, [0.0, 0.0], 0.0, hull);
        // (The chop moves the rest centre by 3 cm, where the swell's crest is flat: 2e-6 m.)
        assert!((with_chop.heave_m - without.heave_m).abs() < 1e-5, "{with_chop:?} {without:?}");
        // Turned about, the bow sees the slope the other way, the port side the other side.
        let ahead = ride(&waves, 1.0, [3.0, 1.0], 0.4, hull);
        let astern = ride(&waves, 1.0, [3.0, 1.0], 0.4 + std::f64::consts::PI, hull);
        assert!((ahead.pitch_rad + astern.pitch_rad).abs() < 1e-12 && (ahead.heave_m - astern.heave_m).abs() < 1e-12);
    }

    #[test]
    fn a_hull_heaves_with_the_water_below_its_natural_frequency_and_peaks_there() {
        let buoy = Waterplane { length_m: 1.0, beam_m: 1.0, draft_m: 0.6 };
        // Without draft, exactly the fitted plane; waves long against the draft carry it.
        let flat = Waterplane { draft_m: 0.0, ..buoy };
        assert_eq!(flat.heave_response(3.0), DVec2::X);
        assert_eq!(flat.relative_heave(3.0), DVec2::ZERO);
        let long = buoy.heave_response(std::f64::consts::TAU / 500.0);
        assert!((long - DVec2::X).length() < 0.01, "{long:?}");
        // The response is largest near kd = 1 (g / d = omega², its natural frequency), and lags
        // the water there by most of a quarter turn (e^(-1) (1 - i / b): 71 degrees here).
        let ks: Vec<f64> = (1..400).map(|i| i as f64 * 0.02 / buoy.draft_m).collect();
        let peak = ks
            .iter()
            .copied()
            .max_by(|a, b| buoy.heave_response(*a).length().total_cmp(&buoy.heave_response(*b).length()));
        let kd = peak.unwrap() * buoy.draft_m;
        assert!((0.8..1.2).contains(&kd), "peak at kd = {kd}");
        let at_one = buoy.heave_response(1.0 / buoy.draft_m);
        assert!(at_one.y < -2.0 * at_one.x.abs(), "{at_one:?}");
        // Short waves leave it still.
        assert!(buoy.heave_response(20.0 / buoy.draft_m).length() < 0.01);
        // A small hull's radiation damping is rho omega³ A² / 2g over rho g A / omega: k² A e^(-2kd) / 2.
        let k = 0.05;
        let small = Waterplane { length_m: 0.1, beam_m: 0.1, draft_m: 0.05 };
        let expected = 0.5 * k * k * small.area() * (-2.0 * k * small.draft_m).exp();
        assert!((small.radiation_damping(k) / expected - 1.0).abs() < 1e-5);
    }
}
