// The ground truth's physical sky: the f64 atmosphere model (src/model/atmosphere.rs) evaluated
// along each ray a sample traces, from tables the CPU built in f64 (measure::truth_sky) and read
// here with the model's own bilinear lookup in f32 (never a sampler: a CPU driver's filter
// weights have 8 bits). Nothing of the renderer's sky map, sky-view table, aerial atlas or
// sea-level light table is used: each reflected ray gets its own sky at its own sea point, each
// sample its own aerial perspective along its own path. Requires frame.glsl, common.glsl and
// planet.glsl.
#ifndef GROUNDTRUTH_SKY_GLSL
#define GROUNDTRUTH_SKY_GLSL

// The tables, one storage buffer (truth_sky::TruthSkyTables::words): a header (the sea-level sky
// irradiance's lowest sun zenith cosine and 1 / its span, the node count, the floor its logarithm
// was taken above), the irradiance's nodes (its floored logarithm), then the transmittance and multiple-scattering tables row by row (rgb; a unused).
layout(set = 0, binding = 2, std430) readonly buffer TruthAtmosphere { vec4 truth_tables[]; };
const int TRUTH_SEA_LIGHT_NODES = 129;                              // truth_sky::SEA_LIGHT_NODES
const int TRUTH_TRANSMITTANCE_OFFSET = 1 + TRUTH_SEA_LIGHT_NODES;
const int TRUTH_MULTIPLE_OFFSET = TRUTH_TRANSMITTANCE_OFFSET + 256 * 64;
// Samples per sky ray and per aerial-perspective path (truth_sky::SKY_STEPS, AERIAL_STEPS): the
// quadrature's own error is measured on the CPU and reported.
const int TRUTH_SKY_STEPS = 128;
const int TRUTH_AERIAL_STEPS = 64;

// atmosphere::bilinear: texel centres at (i + 0.5) / size, clamped to the edge texels.
vec3 truth_bilinear(int offset, ivec2 size, vec2 uv) {
    vec2 x = clamp(uv * vec2(size) - 0.5, vec2(0.0), vec2(size - 1));
    ivec2 i0 = ivec2(floor(x));
    ivec2 i1 = min(i0 + 1, size - 1);
    vec2 f = x - vec2(i0);
    vec3 top = mix(truth_tables[offset + i0.y * size.x + i0.x].rgb, truth_tables[offset + i0.y * size.x + i1.x].rgb, f.x);
    vec3 bottom = mix(truth_tables[offset + i1.y * size.x + i0.x].rgb, truth_tables[offset + i1.y * size.x + i1.x].rgb, f.x);
    return mix(top, bottom, f.y);
}

vec3 truth_transmittance_at(vec2 uv) { return truth_bilinear(TRUTH_TRANSMITTANCE_OFFSET, ivec2(256, 64), uv); }
vec3 truth_multiple_at(vec2 uv) { return truth_bilinear(TRUTH_MULTIPLE_OFFSET, ivec2(32), uv); }

#define TRANSMITTANCE_LOOKUP truth_transmittance_at
#define MULTIPLE_SCATTERING_LOOKUP truth_multiple_at
#include "atmosphere.glsl"

// The sea-level sky irradiance (klux) under a sun of zenith cosine mu_s: linear in its logarithm
// (it falls exponentially through twilight) between the nodes, which span the zenith cosines the
// visible sea's points have (truth_sky); less the floor, so that night's irradiance stays 0.
vec3 truth_sky_irradiance(float mu_s) {
    vec4 header = truth_tables[0];
    float x = clamp((mu_s - header.x) * header.y, 0.0, 1.0) * float(TRUTH_SEA_LIGHT_NODES - 1);
    int i = min(int(x), TRUTH_SEA_LIGHT_NODES - 2);
    vec3 e = exp(mix(truth_tables[1 + i].rgb, truth_tables[2 + i].rgb, x - float(i)));
    return max(e - header.w, vec3(0.0));
}

// A sea point's own frame: its altitude over the sphere (a wave's height; the air below a trough
// is the sea level's) and its zenith, from its position p relative to the eye.
struct SeaPoint { float h; vec3 up; };

SeaPoint truth_sea_point(vec3 p) {
    return SeaPoint(max(p.z + frame.cam_forward.w + sphere_drop(p.xy), 0.0), sea_normal(p.xy));
}

// The sky a ray leaving the sea at `at` towards unit `dir` sees.
vec3 truth_sky(SeaPoint at, vec3 dir) {
    vec3 sun = frame.sun_dir.xyz;
    return sky_radiance_along(air_ray_cosines(at.h, dot(dir, at.up), dot(sun, at.up), dot(dir, sun)), TRUTH_SKY_STEPS);
}

// The sky seen from the eye towards unit dir (the sun disc apart).
vec3 truth_sky_from_eye(vec3 dir) {
    return sky_radiance_along(air_ray(frame.atmosphere[4].z, dir, frame.sun_dir.xyz), TRUTH_SKY_STEPS);
}

// The sun disc's mean radiance outside the air (kcd/m^2): its illuminance over its solid angle
// pi chord^2 (2 pi (1 - cos radius) = pi chord^2).
float truth_sun_mean_radiance() {
    return frame.atmosphere[4].x / (PI * frame.atmosphere[4].y);
}

// The sun's radiance at a sea point, through the air above it (0 where the planet hides it).
vec3 truth_sun_radiance(SeaPoint at) {
    return truth_sun_mean_radiance() * sun_transmittance(at.h, dot(frame.sun_dir.xyz, at.up));
}

// The aerial perspective over the first d metres of the air ray `a` (atmosphere::Atmosphere::
// aerial_perspective): in-scattered light (kcd/m^2), and the transmittance in `transmittance`, by
// TRUTH_AERIAL_STEPS equal midpoint samples from where the ray enters the air, the optical depth
// summed along the same samples.
vec3 truth_aerial(AirRay a, float d, out vec3 transmittance) {
    transmittance = vec3(1.0);
    if (!a.enters) return vec3(0.0);
    float r = bottom_radius() + a.h;
    float dt = max(d - a.skipped, 0.0) / float(TRUTH_AERIAL_STEPS);
    float phase_r = rayleigh_phase(a.nu), phase_m = mie_phase(a.nu);
    vec3 L = vec3(0.0), depth = vec3(0.0);
    for (int i = 0; i < TRUTH_AERIAL_STEPS; ++i) {
        float t = (float(i) + 0.5) * dt;
        float h_t = clamp(altitude_along(a.h, a.mu, t), 0.0, atmosphere_height());
        float mu_s = clamp((r * a.mu_s + t * a.nu) / (bottom_radius() + h_t), -1.0, 1.0);
        Medium m = medium_at(h_t);
        vec3 single = sun_transmittance(h_t, mu_s) * (m.rayleigh * phase_r + m.mie * phase_m);
        vec3 multiple = (m.rayleigh + m.mie) * multiple_scattering(h_t, mu_s);
        L += exp(-(depth + 0.5 * m.extinction * dt)) * (single + multiple) * dt;
        depth += m.extinction * dt;
    }
    transmittance = exp(-depth);
    return L * frame.atmosphere[4].x;
}

// The same from the eye along unit u.
vec3 truth_aerial_from_eye(vec3 u, float d, out vec3 transmittance) {
    return truth_aerial(air_ray(frame.atmosphere[4].z, u, frame.sun_dir.xyz), d, transmittance);
}

#endif
