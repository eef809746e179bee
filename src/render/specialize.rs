//! Leaves out what a scene does not need: from the scene and the camera, which shader terms,
//! which stages' work and which passes and resources a frame needs. Every omission is one the
//! general renderer would compute to zero (or to nothing visible), so the picture stays the same;
//! the report lists each with its reason.

use crate::model::scene::{Scene, ShadowMapMode, SkyKind};
use crate::model::sky::SkyModel;
use crate::model::waves::WaveSet;
use crate::render::frame::{CameraFrame, GEOMETRY_STEPS, NORMAL_STEPS, RAY_HIT_SHARE};
use crate::render::passes::ocean::{Method, TrainReads};
use crate::render::renderer::{Options, Output};
use crate::render::sun_shadow::{displaced_probes, finest_pixel_step, resolving_probes};
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

/// Whether some pixel in view resolves some train into its normal (the shading pass's test, with
/// the grid's safety factor; the grazing factor only makes it stricter).
fn pixels_resolve_some_train(camera: &CameraFrame, waves: &WaveSet, width: u32, height: u32) -> bool {
    !resolving_probes(camera, waves, 1.0, NORMAL_STEPS[1] as f64, (width, height), GEOMETRY_MARGIN).is_empty()
}

/// Screen positions per axis where `farthest_sea` probes the view.
const SEA_PROBES: usize = 41;

/// The largest distance (m) from the eye to the sea anywhere in view: over a grid of rays across
/// the screen, its edges included, and the limb's distance where some ray passes above the limb
/// while others meet the sea (the limb is then in view). None where no ray meets the sea.
fn farthest_sea(camera: &CameraFrame) -> Option<f64> {
    let mut farthest: Option<f64> = None;
    let mut misses = false;
    for i in 0..SEA_PROBES * SEA_PROBES {
        let at = |j: usize| -1.0 + 2.0 * j as f64 / (SEA_PROBES - 1) as f64;
        match camera.sea_hit(camera.ray([at(i % SEA_PROBES), at(i / SEA_PROBES)])) {
            Some(hit) => farthest = Some(farthest.unwrap_or(0.0).max(hit.point.length())),
            None => misses = true,
        }
    }
    farthest.map(|d| if misses { d.max(camera.limb_c().sqrt()) } else { d })
}

/// The air's optical depth below which the aerial perspective is left out: the in-scatter, about
/// that depth times the sky's radiance, and the loss stay under a thousandth of what the sea sends,
/// which reflects at least R0 = 2% of the sky (Fresnel at normal incidence): 1e-3 x 0.02.
const AERIAL_DEPTH: f64 = 2e-5;

/// The options a frame of `scene` needs, starting from `requested` (which it only narrows), and
/// what was left out. `width`, `height` are the output size.
pub fn plan(scene: &Scene, waves: &WaveSet, width: u32, height: u32, requested: Options) -> (Options, Vec<Omission>) {
    let mut options = requested;
    let mut omitted = Vec::new();
    let mut omit = |what: &str, why: String| omitted.push(Omission { what: what.into(), why });
    let sky = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
    let physical = scene.sky.model == SkyKind::Physical;
    options.shader.sky_physical = physical;
    // The physical sky's sun goes when the planet hides the disc's centre from every visible sea
    // point; its night is where astronomical twilight ends there (the sun 18 degrees down,
    // Preetham's fade too): the sunlight the air still scatters is then below the night sky's own
    // light. A visible point lies at most the eye's dip of arc from the point below the eye, so
    // its sun stands at most that much higher (the frame's eye is never lower than the scene's,
    // so it sees at least as far).
    let dip_deg = scene.planet.dip(scene.camera.height_m).to_degrees();
    let highest_sun_deg = scene.sun.elevation_deg + dip_deg;
    let sun_dark = if physical { highest_sun_deg < 0.0 } else { sky.sun_radiance.iter().all(|&l| l == 0.0) };
    let night = if physical { highest_sun_deg <= -18.0 } else { sky.sky_scale == 0.0 };
    let terms = &mut options.shader.terms;
    if terms.sun && sun_dark {
        terms.sun = false;
        omit("sun term", format!("the sun is {:.1} degrees below every visible sea point's horizon", -highest_sun_deg));
    }
    if terms.sky && night {
        terms.sky = false;
        omit(
            "sky term",
            "night: the sun is more than 18 degrees below every visible sea point's horizon, the sky is dark".into(),
        );
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
    // The share of the reflections that enter the sea again (the full method's refracted term) is
    // read from the map too; the sky seen directly is not (the eye's own table, or Preetham's).
    let sea_reads_map = options.shader.terms.sea && options.shader.method == Method::Full;
    let map_read = options.shader.terms.sky || sea_reads_map;
    if !map_read && options.sky_map {
        options.sky_map = false;
        omit(
            "sky map and its mip chain (512x512, 10 levels)",
            "nothing samples it: no sky term, no refracted light it feeds".into(),
        );
    }
    let k = options.ssaa;
    let camera = CameraFrame::new(scene, waves, width * k, height * k);
    // Why a scale resolves nothing: the longest train against the samples it would need.
    let too_short = |scale: &str, unresolved: f32, samples: &str| {
        let longest = waves.trains.last().map_or(0.0, |t| t.wavelength);
        format!(
            "no train is long enough for {scale} anywhere in view (the longest, {longest:.1} m, spans under {} {samples})",
            1.0 / unresolved
        )
    };
    // Wave packets (local waves) may be resolved where no train is: the grid and the normals stay.
    options.shader.packets |= !scene.splashes.is_empty() || !scene.wakes.is_empty();
    let packets = options.shader.packets;
    if options.shader.geometry
        && !packets
        && !options.shader.draws_nothing()
        && !grid_resolves_some_train(&camera, waves, scene.render.grid_cell_px * k as f64, width * k, height * k)
    {
        options.shader.geometry = false;
        omit("vertex displacement", too_short("the grid", GEOMETRY_STEPS[1], "cells"));
    }
    // The unfiltered baseline resolves every train everywhere.
    let resolving = options.shader.method != Method::NoFilter;
    if options.shader.normals
        && resolving
        && !packets
        && !options.shader.draws_nothing()
        && !pixels_resolve_some_train(&camera, waves, width * k, height * k)
    {
        options.shader.normals = false;
        omit("per-pixel wave normals (the shading pass's train loop)", too_short("a pixel", NORMAL_STEPS[1], "pixels"));
    }
    if options.shader.steps_to_ray_hit() && !options.shader.draws_nothing() {
        // The finest footprint in view resolves the most; its cut taken GEOMETRY_MARGIN times
        // finer still, as the probes are a sample of the screen.
        let finest = finest_pixel_step(&camera, (width * k, height * k));
        let share =
            finest.map_or(0.0, |q| waves.resolvable_slope_share(q / (NORMAL_STEPS[1] as f64 * GEOMETRY_MARGIN)));
        if share <= RAY_HIT_SHARE[0] {
            options.shader.ray_hit = false;
            omit(
                "the step to where each pixel's ray meets the sea (its gate and train loop)",
                format!(
                    "no pixel in view can resolve more than {:.0}% of the slope variance, and the step starts at {:.0}%",
                    100.0 * share,
                    100.0 * RAY_HIT_SHARE[0]
                ),
            );
        }
    }
    if physical && options.shader.aerial && !options.shader.draws_nothing() {
        let atm = scene.atmosphere();
        let extinction = atm.coefficients(0.0).extinction.into_iter().fold(0.0, f64::max);
        // Sea-level air is the densest a path to the sea crosses.
        let farthest = farthest_sea(&camera).unwrap_or(0.0);
        if extinction * farthest < AERIAL_DEPTH {
            options.shader.aerial = false;
            omit(
                "aerial perspective (its pass and atlases)",
                format!(
                    "the farthest sea in view is {farthest:.1} m away: the air's optical depth to it is under {AERIAL_DEPTH:.0e}"
                ),
            );
        }
    }
    if let (true, Some(why)) =
        (options.shader.shadow, options.shader.shadow_map_unneeded(scene.render.shadow_map, options.casts_shadows()))
    {
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
        let mut parts = vec![
            options.shader.method.name().to_owned(),
            format!("terms: {}", if terms.is_empty() { "none".to_owned() } else { terms.join(", ") }),
            match (options.shader.geometry, options.shader.normals) {
                (true, _) => "displaced",
                (false, true) => "flat grid",
                (false, false) => "flat grid, no per-pixel normals",
            }
            .to_owned(),
            match options.shader.train_reads {
                TrainReads::Blocks => "wave table read in blocks",
                TrainReads::PerTrain => "wave table read per train",
            }
            .to_owned(),
        ];
        if options.shader.draws_glints() {
            parts.push("sun glints".to_owned());
        }
        names.push(format!("ocean ({})", parts.join("; ")));
    }
    if options.shader.background {
        names.push("sky".to_owned());
    }
    if options.shader.shadow && !options.shader.draws_nothing() {
        names.push("sun shadow".to_owned());
    }
    if options.shader.reflections.screen() && !options.shader.draws_nothing() {
        names.push("reflection sources".to_owned());
    }
    if options.shader.reflections.planar() && !options.shader.draws_nothing() {
        names.push("planar reflection".to_owned());
        // Its tiles sorted where the mirror is the only reflection read (passes/planar_tiles.rs).
        if options.shader.planar_tiles && !options.shader.reflections.screen() {
            names.push("planar tiles".to_owned());
        }
    }
    if options.ssaa > 1 {
        names.push("resolve".to_owned());
    }
    match options.output {
        Output::Readback => names.push("tonemap".to_owned()),
        Output::Host(host) => {
            if host.in_place.is_none() {
                names.push(if host.copies() { "host copy" } else { "composite" }.to_owned());
            }
            if host.formats.ldr.is_some() {
                names.push("host tonemap".to_owned());
            }
        }
    }
    names
}
