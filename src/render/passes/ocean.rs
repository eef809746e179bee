//! The ocean's visibility pass: the projected grid, displaced by the trains it resolves, with
//! reversed-Z depth; each pixel keeps the rest position of the surface point it sees (in the HDR
//! image's bits, see glsl/ocean.frag), for the shading pass (shade.rs). Also the ocean shaders'
//! configuration, shared by both passes.

use super::packets::{
    declare_packet_reads, write_packet_bindings, PACKETS_BINDING_READ, PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE,
};
use super::shade::SHADE_GROUP;
use super::{whole_viewport, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::model::scene::{Reflections, ShadowMapMode};
use crate::render::resources::{Resources, EYE_SKY_BINDING, FRAME_BINDING, WAVES_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::{Device, DEPTH_FORMAT, HDR_BITS_FORMAT};
use crate::vk::owned::Owned;
use crate::vk::pipeline::{graphics_pipeline, Bindings, GraphicsDesc, Specialization};
use ash::vk;

/// Which BRDF terms the ocean shader evaluates (specialization constants 0, 1, 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terms {
    pub sun: bool,
    pub sky: bool,
    pub sea: bool,
}

impl Terms {
    pub const ALL: Terms = Terms { sun: true, sky: true, sea: true };
}

/// How the waves are split between geometry, normals and BRDF, and how the sky is reflected
/// (specialization constant 3: the discriminant, as glsl/common.glsl numbers them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The paper, and ours beyond it: its sky lookup centred on the facets actually seen, and
    /// reflections below the horizon meeting the sea instead of a mirrored sky (docs/results.md).
    Full = 3,
    /// The paper as published: filtered geometry and normals, the unresolved slopes in the BRDF.
    Paper = 0,
    /// The paper's baseline: the same geometry and normals, unresolved waves dropped, a constant
    /// roughness (the residual slope variance of the nearest visible sea).
    ConstantBrdf = 1,
    /// Every train in geometry and normals, unfiltered, with a mirror BRDF (aliased).
    NoFilter = 2,
}

impl Method {
    pub const ALL: [Method; 4] = [Method::Full, Method::Paper, Method::ConstantBrdf, Method::NoFilter];

    pub fn name(self) -> &'static str {
        match self {
            Method::Full => "full",
            Method::Paper => "paper",
            Method::ConstantBrdf => "constant-brdf",
            Method::NoFilter => "no-filter",
        }
    }
}

/// How the shading pass reads the wave table in its per-pixel loop (glsl/shade.glsl). Both give
/// the same sums, to rounding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TrainReads {
    /// A block of trains per read, shared across each subgroup by broadcasts (glsl/train_blocks.glsl),
    /// where the device's compute subgroups allow it; else per train.
    Blocks,
    /// One train per loop iteration, read by every invocation.
    PerTrain,
}

/// The ocean shaders' specialization.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ShaderConfig {
    pub terms: Terms,
    pub method: Method,
    pub train_reads: TrainReads,
    /// Whether the vertex stage displaces the grid (specialization constant 4).
    pub geometry: bool,
    /// Whether the sky is drawn behind the sea; renders of single terms leave it out (black), so
    /// that their pixels hold just those terms.
    pub background: bool,
    /// Whether the shading pass counts the trains it evaluates (specialization constant 7;
    /// profiling only: a normal frame's shader has no counting code).
    pub count_trains: bool,
    /// Whether the sky is the physical atmosphere (specialization constant 8; set from the scene
    /// by the renderer): its map (the sky seen from the sea, which the sea reflects) and the eye's
    /// own sky-view table (the sky seen directly) are raymarched through the atmosphere's tables.
    pub sky_physical: bool,
    /// Whether the displaced grid shadows the reflected sun through the sun's shadow map
    /// (specialization constant 9; passes/shadow.rs draws it). The renderer keeps it only with the
    /// sun term, the displacement and `render.shadow_map` not "off".
    pub shadow: bool,
    /// Whether the shading pass resolves trains into per-pixel normals (specialization constant
    /// 11): its train loop. Left out where no pixel in view resolves any train (specialize::plan).
    pub normals: bool,
    /// Whether the shading pass applies the physical sky's aerial perspective (constant 12), whose
    /// atlases passes/atmosphere.rs builds. Left out where the farthest visible sea is close.
    pub aerial: bool,
    /// Whether the full method draws the reflected sun as glints, a count of lit facets per pixel
    /// (constant 13, glsl/glints.glsl), instead of its expected value. Only the full method has
    /// them; the renderer keeps them only with the sun term.
    pub glints: bool,
    /// Whether the full method's shading pass may step to where a pixel's ray meets the sea
    /// (constant 14, glsl/shade.glsl ray_hit_strength): its gate and its loop. Left out where no
    /// pixel in view can resolve enough of the slopes for the step to be taken.
    pub ray_hit: bool,
    /// How the sea reflects the host's objects: in screen space (constant 15, glsl/shade.glsl
    /// local_reflection; passes/reflections.rs builds what it reads), through the host's mirror
    /// pass (constant 16, planar_reflection; passes/planar.rs), or both. The renderer keeps them
    /// only in a host's frame with depth (objects to reflect) and with the sky term.
    pub reflections: Reflections,
    /// Where the mirror is the only reflection read: whether the sea-only rows' tiles are sorted
    /// by whether they may read it (passes/planar_tiles.rs), and those that cannot are shaded
    /// without its code (constant 17). Off: every tile with it (for comparison).
    pub planar_tiles: bool,
    /// Whether the mirror pass builds its images only where the host's mirrored objects may lie
    /// (passes/planar.rs MirrorCover). Off: over the whole images, whatever the host says (for
    /// comparison).
    pub planar_cover: bool,
    /// Whether the frame has wave packets (constant 18, glsl/packets.glsl): the grid displaces
    /// them and the pixels shade them. Set from the scene's local waves by the renderer.
    pub packets: bool,
}

impl Default for ShaderConfig {
    fn default() -> Self {
        ShaderConfig {
            terms: Terms::ALL,
            method: Method::Full,
            train_reads: TrainReads::Blocks,
            geometry: true,
            background: true,
            count_trains: false,
            sky_physical: false,
            shadow: true,
            normals: true,
            aerial: true,
            glints: true,
            ray_hit: true,
            reflections: Reflections::Screen,
            planar_tiles: true,
            planar_cover: true,
            packets: false,
        }
    }
}

impl ShaderConfig {
    /// Whether a frame draws nothing but black: no term to shade and no sky behind the sea.
    pub fn draws_nothing(&self) -> bool {
        !(self.terms.sun || self.terms.sky || self.terms.sea || self.background)
    }

    /// Whether the shading pass draws glints: asked for, the full method's, and with a sun term.
    pub fn draws_glints(&self) -> bool {
        self.glints && self.method == Method::Full && self.terms.sun
    }

    /// Whether the shading pass may take the step to where the pixel's ray meets the sea: the
    /// full method's, with per-pixel normals to step over.
    pub fn steps_to_ray_hit(&self) -> bool {
        self.ray_hit && self.method == Method::Full && self.normals
    }

    /// Why a frame with this configuration has no use for the sun's shadow map (None: it has);
    /// the renderer and specialize::plan both go by it.
    pub fn shadow_map_unneeded(&self, mode: ShadowMapMode, host_casters: bool) -> Option<String> {
        if mode == ShadowMapMode::Off {
            Some("render.shadow_map = \"off\"".to_owned())
        } else if !self.terms.sun {
            Some("no sun term to shadow".to_owned())
        } else if self.draws_nothing() || (!self.geometry && !host_casters) {
            let forced = if mode == ShadowMapMode::On { " (render.shadow_map = \"on\")" } else { "" };
            Some(format!("no train is displaced by the grid, so none casts a shadow{forced}"))
        } else {
            None
        }
    }

    /// The specialization constants of both ocean passes (glsl/common.glsl, ocean.vert,
    /// shade.comp): the terms (0-2), the method (3), geometry (4) and the background (5); for the
    /// shading pass also whether its rows see only sea (6) and whether it counts trains (7); the
    /// sky's model (8) and the sun's shadows (9) for all; whether the grid is drawn from the sun
    /// (10, the shadow pass's vertex stage only); the shading pass's normals (11) and aerial
    /// perspective (12); the glints (13); the step to where the pixel's ray meets the sea (14).
    pub fn specialization(&self) -> Specialization {
        self.shade_specialization(false)
    }

    /// The shadow pass's: the visibility pass's vertex stage, seen from the sun.
    pub fn sun_view_specialization(&self) -> Specialization {
        self.words(false, true)
    }

    pub fn shade_specialization(&self, sea_only: bool) -> Specialization {
        self.words(sea_only, false)
    }

    /// The sea-only rows' shader for one of the planar tiles' lists (passes/planar_tiles.rs):
    /// with the mirror's code (`reads_mirror`) or without.
    pub fn shade_tiled_specialization(&self, reads_mirror: bool) -> Specialization {
        let mut words = self.word_list(true, false);
        words[16] = u32::from(reads_mirror && self.reflections.planar());
        words[TILED_CONSTANT] = 1;
        Specialization::words(&words)
    }

    fn words(&self, sea_only: bool, sun_view: bool) -> Specialization {
        Specialization::words(&self.word_list(sea_only, sun_view))
    }

    /// Constants 0 to 18 of the ocean's shaders, in order: 17 (glsl/shade.glsl TILED) is the
    /// tiled shading pass's alone, 18 the packets.
    fn word_list(&self, sea_only: bool, sun_view: bool) -> Vec<u32> {
        vec![
            self.terms.sun as u32,
            self.terms.sky as u32,
            self.terms.sea as u32,
            self.method as u32,
            self.geometry as u32,
            self.background as u32,
            sea_only as u32,
            self.count_trains as u32,
            self.sky_physical as u32,
            self.shadow as u32,
            sun_view as u32,
            self.normals as u32,
            self.aerial as u32,
            self.draws_glints() as u32,
            self.steps_to_ray_hit() as u32,
            self.reflections.screen() as u32,
            self.reflections.planar() as u32,
            0,
            self.packets as u32,
        ]
    }

    /// Only `terms`, on black (for comparing terms one by one).
    pub fn terms_only(terms: Terms, method: Method) -> ShaderConfig {
        ShaderConfig { terms, method, background: false, ..ShaderConfig::default() }
    }
}

/// The tiled shading pass's constant (glsl/shade.glsl TILED).
const TILED_CONSTANT: usize = 17;

/// The clear value of pixels no grid triangle covers: +Inf as the rest position's x, the bits of
/// `NO_SEA_BITS` in glsl/common.glsl.
const NO_SEA_CLEAR: [u32; 4] = [0x0000, 0x7f80, 0x0000, 0x7f80];

pub struct OceanPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// The sky in the top rows only sky covers (`sky_shaded_rows`), where the shading pass
    /// does not run; absent when the picture has no background (renders of some terms).
    sky: Option<Owned<'g, vk::Pipeline>>,
}

/// The top rows that the visibility pass shades with the sky itself: the rows only sky covers
/// (frame::sky_only_rows), down to whole workgroup rows of the shading pass.
pub fn sky_shaded_rows(sky_rows: u32) -> u32 {
    sky_rows / SHADE_GROUP * SHADE_GROUP
}

impl<'g> OceanPass<'g> {
    pub fn new(device: &'g Device, r: &Resources, config: ShaderConfig) -> Result<Self> {
        use vk::DescriptorType as D;
        let both = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let bindings = Bindings::new(
            device,
            "ocean",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, both),
                (WAVES_BINDING, D::UNIFORM_BUFFER_DYNAMIC, both),
                (EYE_SKY_BINDING, D::COMBINED_IMAGE_SAMPLER, vk::ShaderStageFlags::FRAGMENT),
                (PACKETS_BINDING_READ, PACKET_READ_TYPE, vk::ShaderStageFlags::VERTEX),
                (PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE, vk::ShaderStageFlags::VERTEX),
            ],
        )?;
        write_frame_uniforms(&bindings, r, true);
        write_packet_bindings(&bindings, r);
        // The physical sky seen directly (sky.frag; a placeholder without the physical sky).
        bindings.write_image(
            EYE_SKY_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            r.eye_sky.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            r.sky_sampler.raw,
        );
        let spec = config.specialization();
        let pipeline = graphics_pipeline(
            device,
            bindings.layout(),
            &GraphicsDesc {
                name: "ocean",
                vertex: shaders::OCEAN_VERT,
                fragment: Some(shaders::OCEAN_FRAG),
                specialization: Some(&spec),
                color_format: Some(HDR_BITS_FORMAT),
                depth_format: DEPTH_FORMAT,
                depth_write: true,
                depth_compare: vk::CompareOp::GREATER, // reversed Z
                depth_bias: None,
                cull_back_faces: None,
            },
        )?;
        let sky = if config.background {
            Some(graphics_pipeline(
                device,
                bindings.layout(),
                &GraphicsDesc {
                    name: "sky",
                    vertex: shaders::FULLSCREEN_VERT,
                    fragment: Some(shaders::SKY_FRAG),
                    specialization: Some(&spec),
                    color_format: Some(HDR_BITS_FORMAT),
                    depth_format: DEPTH_FORMAT,
                    depth_write: false,
                    depth_compare: vk::CompareOp::ALWAYS, // the rows hold no sea
                    depth_bias: None,
                    cull_back_faces: None,
                },
            )?)
        } else {
            None
        };
        Ok(OceanPass { bindings, pipeline, sky })
    }
}

impl Pass for OceanPass<'_> {
    fn name(&self) -> &'static str {
        "ocean"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        if self.sky.is_some() {
            t.image(&r.eye_sky, 0, 1, Access::FragmentSampled, false);
        }
        t.image(&r.hdr, 0, 1, Access::ColorAttachmentWrite, true);
        t.image(&r.depth, 0, 1, Access::DepthAttachmentReadWrite, true);
        declare_packet_reads(r, t, Access::VertexSampled);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let extent = r.hdr.extent;
        let color = [vk::RenderingAttachmentInfo::default()
            .image_view(r.hdr.alias_view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { uint32: NO_SEA_CLEAR } })
            .store_op(vk::AttachmentStoreOp::STORE)];
        let depth = vk::RenderingAttachmentInfo::default()
            .image_view(r.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            // The shading pass places each pixel's surface point from it for the sun's shadows, and
            // the composite each sea pixel's depth in a host's frame.
            .store_op(if r.depth_read { vk::AttachmentStoreOp::STORE } else { vk::AttachmentStoreOp::DONT_CARE })
            .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 } });
        let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&color)
            .depth_attachment(&depth);
        let viewport = whole_viewport(extent);
        let sky_rows = sky_shaded_rows(rec.frame.sky_rows).min(extent.height);
        // SAFETY: attachments are in the layouts declared above; the pipelines were built for
        // these formats; the slot's index buffer holds `count` valid indices.
        unsafe {
            device.cmd_begin_rendering(cmd, &info);
            device.cmd_set_viewport(cmd, 0, &[viewport]);
            self.bindings.bind(cmd, vk::PipelineBindPoint::GRAPHICS, &rec.frame.uniform_offsets);
            if let Some((indices, count)) = rec.frame.grid {
                device.cmd_set_scissor(cmd, 0, &[area]);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
                device.cmd_bind_index_buffer(cmd, indices, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, count, 1, 0, 0, 0);
            }
            if let (Some(sky), true) = (&self.sky, sky_rows > 0) {
                let rows = vk::Rect2D { extent: vk::Extent2D { height: sky_rows, ..extent }, ..area };
                device.cmd_set_scissor(cmd, 0, &[rows]);
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, sky.raw);
                device.cmd_draw(cmd, 3, 1, 0, 0);
            }
            device.cmd_end_rendering(cmd);
        }
    }
}
