#version 450
// Linear HDR radiance -> display (tone.glsl), packed as 8-bit RGBA straight into the host
// readback buffer (row-major from the top-left): no LDR image, no copy.
#include "frame.glsl"
#include "tone.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 4, rgba16f) readonly uniform image2D hdr;
layout(set = 0, binding = 5, std430) writeonly buffer Ldr { uint ldr[]; };

void main() {
    ivec2 size = imageSize(hdr);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    vec3 mapped = tone_map(imageLoad(hdr, p).rgb);
    ldr[p.y * size.x + p.x] = packUnorm4x8(vec4(srgb_encode(mapped), 1.0));
}
