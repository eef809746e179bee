//! The frame's passes, in order. Each declares what it reads and writes; the frame derives the
//! barriers from those declarations (vk::barrier), then records the pass inside a debug label
//! and a timestamp scope of the pass's name.

pub mod atmosphere;
pub mod black;
pub mod composite;
pub mod exposure;
pub mod eye_sky;
pub mod host_copy;
pub mod host_tonemap;
pub mod ocean;
pub mod packets;
pub mod placeholders;
pub mod planar;
pub mod planar_tiles;
pub mod pyramid;
pub mod readback;
pub mod reflections;
pub mod resolve;
pub mod shade;
pub mod shadow;
pub mod sky_map;
pub mod tonemap;

use crate::render::resources::{Resources, FRAME_BINDING, WAVES_BINDING};
use crate::vk::barrier::Tracker;
use crate::vk::device::Device;
use crate::vk::external::HostImage;
use crate::vk::image::PixelRect;
use crate::vk::pipeline::Bindings;
use ash::vk;

/// What one frame's passes use beside the shared resources: its slot's uniform windows and grid,
/// and the window's image when the frame ends on screen.
pub struct Frame {
    /// The frame slot (frames in flight) the frame is recorded for.
    pub slot: usize,
    /// Offsets of the dynamic uniform buffers, indexed by binding number.
    pub uniform_offsets: [u32; 2],
    /// The grid's index buffer and index count (none when no sea is in view).
    pub grid: Option<(vk::Buffer, u32)>,
    /// Top rows of the rendered image that only sky covers.
    pub sky_rows: u32,
    /// The first row of the rendered image from which only sea is seen.
    pub sea_rows: u32,
    /// Whether the sun has a view of the displaced sea this frame (sun_shadow::fit).
    pub sun_view: bool,
    /// A host's attachments, when the frame is recorded into a host's frame (embed::Ocean).
    pub host: Option<HostTargets>,
    /// Whether the host drew its objects mirrored into the planar images this frame
    /// (passes/planar.rs), which the shading pass then reads.
    pub planar_drawn: bool,
    /// The frame's wave packets, their grid's cells and its tiles (0, 0 and 0 without).
    pub packets: u32,
    pub packet_cells: u32,
    pub packet_tiles: u32,
}

/// The host's attachments a frame draws into (passes/composite.rs).
#[derive(Clone, Copy, Debug)]
pub struct HostTargets {
    pub colour: HostImage,
    /// None: the host drew no objects (HostFormats::depth).
    pub depth: Option<HostImage>,
    /// The LDR target the host's frame is tone-mapped into, when asked (passes/host_tonemap.rs).
    pub ldr: Option<HostImage>,
}

pub struct Recorder<'a> {
    pub device: &'a Device,
    pub cmd: vk::CommandBuffer,
    pub tracker: &'a mut Tracker,
    pub frame: &'a Frame,
}

pub trait Pass {
    fn name(&self) -> &'static str;
    /// Declares every resource access of the pass (queued as barriers on the tracker).
    fn declare(&self, resources: &Resources, frame: &Frame, tracker: &mut Tracker);
    fn record(&self, rec: &mut Recorder, resources: &Resources);
    /// Whether the pass only (re)builds the sky map, which a frame under the same sky can skip.
    fn builds_sky_map(&self) -> bool {
        false
    }
    /// Whether the pass only builds what depends on the sky alone, not the sun (the atmosphere's
    /// tables), which a frame under the same sky can skip.
    fn builds_for_sky(&self) -> bool {
        false
    }
    /// Whether the pass only builds what depends on the sky and the camera's rays (the aerial
    /// perspective), which a frame under the same sky and view can skip.
    fn builds_for_view(&self) -> bool {
        false
    }
    /// Whether the pass only builds what depends on the sky, the sun and the eye's altitude (the
    /// sky seen from the eye, whichever way it looks), which a frame under the same sky from the
    /// same height can skip.
    fn builds_for_eye(&self) -> bool {
        false
    }
}

/// Points binding `FRAME_BINDING` (and `WAVES_BINDING` with `waves`) at one slot's window of the
/// uniform rings; the slot is chosen by the offsets at bind time.
pub fn write_frame_uniforms(bindings: &Bindings, r: &Resources, waves: bool) {
    let ty = vk::DescriptorType::UNIFORM_BUFFER_DYNAMIC;
    bindings.write_buffer_range(FRAME_BINDING, ty, r.frame_uniforms.buffer.raw, r.frame_uniforms.size);
    if waves {
        bindings.write_buffer_range(WAVES_BINDING, ty, r.waves.buffer.raw, r.waves.size);
    }
}

/// Records a compute pass over an image: binds the pipeline and its set and dispatches one
/// invocation per texel in the shaders' 8 x 8 groups.
pub fn dispatch_over(rec: &Recorder, pipeline: vk::Pipeline, bindings: &Bindings, extent: vk::Extent2D) {
    bind_compute(rec, pipeline, bindings);
    dispatch_texels(rec, extent);
}

/// The push constants of a compute pass over a rectangle of texels (dispatch_within): its origin
/// and its end, two ivec2.
pub const REGION_PUSH_BYTES: u32 = 16;

/// Records a compute pass over the texels of `region` alone: binds the pipeline and its set
/// (made with REGION_PUSH_BYTES of push constants), pushes the region's origin and end, and
/// dispatches one invocation per texel in the shaders' 8 x 8 groups from the origin. Nothing
/// for an empty region.
pub fn dispatch_within(rec: &Recorder, pipeline: vk::Pipeline, bindings: &Bindings, region: PixelRect) {
    if region.is_empty() {
        return;
    }
    bind_compute(rec, pipeline, bindings);
    bindings.push_compute_words(rec.cmd, &[region.x0, region.y0, region.x1, region.y1]);
    dispatch_texels(rec, region.extent());
}

fn bind_compute(rec: &Recorder, pipeline: vk::Pipeline, bindings: &Bindings) {
    // SAFETY: `cmd` is recording outside a rendering scope; the set was made for this pipeline's
    // layout and its resources were declared (and so transitioned) by the calling pass.
    unsafe { rec.device.raw.cmd_bind_pipeline(rec.cmd, vk::PipelineBindPoint::COMPUTE, pipeline) };
    bindings.bind(rec.cmd, vk::PipelineBindPoint::COMPUTE, &rec.frame.uniform_offsets);
}

/// One invocation per texel of `extent`, in 8 x 8 groups, with a compute pipeline bound.
fn dispatch_texels(rec: &Recorder, extent: vk::Extent2D) {
    // SAFETY: as bind_compute's, the pipeline and its set bound by it.
    unsafe { rec.device.raw.cmd_dispatch(rec.cmd, extent.width.div_ceil(8), extent.height.div_ceil(8), 1) };
}

/// A full-screen pipeline writing one colour attachment of `format`, no depth (the tone mappings
/// into a window's or a host's LDR image).
pub fn colour_only_pipeline<'g>(
    device: &'g Device,
    layout: vk::PipelineLayout,
    name: &str,
    fragment: &[u8],
    specialization: &crate::vk::pipeline::Specialization,
    format: vk::Format,
) -> crate::error::Result<crate::vk::owned::Owned<'g, vk::Pipeline>> {
    crate::vk::pipeline::graphics_pipeline(
        device,
        layout,
        &crate::vk::pipeline::GraphicsDesc {
            name,
            vertex: crate::shaders::FULLSCREEN_VERT,
            fragment: Some(fragment),
            specialization: Some(specialization),
            color_format: Some(format),
            depth_format: vk::Format::UNDEFINED,
            depth_write: false,
            depth_compare: vk::CompareOp::ALWAYS,
            depth_bias: None,
            cull_back_faces: None,
        },
    )
}

/// Records a full-screen triangle of `pipeline` (bound with `bindings`) over the whole of
/// `view`, every pixel written (its old contents not loaded).
pub fn draw_over(
    rec: &Recorder,
    pipeline: vk::Pipeline,
    bindings: &Bindings,
    view: vk::ImageView,
    extent: vk::Extent2D,
) {
    let (device, cmd) = (&rec.device.raw, rec.cmd);
    let color = [vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
    let info = vk::RenderingInfo::default().render_area(area).layer_count(1).color_attachments(&color);
    // SAFETY: the caller declared the image COLOR_ATTACHMENT_OPTIMAL and what the set reads; the
    // pipeline was built for the image's format and the set for the pipeline's layout.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[whole_viewport(extent)]);
        device.cmd_set_scissor(cmd, 0, &[area]);
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        bindings.bind(cmd, vk::PipelineBindPoint::GRAPHICS, &rec.frame.uniform_offsets);
        device.cmd_draw(cmd, 3, 1, 0, 0);
        device.cmd_end_rendering(cmd);
    }
}

/// A viewport over a whole attachment of `extent`, depth over [0, 1].
pub fn whole_viewport(extent: vk::Extent2D) -> vk::Viewport {
    vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    }
}
