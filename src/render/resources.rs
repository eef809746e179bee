//! The GPU resources the frames share, created once for an image size (the per-frame ones are in
//! in_flight.rs); each releases itself when dropped (also when a later one fails to be created).

use crate::error::{Error, Result, VkContext};
use crate::model::fresnel::MeanFresnelTable;
use crate::render::frame::{FrameUniforms, GpuWaves};
use crate::render::packets::{PacketBuffers, PacketTexels};
use crate::render::passes::shade::shade_tiles;
use crate::vk::buffer::Buffer;
use crate::vk::device::{DEPTH_FORMAT, HDR_BITS_FORMAT, HDR_FORMAT};
use crate::vk::external::HostImage;
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use ash::vk;

/// Sky map resolution (texels per side) and thus mip levels: log2(512) + 1.
pub const SKY_MAP_SIZE: u32 = 512;
/// Binding numbers of the two per-frame uniform blocks (glsl/frame.glsl).
pub const FRAME_BINDING: u32 = 0;
pub const WAVES_BINDING: u32 = 1;
/// Binding of the measured exposure in the exposure and tone-mapping passes (glsl/tone.glsl).
pub const EXPOSURE_BINDING: u32 = 7;
/// Binding of the mean Fresnel table in the shading, sky-map and numerics shaders
/// (glsl/slopes.glsl, MeanFresnel).
pub const MEAN_FRESNEL_BINDING: u32 = 11;
/// Binding of the eye's sky-view table in the visibility and shading passes (glsl/sky.glsl,
/// EYE_SKY_SAMPLER).
pub const EYE_SKY_BINDING: u32 = 10;
/// Binding of the sea-level light table in the shading pass (glsl/shade.glsl, each sea point's
/// light under its own sun).
pub const SEA_LIGHT_BINDING: u32 = 13;

/// What the resources are made for.
#[derive(Clone, Copy, Debug)]
pub struct ResourceSpec {
    pub width: u32,
    pub height: u32,
    /// Samples per pixel along each axis.
    pub ssaa: u32,
    /// Whether the sky map is built (else a 1x1 placeholder keeps its binding valid).
    pub sky_map: bool,
    pub anisotropy: f32,
    /// Frames in flight: the uniform ring's slots.
    pub slots: u32,
    /// Whether frames are read back to the host (offscreen rendering).
    pub readback: bool,
    /// Whether frames are composited into a host's frame (passes/composite.rs reads the depth).
    pub composite: bool,
    /// Whether the sky is the physical atmosphere (its tables are made).
    pub atmosphere: bool,
    /// The sun's shadow map's texels per side, when it is drawn (else a 1x1 placeholder keeps
    /// the shading pass's bindings valid).
    pub shadow_map: Option<u32>,
    /// Whether the sky seen directly is raymarched from the eye into its own table (else a 1x1
    /// placeholder keeps the bindings valid).
    pub eye_sky: bool,
    /// Whether the aerial perspective's atlases are built (else 1x1 placeholders).
    pub aerial: bool,
    /// A host's colour image the frame is drawn in place of our HDR image (embed::OceanDesc::
    /// in_place): its format and size are the HDR image's, without supersampling.
    pub in_place: Option<HostImage>,
    /// Whether the sea reflects the host's objects (passes/reflections.rs).
    pub reflections: bool,
    /// Whether the sea reflects the host's objects drawn mirrored (passes/planar.rs).
    pub planar: bool,
    /// Whether the shading pass's sea-only tiles are sorted by whether they may read the mirror
    /// (passes/planar_tiles.rs), where the mirror is its only reflection read.
    pub planar_tiles: bool,
    /// The most wave packets alive at once, where the scene has local waves (their buffers are
    /// made; passes/packets.rs bins them).
    pub packets: Option<usize>,
}

/// What the sea's local reflections read (passes/reflections.rs), at the host's size, every
/// level down to 1 x 1.
pub struct ReflectionImages<'g> {
    /// The objects' radiance premultiplied by their coverage (glsl/reflection_sources.comp).
    pub colour: Image<'g>,
    /// Their nearest forward depth per cell of each level (R32F).
    pub depth: Image<'g>,
    /// A view of each level of `depth`, for the pyramid's storage writes and reads.
    pub depth_levels: Vec<Owned<'g, vk::ImageView>>,
    /// The screen rectangle holding every object, in level-0 pixels (min x, min y, max x, max y;
    /// empty, min past max, without objects), then their nearest forward depth
    /// (glsl/reflection_bounds.comp).
    pub bounds: Buffer<'g>,
}

/// What the sea's planar reflections read (passes/planar.rs), at the host's size: the host's
/// objects drawn mirrored about the sea into `colour`'s level 0 and `depth`, then `colour`'s
/// mipmap and `inverse_depth`'s.
pub struct PlanarImages<'g> {
    /// The mirrored objects' radiance (host unit) premultiplied by their coverage: drawn with
    /// alpha 1 on a cleared (0) image; each level the mean of the one above.
    pub colour: Image<'g>,
    /// The host's depth attachment (PLANAR_DEPTH_FORMAT, the host's depth convention).
    pub depth: Image<'g>,
    /// The objects' coverage (x) and coverage over forward depth (y, 1/m), each level the mean
    /// of every texel above it (RGBA16F, a storage format every device has): a footprint's
    /// harmonic mean depth is x / y.
    pub inverse_depth: Image<'g>,
    pub inverse_depth_levels: Vec<Owned<'g, vk::ImageView>>,
}

/// The mirror pass's depth (every device supports it as a depth attachment, and sampled).
pub const PLANAR_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The depth pyramid's format: forward depths in metres, to 100 km and beyond in full precision.
pub const REFLECTION_DEPTH_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

/// Where the planar tiles' lists start (glsl/planar_tiles.comp PlanarTiles): after two
/// VkDispatchIndirectCommands, each padded to 16 bytes (the lists' own dispatches read them at
/// 0 and PLANAR_TILE_ARGS_STRIDE).
pub const PLANAR_TILE_LISTS_OFFSET: u64 = 32;
pub const PLANAR_TILE_ARGS_STRIDE: u64 = 16;

/// The physical atmosphere's tables (glsl/atmosphere.glsl), sampled linearly, clamped.
pub struct AtmosphereTables<'g> {
    /// Transmittance to the top of the atmosphere (atmosphere::TRANSMITTANCE_SIZE).
    pub transmittance: Image<'g>,
    /// Hillaire's multiple scattering psi_ms (atmosphere::MULTIPLE_SCATTERING_SIZE squared).
    pub multiple_scattering: Image<'g>,
    /// The sky seen from the sea over the upper hemisphere (atmosphere::SKY_VIEW_SIZE), rebuilt
    /// with the sky map, which is resampled from it.
    pub sky_view: Image<'g>,
    /// The light at sea level as a function of the sun's zenith cosine: the sky's irradiance on
    /// level sea (row 0) and the sun's normal to it (row 1) (atmosphere::SEA_IRRADIANCE_SIZE x 2,
    /// glsl/sea_irradiance.comp).
    pub sea_irradiance: Image<'g>,
    pub sampler: Owned<'g, vk::Sampler>,
}

/// Host-written uniform blocks, one window per frame in flight, bound with a dynamic offset.
pub struct UniformRing<'g> {
    pub buffer: Buffer<'g>,
    /// Bytes per slot: the block's size rounded up to minUniformBufferOffsetAlignment.
    pub stride: u64,
    /// The block's size (the descriptor's range).
    pub size: u64,
}

impl<'g> UniformRing<'g> {
    fn new(gpu: &'g Gpu, name: &str, size: u64, slots: u32) -> Result<Self> {
        let align = gpu.device.properties.limits.min_uniform_buffer_offset_alignment.max(1);
        let stride = size.div_ceil(align) * align;
        let buffer =
            Buffer::new(gpu, name, stride * slots as u64, vk::BufferUsageFlags::UNIFORM_BUFFER, Location::Upload)?;
        Ok(UniformRing { buffer, stride, size })
    }

    pub fn write<T: Copy>(&self, slot: usize, value: &T) -> Result<()> {
        self.buffer.write_at(self.stride * slot as u64, std::slice::from_ref(value))
    }

    pub fn offset(&self, slot: usize) -> u32 {
        (self.stride * slot as u64) as u32
    }
}

pub struct Resources<'g> {
    pub frame_uniforms: UniformRing<'g>,
    pub waves: UniformRing<'g>,
    pub sky_map: Image<'g>,
    pub sky_sampler: Owned<'g, vk::Sampler>,
    /// HDR radiance at the rendering size (the output size times the supersampling factor). Its
    /// `alias_view` sees the texels' bits as HDR_BITS_FORMAT: the visibility pass stores each
    /// pixel's rest position there, which the shading pass replaces with the radiance.
    pub hdr: Image<'g>,
    /// The camera's depth (reversed Z); sampled by the shading pass for the sun's shadows.
    pub depth: Image<'g>,
    /// The sun's view of the displaced grid (passes/shadow.rs), depth nearest the sun; a 1x1
    /// placeholder (never written, never read: the shader's code for it is specialized away)
    /// without shadows. `depth` is then bound in its place too.
    pub shadow_map: Image<'g>,
    /// Whether `shadow_map` is the real one.
    pub shadows: bool,
    /// Whether a pass after the visibility pass reads `depth` (the shadows, or the composite).
    pub depth_read: bool,
    /// Compares a depth against the shadow map's (1: lit), blended over 2 x 2 texels where the
    /// device filters depth linearly.
    pub shadow_sampler: Owned<'g, vk::Sampler>,
    /// Nearest, no comparison: the camera's depth read texel by texel.
    pub depth_sampler: Owned<'g, vk::Sampler>,
    /// With supersampling, the resolved HDR radiance at the output size.
    pub resolved: Option<Image<'g>>,
    /// Offscreen rendering only: the HDR radiance and the tone-mapped pixels for the host.
    pub readback: Option<Readback<'g>>,
    /// The shading pass's train counters (TrainCounts in glsl/shade.glsl): bound always, written
    /// only by a shader specialized to count (profiling).
    pub train_counts: Buffer<'g>,
    /// With the physical sky: the atmosphere's tables, built by the `atmosphere` pass.
    pub atmosphere: Option<AtmosphereTables<'g>>,
    /// The aerial perspective between the eye and the sea (glsl/aerial_perspective.comp): with the
    /// physical sky AERIAL_SIZE slices of AERIAL_SIZE^2 rays side by side, else 1x1 placeholders
    /// that keep the shading pass's bindings valid (its code for them is specialized away).
    pub aerial_inscatter: Image<'g>,
    pub aerial_transmittance: Image<'g>,
    /// The sky seen from the eye (passes/eye_sky.rs, glsl/sky_view.comp's EYE_VIEW), where the
    /// eye is high enough for it to differ from the sea's sky in the map; else a 1x1 placeholder.
    pub eye_sky: Image<'g>,
    /// The exact Fresnel averaged over the visible slopes (model::fresnel) by table cell, written once here:
    /// host writes before a submission are visible to it, so no pass declares it.
    pub mean_fresnel: Buffer<'g>,
    /// The measured exposure (glsl/exposure.comp writes it, the tone mapping reads it as a
    /// uniform block: MeasuredExposure); bound always, written only with render.ev100 = "auto".
    pub exposure: Buffer<'g>,
    /// The local reflections' sources, in a host's frame that reflects its objects.
    pub reflections: Option<ReflectionImages<'g>>,
    /// The planar reflections' mirror images, in a host's frame that reflects its objects so.
    pub planar: Option<PlanarImages<'g>>,
    /// The shading pass's tiles sorted by whether they may mirror an object
    /// (passes/planar_tiles.rs): where the mirror is the sea's only reflection read.
    pub planar_tiles: Option<Buffer<'g>>,
    /// The frame's wave packets and their cells, where the scene has local waves.
    pub packets: Option<PacketBuffers<'g>>,
    /// Bound in their place without (the shaders' code for them is specialized away), and its
    /// views (dropped first).
    pub packet_stand_in_texels: PacketTexels<'g>,
    pub packet_stand_in: Buffer<'g>,
}

/// Rays per side of the aerial perspective's camera volume, and slices along each.
pub const AERIAL_SIZE: u32 = 32;

/// Bytes of the train counters: sea pixels, trains evaluated, trains with a weight, packet terms.
pub const TRAIN_COUNTS_BYTES: u64 = 16;

pub struct Readback<'g> {
    pub hdr: Buffer<'g>,
    pub ldr: Buffer<'g>,
}

impl<'g> Resources<'g> {
    /// Resources for `width` x `height` output images rendered with `ssaa` x `ssaa` samples per pixel.
    pub fn new(gpu: &'g Gpu, spec: &ResourceSpec) -> Result<Self> {
        let ResourceSpec {
            width,
            height,
            ssaa,
            sky_map,
            anisotropy,
            slots,
            readback,
            composite,
            atmosphere,
            shadow_map,
            eye_sky,
            aerial,
            in_place,
            reflections,
            planar,
            planar_tiles,
            packets,
        } = *spec;
        let limits = &gpu.device.properties.limits;
        let side = limits.max_image_dimension2_d;
        if width == 0 || height == 0 || width > side || height > side {
            return Err(Error::Argument(format!(
                "image size {width}x{height} is out of range [1, {side}] per side on {}",
                gpu.device.name
            )));
        }
        let (render_w, render_h) = (width as u64 * ssaa as u64, height as u64 * ssaa as u64);
        if ssaa == 0 || render_w > side as u64 || render_h > side as u64 {
            return Err(Error::Argument(format!(
                "supersampling {ssaa}x{ssaa} of {width}x{height} needs {render_w}x{render_h}; {} allows {side} per side",
                gpu.device.name
            )));
        }
        let render_extent = vk::Extent2D { width: render_w as u32, height: render_h as u32 };
        let pixels = width as u64 * height as u64;
        // The tone-mapped pixels read back are one storage buffer.
        if readback && 4 * pixels > limits.max_storage_buffer_range as u64 {
            return Err(Error::Argument(format!(
                "image size {width}x{height} needs a {} MiB storage buffer; {} allows {} MiB",
                (4 * pixels) >> 20,
                gpu.device.name,
                limits.max_storage_buffer_range >> 20
            )));
        }
        let extent = vk::Extent2D { width, height };
        use vk::BufferUsageFlags as B;
        use vk::ImageUsageFlags as I;
        let frame_uniforms =
            UniformRing::new(gpu, "frame uniforms", std::mem::size_of::<FrameUniforms>() as u64, slots)?;
        let waves = UniformRing::new(gpu, "wave trains", std::mem::size_of::<GpuWaves>() as u64, slots)?;
        // Without the sky term nothing samples the map: a 1x1 placeholder keeps its binding valid.
        let sky_size = if sky_map { SKY_MAP_SIZE } else { 1 };
        let sky_extent = vk::Extent2D { width: sky_size, height: sky_size };
        let sky_usage = I::STORAGE | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST;
        let sky_map = Image::new(gpu, "sky map", HDR_FORMAT, sky_extent, sky_size.ilog2() + 1, sky_usage)?;
        // Sampled: the composite reads the radiance with texelFetch (and, drawn in place, the
        // host's tone mapping).
        // Transfer destination: a frame with nothing to shade clears it (passes/black.rs).
        let hdr_usage = I::COLOR_ATTACHMENT | I::STORAGE | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST;
        let hdr = match &in_place {
            Some(host) => Image::borrowed_aliased(gpu, "hdr radiance", host, HDR_BITS_FORMAT)?,
            None => Image::aliased(gpu, "hdr radiance", HDR_FORMAT, HDR_BITS_FORMAT, render_extent, hdr_usage)?,
        };
        let depth_usage = I::DEPTH_STENCIL_ATTACHMENT | I::SAMPLED;
        let depth = Image::new(gpu, "depth", DEPTH_FORMAT, render_extent, 1, depth_usage)?;
        if let Some(size) = shadow_map.filter(|&size| size > side) {
            return Err(Error::Argument(format!(
                "render.shadow_map_size = {size} is above the largest image side of {}, {side}",
                gpu.device.name
            )));
        }
        let shadow_side = shadow_map.unwrap_or(1);
        let shadow_extent = vk::Extent2D { width: shadow_side, height: shadow_side };
        let name = if shadow_map.is_some() { "sun shadow map" } else { "sun shadow map (placeholder)" };
        // A placeholder is cleared once as an attachment (passes/placeholders.rs).
        let shadow_usage = depth_usage;
        let shadow_map_image = Image::new(gpu, name, DEPTH_FORMAT, shadow_extent, 1, shadow_usage)?;
        let resolved = if ssaa > 1 {
            Some(Image::new(gpu, "hdr resolved", HDR_FORMAT, extent, 1, I::STORAGE | I::SAMPLED | I::TRANSFER_SRC)?)
        } else {
            None
        };
        let readback = if readback {
            Some(Readback {
                hdr: Buffer::new(gpu, "hdr readback", pixels * 8, B::TRANSFER_DST, Location::Readback)?,
                ldr: Buffer::new(gpu, "ldr readback", pixels * 4, B::STORAGE_BUFFER, Location::Readback)?,
            })
        } else {
            None
        };
        let train_counts = Buffer::new(gpu, "train counts", TRAIN_COUNTS_BYTES, B::STORAGE_BUFFER, Location::Readback)?;
        let anisotropic = anisotropy > 1.0 && gpu.device.anisotropy;
        let max_anisotropy = if anisotropic { anisotropy.min(limits.max_sampler_anisotropy) } else { 1.0 };
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .anisotropy_enable(anisotropic)
            .max_anisotropy(max_anisotropy)
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid create info; anisotropy only when the feature was enabled.
        let sky_sampler = unsafe { gpu.raw().create_sampler(&sampler_info, None) }.during("vkCreateSampler")?;
        let aerial_extent = if atmosphere && aerial {
            vk::Extent2D { width: AERIAL_SIZE * AERIAL_SIZE, height: AERIAL_SIZE }
        } else {
            vk::Extent2D { width: 1, height: 1 }
        };
        let aerial_usage = I::STORAGE | I::SAMPLED | I::TRANSFER_DST;
        let aerial_inscatter = Image::new(gpu, "aerial inscatter", HDR_FORMAT, aerial_extent, 1, aerial_usage)?;
        let aerial_transmittance = Image::new(gpu, "aerial transmittance", HDR_FORMAT, aerial_extent, 1, aerial_usage)?;
        let eye_extent = if atmosphere && eye_sky {
            let (w, h) = crate::model::atmosphere::SKY_VIEW_SIZE;
            vk::Extent2D { width: w as u32, height: h as u32 }
        } else {
            vk::Extent2D { width: 1, height: 1 }
        };
        let eye_sky = Image::new(gpu, "eye sky view", HDR_FORMAT, eye_extent, 1, aerial_usage)?;
        let atmosphere = if atmosphere { Some(atmosphere_tables(gpu)?) } else { None };
        let filter = if gpu.device.depth_filter_linear { vk::Filter::LINEAR } else { vk::Filter::NEAREST };
        // Lit where the receiver is no farther from the sun than the nearest surface stored.
        let shadow_sampler =
            single_level_sampler(gpu, filter, Some(vk::CompareOp::LESS_OR_EQUAL), "sun shadow sampler")?;
        let depth_sampler = single_level_sampler(gpu, vk::Filter::NEAREST, None, "depth sampler")?;
        let mean_fresnel = mean_fresnel_buffer(gpu)?;
        let reflections = if reflections {
            let extent = vk::Extent2D { width, height };
            let levels = 32 - width.max(height).leading_zeros();
            let usage = I::STORAGE | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST;
            let colour = Image::new(gpu, "reflection colour", HDR_FORMAT, extent, levels, usage)?;
            let depth =
                Image::new(gpu, "reflection depth", REFLECTION_DEPTH_FORMAT, extent, levels, I::STORAGE | I::SAMPLED)?;
            let depth_levels = (0..levels).map(|level| depth.level_view(level)).collect::<Result<Vec<_>>>()?;
            let bounds = Buffer::new(gpu, "reflection bounds", 32, B::STORAGE_BUFFER, Location::Gpu)?;
            Some(ReflectionImages { colour, depth, depth_levels, bounds })
        } else {
            None
        };
        let planar = if planar {
            let extent = vk::Extent2D { width, height };
            let levels = 32 - width.max(height).leading_zeros();
            let usage = I::COLOR_ATTACHMENT | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST;
            let colour = Image::new(gpu, "planar colour", HDR_FORMAT, extent, levels, usage)?;
            let usage = I::DEPTH_STENCIL_ATTACHMENT | I::SAMPLED;
            let depth = Image::new(gpu, "planar depth", PLANAR_DEPTH_FORMAT, extent, 1, usage)?;
            // Cleared outside a host's cover (passes/planar.rs).
            let usage = I::STORAGE | I::SAMPLED | I::TRANSFER_DST;
            let inverse_depth = Image::new(gpu, "planar inverse depth", HDR_FORMAT, extent, levels, usage)?;
            let inverse_depth_levels =
                (0..levels).map(|level| inverse_depth.level_view(level)).collect::<Result<Vec<_>>>()?;
            Some(PlanarImages { colour, depth, inverse_depth, inverse_depth_levels })
        } else {
            None
        };
        // The sea-only rows' tiles sorted for the shading pass (passes/planar_tiles.rs), where the
        // mirror is the only reflection read: two indirect dispatches' arguments, then two lists
        // as long as the view has tiles.
        let planar_tiles = if planar_tiles && planar.is_some() && reflections.is_none() {
            let tiles = u64::from(shade_tiles(hdr.extent));
            let usage = B::STORAGE_BUFFER | B::INDIRECT_BUFFER;
            Some(Buffer::new(gpu, "planar tiles", PLANAR_TILE_LISTS_OFFSET + 2 * 4 * tiles, usage, Location::Gpu)?)
        } else {
            None
        };
        let exposure = Buffer::new(gpu, "measured exposure", 16, B::UNIFORM_BUFFER | B::STORAGE_BUFFER, Location::Gpu)?;
        let packets = packets.map(|max_alive| PacketBuffers::new(gpu, max_alive, slots)).transpose()?;
        let packet_stand_in = Buffer::new(gpu, "packets stand-in", 64, B::UNIFORM_TEXEL_BUFFER, Location::Gpu)?;
        let packet_stand_in_texels = PacketTexels::new(&packet_stand_in, &packet_stand_in, "packets stand-in")?;
        Ok(Resources {
            frame_uniforms,
            waves,
            sky_map,
            sky_sampler: Owned::new(&gpu.device, sky_sampler, "sky map sampler"),
            hdr,
            depth,
            shadow_map: shadow_map_image,
            shadows: shadow_map.is_some(),
            depth_read: shadow_map.is_some() || composite || reflections.is_some() || planar.is_some(),
            shadow_sampler,
            depth_sampler,
            resolved,
            readback,
            train_counts,
            atmosphere,
            aerial_inscatter,
            aerial_transmittance,
            eye_sky,
            mean_fresnel,
            exposure,
            reflections,
            planar,
            planar_tiles,
            packets,
            packet_stand_in_texels,
            packet_stand_in,
        })
    }

    /// The 1x1 stand-ins that keep bindings valid where their passes are left out (their code is
    /// specialized away, but a sampled image must still hold defined texels): cleared once.
    pub fn placeholders(&self) -> Vec<&Image<'g>> {
        let one = |image: &Image| image.extent.width == 1 && image.extent.height == 1;
        let mut images: Vec<&Image<'g>> =
            [&self.sky_map, &self.aerial_inscatter, &self.aerial_transmittance, &self.eye_sky]
                .into_iter()
                .filter(|i| one(i))
                .collect();
        if !self.shadows {
            images.push(&self.shadow_map);
        }
        images
    }

    /// The HDR radiance at the output size: the resolved image with supersampling, else `hdr`.
    pub fn output(&self) -> &Image<'g> {
        self.resolved.as_ref().unwrap_or(&self.hdr)
    }
}

/// The storage block MeanFresnel of glsl/slopes.glsl: a vec4 (eta, unused), then per cell of the
/// table (row-major by sigma) the four corners' values, (i, j), (i + 1, j), (i, j + 1),
/// (i + 1, j + 1): a bilinear lookup is one vec4 read.
pub fn mean_fresnel_buffer(gpu: &Gpu) -> Result<Buffer<'_>> {
    let table = MeanFresnelTable::sea_water();
    let (n, m) = (MeanFresnelTable::COS_SIZE, MeanFresnelTable::SIGMA_SIZE);
    let at = |i: usize, j: usize| table.values[j * n + i];
    let mut words = vec![[table.eta as f32, 0.0, 0.0, 0.0]];
    for j in 0..m - 1 {
        for i in 0..n - 1 {
            words.push([at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)]);
        }
    }
    let bytes = 16 * words.len() as u64;
    let buffer = Buffer::new(gpu, "mean fresnel table", bytes, vk::BufferUsageFlags::STORAGE_BUFFER, Location::Upload)?;
    buffer.write(&words)?;
    Ok(buffer)
}

fn atmosphere_tables(gpu: &Gpu) -> Result<AtmosphereTables<'_>> {
    use crate::model::atmosphere::{MULTIPLE_SCATTERING_SIZE, SEA_IRRADIANCE_SIZE, SKY_VIEW_SIZE, TRANSMITTANCE_SIZE};
    let usage = vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED;
    let (tw, th) = (TRANSMITTANCE_SIZE.0 as u32, TRANSMITTANCE_SIZE.1 as u32);
    let transmittance =
        Image::new(gpu, "atmosphere transmittance", HDR_FORMAT, vk::Extent2D { width: tw, height: th }, 1, usage)?;
    let n = MULTIPLE_SCATTERING_SIZE as u32;
    let multiple_scattering =
        Image::new(gpu, "atmosphere multiple scattering", HDR_FORMAT, vk::Extent2D { width: n, height: n }, 1, usage)?;
    let view_extent = vk::Extent2D { width: SKY_VIEW_SIZE.0 as u32, height: SKY_VIEW_SIZE.1 as u32 };
    let sky_view = Image::new(gpu, "atmosphere sky view", HDR_FORMAT, view_extent, 1, usage)?;
    let irradiance_extent = vk::Extent2D { width: SEA_IRRADIANCE_SIZE as u32, height: 2 };
    let sea_irradiance = Image::new(gpu, "atmosphere sea irradiance", HDR_FORMAT, irradiance_extent, 1, usage)?;
    let sampler = single_level_sampler(gpu, vk::Filter::LINEAR, None, "atmosphere tables sampler")?;
    Ok(AtmosphereTables { transmittance, multiple_scattering, sky_view, sea_irradiance, sampler })
}

/// A sampler of single-level images, clamped to the edge, filtered by `filter`, comparing with
/// `compare` (a depth comparison sampler) when given.
fn single_level_sampler<'g>(
    gpu: &'g Gpu,
    filter: vk::Filter,
    compare: Option<vk::CompareOp>,
    name: &str,
) -> Result<Owned<'g, vk::Sampler>> {
    let info = vk::SamplerCreateInfo::default()
        .mag_filter(filter)
        .min_filter(filter)
        .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
        .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
        .compare_enable(compare.is_some())
        .compare_op(compare.unwrap_or(vk::CompareOp::NEVER))
        // The images have one level; no clamp here (a clamped LOD costs on some GPUs).
        .max_lod(vk::LOD_CLAMP_NONE);
    // SAFETY: valid create info on a live device; a linear filter is asked for depth only where
    // the device filters its depth format linearly.
    let sampler = unsafe { gpu.raw().create_sampler(&info, None) }.during("vkCreateSampler")?;
    Ok(Owned::new(&gpu.device, sampler, name))
}
