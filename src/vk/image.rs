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

/// A rectangle of texels of an image's level: columns x0..x1 and rows y0..y1, ends exclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl PixelRect {
    /// No texel.
    pub const EMPTY: PixelRect = PixelRect { x0: 0, y0: 0, x1: 0, y1: 0 };

    /// The whole of an `extent` level.
    pub fn whole(extent: vk::Extent2D) -> Self {
        PixelRect { x0: 0, y0: 0, x1: extent.width, y1: extent.height }
    }

    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    pub fn extent(&self) -> vk::Extent2D {
        vk::Extent2D { width: self.x1.saturating_sub(self.x0), height: self.y1.saturating_sub(self.y0) }
    }

    /// The texels of level `level` of an image whose level 0 is `base` that hold any texel of this
    /// rectangle of level 0: each level's texel holds the 2 x 2 below it, and an odd level's
    /// trailing row and column fold into its last texel, so level 0's texel x lies in level l's
    /// min(x >> l, size - 1).
    pub fn at_level(&self, level: u32, base: vk::Extent2D) -> Self {
        if self.is_empty() {
            return PixelRect::EMPTY;
        }
        let size = level_extent(base, level);
        let texel = |v: u32, size: u32| (v >> level).min(size - 1);
        PixelRect {
            x0: texel(self.x0, size.width),
            y0: texel(self.y0, size.height),
            x1: texel(self.x1 - 1, size.width) + 1,
            y1: texel(self.y1 - 1, size.height) + 1,
        }
    }
}

/// The size of level `level` of an image whose level 0 is `base`.
pub fn level_extent(base: vk::Extent2D, level: u32) -> vk::Extent2D {
    vk::Extent2D { width: (base.width >> level).max(1), height: (base.height >> level).max(1) }
}

/// Records a linear blit of colour level `level - 1` of `image` (in TRANSFER_SRC_OPTIMAL) onto
/// the texels `dst` of level `level` (in TRANSFER_DST_OPTIMAL; PixelRect::at_level's): one
/// step of a mipmap. Each texel samples the middle of the 2 x 2 above it (their mean); where the
/// region reaches an odd level's far edge, it is scaled to take the trailing row or column in,
/// as a blit of the whole level is (a linear blit of 3 texels onto 1 reads the middle one). The
/// format supports linear blits (checked at device choice, or one the specification requires it
/// of).
fn blit_level(device: &ash::Device, cmd: vk::CommandBuffer, image: &Image, level: u32, dst: PixelRect) {
    if dst.is_empty() {
        return;
    }
    let (src_size, dst_size) = (level_extent(image.extent, level - 1), level_extent(image.extent, level));
    let src_end = |end: u32, dst_end: u32, src_end: u32| if end == dst_end { src_end } else { (2 * end).min(src_end) };
    let src = PixelRect {
        x0: (2 * dst.x0).min(src_size.width - 1),
        y0: (2 * dst.y0).min(src_size.height - 1),
        x1: src_end(dst.x1, dst_size.width, src_size.width),
        y1: src_end(dst.y1, dst_size.height, src_size.height),
    };
    let corners = |r: PixelRect| {
        [vk::Offset3D { x: r.x0 as i32, y: r.y0 as i32, z: 0 }, vk::Offset3D { x: r.x1 as i32, y: r.y1 as i32, z: 1 }]
    };
    let layer = |l: u32| vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: l,
        base_array_layer: 0,
        layer_count: 1,
    };
    let blit = vk::ImageBlit {
        src_subresource: layer(level - 1),
        src_offsets: corners(src),
        dst_subresource: layer(level),
        dst_offsets: corners(dst),
    };
    // SAFETY: `cmd` is recording outside a rendering scope, the two levels are in the layouts
    // named (the caller's barriers) and both regions lie inside their levels.
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
    mipmap_within(device, cmd, tracker, image, PixelRect::whole(image.extent));
}

/// As `mipmap`, over the texels that level 0's rectangle `within` covers on each level alone: the
/// rest of each level keeps what it holds (a caller that clears it leaves it zero). On a level of
/// odd size a part blits exact 2 x 2 blocks where the whole level's blit scales by
/// W / floor(W / 2): the two differ there by a fraction of a texel's offset.
pub fn mipmap_within(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    tracker: &mut Tracker,
    image: &Image,
    within: PixelRect,
) {
    for level in 1..image.mip_levels {
        let region = within.at_level(level, image.extent);
        let whole = region == PixelRect::whole(level_extent(image.extent, level));
        tracker.image(image, level - 1, 1, Access::TransferRead, false);
        tracker.image(image, level, 1, Access::TransferWrite, whole);
        tracker.flush(device, cmd);
        blit_level(device, cmd, image, level, region);
    }
}

/// Clears levels `levels` of colour image `image` (declared ClearWrite by the caller) to zero.
pub fn clear_levels(device: &ash::Device, cmd: vk::CommandBuffer, image: &Image, levels: std::ops::Range<u32>) {
    if levels.is_empty() {
        return;
    }
    let range = single_layer_levels(vk::ImageAspectFlags::COLOR, levels.start, levels.end - levels.start);
    let zero = vk::ClearColorValue { float32: [0.0; 4] };
    // SAFETY: `cmd` is recording outside a rendering scope; the levels are in
    // TRANSFER_DST_OPTIMAL (the caller's declaration) and the image was made TRANSFER_DST.
    unsafe { device.cmd_clear_color_image(cmd, image.raw, vk::ImageLayout::TRANSFER_DST_OPTIMAL, &zero, &[range]) };
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rectangle_covers_on_each_level_the_texels_its_own_fold_into() {
        let base = vk::Extent2D { width: 1023, height: 6 };
        // Level 0's texel x lies in level l's min(x >> l, size - 1): check every one-texel
        // rectangle against that rule, on every level.
        for x in [0, 1, 510, 511, 1020, 1021, 1022] {
            let one = PixelRect { x0: x, y0: 5, x1: x + 1, y1: 6 };
            for level in 0..10 {
                let size = level_extent(base, level);
                let r = one.at_level(level, base);
                let texel = (x >> level).min(size.width - 1);
                assert_eq!((r.x0, r.x1), (texel, texel + 1), "x {x} level {level}");
                assert_eq!((r.y0, r.y1), ((5 >> level).min(size.height - 1), (5 >> level).min(size.height - 1) + 1));
            }
        }
        // The whole level 0 covers the whole of every level; nothing covers nothing.
        for level in 0..10 {
            assert_eq!(PixelRect::whole(base).at_level(level, base), PixelRect::whole(level_extent(base, level)));
            assert!(PixelRect { x0: 3, y0: 3, x1: 3, y1: 5 }.at_level(level, base).is_empty());
        }
    }
}
