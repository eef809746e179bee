//! Shader modules, descriptor layouts and pipelines (compute, and graphics with dynamic rendering).

use super::device::Device;
use super::owned::Owned;
use crate::error::{Result, VkContext};
use ash::vk;

pub fn shader_module<'g>(device: &'g Device, spirv: &[u8], name: &str) -> Result<Owned<'g, vk::ShaderModule>> {
    let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv)).expect("build.rs embeds whole SPIR-V words");
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    // SAFETY: the words are SPIR-V produced by shaderc at build time.
    let module = unsafe { device.raw.create_shader_module(&info, None) }.during("vkCreateShaderModule")?;
    Ok(Owned::new(device, module, name))
}

/// 32-bit specialization constants 0..n (bool as VkBool32, int as its bits).
pub struct Specialization {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u32>,
}

impl Specialization {
    pub fn words(values: &[u32]) -> Specialization {
        let entries = (0..values.len() as u32)
            .map(|i| vk::SpecializationMapEntry { constant_id: i, offset: 4 * i, size: 4 })
            .collect();
        Specialization { entries, data: values.to_vec() }
    }

    /// Only the constants named, by id.
    pub fn constants(values: &[(u32, u32)]) -> Specialization {
        let entries = (0..values.len() as u32)
            .map(|i| vk::SpecializationMapEntry { constant_id: values[i as usize].0, offset: 4 * i, size: 4 })
            .collect();
        Specialization { entries, data: values.iter().map(|v| v.1).collect() }
    }

    pub fn info(&self) -> vk::SpecializationInfo<'_> {
        // SAFETY: u32 has no padding; the slice's bytes are exactly the constants.
        let bytes = unsafe { std::slice::from_raw_parts(self.data.as_ptr() as *const u8, 4 * self.data.len()) };
        vk::SpecializationInfo::default().map_entries(&self.entries).data(bytes)
    }
}

/// A descriptor set layout, its pipeline layout, and one set allocated from its own pool.
pub struct Bindings<'g> {
    device: &'g Device,
    pub set: vk::DescriptorSet,
    /// Binding numbers of the dynamic uniform buffers, in increasing order (the order in which
    /// vkCmdBindDescriptorSets takes their offsets).
    dynamic: Vec<u32>,
    // Declared so that they drop in reverse creation order; the set goes with its pool.
    _pool: Owned<'g, vk::DescriptorPool>,
    pipeline_layout: Owned<'g, vk::PipelineLayout>,
    _set_layout: Owned<'g, vk::DescriptorSetLayout>,
}

impl<'g> Bindings<'g> {
    pub fn new(
        device: &'g Device,
        name: &str,
        bindings: &[(u32, vk::DescriptorType, vk::ShaderStageFlags)],
    ) -> Result<Self> {
        Self::with_push_constants(device, name, bindings, 0)
    }

    /// As `new`, with `push_bytes` of push constants for every stage the bindings name.
    pub fn with_push_constants(
        device: &'g Device,
        name: &str,
        bindings: &[(u32, vk::DescriptorType, vk::ShaderStageFlags)],
        push_bytes: u32,
    ) -> Result<Self> {
        let raw = &device.raw;
        let layout_bindings: Vec<_> = bindings
            .iter()
            .map(|&(binding, ty, stages)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY: valid create info built from locals.
        let set_layout =
            unsafe { raw.create_descriptor_set_layout(&info, None) }.during("vkCreateDescriptorSetLayout")?;
        let set_layout = Owned::new(device, set_layout, name);
        let set_layouts = [set_layout.raw];
        let push_stages = bindings.iter().fold(vk::ShaderStageFlags::empty(), |all, &(_, _, stages)| all | stages);
        let push = [vk::PushConstantRange { stage_flags: push_stages, offset: 0, size: push_bytes }];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_layouts)
            .push_constant_ranges(if push_bytes > 0 { &push } else { &[] });
        // SAFETY: valid create info; the set layout is live.
        let pipeline_layout = unsafe { raw.create_pipeline_layout(&info, None) }.during("vkCreatePipelineLayout")?;
        let pipeline_layout = Owned::new(device, pipeline_layout, name);
        let sizes: Vec<_> =
            bindings.iter().map(|&(_, ty, _)| vk::DescriptorPoolSize { ty, descriptor_count: 1 }).collect();
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(1).pool_sizes(&sizes);
        // SAFETY: valid create info built from locals.
        let pool = unsafe { raw.create_descriptor_pool(&info, None) }.during("vkCreateDescriptorPool")?;
        let pool = Owned::new(device, pool, name);
        let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool.raw).set_layouts(&set_layouts);
        // SAFETY: one set of the layout above from its own pool, sized for it.
        let set = unsafe { raw.allocate_descriptor_sets(&info) }.during("vkAllocateDescriptorSets")?[0];
        device.set_name(set, name);
        let mut dynamic: Vec<u32> = bindings
            .iter()
            .filter(|&&(_, ty, _)| ty == vk::DescriptorType::UNIFORM_BUFFER_DYNAMIC)
            .map(|&(binding, _, _)| binding)
            .collect();
        dynamic.sort_unstable();
        Ok(Bindings { device, set, dynamic, _pool: pool, pipeline_layout, _set_layout: set_layout })
    }

    pub fn layout(&self) -> vk::PipelineLayout {
        self.pipeline_layout.raw
    }

    /// Records `words` as the push constants of a compute layout made by `with_push_constants`
    /// with at least 4 bytes per word.
    pub fn push_compute_words(&self, cmd: vk::CommandBuffer, words: &[u32]) {
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_ne_bytes()).collect();
        let compute = vk::ShaderStageFlags::COMPUTE;
        // SAFETY: `cmd` is recording; the layout's push range covers the words for the compute
        // stage (the caller's precondition).
        unsafe { self.device.raw.cmd_push_constants(cmd, self.pipeline_layout.raw, compute, 0, &bytes) };
    }

    pub fn write_buffer(&self, binding: u32, ty: vk::DescriptorType, buffer: vk::Buffer) {
        self.write_buffer_range(binding, ty, buffer, vk::WHOLE_SIZE);
    }

    /// Binds the first `range` bytes of `buffer` (a dynamic uniform buffer's window, moved by the
    /// offset given at bind time).
    pub fn write_buffer_range(&self, binding: u32, ty: vk::DescriptorType, buffer: vk::Buffer, range: u64) {
        let info = [vk::DescriptorBufferInfo { buffer, offset: 0, range }];
        self.update(self.write(binding, ty).buffer_info(&info));
    }

    /// Binds a texel buffer's view (a UNIFORM_ or STORAGE_TEXEL_BUFFER binding).
    pub fn write_texel_buffer(&self, binding: u32, ty: vk::DescriptorType, view: vk::BufferView) {
        let views = [view];
        self.update(self.write(binding, ty).texel_buffer_view(&views));
    }

    pub fn write_image(
        &self,
        binding: u32,
        ty: vk::DescriptorType,
        view: vk::ImageView,
        layout: vk::ImageLayout,
        sampler: vk::Sampler,
    ) {
        let info = [vk::DescriptorImageInfo { sampler, image_view: view, image_layout: layout }];
        self.update(self.write(binding, ty).image_info(&info));
    }

    fn write(&self, binding: u32, ty: vk::DescriptorType) -> vk::WriteDescriptorSet<'static> {
        vk::WriteDescriptorSet::default().dst_set(self.set).dst_binding(binding).descriptor_type(ty)
    }

    fn update(&self, write: vk::WriteDescriptorSet) {
        // SAFETY: the set is not in use by any pending command buffer when written, and `write`
        // points at descriptors of the binding's type that outlive this call.
        unsafe { self.device.raw.update_descriptor_sets(&[write], &[]) };
    }

    /// Binds the set; `offsets[b]` is the offset of dynamic uniform buffer binding `b` (sets
    /// without dynamic buffers take `&[]`).
    pub fn bind(&self, cmd: vk::CommandBuffer, point: vk::PipelineBindPoint, offsets: &[u32]) {
        let dynamic: Vec<u32> = self.dynamic.iter().map(|&b| offsets[b as usize]).collect();
        // SAFETY: `cmd` is recording with a pipeline made from this layout; each offset keeps the
        // bound window inside its buffer (the frame ring's slots).
        unsafe {
            self.device.raw.cmd_bind_descriptor_sets(cmd, point, self.pipeline_layout.raw, 0, &[self.set], &dynamic)
        };
    }
}

pub fn compute_pipeline<'g>(
    device: &'g Device,
    layout: vk::PipelineLayout,
    spirv: &[u8],
    name: &str,
) -> Result<Owned<'g, vk::Pipeline>> {
    specialized_compute_pipeline(device, layout, spirv, None, name)
}

/// A compute pipeline with specialization constants. Compute pipelines may be dispatched with a
/// base group (vkCmdDispatchBase: a pass can run over part of an image).
pub fn specialized_compute_pipeline<'g>(
    device: &'g Device,
    layout: vk::PipelineLayout,
    spirv: &[u8],
    specialization: Option<&Specialization>,
    name: &str,
) -> Result<Owned<'g, vk::Pipeline>> {
    let module = shader_module(device, spirv, name)?;
    let spec_info = specialization.map(|s| s.info());
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.raw)
        .name(c"main");
    let stage = match spec_info.as_ref() {
        Some(spec) => stage.specialization_info(spec),
        None => stage,
    };
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)
        .flags(vk::PipelineCreateFlags::DISPATCH_BASE);
    // SAFETY: valid create info; the module outlives the call.
    let pipelines = unsafe { device.raw.create_compute_pipelines(device.pipeline_cache.raw, &[info], None) }
        .map_err(|(_, e)| e)
        .during("vkCreateComputePipelines")?;
    Ok(Owned::new(device, pipelines[0], name))
}

/// What differs between our graphics pipelines.
pub struct GraphicsDesc<'a> {
    pub name: &'a str,
    pub vertex: &'a [u8],
    /// None: a depth-only pipeline.
    pub fragment: Option<&'a [u8]>,
    /// Applied to both stages.
    pub specialization: Option<&'a Specialization>,
    /// None: no colour attachment.
    pub color_format: Option<vk::Format>,
    /// UNDEFINED: no depth attachment, no depth test.
    pub depth_format: vk::Format,
    pub depth_write: bool,
    pub depth_compare: vk::CompareOp,
    /// Rasterization's depth bias: (constant, slope) factors (Vulkan's depthBiasConstantFactor,
    /// depthBiasSlopeFactor; no clamp).
    pub depth_bias: Option<(f32, f32)>,
    /// Which winding faces the eye, where back faces are culled (None: nothing culled).
    pub cull_back_faces: Option<vk::FrontFace>,
}

pub fn graphics_pipeline<'g>(
    device: &'g Device,
    layout: vk::PipelineLayout,
    desc: &GraphicsDesc,
) -> Result<Owned<'g, vk::Pipeline>> {
    let vs = shader_module(device, desc.vertex, &format!("{} vs", desc.name))?;
    let fs = desc.fragment.map(|code| shader_module(device, code, &format!("{} fs", desc.name))).transpose()?;
    let spec_info = desc.specialization.map(|s| s.info());
    let stage = |stage, module| {
        let info = vk::PipelineShaderStageCreateInfo::default().stage(stage).module(module).name(c"main");
        match spec_info.as_ref() {
            Some(spec) => info.specialization_info(spec),
            None => info,
        }
    };
    let mut stages = vec![stage(vk::ShaderStageFlags::VERTEX, vs.raw)];
    stages.extend(fs.as_ref().map(|fs| stage(vk::ShaderStageFlags::FRAGMENT, fs.raw)));
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let input_assembly =
        vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(if desc.cull_back_faces.is_some() { vk::CullModeFlags::BACK } else { vk::CullModeFlags::NONE })
        .front_face(desc.cull_back_faces.unwrap_or(vk::FrontFace::COUNTER_CLOCKWISE))
        .line_width(1.0);
    let raster = match desc.depth_bias {
        Some((constant, slope)) => {
            raster.depth_bias_enable(true).depth_bias_constant_factor(constant).depth_bias_slope_factor(slope)
        }
        None => raster,
    };
    let multisample =
        vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let has_depth = desc.depth_format != vk::Format::UNDEFINED;
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(has_depth)
        .depth_write_enable(desc.depth_write)
        .depth_compare_op(desc.depth_compare);
    let blend_attachment =
        [vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA)];
    let colors = if desc.color_format.is_some() { &blend_attachment[..] } else { &[] };
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(colors);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats: Vec<vk::Format> = desc.color_format.into_iter().collect();
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(desc.depth_format);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&input_assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    // SAFETY: valid create info built from locals; the modules outlive the call.
    let pipelines = unsafe { device.raw.create_graphics_pipelines(device.pipeline_cache.raw, &[info], None) }
        .map_err(|(_, e)| e)
        .during("vkCreateGraphicsPipelines")?;
    Ok(Owned::new(device, pipelines[0], desc.name))
}
