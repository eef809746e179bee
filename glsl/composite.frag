#version 450
// The ocean into a host's frame (src/render/passes/composite.rs): each pixel's shaded radiance
// written to the host's HDR colour attachment, depth-tested against the host's depth buffer with
// the sea's depth in the host's own projection, so that the host's objects drawn before hide the
// sea and the sea hides their submerged parts. Sky pixels (no sea) lie at the host's far plane:
// they pass only where the host drew nothing, and only when the host asked for the sky.
#include "frame.glsl"
#include "common.glsl"

// The ocean shaders' constant (ShaderConfig::specialization): whether the sky is drawn where the
// host drew nothing (embed::OceanDesc::sky).
layout(constant_id = 5) const bool BACKGROUND = true;
layout(set = 0, binding = 2) uniform sampler2D radiance;
// The visibility pass's depth (reversed Z, infinite far, frame.shadow.x the near plane): 0 where
// no grid triangle covered the pixel.
layout(set = 0, binding = 3) uniform sampler2D sea_depth;
layout(location = 0) out vec4 out_color;

void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    float depth = texelFetch(sea_depth, texel, 0).r;
    if (depth > 0.0) {
        // camera_ray has unit length along the view, and the view depth is near / depth (> 0;
        // exact where the grid is undisplaced, glsl/ocean.frag).
        vec3 point = camera_ray(pixel_to_ndc(gl_FragCoord.xy)) * (frame.shadow.x / depth);
        vec4 clip = frame.host_clip * vec4(point, 1.0);
        // The point lies in front of the eye (view depth >= near), so clip.w > 0 for any
        // perspective projection of the same camera; past a finite far plane it is the far plane.
        gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);
    } else if (BACKGROUND) {
        gl_FragDepth = frame.host.z;
    } else {
        discard;
    }
    // The radiance in the host's unit, held to what its format stores (frame.host.y).
    vec3 L = texelFetch(radiance, texel, 0).rgb * frame.host.x;
    out_color = vec4(min(max(L, vec3(0.0)), vec3(frame.host.y)), 1.0);
}
