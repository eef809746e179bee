#version 450
// Level 0 of the stereographic sky map: texel centre u in [-R, R]^2 -> direction. Texels beyond the
// unit disc take the folded (mirrored) direction, so filtering across the horizon stays smooth.
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D sky_level0;

void main() {
    ivec2 size = imageSize(sky_level0);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, size))) return;
    vec2 uv = (vec2(texel) + 0.5) / vec2(size);
    vec2 u = (uv * 2.0 - 1.0) * frame.tone.y;
    vec3 dir = inverse_stereographic(u);
    dir.z = abs(dir.z);
    imageStore(sky_level0, texel, vec4(store_radiance(sky_radiance(dir)), 1.0));
}
