//! Packet bins: the frame's wave packets copied from its slot's upload window (a transfer) and
//! binned into the cells of their grid, an invocation a cell testing them against its tile's
//! list (glsl/packet_bins.comp's three steps, each a dispatch behind a barrier from its
//! declared accesses), so that the grid's vertices and the pixels read only the packets that
//! reach them (glsl/packets.glsl). First in the frame: the sun's view of the grid, which a host
//! may record ahead of the frame, displaces the packets too.

use super::{Frame, Pass, Recorder};
use crate::error::Result;
use crate::model::packets::grid::{MAX_CELLS, MAX_TILES, TILE_CELLS};
use crate::render::packets::GpuPacket;
use crate::render::resources::{Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

const CELLS_BINDING: u32 = 3;
const COUNTERS_BINDING: u32 = 4;
const TILES_BINDING: u32 = 5;
const PACKET_TEXELS_BINDING: u32 = 6;
/// The step, the lists' room (entries) and the slot's first word in the tiles' upload window.
const PUSH_BYTES: u32 = 12;
/// Invocations per workgroup (glsl/packet_bins.comp's local size): the scan's width, and the
/// cells of BIN_GROUP / TILE_CELLS^2 tiles in the other steps.
const BIN_GROUP: u32 = 256;
const TILES_PER_GROUP: u32 = BIN_GROUP / (TILE_CELLS * TILE_CELLS);

pub struct PacketBinsPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> PacketBinsPass<'g> {
    pub const NAME: &'static str = "packet bins";

    /// None where the frame has no packets (Resources::packets).
    pub fn new(device: &'g Device, r: &Resources) -> Result<Option<Self>> {
        let Some(p) = &r.packets else { return Ok(None) };
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let bindings = Bindings::with_push_constants(
            device,
            Self::NAME,
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (CELLS_BINDING, D::STORAGE_BUFFER, compute),
                (COUNTERS_BINDING, D::STORAGE_BUFFER, compute),
                (TILES_BINDING, D::STORAGE_BUFFER, compute),
                (PACKET_TEXELS_BINDING, PACKET_READ_TYPE, compute),
            ],
            PUSH_BYTES,
        )?;
        super::write_frame_uniforms(&bindings, r, false);
        bindings.write_buffer(CELLS_BINDING, D::STORAGE_BUFFER, p.cells.raw);
        bindings.write_buffer(COUNTERS_BINDING, D::STORAGE_BUFFER, p.counters.raw);
        bindings.write_buffer(TILES_BINDING, D::STORAGE_BUFFER, p.tile_upload.raw);
        bindings.write_texel_buffer(PACKET_TEXELS_BINDING, PACKET_READ_TYPE, p.texels.packets.raw);
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::PACKET_BINS_COMP, Self::NAME)?;
        Ok(Some(PacketBinsPass { bindings, pipeline }))
    }
}

impl Pass for PacketBinsPass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        let Some(p) = &r.packets else { return };
        t.buffer(&p.upload, Access::TransferRead);
        t.buffer(&p.packets, Access::TransferWrite);
        t.buffer(&p.tile_upload, Access::ComputeStorageRead);
        t.buffer(&p.counters, Access::ComputeStorageWrite);
        t.buffer(&p.cells, Access::ComputeStorageWrite);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let Some(p) = &r.packets else { return };
        let (packets, cells, tiles) = (rec.frame.packets, rec.frame.packet_cells, rec.frame.packet_tiles);
        if packets == 0 {
            return;
        }
        debug_assert!(cells <= MAX_CELLS && tiles <= MAX_TILES);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let packet_bytes = std::mem::size_of::<GpuPacket>() as u64;
        let copy = vk::BufferCopy {
            src_offset: packet_bytes * u64::from(p.first(rec.frame.slot)),
            dst_offset: 0,
            size: packet_bytes * u64::from(packets),
        };
        // SAFETY: outside a rendering scope; both buffers are in transfer states (declared); the
        // slot's window holds `packets` packets (PacketBuffers::write) and `packets` as many.
        unsafe { device.cmd_copy_buffer(cmd, p.upload.raw, p.packets.raw, &[copy]) };
        rec.tracker.buffer(&p.packets, Access::ComputeSampled);
        rec.tracker.flush(device, cmd);
        // SAFETY: as above; the set was made for this pipeline's layout and the pass's buffers
        // were declared.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.raw) };
        self.bindings.bind(cmd, vk::PipelineBindPoint::COMPUTE, &rec.frame.uniform_offsets);
        let tile_first = p.tile_first(rec.frame.slot);
        // Steps 0 to 2 (glsl/packet_bins.comp): count, scan, write.
        let tile_groups = tiles.div_ceil(TILES_PER_GROUP);
        for (step, group_count) in [tile_groups, 1, tile_groups].into_iter().enumerate() {
            if step > 0 {
                // The scan reads the counts, the writing the starts.
                rec.tracker.buffer(&p.counters, Access::ComputeStorageReadWrite);
                rec.tracker.buffer(&p.cells, Access::ComputeStorageReadWrite);
                rec.tracker.flush(device, cmd);
            }
            self.bindings.push_compute_words(cmd, &[step as u32, p.max_entries as u32, tile_first]);
            // SAFETY: as above.
            unsafe { device.cmd_dispatch(cmd, group_count, 1, 1) };
        }
    }
}

/// The bindings of the packets' texel buffers in the passes that read them (glsl/packets.glsl),
/// and their descriptor type.
pub const PACKETS_BINDING_READ: u32 = 20;
pub const PACKET_CELLS_BINDING_READ: u32 = 21;
pub const PACKET_READ_TYPE: vk::DescriptorType = vk::DescriptorType::UNIFORM_TEXEL_BUFFER;

/// Points a pass's packet bindings at the frame's packets, or at the stand-in where it has none
/// (the shaders' code for them is specialized away, and the bindings must still be valid).
pub fn write_packet_bindings(bindings: &Bindings, r: &Resources) {
    let texels = match &r.packets {
        Some(p) => &p.texels,
        None => &r.packet_stand_in_texels,
    };
    bindings.write_texel_buffer(PACKETS_BINDING_READ, PACKET_READ_TYPE, texels.packets.raw);
    bindings.write_texel_buffer(PACKET_CELLS_BINDING_READ, PACKET_READ_TYPE, texels.cells.raw);
}

/// Declares a pass's reads of the frame's packets (at `access`), where it has any.
pub fn declare_packet_reads(r: &Resources, t: &mut Tracker, access: Access) {
    if let Some(p) = &r.packets {
        t.buffer(&p.packets, access);
        t.buffer(&p.cells, access);
    }
}
