//! Objects from glTF files (model::gltf): hand-written files this project has never seen, with
//! node transforms (a mirroring one among them), with and without normals, indices and
//! textures, and broken ones, each refused in one line naming the file and the reason.

use glam::Vec3;
use ocean::model::gltf::load;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// A folder of its own for each test's files.
fn folder(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ocean-gltf-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `document` as `name.gltf` with `bin` as its one buffer, `name.bin`.
fn write(dir: &Path, name: &str, mut document: Value, bin: &[u8]) -> PathBuf {
    document["asset"] = json!({ "version": "2.0" });
    document["buffers"] = json!([{ "uri": format!("{name}.bin"), "byteLength": bin.len() }]);
    std::fs::write(dir.join(format!("{name}.bin")), bin).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_string_pretty(&document).unwrap()).unwrap();
    path
}

fn bytes_f32(values: &[f32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// One triangle in z = 0, counter-clockwise seen from +z: positions (and, with `indices`, a
/// u16 index list), in the buffer from byte 0.
fn triangle(indices: Option<[u16; 3]>) -> (Value, Vec<u8>) {
    let mut bin = bytes_f32(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let mut views = vec![json!({ "buffer": 0, "byteOffset": 0, "byteLength": 36 })];
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
        "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]
    })];
    let mut primitive = json!({ "attributes": { "POSITION": 0 } });
    if let Some(i) = indices {
        bin.extend(i.iter().flat_map(|v| v.to_le_bytes()));
        views.push(json!({ "buffer": 0, "byteOffset": 36, "byteLength": 6 }));
        accessors.push(json!({ "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }));
        primitive["indices"] = json!(1);
    }
    let document = json!({
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [primitive] }],
        "bufferViews": views,
        "accessors": accessors,
    });
    (document, bin)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn node_transforms_place_the_triangles_and_a_mirror_keeps_their_front() {
    let dir = folder("transforms");
    let (mut document, bin) = triangle(None);
    // A parent moved and turned a quarter about +y, its child scaled by -1 along x (a mirror).
    let quarter = std::f32::consts::FRAC_1_SQRT_2;
    document["scenes"] = json!([{ "nodes": [1] }]);
    document["nodes"] = json!([
        { "mesh": 0, "scale": [-1.0, 1.0, 1.0] },
        { "mesh": 0, "translation": [10.0, 2.0, -3.0], "rotation": [0.0, quarter, 0.0, quarter], "children": [0] }
    ]);
    let model = load(&write(&dir, "transforms", document, &bin)).unwrap();
    assert_eq!((model.meshes.len(), model.triangles(), model.materials.len()), (2, 2, 1), "{model:?}");
    assert_eq!(model.materials[0].metallic, 1.0, "glTF's default material");
    // The parent: x -> -z, z -> x under the quarter turn about +y, then the translation.
    let holding = |p: Vec3| model.meshes.iter().find(|m| m.positions.iter().any(|q| close(*q, p)));
    let parent = holding(Vec3::new(10.0, 2.0, -4.0)).expect("the parent's");
    let child = holding(Vec3::new(10.0, 2.0, -2.0)).expect("the child's");
    assert!(!std::ptr::eq(parent, child));
    for mesh in [parent, child] {
        assert_eq!(mesh.indices.len(), 3);
        // Flat normals (the file has none): the face's, +z turned to +x, the mirror's included.
        for n in &mesh.normals {
            assert!(close(*n, Vec3::X), "normal {n} of {mesh:?}");
        }
        let t: Vec<Vec3> = mesh.indices.iter().map(|&i| mesh.positions[i as usize]).collect();
        assert!((t[1] - t[0]).cross(t[2] - t[0]).dot(Vec3::X) > 0.0, "the winding faces the normal: {t:?}");
    }
    let (lo, hi) = model.bounds;
    assert!(close(lo, Vec3::new(10.0, 2.0, -4.0)) && close(hi, Vec3::new(10.0, 3.0, -2.0)), "{lo} {hi}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn normals_uvs_materials_and_textures_are_read() {
    let dir = folder("textured");
    let (mut document, mut bin) = triangle(Some([0, 1, 2]));
    bin.resize(44, 0); // 4-byte alignment after the indices
    let normals = bytes_f32(&[0.0, 0.0, 2.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let uvs = bytes_f32(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0]);
    let (n_at, uv_at) = (bin.len(), bin.len() + normals.len());
    bin.extend(&normals);
    bin.extend(&uvs);
    document["bufferViews"].as_array_mut().unwrap().extend([
        json!({ "buffer": 0, "byteOffset": n_at, "byteLength": normals.len() }),
        json!({ "buffer": 0, "byteOffset": uv_at, "byteLength": uvs.len() }),
    ]);
    document["accessors"].as_array_mut().unwrap().extend([
        json!({ "bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3" }),
        json!({ "bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC2" }),
    ]);
    let primitive = &mut document["meshes"][0]["primitives"][0];
    primitive["attributes"]["NORMAL"] = json!(2);
    primitive["attributes"]["TEXCOORD_0"] = json!(3);
    primitive["material"] = json!(0);
    // A 2x1 PNG: red, then half-transparent green.
    let png = image::RgbaImage::from_raw(2, 1, vec![255, 0, 0, 255, 0, 255, 0, 128]).unwrap();
    png.save(dir.join("paint.png")).unwrap();
    document["images"] = json!([{ "uri": "paint.png" }]);
    document["textures"] = json!([{ "source": 0 }]);
    document["materials"] = json!([{
        "name": "hull",
        "pbrMetallicRoughness": {
            "baseColorFactor": [0.5, 0.25, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.4,
            "baseColorTexture": { "index": 0 }
        },
        "normalTexture": { "index": 0, "scale": 0.5 },
        "doubleSided": true
    }]);
    document["nodes"][0]["scale"] = json!([2.0, 2.0, 2.0]);
    let model = load(&write(&dir, "textured", document, &bin)).unwrap();
    let mesh = &model.meshes[0];
    assert_eq!(mesh.indices, vec![0, 1, 2]);
    assert!(mesh.normals.iter().all(|n| close(*n, Vec3::Z)), "unit normals: {:?}", mesh.normals);
    assert_eq!(mesh.uvs[1], [1.0, 0.0]);
    assert!(close(mesh.positions[2], Vec3::new(0.0, 2.0, 0.0)));
    let m = &model.materials[mesh.material];
    assert_eq!((m.name.as_str(), m.base_colour, m.metallic, m.roughness), ("hull", [0.5, 0.25, 1.0, 1.0], 0.0, 0.4));
    assert_eq!((m.base_colour_texture, m.normal_texture, m.double_sided), (Some(0), Some((0, 0.5)), true));
    assert_eq!(model.textures.len(), 1, "one image, read once");
    assert_eq!(model.textures[0].rgba, vec![255, 0, 0, 255, 0, 255, 0, 128]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn broken_files_are_refused_in_one_line_naming_the_file() {
    let dir = folder("broken");
    let refused = |path: &Path, why: &str| {
        let error = load(path).expect_err(why).to_string();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(error.contains(&name) && error.contains(why) && !error.contains('\n'), "{why}: {error}");
    };
    refused(&dir.join("missing.gltf"), "no such glTF file");
    std::fs::write(dir.join("text.gltf"), "this is not glTF").unwrap();
    refused(&dir.join("text.gltf"), "not a readable glTF 2.0 file");

    let (document, bin) = triangle(Some([0, 1, 3]));
    refused(&write(&dir, "index", document, &bin), "index 3 is out of range (3 vertices)");

    let (document, mut bin) = triangle(None);
    bin[4..8].copy_from_slice(&f32::NAN.to_le_bytes());
    refused(&write(&dir, "nan", document, &bin), "not finite");

    let (mut document, bin) = triangle(None);
    document["accessors"][0]["count"] = json!(4);
    refused(&write(&dir, "overrun", document, &bin), "reads 48 bytes of a 36-byte buffer view");

    let (mut document, bin) = triangle(None);
    document["nodes"][0]["translation"] = json!([3e38, 0.0, 0.0]);
    document["nodes"][0]["scale"] = json!([1e38, 1.0, 1.0]);
    refused(&write(&dir, "huge", document, &bin), "leave the range of f32");

    let (mut document, bin) = triangle(None);
    document["meshes"][0]["primitives"][0]["mode"] = json!(1);
    refused(&write(&dir, "lines", document, &bin), "are not supported (triangles only)");

    let (mut document, bin) = triangle(None);
    document["meshes"][0]["primitives"][0]["targets"] = json!([{ "POSITION": 0 }]);
    refused(&write(&dir, "morph", document, &bin), "morph targets are not supported");

    let (mut document, bin) = triangle(None);
    document["skins"] = json!([{ "joints": [0] }]);
    document["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = json!(0);
    refused(&write(&dir, "skin", document, &bin), "skins are not supported");

    let (mut document, bin) = triangle(None);
    document["animations"] = json!([{
        "channels": [{ "sampler": 0, "target": { "node": 0, "path": "translation" } }],
        "samplers": [{ "input": 0, "output": 0 }]
    }]);
    refused(&write(&dir, "animated", document, &bin), "animations are not supported");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The project's own models (scripts/make_models.py, in scenes/models/): each loads, has the size
/// it is made to, stands through its waterline, and faces outwards: a positive enclosed volume
/// (the divergence theorem over its triangles, each wound counter-clockwise from outside), and
/// face by face, a ray leaving a face along its normal crosses the rest of its mesh an even
/// number of times (it starts outside). Parts of one mesh that touch or overlap (a boom inside
/// its mast, a deckhouse on a deckhouse) make the rays of their buried faces odd: at most 5% of
/// the area (the ship's two deckhouses are 4.3%; the boat's deck wound inwards was 22%).
#[test]
fn our_models_load_at_their_sizes_and_face_outwards() {
    // name, (length along x, height along y) in metres, roughly.
    let expected = [("boat", (6.0, 9.9)), ("pier", (30.0, 8.0)), ("buoy", (1.0, 2.4)), ("ship", (120.0, 34.0))];
    for (name, (length, height)) in expected {
        let model = load(Path::new(&format!("scenes/models/{name}.gltf"))).unwrap();
        let (lo, hi) = model.bounds;
        let size = hi - lo;
        assert!((size.x / length - 1.0).abs() < 0.1 && (size.y / height - 1.0).abs() < 0.1, "{name}: {size}");
        assert!(lo.y < 0.0 && hi.y > 0.0, "{name} stands through its waterline: {lo} {hi}");
        let mut volume = 0.0;
        for mesh in &model.meshes {
            assert!(mesh.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-4), "{name}: unit normals");
            for t in mesh.indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[t[k] as usize].as_dvec3());
                volume += a.dot((b - a).cross(c - a)) / 6.0;
            }
        }
        let (mut inward, mut area) = (0.0, 0.0);
        for mesh in &model.meshes {
            let triangles: Vec<[glam::Vec3; 3]> =
                mesh.indices.chunks_exact(3).map(|t| [0, 1, 2].map(|k| mesh.positions[t[k] as usize])).collect();
            let bvh = ocean::model::bvh::build(&triangles);
            for t in &triangles {
                let [a, b, c] = t.map(|p| p.as_dvec3());
                let normal = (b - a).cross(c - a);
                let (centroid, n) = ((a + b + c) / 3.0, normal.normalize());
                // Off the normal by a hair, so that the ray misses edges it would graze.
                let dir = (n + glam::DVec3::new(1e-3, 2e-3, 3e-3)).normalize();
                let (mut origin, mut crossings) = (centroid + n * 1e-4, 0);
                while let Some(hit) = bvh.intersect(origin, dir, 1e-6, f64::INFINITY) {
                    crossings += 1;
                    origin += dir * hit.t;
                }
                area += normal.length() / 2.0;
                if crossings % 2 == 1 {
                    inward += normal.length() / 2.0;
                }
            }
        }
        assert!(inward <= 0.05 * area, "{name}: {:.1}% of the area faces inwards", 100.0 * inward / area);
        let bounding = (size.x * size.y * size.z) as f64;
        assert!(volume > 0.01 * bounding && volume < bounding, "{name}: volume {volume} of {bounding}");
        assert!(model.materials.iter().all(|m| m.roughness > 0.0 && m.base_colour[3] == 1.0), "{name}");
    }
}
