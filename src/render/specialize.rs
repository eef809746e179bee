//! Leaves out what a scene does not need: from the scene and the camera, which shader terms,
//! which stages' work and which passes and resources a frame needs. Every omission is one the
//! general renderer would compute to zero (or to nothing visible), so the picture stays the same;
//! the report lists each with its reason.

use crate::model::scene::{Scene, ShadowMapMode, SkyKind};
use crate::model::sky::SkyModel;
use crate::model::waves::WaveSet;
use crate::render::frame::{CameraFrame, GEOMETRY_STEPS};
use crate::render::passes::ocean::{Method, TrainReads};
use crate::render::renderer::Options;
use crate::render::sun_shadow::displaced_probes;
use serde::Serialize;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Omission {
    pub what: String,
    pub why: String,
}

/// A train must be this many times past the grid's Nyquist limit at every probe before the
/// vertex stage's displacement is left out (the probes are a sample of the screen).
const GEOMETRY_MARGIN: f64 = 2.0;

/// Whether some train can be displaced by the grid somewhere in view (sun_shadow::displaced_probes
/// with a safety factor).
fn grid_resolves_some_train(camera: &CameraFrame, waves: &WaveSet, cell_px: f64, width: u32, height: u32) -> bool {
    !displaced_probes(camera, waves, cell_px, (width, height), GEOMETRY_MARGIN).is_empty()
}

/// The options a frame of `scene` needs, starting from `requested` (which it only narrows), and
/// what was left out. `width`, `height` are the output size.
pub fn plan(scene: &Scene, waves: &WaveSet, width: u32, height: u32, requested: Options) -> (Options, Vec<Omission>) {
    let mut options = requested;
    let mut omitted = Vec::new();
    let mut omit = |what: &str, why: String| omitted.push(Omission { what: what.into(), why });
    let sky = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
    let physical = scene.sky.model == SkyKind::Physical;
    options.shader.sky_physical = physical;
    // The physical sky's sun goes when the planet hides the disc's centre; its night is where
    // astronomical twilight ends (the sun 18 degrees down, Preetham's fade too): the sunlight the
    // air still scatters is then below the night sky's own light.
    // Hidden: the disc's centre below the eye's geometric horizon (the frame's eye is never
    // lower than the scene's, so it sees at least as far down).
    let sun_dark = if physical {
        let (h, r) = (scene.camera.height_m, scene.planet.radius_m);
        let horizon_mu = -(h * (2.0 * r + h)).sqrt() / (r + h);
        scene.sun.elevation_deg.to_radians().sin() < horizon_mu
    } else {
        sky.sun_radiance.iter().all(|&l| l == 0.0)
    };
    let night = if physical { scene.sun.elevation_deg <= -18.0 } else { sky.sky_scale == 0.0 };
    let terms = &mut options.shader.terms;
    if terms.sun && sun_dark {
        terms.sun = false;
        omit("sun term", format!("the sun is {:.1} degrees below the horizon", -scene.sun.elevation_deg));
    }
    if terms.sky && night {
        terms.sky = false;
        omit("sky term", "night: the sun is more than 18 degrees below the horizon, the sky is dark".into());
    }
    if terms.sea && night {
        terms.sea = false;
        omit("refracted term", "night: no sky light enters the water".into());
    }
    if night && options.shader.background && sun_dark {
        options.shader.background = false;
        omit("sky behind the sea", "night: the sky and the sun are dark (cleared to black instead)".into());
    }
    if options.shader.draws_nothing() {
        omit(
            "the grid, its displacement and the per-pixel shading",
            "no term to shade and no sky behind the sea: the image is black (cleared)".into(),
        );
    }
    // The physical sky behind the sea is read from the map too, and so is the share of the
    // reflections that enter the sea again (the full method's refracted term).
    let sea_reads_map = options.shader.terms.sea && options.shader.method == Method::Full;
    let map_read = options.shader.terms.sky || sea_reads_map || (physical && options.shader.background);
    if !map_read && options.sky_map {
        options.sky_map = false;
        omit(
            "sky map and its mip chain (512x512, 10 levels)",
            "nothing samples it: no sky term, no sky behind the sea".into(),
        );
    }
    let k = options.ssaa;
    let camera = CameraFrame::new(scene, waves, width * k, height * k);
    if options.shader.geometry
        && !options.shader.draws_nothing()
        && !grid_resolves_some_train(&camera, waves, scene.render.grid_cell_px * k as f64, width * k, height * k)
    {
        options.shader.geometry = false;
        let longest = waves.trains.last().map_or(0.0, |t| t.wavelength);
        omit(
            "vertex displacement",
            format!(
                "no train is long enough for the grid anywhere in view (the longest, {longest:.1} m, spans under {} cells)",
                1.0 / GEOMETRY_STEPS[1]
            ),
        );
    }
    if let (true, Some(why)) = (options.shader.shadow, options.shader.shadow_map_unneeded(scene.render.shadow_map)) {
        options.shader.shadow = false;
        // Off is the scene's choice, not an omission: nothing requested is dropped.
        if scene.render.shadow_map != ShadowMapMode::Off {
            let size = scene.render.shadow_map_size;
            omit(&format!("sun shadow map ({size}x{size}) and its pass"), why);
        }
    }
    if options.ssaa == 1 {
        omit("resolve pass and its image", "no supersampling".into());
    }
    (options, omitted)
}

/// Names of the pipelines a renderer with `options` uses, as the report lists them.
pub fn pipelines(options: &Options) -> Vec<String> {
    let t = options.shader.terms;
    let terms: Vec<&str> =
        [("sun", t.sun), ("sky", t.sky), ("sea", t.sea)].iter().filter(|x| x.1).map(|x| x.0).collect();
    let mut names = Vec::new();
    if options.sky_map {
        names.push("sky map".to_owned());
    }
    if options.shader.draws_nothing() {
        names.push("black (cleared)".to_owned());
    } else {
        names.push(format!(
            "ocean ({}; terms: {}; {}; {})",
            options.shader.method.name(),
            if terms.is_empty() { "none".to_owned() } else { terms.join(", ") },
            if options.shader.geometry { "displaced" } else { "flat grid" },
            match options.shader.train_reads {
                TrainReads::Blocks => "wave table read in blocks",
                TrainReads::PerTrain => "wave table read per train",
            }
        ));
    }
    if options.shader.background {
        names.push("sky".to_owned());
    }
    if options.shader.shadow && !options.shader.draws_nothing() {
        names.push("sun shadow".to_owned());
    }
    if options.ssaa > 1 {
        names.push("resolve".to_owned());
    }
    names.push("tonemap".to_owned());
    names
}
