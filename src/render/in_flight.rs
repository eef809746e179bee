//! Frames in flight: what the CPU writes or records for one frame lives in a slot (command
//! buffer and fence, timestamp queries, the grid's index buffer, the window's acquire semaphore,
//! and a window of the uniform ring), so that the CPU prepares frame N+1 while the GPU runs N
//! and waits only for the frame whose slot it is about to reuse.

use crate::error::{Error, Result};
use crate::render::timeline::Submission;
use crate::vk::buffer::Buffer;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::memory::Location;
use crate::vk::profiler::Profiler;
use ash::vk;

/// Most grid nodes a frame may draw: 2^24 nodes need 400 MB of indices; finer grids are an error.
pub const MAX_GRID_NODES: u64 = 1 << 24;

/// The triangle list of a columns x rows projected grid (row-major nodes).
pub struct GridIndices<'g> {
    gpu: &'g Gpu,
    pub buffer: Option<Buffer<'g>>,
    pub count: u32,
    layout: Option<(u32, u32)>,
}

impl<'g> GridIndices<'g> {
    pub fn new(gpu: &'g Gpu) -> Self {
        GridIndices { gpu, buffer: None, count: 0, layout: None }
    }

    /// Writes the indices of a columns x rows grid if the layout changed. The slot's fence was
    /// waited, so the buffer may be rewritten or replaced.
    pub fn set(&mut self, columns: u32, rows: u32) -> Result<()> {
        if self.layout == Some((columns, rows)) {
            return Ok(());
        }
        let nodes = columns as u64 * rows as u64;
        if nodes > MAX_GRID_NODES {
            return Err(Error::Argument(format!(
                "a {columns}x{rows} projected grid has more than {MAX_GRID_NODES} nodes: raise render.grid_cell_px"
            )));
        }
        let mut indices = Vec::with_capacity(6 * columns.saturating_sub(1) as usize * rows.saturating_sub(1) as usize);
        for row in 0..rows.saturating_sub(1) {
            for col in 0..columns.saturating_sub(1) {
                let a = row * columns + col;
                let (b, c, d) = (a + 1, a + columns, a + columns + 1);
                indices.extend_from_slice(&[a, c, b, b, c, d]);
            }
        }
        let bytes = std::mem::size_of_val(indices.as_slice()) as u64;
        if self.buffer.as_ref().is_none_or(|b| b.size < bytes) {
            self.buffer = None; // free the old buffer before placing the larger one
            let usage = vk::BufferUsageFlags::INDEX_BUFFER;
            self.buffer = Some(Buffer::new(self.gpu, "grid indices", bytes, usage, Location::Upload)?);
        }
        if let Some(buffer) = &self.buffer {
            buffer.write(&indices)?;
        }
        self.count = indices.len() as u32;
        self.layout = Some((columns, rows));
        Ok(())
    }
}

pub struct FrameSlot<'g> {
    pub index: usize,
    // Drop order: nothing here may go while the GPU uses it; the renderer waits for idle first.
    pub commands: Commands<'g>,
    pub profiler: Profiler<'g>,
    /// When the slot's last frame was submitted, and the clocks then (for its GPU spans).
    pub submission: Option<Submission>,
    pub grid: GridIndices<'g>,
    /// Whether a frame was recorded into a host's command buffer since the slot was last taken.
    pub host_recorded: bool,
    /// What a host recorded of the slot's frame ahead of it.
    pub ahead: RecordedAhead,
}

/// The passes a host records ahead of its frame, into its own command buffer, for its draws to
/// use (embed::Ocean::record_shadows, record_planar), and the host's own passes timed in its
/// profile (record_host_pass).
#[derive(Clone, Copy, Debug, Default)]
pub struct RecordedAhead {
    /// The slot's profile was reset and its first scopes written.
    pub profile_begun: bool,
    /// The sun's shadow map, with the host's casters.
    pub shadows: bool,
    /// The mirror pass, with the host's mirrored objects: the share of its images it built.
    pub planar: Option<f64>,
    /// The host's own passes.
    pub host_passes: usize,
    /// The wave packets' binning (recorded with the sun's view ahead of the frame).
    pub packets_binned: bool,
}

impl<'g> FrameSlot<'g> {
    /// Before a pass a host records ahead of the slot's frame into `cmd`: the first one resets
    /// the slot's profile.
    pub fn begin_ahead(&mut self, device: &ash::Device, cmd: vk::CommandBuffer) {
        if !std::mem::replace(&mut self.ahead.profile_begun, true) {
            self.profiler.reset(device, cmd);
        }
    }

    /// `statistics`: pipeline statistics per timestamp scope too, where the device has them.
    pub fn new(gpu: &'g Gpu, index: usize, timestamp_scopes: u32, statistics: bool) -> Result<Self> {
        let device = &gpu.device;
        Ok(FrameSlot {
            index,
            commands: Commands::new(device, &format!("frame {index}"))?,
            profiler: Profiler::new(device, timestamp_scopes, statistics)?,
            submission: None,
            grid: GridIndices::new(gpu),
            host_recorded: false,
            ahead: RecordedAhead::default(),
        })
    }
}
