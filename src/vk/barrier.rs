//! Synchronization from declared accesses. Every image level and buffer remembers its last write
//! and who has read since; a pass declares what it reads and writes next, and the tracker emits
//! exactly the pipeline barriers (stages, access masks, layouts) that need, batched in one call:
//! a write or layout change waits for the previous write and every read since (RAW, WAR, WAW);
//! a read waits for the last write only if that write is not yet visible to its stage.

use super::buffer::Buffer;
use super::image::Image;
use ash::vk;
use std::collections::HashMap;

/// An image the tracker can follow: ours, or a swapchain's.
pub trait TrackedImage {
    fn raw(&self) -> vk::Image;
    fn mip_levels(&self) -> u32;
    fn levels(&self, base: u32, count: u32) -> vk::ImageSubresourceRange;
}

/// One image's barrier, from (layout, stages, accesses) to the same, on one queue family.
pub fn image_barrier(
    from: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    to: (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    image: vk::Image,
    range: vk::ImageSubresourceRange,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .old_layout(from.0)
        .src_stage_mask(from.1)
        .src_access_mask(from.2)
        .new_layout(to.0)
        .dst_stage_mask(to.1)
        .dst_access_mask(to.2)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range)
}

/// Levels [base, base + count) of the only layer of an image, in `aspect`.
pub fn single_layer_levels(aspect: vk::ImageAspectFlags, base: u32, count: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: base,
        level_count: count,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl TrackedImage for Image<'_> {
    fn raw(&self) -> vk::Image {
        self.raw
    }
    fn mip_levels(&self) -> u32 {
        self.mip_levels
    }
    fn levels(&self, base: u32, count: u32) -> vk::ImageSubresourceRange {
        Image::levels(self, base, count)
    }
}

/// One way a pass touches a resource. All mapping to stages, accesses and layouts lives here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Contents undefined (new, or about to be fully overwritten).
    Undefined,
    ComputeStorageWrite,
    ComputeStorageRead,
    /// Each invocation reads texels and writes them back (in place).
    ComputeStorageReadWrite,
    ComputeSampled,
    /// A uniform buffer read by a compute or a fragment shader.
    ComputeUniformRead,
    FragmentUniformRead,
    /// A storage buffer read by a vertex shader (vertices pulled by index).
    VertexStorageRead,
    /// A texel buffer (or an image) sampled by a vertex shader.
    VertexSampled,
    /// An index buffer read by indexed draws.
    IndexRead,
    /// Indirect arguments read by vkCmdDispatchIndirect (or an indirect draw).
    IndirectRead,
    TransferRead,
    TransferWrite,
    /// vkCmdClearColorImage (the clear stage, not copy or blit).
    ClearWrite,
    FragmentSampled,
    ColorAttachmentWrite,
    /// A colour attachment loaded (LOAD_OP_LOAD, or blended) and written.
    ColorAttachmentReadWrite,
    DepthAttachmentReadWrite,
    HostRead,
    /// Handed to the presentation engine (a swapchain image after the frame's last write); the
    /// render-finished semaphore, signalled after every command, orders the present.
    Present,
}

impl Access {
    fn stage(self) -> vk::PipelineStageFlags2 {
        use vk::PipelineStageFlags2 as S;
        match self {
            Access::Undefined => S::NONE,
            Access::ComputeStorageWrite
            | Access::ComputeStorageRead
            | Access::ComputeStorageReadWrite
            | Access::ComputeSampled
            | Access::ComputeUniformRead => S::COMPUTE_SHADER,
            Access::FragmentUniformRead => S::FRAGMENT_SHADER,
            Access::VertexStorageRead | Access::VertexSampled => S::VERTEX_SHADER,
            Access::IndexRead => S::INDEX_INPUT,
            Access::IndirectRead => S::DRAW_INDIRECT,
            Access::TransferRead | Access::TransferWrite => S::BLIT | S::COPY,
            Access::ClearWrite => S::CLEAR,
            Access::FragmentSampled => S::FRAGMENT_SHADER,
            Access::ColorAttachmentWrite | Access::ColorAttachmentReadWrite => S::COLOR_ATTACHMENT_OUTPUT,
            Access::DepthAttachmentReadWrite => S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            Access::HostRead => S::HOST,
            Access::Present => S::NONE,
        }
    }

    fn access(self) -> vk::AccessFlags2 {
        use vk::AccessFlags2 as A;
        match self {
            Access::Undefined => A::NONE,
            Access::ComputeStorageWrite => A::SHADER_STORAGE_WRITE,
            Access::ComputeStorageRead => A::SHADER_STORAGE_READ,
            Access::ComputeStorageReadWrite => A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
            Access::ComputeSampled => A::SHADER_SAMPLED_READ,
            Access::ComputeUniformRead | Access::FragmentUniformRead => A::UNIFORM_READ,
            Access::VertexStorageRead => A::SHADER_STORAGE_READ,
            Access::VertexSampled => A::SHADER_SAMPLED_READ,
            Access::IndexRead => A::INDEX_READ,
            Access::IndirectRead => A::INDIRECT_COMMAND_READ,
            Access::TransferRead => A::TRANSFER_READ,
            Access::TransferWrite | Access::ClearWrite => A::TRANSFER_WRITE,
            Access::FragmentSampled => A::SHADER_SAMPLED_READ,
            Access::ColorAttachmentWrite => A::COLOR_ATTACHMENT_WRITE,
            Access::ColorAttachmentReadWrite => A::COLOR_ATTACHMENT_READ | A::COLOR_ATTACHMENT_WRITE,
            Access::DepthAttachmentReadWrite => A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            Access::HostRead => A::HOST_READ,
            Access::Present => A::NONE,
        }
    }

    pub fn layout(self) -> vk::ImageLayout {
        use vk::ImageLayout as L;
        match self {
            Access::Undefined => L::UNDEFINED,
            Access::ComputeStorageWrite | Access::ComputeStorageRead | Access::ComputeStorageReadWrite => L::GENERAL,
            Access::ComputeSampled => L::SHADER_READ_ONLY_OPTIMAL,
            Access::TransferRead => L::TRANSFER_SRC_OPTIMAL,
            Access::TransferWrite | Access::ClearWrite => L::TRANSFER_DST_OPTIMAL,
            Access::FragmentSampled | Access::VertexSampled => L::SHADER_READ_ONLY_OPTIMAL,
            Access::ColorAttachmentWrite | Access::ColorAttachmentReadWrite => L::COLOR_ATTACHMENT_OPTIMAL,
            // Not DEPTH_ATTACHMENT_OPTIMAL, which needs the separateDepthStencilLayouts feature.
            Access::DepthAttachmentReadWrite => L::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            Access::HostRead
            | Access::ComputeUniformRead
            | Access::FragmentUniformRead
            | Access::VertexStorageRead
            | Access::IndexRead
            | Access::IndirectRead => L::GENERAL,
            Access::Present => L::PRESENT_SRC_KHR,
        }
    }

    fn writes(self) -> bool {
        matches!(
            self,
            Access::ComputeStorageWrite
                | Access::ComputeStorageReadWrite
                | Access::TransferWrite
                | Access::ClearWrite
                | Access::ColorAttachmentWrite
                | Access::ColorAttachmentReadWrite
                | Access::DepthAttachmentReadWrite
        )
    }
}

/// What a resource (an image level or a buffer) has seen since its last write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct State {
    layout: vk::ImageLayout,
    /// Stage and access of the last write (NONE before any).
    write_stage: vk::PipelineStageFlags2,
    write_access: vk::AccessFlags2,
    /// Stages that read since that write: a later write must wait for them.
    read_stages: vk::PipelineStageFlags2,
    /// Stages and accesses the last write is already visible to.
    visible_stages: vk::PipelineStageFlags2,
    visible_access: vk::AccessFlags2,
}

impl State {
    const NEW: State = State {
        layout: vk::ImageLayout::UNDEFINED,
        write_stage: vk::PipelineStageFlags2::NONE,
        write_access: vk::AccessFlags2::NONE,
        read_stages: vk::PipelineStageFlags2::NONE,
        visible_stages: vk::PipelineStageFlags2::NONE,
        visible_access: vk::AccessFlags2::NONE,
    };
}

/// The dependency one access needs: (src stage, src access, dst stage, dst access, old, new layout).
struct Dependency {
    src_stage: vk::PipelineStageFlags2,
    src_access: vk::AccessFlags2,
    dst_stage: vk::PipelineStageFlags2,
    dst_access: vk::AccessFlags2,
    old_layout: vk::ImageLayout,
    new_layout: vk::ImageLayout,
}

/// Moves `state` to `next` and returns the barrier the move needs, if any.
/// `is_image`: layouts matter; `discard`: the old contents are not needed.
fn advance(state: &mut State, next: Access, is_image: bool, discard: bool) -> Option<Dependency> {
    let new_layout = if is_image { next.layout() } else { vk::ImageLayout::UNDEFINED };
    let layout_change = is_image && state.layout != new_layout;
    let old_layout = if discard { vk::ImageLayout::UNDEFINED } else { state.layout };
    if next.writes() || layout_change {
        // Wait for the last write (made available) and every read since; a layout change is
        // itself a write, so it gets the same treatment.
        let dep = Dependency {
            src_stage: state.write_stage | state.read_stages,
            src_access: state.write_access,
            dst_stage: next.stage(),
            dst_access: next.access(),
            old_layout,
            new_layout,
        };
        let needed = layout_change || !dep.src_stage.is_empty();
        *state = if next.writes() {
            State { layout: new_layout, write_stage: next.stage(), write_access: next.access(), ..State::NEW }
        } else {
            // A read behind a layout transition: the transition is visible to exactly this read.
            State {
                layout: new_layout,
                write_stage: dep.src_stage | dep.dst_stage,
                write_access: vk::AccessFlags2::NONE,
                read_stages: next.stage(),
                visible_stages: next.stage(),
                visible_access: next.access(),
            }
        };
        return needed.then_some(dep);
    }
    // A read in the same layout: it needs the last write to be visible to its stage and access.
    let visible = state.visible_stages.contains(next.stage()) && state.visible_access.contains(next.access());
    let dep = (!state.write_stage.is_empty() && !visible).then(|| Dependency {
        src_stage: state.write_stage,
        src_access: state.write_access,
        dst_stage: next.stage(),
        dst_access: next.access(),
        old_layout: state.layout,
        new_layout: state.layout,
    });
    if dep.is_some() {
        state.visible_stages |= next.stage();
        state.visible_access |= next.access();
    }
    state.read_stages |= next.stage();
    dep
}

#[derive(Default)]
pub struct Tracker {
    images: HashMap<vk::Image, Vec<State>>,
    buffers: HashMap<vk::Buffer, State>,
    image_barriers: Vec<vk::ImageMemoryBarrier2<'static>>,
    buffer_barriers: Vec<vk::BufferMemoryBarrier2<'static>>,
}

impl Tracker {
    /// Declares that levels [base, base + count) of `image` are next accessed as `next`.
    /// `discard`: the previous contents are not needed (the layout may start from UNDEFINED).
    pub fn image(&mut self, image: &impl TrackedImage, base: u32, count: u32, next: Access, discard: bool) {
        debug_assert!(next != Access::HostRead, "the host reads buffers, not images");
        let levels = self.images.entry(image.raw()).or_insert_with(|| vec![State::NEW; image.mip_levels() as usize]);
        let mut level = base;
        while level < base + count {
            // Batch consecutive levels that share their state into one barrier.
            let prev = levels[level as usize];
            let mut end = level + 1;
            while end < base + count && levels[end as usize] == prev {
                end += 1;
            }
            let mut state = prev;
            if let Some(dep) = advance(&mut state, next, true, discard) {
                self.image_barriers.push(image_barrier(
                    (dep.old_layout, dep.src_stage, dep.src_access),
                    (dep.new_layout, dep.dst_stage, dep.dst_access),
                    image.raw(),
                    image.levels(level, end - level),
                ));
            }
            for l in level..end {
                levels[l as usize] = state;
            }
            level = end;
        }
    }

    /// A host's image handed over for one frame: in `layout`, last accessed by the host's
    /// commands at `stage` with `access`. The first access of ours waits for that (a write made
    /// available, or reads a write of ours must not overtake) and moves it from that layout.
    pub fn external(
        &mut self,
        image: &impl TrackedImage,
        layout: vk::ImageLayout,
        stage: vk::PipelineStageFlags2,
        access: vk::AccessFlags2,
    ) {
        let state = State { layout, write_stage: stage, write_access: access, ..State::NEW };
        self.images.insert(image.raw(), vec![state; image.mip_levels() as usize]);
    }

    /// Forgets an image (destroyed, or a swapchain's that was replaced).
    pub fn forget(&mut self, image: vk::Image) {
        self.images.remove(&image);
    }

    /// Forgets a buffer about to be destroyed (its handle may be reused).
    pub fn forget_buffer(&mut self, buffer: vk::Buffer) {
        self.buffers.remove(&buffer);
    }

    /// Declares that `buffer` is next accessed as `next`.
    pub fn buffer(&mut self, buffer: &Buffer, next: Access) {
        let state = self.buffers.entry(buffer.raw).or_insert(State::NEW);
        if let Some(dep) = advance(state, next, false, false) {
            self.buffer_barriers.push(
                vk::BufferMemoryBarrier2::default()
                    .src_stage_mask(dep.src_stage)
                    .src_access_mask(dep.src_access)
                    .dst_stage_mask(dep.dst_stage)
                    .dst_access_mask(dep.dst_access)
                    .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .buffer(buffer.raw)
                    .offset(0)
                    .size(vk::WHOLE_SIZE),
            );
        }
    }

    /// Records every pending barrier in one vkCmdPipelineBarrier2.
    pub fn flush(&mut self, device: &ash::Device, cmd: vk::CommandBuffer) {
        if self.image_barriers.is_empty() && self.buffer_barriers.is_empty() {
            return;
        }
        let info = vk::DependencyInfo::default()
            .image_memory_barriers(&self.image_barriers)
            .buffer_memory_barriers(&self.buffer_barriers);
        // SAFETY: `cmd` is recording; the barriers name live resources of this device.
        unsafe { device.cmd_pipeline_barrier2(cmd, &info) };
        self.image_barriers.clear();
        self.buffer_barriers.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vk::PipelineStageFlags2 as S;

    #[test]
    fn read_after_write_waits_once_per_stage() {
        let mut state = State::NEW;
        assert!(
            advance(&mut state, Access::ComputeStorageWrite, false, false).is_none(),
            "first use waits for nothing"
        );
        let dep = advance(&mut state, Access::FragmentSampled, false, false).expect("RAW");
        assert_eq!((dep.src_stage, dep.dst_stage), (S::COMPUTE_SHADER, S::FRAGMENT_SHADER));
        assert_eq!(dep.src_access, vk::AccessFlags2::SHADER_STORAGE_WRITE);
        assert!(advance(&mut state, Access::FragmentSampled, false, false).is_none(), "already visible");
        let dep = advance(&mut state, Access::TransferRead, false, false).expect("visible to another stage");
        assert_eq!(dep.dst_stage, S::BLIT | S::COPY);
    }

    #[test]
    fn write_after_reads_waits_for_every_reader() {
        let mut state = State::NEW;
        advance(&mut state, Access::TransferWrite, false, false);
        advance(&mut state, Access::ComputeStorageRead, false, false);
        advance(&mut state, Access::FragmentSampled, false, false);
        let dep = advance(&mut state, Access::ComputeStorageWrite, false, false).expect("WAR");
        assert!(
            dep.src_stage.contains(S::COMPUTE_SHADER | S::FRAGMENT_SHADER | S::BLIT | S::COPY),
            "{:?}",
            dep.src_stage
        );
        let dep = advance(&mut state, Access::ComputeStorageWrite, false, false).expect("WAW");
        assert_eq!(dep.src_stage, S::COMPUTE_SHADER);
    }

    #[test]
    fn image_layout_changes_always_barrier() {
        let mut state = State::NEW;
        let dep = advance(&mut state, Access::ColorAttachmentWrite, true, true).expect("initial layout");
        assert_eq!(
            (dep.old_layout, dep.new_layout),
            (vk::ImageLayout::UNDEFINED, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        );
        let dep = advance(&mut state, Access::ComputeStorageRead, true, false).expect("layout change");
        assert_eq!(dep.new_layout, vk::ImageLayout::GENERAL);
        assert_eq!(dep.src_access, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE);
        let dep = advance(&mut state, Access::TransferRead, true, false).expect("layout change after a read");
        assert!(dep.src_stage.contains(S::COMPUTE_SHADER), "waits for the reader before changing the layout");
        let dep = advance(&mut state, Access::ColorAttachmentWrite, true, true).expect("next frame");
        assert_eq!(dep.old_layout, vk::ImageLayout::UNDEFINED, "discarded contents");
    }
}
