//! The object pass's pipeline layout, descriptor sets and pipelines (glsl/object.vert and
//! object.frag, and the vertex stage alone for the sun's shadow map): set 0 the frame (its light,
//! camera and sun shadow map, the objects' placements; dynamic offsets select the frame slot), set 1 one per material of each model (the model's vertices and the
//! material's textures), the material's factors in push constants.

use crate::embed::{PLANAR_COLOUR_FORMAT, PLANAR_DEPTH_FORMAT, SHADOW_DEPTH_BIAS, SHADOW_FORMAT};
use crate::error::{Result, VkContext};
use crate::shaders;
use crate::vk::device::Device;
use crate::vk::owned::Owned;
use crate::vk::pipeline::{graphics_pipeline, GraphicsDesc, Specialization};
use ash::vk;

pub const FRAME_UNIFORMS: u32 = 0;
pub const INSTANCES: u32 = 1;
pub const SUN_SHADOW: u32 = 2;
pub const VERTICES: u32 = 0;
pub const BASE_COLOUR: u32 = 1;
pub const NORMAL_MAP: u32 = 2;
/// glsl/object.glsl's `Material`: base colour, then metallic, roughness, normal scale.
pub const PUSH_BYTES: u32 = 32;

pub struct ObjectPipelines<'g> {
    device: &'g Device,
    // Drop order: pipelines, then the layout, then the sets' pool and layouts.
    /// Back faces culled (single-sided materials), and none culled (double-sided).
    pub single_sided: Owned<'g, vk::Pipeline>,
    pub double_sided: Owned<'g, vk::Pipeline>,
    /// Depth only, from the sun, into the ocean's shadow map (embed::Ocean::record_shadows):
    /// no face culled, so that open and single-sided surfaces cast too.
    pub caster: Owned<'g, vk::Pipeline>,
    /// Mirrored about the sea into the ocean's planar images (embed::Ocean::record_planar). A
    /// mirror's determinant is -1: a face seen from its outside winds clockwise in its image, so
    /// the single-sided one culls the other winding from the eye's (culling the eye's showed each
    /// solid's far faces from inside: a pier's shaded back wall in place of its sunlit side).
    pub mirrored_single_sided: Owned<'g, vk::Pipeline>,
    pub mirrored_double_sided: Owned<'g, vk::Pipeline>,
    pub layout: Owned<'g, vk::PipelineLayout>,
    pool: Owned<'g, vk::DescriptorPool>,
    _frame_layout: Owned<'g, vk::DescriptorSetLayout>,
    material_layout: Owned<'g, vk::DescriptorSetLayout>,
    pub frame_set: vk::DescriptorSet,
}

impl<'g> ObjectPipelines<'g> {
    /// Pipelines for `colour` and `depth` attachments (reversed or standard depth), with room
    /// for `material_sets` material sets.
    pub fn new(
        device: &'g Device,
        colour: vk::Format,
        depth: vk::Format,
        reversed_z: bool,
        material_sets: u32,
    ) -> Result<Self> {
        let raw = &device.raw;
        use vk::DescriptorType as D;
        use vk::ShaderStageFlags as S;
        let binding = |binding, ty, stages| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(ty)
                .descriptor_count(1)
                .stage_flags(stages)
        };
        let frame_bindings = [
            binding(FRAME_UNIFORMS, D::UNIFORM_BUFFER_DYNAMIC, S::VERTEX | S::FRAGMENT),
            binding(INSTANCES, D::STORAGE_BUFFER_DYNAMIC, S::VERTEX | S::FRAGMENT),
            binding(SUN_SHADOW, D::COMBINED_IMAGE_SAMPLER, S::FRAGMENT),
        ];
        let material_bindings = [
            binding(VERTICES, D::STORAGE_BUFFER, S::VERTEX),
            binding(BASE_COLOUR, D::COMBINED_IMAGE_SAMPLER, S::FRAGMENT),
            binding(NORMAL_MAP, D::COMBINED_IMAGE_SAMPLER, S::FRAGMENT),
        ];
        let set_layout = |bindings: &[vk::DescriptorSetLayoutBinding], name| -> Result<_> {
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
            // SAFETY: valid create info built from locals.
            let layout =
                unsafe { raw.create_descriptor_set_layout(&info, None) }.during("vkCreateDescriptorSetLayout")?;
            Ok(Owned::new(device, layout, name))
        };
        let frame_layout = set_layout(&frame_bindings, "objects frame")?;
        let material_layout = set_layout(&material_bindings, "objects material")?;
        let set_layouts = [frame_layout.raw, material_layout.raw];
        let push = [vk::PushConstantRange { stage_flags: S::FRAGMENT, offset: 0, size: PUSH_BYTES }];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts).push_constant_ranges(&push);
        // SAFETY: valid create info; the set layouts are live.
        let layout = unsafe { raw.create_pipeline_layout(&info, None) }.during("vkCreatePipelineLayout")?;
        let layout = Owned::new(device, layout, "objects");
        let sizes = [
            vk::DescriptorPoolSize { ty: D::UNIFORM_BUFFER_DYNAMIC, descriptor_count: 1 },
            vk::DescriptorPoolSize { ty: D::STORAGE_BUFFER_DYNAMIC, descriptor_count: 1 },
            vk::DescriptorPoolSize { ty: D::STORAGE_BUFFER, descriptor_count: material_sets },
            vk::DescriptorPoolSize { ty: D::COMBINED_IMAGE_SAMPLER, descriptor_count: 2 * material_sets + 1 },
        ];
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(1 + material_sets).pool_sizes(&sizes);
        // SAFETY: valid create info built from locals.
        let pool = unsafe { raw.create_descriptor_pool(&info, None) }.during("vkCreateDescriptorPool")?;
        let pool = Owned::new(device, pool, "objects");
        let frame_set = allocate(raw, pool.raw, frame_layout.raw, 1)?[0];
        device.set_name(frame_set, "objects frame");
        let compare = if reversed_z { vk::CompareOp::GREATER } else { vk::CompareOp::LESS };
        let desc = |name, cull| GraphicsDesc {
            name,
            vertex: shaders::OBJECT_VERT,
            fragment: Some(shaders::OBJECT_FRAG),
            specialization: None,
            color_format: Some(colour),
            depth_format: depth,
            depth_write: true,
            depth_compare: compare,
            depth_bias: None,
            cull_back_faces: cull,
        };
        // Models wind counter-clockwise seen from outside (glTF's rule), which stays
        // counter-clockwise by Vulkan's: its signed area is taken with framebuffer y down, and the
        // projection puts clip y down too (tests/objects.rs sees the sea through the hull's
        // interior from inside it, never the inner walls).
        let single_sided =
            graphics_pipeline(device, layout.raw, &desc("objects", Some(vk::FrontFace::COUNTER_CLOCKWISE)))?;
        let double_sided = graphics_pipeline(device, layout.raw, &desc("objects double-sided", None))?;
        let sun_view = Specialization::words(&[1]);
        let caster = GraphicsDesc {
            name: "object shadow casters",
            fragment: None,
            specialization: Some(&sun_view),
            color_format: None,
            depth_format: SHADOW_FORMAT,
            depth_compare: vk::CompareOp::LESS,
            depth_bias: Some(SHADOW_DEPTH_BIAS),
            ..desc("object shadow casters", None)
        };
        let caster = graphics_pipeline(device, layout.raw, &caster)?;
        let mirror = Specialization::words(&[0, 1]);
        let mirrored = |name, cull| GraphicsDesc {
            specialization: Some(&mirror),
            color_format: Some(PLANAR_COLOUR_FORMAT),
            depth_format: PLANAR_DEPTH_FORMAT,
            ..desc(name, cull)
        };
        let mirrored_single_sided =
            graphics_pipeline(device, layout.raw, &mirrored("objects mirrored", Some(vk::FrontFace::CLOCKWISE)))?;
        let mirrored_double_sided =
            graphics_pipeline(device, layout.raw, &mirrored("objects mirrored double-sided", None))?;
        Ok(ObjectPipelines {
            device,
            single_sided,
            double_sided,
            caster,
            mirrored_single_sided,
            mirrored_double_sided,
            layout,
            pool,
            _frame_layout: frame_layout,
            material_layout,
            frame_set,
        })
    }

    /// `count` material sets (never freed: they go with the pool).
    pub fn material_sets(&self, count: u32) -> Result<Vec<vk::DescriptorSet>> {
        allocate(&self.device.raw, self.pool.raw, self.material_layout.raw, count)
    }
}

fn allocate(
    raw: &ash::Device,
    pool: vk::DescriptorPool,
    layout: vk::DescriptorSetLayout,
    count: u32,
) -> Result<Vec<vk::DescriptorSet>> {
    if count == 0 {
        return Ok(Vec::new());
    }
    let layouts = vec![layout; count as usize];
    let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(pool).set_layouts(&layouts);
    // SAFETY: the pool was sized for one frame set and every material set.
    unsafe { raw.allocate_descriptor_sets(&info) }.during("vkAllocateDescriptorSets")
}

/// Points binding `binding` of `set` at `buffer` (a window of `range` bytes for a dynamic one).
pub fn write_buffer(
    raw: &ash::Device,
    set: vk::DescriptorSet,
    binding: u32,
    ty: vk::DescriptorType,
    buffer: vk::Buffer,
    range: u64,
) {
    let info = [vk::DescriptorBufferInfo { buffer, offset: 0, range }];
    let write =
        vk::WriteDescriptorSet::default().dst_set(set).dst_binding(binding).descriptor_type(ty).buffer_info(&info);
    // SAFETY: the set is not used by a pending command buffer (written before the first frame).
    unsafe { raw.update_descriptor_sets(&[write], &[]) };
}

/// Points sampler binding `binding` of `set` at `view`, in SHADER_READ_ONLY_OPTIMAL.
pub fn write_texture(
    raw: &ash::Device,
    set: vk::DescriptorSet,
    binding: u32,
    view: vk::ImageView,
    sampler: vk::Sampler,
) {
    let info = [vk::DescriptorImageInfo {
        sampler,
        image_view: view,
        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    }];
    let write = vk::WriteDescriptorSet::default()
        .dst_set(set)
        .dst_binding(binding)
        .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
        .image_info(&info);
    // SAFETY: as above.
    unsafe { raw.update_descriptor_sets(&[write], &[]) };
}
