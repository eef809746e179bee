// Where a sea point starts into the mirror's world of the planar reflections (passes/planar.rs),
// and whether any mirrored object lies within the widest search around it: shared by the shading
// pass (shade.glsl mirror_start) and the classification of its tiles (planar_tiles.comp), so that
// the two decide alike. Requires frame.glsl, planet.glsl (sea_point) and, declared before it,
// `planar_inverse_depth`: the mirrored objects' coverage and coverage over forward depth,
// mipmapped by means (the mirror's colour has the same size and levels).
#ifndef PLANAR_START_GLSL
#define PLANAR_START_GLSL

// A sea point's start into the mirror's world: the point mirrored about the mean sea, its forward
// depth and its pixel in the mirror's images.
struct MirrorStart { vec3 point; float z0; vec2 s; };

// Mip levels searched, every other one, for mirrored objects near a point's own pixel: the
// farthest, 2^8 pixels on, is as far as a 2-sigma slope of 0.4 turns a reflection on a 1024-pixel
// view.
const int PLANAR_SEARCH_LEVELS = 8;

// The pixel position (in the reflection images' base level) of camera-relative point q at
// forward depth z = q . forward (> 0).
vec2 reflection_screen(vec3 q, float z, vec2 size) {
    vec3 right = frame.cam_right.xyz, down = frame.cam_down.xyz;
    vec2 ndc = vec2(dot(q, right) / dot(right, right), dot(q, down) / dot(down, down)) / z;
    return (ndc * 0.5 + 0.5) * size;
}

// The mirrored objects' coverage and harmonic mean forward depth over the footprint of `level`
// at pixel s (0 coverage: none there).
vec2 planar_depth(vec2 s, int level) {
    // The level's size by arithmetic (textureSize at a level that differs between lanes is not
    // to be trusted).
    ivec2 cells = max(textureSize(planar_inverse_depth, 0) >> level, ivec2(1));
    ivec2 cell = clamp(ivec2(floor(s / float(1 << level))), ivec2(0), cells - 1);
    vec2 texel = texelFetch(planar_inverse_depth, cell, level).xy;
    return texel.y > 0.0 ? vec2(texel.x, texel.x / texel.y) : vec2(0.0);
}

// The start of camera-relative sea point `point` (sphere normal `up`) into the mirror's world,
// and whether it may see a mirrored object: false where it lies behind the eye's plane or no
// object covers the widest search's cell around its pixel (most of the sea, at one read).
bool planar_start(vec3 point, vec3 up, out MirrorStart start) {
    start.point = point;
    start.z0 = 0.0;
    start.s = vec2(0.0);
    vec2 size = vec2(textureSize(planar_inverse_depth, 0));
    // The mirror world is the mean sea's: the point, on a wave, mirrors to as far below it (an
    // object is cut at the water it stands in, its floating hull's waterline above or below).
    start.point = point - 2.0 * dot(point - sea_point(point.xy), up) * up;
    start.z0 = dot(start.point, frame.cam_forward.xyz);
    if (!(start.z0 > 0.0)) return false;
    start.s = clamp(reflection_screen(start.point, start.z0, size), vec2(0.0), size - 1e-3);
    int top = textureQueryLevels(planar_inverse_depth) - 1;
    return planar_depth(start.s, min(PLANAR_SEARCH_LEVELS, top)).x != 0.0;
}

#endif
