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
#define SKY_MAP_SAMPLER sky_map
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
// Profiling: counts the sea pixels and the trains evaluated for them (and those with a weight)
// into TrainCounts (src/render/resources.rs). Off, the driver drops the counting code.
layout(constant_id = 7) const bool COUNT_TRAINS = false;
layout(set = 0, binding = 4, std430) restrict buffer TrainCounts { uint sea_pixels; uint trains_evaluated; uint trains_weighted; } counts;
#define COUNTS_TRAINS
#include "waves.glsl"
#ifdef TRAIN_BLOCKS
#include "train_blocks.glsl"
#endif
#include "sky.glsl"
#include "brdf.glsl"
layout(set = 0, binding = 5) uniform sampler2D aerial_inscatter;
layout(set = 0, binding = 6) uniform sampler2D aerial_transmittance;
// The sun's shadows from the displaced grid (src/render/passes/shadow.rs): its view's depth, and
// the camera's, which places each pixel's surface point on the same triangles.
layout(constant_id = 9) const bool SHADOW = false;
layout(set = 0, binding = 8) uniform sampler2DShadow sun_shadow_map;
layout(set = 0, binding = 9) uniform sampler2D scene_depth;

const int AERIAL_SIZE = 32;   // resources::AERIAL_SIZE

// The physical sky's aerial perspective (glsl/aerial_perspective.comp) at screen position uv and
// distance d from the eye: slice k of the atlas holds the path to D (k + 1)^2 / 32^2, so d lies
// at slice s = 32 sqrt(d / D) - 1; before slice 0, the path's share of it (in-scatter from 0,
// transmittance from 1). The column within a slice is clamped to its texel centres, so that no
// lookup blends in the next slice.
vec3 aerial_perspective(vec3 radiance, vec2 uv, float d) {
    float depth = frame.atmosphere[4].w;
    float s = float(AERIAL_SIZE) * sqrt(clamp(d / depth, 0.0, 1.0)) - 1.0;
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

layout(local_size_x = 8, local_size_y = 8) in;   // SHADE_GROUP in src/render/passes/shade.rs

const bool ANY_TERM = TERM_SUN || TERM_SKY || TERM_SEA;

// Where a ray meets the mean sea plane (rest position, camera-relative); FAR_LIMIT for a ray that
// does not fall, as the visibility pass stores for the horizon.
vec2 mean_plane_point(vec3 ray) {
    float w = -ray.z;
    vec2 x = w > 0.0 ? frame.cam_forward.w * ray.xy / w : vec2(FAR_LIMIT);
    return all(lessThan(abs(x), vec2(FAR_LIMIT))) ? x : vec2(FAR_LIMIT);
}

// The share of the pixel through whose centre `ray` passes that lies below the mean sea plane's
// horizon. ray.z is linear across the screen (camera_ray), so the horizon is a straight line
// and the share is the pixel's area where that linear function is negative: with no roll (the
// camera has none) it changes along the rows only and the ramp over one pixel's change of ray.z
// is exact for a box pixel; with a slope it would be the usual ramp over |a| + |b|. A view
// straight up or down has ray.z constant on the screen: all or nothing.
float below_horizon_share(vec3 ray) {
    float a = abs(frame.cam_right.z) * 2.0 * frame.viewport.z;
    float b = abs(frame.cam_down.z) * 2.0 * frame.viewport.w;
    float width = a + b;
    return width > 0.0 ? clamp(0.5 - ray.z / width, 0.0, 1.0) : (ray.z < 0.0 ? 1.0 : 0.0);
}

vec3 sky(vec3 dir) {
    if (!BACKGROUND) return vec3(0.0);
    return sky_radiance(dir) + sun_disc(dir);
}

// Every invocation runs to the end (no early return): the blocked train loop needs the whole
// subgroup, and a CPU driver runs both sides of a branch anyway.
void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    bool inside = all(lessThan(p, imageSize(hdr_bits)));
    uvec4 bits = inside ? imageLoad(hdr_bits, p) : NO_SEA_BITS;
    bool covered = bits != NO_SEA_BITS;
    vec3 ray = camera_ray(pixel_to_ndc(vec2(p) + 0.5));   // the pixel's centre, as gl_FragCoord
    // The share of the pixel the sea covers: the part below the mean horizon, also where the grid
    // left the centre uncovered. Where crests can rise over the horizon (the eye no higher than
    // the highest), a pixel the grid drew may be a crest standing above it: left whole.
    bool crests_reach_horizon = frame.wave_extent.y >= frame.cam_forward.w;
    float sea_share = SEA_ONLY || (covered && (ray.z > 0.0 || crests_reach_horizon)) ? 1.0 : below_horizon_share(ray);
    bool is_sea = SEA_ONLY || covered || sea_share > 0.0;
    vec2 x = covered ? bits_to_rest_position(bits) : mean_plane_point(ray);
    // An uncovered pixel's sea lies at most on the horizon (x then FAR_LIMIT: the grazing limit);
    // a ray straight up has no horizon in its pixel (its share is 0) and takes any finite v.
    vec3 toward_sea = covered || ray.z <= 0.0 ? ray : vec3(ray.xy, 0.0);
    vec3 v = dot(toward_sea, toward_sea) > 0.0 ? -normalize(toward_sea) : vec3(0.0, 0.0, 1.0);
    SampleScale pixel = sample_scale(ray, 1.0, frame.filter_steps.zw);
    // v.z <= 0 (the eye below a raised wave) resolves nothing: the grazing limit. Beyond
    // FAR_LIMIT (stored for pixels too far for any train) nothing is resolvable either.
    bool resolves = ANY_TERM && is_sea && pixel.any && v.z > 0.0 && all(lessThan(abs(x), vec2(FAR_LIMIT)));
    float grazing = resolves ? 2.0 * PI / v.z : 0.0;
    vec2 at = resolves ? x : vec2(0.0);
#ifdef TRAIN_BLOCKS
    SurfaceSample s = surface_sample_blocked(at, pixel, frame.filter_steps.zw, grazing, resolves);
#else
    SurfaceSample s = resolves ? surface_sample(at, pixel, frame.filter_steps.zw, grazing) : flat_surface();
#endif
    vec3 n = vec3(0.0, 0.0, 1.0);
    // Nothing resolved: all slopes in the BRDF (none for the unfiltered mirror).
    vec2 sigma2 = METHOD == METHOD_NO_FILTER ? vec2(0.0) : frame.wind.zw;
    if (resolves) {
        // A fully steep train (k h = 1) has a cusp at its crest, where the tangents are parallel:
        // the two sides' normals average to the vertical there.
        vec3 c = cross(s.tangent_x, s.tangent_y);
        float len2 = dot(c, c);
        n = len2 > 0.0 ? c * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
        sigma2 = s.sigma2;
    }
    // The baseline drops whatever the normals do not resolve and keeps one roughness everywhere.
    if (METHOD == METHOD_CONSTANT_BRDF) sigma2 = frame.baseline_sigma2.xy;
    vec3 radiance = is_sea && ANY_TERM ? sea_radiance(n, v, sigma2, sun_visibility(p, ray, covered)) : vec3(0.0);
    if (SKY_PHYSICAL && is_sea && BACKGROUND) {
        vec2 uv = (vec2(p) + 0.5) * frame.viewport.zw;
        radiance = aerial_perspective(radiance, uv, length(vec3(x, frame.cam_forward.w)));
    }
    // The rest of the pixel sees the sky at (or just above) the horizon; a share below 1 means
    // ray.z > -width / 2 with |ray| >= 1 (camera_ray), so this direction is never zero.
    if (!SEA_ONLY && sea_share < 1.0) radiance = mix(sky(normalize(vec3(ray.xy, max(ray.z, 0.0)))), radiance, sea_share);
    if (inside) imageStore(hdr_bits, p, radiance_to_bits(store_radiance(radiance)));
    if (COUNT_TRAINS && inside && is_sea) {
        atomicAdd(counts.sea_pixels, 1u);
        atomicAdd(counts.trains_evaluated, resolves ? trains_evaluated : 0u);
        atomicAdd(counts.trains_weighted, resolves ? trains_weighted : 0u);
    }
}
