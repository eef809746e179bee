//! Scene files (TOML). Every key has a unit in its name, a default (the authors' demo values)
//! and an allowed range; unknown keys, malformed TOML and out-of-range values are errors.

use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::Path;

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
    /// Preetham turbidity: 2 very clear, 3 clear, 6 hazy.
    pub turbidity: f64,
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
    pub lambda_max_m: f64,
    pub seed: u64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Render {
    /// Projected-grid cell size in pixels.
    pub grid_cell_px: f64,
    /// Tone-mapping exposure per kcd/m^2 of radiance: display = 1 - exp(-exposure L).
    pub exposure: f64,
    pub time_s: f64,
    /// Maximum anisotropy of the sky-map sampler (1 = trilinear only).
    pub sky_anisotropy: f64,
}

#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    pub camera: Camera,
    pub sun: Sun,
    pub sky: Sky,
    pub wind: Wind,
    pub waves: Waves,
    pub render: Render,
}

impl Default for Camera {
    fn default() -> Self {
        Self { height_m: 6.0, pitch_deg: 0.0, yaw_deg: 0.0, fov_y_deg: 60.0 }
    }
}
impl Default for Sun {
    fn default() -> Self {
        Self { elevation_deg: 3.0, azimuth_deg: 0.0 }
    }
}
impl Default for Sky {
    fn default() -> Self {
        Self { turbidity: 2.5 }
    }
}
impl Default for Wind {
    fn default() -> Self {
        Self { speed_mps: 10.0, direction_deg: 0.0 }
    }
}
impl Default for Waves {
    fn default() -> Self {
        Self { count: 60, lambda_min_m: 0.02, lambda_max_m: 30.0, seed: 1 }
    }
}
impl Default for Render {
    fn default() -> Self {
        Self { grid_cell_px: 8.0, exposure: 0.1, time_s: 0.0, sky_anisotropy: 1.0 }
    }
}

/// Largest number of wave trains (shader loops and the wave buffer are sized for it).
pub const MAX_WAVES: u32 = 256;

impl Scene {
    pub fn load(path: &Path) -> Result<Scene> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::Scene { file: file.clone(), message: format!("cannot read: {e}") })?;
        Scene::parse(&text, &file)
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
        scene.validate().map_err(|message| Error::Scene { file: file.to_owned(), message })?;
        Ok(scene)
    }

    pub fn validate(&self) -> Result<(), String> {
        let c = &self.camera;
        in_range("camera.height_m", c.height_m, Bound::Open(0.0), Bound::Closed(100_000.0))?;
        in_range("camera.pitch_deg", c.pitch_deg, Bound::Closed(-90.0), Bound::Closed(90.0))?;
        in_range("camera.yaw_deg", c.yaw_deg, Bound::Closed(-360.0), Bound::Closed(360.0))?;
        // Beyond these the projection loses single precision (tan overflows or 1/tan does).
        in_range("camera.fov_y_deg", c.fov_y_deg, Bound::Closed(0.01), Bound::Closed(179.0))?;
        in_range("sun.elevation_deg", self.sun.elevation_deg, Bound::Closed(-90.0), Bound::Closed(90.0))?;
        in_range("sun.azimuth_deg", self.sun.azimuth_deg, Bound::Closed(-360.0), Bound::Closed(360.0))?;
        // Preetham's fit covers turbidities 2 to 10; below 1.7 its zenith chromaticity leaves the gamut.
        in_range("sky.turbidity", self.sky.turbidity, Bound::Closed(1.7), Bound::Closed(10.0))?;
        in_range("wind.speed_mps", self.wind.speed_mps, Bound::Closed(0.0), Bound::Closed(60.0))?;
        in_range("wind.direction_deg", self.wind.direction_deg, Bound::Closed(-360.0), Bound::Closed(360.0))?;
        let w = &self.waves;
        if w.count == 0 || w.count > MAX_WAVES {
            return Err(format!("waves.count = {} is out of range [1, {MAX_WAVES}]", w.count));
        }
        in_range("waves.lambda_min_m", w.lambda_min_m, Bound::Closed(1e-3), Bound::Closed(1e4))?;
        in_range("waves.lambda_max_m", w.lambda_max_m, Bound::Closed(1e-3), Bound::Closed(1e4))?;
        if w.lambda_min_m >= w.lambda_max_m && w.count > 1 {
            return Err(format!(
                "waves.lambda_min_m = {} must be below waves.lambda_max_m = {}",
                w.lambda_min_m, w.lambda_max_m
            ));
        }
        let r = &self.render;
        in_range("render.grid_cell_px", r.grid_cell_px, Bound::Closed(1.0), Bound::Closed(64.0))?;
        in_range("render.exposure", r.exposure, Bound::Open(0.0), Bound::Closed(1e4))?;
        in_range("render.time_s", r.time_s, Bound::Closed(-1e9), Bound::Closed(1e9))?;
        in_range("render.sky_anisotropy", r.sky_anisotropy, Bound::Closed(1.0), Bound::Closed(16.0))?;
        Ok(())
    }
}

enum Bound {
    Open(f64),
    Closed(f64),
}

/// Checks lo (<|<=) value (<|<=) hi; NaN fails every comparison and so is rejected too.
fn in_range(key: &str, value: f64, lo: Bound, hi: Bound) -> Result<(), String> {
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
