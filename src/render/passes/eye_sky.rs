//! The sky seen from the eye (compute): glsl/sky_view.comp specialized EYE_VIEW, raymarched from
//! the eye's altitude over what it sees of the sky, from the planet's limb up (or, from outside the
//! air, up to the air's own limb), for the sky seen directly (the sky map holds the sky seen from
//! the sea). Rebuilt when the sky, the sun or the eye's height changes, not when the eye only turns.

use super::atmosphere::{declare_raymarch, raymarch_bindings};
use super::{dispatch_over, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::resources::{AtmosphereTables, Resources};
use crate::shaders;
use crate::vk::barrier::Tracker;
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{specialized_compute_pipeline, Bindings, Specialization};
use ash::vk;

/// glsl/sky_view.comp's EYE_VIEW, and its table's binding.
const EYE_VIEW_CONSTANT: u32 = 11;
pub const SKY_VIEW_BINDING: u32 = 3;

pub struct EyeSkyPass<'g> {
    bindings: Bindings<'g>,
    pipeline: Owned<'g, vk::Pipeline>,
}

impl<'g> EyeSkyPass<'g> {
    pub fn new(device: &'g Device, r: &Resources, tables: &AtmosphereTables) -> Result<Self> {
        let bindings = raymarch_bindings(device, "eye sky", r, tables, &[(SKY_VIEW_BINDING, r.eye_sky.view)])?;
        let eye = Specialization::constants(&[(EYE_VIEW_CONSTANT, 1)]);
        let pipeline =
            specialized_compute_pipeline(device, bindings.layout(), shaders::SKY_VIEW_COMP, Some(&eye), "eye sky")?;
        Ok(EyeSkyPass { bindings, pipeline })
    }
}

impl Pass for EyeSkyPass<'_> {
    fn name(&self) -> &'static str {
        "eye_sky"
    }

    fn builds_for_eye(&self) -> bool {
        true
    }

    fn declare(&self, r: &Resources, _f: &Frame, t: &mut Tracker) {
        declare_raymarch(t, r, &[&r.eye_sky]);
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        dispatch_over(rec, self.pipeline.raw, &self.bindings, r.eye_sky.extent);
    }
}
