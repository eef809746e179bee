//! Every GPU resource of a frame, created once for an image size; each releases itself when
//! dropped (also when a later one fails to be created).

use crate::error::{Error, Result, VkContext};
use crate::render::frame::{FrameUniforms, GpuWaves};
use crate::vk::buffer::Buffer;
use crate::vk::device::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use ash::vk;

/// Sky map resolution (texels per side) and thus mip levels: log2(512) + 1.
pub const SKY_MAP_SIZE: u32 = 512;
/// Most grid nodes a frame may draw: 2^24 nodes need 400 MB of indices; finer grids are an error.
pub const MAX_GRID_NODES: u64 = 1 << 24;

pub struct Resources<'g> {
    gpu: &'g Gpu,
    pub frame_uniforms: Buffer<'g>,
    pub waves: Buffer<'g>,
    /// Triangle list of the current grid, grown when a larger grid is needed.
    pub grid_indices: Option<Buffer<'g>>,
    pub sky_map: Image<'g>,
    pub sky_sampler: Owned<'g, vk::Sampler>,
    /// HDR radiance at the rendering size (the output size times the supersampling factor).
    pub hdr: Image<'g>,
    pub depth: Image<'g>,
    /// With supersampling, the resolved HDR radiance at the output size.
    pub resolved: Option<Image<'g>>,
    pub hdr_readback: Buffer<'g>,
    pub ldr_readback: Buffer<'g>,
    /// Indices of the current grid layout (rewritten when the layout changes).
    pub grid_index_count: u32,
    pub grid_layout: Option<(u32, u32)>,
}

impl<'g> Resources<'g> {
    /// Resources for `width` x `height` output images rendered with `ssaa` x `ssaa` samples per pixel.
    pub fn new(gpu: &'g Gpu, width: u32, height: u32, ssaa: u32, sky_map: bool, anisotropy: f32) -> Result<Self> {
        let limits = &gpu.device.properties.limits;
        let side = limits.max_image_dimension2_d;
        if width == 0 || height == 0 || width > side || height > side {
            return Err(Error::Argument(format!(
                "image size {width}x{height} is out of range [1, {side}] per side on {}",
                gpu.device.name
            )));
        }
        let (render_w, render_h) = (width as u64 * ssaa as u64, height as u64 * ssaa as u64);
        if ssaa == 0 || render_w > side as u64 || render_h > side as u64 {
            return Err(Error::Argument(format!(
                "supersampling {ssaa}x{ssaa} of {width}x{height} needs {render_w}x{render_h}; {} allows {side} per side",
                gpu.device.name
            )));
        }
        let render_extent = vk::Extent2D { width: render_w as u32, height: render_h as u32 };
        let pixels = width as u64 * height as u64;
        // The tone-mapped pixels are one storage buffer.
        if 4 * pixels > limits.max_storage_buffer_range as u64 {
            return Err(Error::Argument(format!(
                "image size {width}x{height} needs a {} MiB storage buffer; {} allows {} MiB",
                (4 * pixels) >> 20,
                gpu.device.name,
                limits.max_storage_buffer_range >> 20
            )));
        }
        let extent = vk::Extent2D { width, height };
        use vk::BufferUsageFlags as B;
        use vk::ImageUsageFlags as I;
        let uniforms_size = std::mem::size_of::<FrameUniforms>() as u64;
        let frame_uniforms = Buffer::new(gpu, "frame uniforms", uniforms_size, B::UNIFORM_BUFFER, Location::Upload)?;
        let waves_size = std::mem::size_of::<GpuWaves>() as u64;
        let waves = Buffer::new(gpu, "wave trains", waves_size, B::UNIFORM_BUFFER, Location::Upload)?;
        // Without the sky term nothing samples the map: a 1x1 placeholder keeps its binding valid.
        let sky_size = if sky_map { SKY_MAP_SIZE } else { 1 };
        let sky_extent = vk::Extent2D { width: sky_size, height: sky_size };
        let sky_usage = I::STORAGE | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST;
        let sky_map = Image::new(gpu, "sky map", HDR_FORMAT, sky_extent, sky_size.ilog2() + 1, sky_usage)?;
        let hdr_usage = I::COLOR_ATTACHMENT | I::STORAGE | I::TRANSFER_SRC;
        let hdr = Image::new(gpu, "hdr radiance", HDR_FORMAT, render_extent, 1, hdr_usage)?;
        let depth = Image::new(gpu, "depth", DEPTH_FORMAT, render_extent, 1, I::DEPTH_STENCIL_ATTACHMENT)?;
        let resolved = if ssaa > 1 {
            Some(Image::new(gpu, "hdr resolved", HDR_FORMAT, extent, 1, I::STORAGE | I::TRANSFER_SRC)?)
        } else {
            None
        };
        let hdr_readback = Buffer::new(gpu, "hdr readback", pixels * 8, B::TRANSFER_DST, Location::Readback)?;
        let ldr_readback = Buffer::new(gpu, "ldr readback", pixels * 4, B::STORAGE_BUFFER, Location::Readback)?;
        let anisotropic = anisotropy > 1.0 && gpu.device.anisotropy;
        let max_anisotropy = if anisotropic { anisotropy.min(limits.max_sampler_anisotropy) } else { 1.0 };
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .anisotropy_enable(anisotropic)
            .max_anisotropy(max_anisotropy)
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid create info; anisotropy only when the feature was enabled.
        let sky_sampler = unsafe { gpu.raw().create_sampler(&sampler_info, None) }.during("vkCreateSampler")?;
        Ok(Resources {
            gpu,
            frame_uniforms,
            waves,
            grid_indices: None,
            sky_map,
            sky_sampler: Owned::new(&gpu.device, sky_sampler, "sky map sampler"),
            hdr,
            depth,
            resolved,
            hdr_readback,
            ldr_readback,
            grid_index_count: 0,
            grid_layout: None,
        })
    }

    /// The HDR radiance at the output size: the resolved image with supersampling, else `hdr`.
    pub fn output(&self) -> &Image<'g> {
        self.resolved.as_ref().unwrap_or(&self.hdr)
    }

    /// Writes the triangle list of a columns x rows grid (row-major nodes) if it changed. Called
    /// between frames (the previous frame's fence waited), so the buffer may be replaced.
    pub fn set_grid(&mut self, columns: u32, rows: u32) -> Result<()> {
        if self.grid_layout == Some((columns, rows)) {
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
        if self.grid_indices.as_ref().is_none_or(|b| b.size < bytes) {
            self.grid_indices = None; // free the old buffer before placing the larger one
            let usage = vk::BufferUsageFlags::INDEX_BUFFER;
            self.grid_indices = Some(Buffer::new(self.gpu, "grid indices", bytes, usage, Location::Upload)?);
        }
        if let Some(buffer) = &self.grid_indices {
            buffer.write(&indices)?;
        }
        self.grid_index_count = indices.len() as u32;
        self.grid_layout = Some((columns, rows));
        Ok(())
    }
}
