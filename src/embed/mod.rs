//! The ocean as a library: drawn into a host's own Vulkan frame (docs/embedding.md).
//!
//! A host checks its physical device with [`check_physical_device`], enables what
//! [`requirements`] lists, wraps its instance and device in a [`Gpu`] with [`Gpu::from_host`],
//! and makes an [`Ocean`] on it. Each frame it calls [`Ocean::update`] with its camera, then
//! [`Ocean::record`] into its own command buffer, after drawing its objects into its HDR colour
//! and depth attachments; the ocean depth-tests against them. The host submits.
//!
//! Everything a host needs is here or re-exported here.
#![warn(missing_docs)]

pub mod camera;

use crate::error::{Error, Result};
use crate::model::packets::sources::Sources;
use crate::model::scene::Scene;
use crate::model::waves;
use crate::render::frame::FrameData;
use crate::render::passes::HostTargets;
use crate::render::renderer::{HostOutput, Options, Output, PacketStats, Prepared, Renderer};
use crate::render::specialize::{self, Omission};
use crate::render::sun_shadow::CasterBox;
use crate::vk::device::{HDR_BITS_FORMAT, HDR_FORMAT};
use crate::vk::external::{hdr_format_max, HOST_DEPTH_FORMATS};
use ash::vk;
use camera::HostView;
use glam::{DMat4, DVec3};

pub use crate::model::scene::Reflections;
pub use crate::render::passes::composite::HostFormats;
pub use crate::render::passes::ocean::{Method, ShaderConfig, Terms};
pub use crate::render::renderer::{TrainCounts, HOST_PASSES};
pub use crate::render::timeline::{GpuFrame, GpuSpan};
pub use crate::vk::device::HostEnabled;
pub use crate::vk::external::{
    aspect_of, begin_cleared_rendering, clear_targets, ldr_encodes_srgb, transition, HostImage, ImageState,
};
pub use crate::vk::gpu::{Gpu, HostDevice};
pub use crate::vk::memory::MemoryReport;

/// What a host enables for the ocean on its device (see docs/embedding.md).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Requirements {
    /// The Vulkan version the device and the instance must offer.
    pub api_version: u32,
    /// Device extensions that must be enabled (none: Vulkan 1.3 core has what the ocean uses).
    pub device_extensions: Vec<&'static std::ffi::CStr>,
    /// Vulkan 1.3 features that must be enabled.
    pub vulkan13_features: Vec<&'static str>,
    /// Features used where enabled, left out where not (the host states which in
    /// [`HostEnabled`]).
    pub optional_features: Vec<&'static str>,
    /// Device extensions used where enabled.
    pub optional_device_extensions: Vec<&'static std::ffi::CStr>,
}

/// What the ocean needs of a device, for the host to enable before it creates it.
pub fn requirements() -> Requirements {
    Requirements {
        api_version: vk::API_VERSION_1_3,
        device_extensions: Vec::new(),
        vulkan13_features: vec!["synchronization2", "dynamicRendering"],
        optional_features: vec!["samplerAnisotropy", "pipelineStatisticsQuery"],
        optional_device_extensions: vec![ash::ext::calibrated_timestamps::NAME],
    }
}

/// Whether `physical` can run the ocean: Err names the first thing it lacks (a version, a
/// feature, a queue, a format's feature).
pub fn check_physical_device(entry: &ash::Entry, instance: &ash::Instance, physical: vk::PhysicalDevice) -> Result<()> {
    let borrowed = crate::vk::instance::Instance::from_host(entry.clone(), instance.clone(), false);
    crate::vk::device::supports(&borrowed, physical)
}

/// How the ocean is made for a host's frames.
#[derive(Clone, Debug)]
pub struct OceanDesc {
    /// The sea, sun, sky and rendering settings (its camera is replaced by the host's each frame).
    /// Its `[[object]]`s are the host's to draw (the commands' host draws them with
    /// `app::objects`); the ocean depth-tests against whatever the host drew.
    pub scene: Scene,
    /// The targets' width in pixels.
    pub width: u32,
    /// The targets' height in pixels.
    pub height: u32,
    /// The host's HDR colour and depth formats and its depth convention.
    pub formats: HostFormats,
    /// Frames the host records before waiting for the first: each has its own uniforms and grid.
    pub frames_in_flight: u32,
    /// Whether the sky is drawn where the host drew nothing (false: a host with its own sky).
    pub sky: bool,
    /// The host's radiance unit per kcd/m² (the ocean's own; 1000 for cd/m²). The ocean clamps
    /// what it writes to the colour format's largest value.
    pub radiance_scale: f32,
    /// How the ocean shades ([`Shading::default`]: the product's method and terms).
    pub shading: Shading,
    /// The host's colour image, for the ocean to draw in, in place of an HDR image of its own:
    /// for a host whose frame is wholly the ocean's (no depth format, `sky` on, an
    /// R16G16B16A16_SFLOAT colour, a radiance scale of 1, no supersampling). It saves the
    /// ocean's own HDR image (8 bytes a pixel) and the composite. The host made it as
    /// [`IN_PLACE_USAGE`] and [`IN_PLACE_VIEW_FORMATS`] say, single-level, the targets' size,
    /// keeps it alive while the ocean lives, and hands it as the colour target of every frame.
    /// Such an ocean is made again for a new size (with a new image), not resized.
    pub in_place: Option<HostImage>,
    /// Whether the host draws shadow casters (its objects) into the sun's shadow map each frame
    /// ([`Ocean::record_shadows`]) and samples it ([`Ocean::sun_shadow`]): the map is then made
    /// wherever the sun term is, displaced waves or not, and fitted to the box the host gives
    /// ([`Ocean::set_shadow_casters`]) as well as to the sea.
    pub shadow_casters: bool,
}

/// The usages of a host's colour image the ocean draws in place ([`OceanDesc::in_place`]): the
/// visibility pass's attachment, the shading's storage, the exposure's and the tone mapping's
/// reads, a night's clear, the host's own copy out.
pub const IN_PLACE_USAGE: vk::ImageUsageFlags = vk::ImageUsageFlags::from_raw(
    vk::ImageUsageFlags::COLOR_ATTACHMENT.as_raw()
        | vk::ImageUsageFlags::STORAGE.as_raw()
        | vk::ImageUsageFlags::SAMPLED.as_raw()
        | vk::ImageUsageFlags::TRANSFER_SRC.as_raw()
        | vk::ImageUsageFlags::TRANSFER_DST.as_raw(),
);

/// The view formats of a colour image the ocean draws in place, created `MUTABLE_FORMAT` with
/// them in a `VkImageFormatListCreateInfo`: the radiance, and the same 64 bits as the rest
/// positions the visibility pass leaves for the shading.
pub const IN_PLACE_VIEW_FORMATS: [vk::Format; 2] = [HDR_FORMAT, HDR_BITS_FORMAT];

/// How the ocean shades, beyond the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// The method, its terms and what the shaders include. Its `background` off leaves the sky
    /// and the sea's aerial perspective out (black), for renders of single terms.
    pub shader: ShaderConfig,
    /// Samples per pixel along each axis (1: none); above 1 only for a frame wholly the ocean's
    /// (no depth format, `sky` on: the sea's depth that decides what the host keeps is one per
    /// output pixel).
    pub ssaa: u32,
    /// Leave out what the scene seen from its own camera does not need ([`Ocean::omitted`] says
    /// what and why). For a still camera (offline renders): updates must then keep the scene's
    /// camera, as a moved one may need what was left out.
    pub specialize_for_scene_camera: bool,
    /// Pipeline statistics per pass, where the device has them (profiling; see
    /// [`Ocean::last_gpu_frame`]).
    pub statistics: bool,
}

impl Default for Shading {
    fn default() -> Self {
        Shading { shader: ShaderConfig::default(), ssaa: 1, specialize_for_scene_camera: false, statistics: false }
    }
}

/// The most samples per pixel along each axis [`Shading::ssaa`] takes.
pub const MAX_SSAA: u32 = 16;

impl OceanDesc {
    /// What the renderer is told of the host's targets.
    fn host_output(&self) -> HostOutput {
        HostOutput {
            formats: self.formats,
            radiance_scale: self.radiance_scale,
            sky: self.sky,
            in_place: self.in_place,
            shadow_casters: self.shadow_casters,
        }
    }
}

/// The most frames in flight an ocean keeps resources for.
pub const MAX_FRAMES_IN_FLIGHT: u32 = 16;

/// One frame's input: the scene's time and the host's camera.
#[derive(Clone, Copy, Debug)]
pub struct FrameInput {
    /// Seconds: the waves' phase.
    pub time_s: f64,
    /// World (the ocean's: x east, y north, z up, metres, sea level at z = 0) to view space, in
    /// f64 so that an eye far from the origin keeps the short waves' phases (`as_dmat4()` an f32
    /// one).
    pub view: DMat4,
    /// View space to Vulkan clip space (y down, depth in [0, 1], standard or reversed as the
    /// ocean was made for; finite or infinite far plane).
    pub projection: DMat4,
}

/// The light of the last updated frame, for a host to light its objects as the ocean lights the
/// sea: in the host's radiance unit times steradians (klux for the ocean's own kcd/m²), at sea
/// level below the eye, linear sRGB primaries. Under the physical sky these are its
/// transmittance-attenuated sun and its multiply scattered sky (model::atmosphere); under
/// Preetham's, its sun and its sky integrated over the hemisphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Towards the sun, in the ocean's world (unit; below the horizon at night).
    pub sun_direction: glam::DVec3,
    /// The sun's illuminance on a surface facing it (0 while the sea cannot see it).
    pub sun_illuminance: [f32; 3],
    /// The whole sky's illuminance on a level surface.
    pub sky_illuminance: [f32; 3],
    /// The sun disc's radiance seen from the eye (the host's radiance unit), for a host that
    /// draws the disc or a specular highlight of it.
    pub sun_radiance: [f32; 3],
}

/// The host's attachments for one frame and the state it leaves them in.
#[derive(Clone, Copy, Debug)]
pub struct Targets {
    /// The HDR colour attachment the host drew into.
    pub colour: HostImage,
    /// Usually [`ImageState::COLOR_ATTACHMENT`].
    pub colour_entry: ImageState,
    /// The depth attachment the host drew into and its state (usually
    /// [`ImageState::DEPTH_ATTACHMENT`]), where the ocean was made with a depth format; None for a
    /// host that draws no objects.
    pub depth: Option<(HostImage, ImageState)>,
    /// The LDR image the frame is tone-mapped into, where the ocean was made with an LDR format
    /// (a swapchain image: entry [`ImageState::ACQUIRED`]); its old contents are not kept.
    pub ldr: Option<(HostImage, ImageState)>,
}

/// The ocean in a host's frame.
pub struct Ocean<'g> {
    gpu: &'g Gpu,
    desc: OceanDesc,
    /// None while the targets have no pixels (a minimized window): update and record do nothing.
    renderer: Option<Renderer<'g>>,
    /// The renderer's options: the desc's shading, specialized where asked.
    options: Options,
    /// What specialization left out, and why.
    omitted: Vec<Omission>,
    /// Each slot's prepared frame between `update` and `record`.
    prepared: Vec<Option<Prepared>>,
    /// The camera of the last update, as the ocean draws it.
    last_view: Option<HostView>,
    /// The light of the last update.
    light: Option<Light>,
    /// The frame the last record drew, as the ocean built it.
    last_frame: Option<FrameData>,
    /// Why the last rebuild (a resize or a scene change) failed: until one succeeds, the ocean
    /// has no pipelines and every update and record says so.
    broken: Option<String>,
    /// The box (world, m) holding the host's shadow casters, for the next updates.
    casters: Option<(DVec3, DVec3)>,
    /// The sun's view of the last update: camera-relative world to the shadow map's clip space,
    /// and a texel's larger side (m).
    sun_view: Option<(glam::Mat4, f64)>,
    /// What the host's objects are mirrored with in the last update's frame
    /// ([`Ocean::record_planar`]).
    mirror: Option<MirrorView>,
    /// The scene's local waves: its splashes and its moving objects' wakes (the objects are the
    /// host's to draw; their wakes are the sea's).
    sources: Sources,
}

/// The sun's shadow map, for a host's fragment shaders to shadow its objects by the waves and by
/// each other ([`Ocean::sun_shadow`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunShadow {
    /// The map's view (a depth format), in SHADER_READ_ONLY_OPTIMAL after
    /// [`Ocean::record_shadows`], readable by fragment shaders until [`Ocean::record`].
    pub view: vk::ImageView,
    /// A comparing sampler (LESS_OR_EQUAL: 1 where lit), clamped to the edge.
    pub sampler: vk::Sampler,
    /// Camera-relative world (origin at the eye, z up, m) to the map's clip space (x, y over
    /// [-1, 1], depth over [0, 1] nearest the sun first); None while the sun has no view (below
    /// the horizon): everything is lit by the sun the ocean reports.
    pub clip_from_relative: Option<glam::Mat4>,
    /// A texel's larger side on a surface across the sunlight (m; 0 without a view): how far a
    /// receiver is moved along its normal before the lookup, for the map's texels not to shadow
    /// the surface they were drawn from.
    pub texel_m: f64,
}

pub use crate::render::passes::planar::{MirrorCover, MirrorView, PLANAR_COLOUR_FORMAT};
pub use crate::render::passes::shadow::{CasterView, DEPTH_BIAS as SHADOW_DEPTH_BIAS};
pub use crate::render::resources::PLANAR_DEPTH_FORMAT;
/// The sun's shadow map's format, for a host's caster pipeline.
pub const SHADOW_FORMAT: vk::Format = crate::vk::device::DEPTH_FORMAT;

impl<'g> Ocean<'g> {
    /// Makes the ocean's pipelines and resources on the host's device. Fails naming a format the
    /// ocean cannot write or test against, a frame count or size out of range, or what the
    /// device lacks.
    pub fn new(gpu: &'g Gpu, mut desc: OceanDesc) -> Result<Ocean<'g>> {
        check_desc(gpu, &desc)?;
        let sources = Sources::of_named_scene(&desc.scene, "(host scene)")?;
        // A scene's objects are its host's to draw.
        desc.scene.objects.clear();
        let mut ocean = Ocean {
            gpu,
            renderer: None,
            options: Options::default(),
            omitted: Vec::new(),
            prepared: Vec::new(),
            last_view: None,
            light: None,
            last_frame: None,
            broken: None,
            casters: None,
            sun_view: None,
            mirror: None,
            sources,
            desc,
        };
        ocean.build()?;
        Ok(ocean)
    }

    /// The renderer's options for the desc: its shading, specialized for its scene where asked.
    fn plan(&self) -> (Options, Vec<Omission>) {
        let desc = &self.desc;
        // The shading's own `background` stays: the sea's aerial perspective goes with it, which
        // a host with its own sky keeps; the composite leaves that host's sky alone.
        let mut shader = desc.shading.shader;
        shader.packets = !self.sources.is_empty();
        // Local reflections need the host's depth (its objects) and the sky term they replace.
        let mut omitted = Vec::new();
        if shader.reflections != Reflections::None && (desc.formats.depth.is_none() || !shader.terms.sky) {
            let what = match shader.reflections {
                Reflections::Screen => "local reflections (their sources pass and depth pyramid)",
                Reflections::Planar => "planar reflections (the mirror pass and its mipmaps)",
                _ => "local and planar reflections (the sources pass, depth pyramid, mirror pass)",
            };
            shader.reflections = Reflections::None;
            let why = if desc.formats.depth.is_none() {
                "the host hands no depth: no objects to reflect"
            } else {
                "the sky term is off: the objects' reflections stand in for part of it"
            };
            omitted.push(Omission { what: what.into(), why: why.into() });
        }
        if !shader.packets {
            omitted.push(Omission {
                what: "wave packets (their binning pass and shader terms)".into(),
                why: "no local waves: the scene has no [[splash]], no [[wake]] and no moving object".into(),
            });
        }
        // The loop the device runs, so that `shader()` names it.
        shader.train_reads = crate::render::passes::shade::train_reads_on(&self.gpu.device, shader.train_reads);
        let options = Options {
            shader,
            ssaa: desc.shading.ssaa,
            output: Output::Host(desc.host_output()),
            frames_in_flight: desc.frames_in_flight,
            statistics: desc.shading.statistics,
            ..Options::default()
        };
        if !desc.shading.specialize_for_scene_camera || desc.width == 0 || desc.height == 0 {
            return (options, omitted);
        }
        let wave_set = waves::generate(&desc.scene);
        let (options, mut more) = specialize::plan(&desc.scene, &wave_set, desc.width, desc.height, options);
        omitted.append(&mut more);
        (options, omitted)
    }

    /// Makes the renderer for the current size and scene (the old one goes first: its memory is
    /// freed before the new one's is taken). On failure the ocean is broken until a rebuild
    /// succeeds.
    fn build(&mut self) -> Result<()> {
        self.renderer = None;
        self.broken = None;
        self.last_frame = None;
        self.prepared = (0..self.desc.frames_in_flight).map(|_| None).collect();
        (self.options, self.omitted) = self.plan();
        if self.desc.width == 0 || self.desc.height == 0 {
            return Ok(());
        }
        let (width, height) = (self.desc.width, self.desc.height);
        match Renderer::with_local_waves(self.gpu, &self.desc.scene, self.sources.clone(), width, height, self.options)
        {
            Ok(renderer) => {
                self.renderer = Some(renderer);
                Ok(())
            }
            Err(e) => {
                self.broken = Some(e.to_string());
                Err(e)
            }
        }
    }

    /// The renderer and frame `slot`'s update, for a pass a host records ahead of the frame
    /// (None while paused); Err where the slot was not updated since its last record.
    fn updated(&mut self, slot: usize) -> Result<Option<(&mut Renderer<'g>, &Prepared)>> {
        let Some(renderer) = self.renderer.as_mut() else { return Ok(None) };
        let prepared = self.prepared[slot]
            .as_ref()
            .ok_or_else(|| Error::Argument(format!("frame slot {slot} was not updated since its last record")))?;
        Ok(Some((renderer, prepared)))
    }

    /// Err while the last rebuild failed.
    fn check_built(&self) -> Result<()> {
        match &self.broken {
            Some(why) => Err(Error::Argument(format!(
                "the ocean has no pipelines: its last resize or scene change failed ({why}); resize or set a scene again"
            ))),
            None => Ok(()),
        }
    }

    /// The targets' new size; zero in either pauses the ocean (update and record do nothing)
    /// until a later resize. The host has waited for every frame in flight.
    pub fn resize(&mut self, width: u32, height: u32) -> Result<()> {
        if (width, height) == (self.desc.width, self.desc.height) && self.broken.is_none() {
            return Ok(());
        }
        if self.desc.in_place.is_some() && (width, height) != (self.desc.width, self.desc.height) {
            return Err(Error::Argument(
                "an ocean drawn in place in the host's colour image is made again for a new size, with an image of \
                 that size (OceanDesc::in_place)"
                    .into(),
            ));
        }
        let previous = (self.desc.width, self.desc.height);
        (self.desc.width, self.desc.height) = (width, height);
        check_desc(self.gpu, &self.desc).inspect_err(|_| (self.desc.width, self.desc.height) = previous)?;
        self.build()
    }

    /// A new sea, sun, sky or settings. Where the pipelines depend on what changed (the sky's
    /// model, the tone, the shadow map, what a scene specialized for its camera leaves out) they
    /// are rebuilt: the host has then waited for every frame in flight.
    pub fn set_scene(&mut self, mut scene: Scene) -> Result<()> {
        scene.validate().map_err(|message| Error::Scene { file: "(host scene)".into(), message })?;
        let sources = Sources::of_named_scene(&scene, "(host scene)")?;
        scene.objects.clear();
        // The scene is kept even if the rebuild fails: the next resize or scene change retries.
        self.desc.scene = scene;
        let fits = self.renderer.as_ref().is_some_and(|r| r.fits(&self.desc.scene) && r.fits_local_waves(&sources));
        if let (true, Some(renderer)) = (fits, self.renderer.as_mut()) {
            renderer.set_local_waves(sources.clone())?;
        }
        self.sources = sources;
        let rebuild = self.broken.is_some()
            || !fits && self.renderer.is_some()
            || self.desc.shading.specialize_for_scene_camera && self.plan().0 != self.options;
        if rebuild {
            self.build()?;
        }
        Ok(())
    }

    /// Whether the ocean is paused (its targets have no pixels).
    pub fn paused(&self) -> bool {
        self.desc.width == 0 || self.desc.height == 0
    }

    /// The host's part of frame `slot`: reads the camera, writes the slot's uniforms and grid.
    /// The host has waited for the frame that last used `slot` (its GPU times are then kept, if
    /// [`Ocean::finished`] did not keep them already).
    pub fn update(&mut self, slot: usize, input: &FrameInput) -> Result<()> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.check_built()?;
        // A failed update leaves no frame for `record` to take.
        self.prepared[slot] = None;
        let Some(renderer) = self.renderer.as_mut() else { return Ok(()) };
        if !input.time_s.is_finite() {
            return Err(Error::Argument(format!("time_s = {} is not finite", input.time_s)));
        }
        let aspect = self.desc.width as f64 / self.desc.height as f64;
        let view = HostView::new(input.view, input.projection, aspect)?;
        if view.reversed_z != self.desc.formats.reversed_z {
            let (asked, made) = if view.reversed_z { ("reversed", "standard") } else { ("standard", "reversed") };
            return Err(Error::Argument(format!(
                "camera: the projection's depth is {asked}, the ocean was made for {made} depth (formats.reversed_z)"
            )));
        }
        let mut scene = self.desc.scene.clone();
        scene.render.time_s = input.time_s;
        scene.camera.x_m = view.eye.x;
        scene.camera.y_m = view.eye.y;
        scene.camera.yaw_deg = view.yaw_deg;
        scene.camera.pitch_deg = view.pitch_deg;
        scene.camera.fov_y_deg = view.fov_y_deg;
        // The ocean's camera height is above the water under the eye where a crest lifts it.
        scene.camera.height_m = view.eye.z;
        let water = waves::generate(&scene).water_height_at_origin(input.time_s).max(0.0);
        scene.camera.height_m = view.eye.z - water;
        scene.validate().map_err(|message| {
            let under = if view.eye.z <= water {
                format!(
                    "the eye at z = {:.3} m is not above the water (the ocean draws from above mean sea level and \
                     the water under the eye, here {water:.3} m)",
                    view.eye.z
                )
            } else {
                message
            };
            Error::Argument(format!("camera: {under}"))
        })?;
        if self.desc.shading.specialize_for_scene_camera {
            check_same_camera(&self.desc.scene.camera, &scene.camera)?;
        }
        let far = if view.reversed_z { 0.0 } else { 1.0 };
        let max = hdr_format_max(self.desc.formats.colour).unwrap_or(65504.0);
        let host = (mat4_f32(view.clip_from_relative), [self.desc.radiance_scale, max, far, 0.0]);
        renderer.begin_host_frame(slot)?;
        let casters = self.casters.map(|(min, max)| CasterBox { min: min - view.eye, max: max - view.eye });
        let prepared = renderer.prepare_host(slot, &scene, host, casters)?;
        self.sun_view = prepared.data().sun_view.map(|v| (v.view_proj.as_mat4(), v.texel_m[0].max(v.texel_m[1])));
        self.mirror = Some(MirrorView {
            clip_from_relative: view.clip_from_relative.as_mat4(),
            eye_height_m: view.eye.z,
            planet_radius_m: scene.planet.radius_m,
        });
        let u = &prepared.data().uniforms;
        let unit = |v: [f32; 4]| [v[0], v[1], v[2]].map(|x| x * self.desc.radiance_scale);
        self.light = Some(Light {
            sun_direction: glam::DVec3::from(prepared.data().sky.sun_dir),
            sun_illuminance: unit(u.sun_irradiance),
            sky_illuminance: unit(u.sky_irradiance),
            sun_radiance: unit(u.sun_radiance),
        });
        self.prepared[slot] = Some(prepared);
        self.last_view = Some(view);
        Ok(())
    }

    /// Records frame `slot` into the host's command buffer `cmd` (recording, outside a rendering
    /// scope), after the host drew into `targets`. On exit:
    /// - the depth is in DEPTH_STENCIL_ATTACHMENT_OPTIMAL, last written by the fragment tests
    ///   (EARLY_FRAGMENT_TESTS | LATE_FRAGMENT_TESTS, DEPTH_STENCIL_ATTACHMENT_WRITE);
    /// - without an LDR target the colour is in COLOR_ATTACHMENT_OPTIMAL, last written at
    ///   COLOR_ATTACHMENT_OUTPUT (COLOR_ATTACHMENT_WRITE);
    /// - with one, the colour is in SHADER_READ_ONLY_OPTIMAL, last read at FRAGMENT_SHADER, and the
    ///   LDR image in COLOR_ATTACHMENT_OPTIMAL, last written at COLOR_ATTACHMENT_OUTPUT.
    pub fn record(&mut self, cmd: vk::CommandBuffer, slot: usize, targets: &Targets) -> Result<()> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.check_built()?;
        let Some(renderer) = self.renderer.as_mut() else { return Ok(()) };
        let extent = vk::Extent2D { width: self.desc.width, height: self.desc.height };
        let formats = self.desc.formats;
        let given = [
            ("colour", Some(&targets.colour), Some(formats.colour)),
            ("depth", targets.depth.as_ref().map(|(i, _)| i), formats.depth),
            ("LDR", targets.ldr.as_ref().map(|(i, _)| i), formats.ldr),
        ];
        for (name, image, format) in given {
            match (image, format) {
                (Some(image), Some(format)) => {
                    if image.extent != extent {
                        return Err(Error::Argument(format!(
                            "the {name} target is {}x{}, the ocean draws {}x{} (resize first)",
                            image.extent.width, image.extent.height, extent.width, extent.height
                        )));
                    }
                    if image.format != format {
                        return Err(Error::Argument(format!(
                            "the {name} target is {:?}, the ocean was made for {format:?}",
                            image.format
                        )));
                    }
                }
                (None, Some(format)) => {
                    return Err(Error::Argument(format!(
                        "the ocean was made with a {name} target of {format:?}: none given"
                    )))
                }
                (Some(_), None) => {
                    return Err(Error::Argument(format!(
                        "a {name} target was given to an ocean made without a {name} format"
                    )))
                }
                (None, None) => {}
            }
        }
        if let Some(image) = self.desc.in_place.filter(|i| i.raw != targets.colour.raw) {
            return Err(Error::Argument(format!(
                "the colour target {:?} is not the image the ocean draws in place ({:?}, OceanDesc::in_place)",
                targets.colour.raw, image.raw
            )));
        }
        let prepared = self.prepared[slot]
            .take()
            .ok_or_else(|| Error::Argument(format!("frame slot {slot} was not updated since its last record")))?;
        let host = HostTargets {
            colour: targets.colour,
            depth: targets.depth.map(|(image, _)| image),
            ldr: targets.ldr.map(|(image, _)| image),
        };
        let depth_entry = targets.depth.map_or(ImageState::DEPTH_ATTACHMENT, |(_, state)| state);
        let ldr_entry = targets.ldr.map_or(ImageState::ACQUIRED, |(_, state)| state);
        let entry = [targets.colour_entry, depth_entry, ldr_entry];
        self.last_frame = Some(renderer.record_for_host(cmd, slot, prepared, host, entry)?);
        Ok(())
    }

    /// Optional, for profiling: the host has just submitted frame `slot`. The clocks are sampled
    /// now, so that [`Ocean::last_gpu_frame`] places the frame's passes on the host's clock.
    pub fn submitted(&mut self, slot: usize) -> Result<()> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.renderer.as_mut().map_or(Ok(()), |r| r.host_submitted(slot))
    }

    /// Optional: the host has waited for frame `slot` (its fence). Its GPU times are kept now
    /// rather than at the slot's next update.
    pub fn finished(&mut self, slot: usize) -> Result<()> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.renderer.as_mut().map_or(Ok(()), |r| r.host_finished(slot))
    }

    /// The camera of the last update, as the ocean draws it.
    pub fn last_view(&self) -> Option<&HostView> {
        self.last_view.as_ref()
    }

    /// The light of the last update (see [`Light`]); None before the first.
    pub fn light(&self) -> Option<Light> {
        self.light
    }

    /// The frame the last record drew, as the ocean built it: its camera, grid, sky and uniforms.
    pub fn last_frame(&self) -> Option<&FrameData> {
        self.last_frame.as_ref()
    }

    /// GPU time per pass (ms) of the latest frame whose results were kept (see [`Ocean::finished`]).
    pub fn pass_ms(&self) -> &[(&'static str, f64)] {
        self.renderer.as_ref().map_or(&[], |r| r.last_pass_ms())
    }

    /// The latest kept frame's passes on the host's clock, with their pipeline statistics where
    /// [`Shading::statistics`] asked for them: for frames the host noted with
    /// [`Ocean::submitted`] and [`Ocean::finished`].
    pub fn last_gpu_frame(&self) -> Option<&GpuFrame> {
        self.renderer.as_ref().and_then(|r| r.last_gpu_frame())
    }

    /// The trains the latest finished frame's shading pass evaluated, for an ocean whose shader
    /// counts them ([`ShaderConfig::count_trains`]; profiling only).
    pub fn train_counts(&self) -> Result<Option<TrainCounts>> {
        self.renderer.as_ref().map_or(Ok(None), |r| r.train_counts())
    }

    /// Sets the box (the ocean's world, m: its least and greatest corners) that holds the shadow
    /// casters the host draws in [`Ocean::record_shadows`], for the sun's view of the next
    /// updates to cover them and the sea they shadow; None: no casters. Fails naming a corner
    /// that is not finite or a box turned inside out.
    pub fn set_shadow_casters(&mut self, bounds: Option<(DVec3, DVec3)>) -> Result<()> {
        if let Some((min, max)) = bounds {
            if !(min.is_finite() && max.is_finite()) {
                return Err(Error::Argument(format!("shadow casters' box {min} .. {max} is not finite")));
            }
            if min.cmpgt(max).any() {
                return Err(Error::Argument(format!(
                    "shadow casters' box {min} .. {max}: a least corner above its greatest"
                )));
            }
        }
        self.casters = bounds;
        Ok(())
    }

    /// Records the sun's shadow map of frame `slot` (updated, not yet recorded) into the host's
    /// command buffer `cmd` (recording, outside a rendering scope), before the host draws its
    /// objects: the waves, then `casters`, which the host records its casters' draws with
    /// (inside the map's rendering scope: a depth-only pipeline for [`SHADOW_FORMAT`], compare
    /// LESS, bias [`SHADOW_DEPTH_BIAS`]; not called while the sun has no view). The map is then
    /// readable by the host's fragment shaders ([`Ocean::sun_shadow`]) until [`Ocean::record`]
    /// of the same frame, which then does not draw it again. Needs [`OceanDesc::shadow_casters`];
    /// Ok(false) where the ocean has no shadow map (no sun term, or `render.shadow_map` off).
    pub fn record_shadows(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        casters: &mut dyn FnMut(vk::CommandBuffer, &CasterView),
    ) -> Result<bool> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.check_built()?;
        if !self.desc.shadow_casters {
            return Err(Error::Argument("record_shadows: the ocean was made without shadow_casters".into()));
        }
        let Some((renderer, prepared)) = self.updated(slot)? else { return Ok(false) };
        renderer.record_host_shadows(cmd, slot, prepared, casters)
    }

    /// What the host draws its objects mirrored about the sea with in the last update's frame,
    /// where the ocean reads planar reflections (`Shading`'s reflections planar or both, with
    /// depth and the sky term): for the host to test which objects' mirror images are in view
    /// before [`Ocean::record_planar`].
    pub fn mirror_view(&self) -> Option<MirrorView> {
        self.renderer.as_ref()?.has_planar().then_some(self.mirror?)
    }

    /// Records the mirror pass of frame `slot` (updated, not yet recorded) into the host's
    /// command buffer `cmd` (recording, outside a rendering scope), before [`Ocean::record`]:
    /// `draw` records the host's objects mirrored about the sea as [`MirrorView`] says, inside
    /// the pass's rendering scope ([`PLANAR_COLOUR_FORMAT`] written with alpha 1,
    /// [`PLANAR_DEPTH_FORMAT`] in the host's own depth convention). `cover` says where they may
    /// lie ([`MirrorView::cover_of`] the corners of their mirrored bounding boxes, or
    /// [`MirrorCover::Whole`]): the draws are scissored to it, and the pass builds what the
    /// shading reads there alone, so a small object's mirror costs a small rectangle's work. The
    /// frame's shading then reads them along each sea pixel's reflected ray. A frame the host
    /// records none for (none of its objects' mirror images in view) reads none, and costs
    /// nothing. Ok(false) where the ocean reads no planar reflections ([`Ocean::mirror_view`]
    /// None).
    pub fn record_planar(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        cover: MirrorCover,
        draw: &mut dyn FnMut(vk::CommandBuffer, &MirrorView),
    ) -> Result<bool> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.check_built()?;
        let mirror = self.mirror;
        let Some((renderer, prepared)) = self.updated(slot)? else { return Ok(false) };
        let Some(view) = mirror else { return Ok(false) };
        renderer.record_host_planar(cmd, slot, prepared, &view, cover, draw)
    }

    /// The share of the mirror's images (texels) that the latest recorded frame's
    /// [`Ocean::record_planar`] built: the host's [`MirrorCover`], grown by a texel and clamped; 1
    /// for [`MirrorCover::Whole`]. None where that frame drew no mirror.
    pub fn planar_cover_share(&self) -> Option<f64> {
        self.renderer.as_ref()?.planar_cover_share()
    }

    /// The last updated frame's wave packets: how many it drew, in how many cells, and the share
    /// of their sources' energy the budget (`packets.max_alive`) left out. None without local
    /// waves.
    pub fn packet_stats(&self) -> Option<PacketStats> {
        self.renderer.as_ref()?.packet_stats()
    }

    /// The last updated frame's wave packets in the eye's frame (rest positions from the point
    /// below the eye, as the trains'), for a host's floating objects to ride
    /// (model::floating::ride_with_packets). None without local waves.
    pub fn packet_field(&self) -> Option<&crate::model::packets::PacketField> {
        self.renderer.as_ref()?.packet_field()
    }

    /// Records a pass of the host's own (`record`, into its command buffer `cmd`) ahead of
    /// frame `slot`'s [`Ocean::record`], inside the frame's profile: wrapped in a debug label and
    /// a timestamp scope `name`, it is timed with the ocean's passes ([`Ocean::pass_ms`]), and
    /// RenderDoc, Nsight and the ocean's traces show it under that name. The slot is updated and
    /// not yet recorded; at most [`HOST_PASSES`] such passes a frame. While the ocean is paused
    /// (a zero size) `record` runs untimed.
    pub fn record_host_pass(
        &mut self,
        cmd: vk::CommandBuffer,
        slot: usize,
        name: &'static str,
        record: &mut dyn FnMut(vk::CommandBuffer),
    ) -> Result<()> {
        check_slot(slot, self.desc.frames_in_flight)?;
        self.check_built()?;
        match self.updated(slot)? {
            Some((renderer, _)) => renderer.record_host_pass(cmd, slot, name, record),
            None => {
                record(cmd);
                Ok(())
            }
        }
    }

    /// The sun's shadow map of the last update, where the ocean has one; its contents are the
    /// frame's after [`Ocean::record_shadows`].
    pub fn sun_shadow(&self) -> Option<SunShadow> {
        let (view, sampler) = self.renderer.as_ref()?.sun_shadow_map()?;
        let (clip_from_relative, texel_m) = self.sun_view.map_or((None, 0.0), |(m, t)| (Some(m), t));
        Some(SunShadow { view, sampler, clip_from_relative, texel_m })
    }

    /// The names of the ocean's passes in a frame, in order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        self.renderer.as_ref().map_or_else(Vec::new, |r| r.pass_names())
    }

    /// The passes the last recorded frame left out because their results were still current
    /// (the sky's tables and map under the same sun and sky, what depends on an unchanged view).
    pub fn skipped_last_frame(&self) -> &[&'static str] {
        self.renderer.as_ref().map_or(&[], |r| r.skipped_last_frame())
    }

    /// What the shading left out for the scene seen from its camera
    /// ([`Shading::specialize_for_scene_camera`]), and why.
    pub fn omitted(&self) -> &[Omission] {
        &self.omitted
    }

    /// The shader configuration the pipelines were made with: the desc's, specialized where
    /// asked, with the wave-table reads the device runs.
    pub fn shader(&self) -> ShaderConfig {
        self.options.shader
    }

    /// The names of the pipelines the ocean's frame uses (its passes' shaders and variants).
    pub fn pipelines(&self) -> Vec<String> {
        specialize::pipelines(&self.options)
    }

    /// What the ocean's sub-allocator holds on the host's device.
    pub fn memory(&self) -> MemoryReport {
        self.gpu.allocator.borrow().report()
    }

    /// What the ocean was made for, with the size and scene of the latest resize and scene change.
    pub fn desc(&self) -> &OceanDesc {
        &self.desc
    }
}

/// Err unless `camera` is the scene's own (an ocean specialized for the scene's camera).
fn check_same_camera(planned: &crate::model::scene::Camera, camera: &crate::model::scene::Camera) -> Result<()> {
    // The matrices' f64 round trip moves a value by rounding far below a millionth (the eye's
    // distance from the origin and the near plane's set how far); a moved camera by far more.
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1.0);
    let pairs = [
        ("x_m", planned.x_m, camera.x_m),
        ("y_m", planned.y_m, camera.y_m),
        ("height_m", planned.height_m, camera.height_m),
        // The yaw read back from the matrices is within (-180, 180].
        ("yaw_deg", planned.yaw_deg, camera.yaw_deg + 360.0 * ((planned.yaw_deg - camera.yaw_deg) / 360.0).round()),
        ("pitch_deg", planned.pitch_deg, camera.pitch_deg),
        ("fov_y_deg", planned.fov_y_deg, camera.fov_y_deg),
    ];
    match pairs.iter().find(|(_, a, b)| !same(*a, *b)) {
        Some((key, a, b)) => Err(Error::Argument(format!(
            "camera: this ocean was specialized for the scene's camera ({key} = {a}), the frame's has {key} = {b} \
             (shading.specialize_for_scene_camera: a moving camera needs it off)"
        ))),
        None => Ok(()),
    }
}

fn check_slot(slot: usize, frames: u32) -> Result<()> {
    if slot >= frames as usize {
        return Err(Error::Argument(format!(
            "frame slot {slot} is out of range: this ocean has {frames} frames in flight (0 to {})",
            frames - 1
        )));
    }
    Ok(())
}

fn check_desc(gpu: &Gpu, desc: &OceanDesc) -> Result<()> {
    desc.scene.validate().map_err(|message| Error::Scene { file: "(host scene)".into(), message })?;
    if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&desc.frames_in_flight) {
        return Err(Error::Argument(format!(
            "frames_in_flight = {} is out of range [1, {MAX_FRAMES_IN_FLIGHT}]",
            desc.frames_in_flight
        )));
    }
    if !(desc.radiance_scale.is_finite() && desc.radiance_scale > 0.0) {
        return Err(Error::Argument(format!("radiance_scale = {} must be finite and > 0", desc.radiance_scale)));
    }
    let formats = desc.formats;
    if hdr_format_max(formats.colour).is_none() {
        return Err(Error::Argument(format!(
            "colour format {:?} is not one the ocean writes HDR radiance to (R16G16B16A16_SFLOAT, \
             B10G11R11_UFLOAT_PACK32, R32G32B32A32_SFLOAT)",
            formats.colour
        )));
    }
    if let Some(depth) = formats.depth.filter(|d| !HOST_DEPTH_FORMATS.contains(d)) {
        return Err(Error::Argument(format!(
            "depth format {depth:?} is not one the ocean tests against ({HOST_DEPTH_FORMATS:?})"
        )));
    }
    let ssaa = desc.shading.ssaa;
    if !(1..=MAX_SSAA).contains(&ssaa) {
        return Err(Error::Argument(format!("shading.ssaa = {ssaa} is out of range [1, {MAX_SSAA}]")));
    }
    if ssaa > 1 && (formats.depth.is_some() || !desc.sky) {
        return Err(Error::Argument(format!(
            "shading.ssaa = {ssaa} needs a frame wholly the ocean's (formats.depth = None, sky on): the sea's depth \
             that decides what the host keeps is one per output pixel"
        )));
    }
    if let Some(ldr) = formats.ldr.filter(|&f| ldr_encodes_srgb(f).is_none()) {
        return Err(Error::Argument(format!(
            "LDR format {ldr:?} is not one the ocean tone-maps into (R8G8B8A8 or B8G8R8A8, UNORM or SRGB; \
             A8B8G8R8 likewise; A2B10G10R10_UNORM)"
        )));
    }
    if let Some(image) = &desc.in_place {
        if !desc.host_output().owns_frame() || ssaa > 1 {
            return Err(Error::Argument(
                "in_place: only a frame wholly the ocean's is drawn in the host's image (no depth format, sky on, \
                 an R16G16B16A16_SFLOAT colour, radiance_scale 1, ssaa 1)"
                    .into(),
            ));
        }
        if image.format != HDR_FORMAT || image.extent != (vk::Extent2D { width: desc.width, height: desc.height }) {
            return Err(Error::Argument(format!(
                "in_place: the image is {:?} at {}x{}, the ocean draws {HDR_FORMAT:?} at {}x{}",
                image.format, image.extent.width, image.extent.height, desc.width, desc.height
            )));
        }
    }
    let device = &gpu.device;
    let ldr = formats.ldr.map(|f| (f, vk::FormatFeatureFlags::COLOR_ATTACHMENT, "an LDR colour attachment"));
    let depth = formats.depth.map(|f| (f, vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT, "a depth attachment"));
    // With an LDR target the ocean samples the host's colour to tone-map it.
    let colour_needs = if formats.ldr.is_some() {
        vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE
    } else {
        vk::FormatFeatureFlags::COLOR_ATTACHMENT
    };
    for (format, needed, what) in [(formats.colour, colour_needs, "a colour attachment (sampled, with an LDR target)")]
        .into_iter()
        .chain(depth)
        .chain(ldr)
    {
        // SAFETY: plain query on the host's physical device.
        let props = unsafe { gpu.instance.raw.get_physical_device_format_properties(device.physical, format) };
        if !props.optimal_tiling_features.contains(needed) {
            return Err(Error::MissingFeature {
                device: device.name.clone(),
                feature: format!("{format:?} as {what}"),
            });
        }
    }
    Ok(())
}

fn mat4_f32(m: DMat4) -> [[f32; 4]; 4] {
    m.as_mat4().to_cols_array_2d()
}
