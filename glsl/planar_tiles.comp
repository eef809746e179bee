#version 450
// The sea-only rows' 8x8 tiles of the shading pass, sorted by whether any of their pixels may
// mirror an object (src/render/passes/planar_tiles.rs): list 0 is shaded by the pipeline that
// reads the mirror images, list 1 by the one without that code. A CPU driver runs every branch
// of a shader for all lanes, masked, so the mirror's code costs each pixel of the view, though
// few read it; a GPU skips it per wave, and its registers weigh on every pixel.
//
// One invocation per tile, from the camera and the waves' bound alone. A pixel may mirror an
// object where shade.glsl's mirror_start finds one in the widest search's cell of its mirrored
// point P' = P - 2 h up, P its surface point on its ray and h that point's height over the mean
// sea, |h| <= A (frame.wave_extent.y, the summed amplitudes). For one h, the tile's rays meet the
// sphere raised by h on a patch of it, and the eye sees that patch's mirror image through a map
// that is projective to within the sphere's curvature over a tile: the images of the tile's
// corners bound those of its pixels. Over h, each ray's P' moves along a line. So the images of
// the 4 corners at h = -A and +A bound every pixel's P', and a tile whose bounding box (grown by
// a pixel: the shading pass's sphere normal is taken where its ray meets the surface it resolves,
// |dx| / R rad away) meets no covered cell cannot read the mirror. What the bound cannot place (a
// ray that misses a raised sphere, a mirrored point behind the eye's plane, waves that reach the
// eye, a box over more than MAX_CELLS cells) goes to list 0.
// With `reset`, one invocation empties both lists first.
#include "frame.glsl"
#include "common.glsl"
#include "planet.glsl"

layout(local_size_x = 8, local_size_y = 8) in;   // one invocation per tile
layout(set = 0, binding = 3) uniform sampler2D planar_inverse_depth;
#include "planar_start.glsl"
// Indirect dispatch arguments (x workgroups, 1, 1) of each list, then the lists, each as long as
// the view has tiles: a tile's workgroup coordinates packed x | y << 16.
layout(set = 0, binding = 4, std430) restrict buffer PlanarTiles { uvec4 args[2]; uint tiles[]; } planar_tiles;
// first_row: the first tile row of the sea-only rows, which the dispatch's row 0 stands for.
layout(push_constant) uniform Push { uint planar_drawn; uint reset; uint first_row; } push;

const uint SHADE_GROUP = 8u;   // src/render/passes/shade.rs
const int MAX_CELLS = 16;

bool tile_may_reflect(uvec2 tile, vec2 view) {
    if (push.planar_drawn == 0u) return false;
    float A = frame.wave_extent.y, H = frame.cam_forward.w, R = frame.planet.x;
    if (!(H > A)) return true;
    vec2 size = vec2(textureSize(planar_inverse_depth, 0));
    vec2 lo = vec2(3.0e38), hi = vec2(-3.0e38);
    for (int corner = 0; corner < 4; corner++) {
        vec2 pixel = min(vec2(tile + uvec2(corner & 1, corner >> 1)) * float(SHADE_GROUP), view);
        vec3 u = normalize(camera_ray(pixel_to_ndc(pixel)));
        for (int side = 0; side < 2; side++) {
            float h = side == 0 ? -A : A;
            float t = sphere_distance(u, H - h, R + h);
            if (!(t > 0.0)) return true;
            vec3 point = u * t;
            vec3 up = sea_normal(point.xy);
            vec3 mirrored = point - 2.0 * dot(point - sea_point(point.xy), up) * up;
            float z = dot(mirrored, frame.cam_forward.xyz);
            if (!(z > 0.0)) return true;
            vec2 s = reflection_screen(mirrored, z, size);
            lo = min(lo, s);
            hi = max(hi, s);
        }
    }
    int level = min(PLANAR_SEARCH_LEVELS, textureQueryLevels(planar_inverse_depth) - 1);
    ivec2 cells = max(textureSize(planar_inverse_depth, 0) >> level, ivec2(1));
    // Positions beyond the image clamp to its edge, as mirror_start's do.
    ivec2 first = clamp(ivec2(floor((lo - 1.0) / float(1 << level))), ivec2(0), cells - 1);
    ivec2 last = clamp(ivec2(floor((hi + 1.0) / float(1 << level))), ivec2(0), cells - 1);
    ivec2 span = last - first + 1;
    if (span.x * span.y > MAX_CELLS) return true;
    for (int k = 0; k < span.x * span.y; k++) {
        ivec2 cell = first + ivec2(k % span.x, k / span.x);
        if (texelFetch(planar_inverse_depth, cell, level).x != 0.0) return true;
    }
    return false;
}

void main() {
    if (push.reset != 0u) {
        if (gl_GlobalInvocationID.xy == uvec2(0u)) {
            planar_tiles.args[0] = uvec4(0u, 1u, 1u, 0u);
            planar_tiles.args[1] = uvec4(0u, 1u, 1u, 0u);
        }
        return;
    }
    vec2 view = frame.viewport.xy;   // the shading pass's size
    uvec2 tiles = (uvec2(view) + SHADE_GROUP - 1u) / SHADE_GROUP;
    uvec2 tile = gl_GlobalInvocationID.xy + uvec2(0u, push.first_row);
    if (any(greaterThanEqual(tile, tiles))) return;
    uint list = tile_may_reflect(tile, view) ? 0u : 1u;
    uint slot = atomicAdd(planar_tiles.args[list].x, 1u);
    planar_tiles.tiles[list * tiles.x * tiles.y + slot] = tile.x | (tile.y << 16);
}
