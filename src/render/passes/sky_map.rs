//! Sky map: level 0 of the stereographic sky texture from Preetham's model, or resampled from the
//! physical sky's sky-view table, raymarched first through the atmosphere's tables (compute); then,
//! in its own pass, the full mip chain by successive linear blits, each level a barrier from the
//! one above.

use super::atmosphere::{declare_raymarch, raymarch_bindings};
use super::eye_sky::SKY_VIEW_BINDING;
use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::ocean::Method;
use crate::render::resources::{Resources, FRAME_BINDING, MEAN_FRESNEL_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, specialized_compute_pipeline, Bindings, Specialization};
use ash::vk;

/// glsl/common.glsl's METHOD.
const METHOD_CONSTANT: u32 = 3;

pub struct SkyMapPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// The physical sky's sky-view table, raymarched first and resampled into the map.
    sky_view: Option<(Bindings<'g>, Owned<'g, vk::Pipeline>)>,
}

impl<'g> SkyMapPass<'g> {
    /// Preetham's sky, or the physical one from the atmosphere's tables where the resources have them;
    /// below the horizon what `method`'s lookups expect there (glsl/sky_map.glsl).
    pub fn new(device: &'g Device, resources: &Resources, method: Method) -> Result<Self> {
        use vk::DescriptorType as D;
        let stages = vk::ShaderStageFlags::COMPUTE;
        let (general, read) = (vk::ImageLayout::GENERAL, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        let mut layout = vec![
            (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, stages),
            (3, D::STORAGE_IMAGE, stages),
            (MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, stages),
        ];
        if resources.atmosphere.is_some() {
            layout.push((4, D::COMBINED_IMAGE_SAMPLER, stages));
        }
        let bindings = Bindings::new(device, "sky map", &layout)?;
        write_frame_uniforms(&bindings, resources, false);
        bindings.write_buffer(MEAN_FRESNEL_BINDING, D::STORAGE_BUFFER, resources.mean_fresnel.raw);
        let sky = &resources.sky_map;
        bindings.write_image(3, D::STORAGE_IMAGE, sky.level0_view, general, vk::Sampler::null());
        let (code, sky_view) = match &resources.atmosphere {
            Some(tables) => {
                bindings.write_image(4, D::COMBINED_IMAGE_SAMPLER, tables.sky_view.view, read, tables.sampler.raw);
                let target = [(SKY_VIEW_BINDING, tables.sky_view.view)];
                let view_bindings = raymarch_bindings(device, "sky view", resources, tables, &target)?;
                let pipeline = compute_pipeline(device, view_bindings.layout(), shaders::SKY_VIEW_COMP, "sky view")?;
                (shaders::SKY_MAP_PHYSICAL_COMP, Some((view_bindings, pipeline)))
            }
            None => (shaders::SKY_MAP_COMP, None),
        };
        let method = Specialization::constants(&[(METHOD_CONSTANT, method as u32)]);
        let pipeline = specialized_compute_pipeline(device, bindings.layout(), code, Some(&method), "sky map")?;
        Ok(SkyMapPass { bindings, pipeline, sky_view })
    }
}

impl Pass for SkyMapPass<'_> {
    fn name(&self) -> &'static str {
        "sky_map"
    }

    fn builds_sky_map(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        if let Some(tables) = &r.atmosphere {
            declare_raymarch(t, r, &[&tables.sky_view]);
        }
        t.image(&r.sky_map, 0, 1, Access::ComputeStorageWrite, true);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        if let (Some((bindings, pipeline)), Some(tables)) = (&self.sky_view, &r.atmosphere) {
            dispatch_over(rec, pipeline.raw, bindings, tables.sky_view.extent);
            // The map samples the table just written.
            rec.tracker.image(&tables.sky_view, 0, 1, Access::ComputeSampled, false);
            rec.tracker.flush(&rec.device.raw, rec.cmd);
        }
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.sky_map.extent);
    }
}

/// The sky map's mip chain, each level blitted (linear filter) from the one above.
pub struct SkyMipsPass;

impl Pass for SkyMipsPass {
    fn name(&self) -> &'static str {
        "sky_mips"
    }

    fn builds_sky_map(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        // Level by level in `record`: each blit reads the level the previous one wrote.
        t.image(&r.sky_map, 0, 1, Access::TransferRead, false);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        let sky = &r.sky_map;
        crate::vk::image::mipmap(device, cmd, rec.tracker, sky);
    }
}
