//! A pyramid whose levels a compute shader reduces one from the other, one dispatch per level:
//! the objects' nearest-depth pyramid (glsl/reflection_depth_mip.comp) and the mirror's coverage
//! and inverse depth (glsl/planar_mip.comp). The shader reads the finer level at binding 0 and
//! writes the coarser at binding 1, both storage images.

use super::{dispatch_over, Recorder};
use crate::error::Result;
use crate::vk::barrier::Access;
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

pub struct LevelReduction<'g> {
    /// Per level from 1: finer level in, coarser out.
    levels: Vec<Bindings<'g>>,
    /// None for a single-level image, which has nothing to reduce.
    pipeline: Option<Owned<'g, vk::Pipeline>>,
}

impl<'g> LevelReduction<'g> {
    /// The reduction by `spirv` of the image whose level views are `level_views` (one per level).
    pub fn new(device: &'g Device, level_views: &[Owned<'_, vk::ImageView>], spirv: &[u8], name: &str) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let general = vk::ImageLayout::GENERAL;
        let levels = level_views
            .windows(2)
            .map(|pair| {
                let b = Bindings::new(device, name, &[(0, D::STORAGE_IMAGE, compute), (1, D::STORAGE_IMAGE, compute)])?;
                b.write_image(0, D::STORAGE_IMAGE, pair[0].raw, general, vk::Sampler::null());
                b.write_image(1, D::STORAGE_IMAGE, pair[1].raw, general, vk::Sampler::null());
                Ok(b)
            })
            .collect::<Result<Vec<_>>>()?;
        let pipeline = levels.first().map(|b| compute_pipeline(device, b.layout(), spirv, name)).transpose()?;
        Ok(LevelReduction { levels, pipeline })
    }

    /// Writes every level of `image` from 1 on from the one above it (level 0 written already).
    pub fn record(&self, rec: &mut Recorder, image: &Image) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        for (i, (bindings, pipeline)) in self.levels.iter().zip(self.pipeline.iter().cycle()).enumerate() {
            let level = i as u32 + 1;
            rec.tracker.image(image, level - 1, 1, Access::ComputeStorageRead, false);
            rec.tracker.image(image, level, 1, Access::ComputeStorageWrite, true);
            rec.tracker.flush(device, cmd);
            let extent = vk::Extent2D {
                width: (image.extent.width >> level).max(1),
                height: (image.extent.height >> level).max(1),
            };
            dispatch_over(rec, pipeline.raw, bindings, extent);
        }
    }
}
