//! A floating hull's rings: what its heave moves against the water radiates, as a function of the
//! time alone. A still hull with a draft heaves as a damped oscillator under each train
//! (floating::Waterplane::heave_response); against the water at its bottom it moves by
//! Z = a₀ relative_heave(k), a phasor of the train's frequency. That motion is a pulsating
//! source of volume flux −A dZ/dt at the surface, whose waves in deep water are, far from it
//! (Newman, Marine Hydrodynamics, 1977, section 6.17, the source's Green function and its
//! Hankel function's far form):
//!   eta(r, theta) = Re[(k² A / 2) e^(−kd) S(theta) sqrt(2 / (pi k r)) Z e^(i (omega t − k r − pi / 4))],
//! S the waterplane's directional factor. They carry away the power the radiation damping takes
//! from the heave, rho g cg k³ A² e^(−2kd) <S²> |Z|² / 2 (the unit test holds the packets to it).
//! The hull has floated forever: the rings are steady, each a row of packets along every ray from
//! the hull, `RINGS` of them a wavelength apart, each packet's phase the ring's at its centre.
//! Only the trains whose rings carry the most power radiate (MAX_COMPONENTS), and only where
//! their slope could show against the sea's at their scale (VISIBLE_SLOPE_SHARE). The other
//! sources' packets (a wake rocking the hull) leave pulses of rings (`add_pulses`); a moving hull
//! radiates none.

use super::{comb_share, envelope_at, row_sum, Packet, ENVELOPE_SIGMAS, STEEPEST_KA, VISCOSITY};
use crate::model::floating::{complex_product, Waterplane};
use crate::model::waves::{WaveSet, G};
use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// The most trains whose rings one hull radiates, the strongest first, until POWER_SHARE of its
/// radiated power is drawn.
pub const MAX_COMPONENTS: usize = 4;
pub const POWER_SHARE: f64 = 0.95;

/// Rings of packets along each ray, a wavelength apart (their radial sigma half that), the first
/// where its envelope's reach ends at the hull's edge: the far field at the last, seven
/// wavelengths further, is about a third of the first's.
pub const RINGS: usize = 8;

/// A component (or a pulse) radiates only where its first ring's slope amplitude k |eta| could
/// show: at least VISIBLE_SLOPE_SHARE of the trains' rms slope within an octave of its
/// wavelength either way (a pattern is masked by the sea's own at its scale, little by ripples
/// far shorter or swell far longer; ours, a fifth), and at least MIN_VISIBLE_SLOPE (ours: 1e-3
/// turns a reflection by 0.11 degrees, a fifth of the sun's disc). A storm hides a buoy's rings;
/// a glassy sea shows a rocked boat's.
pub const VISIBLE_SLOPE_SHARE: f64 = 0.2;
pub const MIN_VISIBLE_SLOPE: f64 = 1e-3;

/// The most packets one ring takes around the hull.
pub const MAX_RING_DIRECTIONS: usize = 512;

/// The most pulses of rings a hull draws at once, the strongest: a budget, far above the few a
/// wake's crossing makes at a time (the preset harbour's at most 5), so that a pulse's rank
/// never decides whether it is drawn (that would pop it in and out).
pub const MAX_PULSES: usize = 64;

/// One train's rings: its wavenumber and frequency, and the hull's heave against the water at its
/// bottom at time 0 (m, complex).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingComponent {
    pub k: f64,
    pub omega: f64,
    pub relative: DVec2,
}

/// A still floating hull with a draft, and the trains it radiates.
#[derive(Clone, Debug, PartialEq)]
pub struct HeavingHull {
    /// Its centre (m, world frame).
    pub centre: DVec2,
    pub heading_rad: f64,
    pub plane: Waterplane,
    pub components: Vec<RingComponent>,
    /// The share of its whole radiated power the components carry.
    pub drawn_power_share: f64,
    /// The trains' wavenumbers and slope variances, against which a ring's visibility is judged.
    pub sea_slopes: Vec<(f64, f64)>,
}

impl HeavingHull {
    /// The hull at `centre` on `waves`, both in a frame whose origin the trains' phases count
    /// from (sources::heaving_hulls takes the world's, so that the eye's place changes nothing).
    pub fn new(waves: &WaveSet, centre: DVec2, heading_rad: f64, plane: Waterplane) -> HeavingHull {
        let sea_slopes = waves.trains.iter().map(|t| (t.k, t.slope_variance().iter().sum::<f64>())).collect();
        let mut hull =
            HeavingHull { centre, heading_rad, plane, components: Vec::new(), drawn_power_share: 0.0, sea_slopes };
        let mut candidates: Vec<(f64, RingComponent)> = waves
            .trains
            .iter()
            .map(|train| {
                let d = DVec2::from(train.direction);
                // a₀'s phasor: the train at the hull's centre times the waterplane's average.
                let angle = d.y.atan2(d.x) - heading_rad;
                let fitted = train.amplitude * plane.directional(train.k, angle);
                let psi = train.phase0 - train.k * d.dot(centre);
                let a0 = DVec2::new(psi.cos(), psi.sin()) * fitted;
                let relative = complex_product(plane.relative_heave(train.k), a0);
                let component = RingComponent { k: train.k, omega: train.omega, relative };
                (hull.radiated_power(&component), component)
            })
            .collect();
        let total: f64 = candidates.iter().map(|c| c.0).sum();
        // Nothing moves against the water (or a NaN crept in): no rings.
        if total.is_nan() || total <= 0.0 {
            return hull;
        }
        candidates.sort_by(|a, b| b.0.total_cmp(&a.0));
        let mut drawn = 0.0;
        for (power, component) in candidates {
            if hull.components.len() == MAX_COMPONENTS || drawn >= POWER_SHARE * total {
                break;
            }
            let first = hull.strongest_field(&component, hull.first_ring(component.k));
            if component.k * first < hull.least_visible_slope(component.k) {
                continue;
            }
            drawn += power;
            hull.components.push(component);
        }
        hull.drawn_power_share = drawn / total;
        hull
    }

    /// The power a component's rings carry away, over rho g (m⁴/s): cg k³ A² e^(−2kd) <S²> |Z|² / 2,
    /// the radiation damping's take of the heave.
    pub fn radiated_power(&self, c: &RingComponent) -> f64 {
        let group = 0.5 * c.omega / c.k;
        let (k, a) = (c.k, self.plane.area());
        0.5 * group
            * k.powi(3)
            * a
            * a
            * (-2.0 * k * self.plane.draft_m).exp()
            * self.plane.mean_directional2(k)
            * c.relative.length_squared()
    }

    /// The least slope amplitude of rings of wavenumber k that could show (VISIBLE_SLOPE_SHARE).
    pub fn least_visible_slope(&self, k: f64) -> f64 {
        let band: f64 = self.sea_slopes.iter().filter(|&&(ki, _)| ki >= 0.5 * k && ki <= 2.0 * k).map(|t| t.1).sum();
        (VISIBLE_SLOPE_SHARE * band.sqrt()).max(MIN_VISIBLE_SLOPE)
    }

    /// The radius of a component's first ring: its envelope's reach (ENVELOPE_SIGMAS of its half
    /// wavelength sigma) past the waterplane's half diagonal, so that no ring reaches under the
    /// hull and rocks it in turn (floating::ride_with_packets).
    pub fn first_ring(&self, k: f64) -> f64 {
        self.edge() + ENVELOPE_SIGMAS * 0.5 * TAU / k
    }

    /// How far the hull reaches from its centre: its waterplane's half diagonal (m).
    fn edge(&self) -> f64 {
        0.5 * self.plane.length_m.hypot(self.plane.beam_m)
    }

    /// The rings' complex amplitude at `r` from the centre along world angle `theta`, of a
    /// component of wavenumber k and group velocity `group` whose heave against the water is `z`
    /// (complex, at the same time): the far field above, damped by the water's viscosity over its
    /// travel, and never more than the heave that makes it.
    pub fn field(&self, k: f64, group: f64, z: DVec2, r: f64, theta: f64) -> DVec2 {
        let (a, d) = (self.plane.area(), self.plane.draft_m);
        let directional = self.plane.directional(k, theta - self.heading_rad);
        let damping = (-2.0 * VISCOSITY * k * k * r / group).exp();
        let magnitude = 0.5 * k * k * a * (-k * d).exp() * (2.0 / (PI * k * r)).sqrt() * damping;
        // |eta| <= |Z|: the factor on Z held to [-1, 1] (the far form grows without bound
        // towards the hull, where it no longer holds).
        let factor = (magnitude * directional).clamp(-1.0, 1.0);
        let turn = -(k * r + 0.25 * PI);
        complex_product(z, DVec2::new(turn.cos(), turn.sin())) * factor
    }

    /// A component's field at radius r in the direction it radiates most (of eight around the
    /// hull, from its bow), its magnitude.
    pub fn strongest_field(&self, c: &RingComponent, r: f64) -> f64 {
        (0..8).map(|i| self.component_field(c, r, self.heading_rad + i as f64 * PI / 8.0).length()).fold(0.0, f64::max)
    }

    /// A steady component's field at time 0 (`field` of its own heave).
    pub fn component_field(&self, c: &RingComponent, r: f64, theta: f64) -> DVec2 {
        self.field(c.k, 0.5 * c.omega / c.k, c.relative, r, theta)
    }

    /// The packets alive at time t: every steady component's rings, and the pulses of `driving`
    /// (the other sources' packets at t) that have rocked the hull.
    pub fn packets(&self, t: f64, driving: &[Packet]) -> Vec<Packet> {
        let mut packets = Vec::new();
        for c in &self.components {
            let lambda = TAU / c.k;
            let (turn, group) = (c.omega * t, 0.5 * c.omega / c.k);
            let z = complex_product(c.relative, DVec2::new(turn.cos(), turn.sin()));
            for n in 0..RINGS {
                let r = self.first_ring(c.k) + lambda * n as f64;
                self.add_ring(&mut packets, c.k, group, z, r, 0.5 * lambda, Some(comb_share(lambda, 0.5 * lambda)));
            }
        }
        self.add_pulses(&mut packets, driving);
        packets
    }

    /// One ring of packets of radial sigma `radial` at radius r, each `row_share` of the field at
    /// its centre where it is one of a row of rings in phase (the row's comb share), or the whole
    /// of it for a lone ring (None).
    #[allow(clippy::too_many_arguments)]
    fn add_ring(
        &self,
        packets: &mut Vec<Packet>,
        k: f64,
        group: f64,
        z: DVec2,
        r: f64,
        radial: f64,
        row_share: Option<f64>,
    ) {
        let lambda = TAU / k;
        // Straight crests on a curved ring: a packet's phase strays by k x² / 2r at x along the
        // ring from its centre, where its neighbour's envelope peaks (an arc, two of its sigmas).
        // Arcs at most sqrt(r / 2k) hold that to a quarter radian (the power 1.3% short; at
        // sqrt(r / k), half a radian, 5%), and at most a wavelength.
        // Directions a power of two, from +x: a pulse's growing ring doubles them now and then,
        // its old packets' places among the new (rows two sigmas apart sum to one either way).
        let most = lambda.min((0.5 * r / k).sqrt());
        // At most MAX_RING_DIRECTIONS: a pulse far out (its phase error then k arc² / 2r, 0.2
        // radians 100 wavelengths out) is faint by the time it needs more.
        let directions = ((TAU * r / most).ceil() as usize).clamp(8, MAX_RING_DIRECTIONS).next_power_of_two();
        let arc = TAU * r / directions as f64;
        let ring_share = comb_share(arc, 0.5 * arc);
        let share = row_share.unwrap_or(1.0) * ring_share;
        for m in 0..directions {
            let theta = m as f64 * TAU / directions as f64;
            let direction = DVec2::new(theta.cos(), theta.sin());
            let eta = self.field(k, group, z, r, theta);
            packets.push(Packet {
                centre: self.centre + direction * r,
                direction,
                k,
                amplitude: (eta.length() * share).min(STEEPEST_KA / k),
                axis: direction,
                sigma: [radial, 0.5 * arc],
                phase: eta.y.atan2(eta.x),
                // Its neighbours around the ring are in phase, two sigmas apart, and outwards
                // the next of a row, its share of their sum.
                in_phase: [row_share.map(row_sum), Some(row_sum(ring_share))],
            });
        }
    }

    /// The pulses of rings the `driving` packets leave: a packet crossing the hull rocks it at
    /// its frequency for as long as its envelope takes to pass, and the rings it radiates travel
    /// at the same group velocity, so that a pulse's radius is the hull's edge plus how far the
    /// packet's envelope has gone past the hull, and its radial profile is the envelope's along
    /// the packet's path through the hull (retarded by its travel). Its heave is the quasi-steady
    /// response to the envelope's peak there, at the carrier's phase at the hull now. A pulse
    /// rises over the two sigmas before the peak reaches the hull's centre (it stays at the
    /// hull's edge until the peak passes). The strongest MAX_PULSES that could show are drawn.
    fn add_pulses(&self, packets: &mut Vec<Packet>, driving: &[Packet]) {
        let edge = self.edge();
        // (slope, k, group velocity, radius, heave against the water, radial sigma)
        let mut pulses: Vec<(f64, f64, f64, f64, DVec2, f64)> = Vec::new();
        for p in driving {
            let d = p.direction;
            // The hull's path through the envelope, in sigmas along its axes: b + s w at s metres
            // along d from the hull's centre, nearest the packet's centre at s* = -(b . w) / |w|²
            // (how far the envelope has gone past the hull), sigma 1 / |w| along s.
            let rel = self.centre - p.centre;
            let (a0, a1) = (p.axis, p.axis.perp());
            let b = DVec2::new(rel.dot(a0) / p.sigma[0], rel.dot(a1) / p.sigma[1]);
            let w = DVec2::new(d.dot(a0) / p.sigma[0], d.dot(a1) / p.sigma[1]);
            let (w2, bw) = (w.length_squared(), b.dot(w));
            let past = -bw / w2;
            let sigma = w2.sqrt().recip();
            // The envelope on the path where it passes nearest the packet's centre: its peak there
            // (exactly, for a path along an axis, as a ring's own packets travel). Beyond its reach,
            // no pulse.
            let nearest = b + past * w;
            let (peak, _, _) = envelope_at(nearest.x, nearest.y);
            if peak <= 0.0 || past < -2.0 * sigma {
                continue;
            }
            let onset = {
                let x = ((past + 2.0 * sigma) / (2.0 * sigma)).clamp(0.0, 1.0);
                x * x * (3.0 - 2.0 * x)
            };
            let angle = d.y.atan2(d.x) - self.heading_rad;
            let fitted = p.amplitude * peak * self.plane.directional(p.k, angle) * onset;
            // The carrier's phase at the hull's centre now: phase - k d . (c - centre).
            let psi = p.phase - p.k * d.dot(rel);
            let z = complex_product(self.plane.relative_heave(p.k), DVec2::new(psi.cos(), psi.sin()) * fitted);
            // Held its envelope's reach out until the peak has gone that far: its inner tail
            // ends at the hull's edge, never under the hull (which it would rock in turn).
            let r = edge + past.max(ENVELOPE_SIGMAS * sigma);
            let group = 0.5 * (G / p.k).sqrt();
            let slope = p.k * self.field(p.k, group, z, r, self.heading_rad + 0.5 * PI).length();
            // Faded in from the least visible slope to three times it: no pulse pops in or out.
            let least = self.least_visible_slope(p.k);
            if slope > least {
                let x = (0.5 * (slope / least - 1.0)).min(1.0);
                pulses.push((slope, p.k, group, r, z * (x * x * (3.0 - 2.0 * x)), sigma));
            }
        }
        pulses.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(_, k, group, r, z, sigma) in pulses.iter().take(MAX_PULSES) {
            self.add_ring(packets, k, group, z, r, sigma, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::packets::test_support::zero_crossings;
    use crate::model::packets::PacketField;
    use crate::model::waves::{Train, G};

    /// A 1 m buoy of 0.6 m draft and one component of wavelength `lambda` heaving 5 cm against
    /// the water.
    fn buoy(lambda: f64) -> (HeavingHull, RingComponent) {
        let plane = Waterplane { length_m: 1.0, beam_m: 1.0, draft_m: 0.6 };
        let k = TAU / lambda;
        let c = RingComponent { k, omega: (G * k).sqrt(), relative: DVec2::new(0.03, -0.04) };
        let hull = HeavingHull {
            centre: DVec2::new(5.0, -3.0),
            heading_rad: 0.4,
            plane,
            components: vec![c],
            drawn_power_share: 1.0,
            sea_slopes: Vec::new(),
        };
        (hull, c)
    }

    /// The phase average of eta² at `x`, over a period sampled at 16 times.
    fn mean_square(hull: &HeavingHull, c: &RingComponent, x: DVec2) -> f64 {
        let period = TAU / c.omega;
        (0..16)
            .map(|i| {
                let field = PacketField::bounded(hull.packets(i as f64 * period / 16.0, &[]), usize::MAX);
                field.height(x).powi(2)
            })
            .sum::<f64>()
            / 16.0
    }

    #[test]
    fn the_rings_carry_the_power_the_heave_radiates() {
        let (hull, c) = buoy(3.8);
        let lambda = TAU / c.k;
        let group = 0.5 * c.omega / c.k;
        // The flux cg <eta²> r integrated around a circle, against the radiation damping's take,
        // cg k³ A² e^(-2kd) <S²> |Z|² / 2.
        let expected = hull.radiated_power(&c);
        let flux_at = |rings: f64| {
            let r = hull.first_ring(c.k) + (rings - 1.0) * lambda;
            let n = 180;
            (0..n)
                .map(|i| {
                    let theta = (i as f64 + 0.5) * TAU / n as f64;
                    group * mean_square(&hull, &c, hull.centre + r * DVec2::new(theta.cos(), theta.sin())) * r
                })
                .sum::<f64>()
                * TAU
                / n as f64
                / expected
        };
        // Over a ring's spacing (the rings' amplitudes fall between them, and their straight
        // crests stray from the curved ring), from the third ring out and from the sixth.
        for first in [3.0, 6.0] {
            let ratios: Vec<f64> = (0..4).map(|i| flux_at(first + 0.25 * i as f64)).collect();
            let mean = ratios.iter().sum::<f64>() / 4.0;
            assert!(
                (mean - 1.0).abs() < 0.04,
                "from ring {first} the rings carry {mean:.3} of the power: {ratios:.3?}"
            );
            assert!(ratios.iter().all(|r| (r - 1.0).abs() < 0.1), "{ratios:.3?}");
        }
    }

    #[test]
    fn the_rings_have_the_train_s_wavelength_and_fall_as_one_over_root_r() {
        let (hull, c) = buoy(3.8);
        let lambda = TAU / c.k;
        // Along a ray at one time, the height's zero crossings are half a wavelength apart.
        let ray = DVec2::new(0.6, 0.8);
        let (start, end) = (hull.first_ring(c.k) + lambda, hull.first_ring(c.k) + 6.0 * lambda);
        let field = PacketField::bounded(hull.packets(1.3, &[]), usize::MAX);
        let crossings = zero_crossings(&field, hull.centre, ray, start, end, 4000);
        let mean_gap = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
        assert!(
            (2.0 * mean_gap / lambda - 1.0).abs() < 0.01,
            "crests {:.3} m apart against {lambda:.3}",
            2.0 * mean_gap
        );
        // <eta²> r holds from the third ring to the sixth.
        let at = |rings: f64| {
            let r = hull.first_ring(c.k) + (rings - 1.0) * lambda;
            mean_square(&hull, &c, hull.centre + ray * r) * r
        };
        let ratio = at(6.0) / at(3.0);
        assert!((ratio - 1.0).abs() < 0.1, "<eta^2> r at the sixth ring over the third: {ratio:.3}");
    }

    /// A 6 m boat of 0.9 m draft beam-on to a 5.7 m train (its heave resonance) radiates it, and
    /// not the 200 m swell that carries it.
    #[test]
    fn a_hull_radiates_the_trains_it_moves_against_and_not_the_long_ones() {
        let train = |lambda: f64, amplitude: f64| {
            let k = TAU / lambda;
            Train {
                wavelength: lambda,
                k,
                direction: [1.0, 0.0],
                angle_from_wind: 0.0,
                amplitude,
                omega: (G * k).sqrt(),
                phase0: 0.3,
            }
        };
        let waves = WaveSet {
            trains: vec![train(200.0, 0.5), train(5.7, 0.05)],
            wind_direction: [1.0, 0.0],
            sigma2: [0.0; 2],
            mean_height_offset: 0.0,
            packet_crest_m: 0.0,
            packet_longest_m: 0.0,
        };
        let plane = Waterplane { length_m: 6.0, beam_m: 2.2, draft_m: 0.9 };
        let hull = HeavingHull::new(&waves, DVec2::new(20.0, 0.0), 0.5 * PI, plane);
        assert_eq!(hull.components.len(), 1, "{hull:?}");
        assert!((hull.components[0].k - TAU / 5.7).abs() < 1e-12);
        assert!(hull.drawn_power_share > 0.99);
        // Without draft it rides the water exactly and radiates nothing.
        let flat = HeavingHull::new(&waves, DVec2::new(20.0, 0.0), 0.5 * PI, Waterplane { draft_m: 0.0, ..plane });
        assert!(flat.components.is_empty());
    }

    #[test]
    fn a_packet_crossing_the_hull_leaves_a_pulse_of_rings_that_follows_it_out() {
        let (hull, _) = buoy(3.8);
        let hull = HeavingHull { components: Vec::new(), ..hull };
        let edge = hull.edge();
        // A packet of 4 m waves travelling along +x through the hull's centre, sigma 6 m along.
        let k = TAU / 4.0;
        let group = 0.5 * (G / k).sqrt();
        let driving = |t: f64| Packet {
            centre: hull.centre + DVec2::new(-30.0 + group * t, 0.0),
            direction: DVec2::X,
            k,
            amplitude: 0.05,
            axis: DVec2::X,
            sigma: [6.0, 6.0],
            phase: 1.0 + (G * k).sqrt() * t,
            in_phase: [None, None],
        };
        let pulse = |t: f64| hull.packets(t, &[driving(t)]);
        // Before its envelope is two sigmas from the hull, nothing.
        assert!(pulse(0.0).is_empty());
        // Once past by more than its reach, one ring whose radius is the hull's edge plus how far
        // the peak has gone.
        let t = (30.0 + 25.0) / group;
        let ring = pulse(t);
        assert!(!ring.is_empty());
        for p in &ring {
            let r = (p.centre - hull.centre).length();
            assert!((r - (edge + 25.0)).abs() < 1e-9, "{r}");
            assert!((p.sigma[0] - 6.0).abs() < 1e-9);
        }
        // It rises and travels smoothly: its strongest packet's amplitude changes by under 5% of
        // its largest per fiftieth of a sigma of travel, from its onset to well past (its onset's
        // and its fade-in's smoothsteps compound to 3.1% at the steepest; a pop would be all of
        // it).
        let strongest = |t: f64| pulse(t).iter().map(|p| p.amplitude).fold(0.0, f64::max);
        let step = 6.0 / group / 50.0;
        let times: Vec<f64> =
            (0..).map(|i| (30.0 - 12.0) / group + step * i as f64).take_while(|&t| t < 70.0 / group).collect();
        let amplitudes: Vec<f64> = times.iter().map(|&t| strongest(t)).collect();
        let largest = amplitudes.iter().copied().fold(0.0, f64::max);
        assert!(largest > 0.0);
        for (w, t) in amplitudes.windows(2).zip(&times) {
            assert!((w[1] - w[0]).abs() <= 0.05 * largest, "{} -> {} at {t} (largest {largest})", w[0], w[1]);
        }
        // A packet that passes 30 m to the side rocks nothing.
        let aside = |t: f64| Packet { centre: driving(t).centre + DVec2::new(0.0, 30.0), ..driving(t) };
        assert!(hull.packets(t, &[aside(t)]).is_empty());
    }
}
