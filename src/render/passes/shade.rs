//! Shading, once per pixel (compute): the sea with the paper's BRDF at the rest position the
//! visibility pass (ocean.rs) left in the pixel, the sky where it left none; the radiance
//! replaces those bits in the HDR image.

use super::ocean::{sky_shaded_rows, ShaderConfig, TrainReads};
use super::packets::{
    declare_packet_reads, write_packet_bindings, PACKETS_BINDING_READ, PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE,
};
use super::{write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{
    Resources, EYE_SKY_BINDING, FRAME_BINDING, MEAN_FRESNEL_BINDING, PLANAR_TILE_ARGS_STRIDE, SEA_LIGHT_BINDING,
    WAVES_BINDING,
};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings};
use ash::vk;

/// The train counters' binding (TrainCounts in glsl/shade.glsl).
const TRAIN_COUNTS_BINDING: u32 = 4;
/// The aerial perspective's atlases (glsl/shade.glsl; placeholders without the physical sky).
const AERIAL_INSCATTER_BINDING: u32 = 5;
const AERIAL_TRANSMITTANCE_BINDING: u32 = 6;
/// The sun's shadow map and the camera's depth (glsl/shade.glsl; placeholders without shadows).
const SUN_SHADOW_BINDING: u32 = 8;
const SCENE_DEPTH_BINDING: u32 = 9;
/// The local reflections' sources (glsl/shade.glsl local_reflection; the eye's sky table stands
/// in without them, its code specialized away).
const REFLECTION_COLOUR_BINDING: u32 = 14;
const REFLECTION_DEPTH_BINDING: u32 = 15;
const REFLECTION_BOUNDS_BINDING: u32 = 16;
/// The planar reflections' mirror images (glsl/shade.glsl planar_reflection; the eye's sky table
/// stands in without them), and a push constant saying whether the host drew them this frame.
const PLANAR_COLOUR_BINDING: u32 = 17;
const PLANAR_INVERSE_DEPTH_BINDING: u32 = 18;
/// The sea-only rows' tiles sorted by whether they may mirror an object (passes/planar_tiles.rs;
/// any storage buffer stands in where there are none, never read).
const PLANAR_TILES_BINDING: u32 = 19;
/// Whether the host drew the mirror images this frame, and where a tiled dispatch's list starts.
const PUSH_BYTES: u32 = 8;

/// The shading pass's workgroups are SHADE_GROUP x SHADE_GROUP pixels (glsl/shade.comp's
/// local size).
pub const SHADE_GROUP: u32 = 8;

/// Trains per read of the blocked loop (TRAIN_BLOCK in glsl/train_blocks.glsl), which needs compute
/// subgroups at least this wide with these operations.
const TRAIN_BLOCK: u32 = 8;
const BLOCK_OPERATIONS: vk::SubgroupFeatureFlags = vk::SubgroupFeatureFlags::from_raw(
    vk::SubgroupFeatureFlags::BASIC.as_raw()
        | vk::SubgroupFeatureFlags::VOTE.as_raw()
        | vk::SubgroupFeatureFlags::ARITHMETIC.as_raw()
        | vk::SubgroupFeatureFlags::BALLOT.as_raw(),
);

/// The wave-table reads `requested` comes to on `device`: blocks only where its subgroups allow.
pub fn train_reads_on(device: &Device, requested: TrainReads) -> TrainReads {
    match requested {
        TrainReads::Blocks if device.subgroups.compute_offers(TRAIN_BLOCK, BLOCK_OPERATIONS) => TrainReads::Blocks,
        _ => TrainReads::PerTrain,
    }
}

pub struct ShadePass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// The same shader without the sky, for the rows that see only sea (frame::sea_only_rows).
    sea_pipeline: Owned<'g, vk::Pipeline>,
    /// The sea-only rows' pipelines for the planar tiles' two lists, where there are lists.
    tiled: Option<TiledPipelines<'g>>,
    /// Whether the visibility pass shades the rows only sky covers (a picture with a background).
    sky_done_above: bool,
    /// Whether the shader counts trains into `Resources::train_counts` (zeroed by the host first).
    counts: bool,
}

/// The sea-only rows' pipelines for the planar tiles' lists (passes/planar_tiles.rs): list 0
/// (the tiles that may mirror an object) with the mirror's code, list 1 without it.
struct TiledPipelines<'g> {
    reading: Owned<'g, vk::Pipeline>,
    plain: Owned<'g, vk::Pipeline>,
    /// Tiles each list can hold: the view's.
    capacity: u32,
}

/// The shading pass's workgroups (tiles) over an image of `extent`: each planar tile list's length.
pub fn shade_tiles(extent: vk::Extent2D) -> u32 {
    extent.width.div_ceil(SHADE_GROUP) * extent.height.div_ceil(SHADE_GROUP)
}

/// The workgroup rows the shading pass dispatches with its sea-only pipeline: from frame::
/// sea_only_rows (rounded up to whole workgroups) to the bottom, after the rows the visibility
/// pass shaded (`sky_done_above`).
pub fn sea_group_rows(frame: &Frame, extent: vk::Extent2D, sky_done_above: bool) -> std::ops::Range<u32> {
    let (first, rows) = shaded_group_rows(frame, extent, sky_done_above);
    frame.sea_rows.div_ceil(SHADE_GROUP).clamp(first, rows)..rows
}

/// The first workgroup row the shading pass dispatches, and the count of workgroup rows.
fn shaded_group_rows(frame: &Frame, extent: vk::Extent2D, sky_done_above: bool) -> (u32, u32) {
    let rows = extent.height.div_ceil(SHADE_GROUP);
    let skipped = if sky_done_above { sky_shaded_rows(frame.sky_rows) / SHADE_GROUP } else { 0 };
    (skipped.min(rows), rows)
}

impl<'g> ShadePass<'g> {
    pub fn new(device: &'g Device, r: &Resources, config: ShaderConfig) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::with_push_constants(
            device,
            "shade",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (WAVES_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (2, D::COMBINED_IMAGE_SAMPLER, compute),
                (3, D::STORAGE_IMAGE, compute),
                (TRAIN_COUNTS_BINDING, D::STORAGE_BUFFER, compute),
                (AERIAL_INSCATTER_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (AERIAL_TRANSMITTANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (SUN_SHADOW_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (SCENE_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, compute),
                (EYE_SKY_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (SEA_LIGHT_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (REFLECTION_COLOUR_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (REFLECTION_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (REFLECTION_BOUNDS_BINDING, D::STORAGE_BUFFER, compute),
                (PLANAR_COLOUR_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (PLANAR_INVERSE_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (PLANAR_TILES_BINDING, D::STORAGE_BUFFER, compute),
                (PACKETS_BINDING_READ, PACKET_READ_TYPE, compute),
                (PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE, compute),
            ],
            PUSH_BYTES,
        )?;
        write_packet_bindings(&bindings, r);
        bindings.write_buffer(MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, r.mean_fresnel.raw);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        for (binding, image) in [
            (AERIAL_INSCATTER_BINDING, &r.aerial_inscatter),
            (AERIAL_TRANSMITTANCE_BINDING, &r.aerial_transmittance),
            (EYE_SKY_BINDING, &r.eye_sky),
        ] {
            bindings.write_image(binding, D::COMBINED_IMAGE_SAMPLER, image.view, read, r.sky_sampler.raw);
        }
        // Each sea point's light under its own sun: the atmosphere's sea-level light table (a
        // placeholder without the physical sky, whose code is specialized away).
        let (table, sampler) = match &r.atmosphere {
            Some(tables) => (tables.sea_irradiance.view, tables.sampler.raw),
            None => (r.aerial_inscatter.view, r.sky_sampler.raw),
        };
        bindings.write_image(SEA_LIGHT_BINDING, D::COMBINED_IMAGE_SAMPLER, table, read, sampler);
        bindings.write_image(
            SUN_SHADOW_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            r.shadow_map.view,
            read,
            r.shadow_sampler.raw,
        );
        // Trilinear over the objects' radiance (the sky map's sampler: clamped, every level);
        // texelFetch in their depth.
        let (colour, depth_pyramid) = match &r.reflections {
            Some(images) => (images.colour.view, images.depth.view),
            None => (r.eye_sky.view, r.eye_sky.view),
        };
        bindings.write_image(REFLECTION_COLOUR_BINDING, D::COMBINED_IMAGE_SAMPLER, colour, read, r.sky_sampler.raw);
        bindings.write_image(
            REFLECTION_DEPTH_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            depth_pyramid,
            read,
            r.depth_sampler.raw,
        );
        // Without reflections any storage buffer stands in (never read).
        let bounds = r.reflections.as_ref().map_or(r.mean_fresnel.raw, |images| images.bounds.raw);
        bindings.write_buffer(REFLECTION_BOUNDS_BINDING, D::STORAGE_BUFFER, bounds);
        // Trilinear over the mirrored objects' radiance; texelFetch in their inverse depth.
        let (colour, inverse_depth) = match &r.planar {
            Some(images) => (images.colour.view, images.inverse_depth.view),
            None => (r.eye_sky.view, r.eye_sky.view),
        };
        bindings.write_image(PLANAR_COLOUR_BINDING, D::COMBINED_IMAGE_SAMPLER, colour, read, r.sky_sampler.raw);
        let sampler = r.depth_sampler.raw;
        bindings.write_image(PLANAR_INVERSE_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, inverse_depth, read, sampler);
        let tiles = r.planar_tiles.as_ref().map_or(r.mean_fresnel.raw, |tiles| tiles.raw);
        bindings.write_buffer(PLANAR_TILES_BINDING, D::STORAGE_BUFFER, tiles);
        let depth = if r.depth_read { &r.depth } else { &r.shadow_map };
        bindings.write_image(SCENE_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, depth.view, read, r.depth_sampler.raw);
        bindings.write_buffer(TRAIN_COUNTS_BINDING, D::STORAGE_BUFFER, r.train_counts.raw);
        write_frame_uniforms(&bindings, r, true);
        bindings.write_image(
            2,
            D::COMBINED_IMAGE_SAMPLER,
            r.sky_map.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            r.sky_sampler.raw,
        );
        bindings.write_image(3, D::STORAGE_IMAGE, r.hdr.alias_view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        let code = match train_reads_on(device, config.train_reads) {
            TrainReads::Blocks => shaders::SHADE_BLOCKED_COMP,
            TrainReads::PerTrain => shaders::SHADE_COMP,
        };
        let layout = bindings.layout();
        let spec = config.shade_specialization(false);
        let pipeline = specialized_compute_pipeline(device, layout, code, Some(&spec), "shade")?;
        let spec = config.shade_specialization(true);
        let sea_pipeline = specialized_compute_pipeline(device, layout, code, Some(&spec), "shade (sea only)")?;
        let tiled = match &r.planar_tiles {
            Some(_) => {
                let capacity = shade_tiles(r.hdr.extent);
                let spec = config.shade_tiled_specialization(true);
                let reading =
                    specialized_compute_pipeline(device, layout, code, Some(&spec), "shade (sea only, mirror)")?;
                let spec = config.shade_tiled_specialization(false);
                let plain =
                    specialized_compute_pipeline(device, layout, code, Some(&spec), "shade (sea only, no mirror)")?;
                Some(TiledPipelines { reading, plain, capacity })
            }
            None => None,
        };
        Ok(ShadePass {
            bindings,
            pipeline,
            sea_pipeline,
            tiled,
            sky_done_above: config.background,
            counts: config.count_trains,
        })
    }
}

impl Pass for ShadePass<'_> {
    fn name(&self) -> &'static str {
        "shade"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(&r.sky_map, 0, r.sky_map.mip_levels, Access::ComputeSampled, false);
        t.image(&r.hdr, 0, 1, Access::ComputeStorageReadWrite, false);
        t.image(&r.aerial_inscatter, 0, 1, Access::ComputeSampled, false);
        t.image(&r.aerial_transmittance, 0, 1, Access::ComputeSampled, false);
        t.image(&r.eye_sky, 0, 1, Access::ComputeSampled, false);
        if let Some(tables) = &r.atmosphere {
            t.image(&tables.sea_irradiance, 0, 1, Access::ComputeSampled, false);
        }
        t.image(&r.shadow_map, 0, 1, Access::ComputeSampled, false);
        declare_packet_reads(r, t, Access::ComputeSampled);
        if r.depth_read {
            t.image(&r.depth, 0, 1, Access::ComputeSampled, false);
        }
        // Read only in a frame the host drew them in, but bound in every one: a frame without
        // them still holds them in the layout the set names.
        if let Some(images) = &r.planar {
            t.image(&images.colour, 0, images.colour.mip_levels, Access::ComputeSampled, false);
            t.image(&images.inverse_depth, 0, images.inverse_depth.mip_levels, Access::ComputeSampled, false);
        }
        if let Some(images) = &r.reflections {
            t.image(&images.colour, 0, images.colour.mip_levels, Access::ComputeSampled, false);
            t.image(&images.depth, 0, images.depth.mip_levels, Access::ComputeSampled, false);
            t.buffer(&images.bounds, Access::ComputeStorageRead);
        }
        if self.counts {
            t.buffer(&r.train_counts, Access::ComputeStorageReadWrite);
        }
        if let Some(tiles) = &r.planar_tiles {
            t.buffer(tiles, Access::IndirectRead);
            t.buffer(tiles, Access::ComputeStorageRead);
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        // The rows only sky covers were shaded by the visibility pass: a CPU driver runs both
        // sides of a branch for lanes that disagree, and the masked-off side even when no lane
        // takes it, so sky pixels in this shader would pay for all of the sea's code.
        let (first, rows) = shaded_group_rows(rec.frame, r.hdr.extent, self.sky_done_above);
        if first < rows {
            self.dispatch(rec, r, first);
        }
        if self.counts {
            // The host reads the counters after the frame's fence.
            rec.tracker.buffer(&r.train_counts, Access::HostRead);
            rec.tracker.flush(&rec.device.raw, rec.cmd);
        }
    }
}

impl ShadePass<'_> {
    /// Dispatches workgroup rows `first..` to the bottom, split where only sea is seen; those
    /// rows by the planar tiles' lists where there are lists.
    fn dispatch(&self, rec: &Recorder, r: &Resources, first: u32) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let columns = r.hdr.extent.width.div_ceil(SHADE_GROUP);
        // The same reason splits the rest: the rows that see only sea (whole workgroup rows from
        // frame::sea_only_rows down) get the shader without the sky's code.
        let sea = sea_group_rows(rec.frame, r.hdr.extent, self.sky_done_above);
        self.bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &rec.frame.uniform_offsets);
        // PUSH_BYTES: two words.
        let push =
            |tile_list: u32| self.bindings.push_compute_words(cmd, &[u32::from(rec.frame.planar_drawn), tile_list]);
        push(0);
        let mut row_ranges = vec![(&self.pipeline, first..sea.start)];
        match (&self.tiled, &r.planar_tiles) {
            (Some(tiled), Some(tiles)) if !sea.is_empty() => {
                for (list, pipeline) in [(0u32, &tiled.reading), (1, &tiled.plain)] {
                    push(list * tiled.capacity);
                    // SAFETY: outside a rendering scope; the set (bound above) was made for this
                    // layout (every pipeline shares it); the buffer was declared for indirect
                    // reads, and planar_tiles.comp wrote (x, 1, 1) there this frame.
                    unsafe {
                        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                        device.cmd_dispatch_indirect(cmd, tiles.raw, u64::from(list) * PLANAR_TILE_ARGS_STRIDE);
                    }
                }
                push(0);
            }
            _ => row_ranges.push((&self.sea_pipeline, sea)),
        }
        for (pipeline, rows) in row_ranges {
            if rows.is_empty() {
                continue;
            }
            // SAFETY: outside a rendering scope; the set (bound above) was made for this layout
            // (every pipeline shares it), the pass's images were declared, and the pipelines
            // allow a base group.
            unsafe {
                device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
                device.cmd_dispatch_base(cmd, 0, rows.start, 0, columns, rows.len() as u32, 1);
            }
        }
    }
}
