//! A scene's objects for the ground truth (glsl/groundtruth_objects.glsl): every object placed
//! at the frame's time as the commands' hosts place it (model::placement, in f64 around the eye
//! of `embed::camera::scene_view`), its triangles in the eye-relative world, one bounding-volume
//! hierarchy over them all (model::bvh), and each material's factors for the shader.
//!
//! What the tracer leaves out of the raster's material model, and says so here: a base-colour
//! texture counts as its mean linear colour (the tracer reads no textures), and normal maps are
//! not applied (the interpolated normals are).

use crate::error::Result;
use crate::model::bvh;
use crate::model::gltf::{self, Material, Model};
use crate::model::placement::{place, waterplane};
use crate::model::scene::Scene;
use crate::model::waves::WaveSet;
use glam::{DVec3, Vec3};

/// Node visits a ray's walk through the hierarchy may take: glsl/groundtruth_objects.glsl's
/// loop, within the loop budget (a balanced tree over 200 buoys' 60 000 triangles is 15 levels
/// deep; a ray visits a few nodes per level).
pub const BVH_VISITS: u32 = 512;
/// Walks a sample may take: the camera ray, each reflected ray (`bounces + 1`), and at an object
/// its shadow ray and its environment ray.
pub fn walks_per_sample(bounces: u32) -> u32 {
    bounces + 4
}

/// The buffers glsl/groundtruth_objects.glsl reads.
pub struct TruthObjects {
    /// model::bvh's nodes as 32-bit words (floats by their bits): min and the first child or
    /// triangle, max and the count.
    pub nodes: Vec<[u32; 4]>,
    /// Six vec4 per triangle in leaf order, as 32-bit words: its corners (w of the first: the
    /// material) and their normals.
    pub triangles: Vec<[u32; 4]>,
    /// Two vec4 per material, as 32-bit words: the linear base colour (a texture's mean folded
    /// in), and metallic, roughness.
    pub materials: Vec<[u32; 4]>,
}

impl TruthObjects {
    /// The objects of `scene` (None without any), seen from its camera at its time.
    /// `packets`: the wave packets alive at the scene's time, in the eye's frame (the floating
    /// objects ride them).
    pub fn new(
        scene: &Scene,
        waves: &WaveSet,
        packets: Option<&crate::model::packets::PacketField>,
        aspect: f64,
    ) -> Result<Option<TruthObjects>> {
        if scene.objects.is_empty() {
            return Ok(None);
        }
        let (view, _) = crate::embed::camera::scene_view(scene, aspect, true);
        let eye_z = view.inverse().w_axis.z;
        let (models, model_of) = gltf::load_objects(&scene.objects)?;
        // Each model's materials in turn, the first index of each model's.
        let mut materials = Vec::new();
        let mut first_materials = Vec::new();
        for model in &models {
            first_materials.push((materials.len() / 2) as u32);
            let defaults = [Material::default()];
            let model_materials = if model.materials.is_empty() { &defaults[..] } else { &model.materials[..] };
            for material in model_materials {
                materials.extend(material_words(model, material));
            }
        }
        let mut corners: Vec<[Vec3; 3]> = Vec::new();
        let mut attributes: Vec<([Vec3; 3], u32)> = Vec::new();
        for (object, &index) in scene.objects.iter().zip(&model_of) {
            let (model, first_material) = (&models[index], first_materials[index]);
            let placement = place(
                scene,
                waves,
                packets,
                object,
                waterplane(model.bounds, object.scale),
                eye_z,
                scene.render.time_s,
            );
            let m = placement.relative_from_model;
            let normals = glam::DMat3::from_mat4(m).inverse().transpose();
            for mesh in &model.meshes {
                let material = first_material + mesh.material.min(model.materials.len().max(1) - 1) as u32;
                for tri in mesh.indices.chunks_exact(3) {
                    let at = |i: u32| m.transform_point3(mesh.positions[i as usize].as_dvec3()).as_vec3();
                    let normal = |i: u32| (normals * mesh.normals[i as usize].as_dvec3()).normalize_or_zero().as_vec3();
                    corners.push([at(tri[0]), at(tri[1]), at(tri[2])]);
                    attributes.push(([normal(tri[0]), normal(tri[1]), normal(tri[2])], material));
                }
            }
        }
        let hierarchy = bvh::build(&corners);
        let nodes = hierarchy
            .nodes
            .iter()
            .flat_map(|n| {
                let b = |v: [f32; 3]| v.map(f32::to_bits);
                let (lo, hi) = (b(n.min), b(n.max));
                [[lo[0], lo[1], lo[2], n.first], [hi[0], hi[1], hi[2], n.count]]
            })
            .collect();
        let triangles = hierarchy
            .triangles
            .iter()
            .zip(&hierarchy.source)
            .flat_map(|(p, &source)| {
                let (n, material) = attributes[source as usize];
                let b = |v: Vec3, w: u32| {
                    let [x, y, z] = v.to_array().map(f32::to_bits);
                    [x, y, z, w]
                };
                [b(p[0], material), b(p[1], 0), b(p[2], 0), b(n[0], 0), b(n[1], 0), b(n[2], 0)]
            })
            .collect();
        Ok(Some(TruthObjects { nodes, triangles, materials }))
    }
}

/// A material's two vec4: its base colour times its texture's mean linear colour, and its
/// metallic and roughness factors.
fn material_words(model: &Model, material: &Material) -> [[u32; 4]; 2] {
    let mean = material.base_colour_texture.and_then(|t| model.textures.get(t)).map_or([1.0; 3], mean_linear);
    let c = material.base_colour;
    let colour = [c[0] * mean[0], c[1] * mean[1], c[2] * mean[2], c[3]];
    [colour.map(f32::to_bits), [material.metallic, material.roughness, 0.0, 0.0].map(f32::to_bits)]
}

/// The mean linear colour of an sRGB texture.
fn mean_linear(texture: &gltf::Texture) -> [f32; 3] {
    let decode = |v: u8| {
        let c = v as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let mut sum = DVec3::ZERO;
    let texels = texture.rgba.chunks_exact(4);
    let count = texels.len().max(1) as f64;
    for t in texels {
        sum += DVec3::new(decode(t[0]), decode(t[1]), decode(t[2]));
    }
    (sum / count).as_vec3().to_array()
}
