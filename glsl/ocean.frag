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
    // pixel's own ray gives the exact point, and its depth (reversed Z, near frame.shadow.x:
    // near / view depth, the view depth the distance over |ray| as camera_ray has unit length
    // along the view), which the shadows and a host's composite read. FAR_LIMIT guards an
    // interpolation gone wrong.
    // A triangle only some of whose nodes are displaced lies where trains start to be resolved,
    // their displacement still near nothing (the weights ramp from 0), but it may still span a
    // limb's cell: its depth is the sphere's too, its rest positions the triangle's.
    vec2 x = in_rest.xy;
    gl_FragDepth = gl_FragCoord.z;
    if (in_rest.z < 0.999) {
        vec3 ray = camera_ray(pixel_to_ndc(gl_FragCoord.xy));
        float len = length(ray);   // >= 1
        vec3 u = onto_sea(ray / len);
        vec2 hit = sea_distance(u);
        if (in_rest.z <= 0.0) x = hit.x * u.xy;
        // hit.x > 0 (the sea lies below the eye); the depth stays within [0, 1] near the eye.
        gl_FragDepth = min(frame.shadow.x * len / hit.x, 1.0);
    }
    if (!all(lessThan(abs(x), vec2(FAR_LIMIT)))) x = vec2(FAR_LIMIT);
    out_rest_bits = rest_position_to_bits(x);
}
