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
//! Only the trains whose rings carry the most power radiate (MAX_COMPONENTS), and only where their
//! slope could show against the sea's (VISIBLE_SLOPE_SHARE); the packets' own waves (a wake
//! rocking the hull) radiate nothing here, nor does a moving hull.

use super::{comb_share, Packet, STEEPEST_KA, VISCOSITY};
use crate::model::floating::{complex_product, Waterplane};
use crate::model::waves::WaveSet;
use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// The most trains whose rings one hull radiates, the strongest first, until POWER_SHARE of its
/// radiated power is drawn.
pub const MAX_COMPONENTS: usize = 4;
pub const POWER_SHARE: f64 = 0.95;

/// Rings of packets along each ray, a wavelength apart (their radial sigma half that) from a
/// wavelength past the hull's edge: the far field at the last, 8 wavelengths out, is a third of
/// the first's, and the first's envelope is 0.06 of its peak at the hull's centre.
pub const RINGS: usize = 8;

/// A component radiates only where its first ring's slope amplitude k |eta| reaches this share of
/// the trains' rms slope: ours, a hundredth, which moves a pixel's slope variance by 1e-4 of
/// itself (a steady wind sea hides the rings of a small buoy; a calm sea shows them).
pub const VISIBLE_SLOPE_SHARE: f64 = 0.01;

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
}

impl HeavingHull {
    /// The hull at `centre` (world) on `waves`, whose phases count from `eye` (the camera's
    /// horizontal position, as placement::place has them).
    pub fn new(waves: &WaveSet, eye: DVec2, centre: DVec2, heading_rad: f64, plane: Waterplane) -> HeavingHull {
        let offset = centre - eye;
        let sea_slope = waves.trains.iter().map(|t| t.slope_variance().iter().sum::<f64>()).sum::<f64>().sqrt();
        let mut hull = HeavingHull { centre, heading_rad, plane, components: Vec::new(), drawn_power_share: 0.0 };
        let mut candidates: Vec<(f64, RingComponent)> = waves
            .trains
            .iter()
            .map(|train| {
                let d = DVec2::from(train.direction);
                // a₀'s phasor: the train at the hull's centre times the waterplane's average.
                let angle = d.y.atan2(d.x) - heading_rad;
                let fitted = train.amplitude * plane.directional(train.k, angle);
                let psi = train.phase0 - train.k * d.dot(offset);
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
            let first = hull.field(&component, hull.first_ring(component.k), 0.0).length();
            if component.k * first < VISIBLE_SLOPE_SHARE * sea_slope {
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

    /// The radius of a component's first ring: a wavelength past the waterplane's half diagonal.
    pub fn first_ring(&self, k: f64) -> f64 {
        0.5 * self.plane.length_m.hypot(self.plane.beam_m) + TAU / k
    }

    /// The rings' complex amplitude at time 0 at `r` from the centre along world angle `theta`:
    /// the far field above, damped by the water's viscosity over its travel at the group
    /// velocity, and never more than the heave against the water that makes it.
    pub fn field(&self, c: &RingComponent, r: f64, theta: f64) -> DVec2 {
        let (k, a, d) = (c.k, self.plane.area(), self.plane.draft_m);
        let directional = self.plane.directional(k, theta - self.heading_rad);
        let group = 0.5 * c.omega / k;
        let damping = (-2.0 * VISCOSITY * k * k * r / group).exp();
        let magnitude = 0.5 * k * k * a * (-k * d).exp() * (2.0 / (PI * k * r)).sqrt() * damping;
        // |eta| <= |Z|: the factor on Z held to [-1, 1] (the far form grows without bound
        // towards the hull, where it no longer holds).
        let factor = (magnitude * directional).clamp(-1.0, 1.0);
        let turn = -(k * r + 0.25 * PI);
        complex_product(c.relative, DVec2::new(turn.cos(), turn.sin())) * factor
    }

    /// The packets alive at time t: every component's rings.
    pub fn packets(&self, t: f64) -> Vec<Packet> {
        let mut packets = Vec::new();
        for c in &self.components {
            let lambda = TAU / c.k;
            let (spacing, radial) = (lambda, 0.5 * lambda);
            for n in 0..RINGS {
                let r = self.first_ring(c.k) + spacing * n as f64;
                // Straight crests on a curved ring: a packet's phase strays by k x² / 2r at x
                // along the ring from its centre, where its neighbour's envelope peaks (an arc, two
                // of its sigmas). Arcs at most sqrt(r / 2k) hold that to a quarter radian (the
                // power 1.3% short; at sqrt(r / k), half a radian, 5%), and at most a wavelength.
                let most = lambda.min((0.5 * r / c.k).sqrt());
                let directions = ((TAU * r / most).ceil() as usize).max(8);
                let arc = TAU * r / directions as f64;
                let share = comb_share(spacing, radial) * comb_share(arc, 0.5 * arc);
                for m in 0..directions {
                    let theta = (m as f64 + 0.5) * TAU / directions as f64;
                    let direction = DVec2::new(theta.cos(), theta.sin());
                    let eta = self.field(c, r, theta);
                    packets.push(Packet {
                        centre: self.centre + direction * r,
                        direction,
                        k: c.k,
                        amplitude: (eta.length() * share).min(STEEPEST_KA / c.k),
                        axis: direction,
                        sigma: [radial, 0.5 * arc],
                        phase: eta.y.atan2(eta.x) + c.omega * t,
                    });
                }
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
    use crate::model::waves::Train;

    const G_: f64 = 9.81;

    /// A 1 m buoy of 0.6 m draft and one component of wavelength `lambda` heaving 5 cm against
    /// the water.
    fn buoy(lambda: f64) -> (HeavingHull, RingComponent) {
        let plane = Waterplane { length_m: 1.0, beam_m: 1.0, draft_m: 0.6 };
        let k = TAU / lambda;
        let c = RingComponent { k, omega: (G_ * k).sqrt(), relative: DVec2::new(0.03, -0.04) };
        let hull = HeavingHull {
            centre: DVec2::new(5.0, -3.0),
            heading_rad: 0.4,
            plane,
            components: vec![c],
            drawn_power_share: 1.0,
        };
        (hull, c)
    }

    /// The phase average of eta² at `x`, over a period sampled at 16 times.
    fn mean_square(hull: &HeavingHull, c: &RingComponent, x: DVec2) -> f64 {
        let period = TAU / c.omega;
        (0..16)
            .map(|i| {
                let field = PacketField::bounded(hull.packets(i as f64 * period / 16.0), usize::MAX);
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
        // Over a ring's spacing (the rows of packets two sigmas apart ripple by 3% in amplitude,
        // 0.92 of the power between rings), from the third ring out and from the sixth.
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
        let field = PacketField::bounded(hull.packets(1.3), usize::MAX);
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
                omega: (G_ * k).sqrt(),
                phase0: 0.3,
            }
        };
        let waves = WaveSet {
            trains: vec![train(200.0, 0.5), train(3.8, 0.05)],
            wind_direction: [1.0, 0.0],
            sigma2: [0.0; 2],
            mean_height_offset: 0.0,
            packet_crest_m: 0.0,
            packet_longest_m: 0.0,
        };
        let plane = Waterplane { length_m: 1.0, beam_m: 1.0, draft_m: 0.6 };
        let hull = HeavingHull::new(&waves, DVec2::ZERO, DVec2::new(20.0, 0.0), 0.0, plane);
        assert_eq!(hull.components.len(), 1, "{hull:?}");
        assert!((hull.components[0].k - TAU / 3.8).abs() < 1e-12);
        assert!(hull.drawn_power_share > 0.99);
        // Without draft it rides the water exactly and radiates nothing.
        let flat =
            HeavingHull::new(&waves, DVec2::ZERO, DVec2::new(20.0, 0.0), 0.0, Waterplane { draft_m: 0.0, ..plane });
        assert!(flat.components.is_empty());
    }
}
