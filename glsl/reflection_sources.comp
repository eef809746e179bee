#version 450
// What the sea may reflect locally (src/render/passes/reflections.rs): the host's objects, read
// from its colour and depth after it drew them, where the sea does not hide them (a hull's
// underwater part is no reflector: the sea's own depth from the visibility pass decides). Level 0 of two pyramids at the host's size:
// the objects' radiance premultiplied by their coverage (alpha 1 on an object, 0 elsewhere; its
// mipmap is then each footprint's mean radiance and the share of it the objects cover), and
// their forward depth along the view (metres; NO_OBJECT where the host drew none), whose mips
// keep the nearest (reflection_depth_mip.comp).
#include "frame.glsl"
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1) uniform sampler2D host_colour;
layout(set = 0, binding = 2) uniform sampler2D host_depth;
layout(set = 0, binding = 3, rgba16f) uniform writeonly image2D source_colour;
layout(set = 0, binding = 4, r32f) uniform writeonly image2D source_depth;
// The sea's depth (reversed Z: near / forward depth; 0 where no sea: the sky).
layout(set = 0, binding = 5) uniform sampler2D sea_depth;

// Farther than any object: a pyramid cell without objects never stops a ray.
const float NO_OBJECT = 3.0e38;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(source_colour);
    if (any(greaterThanEqual(p, size))) return;
    float depth = texelFetch(host_depth, p, 0).r;
    vec3 ray = camera_ray((vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0);
    // The host's projection along the pixel's ray (unit forward component): at forward depth t
    // its depth is (a t + b) / (c t + d), so t = (b - depth d) / (depth c - a), for any
    // perspective, reversed or not, finite or infinite.
    vec4 along = frame.host_clip * vec4(ray, 0.0);
    vec4 at_eye = frame.host_clip[3];
    float denominator = depth * along.w - along.z;
    float t = denominator != 0.0 ? (at_eye.z - depth * at_eye.w) / denominator : 0.0;
    // The cleared far plane (and a depth beyond it) holds no object, nor does a point under the
    // sea in front of it.
    float sea = texelFetch(sea_depth, p, 0).r;
    float sea_t = sea > 0.0 ? frame.shadow.x / sea : NO_OBJECT;
    bool object = depth != frame.host.z && t > 0.0 && t < sea_t;
    vec3 radiance = clamp(texelFetch(host_colour, p, 0).rgb / frame.host.x, vec3(0.0), vec3(HDR_MAX));
    imageStore(source_colour, p, object ? vec4(radiance, 1.0) : vec4(0.0));
    imageStore(source_depth, p, vec4(object ? t : NO_OBJECT));
}
