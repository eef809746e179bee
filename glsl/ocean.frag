#version 450
// The projected grid's visibility pass: each pixel keeps the rest position (camera-relative, on
// the mean sea plane) of the nearest displaced surface point, for the shading pass (shade.comp).
// The shading runs once per pixel there, not once per rasterized 2x2 or 4x4 block of each small
// grid triangle, which would shade most pixels two to three times over at 8-pixel cells.
#include "frame.glsl"
#include "common.glsl"

layout(location = 0) in vec3 in_rest_h;
// The bits of the rest position as RGBA16 words (the HDR image's texels, reinterpreted).
layout(location = 0) out uvec4 out_rest_bits;

void main() {
    // Only where the interpolated w is positive is the pixel at a finite distance; the rest
    // position can only run off to infinity on the horizon row. FAR_LIMIT stands for "sea, but
    // too far for any train to be resolved" and also replaces an overflowed (Inf) quotient.
    vec2 x = in_rest_h.z > 0.0 ? in_rest_h.xy / in_rest_h.z : vec2(FAR_LIMIT);
    if (!all(lessThan(abs(x), vec2(FAR_LIMIT)))) x = vec2(FAR_LIMIT);
    out_rest_bits = rest_position_to_bits(x);
}
