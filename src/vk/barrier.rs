//! Synchronization from declared accesses. Every image level and buffer remembers its last
//! access; a pass declares what it reads and writes next, and the tracker emits exactly the
//! pipeline barrier (stages, access masks, layout) that the pair needs, batched in one call.

use super::buffer::Buffer;
use super::image::Image;
use ash::vk;
use std::collections::HashMap;

/// One way a pass touches a resource. All mapping to stages, accesses and layouts lives here.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Access {
    /// Contents undefined (new, or about to be fully overwritten).
    Undefined,
    ComputeStorageWrite,
    ComputeStorageRead,
    TransferRead,
    TransferWrite,
    FragmentSampled,
    ColorAttachmentWrite,
    DepthAttachmentReadWrite,
    HostRead,
}

impl Access {
    fn stage(self) -> vk::PipelineStageFlags2 {
        use vk::PipelineStageFlags2 as S;
        match self {
            Access::Undefined => S::NONE,
            Access::ComputeStorageWrite | Access::ComputeStorageRead => S::COMPUTE_SHADER,
            Access::TransferRead | Access::TransferWrite => S::BLIT | S::COPY,
            Access::FragmentSampled => S::FRAGMENT_SHADER,
            Access::ColorAttachmentWrite => S::COLOR_ATTACHMENT_OUTPUT,
            Access::DepthAttachmentReadWrite => S::EARLY_FRAGMENT_TESTS | S::LATE_FRAGMENT_TESTS,
            Access::HostRead => S::HOST,
        }
    }

    fn access(self) -> vk::AccessFlags2 {
        use vk::AccessFlags2 as A;
        match self {
            Access::Undefined => A::NONE,
            Access::ComputeStorageWrite => A::SHADER_STORAGE_WRITE,
            Access::ComputeStorageRead => A::SHADER_STORAGE_READ,
            Access::TransferRead => A::TRANSFER_READ,
            Access::TransferWrite => A::TRANSFER_WRITE,
            Access::FragmentSampled => A::SHADER_SAMPLED_READ,
            Access::ColorAttachmentWrite => A::COLOR_ATTACHMENT_WRITE,
            Access::DepthAttachmentReadWrite => A::DEPTH_STENCIL_ATTACHMENT_READ | A::DEPTH_STENCIL_ATTACHMENT_WRITE,
            Access::HostRead => A::HOST_READ,
        }
    }

    pub fn layout(self) -> vk::ImageLayout {
        use vk::ImageLayout as L;
        match self {
            Access::Undefined => L::UNDEFINED,
            Access::ComputeStorageWrite | Access::ComputeStorageRead => L::GENERAL,
            Access::TransferRead => L::TRANSFER_SRC_OPTIMAL,
            Access::TransferWrite => L::TRANSFER_DST_OPTIMAL,
            Access::FragmentSampled => L::SHADER_READ_ONLY_OPTIMAL,
            Access::ColorAttachmentWrite => L::COLOR_ATTACHMENT_OPTIMAL,
            Access::DepthAttachmentReadWrite => L::DEPTH_ATTACHMENT_OPTIMAL,
            Access::HostRead => L::UNDEFINED,
        }
    }

    fn writes(self) -> bool {
        matches!(
            self,
            Access::ComputeStorageWrite
                | Access::TransferWrite
                | Access::ColorAttachmentWrite
                | Access::DepthAttachmentReadWrite
        )
    }

    /// Whether moving from `self` to `next` needs a barrier: any write on either side (RAW, WAR,
    /// WAW), or a layout change. Read after read in one layout needs none.
    fn needs_barrier_to(self, next: Access, is_image: bool) -> bool {
        self.writes() || next.writes() || (is_image && self.layout() != next.layout())
    }
}

#[derive(Default)]
pub struct Tracker {
    images: HashMap<vk::Image, Vec<Access>>,
    buffers: HashMap<vk::Buffer, Access>,
    image_barriers: Vec<vk::ImageMemoryBarrier2<'static>>,
    buffer_barriers: Vec<vk::BufferMemoryBarrier2<'static>>,
}

impl Tracker {
    /// Declares that levels [base, base + count) of `image` are next accessed as `next`.
    /// `discard`: the previous contents are not needed (the layout may start from UNDEFINED).
    pub fn image(&mut self, image: &Image, base: u32, count: u32, next: Access, discard: bool) {
        let levels = self.images.entry(image.raw).or_insert_with(|| vec![Access::Undefined; image.mip_levels as usize]);
        let mut level = base;
        while level < base + count {
            // Batch consecutive levels that share their previous access into one barrier.
            let prev = levels[level as usize];
            let mut end = level + 1;
            while end < base + count && levels[end as usize] == prev {
                end += 1;
            }
            if prev.needs_barrier_to(next, true) {
                let old_layout = if discard { vk::ImageLayout::UNDEFINED } else { prev.layout() };
                self.image_barriers.push(
                    vk::ImageMemoryBarrier2::default()
                        .src_stage_mask(prev.stage())
                        .src_access_mask(prev.access())
                        .dst_stage_mask(next.stage())
                        .dst_access_mask(next.access())
                        .old_layout(old_layout)
                        .new_layout(next.layout())
                        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                        .image(image.raw)
                        .subresource_range(image.levels(level, end - level)),
                );
            }
            for l in level..end {
                levels[l as usize] = next;
            }
            level = end;
        }
    }

    /// Declares that `buffer` is next accessed as `next`.
    pub fn buffer(&mut self, buffer: &Buffer, next: Access) {
        let prev = self.buffers.insert(buffer.raw, next).unwrap_or(Access::Undefined);
        if prev != Access::Undefined && prev.needs_barrier_to(next, false) {
            self.buffer_barriers.push(
                vk::BufferMemoryBarrier2::default()
                    .src_stage_mask(prev.stage())
                    .src_access_mask(prev.access())
                    .dst_stage_mask(next.stage())
                    .dst_access_mask(next.access())
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

    /// Forgets a destroyed resource.
    pub fn forget_image(&mut self, image: vk::Image) {
        self.images.remove(&image);
    }
}
