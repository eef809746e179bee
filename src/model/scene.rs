//! Scene files (TOML). Every key has a unit in its name, a default (the authors' demo values)
//! and an allowed range; unknown keys, malformed TOML and out-of-range values are errors.
//! Azimuths and yaws are angles on a circle: any finite value is accepted and wrapped into
//! (-180, 180]. Elevations and pitches are limited to [-90, 90], where they mean something.

use crate::error::{Error, Result};
use crate::model::packets::sources::{PacketBudget, SplashEvent, WakeEvent};
use serde::Deserialize;
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Camera {
    /// Height of the eye above the water: above mean sea level, and above the water directly
    /// under the eye where a crest lifts it.
    pub height_m: f64,
    /// Elevation of the view direction; negative looks down.
    pub pitch_deg: f64,
    /// Azimuth of the view direction, counter-clockwise from +x.
    pub yaw_deg: f64,
    /// Vertical field of view.
    pub fov_y_deg: f64,
    /// Where the eye stands over the sea (east, north). The sea is the same everywhere, so this
    /// only moves the waves past the eye (`ocean view` walks with it).
    pub x_m: f64,
    pub y_m: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sun {
    pub elevation_deg: f64,
    /// Counter-clockwise from +x, like the camera's yaw.
    pub azimuth_deg: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Sky {
    /// Which model lights the scene and is seen behind it.
    pub model: SkyKind,
    /// Preetham turbidity: 2 very clear, 3 clear, 6 hazy (the `preetham` model).
    pub turbidity: f64,
    /// The physical model's atmosphere (`[sky.atmosphere]`; Earth's by default).
    pub atmosphere: crate::model::atmosphere::AtmosphereParams,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SkyKind {
    /// Preetham, Shirley & Smits (1999): analytic, fitted to clear skies with the sun well up.
    Preetham,
    /// Precomputed scattering in a spherical atmosphere (src/model/atmosphere.rs).
    Physical,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Wind {
    /// Wind speed driving the Pierson-Moskowitz spectrum.
    pub speed_mps: f64,
    /// Direction the wind blows towards, counter-clockwise from +x.
    pub direction_deg: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Waves {
    pub count: u32,
    pub lambda_min_m: f64,
    /// The longest wavelength, in metres or from the wind (`"peak"`); see `Scene::lambda_max_m`.
    pub lambda_max_m: LongestWave,
    pub seed: u64,
}

/// The longest wavelength of the trains: a length, or the peak of the wind's spectrum.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LongestWave {
    Metres(f64),
    /// The wavelength at the Pierson-Moskowitz spectrum's peak for the scene's wind speed.
    Peak,
}

impl LongestWave {
    /// The key's value as a scene file spells it.
    pub fn describe(self) -> String {
        match self {
            LongestWave::Metres(m) => m.to_string(),
            LongestWave::Peak => "\"peak\"".to_owned(),
        }
    }
}

impl serde::Serialize for LongestWave {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            LongestWave::Metres(m) => serializer.serialize_f64(*m),
            LongestWave::Peak => serializer.serialize_str("peak"),
        }
    }
}

impl<'de> Deserialize<'de> for LongestWave {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = LongestWave;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a wavelength in metres or \"peak\" (the wind spectrum's peak)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<LongestWave, E> {
                Ok(LongestWave::Metres(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<LongestWave, E> {
                Ok(LongestWave::Metres(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<LongestWave, E> {
                Ok(LongestWave::Metres(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<LongestWave, E> {
                match v {
                    "peak" => Ok(LongestWave::Peak),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Render {
    /// Projected-grid cell size in pixels.
    pub grid_cell_px: f64,
    /// Tone-mapping exposure per kcd/m^2 of radiance: display = curve(exposure L). Without it
    /// and without `ev100`, the exposure is automatic.
    pub exposure: Option<f64>,
    /// Exposure value at ISO 100: a number puts the white (the curve's 1) at 1.2 2^EV100 cd/m^2,
    /// "auto" takes it from each frame's log-average luminance (exposure.rs). Instead of `exposure`.
    pub ev100: Option<Ev100>,
    /// The display's curve from exposed radiance to [0, 1].
    pub tone_curve: ToneCurve,
    pub time_s: f64,
    /// Maximum anisotropy of the sky-map sampler (1 = trilinear only).
    pub sky_anisotropy: f64,
    /// The sun's shadow map of the displaced grid (passes/shadow.rs): "auto" draws it wherever
    /// the sun is up and the grid resolves some train, "on" insists (an error with the sun down,
    /// a logged omission where nothing is displaced), "off" (the default, for its cost under the
    /// default scene's low sun: docs/results.md, "Sun shadows") leaves the waves' shadows to the
    /// BRDF's statistical term alone.
    pub shadow_map: ShadowMapMode,
    /// The shadow map's texels per side.
    pub shadow_map_size: u32,
    /// How the sea reflects the scene's objects (`--reflections` overrides it): the object
    /// presets name the method `bench error-vs-time` found best for them.
    pub reflections: Reflections,
}

/// How the sea reflects a host's objects (`render.reflections`, `--reflections`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Reflections {
    /// The sky's reflection alone.
    None,
    /// Each pixel's reflected ray traced in screen space against the objects' depth
    /// (glsl/shade.glsl local_reflection): only what the screen holds.
    Screen,
    /// The objects drawn again, mirrored about the sea (embed::Ocean::record_planar), read along
    /// each pixel's reflected ray (glsl/shade.glsl planar_reflection): what the screen does not
    /// hold too, with the mirror's error where the sea is far from flat.
    Planar,
    /// The mirror's where its images hold an object, the screen's trace where they hold none (an
    /// object a host draws but does not mirror).
    Both,
}

impl Reflections {
    /// Whether the screen-space trace runs.
    pub fn screen(self) -> bool {
        matches!(self, Reflections::Screen | Reflections::Both)
    }

    /// Whether the mirror pass runs.
    pub fn planar(self) -> bool {
        matches!(self, Reflections::Planar | Reflections::Both)
    }

    pub fn name(self) -> &'static str {
        match self {
            Reflections::None => "none",
            Reflections::Screen => "screen",
            Reflections::Planar => "planar",
            Reflections::Both => "both",
        }
    }
}

/// Whether the sun's shadow map is drawn (`render.shadow_map`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ShadowMapMode {
    Auto,
    On,
    Off,
}

/// The shadow map's allowed sides (texels): below 64 it resolves no wave, above 8192 it alone
/// would take 256 MiB.
pub const SHADOW_MAP_SIZES: (u32, u32) = (64, 8192);

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    pub planet: Planet,
    pub camera: Camera,
    pub sun: Sun,
    pub sky: Sky,
    pub wind: Wind,
    pub waves: Waves,
    pub render: Render,
    /// Objects on the sea (`[[object]]`), drawn by the commands as a host draws its own.
    #[serde(rename = "object", skip_serializing_if = "Vec::is_empty")]
    pub objects: Vec<Object>,
    /// Scripted splashes (`[[splash]]`), whose rings are drawn as wave packets.
    #[serde(rename = "splash", skip_serializing_if = "Vec::is_empty")]
    pub splashes: Vec<SplashEvent>,
    /// Wakes of hulls the scene does not draw (`[[wake]]`).
    #[serde(rename = "wake", skip_serializing_if = "Vec::is_empty")]
    pub wakes: Vec<WakeEvent>,
    /// The budget of wave packets alive at once (wakes and rings).
    pub packets: PacketBudget,
}

/// An object on the sea (`[[object]]`): a glTF model placed in the world.
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// The glTF 2.0 file (.gltf or .glb); relative to the scene file.
    pub file: PathBuf,
    /// x, y in the world's horizontal frame (like camera.x_m, y_m), z above mean sea level. On
    /// the planet, the point (x, y) of the plane tangent below the eye is carried straight down
    /// to the sphere, and the object stands along the sphere's normal there.
    #[serde(default)]
    pub position_m: [f64; 3],
    /// The model's +x (its bow) counter-clockwise from +x, like camera.yaw_deg.
    #[serde(default)]
    pub heading_deg: f64,
    /// The bow raised.
    #[serde(default)]
    pub pitch_deg: f64,
    /// The starboard side (right of the bow) raised.
    #[serde(default)]
    pub roll_deg: f64,
    #[serde(default = "unit_scale")]
    pub scale: f64,
    #[serde(default)]
    pub motion: Motion,
    /// At time t the object is at position_m + velocity_mps t (from start_s on): a moving
    /// object sheds a Kelvin wake (model::packets::kelvin).
    #[serde(default)]
    pub velocity_mps: [f64; 2],
    /// Since when it has moved (s); before, it stood at position_m + velocity_mps start_s.
    /// Without it, it has always moved: its wake is steady.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_s: Option<f64>,
    /// Its waterline length, the wake's scale (m); Scene::load takes its model's length along
    /// its bow (x), times scale, where it is not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hull_length_m: Option<f64>,
    /// Its wake's amplitude scale (m, kelvin::Wake::amplitude_m); by default
    /// sources::WAKE_AMPLITUDE_PER_HULL_M times the hull's length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wake_amplitude_m: Option<f64>,
    /// Not a key: its model's waterplane and draft (placement::waterplane), taken by Scene::load
    /// for a floating object that stands still, whose heave radiates rings (packets::heave).
    #[serde(skip)]
    pub waterplane: Option<crate::model::floating::Waterplane>,
}

fn unit_scale() -> f64 {
    1.0
}

/// How an object moves with the sea.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Motion {
    /// Where the scene puts it (a pier, a moored mark).
    #[default]
    Fixed,
    /// Heave, pitch and roll follow the waves under its waterplane (model::floating), on top of
    /// its own position and attitude.
    Floating,
}

/// The most objects a scene may place (a harbour of buoys is 200).
pub const MAX_OBJECTS: usize = 4096;

/// How far from the world's origin an object may stand: the camera's own range.
pub(crate) const MAX_OBJECT_DISTANCE_M: f64 = 1e7;

/// The fastest a hull may move along each axis (m/s): the water speed record is 142 m/s.
pub(crate) const MAX_SPEED_MPS: f64 = 150.0;

/// The scales an object may take: from a millimetre's thousandth of a 1 m model to a 1 m model
/// blown up to 1000 km.
pub const OBJECT_SCALES: (f64, f64) = (1e-6, 1e6);

/// The planet the sea covers (`[planet]`): its radius is the sea's mean level and the
/// atmosphere's ground.
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Planet {
    pub radius_m: f64,
}

impl Planet {
    /// Distance along a ray of depression sine `d` (-z of the unit ray) from an eye `height` m
    /// above the sea to the planet's sphere, None where it misses (glsl/planet.glsl, the same
    /// product forms: in f64 they keep full precision from 5 cm to beyond geostationary orbit).
    pub fn ray_distance(&self, height: f64, d: f64) -> Option<f64> {
        let (r, rh) = (self.radius_m, self.radius_m + height);
        let c = height * (2.0 * r + height);
        let s = c.sqrt() / rh;
        (d > s).then(|| c / (rh * d + rh * ((d - s) * (d + s)).sqrt()))
    }

    /// The horizon's dip below level from `height` m up: arccos(R / (R + H)), formed as
    /// atan(sqrt(H (2R + H)) / R), which keeps its precision where the cosine is 1 to f64.
    pub fn dip(&self, height: f64) -> f64 {
        (height * (2.0 * self.radius_m + height)).sqrt().atan2(self.radius_m)
    }
}

impl Default for Planet {
    fn default() -> Self {
        Self { radius_m: crate::model::atmosphere::EARTH_RADIUS_M }
    }
}

impl Default for Camera {
    fn default() -> Self {
        Self { height_m: 6.0, pitch_deg: 0.0, yaw_deg: 0.0, fov_y_deg: 60.0, x_m: 0.0, y_m: 0.0 }
    }
}
impl Default for Sun {
    fn default() -> Self {
        Self { elevation_deg: 3.0, azimuth_deg: 0.0 }
    }
}
impl Default for Sky {
    fn default() -> Self {
        Self { model: SkyKind::Physical, turbidity: 2.5, atmosphere: Default::default() }
    }
}
impl Default for Wind {
    fn default() -> Self {
        Self { speed_mps: 10.0, direction_deg: 0.0 }
    }
}
impl Default for Waves {
    fn default() -> Self {
        Self { count: 60, lambda_min_m: 0.02, lambda_max_m: LongestWave::Metres(30.0), seed: 1 }
    }
}
impl Default for Render {
    fn default() -> Self {
        Self {
            grid_cell_px: 8.0,
            exposure: None,
            ev100: None,
            tone_curve: ToneCurve::Filmic,
            time_s: 0.0,
            sky_anisotropy: 1.0,
            shadow_map: ShadowMapMode::Off,
            shadow_map_size: 1024,
            reflections: Reflections::Screen,
        }
    }
}

/// An exposure value at ISO 100, or automatic.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub enum Ev100 {
    Value(f64),
    Auto,
}

impl<'de> Deserialize<'de> for Ev100 {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> std::result::Result<Ev100, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Ev100;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an exposure value (EV100) or \"auto\"")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> std::result::Result<Ev100, E> {
                Ok(Ev100::Value(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Ev100, E> {
                Ok(Ev100::Value(v as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Ev100, E> {
                Ok(Ev100::Value(v as f64))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> std::result::Result<Ev100, E> {
                match v {
                    "auto" => Ok(Ev100::Auto),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// The display's tone curve (glsl/tone.glsl).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ToneCurve {
    /// 1 - exp(-x) per channel: the authors' demo.
    Exponential,
    /// Narkowicz (2015)'s fit of the ACES filmic curve on luminance, hue kept, desaturated only as
    /// much as the brightest channel needs to stay displayable.
    Filmic,
}

/// The exposure a frame's tone mapping uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Exposure {
    /// Display scale per kcd/m^2.
    PerKcd(f64),
    /// From the frame's log-average luminance.
    Auto,
}

/// A white at 1.2 2^EV100 cd/m^2 (saturation-based speed at ISO 100; Lagarde & de Rousiers,
/// "Moving Frostbite to Physically Based Rendering", 2014) as a display scale per kcd/m^2.
pub fn ev100_to_exposure(ev100: f64) -> f64 {
    1000.0 / (1.2 * 2f64.powf(ev100))
}

impl Render {
    pub fn exposure(&self) -> Exposure {
        match (self.ev100, self.exposure) {
            (Some(Ev100::Auto), _) => Exposure::Auto,
            (Some(Ev100::Value(ev)), _) => Exposure::PerKcd(ev100_to_exposure(ev)),
            (None, Some(e)) => Exposure::PerKcd(e),
            (None, None) => Exposure::Auto,
        }
    }
}

/// Largest number of wave trains (shader loops and the wave buffer are sized for it).
pub const MAX_WAVES: u32 = 256;

impl Scene {
    pub fn load(path: &Path) -> Result<Scene> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::Scene { file: file.clone(), message: format!("cannot read: {e}") })?;
        let mut scene = Scene::parse(&text, &file)?;
        // Objects' files are named relative to the scene file.
        let dir = path.parent().unwrap_or(Path::new(""));
        for object in &mut scene.objects {
            if object.file.is_relative() {
                object.file = dir.join(&object.file);
            }
        }
        scene.resolve_hulls()?;
        Ok(scene)
    }

    /// Reads what the objects' models give the local waves, each model once: a moving object's
    /// hull length where hull_length_m is not given (the model's x extent, times scale:
    /// placement::waterplane's length), and a still floating object's waterplane and draft.
    pub fn resolve_hulls(&mut self) -> Result<()> {
        let mut bounds = std::collections::HashMap::new();
        for (i, object) in self.objects.iter_mut().enumerate() {
            let moves = object.velocity_mps != [0.0, 0.0];
            let wants_length = object.hull_length_m.is_none() && moves;
            let heaves = object.motion == Motion::Floating && !moves;
            if !(wants_length || heaves) {
                continue;
            }
            let model_bounds = match bounds.get(&object.file) {
                Some(&b) => b,
                None => {
                    let b = crate::model::gltf::load(&object.file)?.bounds;
                    bounds.insert(object.file.clone(), b);
                    b
                }
            };
            let plane = crate::model::placement::waterplane(model_bounds, object.scale);
            if heaves {
                object.waterplane = Some(plane);
            }
            if wants_length {
                let length = plane.length_m;
                if !(length > 0.0 && length <= 1e4) {
                    return Err(Error::Scene {
                        file: object.file.display().to_string(),
                        message: format!(
                            "object {} moves and its model is {length} m long along its bow (x), outside a hull's (0, 10000] m: set hull_length_m",
                            i + 1
                        ),
                    });
                }
                object.hull_length_m = Some(length);
            }
        }
        Ok(())
    }

    /// Parses and validates; `file` names the source in errors.
    pub fn parse(text: &str, file: &str) -> Result<Scene> {
        let scene: Scene = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            let message = e.message().replace('\n', " ");
            let file = match line {
                Some(line) => format!("{file} line {line}"),
                None => file.to_owned(),
            };
            Error::Scene { file, message }
        })?;
        let mut scene = scene;
        scene.validate().map_err(|message| Error::Scene { file: file.to_owned(), message })?;
        scene.wrap_angles();
        Ok(scene)
    }

    /// Wraps every azimuth into (-180, 180] degrees, so that equal directions compare equal.
    pub fn wrap_angles(&mut self) {
        self.camera.yaw_deg = wrap_degrees(self.camera.yaw_deg);
        self.sun.azimuth_deg = wrap_degrees(self.sun.azimuth_deg);
        self.wind.direction_deg = wrap_degrees(self.wind.direction_deg);
        for object in &mut self.objects {
            object.heading_deg = wrap_degrees(object.heading_deg);
        }
    }

    /// The longest wavelength in metres, with `"peak"` resolved from the wind speed.
    pub fn lambda_max_m(&self) -> f64 {
        match self.waves.lambda_max_m {
            LongestWave::Metres(m) => m,
            LongestWave::Peak => crate::model::waves::peak_wavelength(self.wind.speed_mps),
        }
    }

    /// The atmosphere on this scene's planet: `[sky.atmosphere]` with its ground at the planet's
    /// radius.
    pub fn atmosphere(&self) -> crate::model::atmosphere::AtmosphereParams {
        let r = self.planet.radius_m;
        crate::model::atmosphere::AtmosphereParams {
            bottom_radius_m: r,
            top_radius_m: r + self.sky.atmosphere.thickness_m,
            ..self.sky.atmosphere.clone()
        }
    }

    pub fn validate(&self) -> Result<(), String> {
        let c = &self.camera;
        // Up to beyond geostationary orbit (35,786 km).
        in_range("camera.height_m", c.height_m, Bound::Open(0.0), Bound::Closed(4e7))?;
        in_range("camera.pitch_deg", c.pitch_deg, Bound::Closed(-90.0), Bound::Closed(90.0))?;
        // Phases k.x are reduced in f64: at 1e7 m and k = 314 rad/m that keeps 3e-5 rad.
        in_range("camera.x_m", c.x_m, Bound::Closed(-1e7), Bound::Closed(1e7))?;
        in_range("camera.y_m", c.y_m, Bound::Closed(-1e7), Bound::Closed(1e7))?;
        finite_angle("camera.yaw_deg", c.yaw_deg)?;
        // Beyond these the projection loses single precision (tan overflows or 1/tan does).
        in_range("camera.fov_y_deg", c.fov_y_deg, Bound::Closed(0.01), Bound::Closed(179.0))?;
        in_range("sun.elevation_deg", self.sun.elevation_deg, Bound::Closed(-90.0), Bound::Closed(90.0))?;
        finite_angle("sun.azimuth_deg", self.sun.azimuth_deg)?;
        // Preetham's fit covers turbidities 2 to 10; below 1.7 its zenith chromaticity leaves the gamut.
        in_range("sky.turbidity", self.sky.turbidity, Bound::Closed(1.7), Bound::Closed(10.0))?;
        // From an asteroid's 1 km to ten times Jupiter's radius.
        in_range("planet.radius_m", self.planet.radius_m, Bound::Closed(1e3), Bound::Closed(1e9))?;
        self.atmosphere().validate().map_err(|e| format!("sky.{e}"))?;
        in_range("wind.speed_mps", self.wind.speed_mps, Bound::Closed(0.0), Bound::Closed(60.0))?;
        finite_angle("wind.direction_deg", self.wind.direction_deg)?;
        let w = &self.waves;
        if w.count == 0 || w.count > MAX_WAVES {
            return Err(format!("waves.count = {} is out of range [1, {MAX_WAVES}]", w.count));
        }
        in_range("waves.lambda_min_m", w.lambda_min_m, Bound::Closed(1e-3), Bound::Closed(1e4))?;
        let lambda_max = self.lambda_max_m();
        if w.lambda_max_m == LongestWave::Peak && self.wind.speed_mps <= 0.0 {
            return Err("waves.lambda_max_m = \"peak\" needs a wind: wind.speed_mps = 0 has no spectral peak".into());
        }
        let key = format!("waves.lambda_max_m = {}", w.lambda_max_m.describe());
        let resolved = match w.lambda_max_m {
            LongestWave::Metres(_) => String::new(),
            LongestWave::Peak => format!(" (resolved from wind.speed_mps = {})", self.wind.speed_mps),
        };
        if !(1e-3..=1e4).contains(&lambda_max) {
            return Err(format!("{key}{resolved} = {lambda_max} m is out of range [0.001, 10000]"));
        }
        if w.lambda_min_m >= lambda_max && w.count > 1 {
            return Err(format!(
                "waves.lambda_min_m = {} must be below {key}{resolved} = {lambda_max} m",
                w.lambda_min_m
            ));
        }
        let r = &self.render;
        in_range("render.grid_cell_px", r.grid_cell_px, Bound::Closed(1.0), Bound::Closed(64.0))?;
        if let Some(e) = r.exposure {
            in_range("render.exposure", e, Bound::Open(0.0), Bound::Closed(1e4))?;
        }
        if let Some(Ev100::Value(ev)) = r.ev100 {
            in_range("render.ev100", ev, Bound::Closed(-10.0), Bound::Closed(30.0))?;
        }
        if r.exposure.is_some() && r.ev100.is_some() {
            return Err("render.exposure and render.ev100 both set: give one (ev100 wins otherwise, silently)".into());
        }
        in_range("render.time_s", r.time_s, Bound::Closed(-1e9), Bound::Closed(1e9))?;
        in_range("render.sky_anisotropy", r.sky_anisotropy, Bound::Closed(1.0), Bound::Closed(16.0))?;
        let (lo, hi) = SHADOW_MAP_SIZES;
        if !(lo..=hi).contains(&r.shadow_map_size) {
            return Err(format!("render.shadow_map_size = {} is out of range [{lo}, {hi}]", r.shadow_map_size));
        }
        if r.shadow_map == ShadowMapMode::On && self.sun.elevation_deg <= 0.0 {
            return Err(format!(
                "render.shadow_map = \"on\" needs the sun above the horizon: sun.elevation_deg = {} casts no shadow on the sea (use \"auto\" or \"off\")",
                self.sun.elevation_deg
            ));
        }
        if self.objects.len() > MAX_OBJECTS {
            return Err(format!("{} [[object]] tables: at most {MAX_OBJECTS} are allowed", self.objects.len()));
        }
        for (i, object) in self.objects.iter().enumerate() {
            object.validate().map_err(|e| format!("object {} ({}): {e}", i + 1, object.file.display()))?;
        }
        for (i, splash) in self.splashes.iter().enumerate() {
            splash.validate().map_err(|e| format!("splash {}: {e}", i + 1))?;
        }
        for (i, wake) in self.wakes.iter().enumerate() {
            wake.validate().map_err(|e| format!("wake {}: {e}", i + 1))?;
        }
        self.packets.validate()
    }
}

impl Scene {
    /// Err where the scene places objects and `what` (a measurement that draws the ocean alone)
    /// would drop them.
    pub fn refuse_objects(&self, what: &str) -> Result<()> {
        match self.objects.first() {
            None => Ok(()),
            Some(first) => Err(Error::Argument(format!(
                "{what} draws no objects, and the scene places {} ([[object]] file = {:?}): `ocean render`, `animate`, `profile` and `view` draw them",
                self.objects.len(),
                first.file.display().to_string()
            ))),
        }
    }
}

impl Object {
    fn validate(&self) -> Result<(), String> {
        let d = MAX_OBJECT_DISTANCE_M;
        each_in_range("position_m", &self.position_m[..2], Bound::Closed(-d), Bound::Closed(d))?;
        // Up to a mountain's height over the sea; down to a wreck's depth.
        in_range("position_m.z", self.position_m[2], Bound::Closed(-1e4), Bound::Closed(1e4))?;
        finite_angle("heading_deg", self.heading_deg)?;
        in_range("pitch_deg", self.pitch_deg, Bound::Closed(-90.0), Bound::Closed(90.0))?;
        in_range("roll_deg", self.roll_deg, Bound::Closed(-180.0), Bound::Closed(180.0))?;
        let (lo, hi) = OBJECT_SCALES;
        in_range("scale", self.scale, Bound::Closed(lo), Bound::Closed(hi))?;
        each_in_range("velocity_mps", &self.velocity_mps, Bound::Closed(-MAX_SPEED_MPS), Bound::Closed(MAX_SPEED_MPS))?;
        crate::model::packets::sources::validate_wake(self)
    }

    /// Where the object's origin stands at time `t` (world frame, before the planet's curvature).
    pub fn position_at(&self, t: f64) -> [f64; 3] {
        let [x, y, z] = self.position_m;
        let t = self.start_s.map_or(t, |start| t.max(start));
        [x + self.velocity_mps[0] * t, y + self.velocity_mps[1] * t, z]
    }
}

/// The angle wrapped into (-180, 180] degrees; `%` on floats is exact, so nothing is lost.
pub fn wrap_degrees(angle: f64) -> f64 {
    let r = angle % 360.0; // in (-360, 360), same sign as angle
    if r > 180.0 {
        r - 360.0
    } else if r <= -180.0 {
        r + 360.0
    } else {
        r
    }
}

/// Any finite angle: it is wrapped, not limited.
fn finite_angle(key: &str, value: f64) -> Result<(), String> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(format!("{key} = {value} is not a finite angle (any finite value in degrees is wrapped)"))
    }
}

#[derive(Clone, Copy)]
pub(crate) enum Bound {
    Open(f64),
    Closed(f64),
}

/// in_range for each component of a vector key, named key.x, key.y (and key.z).
pub(crate) fn each_in_range(key: &str, values: &[f64], lo: Bound, hi: Bound) -> Result<(), String> {
    for (axis, &v) in ["x", "y", "z"].iter().zip(values) {
        in_range(&format!("{key}.{axis}"), v, lo, hi)?;
    }
    Ok(())
}

/// Checks lo (<|<=) value (<|<=) hi; NaN fails every comparison and so is rejected too.
pub(crate) fn in_range(key: &str, value: f64, lo: Bound, hi: Bound) -> Result<(), String> {
    let (lo_ok, lo_text) = match lo {
        Bound::Open(b) => (value > b, format!("({b}")),
        Bound::Closed(b) => (value >= b, format!("[{b}")),
    };
    let (hi_ok, hi_text) = match hi {
        Bound::Open(b) => (value < b, format!("{b})")),
        Bound::Closed(b) => (value <= b, format!("{b}]")),
    };
    if lo_ok && hi_ok {
        Ok(())
    } else {
        Err(format!("{key} = {value} is out of range {lo_text}, {hi_text}"))
    }
}
