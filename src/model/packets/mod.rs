//! Wave packets in f64: short trains of one wavelength under a smooth envelope, moving at deep
//! water's group velocity (Jeschke & Wojtan, "Water Wave Packets", SIGGRAPH 2017), the local waves
//! beside the trochoid trains. A packet displaces the surface as a trochoid train does, times its
//! envelope, so the filtering of the three scales carries over with the same closed forms: one
//! wavelength, one slope amplitude k a E. Sources turn a scene's moving objects and events into
//! the packets alive at a time t (`kelvin`), as a function of t alone: no history is replayed.

pub mod grid;
pub mod heave;
pub mod kelvin;
pub mod sources;
pub mod splash;

use crate::model::waves::trochoid_slope_variance;
use glam::{DVec2, DVec3};

/// Deep water's steepest wave: Stokes' limiting height H / lambda = 0.142 (Michell 1893), so
/// k a = pi 0.142. A packet's slope amplitude is held to it; the trains' own limit, k h <= 1 (a
/// trochoid that would loop), is looser.
pub const STEEPEST_KA: f64 = std::f64::consts::PI * 0.142;

/// Kinematic viscosity of sea water at 20 C (m^2/s): a linear wave's amplitude decays as
/// exp(-2 nu k^2 t) (Lamb, Hydrodynamics, 1932, section 348).
pub const VISCOSITY: f64 = 1.05e-6;

/// A packet's envelope reaches this far along each of its axes, in sigmas: along each axis it is
/// the window w(t) = 1 - smoothstep(0, 2, |t|) = 1 - 3 (t/2)^2 + 2 |t/2|^3, and the envelope their
/// product w(u) w(v). A row of windows two sigmas apart is a partition of unity (w(t) + w(t - 2) =
/// 1, as smoothstep(x) + smoothstep(1 - x) = 1): a chain of equal packets sums to one flat train,
/// where Gaussians two sigmas apart rippled by 2%. A product, so that a lattice sums to the
/// product of its rows' sums and a row's share (`comb_share`) holds in two dimensions too. Its
/// reach sets how many packets a point reads, reach^2 of a lattice two sigmas apart: 4, against
/// 5.3 for the tapered Gaussians reaching 2.3 sigmas drawn before (docs/bench/packets.md), and a
/// polynomial has no exponential to evaluate. Sigma is the half-width at half the peak, w(1) = 1/2.
pub const ENVELOPE_SIGMAS: f64 = 2.0;

/// The envelope's square integrated over the plane, over sigma_1 sigma_2: the window's own,
/// integral of w^2 over [-2, 2] = 4 (13/35), squared.
pub const ENVELOPE_SQUARE_INTEGRAL: f64 = (52.0 / 35.0) * (52.0 / 35.0);

/// The window along one axis at t sigmas and its derivative: 1 - smoothstep(0, ENVELOPE_SIGMAS,
/// |t|); 0 from ENVELOPE_SIGMAS out.
fn window(t: f64) -> (f64, f64) {
    let x = t.abs() / ENVELOPE_SIGMAS;
    if x >= 1.0 {
        return (0.0, 0.0);
    }
    (1.0 - x * x * (3.0 - 2.0 * x), -6.0 * x * (1.0 - x) / ENVELOPE_SIGMAS * t.signum())
}

/// The envelope at normalized coordinates (u, v) (sigmas along each axis) and its derivatives in
/// them: the product of each axis's window (glsl/packet_data.glsl `packet_envelope` is its twin).
pub fn envelope_at(u: f64, v: f64) -> (f64, f64, f64) {
    let ((eu, du), (ev, dv)) = (window(u), window(v));
    (eu * ev, du * ev, eu * dv)
}

/// The envelope's integral along an axis through its centre, in sigmas: the window's, exactly 2
/// (half its support, a partition of unity two sigmas apart).
pub const ENVELOPE_LINE_INTEGRAL: f64 = 2.0;

/// A packet's share of the field its row makes: envelopes of sigma `sigma`, `spacing` apart and
/// in phase, sum to ENVELOPE_LINE_INTEGRAL sigma / spacing times one on average (exactly one
/// everywhere two sigmas apart); at most the whole (a packet alone).
pub fn comb_share(spacing: f64, sigma: f64) -> f64 {
    (spacing / (ENVELOPE_LINE_INTEGRAL * sigma)).min(1.0)
}

/// What the envelopes of a row in phase sum to, of which each packet holds `share` of the field
/// (`comb_share`): its reciprocal, 1 two sigmas apart or further; 1 for a packet of no share,
/// whose amplitude is 0 (Packet::in_phase).
pub fn row_sum(share: f64) -> f64 {
    if share > 0.0 {
        1.0 / share
    } else {
        1.0
    }
}

/// One packet at the field's time: a carrier of wavenumber k travelling along `direction`, under a
/// smooth envelope (`envelope_at`) whose axes are `axis` and its perpendicular.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Packet {
    /// The envelope's centre (m, the trains' horizontal frame).
    pub centre: DVec2,
    /// Unit: where the carrier travels, its wave vector's direction.
    pub direction: DVec2,
    /// Wavenumber (rad/m).
    pub k: f64,
    /// Amplitude at the envelope's centre (m), k a <= STEEPEST_KA.
    pub amplitude: f64,
    /// Unit: the envelope's first axis (a wake's chain of packets lies along it).
    pub axis: DVec2,
    /// The envelope's half-widths at half its peak along `axis` and across it (m): it reaches
    /// ENVELOPE_SIGMAS of them.
    pub sigma: [f64; 2],
    /// The carrier's phase at the centre (rad): at rest position x it is
    /// phase - k direction . (x - centre), as a train's omega t - k . x + phase0.
    pub phase: f64,
    /// Along each axis (`axis`, then across), whether its neighbours carry its own wave in phase
    /// with it (a chain's packets along it, a ring's around it) and, where they do, what their
    /// envelopes sum to there: 1 for a row two sigmas apart (the windows' partition of unity),
    /// 2 sigma / spacing for one closer (a wake's band held at its cusp's width, each packet's
    /// amplitude the reciprocal share of the field, `comb_share`). The slope variance it leaves to
    /// the BRDF then takes its window along that axis times that sum, not the window's square, so
    /// that the row's variances sum to that of its summed amplitude (exactly, for equal packets),
    /// where squares would leave 0.743 of it on average two sigmas apart, and less the closer they
    /// are (`variance_envelope`). None: its neighbours' waves are not in phase with its own, and
    /// their variances add.
    pub in_phase: [Option<f64>; 2],
}

/// The surface a packet adds at a rest position: its displacement, and its share of the
/// tangents d p / d x and d p / d y (as waves::add_tangents adds a train's).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceSum {
    pub displacement: DVec3,
    pub tx: DVec3,
    pub ty: DVec3,
}

impl Packet {
    pub fn wavelength(&self) -> f64 {
        std::f64::consts::TAU / self.k
    }

    /// Its wave energy over rho g (m^4): the phase-averaged 1/2 a^2 E^2 integrated over the
    /// envelope, 1/2 a^2 sigma_1 sigma_2 ENVELOPE_SQUARE_INTEGRAL.
    pub fn energy(&self) -> f64 {
        0.5 * self.amplitude * self.amplitude * self.sigma[0] * self.sigma[1] * ENVELOPE_SQUARE_INTEGRAL
    }

    /// Whether rest position x lies within the envelope's reach (ENVELOPE_SIGMAS along each axis).
    pub fn reaches(&self, x: DVec2) -> bool {
        let (u, v) = self.normalized(x);
        u.abs() < ENVELOPE_SIGMAS && v.abs() < ENVELOPE_SIGMAS
    }

    /// Rest position x in sigmas along the envelope's two axes.
    fn normalized(&self, x: DVec2) -> (f64, f64) {
        let r = x - self.centre;
        (r.dot(self.axis) / self.sigma[0], r.dot(self.axis.perp()) / self.sigma[1])
    }

    /// The envelope at rest position x (envelope_at) and its gradient.
    pub fn envelope(&self, x: DVec2) -> (f64, DVec2) {
        let (u, v) = self.normalized(x);
        let (e, de_du, de_dv) = envelope_at(u, v);
        (e, self.axis * (de_du / self.sigma[0]) + self.axis.perp() * (de_dv / self.sigma[1]))
    }

    /// Adds this packet's displacement and tangents at rest position x to `sum`: a trochoid's,
    /// horizontal direction a E sin(theta) and vertical a E cos(theta), with the envelope's own
    /// gradient in the derivatives.
    pub fn add_to(&self, x: DVec2, sum: &mut SurfaceSum) {
        let (e, grad) = self.envelope(x);
        let theta = self.phase - self.k * self.direction.dot(x - self.centre);
        let (sin, cos) = theta.sin_cos();
        let (a, d) = (self.amplitude, self.direction);
        sum.displacement += DVec3::new(d.x * a * e * sin, d.y * a * e * sin, a * e * cos);
        // d/dx_j of a E sin(theta) = a (dE/dx_j sin + E cos (-k d_j)), and of a E cos(theta)
        // = a (dE/dx_j cos + E sin k d_j).
        let horizontal = |j: f64, g: f64| a * (g * sin - e * cos * self.k * j);
        let vertical = |j: f64, g: f64| a * (g * cos + e * sin * self.k * j);
        let (hx, hy) = (horizontal(d.x, grad.x), horizontal(d.y, grad.y));
        sum.tx += DVec3::new(d.x * hx, d.y * hx, vertical(d.x, grad.x));
        sum.ty += DVec3::new(d.x * hy, d.y * hy, vertical(d.y, grad.y));
    }

    /// The envelope's factor in its slope variance at rest position x: along each axis its
    /// window times the row's envelope sum where the row is in phase (`in_phase`), else the
    /// window's square.
    pub fn variance_envelope(&self, x: DVec2) -> f64 {
        let (u, v) = self.normalized(x);
        let factor = |t: f64, in_phase: Option<f64>| {
            let w = window(t).0;
            match in_phase {
                Some(row_sum) => w * row_sum,
                None => w * w,
            }
        };
        factor(u, self.in_phase[0]) * factor(v, self.in_phase[1])
    }

    /// The square of the slope amplitude it leaves to the BRDF at rest position x where no scale
    /// resolves it: (k a)^2 times `variance_envelope` ((k a E)^2 for a lone packet).
    pub fn unresolved_slope2(&self, x: DVec2) -> f64 {
        (self.k * self.amplitude).powi(2) * self.variance_envelope(x)
    }

    /// Its slope variance at rest position x where no scale resolves it (the BRDF's share),
    /// along and across `wind` (a unit vector): a trochoid's 1 - sqrt(1 - s^2) of
    /// s^2 = `unresolved_slope2`, split by the squared cosine and sine of its direction to the
    /// wind, as a train's.
    pub fn slope_variance(&self, x: DVec2, wind: DVec2) -> [f64; 2] {
        let v = trochoid_slope_variance(self.unresolved_slope2(x));
        let c = self.direction.dot(wind);
        [c * c * v, (1.0 - c * c) * v]
    }
}

/// The packets alive at one time, within a bound on their number.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PacketField {
    pub packets: Vec<Packet>,
    /// The energy (Packet::energy) of those the bound left out, and of all the sources made.
    pub dropped_energy: f64,
    pub total_energy: f64,
}

impl PacketField {
    /// At most `max` of `candidates`: the weakest (least energy) are left out first, which the
    /// spreading and damping of every source make its oldest. Ties keep the earlier candidate.
    pub fn bounded(mut candidates: Vec<Packet>, max: usize) -> Self {
        let total_energy = candidates.iter().map(Packet::energy).sum();
        let mut dropped_energy = 0.0;
        if candidates.len() > max {
            // Strongest first; a stable sort keeps ties in the sources' order.
            candidates.sort_by(|a, b| b.energy().total_cmp(&a.energy()));
            dropped_energy = candidates[max..].iter().map(Packet::energy).sum();
            candidates.truncate(max);
        }
        PacketField { packets: candidates, dropped_energy, total_energy }
    }

    /// The same packets with `eye` as the frame's origin (the trains' and the shaders' frame:
    /// rest positions count from the point below the eye).
    pub fn relative_to(&self, eye: DVec2) -> PacketField {
        let packets = self.packets.iter().map(|p| Packet { centre: p.centre - eye, ..*p }).collect();
        PacketField { packets, ..*self }
    }

    /// The longest packet's wavelength (m); 0 without packets.
    pub fn longest_wavelength(&self) -> f64 {
        self.packets.iter().map(Packet::wavelength).fold(0.0, f64::max)
    }

    /// The packets' displacement and tangents at rest position x.
    pub fn surface(&self, x: DVec2) -> SurfaceSum {
        let mut sum = SurfaceSum::default();
        for p in self.packets.iter().filter(|p| p.reaches(x)) {
            p.add_to(x, &mut sum);
        }
        sum
    }

    /// The packets' height at rest position x (their vertical displacement).
    pub fn height(&self, x: DVec2) -> f64 {
        self.surface(x).displacement.z
    }

    /// Over the square of side `side` m from `corner`, sampled `per_side` times along each side:
    /// the mean square of the field's surface slope (every packet summed, its tangents) and the
    /// mean slope variance its model leaves to the BRDF where nothing resolves it (each reaching
    /// packet's `slope_variance`), the pair whose ratio says whether the model is told the
    /// surface's roughness.
    pub fn slope_variance_over(&self, corner: DVec2, side: f64, per_side: usize) -> (f64, f64) {
        let centre = corner + DVec2::splat(0.5 * side);
        // A packet reaches ENVELOPE_SIGMAS sqrt(2) = 2.8 of its sigmas from its centre at most, a
        // point of the square side / sqrt(2) from the square's.
        let near: Vec<&Packet> = self
            .packets
            .iter()
            .filter(|p| (p.centre - centre).length() < side + 4.0 * p.sigma[0].max(p.sigma[1]))
            .collect();
        let (mut surface, mut model) = (0.0, 0.0);
        for a in 0..per_side {
            for b in 0..per_side {
                let x = corner + DVec2::new(a as f64 + 0.5, b as f64 + 0.5) * (side / per_side as f64);
                let mut sum = SurfaceSum::default();
                for p in near.iter().filter(|p| p.reaches(x)) {
                    p.add_to(x, &mut sum);
                    model += p.slope_variance(x, DVec2::X).iter().sum::<f64>();
                }
                let normal = (DVec3::X + sum.tx).cross(DVec3::Y + sum.ty);
                surface += (normal.x * normal.x + normal.y * normal.y) / (normal.z * normal.z);
            }
        }
        let samples = (per_side * per_side) as f64;
        (surface / samples, model / samples)
    }

    /// The packets' whole slope variance at rest position x, along and across `wind` (a unit
    /// vector), as if nothing resolved them, to first order: each one's `unresolved_slope2` / 2
    /// (glsl/packets.glsl packet_slope_variance).
    pub fn linear_slope_variance(&self, x: DVec2, wind: DVec2) -> [f64; 2] {
        self.packets.iter().filter(|p| p.reaches(x)).fold([0.0; 2], |sum, p| {
            let (v, c) = (0.5 * p.unresolved_slope2(x), p.direction.dot(wind));
            [sum[0] + c * c * v, sum[1] + (1.0 - c * c) * v]
        })
    }
}

/// What the sources' tests share.
#[cfg(test)]
pub(crate) mod test_support {
    use super::PacketField;
    use glam::DVec2;

    /// Where the field's height changes sign along `direction` from `origin`, between `from` and
    /// `to` m, sampled at `steps` intervals and interpolated linearly.
    pub fn zero_crossings(
        field: &PacketField,
        origin: DVec2,
        direction: DVec2,
        from: f64,
        to: f64,
        steps: usize,
    ) -> Vec<f64> {
        let at = |i: usize| from + (to - from) * i as f64 / steps as f64;
        let heights: Vec<f64> = (0..=steps).map(|i| field.height(origin + direction * at(i))).collect();
        heights
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[0] * w[1] < 0.0)
            .map(|(i, w)| from + (to - from) * (i as f64 + w[0] / (w[0] - w[1])) / steps as f64)
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn packet() -> Packet {
        Packet {
            centre: DVec2::new(3.0, -2.0),
            direction: DVec2::new(0.6, 0.8),
            k: 2.0,
            amplitude: 0.1,
            axis: DVec2::new(1.0, 0.0),
            sigma: [4.0, 2.5],
            phase: 0.7,
            in_phase: [None, None],
        }
    }

    #[test]
    fn a_packet_s_tangents_are_the_derivatives_of_its_displacement() {
        let p = packet();
        let at = |x: DVec2| {
            let mut s = SurfaceSum::default();
            p.add_to(x, &mut s);
            s
        };
        let h = 1e-6;
        for x in [DVec2::new(3.0, -2.0), DVec2::new(5.5, 0.3), DVec2::new(-1.0, -4.0)] {
            let s = at(x);
            let dx = (at(x + DVec2::X * h).displacement - at(x - DVec2::X * h).displacement) / (2.0 * h);
            let dy = (at(x + DVec2::Y * h).displacement - at(x - DVec2::Y * h).displacement) / (2.0 * h);
            assert!((s.tx - dx).length() < 1e-8, "{:?} {dx:?}", s.tx);
            assert!((s.ty - dy).length() < 1e-8, "{:?} {dy:?}", s.ty);
        }
    }

    #[test]
    fn a_packet_s_energy_is_its_envelope_s_integral() {
        // The phase-averaged 1/2 a^2 E^2 summed over a fine grid.
        let p = packet();
        let (step, mut sum) = (0.05, 0.0);
        for i in -400..=400 {
            for j in -400..=400 {
                let x = p.centre + DVec2::new(i as f64, j as f64) * step;
                let (e, _) = p.envelope(x);
                sum += 0.5 * (p.amplitude * e).powi(2) * step * step;
            }
        }
        assert!((sum / p.energy() - 1.0).abs() < 1e-3, "{sum} {}", p.energy());
    }

    /// A lattice of equal packets two sigmas apart, in phase along its rows and not across
    /// them: the variances left to the BRDF sum to those of the rows' summed amplitudes, the
    /// rows' own adding (the windows' partition of unity makes each row's sum exact).
    #[test]
    fn a_row_in_phase_leaves_the_variance_of_its_summed_amplitude() {
        let lattice: Vec<Packet> = (-4..=4)
            .flat_map(|i| (-4..=4).map(move |j| (i, j)))
            .map(|(i, j)| Packet {
                centre: DVec2::new(8.0 * i as f64, 5.0 * j as f64),
                axis: DVec2::X,
                in_phase: [Some(1.0), None],
                ..packet()
            })
            .collect();
        let (k, a) = (lattice[0].k, lattice[0].amplitude);
        for x in [DVec2::new(1.3, 0.4), DVec2::new(-5.9, 2.2), DVec2::new(3.99, -7.1)] {
            let summed: f64 = lattice.iter().map(|p| p.unresolved_slope2(x)).sum();
            // Each row (fixed j) sums to amplitude a times its across window; rows add in squares.
            let rows: f64 = (-4..=4)
                .map(|j: i32| {
                    let across = window((x.y - 5.0 * j as f64) / 2.5).0;
                    (k * a * across).powi(2)
                })
                .sum();
            assert!((summed / rows - 1.0).abs() < 1e-12, "{x}: {summed} against {rows}");
            // Lone packets leave only their squares: less between the row's packets.
            let lone: f64 = lattice.iter().map(|p| Packet { in_phase: [None; 2], ..*p }.unresolved_slope2(x)).sum();
            assert!(lone < summed, "{x}: {lone} {summed}");
        }
    }

    #[test]
    fn the_bound_leaves_out_the_weakest_and_counts_their_energy() {
        let packets: Vec<Packet> = (1..=10).map(|i| Packet { amplitude: 0.01 * i as f64, ..packet() }).collect();
        let field = PacketField::bounded(packets.clone(), 4);
        assert_eq!(field.packets.len(), 4);
        assert!(field.packets.iter().all(|p| p.amplitude >= 0.07 - 1e-12));
        let dropped: f64 = packets[..6].iter().map(Packet::energy).sum();
        assert!((field.dropped_energy - dropped).abs() < 1e-15);
        assert!((field.total_energy - packets.iter().map(Packet::energy).sum::<f64>()).abs() < 1e-15);
        assert_eq!(PacketField::bounded(packets, 20).dropped_energy, 0.0);
    }
}
