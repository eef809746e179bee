#version 450
// Level 0 of the mirrored objects' inverse depth (src/render/passes/planar.rs): where the host
// drew a mirrored object, 1 / its forward depth along the pixel's ray (1/m), else 0, so that the
// mean of a footprint (planar_mip.comp's levels) over its coverage (the colour's alpha there) is
// the footprint's harmonic mean depth.
#include "frame.glsl"
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1) uniform sampler2D mirror_depth;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D inverse_depth;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(inverse_depth);
    if (any(greaterThanEqual(p, size))) return;
    float depth = texelFetch(mirror_depth, p, 0).r;
    vec3 ray = camera_ray((vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0);
    // The host's projection inverted along the ray, as glsl/reflection_sources.comp does: at
    // forward depth t its depth is (a t + b) / (c t + d).
    vec4 along = frame.host_clip * vec4(ray, 0.0);
    vec4 at_eye = frame.host_clip[3];
    float denominator = depth * along.w - along.z;
    float t = denominator != 0.0 ? (at_eye.z - depth * at_eye.w) / denominator : 0.0;
    bool object = depth != frame.host.z && t > 0.0;
    imageStore(inverse_depth, p, vec4(object ? 1.0 / t : 0.0));
}
