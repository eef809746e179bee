//! Models onto the GPU: each model's vertices (pulled by index in glsl/object.vert) and indices
//! in device-local buffers, its textures as mipmapped images, all through one staging buffer and
//! one submission, left in the states the object pass reads them in.

use crate::error::Result;
use crate::model::gltf::{Material, Model};
use crate::vk::barrier::{Access, Tracker};
use crate::vk::buffer::Buffer;
use crate::vk::commands::Commands;
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use crate::vk::memory::Location;
use ash::vk;

/// glsl/object.glsl's `Vertex`: position and u, normal and v, tangent and the bitangent's sign.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct GpuVertex {
    pub position_u: [f32; 4],
    pub normal_v: [f32; 4],
    pub tangent: [f32; 4],
}

/// One draw: a mesh's indices in its model's index buffer.
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
    pub material: usize,
}

/// A model on the GPU.
pub struct GpuModel<'g> {
    pub vertices: Buffer<'g>,
    pub indices: Buffer<'g>,
    /// Each material's textures: base colour (sRGB) and normal map (linear), None for the
    /// object pass's stand-ins.
    pub material_textures: Vec<(Option<usize>, Option<usize>)>,
    pub textures: Vec<Image<'g>>,
    pub draws: Vec<Draw>,
    pub materials: Vec<Material>,
}

/// The texel formats: base colours are stored sRGB-encoded (glTF's rule), normal maps linear.
pub const BASE_COLOUR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
pub const NORMAL_MAP_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

fn mip_levels(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// Uploads `models` and `stand_ins` (1x1 texels: (rgba, format)) in one submission; returns the
/// models and the stand-in images.
pub fn upload<'g>(
    gpu: &'g Gpu,
    models: &[std::sync::Arc<Model>],
    stand_ins: &[([u8; 4], vk::Format)],
) -> Result<(Vec<GpuModel<'g>>, Vec<Image<'g>>)> {
    let mut staged: Vec<u8> = Vec::new();
    let stage = |staged: &mut Vec<u8>, bytes: &[u8]| {
        // Copies from a buffer to an image need offsets that are multiples of the texel size (4).
        while staged.len() % 16 != 0 {
            staged.push(0);
        }
        let offset = staged.len() as u64;
        staged.extend_from_slice(bytes);
        offset
    };
    struct Pending {
        vertices: u64,
        indices: u64,
        textures: Vec<u64>,
    }
    let mut gpu_models = Vec::new();
    let mut pending = Vec::new();
    for model in models {
        let name = model.file.file_name().map_or_else(|| "model".into(), |n| n.to_string_lossy().into_owned());
        let mut vertices = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut draws = Vec::new();
        for mesh in &model.meshes {
            draws.push(Draw {
                first_index: indices.len() as u32,
                index_count: mesh.indices.len() as u32,
                vertex_offset: vertices.len() as i32,
                material: mesh.material,
            });
            indices.extend_from_slice(&mesh.indices);
            for (i, (p, n)) in mesh.positions.iter().zip(&mesh.normals).enumerate() {
                let [u, v] = mesh.uvs[i];
                let tangent = mesh.tangents.as_ref().map_or([0.0; 4], |t| t[i]);
                vertices.push(GpuVertex { position_u: [p.x, p.y, p.z, u], normal_v: [n.x, n.y, n.z, v], tangent });
            }
        }
        let vertex_bytes = as_bytes(&vertices);
        let index_bytes = as_bytes(&indices);
        use vk::BufferUsageFlags as B;
        let vertex_buffer = Buffer::new(
            gpu,
            &format!("{name} vertices"),
            vertex_bytes.len() as u64,
            B::STORAGE_BUFFER | B::TRANSFER_DST,
            Location::Gpu,
        )?;
        let index_buffer = Buffer::new(
            gpu,
            &format!("{name} indices"),
            index_bytes.len() as u64,
            B::INDEX_BUFFER | B::TRANSFER_DST,
            Location::Gpu,
        )?;
        // A texture takes the format of its first use; glTF's files do not share one between a
        // base colour and a normal map.
        let mut formats: Vec<Option<vk::Format>> = vec![None; model.textures.len()];
        for m in &model.materials {
            if let Some(t) = m.base_colour_texture {
                formats[t].get_or_insert(BASE_COLOUR_FORMAT);
            }
            if let Some((t, _)) = m.normal_texture {
                formats[t].get_or_insert(NORMAL_MAP_FORMAT);
            }
        }
        let mut textures = Vec::new();
        let mut texture_offsets = Vec::new();
        for (i, (texture, format)) in model.textures.iter().zip(&formats).enumerate() {
            let format = format.unwrap_or(BASE_COLOUR_FORMAT);
            let extent = vk::Extent2D { width: texture.width, height: texture.height };
            use vk::ImageUsageFlags as I;
            let usage = I::SAMPLED | I::TRANSFER_DST | I::TRANSFER_SRC;
            let levels = mip_levels(texture.width, texture.height);
            textures.push(Image::new(gpu, &format!("{name} texture {i}"), format, extent, levels, usage)?);
            texture_offsets.push(stage(&mut staged, &texture.rgba));
        }
        pending.push(Pending {
            vertices: stage(&mut staged, vertex_bytes),
            indices: stage(&mut staged, index_bytes),
            textures: texture_offsets,
        });
        let material_textures =
            model.materials.iter().map(|m| (m.base_colour_texture, m.normal_texture.map(|(t, _)| t))).collect();
        gpu_models.push(GpuModel {
            vertices: vertex_buffer,
            indices: index_buffer,
            material_textures,
            textures,
            draws,
            materials: model.materials.clone(),
        });
    }
    let mut stand_in_images = Vec::new();
    let mut stand_in_offsets = Vec::new();
    for (i, (rgba, format)) in stand_ins.iter().enumerate() {
        let usage = vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let extent = vk::Extent2D { width: 1, height: 1 };
        stand_in_images.push(Image::new(gpu, &format!("object stand-in texture {i}"), *format, extent, 1, usage)?);
        stand_in_offsets.push(stage(&mut staged, rgba));
    }
    let staging = Buffer::new(
        gpu,
        "object upload staging",
        staged.len().max(4) as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        Location::Upload,
    )?;
    staging.write(&staged)?;

    let commands = Commands::new(&gpu.device, "object upload")?;
    let (device, cmd) = (&gpu.device.raw, commands.cmd);
    let mut tracker = Tracker::default();
    commands.begin()?;
    tracker.buffer(&staging, Access::TransferRead);
    for (model, p) in gpu_models.iter().zip(&pending) {
        tracker.buffer(&model.vertices, Access::TransferWrite);
        tracker.buffer(&model.indices, Access::TransferWrite);
        for texture in &model.textures {
            tracker.image(texture, 0, 1, Access::TransferWrite, true);
        }
        tracker.flush(device, cmd);
        copy_buffer(device, cmd, &staging, p.vertices, &model.vertices);
        copy_buffer(device, cmd, &staging, p.indices, &model.indices);
        for (texture, &offset) in model.textures.iter().zip(&p.textures) {
            copy_to_image(device, cmd, &staging, offset, texture);
        }
    }
    for (image, &offset) in stand_in_images.iter().zip(&stand_in_offsets) {
        tracker.image(image, 0, 1, Access::TransferWrite, true);
        tracker.flush(device, cmd);
        copy_to_image(device, cmd, &staging, offset, image);
    }
    for model in &gpu_models {
        for texture in &model.textures {
            crate::vk::image::mipmap(device, cmd, &mut tracker, texture);
        }
        // Later frames read them: the barriers' second scope covers later submissions too.
        tracker.buffer(&model.vertices, Access::VertexStorageRead);
        tracker.buffer(&model.indices, Access::IndexRead);
        for texture in &model.textures {
            tracker.image(texture, 0, texture.mip_levels, Access::FragmentSampled, false);
        }
    }
    for image in &stand_in_images {
        tracker.image(image, 0, 1, Access::FragmentSampled, false);
    }
    tracker.flush(device, cmd);
    commands.submit_and_wait()?;
    Ok((gpu_models, stand_in_images))
}

fn as_bytes<T: Copy>(data: &[T]) -> &[u8] {
    // SAFETY: T is plain old data (f32 and u32 fields, repr(C) without padding).
    unsafe { std::slice::from_raw_parts(data.as_ptr() as *const u8, std::mem::size_of_val(data)) }
}

fn copy_buffer(device: &ash::Device, cmd: vk::CommandBuffer, staging: &Buffer, offset: u64, to: &Buffer) {
    let region = [vk::BufferCopy { src_offset: offset, dst_offset: 0, size: to.size }];
    // SAFETY: both buffers are live and in transfer states (barriers flushed); the region lies
    // inside both (the staging buffer holds these bytes at `offset`).
    unsafe { device.cmd_copy_buffer(cmd, staging.raw, to.raw, &region) };
}

fn copy_to_image(device: &ash::Device, cmd: vk::CommandBuffer, staging: &Buffer, offset: u64, to: &Image) {
    let mut region = [crate::vk::image::level0_region(to.extent, offset)];
    region[0].image_subresource.aspect_mask = to.aspect;
    // SAFETY: level 0 is in TRANSFER_DST_OPTIMAL (flushed above); the staging buffer holds
    // width x height texels of 4 bytes (RGBA8, or a 32-bit depth) at `offset`, a multiple of 4.
    unsafe {
        device.cmd_copy_buffer_to_image(cmd, staging.raw, to.raw, vk::ImageLayout::TRANSFER_DST_OPTIMAL, &region)
    };
}
