//! 2D images placed in our allocator, with a view of all levels and one per level on demand.

use super::barrier::{single_layer_levels, Access, Tracker};
use super::external::HostImage;
use super::gpu::Gpu;
use super::memory::{Allocation, Location, ResourceKind};
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;

/// An image, its views and its memory, all released when dropped.
pub struct Image<'g> {
    gpu: &'g Gpu,
    pub raw: vk::Image,
    /// View of every mip level.
    pub view: vk::ImageView,
    /// View of level 0 alone (storage writes need single-level views).
    pub level0_view: vk::ImageView,
    /// View of level 0 in another format of the same texel size (see `Image::aliased`); null
    /// for images made without one.
    pub alias_view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub mip_levels: u32,
    pub aspect: vk::ImageAspectFlags,
    allocation: Option<Allocation>,
    /// Whether `raw` is ours to destroy (false: a host's image we made views of).
    owned: bool,
}

impl<'g> Image<'g> {
    pub fn new(
        gpu: &'g Gpu,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        mip_levels: u32,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        Self::create(gpu, name, format, None, extent, mip_levels, usage)
    }

    /// A single-level image whose texels are also read and written as `alias` (a format of the
    /// same size class, so the bits are reinterpreted, never converted) through `alias_view`.
    pub fn aliased(
        gpu: &'g Gpu,
        name: &str,
        format: vk::Format,
        alias: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        Self::create(gpu, name, format, Some(alias), extent, 1, usage)
    }

    /// A host's single-level colour image, drawn into in place: our views of it (its own format,
    /// and `alias` through `alias_view`), never its memory. The host made it `MUTABLE_FORMAT`
    /// with both formats allowed, and keeps it alive while we do; dropping destroys the views.
    pub fn borrowed_aliased(gpu: &'g Gpu, name: &str, host: &HostImage, alias: vk::Format) -> Result<Self> {
        // The host made it single-level and mutable with both formats among its view formats (its
        // precondition, embed::IN_PLACE_VIEW_FORMATS).
        let range = single_layer_levels(vk::ImageAspectFlags::COLOR, 0, 1);
        let make_view = |format, label: &str| create_view(gpu, host.raw, format, range, &format!("{name} {label}"));
        let view = make_view(host.format, "(the host's, in place)")?;
        let mut image = Image {
            gpu,
            raw: host.raw,
            view,
            level0_view: view,
            alias_view: vk::ImageView::null(),
            format: host.format,
            extent: host.extent,
            mip_levels: 1,
            aspect: vk::ImageAspectFlags::COLOR,
            allocation: None,
            owned: false,
        };
        image.alias_view = make_view(alias, &format!("as {alias:?}"))?;
        Ok(image)
    }

    fn create(
        gpu: &'g Gpu,
        name: &str,
        format: vk::Format,
        alias: Option<vk::Format>,
        extent: vk::Extent2D,
        mip_levels: u32,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        let device = gpu.raw();
        // The formats the views will use, so that a driver may keep compression it can share.
        let formats = [format, alias.unwrap_or(format)];
        let mut format_list = vk::ImageFormatListCreateInfo::default().view_formats(&formats);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let info = if alias.is_some() {
            info.flags(vk::ImageCreateFlags::MUTABLE_FORMAT).push_next(&mut format_list)
        } else {
            info
        };
        // SAFETY: valid create info (formats checked at device choice); destroyed in Drop.
        let raw = unsafe { device.create_image(&info, None) }.during("vkCreateImage")?;
        gpu.device.set_name(raw, name);
        let mut dedicated = vk::MemoryDedicatedRequirements::default();
        let mut req2 = vk::MemoryRequirements2::default().push_next(&mut dedicated);
        // SAFETY: `raw` is a live image of this device.
        unsafe {
            device.get_image_memory_requirements2(&vk::ImageMemoryRequirementsInfo2::default().image(raw), &mut req2)
        };
        let req = req2.memory_requirements;
        let wants_own =
            dedicated.prefers_dedicated_allocation == vk::TRUE || dedicated.requires_dedicated_allocation == vk::TRUE;
        let own = wants_own.then(|| vk::MemoryDedicatedAllocateInfo::default().image(raw));
        let allocation = match gpu.allocator.borrow_mut().allocate(name, req, Location::Gpu, ResourceKind::Optimal, own)
        {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: never bound, never used.
                unsafe { device.destroy_image(raw, None) };
                return Err(e);
            }
        };
        let aspect =
            if format == vk::Format::D32_SFLOAT { vk::ImageAspectFlags::DEPTH } else { vk::ImageAspectFlags::COLOR };
        // From here on Drop releases whatever exists (null views are skipped by Vulkan).
        let mut image = Image {
            gpu,
            raw,
            view: vk::ImageView::null(),
            level0_view: vk::ImageView::null(),
            alias_view: vk::ImageView::null(),
            format,
            extent,
            mip_levels,
            aspect,
            allocation: Some(allocation),
            owned: true,
        };
        let (memory, offset) = image.allocation.as_ref().map(|a| (a.memory, a.offset)).expect("just placed");
        // SAFETY: the allocation satisfies the image's requirements.
        unsafe { device.bind_image_memory(raw, memory, offset) }.during("vkBindImageMemory")?;
        let make_view = |format, base, count, label: &str| {
            let range = single_layer_levels(aspect, base, count);
            create_view(gpu, raw, format, range, &format!("{name} {label}"))
        };
        image.view = make_view(format, 0, mip_levels, "all levels")?;
        image.level0_view = if mip_levels > 1 { make_view(format, 0, 1, "level 0")? } else { image.view };
        if let Some(alias) = alias {
            image.alias_view = make_view(alias, 0, 1, &format!("as {alias:?}"))?;
        }
        Ok(image)
    }

    /// A view of level `level` alone (storage access to one level of a pyramid).
    pub fn level_view(&self, level: u32) -> Result<Owned<'g, vk::ImageView>> {
        let view = create_view(self.gpu, self.raw, self.format, self.levels(level, 1), &format!("level {level}"))?;
        Ok(Owned::new(&self.gpu.device, view, "image level"))
    }

    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        self.levels(0, self.mip_levels)
    }

    pub fn levels(&self, base: u32, count: u32) -> vk::ImageSubresourceRange {
        single_layer_levels(self.aspect, base, count)
    }
}

impl Drop for Image<'_> {
    fn drop(&mut self) {
        let device = self.gpu.raw();
        // SAFETY: the device is idle (Renderer's Drop waits) or the image was never used.
        unsafe {
            if self.level0_view != self.view {
                device.destroy_image_view(self.level0_view, None);
            }
            device.destroy_image_view(self.alias_view, None); // a null handle is ignored
            device.destroy_image_view(self.view, None);
            if self.owned {
                device.destroy_image(self.raw, None);
            }
        }
        if let Some(a) = self.allocation.take() {
            self.gpu.allocator.borrow_mut().free(a);
        }
    }
}

/// A 2D view of `range` of `raw`, named `name`. `raw` is a live image of this device, bound to
/// memory, `range` lies inside it, and `format` is its own or one its views may take.
fn create_view(
    gpu: &Gpu,
    raw: vk::Image,
    format: vk::Format,
    range: vk::ImageSubresourceRange,
    name: &str,
) -> Result<vk::ImageView> {
    let info = vk::ImageViewCreateInfo::default()
        .image(raw)
        .view_type(vk::ImageViewType::TYPE_2D)
        .format(format)
        .subresource_range(range);
    // SAFETY: the image, range and format are valid for a view (the callers' invariant above).
    let view = unsafe { gpu.raw().create_image_view(&info, None) }.during("vkCreateImageView")?;
    gpu.device.set_name(view, name);
    Ok(view)
}

/// A view of a host's depth image's depth aspect alone, the one a shader samples (a combined
/// depth-stencil view cannot be). The host made it SAMPLED (embed::OceanDesc::shading's
/// reflections) and keeps it alive while the view lives.
pub fn host_depth_view<'g>(gpu: &'g Gpu, host: &HostImage) -> Result<Owned<'g, vk::ImageView>> {
    let range = single_layer_levels(vk::ImageAspectFlags::DEPTH, 0, 1);
    let view = create_view(gpu, host.raw, host.format, range, "host depth, sampled")?;
    Ok(Owned::new(&gpu.device, view, "host depth, sampled"))
}

/// Records a linear blit of colour level `level - 1` of `image` (in TRANSFER_SRC_OPTIMAL) onto
/// level `level` (in TRANSFER_DST_OPTIMAL): one step of a mipmap. The format supports linear
/// blits (checked at device choice, or one the specification requires it of).
fn blit_level(device: &ash::Device, cmd: vk::CommandBuffer, image: &Image, level: u32) {
    let size = |l: u32| vk::Offset3D {
        x: (image.extent.width >> l).max(1) as i32,
        y: (image.extent.height >> l).max(1) as i32,
        z: 1,
    };
    let layer = |l: u32| vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: l,
        base_array_layer: 0,
        layer_count: 1,
    };
    let blit = vk::ImageBlit {
        src_subresource: layer(level - 1),
        src_offsets: [vk::Offset3D::default(), size(level - 1)],
        dst_subresource: layer(level),
        dst_offsets: [vk::Offset3D::default(), size(level)],
    };
    // SAFETY: `cmd` is recording outside a rendering scope and the two levels are in the
    // layouts named (the caller's barriers).
    unsafe {
        device.cmd_blit_image(
            cmd,
            image.raw,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            image.raw,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[blit],
            vk::Filter::LINEAR,
        )
    };
}

/// Fills levels 1.. of `image` from level 0, each a linear blit of the one above, with the
/// barriers between them; the levels are left in transfer layouts for the caller to declare on.
pub fn mipmap(device: &ash::Device, cmd: vk::CommandBuffer, tracker: &mut Tracker, image: &Image) {
    for level in 1..image.mip_levels {
        tracker.image(image, level - 1, 1, Access::TransferRead, false);
        tracker.image(image, level, 1, Access::TransferWrite, true);
        tracker.flush(device, cmd);
        blit_level(device, cmd, image, level);
    }
}

/// A copy of the whole of colour level 0 of an `extent` image to or from a tightly packed buffer
/// at `buffer_offset`.
pub fn level0_region(extent: vk::Extent2D, buffer_offset: u64) -> vk::BufferImageCopy {
    vk::BufferImageCopy {
        buffer_offset,
        buffer_row_length: 0,
        buffer_image_height: 0,
        image_subresource: vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        },
        image_offset: vk::Offset3D::default(),
        image_extent: vk::Extent3D { width: extent.width, height: extent.height, depth: 1 },
    }
}

/// Copies a whole single-level colour image (in TRANSFER_SRC_OPTIMAL) into a tightly packed buffer.
pub fn copy_to_buffer(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    buffer: vk::Buffer,
) {
    let region = level0_region(extent, 0);
    // SAFETY: the image was declared TransferRead (TRANSFER_SRC_OPTIMAL) and the buffer
    // TransferWrite, and the buffer holds the whole image.
    unsafe { device.cmd_copy_image_to_buffer(cmd, image, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, buffer, &[region]) };
}
