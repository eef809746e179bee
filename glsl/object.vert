#version 450
// An object's triangles, vertices pulled from its model's buffer by index, placed by its
// instance (src/app/objects), seen from the eye (or its mirror image, MIRROR in object.glsl) or,
// as a shadow caster, from the sun.
#include "object.glsl"

// The objects drawn from the sun into its shadow map (depth only), not from the eye.
layout(constant_id = 0) const bool SUN_VIEW = false;

layout(location = 0) out vec3 out_relative;   // eye-relative world position
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec4 out_tangent;
layout(location = 3) out vec2 out_uv;
layout(location = 4) flat out uint out_instance;

void main() {
    Vertex v = vertices[gl_VertexIndex];
    Instance o = instances[gl_InstanceIndex];
    vec4 relative = o.relative_from_model * vec4(v.position_u.xyz, 1.0);
    mat3 normal_matrix = transpose(mat3(o.normal_from_model[0].xyz, o.normal_from_model[1].xyz,
                                        o.normal_from_model[2].xyz));
    vec4 placed = relative;
    if (MIRROR) {
        vec4 plane = o.mirror_plane;
        placed.xyz -= 2.0 * (dot(plane.xyz, relative.xyz) - plane.w) * plane.xyz;
    }
    gl_Position = (SUN_VIEW ? frame.sun_clip_from_relative : frame.clip_from_relative) * placed;
    out_relative = relative.xyz;
    out_normal = normal_matrix * v.normal_v.xyz;
    out_tangent = vec4(mat3(o.relative_from_model) * v.tangent.xyz, v.tangent.w);
    out_uv = vec2(v.position_u.w, v.normal_v.w);
    out_instance = gl_InstanceIndex;
}
