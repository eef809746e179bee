//! Where the reflected sky's error comes from, band by band: the ground truth against the f64
//! quadrature of each method's model (src/measure/reference.rs) and against the method's lookup
//! on the GPU, so a band's error splits into the model's and the lookup's; and the one
//! assumption of the model the quadrature cannot test, Smith's masking, against the sea's own
//! profiles: the mean Fresnel of the facets a grazing ray really reaches first.

use crate::error::{Error, Result};
use crate::measure::bench::error_vs_time::{band_label, sea_pixels_by_band};
use crate::measure::groundtruth::GroundTruthFiles;
use crate::measure::reference::ReferenceScene;
use crate::model::masking::{self, Masking};
use crate::model::scene::{Scene, SkyKind};
use crate::model::sky::SkyModel;
use crate::model::waves::{self, WaveSet};
use crate::output::{luminance, luminance_rgb, write_text};
use crate::render::footprint::Footprint;
use crate::render::frame::CameraFrame;
use crate::render::passes::ocean::{Method, ShaderConfig, Terms};
use crate::render::renderer::{Options, Renderer};
use crate::vk::gpu::Gpu;
use std::fmt::Write as _;
use std::path::Path;

/// One band's reflected sky: the ground truth's mean luminance and each estimate's relative error.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SkyBand {
    pub band: usize,
    pub pixels: usize,
    /// Share of the band's pixels where the grid displaces some train: there the quadrature,
    /// which sees the rest plane, is not the method's model.
    pub displaced: f64,
    pub truth: f64,
    /// (f64 quadrature of the model, the GPU's lookup) relative to the truth, full then paper.
    pub full: (f64, f64),
    pub paper: (f64, f64),
}

/// The sea's own masking at one azimuth and depression of the view.
#[derive(Debug, Clone, serde::Serialize)]
pub struct MaskingRow {
    pub azimuth: &'static str,
    pub depression_deg: f64,
    pub masking: Masking,
}

pub fn run(gpu: &Gpu, scene: &Scene, scene_name: &str, reference: &Path, out_dir: &Path) -> Result<()> {
    let truth = GroundTruthFiles::load(reference)?;
    if !truth.meta.is_of(scene) {
        return Err(Error::Argument(format!(
            "reference {} was made for another scene than {scene_name}: make it with `ocean reference --scene {scene_name}`",
            reference.display()
        )));
    }
    if truth.meta.region.is_some() {
        return Err(Error::Argument(format!(
            "reference {} traces a region of its view (--region): bench sky-model takes a ground truth of the whole view",
            reference.display()
        )));
    }
    let (w, h) = (truth.meta.width, truth.meta.height);
    let wave_set = waves::generate(scene);
    let camera = CameraFrame::new(scene, &wave_set, w, h);
    let preetham = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
    let physical = (scene.sky.model == SkyKind::Physical)
        .then(|| crate::model::sky_table::SeaLevelSky::new(&scene.atmosphere(), preetham.sun_dir));
    let sky: &dyn crate::model::sky::SkyLight = match &physical {
        Some(p) => p,
        None => &preetham,
    };
    let footprint = Footprint {
        camera: &camera,
        waves: &wave_set,
        time_s: scene.render.time_s,
        width: w,
        height: h,
        packets: None,
    };
    let model = |full| ReferenceScene { footprint: Footprint { ..footprint }, sky, full };
    let (full_model, paper_model) = (model(true), model(false));
    let lookup = |method| -> Result<Vec<[f32; 4]>> {
        let shader = ShaderConfig::terms_only(Terms { sun: false, sky: true, sea: false }, method);
        let mut renderer = Renderer::new(gpu, scene, w, h, Options { shader, ..Options::default() })?;
        Ok(renderer.render(scene)?.hdr)
    };
    let (full_gpu, paper_gpu) = (lookup(Method::Full)?, lookup(Method::Paper)?);
    let sky_of = |m: &ReferenceScene, px: f64, py: f64| m.shade(px, py).map(|r| r.sky);
    let mut bands = Vec::new();
    for (b, pixels) in sea_pixels_by_band(&camera, w, h).iter().enumerate() {
        let mut sums = [0.0f64; 5];
        let (mut counted, mut displaced) = (0usize, 0usize);
        for &i in pixels {
            let (px, py) = ((i as u32 % w) as f64, (i as u32 / w) as f64);
            let (Some(f), Some(p)) = (sky_of(&full_model, px, py), sky_of(&paper_model, px, py)) else { continue };
            let values = [
                luminance(truth.sky[i]),
                luminance_rgb(f),
                luminance(full_gpu[i]),
                luminance_rgb(p),
                luminance(paper_gpu[i]),
            ];
            for (s, v) in sums.iter_mut().zip(values) {
                *s += v;
            }
            counted += 1;
            displaced += usize::from(full_model.displaced_train(scene.render.grid_cell_px, px, py).is_some());
        }
        if counted == 0 || sums[0] <= 0.0 {
            continue;
        }
        let rel = |s: f64| s / sums[0] - 1.0;
        bands.push(SkyBand {
            band: b,
            pixels: counted,
            displaced: displaced as f64 / counted as f64,
            truth: sums[0] / counted as f64,
            full: (rel(sums[1]), rel(sums[2])),
            paper: (rel(sums[3]), rel(sums[4])),
        });
    }
    let masking = profiles(&wave_set, scene.render.time_s);
    std::fs::create_dir_all(out_dir).map_err(|e| Error::io(out_dir, e))?;
    let mut text = markdown(scene_name, reference, &bands, &masking);
    text.push_str(&glint_markdown(scene, &wave_set));
    write_text(&out_dir.join("sky_model.md"), &text)?;
    Ok(())
}

/// Depressions of the view measured (degrees): the far field's 1-3 degrees to the mid field's 20.
const DEPRESSIONS_DEG: [f64; 7] = [1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 30.0];

/// The sea's own masking (src/model/masking.rs) down the wind and across it, sampled every
/// centimetre.
pub fn profiles(waves: &WaveSet, t: f64) -> Vec<MaskingRow> {
    let mut rows = Vec::new();
    for (azimuth, azimuth_deg) in [("down the wind", 0.0), ("across the wind", 90.0)] {
        let measured = masking::measure(waves, t, azimuth_deg, &DEPRESSIONS_DEG, 0.01);
        for (masking, depression_deg) in measured.into_iter().zip(DEPRESSIONS_DEG) {
            rows.push(MaskingRow { azimuth, depression_deg, masking });
        }
    }
    rows
}

/// The sun's glint against the sea's own masking (src/model/masking.rs `glint`), looking towards
/// the sun at the depressions measured; nothing where the sun is down.
fn glint_markdown(scene: &Scene, waves: &WaveSet) -> String {
    let mut s = String::new();
    if scene.sun.elevation_deg <= 0.0 {
        return s;
    }
    let azimuth = scene.sun.azimuth_deg - scene.wind.direction_deg;
    let rows = masking::glint(waves, scene.render.time_s, azimuth, scene.sun.elevation_deg, &DEPRESSIONS_DEG, 0.01);
    let _ = writeln!(
        s,
        "\nThe sun's glint, looking towards the sun ({:.1} degrees up, {azimuth:.0} degrees from the wind): among the \
         facets that mirror the eye into the sun (slope along the view within 0.2 sigma of the mirror slope, by projected \
         area), the shares seen from the eye, lit by the sun and both on the sea's own profiles, and Smith's (which the \
         sun term takes: the last column is the share both seen and lit over the height-correlated 1 / (1 + Lambda_v + \
         Lambda_l), the factor by which Smith's masking leaves the sun too bright; and Smith's at each facet's own height, \
         C(h)^(Lambda_v + Lambda_l), which keeps the correlation of height and slope but not of the facet's slope with \
         its neighbours'; and the mirror facets' projected area per unit length over the Gaussian slopes', before any \
         masking). A share is left blank (—) where no facet of the profiles has the mirror slope.\n",
        scene.sun.elevation_deg
    );
    s.push_str("| depression | mirror slope | seen | Smith | lit | Smith | seen and lit | Smith | exact / Smith | Smith at height | density / Gaussian |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|---|\n");
    // A share over no facet (none of the profiles' has the mirror slope) is left blank.
    let share = |x: f64, decimals: usize| if x.is_finite() { format!("{x:.decimals$}") } else { "—".to_owned() };
    for (m, depression) in rows.iter().zip(DEPRESSIONS_DEG) {
        let _ = writeln!(
            s,
            "| {depression}° | {:+.4} | {} | {:.4} | {} | {:.4} | {} | {:.4} | {} | {} | {:.3} |",
            m.mirror_slope,
            share(m.seen, 4),
            m.smith_seen,
            share(m.lit, 4),
            m.smith_lit,
            share(m.seen_and_lit, 4),
            m.smith_seen_and_lit,
            share(m.seen_and_lit / m.smith_seen_and_lit, 3),
            share(m.smith_at_height, 4),
            m.density_over_gaussian
        );
    }
    s
}

fn percent(e: f64) -> String {
    format!("{:+.1}%", 100.0 * e)
}

fn markdown(scene_name: &str, reference: &Path, bands: &[SkyBand], masking: &[MaskingRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Where the reflected sky's error comes from: scene `{scene_name}`, ground truth `{}`. Per distance band (m), \
         the relative error of the band's mean sky luminance: the f64 quadrature of each method's model (`model`, \
         src/measure/reference.rs, which sees the rest plane: not the method where the grid displaces a train) and the \
         method on the GPU (`lookup`); lookup - model is the lookup's own error. The model's farthest band leaves out \
         the split of the horizon's pixel between sea and sky (shade.glsl), so it is not the method's there.\n",
        reference.display()
    );
    s.push_str("| band | pixels | grid displaces | full model | full lookup | paper model | paper lookup |\n");
    s.push_str("|---|---|---|---|---|---|---|\n");
    for b in bands {
        let _ = writeln!(
            s,
            "| {} | {} | {:.0}% | {} | {} | {} | {} |",
            band_label(b.band),
            b.pixels,
            100.0 * b.displaced,
            percent(b.full.0),
            percent(b.full.1),
            percent(b.paper.0),
            percent(b.paper.1)
        );
    }
    s.push_str(
        "\nThe visible facets' mean Fresnel: over the facets a ray from the eye reaches first on the sea's own \
         profiles (exact masking), over every facet facing the eye by its projected area (no masking), and the \
         model's (Gaussian slopes, Smith's masking, which does not depend on the facet's slope and cancels); and \
         how much further the visible facets lean towards the eye than the facing ones (mean slope).\n\n",
    );
    s.push_str(
        "| azimuth | depression | visible | facing | model | visible / model | visible share | further lean |\n",
    );
    s.push_str("|---|---|---|---|---|---|---|---|\n");
    for r in masking {
        let m = &r.masking;
        let _ = writeln!(
            s,
            "| {} | {}° | {:.4} | {:.4} | {:.4} | {:.3} | {:.3} | {:+.4} |",
            r.azimuth,
            r.depression_deg,
            m.visible,
            m.facing,
            m.model,
            m.visible / m.model,
            m.visible_share,
            m.visible_tilt - m.facing_tilt
        );
    }
    s
}
