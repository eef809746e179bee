//! Objects on the sea, drawn as a host of the ocean library draws its own: a scene's `[[object]]`
//! models (glTF, model::gltf) uploaded once (`upload`), placed each frame in f64 around the eye
//! (model::placement, floating ones on the waves), lit by the ocean's sun and by the sky above
//! and the sea below (`light`), seen through the air, and drawn into the host's HDR colour and
//! depth before the ocean, which then depth-tests against them (embed::Ocean::record). Objects
//! sharing a model are drawn instanced.

mod light;
mod pipeline;
mod upload;

use crate::embed::Light;
use crate::embed::{MirrorCover, MirrorView};
use crate::error::{Error, Result, VkContext};
use crate::model::environment::{IRRADIANCE_COLUMNS, IRRADIANCE_ROWS};
use crate::model::floating::Waterplane;
use crate::model::gltf;
use crate::model::placement::{place, sea_plane_below, waterplane};
use crate::model::scene::{Object, Scene};
use crate::model::sky::SUN_ANGULAR_RADIUS;
use crate::model::waves::WaveSet;
use crate::render::sun_shadow::CasterBox;
use crate::vk::buffer::Buffer;
use crate::vk::external::{begin_cleared_rendering, hdr_format_max, HostImage};
use crate::vk::gpu::Gpu;
use crate::vk::image::Image;
use crate::vk::memory::Location;
use crate::vk::owned::Owned;
use ash::vk;
use glam::{DMat3, DMat4, DVec3};
use light::ObjectLight;
use pipeline::ObjectPipelines;
use upload::{GpuModel, BASE_COLOUR_FORMAT, NORMAL_MAP_FORMAT};

/// The planes bounding the view of `clip` (camera-relative world to clip space): its four sides,
/// and in front of the eye (clip w > 0); inside where a . x + w > 0.
fn view_planes(clip: DMat4) -> [glam::DVec4; 5] {
    let rows = [0, 1, 2, 3].map(|i| clip.row(i));
    [rows[3] + rows[0], rows[3] - rows[0], rows[3] + rows[1], rows[3] - rows[1], rows[3]]
}

/// Whether the box of `corners` may be in view of `planes` (no plane has them all outside).
fn in_view(planes: &[glam::DVec4; 5], corners: &[DVec3]) -> bool {
    planes.iter().all(|plane| corners.iter().any(|c| plane.truncate().dot(*c) + plane.w > 0.0))
}

/// The pass's name in profiles and debug labels.
pub const NAME: &str = "objects";

/// The depth the commands' hosts draw objects with (reversed Z: 1 near, 0 far; every device
/// supports it as a depth attachment).
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// glsl/object.glsl's `ObjectFrame` (std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct FrameUniforms {
    clip_from_relative: [[f32; 4]; 4],
    sun_direction: [f32; 4],
    sun_irradiance: [f32; 4],
    sun_clip_from_relative: [[f32; 4]; 4],
    shadow: [f32; 4],
    irradiance: [[f32; 4]; IRRADIANCE_ROWS * IRRADIANCE_COLUMNS],
}

/// A plane (unit normal n, offset w: n . x = w on it) as glsl/object.glsl's vec4.
fn plane4((n, w): (DVec3, f64)) -> [f32; 4] {
    [n.x as f32, n.y as f32, n.z as f32, w as f32]
}

/// glsl/object.glsl's `Instance` (std430).
#[repr(C)]
#[derive(Clone, Copy, Default)]
struct Instance {
    relative_from_model: [[f32; 4]; 4],
    normal_from_model: [[f32; 4]; 3],
    inscatter: [f32; 4],
    transmittance: [f32; 4],
    mirror_inscatter: [f32; 4],
    mirror_transmittance: [f32; 4],
    mirror_plane: [f32; 4],
    water_plane: [f32; 4],
}

/// The camera and light of one frame, as the host handed them to the ocean.
pub struct ObjectFrame<'a> {
    pub scene: &'a Scene,
    pub waves: &'a WaveSet,
    pub time_s: f64,
    /// The host's projection times its view without the eye's translation.
    pub clip_from_relative: DMat4,
    /// The eye in the world (z above mean sea level).
    pub eye: DVec3,
    pub light: &'a Light,
    /// The host's radiance unit per kcd/m² (embed::OceanDesc::radiance_scale).
    pub radiance_scale: f64,
    /// The colour format's largest finite value.
    pub colour_max: f32,
    /// The ocean's sun shadow map (embed::Ocean::sun_shadow), where it has one (None from `new`).
    pub sun_shadow: Option<crate::embed::SunShadow>,
    /// What the objects are mirrored with for the sea's planar reflections
    /// (embed::Ocean::mirror_view), where it reads them (None from `new`).
    pub mirror: Option<MirrorView>,
    /// The wave packets the floating objects ride (embed::Ocean::packet_field; None from `new`).
    pub packets: Option<&'a crate::model::packets::PacketField>,
}

impl<'a> ObjectFrame<'a> {
    /// The frame a host draws with `view` and `projection` (the matrices it hands the ocean).
    pub fn new(
        scene: &'a Scene,
        waves: &'a WaveSet,
        view: DMat4,
        projection: DMat4,
        light: &'a Light,
        radiance_scale: f64,
        colour_max: f32,
    ) -> ObjectFrame<'a> {
        let eye = view.inverse().w_axis.truncate();
        ObjectFrame {
            scene,
            waves,
            time_s: scene.render.time_s,
            clip_from_relative: projection * view * DMat4::from_translation(eye),
            eye,
            light,
            radiance_scale,
            colour_max,
            sun_shadow: None,
            mirror: None,
            packets: None,
        }
    }
}

pub struct Objects<'g> {
    gpu: &'g Gpu,
    // Field order is drop order: the pipelines (and the sets' pool) before what the sets name.
    pipelines: ObjectPipelines<'g>,
    /// The material sets' sampler.
    _sampler: Owned<'g, vk::Sampler>,
    uniforms: Buffer<'g>,
    uniform_stride: u64,
    instances: Buffer<'g>,
    instance_stride: u64,
    models: Vec<GpuModel<'g>>,
    /// White (sRGB) and a flat normal (linear) for materials without textures, and a lit 1 x 1
    /// shadow map for an ocean without one.
    stand_ins: Vec<Image<'g>>,
    /// Samples the stand-in shadow map.
    stand_in_shadow_sampler: Owned<'g, vk::Sampler>,
    /// The shadow map the frame set names (its view changes when the ocean is made again).
    shadow_bound: vk::ImageView,
    /// Each model's bounds (model space).
    model_bounds: Vec<(glam::Vec3, glam::Vec3)>,
    /// Per model, one set per material.
    material_sets: Vec<Vec<vk::DescriptorSet>>,
    /// The scene's objects and the model each draws.
    objects: Vec<(Object, usize)>,
    waterplanes: Vec<Waterplane>,
    /// Object indices in instance order: grouped by model, each group's range.
    order: Vec<usize>,
    batches: Vec<(usize, std::ops::Range<u32>)>,
    light: ObjectLight,
    /// Per frame slot: whether any object's mirror image is in view (the mirror pass is drawn).
    mirrored_in_view: Vec<bool>,
    /// Per slot, where the objects' mirror images may lie (as of its `update`).
    mirror_cover: Vec<MirrorCover>,
}

impl<'g> Objects<'g> {
    /// The pass for `objects` drawn into `colour` and `depth` attachments, `slots` frames in
    /// flight.
    pub fn new(
        gpu: &'g Gpu,
        objects: &[Object],
        colour: vk::Format,
        depth: vk::Format,
        reversed_z: bool,
        slots: u32,
    ) -> Result<Self> {
        let (models, model_of) = gltf::load_objects(objects)?;
        let lit = 1f32.to_ne_bytes();
        let stand_ins = [
            ([255, 255, 255, 255], BASE_COLOUR_FORMAT),
            ([128, 128, 255, 255], NORMAL_MAP_FORMAT),
            (lit, crate::embed::SHADOW_FORMAT),
        ];
        let (gpu_models, stand_in_images) = upload::upload(gpu, &models, &stand_ins)?;
        let material_count: u32 = gpu_models.iter().map(|m| m.materials.len().max(1) as u32).sum();
        let pipelines = ObjectPipelines::new(&gpu.device, colour, depth, reversed_z, material_count)?;
        let raw = &gpu.device.raw;
        let anisotropic = gpu.device.anisotropy;
        let limits = gpu.device.properties.limits;
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::REPEAT)
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .anisotropy_enable(anisotropic)
            .max_anisotropy(if anisotropic { limits.max_sampler_anisotropy.min(8.0) } else { 1.0 })
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE);
        // SAFETY: valid create info; anisotropy only where the feature was enabled.
        let sampler = unsafe { raw.create_sampler(&sampler_info, None) }.during("vkCreateSampler")?;
        let sampler = Owned::new(&gpu.device, sampler, "object textures");
        let compare_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .compare_enable(true)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL);
        // SAFETY: valid create info.
        let compare = unsafe { raw.create_sampler(&compare_info, None) }.during("vkCreateSampler")?;
        let compare = Owned::new(&gpu.device, compare, "object stand-in shadow");
        let shadow_bound = stand_in_images[2].view;
        pipeline::write_texture(raw, pipelines.frame_set, pipeline::SUN_SHADOW, shadow_bound, compare.raw);

        let align = |size: u64, to: u64| size.div_ceil(to.max(1)) * to.max(1);
        let uniform_stride =
            align(std::mem::size_of::<FrameUniforms>() as u64, limits.min_uniform_buffer_offset_alignment);
        let instance_bytes = (objects.len().max(1) * std::mem::size_of::<Instance>()) as u64;
        let instance_stride = align(instance_bytes, limits.min_storage_buffer_offset_alignment);
        let slots = slots.max(1) as u64;
        use vk::BufferUsageFlags as B;
        let uniforms = Buffer::new(gpu, "objects frame", uniform_stride * slots, B::UNIFORM_BUFFER, Location::Upload)?;
        let instances =
            Buffer::new(gpu, "objects instances", instance_stride * slots, B::STORAGE_BUFFER, Location::Upload)?;
        use vk::DescriptorType as D;
        let frame_set = pipelines.frame_set;
        let uniform_range = std::mem::size_of::<FrameUniforms>() as u64;
        pipeline::write_buffer(
            raw,
            frame_set,
            pipeline::FRAME_UNIFORMS,
            D::UNIFORM_BUFFER_DYNAMIC,
            uniforms.raw,
            uniform_range,
        );
        pipeline::write_buffer(
            raw,
            frame_set,
            pipeline::INSTANCES,
            D::STORAGE_BUFFER_DYNAMIC,
            instances.raw,
            instance_bytes,
        );

        let mut material_sets = Vec::new();
        for model in &gpu_models {
            let sets = pipelines.material_sets(model.materials.len().max(1) as u32)?;
            for (m, &set) in sets.iter().enumerate() {
                pipeline::write_buffer(
                    raw,
                    set,
                    pipeline::VERTICES,
                    D::STORAGE_BUFFER,
                    model.vertices.raw,
                    vk::WHOLE_SIZE,
                );
                let (base, normal) = model.material_textures.get(m).copied().unwrap_or((None, None));
                let view = |texture: Option<usize>, stand_in: usize| {
                    texture.map_or(stand_in_images[stand_in].view, |t| model.textures[t].view)
                };
                pipeline::write_texture(raw, set, pipeline::BASE_COLOUR, view(base, 0), sampler.raw);
                pipeline::write_texture(raw, set, pipeline::NORMAL_MAP, view(normal, 1), sampler.raw);
            }
            material_sets.push(sets);
        }

        let mut order = Vec::new();
        let mut batches = Vec::new();
        for model in 0..gpu_models.len() {
            let first = order.len() as u32;
            order.extend((0..objects.len()).filter(|&i| model_of[i] == model));
            batches.push((model, first..order.len() as u32));
        }
        let waterplanes = objects.iter().zip(&model_of).map(|(o, &m)| waterplane(models[m].bounds, o.scale)).collect();
        Ok(Objects {
            gpu,
            pipelines,
            _sampler: sampler,
            uniforms,
            uniform_stride,
            instances,
            instance_stride,
            models: gpu_models,
            stand_ins: stand_in_images,
            stand_in_shadow_sampler: compare,
            shadow_bound,
            model_bounds: models.iter().map(|m| m.bounds).collect(),
            material_sets,
            objects: objects.iter().cloned().zip(model_of).collect(),
            waterplanes,
            order,
            batches,
            light: ObjectLight::default(),
            mirrored_in_view: vec![false; slots as usize],
            mirror_cover: vec![MirrorCover::NOTHING; slots as usize],
        })
    }

    /// Whether `objects` are the ones this pass was made for (else the host makes a new pass).
    pub fn draws(&self, objects: &[Object]) -> bool {
        self.objects.len() == objects.len() && self.objects.iter().zip(objects).all(|((a, _), b)| a == b)
    }

    /// Writes frame `slot` of `scene` seen with `view` and `projection` (the matrices the host
    /// handed `ocean`, updated for the slot already), in the ocean's light and the host's unit.
    pub fn update_for(
        &mut self,
        slot: usize,
        scene: &Scene,
        view: DMat4,
        projection: DMat4,
        ocean: &crate::embed::Ocean,
    ) -> Result<()> {
        let light = ocean.light().expect("an updated ocean has its light");
        let waves = crate::model::waves::generate(scene);
        let desc = ocean.desc();
        let max = hdr_format_max(desc.formats.colour).unwrap_or(f32::MAX);
        let frame = ObjectFrame {
            sun_shadow: ocean.sun_shadow(),
            mirror: ocean.mirror_view(),
            packets: ocean.packet_field(),
            ..ObjectFrame::new(scene, &waves, view, projection, &light, desc.radiance_scale as f64, max)
        };
        self.update(slot, &frame)
    }

    /// The box (world, m) holding the objects of `scene` in the view of `view` and `projection`,
    /// for the ocean's sun view to cover them (embed::Ocean::set_shadow_casters); None when
    /// none is in view. An object outside the view casts no shadow (the map covers what is
    /// seen).
    pub fn shadow_casters(&self, scene: &Scene, view: DMat4, projection: DMat4) -> Option<(DVec3, DVec3)> {
        let waves = crate::model::waves::generate(scene);
        let eye = view.inverse().w_axis.truncate();
        let planes = view_planes(projection * view * DMat4::from_translation(eye));
        let mut bounds: Option<(DVec3, DVec3)> = None;
        for (i, (object, model)) in self.objects.iter().enumerate() {
            // The trains' pose: the packets' heave is within the box's margin of the sun's view.
            let p = place(scene, &waves, None, object, self.waterplanes[i], eye.z, scene.render.time_s);
            let (lo, hi) = self.model_bounds[*model];
            let model_box = CasterBox { min: lo.as_dvec3(), max: hi.as_dvec3() };
            let corners: Vec<DVec3> = model_box.corners().map(|c| p.relative_from_model.transform_point3(c)).collect();
            if !in_view(&planes, &corners) {
                continue;
            }
            for c in corners {
                let world = c + eye;
                bounds = Some(bounds.map_or((world, world), |(a, b)| (a.min(world), b.max(world))));
            }
        }
        bounds
    }

    /// Draws the objects of frame `slot` into the sun's shadow map, inside the ocean's shadow
    /// pass (embed::Ocean::record_shadows' callback).
    pub fn record_casters(&self, cmd: vk::CommandBuffer, slot: usize) {
        let raw = &self.gpu.device.raw;
        self.bind_frame(cmd, slot);
        // SAFETY: inside the ocean's shadow map scope; the caster pipeline was made for its
        // format and no colour attachment.
        unsafe { raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipelines.caster.raw) };
        self.draw_all(cmd, |_| {});
    }

    /// Whether frame `slot` has any object's mirror image in view (as of its `update`): the host
    /// records the ocean's mirror pass (embed::Ocean::record_planar) only then.
    pub fn mirrored_in_view(&self, slot: usize) -> bool {
        self.mirrored_in_view[slot]
    }

    /// Where the objects' mirror images in view may lie in frame `slot` (as of its `update`): the
    /// union of their mirrored boxes' covers (embed::Ocean::record_planar's `cover`).
    pub fn mirror_cover(&self, slot: usize) -> MirrorCover {
        self.mirror_cover[slot]
    }

    /// Draws the objects of frame `slot` mirrored about the sea, inside the ocean's mirror pass
    /// (embed::Ocean::record_planar's callback).
    pub fn record_mirrored(&self, cmd: vk::CommandBuffer, slot: usize) {
        self.bind_frame(cmd, slot);
        let p = &self.pipelines;
        self.draw_shaded(cmd, &p.mirrored_single_sided, &p.mirrored_double_sided);
    }

    /// Every object's meshes with their materials, through `single_sided` or `double_sided`.
    fn draw_shaded(
        &self,
        cmd: vk::CommandBuffer,
        single_sided: &Owned<vk::Pipeline>,
        double_sided: &Owned<vk::Pipeline>,
    ) {
        let raw = &self.gpu.device.raw;
        let layout = self.pipelines.layout.raw;
        self.draw_all(cmd, |material| {
            let pipeline = if material.double_sided { double_sided } else { single_sided };
            let normal_scale = material.normal_texture.map_or(0.0, |(_, s)| s);
            let push = [material.base_colour, [material.metallic, material.roughness, normal_scale, 0.0]];
            let bytes: Vec<u8> = push.iter().flatten().flat_map(|f| f.to_ne_bytes()).collect();
            // SAFETY: inside a rendering scope; the pipelines were made for its targets' formats
            // and this layout, whose push range holds the material's 32 bytes.
            unsafe {
                raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
                raw.cmd_push_constants(cmd, layout, vk::ShaderStageFlags::FRAGMENT, 0, &bytes);
            }
        });
    }

    /// Draws every object's meshes, instanced per model: binds each model's indices and each
    /// mesh's material set, `before_draw` binding what else the mesh's material needs.
    fn draw_all(&self, cmd: vk::CommandBuffer, mut before_draw: impl FnMut(&gltf::Material)) {
        let raw = &self.gpu.device.raw;
        let layout = self.pipelines.layout.raw;
        for (model, instances) in &self.batches {
            let gpu_model = &self.models[*model];
            // SAFETY: inside a rendering scope with a pipeline of this layout bound; the index
            // buffer and the sets live as long as self; the draws stay inside the model's
            // indices and the slot's instances.
            unsafe { raw.cmd_bind_index_buffer(cmd, gpu_model.indices.raw, 0, vk::IndexType::UINT32) };
            for draw in &gpu_model.draws {
                let material = gpu_model.materials.get(draw.material).cloned().unwrap_or_default();
                before_draw(&material);
                let sets = &self.material_sets[*model];
                let set = sets[draw.material.min(sets.len() - 1)];
                // SAFETY: as above.
                unsafe {
                    raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 1, &[set], &[]);
                    raw.cmd_draw_indexed(
                        cmd,
                        draw.index_count,
                        instances.len() as u32,
                        draw.first_index,
                        draw.vertex_offset,
                        instances.start,
                    );
                }
            }
        }
    }

    /// Binds the frame set at slot `slot`'s windows.
    fn bind_frame(&self, cmd: vk::CommandBuffer, slot: usize) {
        let offsets = [(slot as u64 * self.uniform_stride) as u32, (slot as u64 * self.instance_stride) as u32];
        // SAFETY: the dynamic offsets select slot windows inside the buffers; the set's
        // resources live as long as self.
        unsafe {
            self.gpu.device.raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.pipelines.layout.raw,
                0,
                &[self.pipelines.frame_set],
                &offsets,
            )
        };
    }

    /// Writes frame `slot`'s camera, light and placements (its previous use has finished).
    pub fn update(&mut self, slot: usize, frame: &ObjectFrame) -> Result<()> {
        let light = frame.light;
        let table = self.light.environment(frame.scene, light, frame.radiance_scale);
        let sun = light.sun_direction;
        // The map the ocean made (its view changes only when the ocean is made again, after the
        // host waited for its frames), else the lit stand-in.
        let map = frame.sun_shadow.map_or((self.stand_ins[2].view, None), |s| (s.view, Some(s)));
        if map.0 != self.shadow_bound {
            let sampler = map.1.map_or(self.stand_in_shadow_sampler.raw, |s| s.sampler);
            pipeline::write_texture(
                &self.gpu.device.raw,
                self.pipelines.frame_set,
                pipeline::SUN_SHADOW,
                map.0,
                sampler,
            );
            self.shadow_bound = map.0;
        }
        let sun_view = frame.sun_shadow.and_then(|s| s.clip_from_relative.map(|m| (m, s.texel_m)));
        let uniforms = FrameUniforms {
            clip_from_relative: frame.clip_from_relative.as_mat4().to_cols_array_2d(),
            sun_direction: [sun.x as f32, sun.y as f32, sun.z as f32, SUN_ANGULAR_RADIUS as f32],
            sun_irradiance: [
                light.sun_illuminance[0],
                light.sun_illuminance[1],
                light.sun_illuminance[2],
                frame.colour_max,
            ],
            sun_clip_from_relative: sun_view.map_or(glam::Mat4::ZERO, |(m, _)| m).to_cols_array_2d(),
            // A texel's diagonal: the receiver's offset along its normal.
            shadow: sun_view.map_or([0.0; 4], |(_, texel)| [1.0, (texel * std::f64::consts::SQRT_2) as f32, 0.0, 0.0]),
            irradiance: table.try_into().expect("the table's size"),
        };
        self.uniforms.write_at(slot as u64 * self.uniform_stride, &[uniforms])?;
        let planes = view_planes(frame.clip_from_relative);
        let mut mirrored_in_view = false;
        let mut mirror_cover = MirrorCover::NOTHING;
        let instances: Vec<Instance> = self
            .order
            .iter()
            .map(|&i| {
                let (object, model) = &self.objects[i];
                let p = place(
                    frame.scene,
                    frame.waves,
                    frame.packets,
                    object,
                    self.waterplanes[i],
                    frame.eye.z,
                    frame.time_s,
                );
                let (n, w) = sea_plane_below(p.origin, frame.eye.z, frame.scene.planet.radius_m);
                if let Some(view) = &frame.mirror {
                    let (lo, hi) = self.model_bounds[*model];
                    let model_box = CasterBox { min: lo.as_dvec3(), max: hi.as_dvec3() };
                    let mirror = MirrorView::mirror((n, w)) * p.relative_from_model;
                    let corners: Vec<DVec3> = model_box.corners().map(|c| mirror.transform_point3(c)).collect();
                    if in_view(&planes, &corners) {
                        mirrored_in_view = true;
                        mirror_cover = mirror_cover.union(view.cover_of(corners));
                    }
                }
                // Normals: the inverse transpose of the linear part, scaled to keep unit normals
                // unit (the scale is uniform).
                let linear = DMat3::from_mat4(p.relative_from_model);
                let normal = linear.inverse().transpose() * (linear.determinant().abs().cbrt());
                let rows =
                    [normal.row(0), normal.row(1), normal.row(2)].map(|r| [r.x as f32, r.y as f32, r.z as f32, 0.0]);
                let (inscatter, transmittance) =
                    self.light.air_between(frame.scene, sun, frame.eye.z, p.origin, frame.radiance_scale);
                // Its mirror image carries the air from the object to the sea that reflects it
                // alone: the shading sees that sea through the air between it and the eye.
                let from_sea = p.origin - MirrorView::reflecting_point(p.origin, (n, w));
                let (mirror_inscatter, mirror_transmittance) =
                    self.light.air_between(frame.scene, sun, 0.0, from_sea, frame.radiance_scale);
                let v4 = |v: [f64; 3]| [v[0] as f32, v[1] as f32, v[2] as f32, 0.0];
                Instance {
                    relative_from_model: p.relative_from_model.as_mat4().to_cols_array_2d(),
                    normal_from_model: rows,
                    inscatter: v4(inscatter),
                    transmittance: v4(transmittance),
                    mirror_inscatter: v4(mirror_inscatter),
                    mirror_transmittance: v4(mirror_transmittance),
                    mirror_plane: plane4((n, w)),
                    water_plane: plane4(p.water_plane),
                }
            })
            .collect();
        if !instances.iter().all(|i| i.relative_from_model.iter().flatten().all(|v| v.is_finite())) {
            return Err(Error::Argument("an object's placement is not finite".into()));
        }
        self.mirrored_in_view[slot] = mirrored_in_view;
        self.mirror_cover[slot] = mirror_cover;
        self.instances.write_at(slot as u64 * self.instance_stride, &instances)
    }

    /// Clears `colour` (to black: the ocean's sky fills what no object covers) and `depth` (to
    /// the far plane) and draws the objects of frame `slot`. Both are in attachment layouts.
    pub fn record(&self, cmd: vk::CommandBuffer, slot: usize, colour: &HostImage, depth: &HostImage, far: f32) {
        let raw = &self.gpu.device.raw;
        begin_cleared_rendering(raw, cmd, colour, depth, far);
        self.bind_frame(cmd, slot);
        self.draw_shaded(cmd, &self.pipelines.single_sided, &self.pipelines.double_sided);
        // SAFETY: the scope begun above.
        unsafe {
            raw.cmd_end_rendering(cmd);
        }
    }

    /// Triangles drawn per frame (every object's model).
    pub fn triangles(&self) -> usize {
        self.batches
            .iter()
            .map(|(m, r)| self.models[*m].draws.iter().map(|d| d.index_count as usize / 3).sum::<usize>() * r.len())
            .sum()
    }
}
