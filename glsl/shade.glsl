// Per-pixel shading of the sea and the sky, once per pixel: resolved normals from the trains
// longer than the pixel footprint, the rest as BRDF slope variance (paper, sections 4-5), at the
// rest position the visibility pass (ocean.frag) left in the pixel; the sky where it left none.
// The rows above the horizon that no crest reaches were shaded by the visibility pass already
// (sky.frag) and are not dispatched.
// The result replaces those bits in place, as the RGBA16F radiance.
// Entry points: shade.comp (one train per loop iteration) and shade_blocked.comp (TRAIN_BLOCKS:
// the wave table read a block at a time through subgroup broadcasts, train_blocks.glsl).
#include "frame.glsl"
#include "common.glsl"
WAVES_BLOCK;
layout(set = 0, binding = 2) uniform sampler2D sky_map;
layout(set = 0, binding = 10) uniform sampler2D eye_sky;   // resources::EYE_SKY_BINDING
#define EYE_SKY_SAMPLER eye_sky
layout(set = 0, binding = 3, rgba16ui) uniform restrict uimage2D hdr_bits;
layout(constant_id = 0) const bool TERM_SUN = true;
layout(constant_id = 1) const bool TERM_SKY = true;
layout(constant_id = 2) const bool TERM_SEA = true;
// Whether pixels without sea show the sky (else black: renders of single terms).
layout(constant_id = 5) const bool BACKGROUND = true;
// Whether this dispatch covers only rows whose rays all fall (frame::sea_only_rows), where only
// sea is seen: the sky's code is left out (a CPU driver would run it for every pixel, masked). A
// pixel the grid left uncovered there takes the mean plane's point.
layout(constant_id = 6) const bool SEA_ONLY = false;
// Profiling: counts the sea pixels, the trains evaluated for them (and those with a weight) and
// the wave packets' terms into TrainCounts (src/render/resources.rs). Off, the driver drops the
// counting code.
layout(constant_id = 7) const bool COUNT_TRAINS = false;
layout(set = 0, binding = 4, std430) restrict buffer TrainCounts {
    uint sea_pixels;
    uint trains_evaluated;
    uint trains_weighted;
    uint packet_terms;
} counts;
#define COUNTS_TRAINS
#include "waves.glsl"
#ifdef TRAIN_BLOCKS
#include "train_blocks.glsl"
#endif
#include "packets.glsl"
#include "sky.glsl"
// The sea's reflections of the host's objects in screen space (constant 15; passes/reflections.rs
// builds what local_reflection reads) and through their mirror images (constant 16;
// passes/planar.rs, planar_reflection): left out where the host hands no depth, or asks for none.
layout(constant_id = 15) const bool LOCAL_REFLECTIONS = false;
layout(constant_id = 16) const bool PLANAR_REFLECTIONS = false;
// The host's objects mirrored about the sea (passes/planar.rs): their radiance (host unit)
// premultiplied by coverage, and their coverage and coverage over forward depth, both mipmapped
// by means; whether the host drew them this frame.
layout(set = 0, binding = 17) uniform sampler2D planar_colour;
layout(set = 0, binding = 18) uniform sampler2D planar_inverse_depth;
#include "planar_start.glsl"
// Whether this dispatch shades the 8x8 tiles a list names (constant 17; passes/planar_tiles.rs
// sorts the sea-only rows' tiles by whether any of their pixels may mirror an object, and each
// list is shaded by the pipeline that reads the mirror or by the one without its code), and
// where its list starts among `planar_tiles.tiles`.
layout(constant_id = 17) const bool TILED = false;
layout(set = 0, binding = 19, std430) readonly buffer PlanarTiles { uvec4 args[2]; uint tiles[]; } planar_tiles;
layout(push_constant) uniform ShadePush { uint planar_drawn; uint tile_list; } shade_push;
#define HAS_LOCAL_REFLECTIONS
#include "brdf.glsl"
layout(set = 0, binding = 5) uniform sampler2D aerial_inscatter;
layout(set = 0, binding = 6) uniform sampler2D aerial_transmittance;
// The sun's shadows from the displaced grid (src/render/passes/shadow.rs): its view's depth, and
// the camera's, which places each pixel's surface point on the same triangles.
layout(constant_id = 9) const bool SHADOW = false;
// Whether any pixel in view resolves a train into its normal (the train loop; constant 11) and
// whether the physical sky's aerial perspective is applied (constant 12): specialize::plan leaves
// each out where it changes nothing.
layout(constant_id = 11) const bool NORMALS = true;
layout(constant_id = 12) const bool AERIAL = true;
// Whether the full method may step to where the pixel's ray meets the sea (ray_hit_strength):
// specialize::plan leaves its gate and loop out where no pixel in view resolves enough of the
// slopes (RAY_HIT_SHARE) for the step to be taken.
layout(constant_id = 14) const bool RAY_HIT = true;
layout(set = 0, binding = 8) uniform sampler2DShadow sun_shadow_map;
layout(set = 0, binding = 9) uniform sampler2D scene_depth;

#include "atmosphere.glsl"

// The objects' radiance premultiplied by their coverage, mipmapped, and their nearest forward
// depth per cell of each level (glsl/reflection_sources.comp, reflection_depth_mip.comp).
layout(set = 0, binding = 14) uniform sampler2D reflection_colour;
layout(set = 0, binding = 15) uniform sampler2D reflection_depth;
// The screen rectangle (level-0 pixels: min x, min y, max x, max y) holding every object, and
// their nearest forward depth (glsl/reflection_bounds.comp).
layout(set = 0, binding = 16, std430) readonly buffer ReflectionBounds { vec4 rect; float nearest; } reflection_bounds;


// Cells a reflected ray visits at most: skipping up the pyramid, a ray crosses a 1024-pixel
// screen in about 2 log2(1024) of them; the rest go to refining near objects and to the pixels
// it passes behind one.
const int REFLECTION_STEPS = 64;
// How deep an object is taken to be behind its visible surface, as a share of its distance: a
// 1 m buoy at 20 m, a 20 m hull at 400 m. A ray passing farther behind it goes on, so a near
// silhouette leaves no streak over what lies beyond it, and what stands in front of the
// reflecting point (nearer the eye by more) is never taken for its reflection.
const float OBJECT_DEPTH_SHARE = 0.05;
// The reflection fades out over this many pixels, at least, before a screen edge.
const float EDGE_FADE_PX = 16.0;

// How far behind a pixel's nearest object depth `nearest` a ray may pass and still meet it: the
// object's assumed depth, and more where its surface recedes across the pixel (seen at a grazing
// angle, a hull's side spans metres of depth within one pixel): as far as the neighbours the ray
// goes on towards, where they are the same kind of surface (no farther than twice the assumed
// depth beyond, so that a silhouette over a far background is not one).
float surface_back(ivec2 cell, float nearest, vec2 ds) {
    ivec2 last = textureSize(reflection_depth, 0) - 1;
    ivec2 step_to = ivec2(sign(ds));
    float back = nearest * (1.0 + OBJECT_DEPTH_SHARE);
    float beyond = nearest * (1.0 + 3.0 * OBJECT_DEPTH_SHARE);
    for (int k = 0; k < 2; k++) {
        ivec2 next = clamp(cell + (k == 0 ? ivec2(step_to.x, 0) : ivec2(0, step_to.y)), ivec2(0), last);
        float d = texelFetch(reflection_depth, next, 0).r;
        if (d < beyond) back = max(back, d);
    }
    return back;
}

// The pixel size in metres at forward depth z > 0, in images of the view's size.
float pixel_m_at(float z, vec2 size) {
    return z * 2.0 * length(frame.cam_down.xyz) / size.y;
}

// One lookup of a reflection cone (brdf.glsl ReflectionCone) in `image`, an image of the view's
// size: at the screen position of camera-relative q, filtered over blur_m metres there, and
// faded out towards the image's edges, beyond which it holds nothing.
vec4 cone_tap(sampler2D image, vec3 q, float blur_m, vec2 size) {
    float z = dot(q, frame.cam_forward.xyz);
    if (!(z > 0.0)) return vec4(0.0);   // turned back past the eye's plane: not in the image
    vec2 at = reflection_screen(q, z, size);
    float texel_px = blur_m / pixel_m_at(z, size);
    vec4 seen = textureLod(image, at / size, log2(max(texel_px, 1.0)));
    float margin = min(min(at.x, size.x - at.x), min(at.y, size.y - at.y));
    return seen * smoothstep(0.0, 1.0, margin / max(0.5 * texel_px, EDGE_FADE_PX));
}

// A footprint no longer than this (pixels, its 2-sigma extent along the longer axis) is read by
// one lookup over all of it: its taps would lie within a texel or two of each other.
const float CONE_ONE_TAP_PX = 4.0;

// The change a cone's lookups in `image` make to the reflected sky (brdf.glsl add_tap), `path`
// metres along its taps from `point`, mirrored about the plane of unit normal `mirror` where that
// is not 0; each lookup's radiance times `to_radiance`, held to the half float's range (the
// screen's sources are already, glsl/reflection_sources.comp).
vec4 cone_change(sampler2D image, vec3 point, ReflectionCone cone, vec3 mirror, float path, vec2 size,
                 float to_radiance, ConeSky sky) {
    bool mirrored = dot(mirror, mirror) > 0.0;
    vec3 centre = point + (mirrored ? reflect(cone.r, mirror) : cone.r) * path;
    float z = dot(centre, frame.cam_forward.xyz);
    if (z > 0.0 && path * cone.extent < CONE_ONE_TAP_PX * pixel_m_at(z, size)) {
        vec4 tap = cone_tap(image, centre, path * cone.extent, size);
        return one_tap_change(cone, vec4(clamp(tap.rgb * to_radiance, vec3(0.0), vec3(HDR_MAX)), tap.a), sky);
    }
    ConeSum sum = no_cone_sum();
    for (int i = 0; i < cone.count; i++) {
        vec3 d = cone_tap_dir(cone, i);
        vec4 tap = cone_tap(image, point + (mirrored ? reflect(d, mirror) : d) * path, path * cone.blur, size);
        add_tap(sum, cone, i, d, vec4(clamp(tap.rgb * to_radiance, vec3(0.0), vec3(HDR_MAX)), tap.a), sky);
    }
    return cone_sum_change(sum);
}

// The objects the sea point `point` (camera-relative) mirrors along the cone of its unresolved
// slopes (brdf.glsl ReflectionCone), which widens the reflection as it widens the sky's: each
// tap's change (cone_change) at the path where the centre ray meets them, nothing where the ray
// meets nothing on screen. The ray is marched in screen space, where 1 / depth is linear,
// through the depth pyramid: a cell whose nearest object lies beyond the ray's farthest point
// there is stepped over whole, and the walk climbs a level; otherwise it goes down one, and on
// level 0 the ray meets the object if it is no farther behind it than the object's assumed depth
// (McGuire & Mara 2014's screen-space march; the hierarchy is Uludag's, GPU Pro 5, 2014).
vec4 local_reflection(vec3 point, ReflectionCone cone, ConeSky sky) {
    if (!LOCAL_REFLECTIONS) return vec4(0.0);
    vec3 r = cone.r;
    vec2 size = vec2(textureSize(reflection_depth, 0));
    vec3 forward = frame.cam_forward.xyz;
    float z0 = dot(point, forward), rf = dot(r, forward);
    if (!(z0 > 0.0)) return vec4(0.0);
    // Far enough that the segment's end is at the vanishing point to within a pixel, or half way
    // to the eye's plane for a ray turning back towards the eye (its depth stays positive).
    float reach = 1e4 * z0;
    if (rf < 0.0) reach = min(reach, 0.5 * z0 / -rf);
    vec3 end = point + r * reach;
    float z1 = dot(end, forward);
    vec2 s0 = reflection_screen(point, z0, size), s1 = reflection_screen(end, z1, size);
    // The start is on screen (it is a pixel's); a start a hair outside is clamped in.
    s0 = clamp(s0, vec2(0.0), size - 1e-3);
    float k0 = 1.0 / z0, k1 = 1.0 / z1;
    vec2 ds = s1 - s0;
    float len = max(abs(ds.x), abs(ds.y));
    if (len < 1.0) return vec4(0.0);   // the reflection stays in its own pixel
    // Where the ray leaves the screen.
    vec2 exits = vec2(ds.x > 0.0 ? (size.x - s0.x) / ds.x : ds.x < 0.0 ? -s0.x / ds.x : 1.0,
                      ds.y > 0.0 ? (size.y - s0.y) / ds.y : ds.y < 0.0 ? -s0.y / ds.y : 1.0);
    float end_alpha = min(1.0, min(exits.x, exits.y));
    float nudge = 1e-3 / len;                   // past a cell's edge
    float alpha = 1.0 / len;                    // a pixel on: the point's own pixel is sea
    // Only the part of the path inside the objects' rectangle can meet one: the rest is not
    // walked, and a path that misses it (most of the sea's) returns at once.
    vec4 rect = reflection_bounds.rect;
    if (rect.x >= rect.z || rect.y >= rect.w) return vec4(0.0);   // no object on screen
    for (int axis = 0; axis < 2; axis++) {
        float lo = rect[axis], hi = rect[axis + 2];
        if (ds[axis] != 0.0) {
            float a = (lo - s0[axis]) / ds[axis], b = (hi - s0[axis]) / ds[axis];
            alpha = max(alpha, min(a, b));
            end_alpha = min(end_alpha, max(a, b));
        } else if (s0[axis] < lo || s0[axis] >= hi) {
            return vec4(0.0);
        }
    }
    if (alpha >= end_alpha) return vec4(0.0);
    // Depth is monotonic along the path (1 / depth is linear): nearer than every object at both
    // ends of its part in the rectangle, it passes in front of them all.
    float z_far = max(1.0 / (k0 + alpha * (k1 - k0)), 1.0 / (k0 + end_alpha * (k1 - k0)));
    if (z_far < reflection_bounds.nearest) return vec4(0.0);
    int level = 0;
    int top = textureQueryLevels(reflection_depth) - 1;
    float hit = -1.0;
    // The cell a step is in is the one holding the point half a pixel on along the ray: a
    // point on a cell's edge, rounded in f32, could otherwise count as still in the cell it
    // left (a near-vertical ray moves a millionth of a pixel across an edge it crosses), and that
    // cell's parent be skipped in place of the one it goes on into.
    float ahead = 0.5 / len;
    for (int i = 0; i < REFLECTION_STEPS; i++) {
        if (alpha >= end_alpha) break;
        vec2 s = s0 + ds * (alpha + ahead);
        float cell_px = float(1 << level);   // exact (a driver's exp2 may be approximate)
        // The level's size by arithmetic: textureSize with a level that differs between lanes
        // returned one lane's size for all on lavapipe, and a comb of lost rays with it.
        ivec2 level_texels = max(ivec2(size) >> level, ivec2(1));
        ivec2 cell = clamp(ivec2(floor(s / cell_px)), ivec2(0), level_texels - 1);
        // Where the ray leaves the cell (a coarse level's last cell also holds an odd level's
        // trailing texels, so clamping the cell keeps it conservative).
        vec2 bound = (vec2(cell) + step(0.0, ds)) * cell_px;
        vec2 leave = vec2(ds.x != 0.0 ? (bound.x - s0.x) / ds.x : 1.0, ds.y != 0.0 ? (bound.y - s0.y) / ds.y : 1.0);
        float exit_alpha = min(min(leave.x, leave.y), end_alpha);
        float za = 1.0 / (k0 + alpha * (k1 - k0)), zb = 1.0 / (k0 + exit_alpha * (k1 - k0));
        float nearest = texelFetch(reflection_depth, cell, level).r;
        if (max(za, zb) < nearest) {
            alpha = max(exit_alpha, alpha) + nudge;
            level = min(level + 1, top);
        } else if (level > 0) {
            level--;
        } else if (min(za, zb) <= surface_back(cell, nearest, ds)) {
            hit = alpha;
            break;
        } else {
            alpha = max(exit_alpha, alpha) + nudge;
        }
    }
    if (hit < 0.0) return vec4(0.0);
    vec2 at = s0 + ds * hit;
    float z = 1.0 / (k0 + hit * (k1 - k0));
    // The path from the sea to the object, along which the cone's lookups meet its depth.
    float path = abs(rf) > 1e-3 ? (z - z0) / rf : hit * reach;
    return cone_change(reflection_colour, point, cone, vec3(0.0), path, size, 1.0, sky);
}

// Where the sea point `point` (camera-relative) starts into the mirror's world (planar_start):
// false where the host drew no mirror images this frame, or none lies within the widest search
// around the point's pixel (most of the sea, at one read): the caller then builds no reflection
// cone.
bool mirror_start(vec3 point, vec3 up, out MirrorStart start) {
    start = MirrorStart(point, 0.0, vec2(0.0));
    if (!PLANAR_REFLECTIONS || shade_push.planar_drawn == 0u) return false;
    return planar_start(point, up, start);
}

// The objects the sea point mirrors along the cone of its unresolved slopes (brdf.glsl
// ReflectionCone), read from their mirror images (a planar reflection: the objects drawn
// mirrored about the sea's tangent plane, normal `up`), tap by tap (cone_change), from
// where mirror_start found it starts. The mirrored centre ray m, from the mirrored point, goes on
// into the mirror's world; where it meets a mirrored object is found by fixed-point steps on its
// path t: the image's depth over the whole footprint at the screen position of point + t m, the
// first from the objects found nearest the point's own pixel. The cone's lookups are read at that
// path, so a footprint whose centre passes beside an object still takes its share of it. A flat
// sea's ray is the view ray and needs none.
vec4 planar_reflection(MirrorStart start, ReflectionCone cone, vec3 up, ConeSky sky) {
    vec2 size = vec2(textureSize(planar_colour, 0));
    vec3 forward = frame.cam_forward.xyz;
    vec3 point = start.point;
    vec3 m = reflect(cone.r, up);
    float z0 = start.z0, mf = dot(m, forward);
    // A mirrored ray that does not recede from the eye meets nothing the view holds beyond the
    // point.
    if (!(mf > 0.0)) return vec4(0.0);
    vec2 s = start.s;
    vec2 found = vec2(0.0);
    int top = textureQueryLevels(planar_colour) - 1;
    for (int level = 0; level <= PLANAR_SEARCH_LEVELS && found.x == 0.0; level += 2) {
        found = planar_depth(s, min(level, top));
    }
    if (found.x == 0.0) return vec4(0.0);
    float path = 0.0;
    for (int i = 0; i < 2; i++) {
        // What stands nearer the eye than the point is not behind the mirror: no reflection of it.
        path = (found.y - z0) / mf;
        if (!(path > 0.0)) return vec4(0.0);
        vec3 q = point + m * path;
        float z = dot(q, forward);
        vec2 at = clamp(reflection_screen(q, z, size), vec2(0.0), size - 1e-3);
        float lod = log2(max(path * cone.extent / pixel_m_at(z, size), 1.0));
        vec2 next = planar_depth(at, min(int(lod), top));
        if (next.x == 0.0) break;
        found = next;
    }
    // The host's unit to the ocean's.
    return cone_change(planar_colour, point, cone, up, path, size, 1.0 / frame.host.x, sky);
}

// The physical sky's aerial perspective (glsl/aerial_perspective.comp) at screen position uv and
// distance d from the eye along the unit ray u: slice k of the atlas holds the path to
// D (k + 1)^2 / 32^2 past the ray's entry into the air, D its span (aerial_span), so d lies at
// slice s = 32 sqrt((d - entry) / D) - 1, the last slice where the sea's sphere is; before slice 0,
// the path's share of it (in-scatter from 0, transmittance from 1). The column within a slice is
// clamped to its texel centres, so that no lookup blends in the next slice.
vec3 aerial_perspective(vec3 radiance, vec2 uv, vec3 u, float d) {
    float span = aerial_span(u);
    float past_entry = d - max(air_entry(frame.atmosphere[4].z, u), 0.0);
    float s = span > 0.0 ? float(AERIAL_SIZE) * sqrt(clamp(past_entry / span, 0.0, 1.0)) - 1.0 : -1.0;
    vec2 column = clamp(uv * float(AERIAL_SIZE), vec2(0.5), vec2(float(AERIAL_SIZE) - 0.5));
    float k0 = clamp(floor(s), 0.0, float(AERIAL_SIZE - 1)), k1 = min(k0 + 1.0, float(AERIAL_SIZE - 1));
    float f = clamp(s - k0, 0.0, 1.0);
    vec2 size = vec2(AERIAL_SIZE * AERIAL_SIZE, AERIAL_SIZE);
    vec2 a = vec2(k0 * float(AERIAL_SIZE) + column.x, column.y) / size;
    vec2 b = vec2(k1 * float(AERIAL_SIZE) + column.x, column.y) / size;
    vec3 inscatter = mix(textureLod(aerial_inscatter, a, 0.0).rgb, textureLod(aerial_inscatter, b, 0.0).rgb, f);
    vec3 transmittance = mix(textureLod(aerial_transmittance, a, 0.0).rgb, textureLod(aerial_transmittance, b, 0.0).rgb, f);
    if (s < 0.0) {
        float share = s + 1.0;   // in [0, 1): the path's fraction of slice 0, in sqrt(d) as the slices
        inscatter *= share;
        transmittance = mix(vec3(1.0), transmittance, share);
    }
    return radiance * transmittance + inscatter;
}

// Each sea point's light under its own sun (the sphere turns the sun's elevation from point to
// point: seen from high up, the terminator and the night side): the sea-level sky irradiance and
// the sun's irradiance at the point's sun zenith cosine, from the GPU's table
// (glsl/sea_irradiance.comp), calibrated on the CPU by the frame's exact values below the eye
// over the table's there (frame::sea_light_calibration), so that near the eye nothing changes. The
// sky map holds the sky under the sun below the eye; its radiance is scaled by the sky
// irradiance's ratio, held to at most tenfold (a map of twilight does not stand for a daylit sky);
// under a dark map it stays dark.
layout(set = 0, binding = 13) uniform sampler2D sea_light_table;   // resources::SEA_LIGHT_BINDING
const float SKY_SCALE_MAX = 10.0;

SeaLight local_sea_light(vec3 up) {
    if (!SKY_PHYSICAL) return frame_sea_light();
    float u = sea_irradiance_u(clamp(dot(frame.sun_dir.xyz, up), -1.0, 1.0));
    vec3 sky = textureLod(sea_light_table, vec2(u, 0.25), 0.0).rgb;
    vec3 sun = textureLod(sea_light_table, vec2(u, 0.75), 0.0).rgb;
    return SeaLight(sun * frame.sea_light[0].rgb, sky * frame.sea_light[1].rgb,
                    min(sky * frame.sea_light[2].rgb, vec3(SKY_SCALE_MAX)));
}

// The share of the sun a pixel's surface point sees past the displaced grid (1 where nothing
// displaced stands between it and the sun, or the map does not reach). Reversed Z: depth is
// near / (view depth), and camera_ray has unit length along the view, so the point is
// ray near / depth. Only pixels the grid covered are read (inside the image, depth > 0); the
// rest are lit.
float sun_visibility(ivec2 p, vec3 ray, bool covered) {
    if (!SHADOW || frame.shadow.y == 0.0 || !covered) return 1.0;
    float depth = texelFetch(scene_depth, p, 0).r;
    if (depth <= 0.0) return 1.0;
    vec4 c = frame.sun_view_proj * vec4(ray * (frame.shadow.x / depth), 1.0);
    if (any(greaterThan(abs(c.xy), vec2(1.0))) || c.z > 1.0) return 1.0;
    return texture(sun_shadow_map, vec3(c.xy * 0.5 + 0.5, c.z));
}

// How much of the step to where the pixel's ray meets the surface (waves.glsl
// ray_hit_rest_position) a pixel takes. The step moves the shaded point by about a pixel; what
// that changes beyond the picture's detail is the share of steep facets seen (a trochoid's
// compressed crest no longer counts as much as its trough), and so the reflected sun, whose
// glitter lives in the slopes' tail: in the default view +114%, +55% -> +70%, +13% against the
// truth at 10-20 and 20-50 m (docs/results.md, "Where the pixel's ray meets the sea"). Its cost
// is one more loop over the trains, so it is taken only in the sun's path: where the sun's
// glitter on the mean plane (all slopes in the BRDF) reaches RAY_HIT_SUN times the
// least reflected sky, water's Fresnel at normal incidence times the sky's mean radiance (the
// sun's reflection without Fresnel, masking and 1 / cos_v: sun_glitter_density), ramped
// from a tenth of that, so that it fades in without a seam, and where the normal resolves enough
// of the slopes to matter (RAY_HIT_SHARE). On the default view the sun's two nearest bands are
// within 1.2 points of the step taken everywhere. Whether the sun term is drawn does not enter:
// each term's image is its share of the whole one (measure::reference's ray_hit_strength is the
// f64 twin).
const float RAY_HIT_SUN = 300.0;

// Rec. 709's luminance weights, which the gate compares in.
const vec3 REC709 = vec3(0.2126, 0.7152, 0.0722);

// The share of the sea's slope variance in the trains a pixel's normal can resolve at all (longer
// than its lambda_cut), from the prefix sums of the rest: trains are sorted by wavelength, so a
// binary search finds how many are too short.
float resolvable_slope_share(SampleScale s) {
    int lo = 0, hi = int(frame.grid_dims.z);   // trains [0, lo) too short, [hi, n) resolvable
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        Wave wave = unpack_wave(wave_data[mid].xy);
        if (dot(wave.k, wave.k) * s.lambda_cut2 >= 1.0) lo = mid + 1; else hi = mid;
    }
    vec2 unresolved = lo > 0 ? wave_prefix[lo - 1].xy : vec2(0.0);
    float total = frame.wind.z + frame.wind.w;
    return total > 0.0 ? clamp(1.0 - (unresolved.x + unresolved.y) / total, 0.0, 1.0) : 0.0;
}

// The step matters as much as the normal holds of the slopes: it is ramped in from 0.4 of their
// variance to 0.6 (the default view's sun path holds 0.66-0.88 at 320x240, the high-altitude
// preset's 0.10-0.34, an airliner's 0.02: the step changes little there and would cost the most).
// frame::RAY_HIT_SHARE is the same.
const vec2 RAY_HIT_SHARE = vec2(0.4, 0.6);

// The sun's glitter on the mean plane, all slopes in the BRDF, without its Fresnel, masking and
// 1 / cos_v: the slopes' density at the half vector over 4 h_z^4 (reflect_sun's), times the sun's
// irradiance. Where the sun lies the slope density decides: a lookup's worth of work per pixel
// instead of the whole BRDF (docs/results.md measures both).
float sun_glitter_density(vec3 v, vec3 up, vec3 sun_irradiance) {
    Frame3 f = wind_frame(up);
    vec3 vl = to_local(f, v), ll = to_local(f, frame.sun_dir.xyz);
    if (vl.z <= 0.0 || ll.z <= 0.0) return 0.0;
    vec3 h = normalize(vl + ll);   // h.z = (vl.z + ll.z) / |vl + ll| > 0
    float hz2 = h.z * h.z;
    vec2 s2 = frame.wind.zw + vec2(frame.sun_radiance.w);
    float q = h.x * h.x / s2.x + h.y * h.y / s2.y;
    if (q >= 2.0 * EXP_UNDERFLOW * hz2) return 0.0;
    return exp(-0.5 * q / hz2) / (8.0 * PI * sqrt(s2.x * s2.y) * hz2 * hz2) * dot(sun_irradiance, REC709);
}

float ray_hit_strength(vec3 v, vec3 up, SeaLight light, SampleScale s) {
    float sun = sun_glitter_density(v, up, light.sun);
    float sky_floor = FRESNEL_R0 * dot(light.sky_irradiance, REC709) / PI;
    float ramp = 0.9 * RAY_HIT_SUN * sky_floor;
    // sky_floor = 0 (no sky) makes the ramp a step at sun = 0.
    float in_path = ramp > 0.0 ? clamp((sun - 0.1 * RAY_HIT_SUN * sky_floor) / ramp, 0.0, 1.0) : (sun > 0.0 ? 1.0 : 0.0);
    if (in_path <= 0.0) return 0.0;
    return in_path * smoothstep(RAY_HIT_SHARE.x, RAY_HIT_SHARE.y, resolvable_slope_share(s));
}

layout(local_size_x = 8, local_size_y = 8) in;   // SHADE_GROUP in src/render/passes/shade.rs

const bool ANY_TERM = TERM_SUN || TERM_SKY || TERM_SEA;

vec3 sky(vec3 dir) {
    if (!BACKGROUND) return vec3(0.0);
    return sky_seen(dir) + sun_disc(dir);
}

// Every invocation runs to the end (no early return): the blocked train loop needs the whole
// subgroup, and a CPU driver runs both sides of a branch anyway.
void main() {
    // A listed tile's pixels (its workgroup coordinates packed x | y << 16), or the dispatch's.
    uint tile = TILED ? planar_tiles.tiles[shade_push.tile_list + gl_WorkGroupID.x] : 0u;
    ivec2 p = TILED ? ivec2(uvec2(tile & 0xffffu, tile >> 16) * 8u + gl_LocalInvocationID.xy)
                    : ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(p, imageSize(hdr_bits)));
    uvec4 bits = inside ? imageLoad(hdr_bits, p) : NO_SEA_BITS;
    bool covered = bits != NO_SEA_BITS;
    vec3 ray = camera_ray(pixel_to_ndc(vec2(p) + 0.5));   // the pixel's centre, as gl_FragCoord
    vec3 u = normalize(ray);
    // The share of the pixel the sea covers: the part below the limb, also where the grid left the
    // centre uncovered. Where crests can rise over the limb (the eye no higher than the highest),
    // a pixel the grid drew may be a crest standing above it: left whole.
    bool crests_reach_horizon = frame.wave_extent.y >= frame.cam_forward.w;
    float sea_share = SEA_ONLY || (covered && (!meets_sea(u) || crests_reach_horizon)) ? 1.0 : below_limb_share(ray);
    bool is_sea = SEA_ONLY || covered || sea_share > 0.0;
    vec2 x = covered ? bits_to_rest_position(bits) : mean_sea_point(ray);
    // An uncovered pixel's sea lies at most on the limb (its ray moved onto it: the grazing limit).
    vec3 v = -(covered ? u : onto_sea(u));
    // The sphere's normal under the pixel: the frame the waves' normal is tilted into.
    vec3 up = sea_normal(x);
    float v_up = dot(v, up);
    SampleScale pixel = sample_scale(ray, 1.0, frame.filter_steps.zw);
    // v . up <= 0 (the eye below a raised wave) resolves nothing: the grazing limit. Beyond
    // FAR_LIMIT (a rest position gone wrong) nothing is resolvable either.
    bool resolves = NORMALS && ANY_TERM && is_sea && pixel.any && v_up > 0.0 && all(lessThan(abs(x), vec2(FAR_LIMIT)));
    SeaLight light = local_sea_light(up);
    // METHOD_FULL shades the point the pixel's ray meets on the surface it resolves (waves.glsl),
    // where the sun's glitter needs it.
    if (RAY_HIT && METHOD == METHOD_FULL && resolves) {
        float strength = ray_hit_strength(v, up, light, pixel);
        x = ray_hit_rest_position(x, u, pixel, strength);
    }
    vec2 at = resolves ? x : vec2(0.0);
#ifdef TRAIN_BLOCKS
    SurfaceSample s = surface_sample_blocked(at, pixel, frame.filter_steps.zw, resolves);
#else
    SurfaceSample s = resolves ? surface_sample(at, pixel, frame.filter_steps.zw) : flat_surface();
#endif
    // The wave packets where the pixel sees the sea: in its normal as far as it resolves them
    // (not at all where it resolves no train), the rest of their slopes in the BRDF.
    if (PACKETS && is_sea && all(lessThan(abs(x), vec2(FAR_LIMIT)))) add_packets(s, x, pixel, resolves);
    vec3 n = up;
    // Nothing resolved: all slopes in the BRDF (none for the unfiltered mirror), the trains' and
    // the packets' at this point.
    vec2 sigma2 = METHOD == METHOD_NO_FILTER ? vec2(0.0) : frame.wind.zw + s.sigma2;
    if (resolves) {
        // A fully steep train (k h = 1) has a cusp at its crest, where the tangents are parallel:
        // the two sides' normals average to the vertical there. The waves' normal is in the
        // tangent frame of the point below the eye; the sphere's drop tilts it by up.
        vec3 c = cross(s.tangent_x, s.tangent_y);
        float len2 = dot(c, c);
        n = tilt_to(len2 > 0.0 ? c * inversesqrt(len2) : vec3(0.0, 0.0, 1.0), up);
        sigma2 = s.sigma2;
    }
    // The baseline drops whatever the normals do not resolve and keeps one roughness everywhere.
    if (METHOD == METHOD_CONSTANT_BRDF) sigma2 = frame.baseline_sigma2.xy;
    // The glints' site: without resolved trains every train's curvature is unresolved.
    int trains = int(frame.grid_dims.z);
    float curvature = resolves ? s.curvature : (trains > 0 ? wave_prefix[trains - 1].z : 0.0) + s.curvature;
    GlintSite glint = GlintSite(x, u.xy, pixel.a_u_w, pixel.a_v_w, pixel.w, v_up, curvature, sigma2);
    // The point the pixel sees, for its local reflections: on the displaced surface where the
    // grid drew it (reversed Z: ray near / depth), else on the mean sea.
    vec3 point = sea_point(x);
    if ((LOCAL_REFLECTIONS || PLANAR_REFLECTIONS) && covered) {
        float depth = texelFetch(scene_depth, p, 0).r;
        if (depth > 0.0) point = ray * (frame.shadow.x / depth);
    }
    vec3 radiance = is_sea && ANY_TERM ? sea_radiance(n, up, v, sigma2, packet_slope_variance, sun_visibility(p, ray, covered), light, glint, point) : vec3(0.0);
    if (SKY_PHYSICAL && AERIAL && is_sea && BACKGROUND) {
        vec2 uv = (vec2(p) + 0.5) * frame.viewport.zw;
        radiance = aerial_perspective(radiance, uv, u, length(sea_point(x)));
    }
    // The rest of the pixel sees the sky at (or just above) the limb: its ray, raised onto the
    // limb where it falls below it.
    if (!SEA_ONLY && sea_share < 1.0) radiance = mix(sky(above_sea(u)), radiance, sea_share);
    if (inside) imageStore(hdr_bits, p, radiance_to_bits(store_radiance(radiance)));
    if (COUNT_TRAINS && inside && is_sea) {
        atomicAdd(counts.sea_pixels, 1u);
        atomicAdd(counts.trains_evaluated, resolves ? trains_evaluated : 0u);
        atomicAdd(counts.trains_weighted, resolves ? trains_weighted : 0u);
        // 32-bit sums: a 4K frame wraps past about 500 trains or packet terms a pixel.
        atomicAdd(counts.packet_terms, packet_terms);
    }
}
