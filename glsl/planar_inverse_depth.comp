#version 450
// Level 0 of the mirrored objects' coverage and inverse depth (src/render/passes/planar.rs): x 1
// where the host drew a mirrored object, y 1 / its forward depth along the pixel's ray (1/m),
// both 0 elsewhere, so that over any footprint of planar_mip.comp's levels x is the share the
// objects cover and x / y their harmonic mean depth. (The colour's alpha, mipmapped by blits,
// drops an odd level's trailing texels and with them a small object's coverage.)
#include "frame.glsl"
#include "common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1) uniform sampler2D mirror_depth;
layout(set = 0, binding = 2, rgba16f) uniform writeonly image2D inverse_depth;

// The texels written: origin <= p < end, where the host's mirrored objects may lie
// (src/render/passes/mod.rs dispatch_within); the pass clears the rest.
layout(push_constant) uniform Region { ivec2 origin; ivec2 end; } region;

void main() {
    ivec2 p = region.origin + ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(inverse_depth);
    if (any(greaterThanEqual(p, min(size, region.end)))) return;
    float depth = texelFetch(mirror_depth, p, 0).r;
    vec3 ray = camera_ray((vec2(p) + 0.5) / vec2(size) * 2.0 - 1.0);
    // The host's projection inverted along the ray, as glsl/reflection_sources.comp does: at
    // forward depth t its depth is (a t + b) / (c t + d).
    vec4 along = frame.host_clip * vec4(ray, 0.0);
    vec4 at_eye = frame.host_clip[3];
    float denominator = depth * along.w - along.z;
    float t = denominator != 0.0 ? (at_eye.z - depth * at_eye.w) / denominator : 0.0;
    bool object = depth != frame.host.z && t > 0.0;
    imageStore(inverse_depth, p, object ? vec4(1.0, 1.0 / t, 0.0, 0.0) : vec4(0.0));
}
