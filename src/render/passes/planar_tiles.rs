//! Planar tiles: the shading pass's tiles in the rows that see only sea, sorted by whether any of
//! their pixels may mirror an object (glsl/planar_tiles.comp: one invocation per tile, bounding
//! where its pixels' mirrored points can lie from the camera and the waves' height), into two
//! lists that the shading pass dispatches indirectly, each with its own pipeline: the one that
//! reads the mirror images, and the one without that code. A CPU driver runs all of a shader's branches for every lane,
//! masked, so the mirror's code cost every pixel of the boat's view 13% of the shading though a
//! tenth of them read it (docs/bench/objects.md). Only where the mirror is the sea's one
//! reflection read (the screen's trace, where asked, runs everywhere).

use super::shade::{sea_group_rows, SHADE_GROUP};
use super::{write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

const PLANAR_INVERSE_DEPTH_BINDING: u32 = 3;
const TILES_BINDING: u32 = 4;
/// Whether the host drew the mirror images this frame, whether the dispatch empties the lists
/// (one invocation) instead of filling them, and the first tile row it sorts.
const PUSH_BYTES: u32 = 12;

pub struct PlanarTilesPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// Whether the rows only sky covers were shaded by the visibility pass (ShadePass's).
    sky_done_above: bool,
}

impl<'g> PlanarTilesPass<'g> {
    pub const NAME: &'static str = "planar tiles";

    /// None where the frame has no tile lists (Resources::planar_tiles).
    pub fn new(device: &'g Device, r: &Resources, background: bool) -> Result<Option<Self>> {
        let (Some(tiles), Some(planar)) = (&r.planar_tiles, &r.planar) else { return Ok(None) };
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::with_push_constants(
            device,
            Self::NAME,
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (PLANAR_INVERSE_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (TILES_BINDING, D::STORAGE_BUFFER, compute),
            ],
            PUSH_BYTES,
        )?;
        write_frame_uniforms(&bindings, r, false);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // texelFetch only: the sampler's filter is never used.
        let inverse_depth = planar.inverse_depth.view;
        bindings.write_image(
            PLANAR_INVERSE_DEPTH_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            inverse_depth,
            read,
            r.depth_sampler.raw,
        );
        bindings.write_buffer(TILES_BINDING, D::STORAGE_BUFFER, tiles.raw);
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::PLANAR_TILES_COMP, Self::NAME)?;
        Ok(Some(PlanarTilesPass { bindings, pipeline, sky_done_above: background }))
    }

    fn push(&self, rec: &Recorder, reset: bool, first_row: u32) {
        // PUSH_BYTES: three words.
        self.bindings.push_compute_words(rec.cmd, &[u32::from(rec.frame.planar_drawn), u32::from(reset), first_row]);
    }
}

impl Pass for PlanarTilesPass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        let (Some(tiles), Some(planar)) = (&r.planar_tiles, &r.planar) else { return };
        t.image(&planar.inverse_depth, 0, planar.inverse_depth.mip_levels, Access::ComputeSampled, false);
        t.buffer(tiles, Access::ComputeStorageWrite);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let Some(tiles) = &r.planar_tiles else { return };
        let extent = r.hdr.extent;
        let rows = sea_group_rows(rec.frame, extent, self.sky_done_above);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        // SAFETY: outside a rendering scope; the set was made for this pipeline's layout and the
        // pass's resources were declared.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.raw) };
        self.bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &rec.frame.uniform_offsets);
        self.push(rec, true, 0);
        // SAFETY: as above.
        unsafe { device.cmd_dispatch(cmd, 1, 1, 1) };
        if rows.is_empty() {
            return;
        }
        // The lists' counters, emptied above, are counted into by every tile.
        rec.tracker.buffer(tiles, Access::ComputeStorageReadWrite);
        rec.tracker.flush(device, cmd);
        self.push(rec, false, rows.start);
        // One invocation per tile, 8 x 8 tiles per workgroup.
        let columns = extent.width.div_ceil(SHADE_GROUP);
        let groups = (columns.div_ceil(8), (rows.len() as u32).div_ceil(8));
        // SAFETY: as above.
        unsafe { device.cmd_dispatch(cmd, groups.0, groups.1, 1) };
    }
}
