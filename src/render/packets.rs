//! A frame's wave packets for the GPU: the scene's packet field at the frame's time, moved to the
//! eye's frame, binned into cells (model::packets::grid), and packed as glsl/packet_data.glsl
//! has them; and the buffers they live in (passes/packets.rs bins them on the GPU).

use crate::error::{Error, Result};
use crate::model::packets::grid::{
    self, CellMap, Footprint, PacketGrid, MAX_CELLS, MAX_TILES, PERSPECTIVE_CELLS_PER_SIDE,
};
use crate::model::packets::sources::Sources;
use crate::model::packets::{Packet, PacketField};
use crate::vk::buffer::Buffer;
use crate::vk::gpu::Gpu;
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use ash::vk;
use glam::DVec2;
use std::f64::consts::TAU;

/// One packet as glsl/packet_data.glsl's `Packet` (std430, 80 bytes: five texels).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuPacket {
    /// The envelope's centre (m, camera-relative) and the wave vector (turns per m).
    pub centre_k: [f32; 4],
    /// The envelope's two axes, each over its sigma (1/m).
    pub envelope: [f32; 4],
    /// Amplitude at the centre (m), the phase there (turns, [0, 1)), the wavelength (m, 1 over
    /// the wave vector's length in turns: the direction is the wave vector times it) and the
    /// slope amplitude the BRDF's variance takes, k a times the square root of the in-phase rows'
    /// envelope sums (Packet::in_phase); the last two negative where the row along the first
    /// axis, and the second's, is in phase.
    pub wave: [f32; 4],
    /// Its rectangle in the cells' plane, a quad (grid::Footprint, to the bit): the binning's
    /// alone.
    pub footprint: [f32; 8],
}

/// The lists' room per packet alive: a packet overlaps this many cells on average before the
/// grid coarsens (grid::PacketGrid::new).
pub const ENTRIES_PER_PACKET: usize = 32;

impl GpuPacket {
    /// Packet `p` and its quad in the cells' plane, `footprint`.
    fn new(p: &Packet, footprint: &Footprint) -> GpuPacket {
        let k = p.direction * (p.k / TAU);
        let (along, across) = (p.axis / p.sigma[0], p.axis.perp() / p.sigma[1]);
        let phase = (p.phase / TAU).rem_euclid(1.0);
        let signed = |v: f64, in_phase: Option<f64>| if in_phase.is_some() { -v } else { v };
        let row_sums: f64 = p.in_phase.iter().flatten().product();
        let slope = p.k * p.amplitude * row_sums.sqrt();
        let (wavelength, slope) = (signed(p.wavelength(), p.in_phase[0]), signed(slope, p.in_phase[1]));
        let [a, b, c, d] = footprint.quad;
        GpuPacket {
            centre_k: [p.centre.x, p.centre.y, k.x, k.y].map(|v| v as f32),
            envelope: [along.x, along.y, across.x, across.y].map(|v| v as f32),
            wave: [p.amplitude, phase, wavelength, slope].map(|v| v as f32),
            footprint: [a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]],
        }
    }
}

/// One frame's packets: the field in the eye's frame, its cells and the packed packets.
#[derive(Clone, Debug, Default)]
pub struct FramePackets {
    pub field: PacketField,
    pub grid: PacketGrid,
    pub gpu: Vec<GpuPacket>,
}

impl FramePackets {
    /// The packets of `sources` at time `t`, the eye above world position `eye` (the scene's
    /// camera x_m, y_m), binned within `max_entries` list entries in perspective cells over the
    /// view `view` gives for a bound on the packets' crests (render::packet_view; None: the
    /// view holds no sea, and nothing is binned).
    pub fn new(
        sources: &Sources,
        t: f64,
        eye: DVec2,
        max_entries: usize,
        view: impl Fn(f64) -> Option<CellMap>,
    ) -> FramePackets {
        let field = sources.field(t).relative_to(eye);
        let binned = |crest_m: f64| {
            view(crest_m).map(|map| PacketGrid::new(&field.packets, max_entries, map, PERSPECTIVE_CELLS_PER_SIDE))
        };
        // Coarse square cells sum more packets than fine ones: their crest bounds the view's. The
        // view's cells, finer, bound it closer over the view they cover, which holds the view
        // that closer bound gives: its cells are made again for it once.
        let coarse = PacketGrid::new(&field.packets, usize::MAX, CellMap::Plane, COARSE_CELLS_PER_SIDE).crest_m;
        let grid =
            binned(coarse).and_then(|first| if first.crest_m < coarse { binned(first.crest_m) } else { Some(first) });
        let grid = grid.unwrap_or_else(|| PacketGrid::unbinned(field.packets.len()));
        Self::packed(field, grid)
    }

    /// The packets of `sources` at time `t` around `eye`, every one binned in square cells, at
    /// most `per_side` a side (the ground truth's, whose rays go anywhere).
    pub fn everywhere(sources: &Sources, t: f64, eye: DVec2, max_entries: usize, per_side: u32) -> FramePackets {
        let field = sources.field(t).relative_to(eye);
        let grid = PacketGrid::new(&field.packets, max_entries, CellMap::Plane, per_side);
        Self::packed(field, grid)
    }

    fn packed(field: PacketField, grid: PacketGrid) -> FramePackets {
        let gpu = field.packets.iter().zip(&grid.footprints).map(|(p, f)| GpuPacket::new(p, f)).collect();
        FramePackets { field, grid, gpu }
    }

    /// FrameUniforms::packet_grid, packet_map and packet_dims.
    pub fn uniforms(&self) -> ([f32; 4], [f32; 4], [u32; 4]) {
        let g = &self.grid;
        (g.uniform(), g.map.uniform(), [g.cols, g.rows, self.gpu.len() as u32, g.tiles()])
    }
}

/// Cells a side of the square grid whose crest bounds the packets' before the view's cells are
/// made (its cost is its entries', a few a packet).
const COARSE_CELLS_PER_SIDE: u32 = 32;

/// The packets and their cells as the drawing passes read them: texel buffers, fetched by
/// texelFetch (glsl/packets.glsl). A storage buffer's divergent reads cost lavapipe a scalar load
/// per lane and component, a texel fetch one gather (docs/bench/packets.md: the mast's wake's
/// shading pass 0.66x).
pub struct PacketTexels<'g> {
    /// RGBA32_SFLOAT, five texels a packet: bit-exact for its floats (a fetch may flush a
    /// denormal, which no packet's quad nears: its corners lie metres or 1/w from 0). Not
    /// RGBA32_UINT: lavapipe 22.3 fetched the third of each three such texels as zeros.
    pub packets: Owned<'g, vk::BufferView>,
    /// R32_UINT: the cells' starts, then their lists.
    pub cells: Owned<'g, vk::BufferView>,
}

impl<'g> PacketTexels<'g> {
    pub const PACKET_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
    pub const CELL_FORMAT: vk::Format = vk::Format::R32_UINT;

    /// Views of `packets` and `cells`, made with UNIFORM_TEXEL_BUFFER usage (both formats'
    /// uniform texel buffer support is required by Vulkan).
    pub fn new(packets: &Buffer<'g>, cells: &Buffer<'g>, name: &str) -> Result<Self> {
        Ok(PacketTexels {
            packets: packets.texel_view(Self::PACKET_FORMAT, 16, &format!("{name} texels"))?,
            cells: cells.texel_view(Self::CELL_FORMAT, 4, &format!("{name} cell texels"))?,
        })
    }
}

/// The packets' buffers, made for a budget of packets alive.
pub struct PacketBuffers<'g> {
    /// How the drawing passes read `packets` and `cells` (dropped before them).
    pub texels: PacketTexels<'g>,
    /// Each frame slot's packets, written by the CPU: `max_alive` of them a slot.
    pub upload: Buffer<'g>,
    /// The frame's packets, copied from the slot's window by the binning (a transfer).
    pub packets: Buffer<'g>,
    /// Each cell's start in the lists (MAX_CELLS + 1 of them), then the lists.
    pub cells: Buffer<'g>,
    /// The binning's per-cell counters.
    pub counters: Buffer<'g>,
    /// Each frame slot's tiles' lists, written by the CPU: MAX_TILES + 1 starts, then the lists
    /// (grid::PacketGrid::tile_starts and tile_packets), `tile_words` a slot.
    pub tile_upload: Buffer<'g>,
    pub tile_words: usize,
    pub max_alive: usize,
    /// The lists' room (entries).
    pub max_entries: usize,
}

impl<'g> PacketBuffers<'g> {
    pub fn new(gpu: &'g Gpu, max_alive: usize, slots: u32) -> Result<Self> {
        use vk::BufferUsageFlags as B;
        let packet_bytes = std::mem::size_of::<GpuPacket>() as u64 * max_alive as u64;
        let max_entries = ENTRIES_PER_PACKET * max_alive;
        let tile_words = MAX_TILES as usize + 1 + grid::tile_room(max_entries);
        let cell_words = MAX_CELLS as u64 + 1 + max_entries as u64;
        // The cells' view is the longest (4 bytes a texel): a budget whose lists it cannot hold is
        // refused by its key, with the most this device takes.
        let limit = u64::from(gpu.device.properties.limits.max_texel_buffer_elements);
        if cell_words > limit {
            let most = limit.saturating_sub(MAX_CELLS as u64 + 1) / ENTRIES_PER_PACKET as u64;
            return Err(Error::MissingFeature {
                device: gpu.device.name.clone(),
                feature: format!(
                    "room for [packets] max_alive = {max_alive}: its cells' lists need {cell_words} texels, \
                     maxTexelBufferElements is {limit} (max_alive at most {most} here)"
                ),
            });
        }
        let storage = B::STORAGE_BUFFER;
        // Copied in from the slot's window by the binning, read as texels.
        let packets =
            Buffer::new(gpu, "packets", packet_bytes, B::TRANSFER_DST | B::UNIFORM_TEXEL_BUFFER, Location::Gpu)?;
        // Written by the binning, read as texels, copied out by Renderer::read_packet_lists.
        let cell_usage = B::STORAGE_BUFFER | B::UNIFORM_TEXEL_BUFFER | B::TRANSFER_SRC;
        let cells = Buffer::new(gpu, "packet cells", 4 * cell_words, cell_usage, Location::Gpu)?;
        let tile_bytes = 4 * (tile_words * slots as usize) as u64;
        Ok(PacketBuffers {
            texels: PacketTexels::new(&packets, &cells, "packets")?,
            upload: Buffer::new(gpu, "packets upload", packet_bytes * slots as u64, B::TRANSFER_SRC, Location::Upload)?,
            packets,
            cells,
            counters: Buffer::new(gpu, "packet counters", 4 * MAX_CELLS as u64, storage, Location::Gpu)?,
            tile_upload: Buffer::new(gpu, "packet tiles upload", tile_bytes, storage, Location::Upload)?,
            tile_words,
            max_alive,
            max_entries,
        })
    }

    /// The first packet of `slot`'s window in `upload`.
    pub fn first(&self, slot: usize) -> u32 {
        (slot * self.max_alive) as u32
    }

    /// The first word of `slot`'s window in `tile_upload`.
    pub fn tile_first(&self, slot: usize) -> u32 {
        (slot * self.tile_words) as u32
    }

    /// Writes a frame's packets and its tiles' lists into `slot`'s windows (the slot's last
    /// frame is done).
    pub fn write(&self, slot: usize, packets: &FramePackets) -> Result<()> {
        let grid = &packets.grid;
        debug_assert!(packets.gpu.len() <= self.max_alive && grid.entries <= self.max_entries);
        debug_assert!(MAX_TILES as usize + 1 + grid.tile_packets.len() <= self.tile_words);
        let offset = std::mem::size_of::<GpuPacket>() as u64 * self.first(slot) as u64;
        self.upload.write_at(offset, &packets.gpu)?;
        let tiles = 4 * self.tile_first(slot) as u64;
        self.tile_upload.write_at(tiles, &grid.tile_starts)?;
        self.tile_upload.write_at(tiles + 4 * (MAX_TILES as u64 + 1), &grid.tile_packets)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gpu_packet_is_five_texels() {
        assert_eq!(std::mem::size_of::<GpuPacket>(), 5 * 16);
    }
}
