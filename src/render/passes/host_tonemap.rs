//! A host's frame tone-mapped into its LDR target (glsl/host_tonemap.frag): a full-screen
//! triangle reading the host's HDR colour after the composite, its objects included. Only in a
//! host's frame that asks for it (embed::Targets::ldr). The host's colour image may change from
//! frame to frame, so each frame slot has its own descriptor set, rewritten as the frame is
//! recorded (the slot's previous frame has finished: the host's precondition).

use super::{colour_only_pipeline, draw_over, write_frame_uniforms, Frame, Pass, Recorder};
use crate::error::Result;
use crate::render::passes::exposure::Tone;
use crate::render::resources::{Resources, EXPOSURE_BINDING, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::{Access, Tracker};
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::Bindings;
use ash::vk;

const HDR_BINDING: u32 = 4;

pub struct HostTonemapPass<'g> {
    /// One set per frame slot, identically laid out (the pipeline's layout is the first's).
    bindings: Vec<Bindings<'g>>,
    pipeline: Owned<'g, vk::Pipeline>,
    /// Whether the exposure is the exposure pass's measurement.
    auto: bool,
}

impl HostTonemapPass<'_> {
    pub const NAME: &'static str = "host tonemap";
}

impl<'g> HostTonemapPass<'g> {
    /// For LDR targets of `format` (`encode_srgb`: a UNORM format the shader encodes), with
    /// `slots` frames in flight.
    pub fn new(
        device: &'g Device,
        r: &Resources,
        format: vk::Format,
        encode_srgb: bool,
        tone: Tone,
        slots: u32,
    ) -> Result<Self> {
        use vk::DescriptorType as D;
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        let bindings = (0..slots)
            .map(|_| {
                let b = Bindings::new(
                    device,
                    Self::NAME,
                    &[
                        (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, fragment),
                        (HDR_BINDING, D::COMBINED_IMAGE_SAMPLER, fragment),
                        (EXPOSURE_BINDING, D::UNIFORM_BUFFER, fragment),
                    ],
                )?;
                b.write_buffer(EXPOSURE_BINDING, D::UNIFORM_BUFFER, r.exposure.raw);
                write_frame_uniforms(&b, r, false);
                Ok(b)
            })
            .collect::<Result<Vec<_>>>()?;
        let spec = tone.specialization(encode_srgb);
        let layout = bindings[0].layout();
        let pipeline = colour_only_pipeline(device, layout, Self::NAME, shaders::HOST_TONEMAP_FRAG, &spec, format)?;
        Ok(HostTonemapPass { bindings, pipeline, auto: tone.auto })
    }
}

impl Pass for HostTonemapPass<'_> {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn declare(&self, r: &Resources, f: &Frame, t: &mut Tracker) {
        if self.auto {
            t.buffer(&r.exposure, Access::FragmentUniformRead);
        }
        if let Some(host) = &f.host {
            t.image(&host.colour, 0, 1, Access::FragmentSampled, false);
            if let Some(ldr) = &host.ldr {
                t.image(ldr, 0, 1, Access::ColorAttachmentWrite, true);
            }
        }
    }

    fn record(&self, rec: &mut Recorder, r: &Resources) {
        let Some(host) = rec.frame.host else { return };
        let Some(ldr) = host.ldr else { return };
        let bindings = &self.bindings[rec.frame.slot];
        // texelFetch ignores the sampler's filtering; any valid sampler does. The slot's set is
        // not in use by a pending frame: the host waited for the slot's last.
        bindings.write_image(
            HDR_BINDING,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            host.colour.view,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            r.sky_sampler.raw,
        );
        draw_over(rec, self.pipeline.raw, bindings, ldr.view, ldr.extent);
    }
}
