//! The example host's own object: a buoy drawn by its own pipeline (examples/host/box.vert and
//! box.frag) into the HDR colour and depth, before the ocean.

use super::engine::Host;
use super::{shaders, BUOY, DEPTH_FORMAT, HDR_FORMAT};
use ash::vk;
use glam::{Mat4, Quat};
use ocean::embed::{begin_cleared_rendering, HostImage, Light};

/// The host's own pipeline: the buoy, drawn before the ocean into the HDR colour and depth.
pub struct BuoyPipeline {
    pub layout: vk::PipelineLayout,
    pub pipeline: vk::Pipeline,
}

impl BuoyPipeline {
    pub fn new(host: &Host) -> Result<BuoyPipeline, Box<dyn std::error::Error>> {
        let device = &host.device;
        let module = |spirv: &[u8]| {
            let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv)).expect("SPIR-V");
            // SAFETY: valid SPIR-V compiled by build.rs.
            unsafe { device.create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None) }
        };
        let (vertex, fragment) = (module(shaders::BOX_VERT)?, module(shaders::BOX_FRAG)?);
        let ranges = [
            vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::VERTEX, offset: 0, size: 64 },
            vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::FRAGMENT, offset: 64, size: 48 },
        ];
        // SAFETY: a live device; the ranges fit the 128 bytes every device offers.
        let layout = unsafe {
            device.create_pipeline_layout(&vk::PipelineLayoutCreateInfo::default().push_constant_ranges(&ranges), None)
        }?;
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vertex)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(fragment)
                .name(c"main"),
        ];
        let blend = [vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA)];
        let formats = [HDR_FORMAT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(DEPTH_FORMAT);
        let dynamic = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        // Faces wound counter-clockwise from outside stay counter-clockwise by Vulkan's rule: its
        // signed area is taken with framebuffer y down, and the projection puts clip y down too.
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .cull_mode(vk::CullModeFlags::BACK)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
        // Reversed Z: nearer is greater.
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(vk::CompareOp::GREATER);
        let blending = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blending)
            .dynamic_state(&dynamic)
            .layout(layout)
            .push_next(&mut rendering);
        // SAFETY: valid create info; the modules may go once the pipeline exists.
        let pipeline = unsafe {
            let pipeline =
                device.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None).map_err(|(_, e)| e)?[0];
            device.destroy_shader_module(vertex, None);
            device.destroy_shader_module(fragment, None);
            pipeline
        };
        Ok(BuoyPipeline { layout, pipeline })
    }

    /// Clears the targets (far depth 0: reversed Z) and draws the buoy in the ocean's light.
    pub fn record(
        &self,
        host: &Host,
        cmd: vk::CommandBuffer,
        hdr: &HostImage,
        depth: &HostImage,
        clip_from_world: Mat4,
        light: &Light,
    ) {
        // The ocean's sun and sky (klux in its unit, OceanDesc::radiance_scale = 1): the buoy lit
        // as the sea around it is.
        let sun = light.sun_direction.as_vec3();
        let clip_from_box = clip_from_world * Mat4::from_scale_rotation_translation(BUOY.1, Quat::IDENTITY, BUOY.0);
        let vertex = clip_from_box.to_cols_array();
        let (e, s) = (light.sun_illuminance, light.sky_illuminance);
        let fragment = [sun.x, sun.y, sun.z, 0.0, e[0], e[1], e[2], 0.0, s[0], s[1], s[2], 0.0];
        let bytes = |v: &[f32]| v.iter().flat_map(|f| f.to_ne_bytes()).collect::<Vec<u8>>();
        // Reversed Z: the far plane is 0.
        begin_cleared_rendering(&host.device, cmd, hdr, depth, 0.0);
        // SAFETY: inside the rendering scope begun above (the targets in attachment layouts,
        // barriers before); the pipeline was made for their formats; the push constants fit the
        // layout's ranges.
        unsafe {
            host.device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            host.device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::VERTEX, 0, &bytes(&vertex));
            host.device.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::FRAGMENT, 64, &bytes(&fragment));
            host.device.cmd_draw(cmd, 36, 1, 0, 0);
            host.device.cmd_end_rendering(cmd);
        }
    }

    pub fn destroy(&self, host: &Host) {
        // SAFETY: the device is idle (finish waits first).
        unsafe {
            host.device.destroy_pipeline(self.pipeline, None);
            host.device.destroy_pipeline_layout(self.layout, None);
        }
    }
}
