//! Every GPU resource of a frame, created once for an image size and torn down in reverse.

use crate::error::{Error, Result, VkContext};
use crate::frame::{FrameUniforms, GpuWaves};
use crate::vk::buffer::Buffer;
use crate::vk::device::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use crate::vk::memory::Location;
use ash::vk;

/// Sky map resolution (texels per side) and thus mip levels: log2(512) + 1.
pub const SKY_MAP_SIZE: u32 = 512;

pub struct Resources {
    pub frame_uniforms: Buffer,
    pub waves: Buffer,
    /// Triangle list of the current grid, grown when a larger grid is needed.
    pub grid_indices: Option<Buffer>,
    pub sky_map: Image,
    pub sky_sampler: vk::Sampler,
    pub hdr: Image,
    pub depth: Image,
    pub hdr_readback: Buffer,
    pub ldr_readback: Buffer,
    /// Indices of the current grid layout (rewritten when the layout changes).
    pub grid_index_count: u32,
    pub grid_layout: Option<(u32, u32)>,
}

impl Resources {
    pub fn new(gpu: &Gpu, width: u32, height: u32, anisotropy: f32) -> Result<Resources> {
        let limit = gpu.device.properties.limits.max_image_dimension2_d;
        if width == 0 || height == 0 || width > limit || height > limit {
            return Err(Error::Argument(format!(
                "image size {width}x{height} is out of range [1, {limit}] per side on {}",
                gpu.device.name
            )));
        }
        let extent = vk::Extent2D { width, height };
        let pixels = width as u64 * height as u64;
        use vk::BufferUsageFlags as B;
        use vk::ImageUsageFlags as I;
        let frame_uniforms = Buffer::new(
            gpu,
            "frame uniforms",
            std::mem::size_of::<FrameUniforms>() as u64,
            B::UNIFORM_BUFFER,
            Location::Upload,
        )?;
        let waves = Buffer::new(
            gpu,
            "wave trains",
            std::mem::size_of::<GpuWaves>() as u64,
            B::UNIFORM_BUFFER,
            Location::Upload,
        )?;
        let sky_extent = vk::Extent2D { width: SKY_MAP_SIZE, height: SKY_MAP_SIZE };
        let sky_levels = SKY_MAP_SIZE.ilog2() + 1;
        let sky_map = Image::new(
            gpu,
            "sky map",
            HDR_FORMAT,
            sky_extent,
            sky_levels,
            I::STORAGE | I::SAMPLED | I::TRANSFER_SRC | I::TRANSFER_DST,
        )?;
        let hdr =
            Image::new(gpu, "hdr radiance", HDR_FORMAT, extent, 1, I::COLOR_ATTACHMENT | I::STORAGE | I::TRANSFER_SRC)?;
        let depth = Image::new(gpu, "depth", DEPTH_FORMAT, extent, 1, I::DEPTH_STENCIL_ATTACHMENT)?;
        let hdr_readback = Buffer::new(gpu, "hdr readback", pixels * 8, B::TRANSFER_DST, Location::Readback)?;
        let ldr_readback = Buffer::new(gpu, "ldr readback", pixels * 4, B::STORAGE_BUFFER, Location::Readback)?;
        let anisotropic = anisotropy > 1.0 && gpu.device.anisotropy;
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .anisotropy_enable(anisotropic)
            .max_anisotropy(if anisotropic {
                anisotropy.min(gpu.device.properties.limits.max_sampler_anisotropy)
            } else {
                1.0
            })
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid create info; anisotropy only when the feature was enabled.
        let sky_sampler = unsafe { gpu.raw().create_sampler(&sampler_info, None) }.during("vkCreateSampler")?;
        gpu.device.set_name(sky_sampler, "sky map sampler");
        Ok(Resources {
            frame_uniforms,
            waves,
            grid_indices: None,
            sky_map,
            sky_sampler,
            hdr,
            depth,
            hdr_readback,
            ldr_readback,
            grid_index_count: 0,
            grid_layout: None,
        })
    }

    /// Writes the triangle list of a columns x rows grid (row-major nodes) if it changed. Called
    /// between frames (the previous frame's fence waited), so the buffer may be replaced.
    pub fn set_grid(&mut self, gpu: &Gpu, columns: u32, rows: u32) -> Result<()> {
        if self.grid_layout == Some((columns, rows)) {
            return Ok(());
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
            if let Some(old) = self.grid_indices.take() {
                old.destroy(gpu);
            }
            let usage = vk::BufferUsageFlags::INDEX_BUFFER;
            self.grid_indices = Some(Buffer::new(gpu, "grid indices", bytes, usage, Location::Upload)?);
        }
        if let Some(buffer) = &self.grid_indices {
            buffer.write(gpu, &indices)?;
        }
        self.grid_index_count = indices.len() as u32;
        self.grid_layout = Some((columns, rows));
        Ok(())
    }

    pub fn destroy(self, gpu: &Gpu) {
        // SAFETY: the device is idle.
        unsafe { gpu.raw().destroy_sampler(self.sky_sampler, None) };
        self.ldr_readback.destroy(gpu);
        self.hdr_readback.destroy(gpu);
        self.depth.destroy(gpu);
        self.hdr.destroy(gpu);
        self.sky_map.destroy(gpu);
        if let Some(buffer) = self.grid_indices {
            buffer.destroy(gpu);
        }
        self.waves.destroy(gpu);
        self.frame_uniforms.destroy(gpu);
    }
}
