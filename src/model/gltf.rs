//! Objects on the sea from glTF 2.0 files (.gltf or .glb): their triangles with the node
//! transforms applied, and their metallic-roughness materials with base-colour and normal-map
//! textures. What the format allows and an object on the sea does not use (skins, morph targets,
//! animation, points and lines, sparse accessors) is refused with one line naming the file and
//! the feature, as is every malformed file: no accessor is read before its bytes are checked to
//! lie inside its buffer, and no vertex leaves here that is not finite.

use crate::error::{Error, Result};
use glam::{Mat3, Mat4, Vec3};
use std::path::{Path, PathBuf};

/// The most triangles one model may hold: 2²² (4.2 million), far past a boat's or a pier's
/// detail at any distance the sea is drawn from, and 200 MiB of vertices at most.
pub const MAX_TRIANGLES: usize = 1 << 22;

/// The largest side of a texture a model may bring (the Vulkan minimum of maxImageDimension2D).
pub const MAX_TEXTURE_SIDE: u32 = 4096;

/// A model's triangles and materials, in its own space (metres, +y up as glTF has it; the scene
/// places it).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub file: PathBuf,
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub textures: Vec<Texture>,
    /// The smallest box holding every vertex: (min, max).
    pub bounds: (Vec3, Vec3),
}

/// Triangles of one material, their node's transform applied.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    /// Unit normals; a primitive without them gets each triangle's own (glTF's rule: flat).
    pub normals: Vec<Vec3>,
    /// The first texture coordinates, zero where the primitive has none.
    pub uvs: Vec<[f32; 2]>,
    /// xyz along +u in the surface, w the bitangent's sign, where the file gives them.
    pub tangents: Option<Vec<[f32; 4]>>,
    /// Three per triangle, counter-clockwise seen from the front (glTF's winding, a node with a
    /// mirroring transform reversed back).
    pub indices: Vec<u32>,
    /// Index into `Model::materials`.
    pub material: usize,
}

/// glTF's metallic-roughness material, as the object pass shades it.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGBA.
    pub base_colour: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    /// Index into `Model::textures` (sRGB).
    pub base_colour_texture: Option<usize>,
    /// Index into `Model::textures` (linear), and the scale of its xy.
    pub normal_texture: Option<(usize, f32)>,
    pub double_sided: bool,
}

impl Default for Material {
    /// glTF's default material: white, fully metallic, fully rough.
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_colour: [1.0; 4],
            metallic: 1.0,
            roughness: 1.0,
            base_colour_texture: None,
            normal_texture: None,
            double_sided: false,
        }
    }
}

/// A texture's texels, RGBA8, row-major from the top-left.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
}

impl Model {
    pub fn triangles(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len() / 3).sum()
    }
}

/// Loads each distinct file of `objects` once: the models, and for each object the index of
/// its model. Errors name the file.
pub fn load_objects(objects: &[crate::model::scene::Object]) -> Result<(Vec<std::sync::Arc<Model>>, Vec<usize>)> {
    let mut files: Vec<PathBuf> = Vec::new();
    let mut models = Vec::new();
    let mut model_of = Vec::new();
    for object in objects {
        let index = match files.iter().position(|f| *f == object.file) {
            Some(i) => i,
            None => {
                models.push(std::sync::Arc::new(load(&object.file)?));
                files.push(object.file.clone());
                files.len() - 1
            }
        };
        model_of.push(index);
    }
    Ok((models, model_of))
}

/// Loads `path` (.gltf with its buffers and images beside it, or .glb).
pub fn load(path: &Path) -> Result<Model> {
    let bad = |message: String| Error::Io { path: path.to_owned(), message };
    if !path.is_file() {
        return Err(bad("no such glTF file".into()));
    }
    let (document, buffers, images) =
        gltf::import(path).map_err(|e| bad(format!("not a readable glTF 2.0 file: {e}")))?;
    if let Some(skin) = document.skins().next() {
        return Err(bad(format!("skins are not supported (skin {})", skin.index())));
    }
    if let Some(animation) = document.animations().next() {
        return Err(bad(format!("animations are not supported (animation {})", animation.index())));
    }
    if let Some(extension) = document.extensions_required().next() {
        return Err(bad(format!("the required extension {extension} is not supported")));
    }
    let scene = document.default_scene().or_else(|| document.scenes().next()).ok_or_else(|| bad("no scene".into()))?;
    let mut textures = Vec::new();
    let mut texture_of_image = vec![None; images.len()];
    let mut texture = |index: usize| -> Result<usize> {
        if let Some(t) = texture_of_image[index] {
            return Ok(t);
        }
        let t = textures.len();
        textures.push(rgba8(&images[index]).map_err(|m| bad(format!("image {index}: {m}")))?);
        texture_of_image[index] = Some(t);
        Ok(t)
    };
    let mut materials: Vec<Material> = Vec::new();
    for m in document.materials() {
        let pbr = m.pbr_metallic_roughness();
        let base_colour_texture =
            pbr.base_color_texture().map(|t| texture(t.texture().source().index())).transpose()?;
        let normal_texture = m
            .normal_texture()
            .map(|t| Ok::<_, Error>((texture(t.texture().source().index())?, t.scale())))
            .transpose()?;
        let material = Material {
            name: m.name().unwrap_or("unnamed").to_owned(),
            base_colour: pbr.base_color_factor(),
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            base_colour_texture,
            normal_texture,
            double_sided: m.double_sided(),
        };
        let factors = material.base_colour.iter().chain([&material.metallic, &material.roughness]);
        if factors.into_iter().any(|v| !v.is_finite()) {
            return Err(bad(format!("material {:?} has a factor that is not finite", material.name)));
        }
        materials.push(material);
    }
    // Primitives without a material take glTF's default, appended once.
    let default_material = materials.len();
    let mut uses_default = false;
    let mut meshes = Vec::new();
    let mut triangles = 0;
    let mut stack: Vec<(gltf::Node, Mat4)> = scene.nodes().map(|n| (n, Mat4::IDENTITY)).collect();
    let mut visited = 0;
    while let Some((node, parent)) = stack.pop() {
        visited += 1;
        if visited > document.nodes().count() {
            return Err(bad("its node hierarchy has a cycle".into()));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        let world = parent * local;
        if !world.is_finite() {
            return Err(bad(format!("node {} has a transform that is not finite", node.index())));
        }
        stack.extend(node.children().map(|c| (c, world)));
        let Some(mesh) = node.mesh() else { continue };
        for primitive in mesh.primitives() {
            let what = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            let mut read = read_primitive(&primitive, &buffers, world).map_err(|m| bad(format!("{what}: {m}")))?;
            triangles += read.indices.len() / 3;
            if triangles > MAX_TRIANGLES {
                return Err(bad(format!("more than {MAX_TRIANGLES} triangles")));
            }
            read.material = primitive.material().index().unwrap_or_else(|| {
                uses_default = true;
                default_material
            });
            meshes.push(read);
        }
    }
    if uses_default {
        materials.push(Material::default());
    }
    if meshes.is_empty() {
        return Err(bad("its scene has no triangles".into()));
    }
    let points = meshes.iter().flat_map(|m| m.positions.iter());
    let bounds = points.fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    Ok(Model { file: path.to_owned(), meshes, materials, textures, bounds })
}

/// One triangle primitive's vertices, transformed by `world`, every accessor checked first.
fn read_primitive(
    primitive: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    world: Mat4,
) -> std::result::Result<Mesh, String> {
    if primitive.mode() != gltf::mesh::Mode::Triangles {
        return Err(format!("{:?} are not supported (triangles only)", primitive.mode()));
    }
    if primitive.morph_targets().next().is_some() {
        return Err("morph targets are not supported".into());
    }
    for (semantic, accessor) in primitive.attributes() {
        check_accessor(&accessor, buffers).map_err(|m| format!("{semantic:?}: {m}"))?;
    }
    if let Some(indices) = primitive.indices() {
        check_accessor(&indices, buffers).map_err(|m| format!("indices: {m}"))?;
    }
    let reader = primitive.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<Vec3> = reader.read_positions().ok_or("no positions")?.map(Vec3::from).collect();
    let count = positions.len();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(indices) => indices.into_u32().collect(),
        None => (0..count as u32).collect(),
    };
    if indices.len() % 3 != 0 {
        return Err(format!("{} indices, not a whole number of triangles", indices.len()));
    }
    if let Some(i) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!("index {i} is out of range ({count} vertices)"));
    }
    let normals: Option<Vec<Vec3>> = reader.read_normals().map(|n| n.map(Vec3::from).collect());
    let uvs: Vec<[f32; 2]> =
        reader.read_tex_coords(0).map(|t| t.into_f32().collect()).unwrap_or_else(|| vec![[0.0; 2]; count]);
    let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
    let finite = |v: &[f32]| v.iter().all(|x| x.is_finite());
    if !positions.iter().all(|p| p.is_finite())
        || !normals.as_ref().is_none_or(|n| n.iter().all(|v| v.is_finite()))
        || !uvs.iter().all(|uv| finite(uv))
        || !tangents.as_ref().is_none_or(|t| t.iter().all(|v| finite(v)))
    {
        return Err("a vertex attribute is not finite".into());
    }
    let lengths = [normals.as_ref().map(Vec::len), Some(uvs.len()), tangents.as_ref().map(Vec::len)];
    if lengths.iter().flatten().any(|&n| n != count) {
        return Err("its attributes have different vertex counts".into());
    }
    let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
    // A mirroring transform turns the winding over: swap two corners to keep the front.
    let mirrored = Mat3::from_mat4(world).determinant() < 0.0;
    let mut mesh = Mesh {
        positions: positions.iter().map(|&p| world.transform_point3(p)).collect(),
        normals: Vec::new(),
        uvs,
        tangents: tangents.map(|t| {
            t.iter()
                .map(|&[x, y, z, w]| {
                    let d = world.transform_vector3(Vec3::new(x, y, z)).normalize_or_zero();
                    [d.x, d.y, d.z, if mirrored { -w } else { w }]
                })
                .collect()
        }),
        indices,
        material: 0,
    };
    if mirrored {
        mesh.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
    }
    match normals {
        Some(n) => mesh.normals = n.iter().map(|&v| (normal_matrix * v).normalize_or(Vec3::Y)).collect(),
        None => flat_normals(&mut mesh),
    }
    if !mesh.positions.iter().all(|p| p.is_finite()) {
        return Err("its vertices leave the range of f32 under the node's transform".into());
    }
    Ok(mesh)
}

/// Gives each triangle its own three vertices and its face's normal (glTF: a primitive without
/// normals is flat-shaded).
fn flat_normals(mesh: &mut Mesh) {
    let (mut positions, mut uvs, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    let mut tangents = mesh.tangents.as_ref().map(|_| Vec::new());
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize]);
        // A degenerate triangle has no face: any unit normal does, it covers no pixel.
        let n = (b - a).cross(c - a).normalize_or(Vec3::Y);
        for &i in t {
            positions.push(mesh.positions[i as usize]);
            uvs.push(mesh.uvs[i as usize]);
            normals.push(n);
            if let (Some(out), Some(all)) = (tangents.as_mut(), mesh.tangents.as_ref()) {
                out.push(all[i as usize]);
            }
        }
    }
    mesh.indices = (0..positions.len() as u32).collect();
    (mesh.positions, mesh.uvs, mesh.normals, mesh.tangents) = (positions, uvs, normals, tangents);
}

/// Err unless every byte `accessor` reads lies inside its buffer view and the view inside its
/// buffer (the reader would slice past them), and it is not sparse.
fn check_accessor(accessor: &gltf::Accessor, buffers: &[gltf::buffer::Data]) -> std::result::Result<(), String> {
    if accessor.sparse().is_some() {
        return Err("sparse accessors are not supported".into());
    }
    let Some(view) = accessor.view() else { return Err("an accessor without a buffer view".into()) };
    let data = buffers.get(view.buffer().index()).ok_or("a buffer that is not loaded")?;
    let view_end = view.offset().checked_add(view.length()).ok_or("a buffer view out of range")?;
    if view_end > data.0.len() {
        return Err(format!("buffer view {} ends at byte {view_end}, its buffer has {}", view.index(), data.0.len()));
    }
    let element = accessor.size();
    let stride = view.stride().unwrap_or(element);
    let count = accessor.count();
    let end = match count {
        0 => accessor.offset(),
        _ => (count - 1)
            .checked_mul(stride)
            .and_then(|s| s.checked_add(accessor.offset() + element))
            .ok_or("overflow")?,
    };
    if end > view.length() {
        return Err(format!("accessor {} reads {end} bytes of a {}-byte buffer view", accessor.index(), view.length()));
    }
    Ok(())
}

/// An image's texels as RGBA8 (8-bit formats; 16 and 32-bit ones are refused).
fn rgba8(image: &gltf::image::Data) -> std::result::Result<Texture, String> {
    use gltf::image::Format as F;
    let (width, height) = (image.width, image.height);
    if width == 0 || height == 0 || width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(format!("{width}x{height} texels, outside 1 to {MAX_TEXTURE_SIDE} a side"));
    }
    let channels = match image.format {
        F::R8 => 1,
        F::R8G8 => 2,
        F::R8G8B8 => 3,
        F::R8G8B8A8 => 4,
        other => return Err(format!("{other:?} texels are not supported (8-bit textures only)")),
    };
    let pixels = width as usize * height as usize;
    if image.pixels.len() != pixels * channels {
        return Err("its texels do not fill its size".into());
    }
    let rgba = image
        .pixels
        .chunks_exact(channels)
        .flat_map(|p| match channels {
            1 => [p[0], p[0], p[0], 255],
            2 => [p[0], p[1], 0, 255],
            3 => [p[0], p[1], p[2], 255],
            _ => [p[0], p[1], p[2], p[3]],
        })
        .collect();
    Ok(Texture { width, height, rgba })
}
