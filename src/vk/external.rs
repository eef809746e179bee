//! A host's images, handed to the ocean for one frame (embed::Ocean): the handles, the state the
//! host leaves them in, and what each format means to us. All mapping of host formats lives here.

use super::barrier::{image_barrier, single_layer_levels, TrackedImage};
use ash::vk;

/// A host's image: its handle, a view of its first level and layer, its format and extent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HostImage {
    /// The image.
    pub raw: vk::Image,
    /// A view of its first level and layer (its depth aspect, for a depth image).
    pub view: vk::ImageView,
    /// The format it was created with.
    pub format: vk::Format,
    /// Its size in pixels.
    pub extent: vk::Extent2D,
}

impl From<&super::image::Image<'_>> for HostImage {
    /// One of our own images handed over as a host's (the commands host the ocean this way).
    fn from(image: &super::image::Image) -> HostImage {
        HostImage { raw: image.raw, view: image.level0_view, format: image.format, extent: image.extent }
    }
}

impl TrackedImage for HostImage {
    fn raw(&self) -> vk::Image {
        self.raw
    }
    fn mip_levels(&self) -> u32 {
        1
    }
    fn levels(&self, base: u32, count: u32) -> vk::ImageSubresourceRange {
        single_layer_levels(aspect_of(self.format), base, count)
    }
}

/// How a host leaves an image for the ocean: its layout, and the stages and accesses of the
/// host's last use of it that the ocean's first access must wait for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageState {
    /// The image's layout.
    pub layout: vk::ImageLayout,
    /// The stages of its last use (or of the semaphore wait that makes it available).
    pub stage: vk::PipelineStageFlags2,
    /// The accesses of its last use (writes to make available; none for reads).
    pub access: vk::AccessFlags2,
}

impl ImageState {
    /// A colour attachment the host rendered into (the HDR target's usual state on entry).
    pub const COLOR_ATTACHMENT: ImageState = ImageState {
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        stage: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    };
    /// A depth attachment the host rendered into (the depth target's usual state on entry).
    pub const DEPTH_ATTACHMENT: ImageState = ImageState {
        layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        stage: vk::PipelineStageFlags2::from_raw(
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw()
                | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
        ),
        access: vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
    };
    /// A swapchain image just acquired, its semaphore waited at COLOR_ATTACHMENT_OUTPUT (an LDR
    /// target's usual state on entry; its contents are not kept).
    pub const ACQUIRED: ImageState = ImageState {
        layout: vk::ImageLayout::UNDEFINED,
        stage: vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        access: vk::AccessFlags2::NONE,
    };
}

impl ImageState {
    /// A state from its layout, stages and accesses.
    pub const fn new(layout: vk::ImageLayout, stage: vk::PipelineStageFlags2, access: vk::AccessFlags2) -> ImageState {
        ImageState { layout, stage, access }
    }

    /// The barrier that takes `image` from this state to `next`: `next`'s accesses wait for this
    /// state's, and the layout changes between them.
    pub fn barrier_to(&self, next: ImageState, image: &HostImage) -> vk::ImageMemoryBarrier2<'static> {
        let (from, to) = ((self.layout, self.stage, self.access), (next.layout, next.stage, next.access));
        image_barrier(from, to, image.raw, image.levels(0, 1))
    }
}

/// Records the barriers taking each image from one state to the next, in one call (a host's
/// transitions into and out of the states the ocean's contract names).
pub fn transition(device: &ash::Device, cmd: vk::CommandBuffer, moves: &[(HostImage, ImageState, ImageState)]) {
    let barriers: Vec<_> = moves.iter().map(|(image, from, to)| from.barrier_to(*to, image)).collect();
    // SAFETY: the caller's `cmd` is recording outside a rendering scope and its images are live
    // (a documented precondition of this helper, which only builds the barriers).
    unsafe { device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barriers)) };
}

/// Begins a rendering scope over the whole of a host's colour and depth, the colour cleared to
/// black and the depth to `far` (0 reversed, 1 standard), the viewport and scissor set to the
/// whole target: where a host draws its objects. Both are in their attachment layouts and `cmd`
/// is recording outside a rendering scope (this helper's precondition); the caller ends the scope.
pub fn begin_cleared_rendering(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    colour: &HostImage,
    depth: &HostImage,
    far: f32,
) {
    let colour_attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(colour.view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(depth.view)
        .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: far, stencil: 0 } });
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: colour.extent };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&colour_attachment)
        .depth_attachment(&depth_attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: colour.extent.width as f32,
        height: colour.extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: the caller's `cmd` is recording outside a rendering scope and the images are in
    // their attachment layouts (this helper's documented precondition).
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// Clears a host's colour to black and its depth to `far` (0 reversed, 1 standard) in one
/// rendering scope, both in their attachment layouts: a host frame that starts with the ocean,
/// nothing of the host's own drawn (a bench, a test).
pub fn clear_targets(device: &ash::Device, cmd: vk::CommandBuffer, colour: &HostImage, depth: &HostImage, far: f32) {
    begin_cleared_rendering(device, cmd, colour, depth, far);
    // SAFETY: the scope was begun just above on `cmd`.
    unsafe { device.cmd_end_rendering(cmd) };
}

/// The aspects a layout transition of an image of `format` names: depth, with stencil where the
/// format has it (both aspects change layout together without separateDepthStencilLayouts).
pub fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    use vk::Format as F;
    match format {
        F::D16_UNORM | F::D32_SFLOAT | F::X8_D24_UNORM_PACK32 => vk::ImageAspectFlags::DEPTH,
        F::D16_UNORM_S8_UINT | F::D24_UNORM_S8_UINT | F::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// The host depth formats the ocean depth-tests against.
pub const HOST_DEPTH_FORMATS: [vk::Format; 5] = [
    vk::Format::D32_SFLOAT,
    vk::Format::D32_SFLOAT_S8_UINT,
    vk::Format::D24_UNORM_S8_UINT,
    vk::Format::X8_D24_UNORM_PACK32,
    vk::Format::D16_UNORM,
];

/// The largest radiance an HDR colour format of the host holds (what the ocean clamps to so that
/// no Inf reaches it), or None for a format the ocean does not write as HDR colour.
pub fn hdr_format_max(format: vk::Format) -> Option<f32> {
    use vk::Format as F;
    match format {
        // binary16's largest finite value.
        F::R16G16B16A16_SFLOAT => Some(65504.0),
        // The 11- and 10-bit floats' largest finite values are 65024 and 64512 (both exponent
        // 15 with the mantissa full); the smaller bounds every channel.
        F::B10G11R11_UFLOAT_PACK32 => Some(64512.0),
        F::R32G32B32A32_SFLOAT => Some(f32::MAX),
        _ => None,
    }
}

/// Whether the ocean tone-maps into an LDR format of the host, and whether the shader applies
/// the sRGB encoding (a UNORM format) or the format does on store (an SRGB one).
pub fn ldr_encodes_srgb(format: vk::Format) -> Option<bool> {
    use vk::Format as F;
    match format {
        F::R8G8B8A8_SRGB | F::B8G8R8A8_SRGB | F::A8B8G8R8_SRGB_PACK32 => Some(false),
        F::R8G8B8A8_UNORM | F::B8G8R8A8_UNORM | F::A8B8G8R8_UNORM_PACK32 | F::A2B10G10R10_UNORM_PACK32 => Some(true),
        _ => None,
    }
}
