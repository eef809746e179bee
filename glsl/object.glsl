// The object pass's bindings (src/app/objects): the frame's light and camera, each object's
// placement, and the drawn model's vertices and material.

const int IRRADIANCE_ROWS = 17;
const int IRRADIANCE_COLUMNS = 32;

// Set 0: the frame (one window of the ring per frame slot, dynamic offsets).
layout(set = 0, binding = 0) uniform ObjectFrame {
    // Eye-relative world (z up, metres) to clip space.
    mat4 clip_from_relative;
    // xyz: towards the sun; w: the sun disc's angular radius (rad).
    vec4 sun_direction;
    // rgb: the sun's irradiance on a surface facing it (host unit x sr); w: the colour
    // format's largest finite value.
    vec4 sun_irradiance;
    // Eye-relative world to the sun's shadow map's clip space (embed::Ocean::sun_shadow).
    mat4 sun_clip_from_relative;
    // x: 1 where the map holds the sun's view this frame, 0 where everything is lit.
    vec4 shadow;
    // The environment's irradiance on a surface of each normal: rows of zenith angles from the
    // zenith to the nadir, columns of azimuths from +x (model::environment's table).
    vec4 irradiance[IRRADIANCE_ROWS * IRRADIANCE_COLUMNS];
} frame;

struct Instance {
    mat4 relative_from_model;
    // Rows of the normal matrix (the inverse transpose of the model's 3x3, unit scale).
    vec4 normal_from_model[3];
    // rgb: the air's in-scatter between the eye and the object; w unused.
    vec4 inscatter;
    // rgb: the air's transmittance over that path.
    vec4 transmittance;
    // The same between the object and the sea that mirrors it into the eye (its mirror image's:
    // the shading sees that sea through the air between it and the eye).
    vec4 mirror_inscatter;
    vec4 mirror_transmittance;
    // The mean sea's tangent plane below the object, which it is mirrored about for the sea's
    // planar reflections: xyz its unit normal n, w its offset (n . x = w on it).
    vec4 mirror_plane;
    // The water's plane at the object, the same way: what lies below it is under water, and not
    // mirrored (a floating hull's waterline, which rides above or below the mean sea).
    vec4 water_plane;
};
layout(std430, set = 0, binding = 1) readonly buffer Instances { Instance instances[]; };
// The sun's shadow map: the waves and every object, seen from the sun (depth 0 nearest it).
layout(set = 0, binding = 2) uniform sampler2DShadow sun_shadow_map;

// Set 1: the model's vertices (pulled by index) and a material's textures.
struct Vertex {
    vec4 position_u;    // xyz, the texture's u
    vec4 normal_v;      // xyz, the texture's v
    vec4 tangent;       // xyz along +u, w the bitangent's sign (0: the model gives none)
};
layout(std430, set = 1, binding = 0) readonly buffer Vertices { Vertex vertices[]; };
layout(set = 1, binding = 1) uniform sampler2D base_colour_texture;
layout(set = 1, binding = 2) uniform sampler2D normal_texture;

// The objects drawn mirrored about the sea (embed::Ocean::record_planar): placed at their mirror
// images, lit where they stand, seen from the mirrored eye, and only above the sea.
layout(constant_id = 1) const bool MIRROR = false;

layout(push_constant) uniform Material {
    vec4 base_colour;
    // x metallic, y roughness, z the normal map's xy scale (0: none), w unused.
    vec4 surface;
} material;
