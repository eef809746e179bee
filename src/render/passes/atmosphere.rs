//! The physical atmosphere's tables (compute): transmittance, then Hillaire's multiple
//! scattering from it, then the sea-level sky irradiance over the sun's elevation from both,
//! rebuilt only when the sky (the air, not the sun) changes; and the
//! aerial perspective between the eye and the sea, every frame (the eye moves).

use super::{dispatch_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{AtmosphereTables, Resources, AERIAL_SIZE, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;

/// Bindings of the tables: written at 3, the transmittance read at 4 (glsl/transmittance.comp,
/// multiple_scattering.comp).
const TABLE_BINDING: u32 = 3;
const TRANSMITTANCE_BINDING: u32 = 4;
const MULTIPLE_SCATTERING_BINDING: u32 = 5;

pub struct AtmospherePass<'g> {
    transmittance_bindings: Bindings<'g>,
    transmittance: Owned<'g, vk::Pipeline>,
    multiple_bindings: Bindings<'g>,
    multiple: Owned<'g, vk::Pipeline>,
    /// The sea-level sky irradiance over the sun's zenith cosine, from both tables.
    irradiance_bindings: Bindings<'g>,
    irradiance: Owned<'g, vk::Pipeline>,
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
        let irradiance_bindings = raymarch_bindings(
            device,
            "atmosphere sea irradiance",
            r,
            tables,
            &[(TABLE_BINDING, tables.sea_irradiance.view)],
        )?;
        let irradiance = compute_pipeline(
            device,
            irradiance_bindings.layout(),
            shaders::SEA_IRRADIANCE_COMP,
            "atmosphere sea irradiance",
        )?;
        Ok(AtmospherePass {
            transmittance_bindings,
            transmittance,
            multiple_bindings,
            multiple,
            irradiance_bindings,
            irradiance,
        })
    }
}

impl Pass for AtmospherePass<'_> {
    fn name(&self) -> &'static str {
        "atmosphere"
    }

    /// The tables hold the air, not the sun's light: a moving sun keeps them.
    fn builds_for_sky(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        let tables = r.atmosphere.as_ref().expect("made with the physical sky");
        t.image(&tables.transmittance, 0, 1, Access::ComputeStorageWrite, true);
        t.image(&tables.multiple_scattering, 0, 1, Access::ComputeStorageWrite, true);
        t.image(&tables.sea_irradiance, 0, 1, Access::ComputeStorageWrite, true);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let tables = r.atmosphere.as_ref().expect("made with the physical sky");
        dispatch_over(rec, self.transmittance.raw, &self.transmittance_bindings, tables.transmittance.extent);
        // The multiple scattering samples the transmittance just written.
        rec.tracker.image(&tables.transmittance, 0, 1, Access::ComputeSampled, false);
        rec.tracker.flush(&rec.device.raw, rec.cmd);
        dispatch_over(rec, self.multiple.raw, &self.multiple_bindings, tables.multiple_scattering.extent);
        // The irradiance raymarches through both.
        rec.tracker.image(&tables.multiple_scattering, 0, 1, Access::ComputeSampled, false);
        rec.tracker.flush(&rec.device.raw, rec.cmd);
        // SEA_IRRADIANCE_SIZE texels as 32 x 8 invocations (glsl/sea_irradiance.comp).
        let extent = vk::Extent2D { width: 32, height: crate::model::atmosphere::SEA_IRRADIANCE_SIZE as u32 / 32 };
        dispatch_over(rec, self.irradiance.raw, &self.irradiance_bindings, extent);
    }
}

/// The aerial perspective atlases (glsl/aerial_perspective.comp), from the tables.
pub struct AerialPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> AerialPass<'g> {
    pub fn new(device: &'g Device, r: &Resources, tables: &AtmosphereTables) -> Result<Self> {
        let outputs = [(TABLE_BINDING, r.aerial_inscatter.view), (6, r.aerial_transmittance.view)];
        let bindings = raymarch_bindings(device, "aerial perspective", r, tables, &outputs)?;
        let pipeline =
            compute_pipeline(device, bindings.layout(), shaders::AERIAL_PERSPECTIVE_COMP, "aerial perspective")?;
        Ok(AerialPass { bindings, pipeline })
    }
}

/// The bindings of a pass that raymarches the air through both tables (glsl/atmosphere.glsl's
/// TRANSMITTANCE_TABLE at 4, MULTIPLE_SCATTERING_TABLE at 5) into storage images at `outputs`.
pub fn raymarch_bindings<'g>(
    device: &'g Device,
    name: &str,
    r: &Resources,
    tables: &AtmosphereTables,
    outputs: &[(u32, vk::ImageView)],
) -> Result<Bindings<'g>> {
    use vk::DescriptorType as D;
    let compute = vk::ShaderStageFlags::COMPUTE;
    let mut layout = vec![
        (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
        (TRANSMITTANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
        (MULTIPLE_SCATTERING_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
    ];
    layout.extend(outputs.iter().map(|&(binding, _)| (binding, D::STORAGE_IMAGE, compute)));
    let bindings = Bindings::new(device, name, &layout)?;
    write_frame_uniforms(&bindings, r, false);
    let (general, read) = (vk::ImageLayout::GENERAL, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
    let sampler = tables.sampler.raw;
    bindings.write_image(TRANSMITTANCE_BINDING, D::COMBINED_IMAGE_SAMPLER, tables.transmittance.view, read, sampler);
    let ms = tables.multiple_scattering.view;
    bindings.write_image(MULTIPLE_SCATTERING_BINDING, D::COMBINED_IMAGE_SAMPLER, ms, read, sampler);
    for &(binding, view) in outputs {
        bindings.write_image(binding, D::STORAGE_IMAGE, view, general, vk::Sampler::null());
    }
    Ok(bindings)
}

/// Declares a raymarching pass's accesses: both tables sampled, `outputs` written whole.
pub fn declare_raymarch(t: &mut Tracker, r: &Resources, outputs: &[&Image]) {
    let tables = r.atmosphere.as_ref().expect("made with the physical sky");
    t.image(&tables.transmittance, 0, 1, Access::ComputeSampled, false);
    t.image(&tables.multiple_scattering, 0, 1, Access::ComputeSampled, false);
    for image in outputs {
        t.image(*image, 0, 1, Access::ComputeStorageWrite, true);
    }
}

impl Pass for AerialPass<'_> {
    fn name(&self) -> &'static str {
        "aerial_perspective"
    }

    fn builds_for_view(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        declare_raymarch(t, r, &[&r.aerial_inscatter, &r.aerial_transmittance]);
    }

    fn record(&self, rec: &mut Recorder, _r: &Resources) {
        // One invocation per ray; each writes its AERIAL_SIZE slices.
        dispatch_over(rec, self.pipeline.raw, &self.bindings, vk::Extent2D { width: AERIAL_SIZE, height: AERIAL_SIZE });
    }
}
