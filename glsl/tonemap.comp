#version 450
// Linear HDR radiance -> display: L' = 1 - exp(-exposure L) per channel (the authors' demo curve),
// then the sRGB transfer function (IEC 61966-2-1), packed as 8-bit RGBA straight into the host
// readback buffer (row-major from the top-left): no LDR image, no copy.
#include "frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 4, rgba16f) readonly uniform image2D hdr;
layout(set = 0, binding = 5, std430) writeonly buffer Ldr { uint ldr[]; };

vec3 srgb_encode(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

void main() {
    ivec2 size = imageSize(hdr);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    vec3 radiance = imageLoad(hdr, p).rgb;
    vec3 mapped = 1.0 - exp(-frame.tone.x * max(radiance, vec3(0.0)));
    ldr[p.y * size.x + p.x] = packUnorm4x8(vec4(srgb_encode(clamp(mapped, 0.0, 1.0)), 1.0));
}
