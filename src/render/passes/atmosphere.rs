//! The physical atmosphere's tables (compute): transmittance, then Hillaire's multiple
//! scattering from it; rebuilt with the sky map, only when the sun or the sky changes.

use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{AtmosphereTables, Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

/// Bindings of the tables: written at 3, the transmittance read at 4 (glsl/transmittance.comp,
/// multiple_scattering.comp).
const TABLE_BINDING: u32 = 3;
const TRANSMITTANCE_BINDING: u32 = 4;

pub struct AtmospherePass<'g> {
    transmittance_bindings: Bindings<'g>,
    transmittance: Owned<'g, vk::Pipeline>,
    multiple_bindings: Bindings<'g>,
    multiple: Owned<'g, vk::Pipeline>,
}

impl<'g> AtmospherePass<'g> {
    pub fn new(device: &'g Device, r: &Resources, tables: &AtmosphereTables) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let storage = |b: &Bindings, view| {
            b.write_image(TABLE_BINDING, D::STORAGE_IMAGE, view, vk::ImageLayout::GENERAL, vk::Sampler::null())
        };
        let transmittance_bindings = Bindings::new(
            device,
            "atmosphere transmittance",
            &[(FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute), (TABLE_BINDING, D::STORAGE_IMAGE, compute)],
        )?;
        write_frame_uniforms(&transmittance_bindings, r, false);
        storage(&transmittance_bindings, tables.transmittance.view);
        let multiple_bindings = Bindings::new(
            device,
            "atmosphere multiple scattering",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (TABLE_BINDING, D::STORAGE_IMAGE, compute),
                (TRANSMITTANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
            ],
        )?;
        write_frame_uniforms(&multiple_bindings, r, false);
        storage(&multiple_bindings, tables.multiple_scattering.view);
        multiple_bindings.write_image(
            TRANSMITTANCE_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            tables.transmittance.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            tables.sampler.raw,
        );
        let transmittance = compute_pipeline(
            device,
            transmittance_bindings.layout(),
            shaders::TRANSMITTANCE_COMP,
            "atmosphere transmittance",
        )?;
        let multiple = compute_pipeline(
            device,
            multiple_bindings.layout(),
            shaders::MULTIPLE_SCATTERING_COMP,
            "atmosphere multiple scattering",
        )?;
        Ok(AtmospherePass { transmittance_bindings, transmittance, multiple_bindings, multiple })
    }
}

impl Pass for AtmospherePass<'_> {
    fn name(&self) -> &'static str {
        "atmosphere"
    }

    fn builds_sky_map(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        let tables = r.atmosphere.as_ref().expect("made with the physical sky");
        t.image(&tables.transmittance, 0, 1, Access::ComputeStorageWrite, true);
        t.image(&tables.multiple_scattering, 0, 1, Access::ComputeStorageWrite, true);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let tables = r.atmosphere.as_ref().expect("made with the physical sky");
        dispatch_over(rec, self.transmittance.raw, &self.transmittance_bindings, tables.transmittance.extent);
        // The multiple scattering samples the transmittance just written.
        rec.tracker.image(&tables.transmittance, 0, 1, Access::ComputeSampled, false);
        rec.tracker.flush(&rec.device.raw, rec.cmd);
        dispatch_over(rec, self.multiple.raw, &self.multiple_bindings, tables.multiple_scattering.extent);
    }
}
