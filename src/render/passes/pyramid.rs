//! A pyramid whose levels a compute shader reduces one from the other, one dispatch per level:
//! the objects' nearest-depth pyramid (glsl/reflection_depth_mip.comp) and the mirror's coverage
//! and inverse depth (glsl/planar_mip.comp). The shader reads the finer level at binding 0 and
//! writes the coarser at binding 1, both storage images, over the texels of a rectangle that its
//! push constants give (origin, end), REGION_PUSH_BYTES.

use super::{dispatch_within, Recorder, REGION_PUSH_BYTES};
use crate::error::Result;
use crate::vk::barrier::Access;
use crate::vk::device::Device;
use crate::vk::image::{level_extent, Image, PixelRect};
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
                let images = [(0, D::STORAGE_IMAGE, compute), (1, D::STORAGE_IMAGE, compute)];
                let b = Bindings::with_push_constants(device, name, &images, REGION_PUSH_BYTES)?;
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
        self.record_within(rec, image, PixelRect::whole(image.extent));
    }

    /// As `record`, over the texels that level 0's rectangle `within` covers on each level alone:
    /// the rest of each level keeps what it holds.
    pub fn record_within(&self, rec: &mut Recorder, image: &Image, within: PixelRect) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        for (i, (bindings, pipeline)) in self.levels.iter().zip(self.pipeline.iter().cycle()).enumerate() {
            let level = i as u32 + 1;
            let region = within.at_level(level, image.extent);
            let whole = region == PixelRect::whole(level_extent(image.extent, level));
            rec.tracker.image(image, level - 1, 1, Access::ComputeStorageRead, false);
            rec.tracker.image(image, level, 1, Access::ComputeStorageWrite, whole);
            rec.tracker.flush(device, cmd);
            dispatch_within(rec, pipeline.raw, bindings, region);
        }
    }
}
