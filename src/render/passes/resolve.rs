//! Supersampling resolve: box-averages K x K samples of the HDR radiance into the output image
//! (compute). Only in the frame when supersampling is asked for.

use super::{dispatch_over, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::Resources;
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

pub struct ResolvePass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> ResolvePass<'g> {
    pub fn new(device: &'g Device, samples: &Image, resolved: &Image) -> Result<Self> {
        use vk::DescriptorType as D;
        let stages = vk::ShaderStageFlags::COMPUTE;
        let bindings =
            Bindings::new(device, "resolve", &[(6, D::STORAGE_IMAGE, stages), (7, D::STORAGE_IMAGE, stages)])?;
        bindings.write_image(6, D::STORAGE_IMAGE, samples.view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        bindings.write_image(7, D::STORAGE_IMAGE, resolved.view, vk::ImageLayout::GENERAL, vk::Sampler::null());
        let pipeline = compute_pipeline(device, bindings.layout(), shaders::RESOLVE_COMP, "resolve")?;
        Ok(ResolvePass { bindings, pipeline })
    }
}

impl Pass for ResolvePass<'_> {
    fn name(&self) -> &'static str {
        "resolve"
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        t.image(&r.hdr, 0, 1, Access::ComputeStorageRead, false);
        t.image(r.output(), 0, 1, Access::ComputeStorageWrite, true);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.output().extent);
    }
}
