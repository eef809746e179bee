//! A scene's local waves: its `[[splash]]` events, its moving objects' wakes and its still
//! floating objects' rings (their models' drafts, packets::heave), and the budget of packets
//! alive at once (`[packets]`). `Sources::field` is the packet field at a time, a
//! function of the scene and the time alone.

use super::heave::HeavingHull;
use super::kelvin::{Wake, WakeSampling};
use super::splash::{Splash, SplashSampling};
use super::PacketField;
use crate::model::scene::Bound::Closed;
use crate::model::scene::{each_in_range, Motion, Object, Scene, MAX_OBJECT_DISTANCE_M, MAX_SPEED_MPS};
use crate::model::waves::G;
use glam::DVec2;
use serde::Deserialize;
use std::f64::consts::TAU;

/// The most packets a scene may keep alive at once (`packets.max_alive`): 6 MiB of packets on
/// the GPU, and a wake of every preset object many times over.
pub const MAX_PACKETS: u32 = 1 << 17;

/// The wavelengths a local wave may have (m): the trains' own band (`waves.lambda_min_m`,
/// `waves.lambda_max_m`).
pub const WAVELENGTH_BAND_M: (f64, f64) = (1e-3, 1e4);

/// A splash's wavenumbers span k R in [0.05, 4] (splash::K_R_RANGE): its wavelengths are
/// 2 pi R / 4 to 2 pi R / 0.05.
const SPLASH_WAVELENGTHS_PER_RADIUS: (f64, f64) = (TAU / 4.0, TAU / 0.05);

/// A wake's amplitude scale (Wake::amplitude_m) per metre of hull, where the scene gives none:
/// ours, 6 cm per metre. The drawn crests 1 to 8 hull lengths behind reach about a third of the
/// scale (the far-field law overstates the field near the hull): a 6 m launch at hull Froude
/// number 0.65 raises crests of 3 to 13 cm (examples/wake_heights.rs), a 120 m ship at 0.23 about
/// half a metre after the slow hull's weakening (Wake::amplitude_m).
pub const WAKE_AMPLITUDE_PER_HULL_M: f64 = 0.06;

/// How far behind its object a wake is drawn, in hull lengths along its slowest ray (the
/// transverse waves', which leave at half the object's speed)...
const WAKE_LENGTH_HULLS: f64 = 40.0;
/// ...and no older than this (s): a slow object's wake is otherwise minutes of packets.
const WAKE_MAX_AGE_S: f64 = 600.0;

/// A wake's components per side of its track and its packets' spacing along their chains: each
/// component's waves are two of its wavelengths per packet, and a short one's packets at least a
/// hull length apart (kelvin::WakeSampling).
const WAKE_COMPONENTS: usize = 24;
const WAKE_SPACING_WAVELENGTHS: f64 = 2.0;

/// A splash's wavenumber bands and directions: 1 536 packets a splash.
const SPLASH_SAMPLING: SplashSampling = SplashSampling { bands: 24, directions: 64 };

/// A scripted splash (`[[splash]]`): a crater of `radius_m` at `position_m` at `time_s`, whose
/// rings spread from then on (packets::splash).
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct SplashEvent {
    /// x, y in the world's horizontal frame (like camera.x_m, y_m).
    pub position_m: [f64; 2],
    pub time_s: f64,
    pub radius_m: f64,
}

/// A wake without an object of ours (`[[wake]]`): a hull moving in a straight line that the
/// scene does not draw (a host's own object, or a measurement of the wake alone).
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct WakeEvent {
    /// Where the hull is at time 0: x, y in the world's horizontal frame.
    pub position_m: [f64; 2],
    pub velocity_mps: [f64; 2],
    pub hull_length_m: f64,
    /// Since when it has moved (s); without it, always: a steady wake.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_s: Option<f64>,
    /// The wake's amplitude scale (m; kelvin::Wake::amplitude_m); by default
    /// WAKE_AMPLITUDE_PER_HULL_M times the hull's length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude_m: Option<f64>,
}

impl WakeEvent {
    pub fn validate(&self) -> Result<(), String> {
        each_in_range("position_m", &self.position_m, Closed(-MAX_OBJECT_DISTANCE_M), Closed(MAX_OBJECT_DISTANCE_M))?;
        each_in_range("velocity_mps", &self.velocity_mps, Closed(-MAX_SPEED_MPS), Closed(MAX_SPEED_MPS))?;
        if DVec2::from(self.velocity_mps).length() == 0.0 {
            return Err("velocity_mps = [0, 0]: a wake needs a moving hull".into());
        }
        check_hull(self.velocity_mps, Some(self.hull_length_m), self.start_s, ("amplitude_m", self.amplitude_m))
    }
}

/// The budget of packets alive at once (`[packets]`).
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct PacketBudget {
    /// Past it, the weakest packets (the oldest, by the sources' spreading and damping) are left
    /// out and their energy reported.
    pub max_alive: u32,
}

impl Default for PacketBudget {
    fn default() -> Self {
        PacketBudget { max_alive: 16_384 }
    }
}

impl PacketBudget {
    pub fn validate(&self) -> Result<(), String> {
        if !(1..=MAX_PACKETS).contains(&self.max_alive) {
            return Err(format!("packets.max_alive = {} is out of range [1, {MAX_PACKETS}]", self.max_alive));
        }
        Ok(())
    }
}

fn in_band(what: &str, shortest: f64, longest: f64) -> Result<(), String> {
    let (lo, hi) = WAVELENGTH_BAND_M;
    if shortest >= lo && longest <= hi {
        Ok(())
    } else {
        Err(format!("{what} makes waves {shortest:.4} to {longest:.4} m long, outside the model's band [{lo}, {hi}] m"))
    }
}

impl SplashEvent {
    pub fn validate(&self) -> Result<(), String> {
        each_in_range("position_m", &self.position_m, Closed(-MAX_OBJECT_DISTANCE_M), Closed(MAX_OBJECT_DISTANCE_M))?;
        if !(self.time_s >= 0.0 && self.time_s <= 1e9) {
            return Err(format!("time_s = {} is out of range [0, 1e9] (a splash's clock starts at 0)", self.time_s));
        }
        if !(self.radius_m > 0.0 && self.radius_m.is_finite()) {
            return Err(format!("radius_m = {} must be a positive length", self.radius_m));
        }
        let (short, long) = SPLASH_WAVELENGTHS_PER_RADIUS;
        in_band(&format!("radius_m = {}", self.radius_m), short * self.radius_m, long * self.radius_m)
    }

    fn splash(&self) -> Splash {
        Splash { position: DVec2::from(self.position_m), time_s: self.time_s, radius_m: self.radius_m }
    }
}

/// The checks on an object's wake keys (called from Object::validate).
pub fn validate_wake(object: &Object) -> Result<(), String> {
    let amplitude = ("wake_amplitude_m", object.wake_amplitude_m);
    check_hull(object.velocity_mps, object.hull_length_m, object.start_s, amplitude)
}

/// The checks a moving hull's keys share; `amplitude` is the amplitude's key and value.
fn check_hull(
    velocity_mps: [f64; 2],
    hull_length_m: Option<f64>,
    start_s: Option<f64>,
    amplitude: (&str, Option<f64>),
) -> Result<(), String> {
    if let Some(start) = start_s {
        if !(-1e9..=1e9).contains(&start) {
            return Err(format!("start_s = {start} is out of range [-1e9, 1e9]"));
        }
    }
    if let Some(length) = hull_length_m {
        if !(length > 0.0 && length <= 1e4) {
            return Err(format!("hull_length_m = {length} is out of range (0, 10000]"));
        }
    }
    if let (key, Some(a)) = amplitude {
        if !(0.0..=100.0).contains(&a) {
            return Err(format!("{key} = {a} is out of range [0, 100]"));
        }
    }
    let speed = DVec2::from(velocity_mps).length();
    if speed > 0.0 {
        // The transverse waves, the wake's longest, are 2 pi U^2 / g long.
        let longest = TAU * speed * speed / G;
        let [x, y] = velocity_mps;
        in_band(&format!("velocity_mps = [{x}, {y}] ({speed:.1} m/s)"), WAVELENGTH_BAND_M.0, longest)?;
    }
    Ok(())
}

/// The scene's still floating objects with a draft, on the scene's trains, that radiate anything:
/// steady rings, or (where the scene has wakes or splashes) pulses.
fn heaving_hulls(scene: &Scene) -> Vec<HeavingHull> {
    let rocked = !scene.wakes.is_empty()
        || !scene.splashes.is_empty()
        || scene.objects.iter().any(|o| o.velocity_mps != [0.0, 0.0]);
    let heaves = |o: &&Object| o.motion == Motion::Floating && o.velocity_mps == [0.0, 0.0];
    let planes: Vec<_> = scene
        .objects
        .iter()
        .filter(heaves)
        .filter_map(|o| o.waterplane.filter(|p| p.draft_m > 0.0).map(|p| (o, p)))
        .collect();
    if planes.is_empty() {
        return Vec::new();
    }
    // The trains with their phases counted from the world's origin, not the eye: the rings are
    // then the same bits wherever the camera goes (the renderer compares the sources a scene
    // gives with its own every frame).
    let mut at_origin = scene.clone();
    (at_origin.camera.x_m, at_origin.camera.y_m) = (0.0, 0.0);
    let waves = crate::model::waves::generate(&at_origin);
    planes
        .into_iter()
        .map(|(o, plane)| {
            let centre = DVec2::new(o.position_m[0], o.position_m[1]);
            HeavingHull::new(&waves, centre, o.heading_deg.to_radians(), plane)
        })
        .filter(|h| rocked || !h.components.is_empty())
        .collect()
}

/// How a wake of a hull `hull` m long moving at `speed` is cut into packets.
fn wake_sampling(hull: f64, speed: f64) -> WakeSampling {
    WakeSampling {
        components: WAKE_COMPONENTS,
        spacing_wavelengths: WAKE_SPACING_WAVELENGTHS,
        min_spacing_m: hull,
        max_age_s: (2.0 * WAKE_LENGTH_HULLS * hull / speed).min(WAKE_MAX_AGE_S),
    }
}

/// What a scene's local waves come from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sources {
    pub wakes: Vec<(Wake, WakeSampling)>,
    pub splashes: Vec<Splash>,
    /// The still floating objects whose heave radiates rings: those with a draft (Scene::load
    /// takes their waterplanes from their models).
    pub hulls: Vec<HeavingHull>,
    pub max_alive: usize,
}

impl Sources {
    /// The scene's splashes and the wakes of its moving objects. Err names a moving object whose
    /// hull length is unknown (Scene::load takes it from the model; a scene built in code sets
    /// hull_length_m).
    pub fn of_scene(scene: &Scene) -> Result<Sources, String> {
        let mut wakes: Vec<(Wake, WakeSampling)> = scene
            .wakes
            .iter()
            .map(|w| {
                let velocity = DVec2::from(w.velocity_mps);
                let wake = Wake {
                    origin: DVec2::from(w.position_m),
                    velocity,
                    start_s: w.start_s,
                    hull_length_m: w.hull_length_m,
                    amplitude_m: w.amplitude_m.unwrap_or(WAKE_AMPLITUDE_PER_HULL_M * w.hull_length_m),
                };
                (wake, wake_sampling(w.hull_length_m, velocity.length()))
            })
            .collect();
        for (i, object) in scene.objects.iter().enumerate() {
            let velocity = DVec2::from(object.velocity_mps);
            let speed = velocity.length();
            if speed == 0.0 {
                continue;
            }
            let Some(hull) = object.hull_length_m else {
                return Err(format!(
                    "object {} ({}) moves (velocity_mps) and its hull length is unknown: set hull_length_m",
                    i + 1,
                    object.file.display()
                ));
            };
            let wake = Wake {
                origin: DVec2::new(object.position_m[0], object.position_m[1]),
                velocity,
                start_s: object.start_s,
                hull_length_m: hull,
                amplitude_m: object.wake_amplitude_m.unwrap_or(WAKE_AMPLITUDE_PER_HULL_M * hull),
            };
            wakes.push((wake, wake_sampling(hull, speed)));
        }
        Ok(Sources {
            wakes,
            splashes: scene.splashes.iter().map(SplashEvent::splash).collect(),
            hulls: heaving_hulls(scene),
            max_alive: scene.packets.max_alive as usize,
        })
    }

    /// `of_scene`, its error a scene error naming `file`.
    pub fn of_named_scene(scene: &Scene, file: &str) -> crate::error::Result<Sources> {
        Self::of_scene(scene).map_err(|message| crate::error::Error::Scene { file: file.into(), message })
    }

    /// Whether the scene has any local wave source (else the packet passes and terms are left
    /// out).
    pub fn is_empty(&self) -> bool {
        self.wakes.is_empty() && self.splashes.is_empty() && self.hulls.is_empty()
    }

    /// The packets alive at time t, within the budget.
    pub fn field(&self, t: f64) -> PacketField {
        let mut candidates = Vec::new();
        for (wake, sampling) in &self.wakes {
            candidates.extend(wake.packets(t, sampling));
        }
        for splash in &self.splashes {
            candidates.extend(splash.packets(t, &SPLASH_SAMPLING));
        }
        // The hulls' rings: steady, and the pulses the wakes and splashes rock them into.
        let rings: Vec<_> = self.hulls.iter().flat_map(|hull| hull.packets(t, &candidates)).collect();
        candidates.extend(rings);
        // No packet without amplitude takes a place in the budget.
        candidates.retain(|p| p.amplitude > 0.0);
        PacketField::bounded(candidates, self.max_alive)
    }
}
