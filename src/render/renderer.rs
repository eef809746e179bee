//! The renderer: the frame's shared resources and passes for one image size, and its frames in
//! flight. A frame is recorded against a target: a host's frame (embed::Ocean, which every
//! command draws through), recorded into the host's command buffer and composited into its
//! images, or, for the measurements, offscreen (tone-mapped and read back within, `render`).
//! Both run the same passes with barriers from their declared accesses and timestamps.

use crate::error::{Error, Result};
use crate::model::masking::{GlintMaskingTable, VisibleFacetTable};
use crate::model::packets::grid::CellMap;
use crate::model::packets::sources::Sources;
use crate::model::packets::PacketField;
use crate::model::scene::{Planet, Reflections, Scene, ShadowMapMode, Sky, SkyKind, Sun};
use crate::model::waves;
use crate::render::frame::{self, FrameData};
use crate::render::in_flight::{FrameSlot, RecordedAhead};
use crate::render::packet_view;
use crate::render::packets::FramePackets;
use crate::render::passes::atmosphere::{AerialPass, AtmospherePass};
use crate::render::passes::black::BlackPass;
use crate::render::passes::composite::{CompositePass, HostFormats};
use crate::render::passes::exposure::{ExposurePass, Tone};
use crate::render::passes::eye_sky::EyeSkyPass;
use crate::render::passes::host_copy::HostCopyPass;
use crate::render::passes::host_tonemap::HostTonemapPass;
use crate::render::passes::ocean::{Method, OceanPass, ShaderConfig};
use crate::render::passes::packets::PacketBinsPass;
use crate::render::passes::placeholders::PlaceholdersPass;
use crate::render::passes::planar::{MirrorCover, MirrorView, PlanarPass};
use crate::render::passes::planar_tiles::PlanarTilesPass;
use crate::render::passes::readback::ReadbackPass;
use crate::render::passes::reflections::ReflectionsPass;
use crate::render::passes::resolve::ResolvePass;
use crate::render::passes::shade::ShadePass;
use crate::render::passes::shadow::{CasterView, ShadowPass};
use crate::render::passes::sky_map::{SkyMapPass, SkyMipsPass};
use crate::render::passes::tonemap::TonemapPass;
use crate::render::passes::{Frame, HostTargets, Pass, Recorder};
use crate::render::resources::{ResourceSpec, Resources};
use crate::render::sun_shadow::CasterBox;
use crate::render::timeline::{CpuSpans, GpuFrame, Submission};
use crate::vk::barrier::{Access, Tracker};
use crate::vk::buffer::Buffer;
use crate::vk::clock::{host_now_ns, DeviceClock};
use crate::vk::commands::{Commands, Wait};
use crate::vk::device::HDR_FORMAT;
use crate::vk::external::{ldr_encodes_srgb, HostImage, ImageState};
use crate::vk::gpu::Gpu;
use crate::vk::memory::{Location, MemoryReport};
use ash::vk;

/// Passes of a host's own a frame's profile has room for (embed::Ocean::record_host_pass).
pub const HOST_PASSES: usize = 4;

/// A rendered frame, read back to the CPU.
pub struct RenderedFrame {
    pub width: u32,
    pub height: u32,
    /// Linear HDR radiance, RGBA, row-major from the top-left.
    pub hdr: Vec<[f32; 4]>,
    /// Tone-mapped sRGB, RGBA8.
    pub ldr: Vec<u8>,
    /// GPU time per pass (ms); empty when the queue has no timestamps.
    pub pass_ms: Vec<(String, f64)>,
    pub frame: FrameData,
    /// The share of the mirror's images its pass built, where a host drew its objects into them.
    pub planar_cover_share: Option<f64>,
    /// The frame's wave packets, where the scene has local waves.
    pub packets: Option<PacketStats>,
}

/// Where a frame ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Output {
    /// Tone-mapped into a host buffer and read back with the HDR radiance.
    Readback,
    /// Composited into a host's HDR colour and depth attachments, in the host's command buffer
    /// (embed::Ocean; passes/composite.rs, or passes/host_copy.rs).
    Host(HostOutput),
}

/// A host's targets and the unit it wants radiance in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostOutput {
    pub formats: HostFormats,
    /// The host's radiance unit per kcd/m^2 (embed::OceanDesc::radiance_scale).
    pub radiance_scale: f32,
    /// Whether the ocean writes the sky where the host drew nothing (embed::OceanDesc::sky); a
    /// night the scene leaves dark (specialize::plan) is then written black.
    pub sky: bool,
    /// The host's colour image, drawn in place of the ocean's own HDR image (a frame wholly the
    /// ocean's: `owns_frame`; embed::OceanDesc::in_place).
    pub in_place: Option<HostImage>,
    /// Whether the host draws shadow casters into the sun's map (embed::OceanDesc::shadow_casters):
    /// the map is then made wherever the sun term is, displaced waves or not.
    pub shadow_casters: bool,
}

impl HostOutput {
    /// Whether compositing changes no value: no depth (no host objects), the sky everywhere the
    /// sea is not, the ocean's own format and unit. A copy then does it, or nothing at all when
    /// the frame is drawn in the host's image in place.
    pub fn owns_frame(&self) -> bool {
        self.formats.depth.is_none() && self.sky && self.formats.colour == HDR_FORMAT && self.radiance_scale == 1.0
    }

    /// Whether the composite is a copy (passes/host_copy.rs).
    pub fn copies(&self) -> bool {
        self.owns_frame() && self.in_place.is_none()
    }
}

/// How a renderer renders: the ocean shaders' specialization and the supersampling factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub shader: ShaderConfig,
    /// Samples per pixel along each axis (1: none).
    pub ssaa: u32,
    /// Whether the sky map is built (without it, a 1x1 placeholder keeps the descriptor valid
    /// and its passes are left out); only a shader without the sky term may do without.
    pub sky_map: bool,
    pub output: Output,
    /// Frames the CPU may prepare while the GPU runs earlier ones (1: each frame waits).
    pub frames_in_flight: u32,
    /// Pipeline statistics per pass, where the device has them (profiling; off for normal frames).
    pub statistics: bool,
}

impl Options {
    /// Whether a host draws shadow casters into the sun's map (HostOutput::shadow_casters).
    pub fn casts_shadows(&self) -> bool {
        matches!(self.output, Output::Host(h) if h.shadow_casters)
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            shader: ShaderConfig::default(),
            ssaa: 1,
            sky_map: true,
            output: Output::Readback,
            frames_in_flight: 1,
            statistics: false,
        }
    }
}

/// One frame's wave packets, for the report.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PacketStats {
    /// Packets drawn.
    pub alive: usize,
    /// Their cells and the lists' length; the tiles that bin the cells and their lists' length.
    pub cells: u32,
    pub entries: usize,
    pub tiles: u32,
    pub tile_entries: usize,
    /// The energy of the packets the budget (packets.max_alive) left out, over all the sources
    /// made (Packet::energy, m^4).
    pub dropped_energy_share: f64,
    /// The highest crest they add at one place (m).
    pub crest_m: f64,
}

/// A frame's host-side work, done: see `Renderer::prepare`.
pub struct Prepared {
    data: FrameData,
    /// The sun and sky the frame's sky map must hold.
    sky: MapKey,
}

impl Prepared {
    /// The frame as built: its camera, grid and uniforms (the light embed::Ocean::light reads).
    pub fn data(&self) -> &FrameData {
        &self.data
    }
}

/// What the sky map depends on: the sun and sky, and the sea's slopes (their variances and the
/// wind's axes, as the frame's uniforms hold them, bit-exact), which shape the full method's
/// region below the horizon.
#[derive(Clone, Debug, PartialEq)]
struct MapKey {
    sun: Sun,
    /// The sky with the planet under it (Scene::atmosphere's ground).
    sky: (Sky, Planet),
    slopes: [u32; 4],
}

pub struct Renderer<'g> {
    gpu: &'g Gpu,
    width: u32,
    height: u32,
    ssaa: u32,
    anisotropy: f64,
    output: Output,
    // Field order is drop order (after Drop::drop waits for the device): the slots (command
    // buffers, queries, grids), the passes, then the resources they refer to.
    slots: Vec<FrameSlot<'g>>,
    next_slot: usize,
    /// GPU time per pass of the last frame whose fence was waited (no wait added to read them).
    last_pass_ms: Vec<(&'static str, f64)>,
    /// That frame's passes on the host clock, with their statistics.
    last_gpu_frame: Option<GpuFrame>,
    /// The CPU's steps of the last `render`.
    cpu_spans: CpuSpans,
    clock: DeviceClock,
    /// The sun's shadow map pass, outside `passes`: a host may record it ahead of the frame.
    shadow: Option<ShadowPass<'g>>,
    /// The mirror pass, which only a host records, ahead of its frame.
    planar: Option<PlanarPass<'g>>,
    /// The share of the mirror's images the latest recorded frame's mirror pass built (the host's
    /// cover; 1 without one); None where that frame drew no mirror.
    planar_cover_share: Option<f64>,
    /// The wave packets' binning, first in a frame (or ahead of it, with the sun's view).
    packet_bins: Option<PacketBinsPass<'g>>,
    /// The local waves the frames' packets come from.
    sources: Sources,
    /// The last prepared frame's packets: how many, and the energy the budget left out.
    last_packets: Option<PacketStats>,
    /// ...and their field, in the eye's frame (the host's floating objects ride it).
    last_field: Option<PacketField>,
    /// ...and the map of the cells they were binned in (the view's perspective).
    last_cell_map: Option<CellMap>,
    /// Whether `sources` are the scene's own (`new`): each frame's scene must then have the same.
    sources_from_scene: bool,
    /// In execution order.
    passes: Vec<Box<dyn Pass + 'g>>,
    resources: Resources<'g>,
    tracker: Tracker,
    /// The sun and sky the sky map holds, once built: frames under the same sky skip rebuilding it.
    sky_in_map: Option<MapKey>,
    /// The view (camera rays, eye height) the view-dependent passes last built for, with the sky.
    view_built: Option<ViewKey>,
    /// The sky and the eye's altitude (its bits, as the frame's uniforms hold it) the eye's sky
    /// table was last built for.
    eye_built: Option<(MapKey, u32)>,
    /// The passes the last recorded frame left out, their results still current.
    skipped_last_frame: Vec<&'static str>,
    /// Whether the shading pass counts trains (ShaderConfig::count_trains).
    counts_trains: bool,
    /// The sky model and the tone mapping the pipelines were specialized for.
    sky_model: SkyKind,
    tone: Tone,
    /// The sky map's extent in stereographic u, as the method's lookups want it.
    sky_map_extent: f32,
    /// The scene's shadow-map setting the passes and resources were made for.
    shadow_setting: (ShadowMapMode, u32),
    /// Whether the shading reads the glint's masking table (the full method's sun term), and the
    /// table with the sea and sun it was measured for: measuring takes up to half a second, so
    /// frames under the same sea and sun reuse it.
    measures_glint_masking: bool,
    glint_masking: Option<(GlintMaskingKey, GlintMaskingTable)>,
    /// The same for the visible facets' table (the full method's sky and refracted terms), which
    /// depends on the sea alone.
    measures_visible_facets: bool,
    visible_facets: Option<(VisibleFacetKey, VisibleFacetTable)>,
}

/// What the visible facets' table depends on: the sea's trains.
type VisibleFacetKey = (crate::model::scene::Waves, crate::model::scene::Wind);

/// What the glint's masking table depends on: the sea's trains (their statistics do not change
/// with time) and the sun's direction.
type GlintMaskingKey = (crate::model::scene::Waves, crate::model::scene::Wind, crate::model::scene::Sun);

/// What the view-dependent passes depend on: the sky and the camera's rays and height, as the
/// frame's uniforms hold them (bit-exact).
#[derive(Clone, Debug, PartialEq)]
struct ViewKey {
    sky: MapKey,
    camera: [u32; 16],
}

impl ViewKey {
    fn new(data: &FrameData, sky: &MapKey) -> ViewKey {
        let u = &data.uniforms;
        let mut camera = [0u32; 16];
        let values = [u.cam_right, u.cam_down, u.cam_forward, u.atmosphere[4]];
        for (i, v) in values.iter().flatten().enumerate() {
            camera[i] = v.to_bits();
        }
        ViewKey { sky: sky.clone(), camera }
    }
}

/// What a counting shading pass saw in a frame (ShaderConfig::count_trains).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TrainCounts {
    pub sea_pixels: u64,
    pub trains_evaluated: u64,
    pub trains_weighted: u64,
    /// Wave packets within their reach at a sea pixel, their terms added (every sea pixel's:
    /// where it resolves nothing too, their variance in the BRDF).
    pub packet_terms: u64,
}

impl TrainCounts {
    pub fn evaluated_per_sea_pixel(&self) -> f64 {
        self.trains_evaluated as f64 / self.sea_pixels.max(1) as f64
    }

    pub fn weighted_per_sea_pixel(&self) -> f64 {
        self.trains_weighted as f64 / self.sea_pixels.max(1) as f64
    }

    pub fn packet_terms_per_sea_pixel(&self) -> f64 {
        self.packet_terms as f64 / self.sea_pixels.max(1) as f64
    }
}

impl<'g> Renderer<'g> {
    /// A renderer for `width` x `height` images of scenes with `scene`'s sky-map anisotropy.
    /// With supersampling the grid keeps its cell size in output pixels. The scene's local waves
    /// are its splashes (it has no objects, whose wakes a host hands `with_local_waves`).
    pub fn new(gpu: &'g Gpu, scene: &Scene, width: u32, height: u32, options: Options) -> Result<Renderer<'g>> {
        // The ocean alone: a host draws the objects (embed::Ocean hands it none).
        scene.refuse_objects("a measurement of the ocean's own frame")?;
        let sources = Sources::of_named_scene(scene, "(scene)")?;
        let mut renderer = Self::with_local_waves(gpu, scene, sources, width, height, options)?;
        renderer.sources_from_scene = true;
        Ok(renderer)
    }

    /// `new`, with the local waves `sources` (the scene's splashes and its objects' wakes,
    /// embed::Ocean's).
    pub fn with_local_waves(
        gpu: &'g Gpu,
        scene: &Scene,
        sources: Sources,
        width: u32,
        height: u32,
        options: Options,
    ) -> Result<Renderer<'g>> {
        scene.refuse_objects("the ocean's renderer (a host draws the objects)")?;
        let device = &gpu.device;
        // The sky's model is the scene's; the packets, its local waves'.
        let mut options = options;
        options.shader.sky_physical = scene.sky.model == SkyKind::Physical;
        options.shader.packets = !sources.is_empty();
        assert!(options.sky_map || !options.shader.terms.sky, "the sky term samples the sky map");
        assert!(
            options.sky_map || !options.shader.terms.sea || options.shader.method != Method::Full,
            "the full method's refracted term samples the sky map"
        );
        // The sun's shadow map: only for the sun term over a displaced grid or a host's casters,
        // unless the scene turns it off.
        options.shader.shadow &=
            options.shader.shadow_map_unneeded(scene.render.shadow_map, options.casts_shadows()).is_none();
        // The sea reflects a host's objects: in its frame with depth, through the sky term.
        let host_depth = matches!(options.output, Output::Host(h) if h.formats.depth.is_some());
        if !(host_depth && options.shader.terms.sky && !options.shader.draws_nothing()) {
            options.shader.reflections = Reflections::None;
        }
        let frames_in_flight = options.frames_in_flight.max(1);
        let spec = ResourceSpec {
            width,
            height,
            ssaa: options.ssaa,
            sky_map: options.sky_map,
            anisotropy: scene.render.sky_anisotropy as f32,
            slots: frames_in_flight,
            readback: options.output == Output::Readback,
            composite: matches!(options.output, Output::Host(h) if !h.owns_frame()),
            atmosphere: options.shader.sky_physical && !options.shader.draws_nothing(),
            shadow_map: options.shader.shadow.then_some(scene.render.shadow_map_size),
            eye_sky: options.shader.background,
            aerial: options.shader.aerial,
            in_place: match options.output {
                Output::Host(host) => host.in_place,
                Output::Readback => None,
            },
            reflections: options.shader.reflections.screen(),
            planar: options.shader.reflections.planar(),
            planar_tiles: options.shader.planar_tiles,
            packets: options.shader.packets.then_some(sources.max_alive),
        };
        let resources = Resources::new(gpu, &spec)?;
        let packet_bins = PacketBinsPass::new(device, &resources)?;
        // First in every frame, or recorded ahead of it by a host that draws casters into it.
        let shadow = (options.shader.shadow && !options.shader.draws_nothing())
            .then(|| ShadowPass::new(device, &resources, options.shader))
            .transpose()?;
        let mut passes: Vec<Box<dyn Pass + 'g>> = Vec::new();
        if !resources.placeholders().is_empty() {
            passes.push(Box::new(PlaceholdersPass));
        }
        if let Some(tables) = &resources.atmosphere {
            passes.push(Box::new(AtmospherePass::new(device, &resources, tables)?));
        }
        if options.sky_map {
            passes.push(Box::new(SkyMapPass::new(device, &resources, options.shader.method)?));
            passes.push(Box::new(SkyMipsPass));
        }
        if let (Some(tables), false) = (&resources.atmosphere, options.shader.draws_nothing()) {
            if options.shader.aerial {
                passes.push(Box::new(AerialPass::new(device, &resources, tables)?));
            }
            if options.shader.background {
                passes.push(Box::new(EyeSkyPass::new(device, &resources, tables)?));
            }
        }
        if options.shader.draws_nothing() {
            passes.push(Box::new(BlackPass));
        } else {
            passes.push(Box::new(OceanPass::new(device, &resources, options.shader)?));
            if let Some(images) = &resources.reflections {
                passes.push(Box::new(ReflectionsPass::new(gpu, &resources, images, frames_in_flight)?));
            }
            if let Some(tiles) = PlanarTilesPass::new(device, &resources, options.shader.background)? {
                passes.push(Box::new(tiles));
            }
            passes.push(Box::new(ShadePass::new(device, &resources, options.shader)?));
        }
        if let Some(resolved) = &resources.resolved {
            passes.push(Box::new(ResolvePass::new(device, &resources.hdr, resolved)?));
        }
        let tone = Tone::of(scene);
        // A host's frame is tone-mapped by the host, unless it asks the ocean to.
        let tone_maps =
            !matches!(options.output, Output::Host(HostOutput { formats: HostFormats { ldr: None, .. }, .. }));
        if tone.auto && tone_maps {
            passes.push(Box::new(ExposurePass::new(device, &resources)?));
        }
        match options.output {
            Output::Host(host) => {
                let formats = host.formats;
                if formats.depth.is_some() && options.ssaa > 1 {
                    return Err(Error::Argument(
                        "supersampling needs a host without depth: the sea's depth is one per output pixel".into(),
                    ));
                }
                if host.in_place.is_some() {
                    // Drawn where the host wanted it: nothing to composite.
                } else if host.copies() {
                    passes.push(Box::new(HostCopyPass));
                } else {
                    let config = ShaderConfig { background: host.sky, ..options.shader };
                    passes.push(Box::new(CompositePass::new(device, &resources, formats, config)?));
                }
                if let Some(format) = formats.ldr {
                    let encode = ldr_encodes_srgb(format).ok_or_else(|| {
                        Error::Argument(format!("LDR format {format:?} is not one the ocean tone-maps into"))
                    })?;
                    let pass = HostTonemapPass::new(device, &resources, format, encode, tone, frames_in_flight)?;
                    passes.push(Box::new(pass));
                }
            }
            Output::Readback => {
                passes.push(Box::new(TonemapPass::new(device, &resources, tone)?));
                passes.push(Box::new(ReadbackPass));
            }
        }
        let planar = resources
            .planar
            .as_ref()
            .map(|images| PlanarPass::new(device, &resources, images, options.shader.planar_cover))
            .transpose()?;
        let scopes = (passes.len()
            + usize::from(shadow.is_some())
            + usize::from(planar.is_some())
            + usize::from(packet_bins.is_some())
            + HOST_PASSES) as u32;
        let slots = (0..frames_in_flight as usize)
            .map(|i| FrameSlot::new(gpu, i, scopes, options.statistics))
            .collect::<Result<Vec<_>>>()?;
        Ok(Renderer {
            gpu,
            width,
            height,
            ssaa: options.ssaa,
            anisotropy: scene.render.sky_anisotropy,
            output: options.output,
            slots,
            next_slot: 0,
            last_pass_ms: Vec::new(),
            last_gpu_frame: None,
            cpu_spans: CpuSpans::default(),
            clock: DeviceClock::new(device),
            shadow,
            planar,
            planar_cover_share: None,
            packet_bins,
            sources,
            last_packets: None,
            last_field: None,
            last_cell_map: None,
            sources_from_scene: false,
            passes,
            resources,
            tracker: Tracker::default(),
            sky_in_map: None,
            view_built: None,
            eye_built: None,
            skipped_last_frame: Vec::new(),
            counts_trains: options.shader.count_trains && !options.shader.draws_nothing(),
            sky_model: scene.sky.model,
            tone,
            sky_map_extent: frame::sky_map_extent(options.shader.method),
            measures_glint_masking: options.shader.method == Method::Full && options.shader.terms.sun,
            glint_masking: None,
            measures_visible_facets: options.shader.method == Method::Full
                && (options.shader.terms.sky || options.shader.terms.sea),
            visible_facets: None,
            shadow_setting: (scene.render.shadow_map, scene.render.shadow_map_size),
        })
    }

    /// Whether this renderer's pipelines and resources suit `scene` (else make a new renderer):
    /// the sky's model and sampler, the tone mapping and the shadow map, and where it was made
    /// from a scene (`new`), that scene's local waves.
    pub fn fits(&self, scene: &Scene) -> bool {
        let waves_fit = !self.sources_from_scene || Sources::of_scene(scene).is_ok_and(|s| s == self.sources);
        waves_fit
            && scene.sky.model == self.sky_model
            && scene.render.sky_anisotropy == self.anisotropy
            && Tone::of(scene) == self.tone
            && (scene.render.shadow_map, scene.render.shadow_map_size) == self.shadow_setting
    }

    pub fn memory(&self) -> MemoryReport {
        self.gpu.allocator.borrow().report()
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    pub fn output(&self) -> Output {
        self.output
    }

    /// The passes the last recorded frame left out because their results were still current (the
    /// sky's tables and map under the same sun and sky, the aerial perspective under the same view).
    pub fn skipped_last_frame(&self) -> &[&'static str] {
        &self.skipped_last_frame
    }

    /// The names of the passes, in execution order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        let planar = self.planar.as_ref().map(|_| PlanarPass::NAME);
        self.shadow.iter().map(|p| p.name()).chain(planar).chain(self.passes.iter().map(|p| p.name())).collect()
    }

    /// GPU time per pass (ms) of the most recent frame known to be finished.
    pub fn last_pass_ms(&self) -> &[(&'static str, f64)] {
        &self.last_pass_ms
    }

    /// The passes of the most recent frame known to be finished, on the host clock, with their
    /// pipeline statistics where collected.
    pub fn last_gpu_frame(&self) -> Option<&GpuFrame> {
        self.last_gpu_frame.as_ref()
    }

    /// The trains the last finished frame's shading pass counted (a renderer made to count only).
    pub fn train_counts(&self) -> Result<Option<TrainCounts>> {
        if !self.counts_trains {
            return Ok(None);
        }
        let c: Vec<u32> = self.resources.train_counts.read(4)?;
        let [sea_pixels, trains_evaluated, trains_weighted, packet_terms] = [c[0], c[1], c[2], c[3]].map(u64::from);
        Ok(Some(TrainCounts { sea_pixels, trains_evaluated, trains_weighted, packet_terms }))
    }

    /// The CPU's steps of the last `render` (scene and waves, recording, submit, the fence, readback).
    pub fn cpu_spans(&self) -> &CpuSpans {
        &self.cpu_spans
    }

    /// Renders `scene` offscreen, waits for it and reads it back.
    pub fn render(&mut self, scene: &Scene) -> Result<RenderedFrame> {
        assert_eq!(self.output, Output::Readback, "render() needs an offscreen renderer");
        self.cpu_spans.clear();
        let slot = self.begin_frame()?;
        let t = host_now_ns();
        let prepared = self.prepare(slot, scene)?;
        self.cpu_spans.push("scene and waves", t);
        let t = host_now_ns();
        let data = self.record(slot, prepared)?;
        self.cpu_spans.push("record", t);
        let t = host_now_ns();
        self.submit(slot, &[], None)?;
        self.cpu_spans.push("submit", t);
        let t = host_now_ns();
        self.finish(slot)?;
        self.cpu_spans.push("wait for fence", t);
        let t = host_now_ns();
        let readback = self.resources.readback.as_ref().expect("an offscreen renderer has readback buffers");
        let pixels = self.width as usize * self.height as usize;
        let hdr = readback.hdr.read_rgba16f(pixels)?;
        let ldr = readback.ldr.read(4 * pixels)?;
        self.cpu_spans.push("readback", t);
        let pass_ms = self.last_pass_ms.iter().map(|&(n, ms)| (n.to_owned(), ms)).collect();
        Ok(RenderedFrame {
            width: self.width,
            height: self.height,
            hdr,
            ldr,
            pass_ms,
            frame: data,
            planar_cover_share: None,
            packets: self.last_packets,
        })
    }

    /// Takes the next frame slot, waiting for the frame that last used it (and only that one), and
    /// keeps that frame's GPU times. Returns the slot for `prepare`.
    fn begin_frame(&mut self) -> Result<usize> {
        let slot = self.next_slot;
        self.next_slot = (slot + 1) % self.slots.len();
        self.finish(slot)?;
        Ok(slot)
    }

    /// Submits the slot's recorded frame, noting when (and the clocks then) for its GPU spans.
    fn submit(&mut self, slot: usize, waits: &[Wait], signal: Option<vk::Semaphore>) -> Result<()> {
        self.slots[slot].commands.submit(waits, signal)?;
        self.submit_noted(slot)
    }

    /// Notes the submission of the slot's frame, just made, with the clocks sampled now.
    fn submit_noted(&mut self, slot: usize) -> Result<()> {
        let submit_ns = host_now_ns();
        let calibration = self.clock.calibrate(&self.gpu.device)?;
        self.slots[slot].submission = Some(Submission { submit_ns, calibration });
        Ok(())
    }

    /// Takes a host's frame slot: the host has waited for the frame that last used it (a
    /// precondition: embed::Ocean documents it). Keeps that frame's GPU times where its queries
    /// have results, without waiting.
    /// `slot` is in range (embed::Ocean checks it).
    pub fn begin_host_frame(&mut self, slot: usize) -> Result<()> {
        let s = &mut self.slots[slot];
        // What was recorded ahead of a frame that was never recorded is not this frame's.
        s.ahead = RecordedAhead::default();
        if !std::mem::take(&mut s.host_recorded) {
            return Ok(());
        }
        if let Some(scopes) = s.profiler.try_read_scopes(&self.gpu.device.raw)? {
            self.last_pass_ms = scopes.iter().map(|s| (s.name, s.ms())).collect();
        }
        Ok(())
    }

    /// Waits for the frame in `slot` (if one is pending) and keeps its GPU times.
    fn finish(&mut self, slot: usize) -> Result<()> {
        if !self.slots[slot].commands.wait()? {
            return Ok(()); // nothing ran since its queries were last read
        }
        self.keep_times(slot, host_now_ns())
    }

    /// Reads the finished frame's queries in `slot`: its pass times and, where its submission
    /// was noted, its spans on the host clock.
    fn keep_times(&mut self, slot: usize, fence_ns: u64) -> Result<()> {
        let s = &mut self.slots[slot];
        let Some(scopes) = s.profiler.read_scopes(&self.gpu.device.raw)? else { return Ok(()) };
        if scopes.iter().all(|s| s.device_ns.is_some()) {
            self.last_pass_ms = scopes.iter().map(|s| (s.name, s.ms())).collect();
        }
        if let Some(submission) = s.submission.take() {
            self.last_gpu_frame = Some(GpuFrame::new(&scopes, submission, fence_ns, &self.clock));
        }
        Ok(())
    }

    /// The host's part of a frame in `slot`: checks the scene against the renderer, builds the
    /// frame and writes the slot's uniforms and grid.
    fn prepare(&mut self, slot: usize, scene: &Scene) -> Result<Prepared> {
        self.prepare_with(slot, scene, None, None)
    }

    /// `prepare` for a frame in a host's frame: `host` holds the camera-relative world to the
    /// host's clip space and the host's radiance scale, colour maximum and far depth
    /// (FrameUniforms::host_clip, host).
    /// `casters` holds the host's shadow casters (camera-relative), for the sun's view to cover.
    pub fn prepare_host(
        &mut self,
        slot: usize,
        scene: &Scene,
        host: ([[f32; 4]; 4], [f32; 4]),
        casters: Option<CasterBox>,
    ) -> Result<Prepared> {
        self.prepare_with(slot, scene, Some(host), casters)
    }

    fn prepare_with(
        &mut self,
        slot: usize,
        scene: &Scene,
        host: Option<([[f32; 4]; 4], [f32; 4])>,
        casters: Option<CasterBox>,
    ) -> Result<Prepared> {
        if Tone::of(scene) != self.tone {
            return Err(Error::Argument(format!(
                "this renderer's tone mapping was built for {:?}, the scene asks {:?} (render.tone_curve, render.ev100)",
                self.tone,
                Tone::of(scene)
            )));
        }
        if scene.sky.model != self.sky_model {
            return Err(Error::Argument(format!(
                "this renderer was built for sky.model = {:?}, the scene asks {:?}",
                self.sky_model, scene.sky.model
            )));
        }
        if scene.render.sky_anisotropy != self.anisotropy {
            return Err(Error::Argument(format!(
                "this renderer's sky sampler was built for sky_anisotropy = {}, the scene asks {}",
                self.anisotropy, scene.render.sky_anisotropy
            )));
        }
        let shadow_setting = (scene.render.shadow_map, scene.render.shadow_map_size);
        if shadow_setting != self.shadow_setting {
            return Err(Error::Argument(format!(
                "this renderer was built for render.shadow_map = {:?} at {} texels, the scene asks {:?} at {}",
                self.shadow_setting.0, self.shadow_setting.1, shadow_setting.0, shadow_setting.1
            )));
        }
        if self.sources_from_scene {
            let sources = Sources::of_named_scene(scene, "(scene)")?;
            if sources != self.sources {
                return Err(Error::Argument(
                    "this renderer was made for other local waves ([[splash]], [[wake]], [packets]) than the scene's: make a new renderer".into(),
                ));
            }
        }
        let mut wave_set = waves::generate(scene);
        let k = self.ssaa;
        let (width, height, cell_px) = (self.width * k, self.height * k, scene.render.grid_cell_px * k as f64);
        let packets = self.resources.packets.as_ref().map(|buffers| {
            let eye = glam::DVec2::new(scene.camera.x_m, scene.camera.y_m);
            let view = |crest| packet_view::cell_map(scene, &wave_set, crest, width, height, cell_px);
            FramePackets::new(&self.sources, scene.render.time_s, eye, buffers.max_entries, view)
        });
        if let Some(p) = &packets {
            wave_set.packet_crest_m = p.grid.crest_m;
            wave_set.packet_longest_m = p.field.longest_wavelength();
        }
        let mut data = frame::build_with_casters(scene, &wave_set, width, height, cell_px, casters);
        self.last_packets = None;
        self.last_cell_map = None;
        if let (Some(p), Some(buffers)) = (&packets, &self.resources.packets) {
            (data.uniforms.packet_grid, data.uniforms.packet_map, data.uniforms.packet_dims) = p.uniforms();
            self.last_cell_map = Some(p.grid.map);
            buffers.write(slot, p)?;
            let total = p.field.total_energy;
            self.last_packets = Some(PacketStats {
                alive: p.gpu.len(),
                cells: p.grid.cols * p.grid.rows,
                entries: p.grid.entries,
                tiles: p.grid.tiles(),
                tile_entries: p.grid.tile_packets.len(),
                dropped_energy_share: if total > 0.0 { p.field.dropped_energy / total } else { 0.0 },
                crest_m: p.grid.crest_m,
            });
        }
        // Kept for the host's floating objects (packet_field): moved, not copied.
        self.last_field = packets.map(|p| p.field);
        data.uniforms.tone[1] = self.sky_map_extent;
        if let Some((clip, values)) = host {
            data.uniforms.host_clip = clip;
            data.uniforms.host = values;
        }
        if self.measures_glint_masking {
            let key = (scene.waves.clone(), scene.wind.clone(), scene.sun.clone());
            if self.glint_masking.as_ref().is_none_or(|(k, _)| *k != key) {
                let azimuth = scene.sun.azimuth_deg - scene.wind.direction_deg;
                let table = GlintMaskingTable::cached(&wave_set, 0.0, azimuth, scene.sun.elevation_deg);
                self.glint_masking = Some((key, table));
            }
            if let Some((_, table)) = &self.glint_masking {
                data.waves.set_glint_masking(table);
            }
        }
        if self.measures_visible_facets {
            let key = (scene.waves.clone(), scene.wind.clone());
            if self.visible_facets.as_ref().is_none_or(|(k, _)| *k != key) {
                self.visible_facets = Some((key, VisibleFacetTable::cached(&wave_set, 0.0)));
            }
            if let Some((_, table)) = &self.visible_facets {
                data.waves.set_visible_facets(table);
            }
        }
        self.resources.frame_uniforms.write(slot, &data.uniforms)?;
        self.resources.waves.write(slot, data.waves.as_ref())?;
        self.slots[slot].grid.set(data.grid.columns, data.grid.rows)?;
        if self.counts_trains {
            // Host writes before the submit are visible to it; the slot's last frame is done.
            self.resources.train_counts.write(&[0u32; 4])?;
        }
        let slopes = data.uniforms.wind.map(f32::to_bits);
        Ok(Prepared {
            data,
            sky: MapKey { sun: scene.sun.clone(), sky: (scene.sky.clone(), scene.planet.clone()), slopes },
        })
    }

    /// Records the frame `prepared` for `slot` into the slot's command buffer.
    fn record(&mut self, slot: usize, prepared: Prepared) -> Result<FrameData> {
        let cmd = self.slots[slot].commands.cmd;
        self.slots[slot].commands.begin()?;
        self.record_passes(cmd, slot, prepared, None)
    }

    /// Records the frame `prepared` for `slot` into a host's command buffer `cmd` (recording,
    /// outside a rendering scope), compositing into the host's `targets`, which the host left
    /// in the states `entry` (colour, depth, LDR). The exit states are embed::Ocean::record's.
    pub fn record_for_host(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        prepared: Prepared,
        targets: HostTargets,
        entry: [ImageState; 3],
    ) -> Result<FrameData> {
        assert!(matches!(self.output, Output::Host(_)), "record_for_host() needs a host renderer");
        let entered = [(Some(targets.colour), entry[0]), (targets.depth, entry[1]), (targets.ldr, entry[2])];
        for (image, state) in entered.iter().filter_map(|(i, s)| i.map(|i| (i, s))) {
            self.tracker.external(&image, state.layout, state.stage, state.access);
        }
        self.slots[slot].host_recorded = true;
        let data = self.record_passes(cmd, slot, prepared, Some(targets))?;
        // The exit states embed::Ocean::record documents, whichever passes ran last.
        let colour_exit = if targets.ldr.is_some() { Access::FragmentSampled } else { Access::ColorAttachmentWrite };
        self.tracker.image(&targets.colour, 0, 1, colour_exit, false);
        if let Some(ldr) = &targets.ldr {
            self.tracker.image(ldr, 0, 1, Access::ColorAttachmentWrite, false);
        }
        self.tracker.flush(&self.gpu.device.raw, cmd);
        // The host's images are the host's again: their handles may be reused for other images.
        for image in entered.iter().filter_map(|(i, _)| *i) {
            self.tracker.forget(image.raw);
        }
        Ok(data)
    }

    /// Notes that the host submitted the frame in `slot` (now), sampling the clocks for its GPU
    /// spans on the host's clock (profiling; see `host_finished`).
    pub fn host_submitted(&mut self, slot: usize) -> Result<()> {
        self.submit_noted(slot)
    }

    /// Keeps the GPU times and spans of the frame in `slot`, which the host has waited for.
    pub fn host_finished(&mut self, slot: usize) -> Result<()> {
        let fence_ns = host_now_ns();
        let s = &mut self.slots[slot];
        if !std::mem::take(&mut s.host_recorded) {
            return Ok(());
        }
        self.keep_times(slot, fence_ns)
    }

    /// Records the frame's passes into `cmd`.
    fn record_passes(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        prepared: Prepared,
        host: Option<HostTargets>,
    ) -> Result<FrameData> {
        let Prepared { data, sky } = prepared;
        let sky_current = self.sky_in_map.as_ref() == Some(&sky);
        let air_current = self.sky_in_map.as_ref().is_some_and(|k| k.sky == sky.sky);
        let view = ViewKey::new(&data, &sky);
        let view_current = sky_current && self.view_built.as_ref() == Some(&view);
        self.view_built = Some(view);
        let eye = (sky.clone(), data.uniforms.atmosphere[4][2].to_bits());
        let eye_current = sky_current && self.eye_built.as_ref() == Some(&eye);
        self.eye_built = Some(eye);
        self.sky_in_map = Some(sky);
        let ahead = self.slots[slot].ahead;
        let frame = Frame { planar_drawn: ahead.planar.is_some(), ..self.frame(slot, &data, host) };
        self.planar_cover_share = ahead.planar;
        // A host that recorded a pass ahead began the slot's profile with it.
        if !ahead.profile_begun {
            self.slots[slot].profiler.reset(&self.gpu.device.raw, cmd);
        }
        self.record_packet_bins(cmd, &frame);
        self.slots[slot].ahead = RecordedAhead::default();
        let device = &self.gpu.device;
        let s = &mut self.slots[slot];
        if !ahead.shadows {
            if let Some(pass) = &self.shadow {
                s.profiler.begin(device, cmd, pass.name());
                pass.declare(&self.resources, &frame, &mut self.tracker);
                self.tracker.flush(&device.raw, cmd);
                pass.record(&mut Recorder { device, cmd, tracker: &mut self.tracker, frame: &frame }, &self.resources);
                s.profiler.end(device, cmd);
            }
        }
        let skipped = |p: &(dyn Pass + 'g)| {
            (sky_current && p.builds_sky_map())
                || (air_current && p.builds_for_sky())
                || (view_current && p.builds_for_view())
                || (eye_current && p.builds_for_eye())
        };
        self.skipped_last_frame = self.passes.iter().filter(|p| skipped(p.as_ref())).map(|p| p.name()).collect();
        for pass in self.passes.iter().filter(|p| !skipped(p.as_ref())) {
            s.profiler.begin(device, cmd, pass.name());
            pass.declare(&self.resources, &frame, &mut self.tracker);
            self.tracker.flush(&device.raw, cmd);
            pass.record(&mut Recorder { device, cmd, tracker: &mut self.tracker, frame: &frame }, &self.resources);
            s.profiler.end(device, cmd);
        }
        Ok(data)
    }

    /// What the passes of frame `data` in `slot` read of it.
    fn frame(&self, slot: usize, data: &FrameData, host: Option<HostTargets>) -> Frame {
        let s = &self.slots[slot];
        Frame {
            slot,
            uniform_offsets: [self.resources.frame_uniforms.offset(slot), self.resources.waves.offset(slot)],
            grid: s.grid.buffer.as_ref().filter(|_| s.grid.count > 0).map(|b| (b.raw, s.grid.count)),
            sky_rows: data.sky_rows,
            sea_rows: data.sea_rows,
            sun_view: data.sun_view.is_some(),
            host,
            planar_drawn: false,
            packets: data.uniforms.packet_dims[2],
            packet_cells: data.uniforms.packet_dims[0] * data.uniforms.packet_dims[1],
            packet_tiles: data.uniforms.packet_dims[3],
        }
    }

    /// Records the packets' binning for frame `frame` into `cmd`, unless it was recorded ahead.
    fn record_packet_bins(&mut self, cmd: vk::CommandBuffer, frame: &Frame) {
        let Some(pass) = &self.packet_bins else { return };
        let device = &self.gpu.device;
        let s = &mut self.slots[frame.slot];
        if std::mem::replace(&mut s.ahead.packets_binned, true) {
            return;
        }
        s.profiler.begin(device, cmd, pass.name());
        pass.declare(&self.resources, frame, &mut self.tracker);
        self.tracker.flush(&device.raw, cmd);
        pass.record(&mut Recorder { device, cmd, tracker: &mut self.tracker, frame }, &self.resources);
        s.profiler.end(device, cmd);
    }

    /// The last prepared frame's packets (None without local waves).
    pub fn packet_stats(&self) -> Option<PacketStats> {
        self.last_packets
    }

    /// The cells' lists the GPU's binning left for the last frame: each cell's start in the lists
    /// (one more start than cells) and the lists' packet indices, as model::packets::grid::
    /// PacketGrid::lists has them (None without local waves). Waits for the device; for tests.
    pub fn read_packet_lists(&mut self) -> Result<Option<(Vec<u32>, Vec<u32>)>> {
        self.wait_idle()?;
        let (Some(buffers), Some(stats)) = (&self.resources.packets, self.last_packets) else { return Ok(None) };
        // Without packets the binning wrote nothing this frame: the lists are empty.
        if stats.alive == 0 {
            return Ok(Some((vec![0], Vec::new())));
        }
        let starts_bytes = 4 * (u64::from(stats.cells) + 1);
        let lists_bytes = 4 * stats.entries as u64;
        let usage = vk::BufferUsageFlags::TRANSFER_DST;
        let readback =
            Buffer::new(self.gpu, "packet lists readback", starts_bytes + lists_bytes, usage, Location::Readback)?;
        let commands = Commands::new(&self.gpu.device, "packet lists readback")?;
        let (device, cmd) = (&self.gpu.device.raw, commands.cmd);
        commands.begin()?;
        let mut tracker = Tracker::default();
        // The binning wrote them last; the copy reads them, the host the copy.
        tracker.buffer(&buffers.cells, Access::ComputeStorageWrite);
        tracker.buffer(&buffers.cells, Access::TransferRead);
        tracker.buffer(&readback, Access::TransferWrite);
        tracker.flush(device, cmd);
        let lists_at = 4 * u64::from(crate::model::packets::grid::MAX_CELLS + 1);
        let regions = [
            vk::BufferCopy { src_offset: 0, dst_offset: 0, size: starts_bytes },
            vk::BufferCopy { src_offset: lists_at, dst_offset: starts_bytes, size: lists_bytes.max(4) },
        ];
        let count = if lists_bytes > 0 { 2 } else { 1 };
        // SAFETY: both buffers are live and in transfer states (flushed above); the regions lie
        // inside both (the lists hold `entries` words after MAX_CELLS + 1 starts; the readback
        // is sized for them).
        unsafe { device.cmd_copy_buffer(cmd, buffers.cells.raw, readback.raw, &regions[..count]) };
        tracker.buffer(&readback, Access::HostRead);
        tracker.flush(device, cmd);
        commands.submit(&[], None)?;
        commands.wait()?;
        let mut words: Vec<u32> = readback.read(((starts_bytes + lists_bytes) / 4) as usize)?;
        let lists = words.split_off((starts_bytes / 4) as usize);
        Ok(Some((words, lists)))
    }

    /// The last prepared frame's wave packets, in the eye's frame (None without local waves).
    pub fn packet_field(&self) -> Option<&PacketField> {
        self.last_field.as_ref()
    }

    /// The map of the cells the last prepared frame's packets were binned in (None without
    /// local waves).
    pub fn packet_cell_map(&self) -> Option<CellMap> {
        self.last_cell_map
    }

    /// Whether this renderer was made for local waves like `sources` (with them or without, and
    /// the same budget); `set_local_waves` then changes them.
    pub fn fits_local_waves(&self, sources: &Sources) -> bool {
        self.sources.is_empty() == sources.is_empty() && self.sources.max_alive == sources.max_alive
    }

    /// New local waves for the next frames; Err (nothing changed) where they do not fit
    /// (`fits_local_waves`: make a new renderer).
    pub fn set_local_waves(&mut self, sources: Sources) -> Result<()> {
        if !self.fits_local_waves(&sources) {
            return Err(Error::Argument(format!(
                "this renderer was made for {} local waves within packets.max_alive = {}; the new ones are {} within {}",
                if self.sources.is_empty() { "no" } else { "some" },
                self.sources.max_alive,
                if sources.is_empty() { "none" } else { "some" },
                sources.max_alive
            )));
        }
        self.sources = sources;
        self.sources_from_scene = false;
        Ok(())
    }

    /// Records the sun's shadow map of frame `prepared` in `slot` into a host's command buffer
    /// `cmd` ahead of the frame (embed::Ocean::record_shadows), `casters` drawing the host's
    /// shadow casters into it, and leaves it for the host's fragment shaders to sample. Does
    /// nothing where the renderer has no shadow pass (Ok(false)).
    pub fn record_host_shadows(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        prepared: &Prepared,
        casters: &mut dyn FnMut(vk::CommandBuffer, &CasterView),
    ) -> Result<bool> {
        if self.shadow.is_none() {
            return Ok(false);
        }
        let frame = self.frame(slot, &prepared.data, None);
        self.slots[slot].begin_ahead(&self.gpu.device.raw, cmd);
        // The sun's view displaces the packets too.
        self.record_packet_bins(cmd, &frame);
        let Some(pass) = &self.shadow else { return Ok(false) };
        let device = &self.gpu.device;
        let s = &mut self.slots[slot];
        s.profiler.begin(device, cmd, pass.name());
        pass.declare(&self.resources, &frame, &mut self.tracker);
        self.tracker.flush(&device.raw, cmd);
        let view = prepared.data.sun_view.map(|v| CasterView { clip_from_relative: v.view_proj.as_mat4() });
        let mut rec = Recorder { device, cmd, tracker: &mut self.tracker, frame: &frame };
        pass.record_casting(&mut rec, &self.resources, view.map(|v| (v, casters)));
        s.profiler.end(device, cmd);
        self.tracker.image(&self.resources.shadow_map, 0, 1, Access::FragmentSampled, false);
        self.tracker.flush(&device.raw, cmd);
        s.ahead.shadows = true;
        Ok(true)
    }

    /// Records the mirror pass of frame `prepared` in `slot` into a host's command buffer `cmd`
    /// ahead of the frame (embed::Ocean::record_planar): `draw` records the host's objects
    /// mirrored about the sea with `view` within `cover`, into images the frame's shading then reads. Does
    /// nothing where the renderer has no mirror pass (Ok(false)); a frame the host records none
    /// for reads none.
    pub fn record_host_planar(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        prepared: &Prepared,
        view: &MirrorView,
        cover: MirrorCover,
        draw: &mut dyn FnMut(vk::CommandBuffer, &MirrorView),
    ) -> Result<bool> {
        let Some(pass) = &self.planar else { return Ok(false) };
        let far = prepared.data.uniforms.host[2];
        let frame = self.frame(slot, &prepared.data, None);
        let device = &self.gpu.device;
        let s = &mut self.slots[slot];
        s.begin_ahead(&device.raw, cmd);
        s.profiler.begin(device, cmd, PlanarPass::NAME);
        let mut rec = Recorder { device, cmd, tracker: &mut self.tracker, frame: &frame };
        let built = pass.record_mirrored(&mut rec, &self.resources, view, cover, far, draw);
        s.profiler.end(device, cmd);
        let texels = |e: vk::Extent2D| e.width as f64 * e.height as f64;
        s.ahead.planar = Some(built.map_or(0.0, |(within, extent)| texels(within.extent()) / texels(extent)));
        Ok(true)
    }

    /// A pass of the host's own, `record`ed into its command buffer `cmd` ahead of frame
    /// `slot`'s passes, inside the frame's profile: a debug label and a timestamp scope `name`,
    /// timed with the ocean's own. At most HOST_PASSES a frame.
    pub fn record_host_pass(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        name: &'static str,
        record: &mut dyn FnMut(vk::CommandBuffer),
    ) -> Result<()> {
        let device = &self.gpu.device;
        let s = &mut self.slots[slot];
        if s.ahead.host_passes >= HOST_PASSES {
            return Err(Error::Argument(format!(
                "record_host_pass \"{name}\": at most {HOST_PASSES} host passes a frame"
            )));
        }
        s.begin_ahead(&device.raw, cmd);
        s.ahead.host_passes += 1;
        s.profiler.begin(device, cmd, name);
        record(cmd);
        s.profiler.end(device, cmd);
        Ok(())
    }

    /// Whether the renderer has the mirror pass (a host's planar reflections).
    pub fn has_planar(&self) -> bool {
        self.planar.is_some()
    }

    /// The share of the mirror's images (texels of level 0) the latest recorded frame's mirror
    /// pass built: the host's cover's. None where that frame drew no mirror.
    pub fn planar_cover_share(&self) -> Option<f64> {
        self.planar_cover_share
    }

    /// The sun's shadow map (SHADER_READ_ONLY_OPTIMAL after `record_host_shadows`) and its
    /// comparing sampler, where the renderer has a shadow pass.
    pub fn sun_shadow_map(&self) -> Option<(vk::ImageView, vk::Sampler)> {
        self.shadow.as_ref().map(|_| (self.resources.shadow_map.view, self.resources.shadow_sampler.raw))
    }

    /// Waits for every frame in flight.
    pub fn wait_idle(&mut self) -> Result<()> {
        for slot in 0..self.slots.len() {
            self.finish(slot)?;
        }
        Ok(())
    }
}

impl Drop for Renderer<'_> {
    fn drop(&mut self) {
        // Nothing may be destroyed while the GPU still uses it; the fields then drop in order.
        let _ = self.gpu.device.wait_idle();
    }
}
