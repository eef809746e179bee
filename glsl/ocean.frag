#version 450
// The projected grid's visibility pass: each pixel keeps the rest position (horizontal offset from
// the eye, on the sea's mean sphere) of the nearest displaced surface point, for the shading pass
// (shade.comp). The shading runs once per pixel there, not once per rasterized 2x2 or 4x4 block
// of each small grid triangle, which would shade most pixels two to three times over at 8-pixel
// cells.
#include "frame.glsl"
#include "common.glsl"
#include "planet.glsl"

layout(location = 0) in vec3 in_rest;
// The bits of the rest position as RGBA16 words (the HDR image's texels, reinterpreted).
layout(location = 0) out uvec4 out_rest_bits;

void main() {
    // Where no node of the triangle is displaced the surface is the sphere itself, which the flat
    // triangle only approximates (by metres near the limb, where a cell spans kilometres): the
    // pixel's own ray gives the exact point. FAR_LIMIT guards an interpolation gone wrong.
    vec2 x = in_rest.z > 0.0 ? in_rest.xy : mean_sea_point(camera_ray(pixel_to_ndc(gl_FragCoord.xy)));
    if (!all(lessThan(abs(x), vec2(FAR_LIMIT)))) x = vec2(FAR_LIMIT);
    out_rest_bits = rest_position_to_bits(x);
}
