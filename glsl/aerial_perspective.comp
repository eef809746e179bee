#version 450
// Aerial perspective (Hillaire 2020's camera volume, laid out as a 2D atlas): for each of 32 x 32
// view rays across the screen and 32 distances along them, the light the air scatters towards
// the eye over that distance and the transmittance over it. Slice k ends at
// D (k + 1)^2 / 32^2, D the distance to the top of the atmosphere along the horizontal, so the
// last slice of a ray near the horizon holds the horizon sky itself: the far sea fades into it.
// Texel (32 k + column, row) of each atlas. Integrated like the sky (atmosphere.glsl), SUBSTEPS
// samples per slice.
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
layout(set = 0, binding = 5) uniform sampler2D multiple_scattering_table;
#define TRANSMITTANCE_TABLE transmittance_table
#define MULTIPLE_SCATTERING_TABLE multiple_scattering_table
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D inscatter_atlas;
layout(set = 0, binding = 6, rgba16f) writeonly uniform image2D transmittance_atlas;

const int SUBSTEPS = 4;

// The sea is flat but the air is a sphere. A ray that enters the sphere's ground meets every
// sea point before it does (the flat sea lies above the sphere away from the eye), so its slices
// up to the ground are its own; past it no sea point lies on the ray, and those slices matter only
// to pixels between this ray and one above the sphere's horizon, near the horizon line. They hold
// the tangent ray's values at the same distances (the same azimuth, grazing the sphere), which is
// what the ray above holds too: the far sea meets the horizon sky without a seam.
vec3 tangent_direction(vec3 dir, float horizon_mu) {
    float len = length(dir.xy);
    vec2 azimuth = len > 0.0 ? dir.xy / len : vec2(1.0, 0.0);   // straight down: any azimuth
    return vec3(azimuth * sqrt(max(1.0 - horizon_mu * horizon_mu, 0.0)), horizon_mu);
}

// In-scatter and transmittance over [t0, t1] along (h, dir), SUBSTEPS midpoint samples.
vec3 inscatter_between(float h, vec3 dir, float t0, float t1) {
    vec3 sun = frame.sun_dir.xyz;
    float r = bottom_radius() + h;
    float mu = dir.z, nu = dot(dir, sun);
    float phase_r = rayleigh_phase(nu), phase_m = mie_phase(nu);
    float dt = (t1 - t0) / float(SUBSTEPS);
    vec3 L = vec3(0.0);
    for (int i = 0; i < SUBSTEPS; ++i) {
        float t = t0 + (float(i) + 0.5) * dt;
        float h_t = clamp(altitude_along(h, mu, t), 0.0, atmosphere_height());
        float mu_s = clamp((r * sun.z + t * nu) / (bottom_radius() + h_t), -1.0, 1.0);
        Medium m = medium_at(h_t);
        vec3 single = sun_transmittance(h_t, mu_s) * (m.rayleigh * phase_r + m.mie * phase_m);
        vec3 multiple = (m.rayleigh + m.mie) * multiple_scattering(h_t, mu_s);
        L += aerial_transmittance(h, mu, t) * (single + multiple) * dt;
    }
    return L;
}

void main() {
    ivec2 column = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(column, ivec2(AERIAL_SIZE)))) return;
    vec3 dir = normalize(camera_ray((vec2(column) + 0.5) / float(AERIAL_SIZE) * 2.0 - 1.0));
    float h = frame.atmosphere[4].z;
    float horizon_mu = -sqrt(max(h * (2.0 * bottom_radius() + h), 0.0)) / (bottom_radius() + h);
    bool ground = meets_ground(h, dir.z);
    float d_ground = ground ? distance_to_ground(h, dir.z) : 3.0e38;
    vec3 tangent = tangent_direction(dir, horizon_mu);
    float depth = frame.atmosphere[4].w;   // to the top of the atmosphere along the horizontal
    vec3 own = vec3(0.0), grazing = vec3(0.0);
    float t0 = 0.0;
    for (int k = 0; k < AERIAL_SIZE; ++k) {
        float t1 = depth * float((k + 1) * (k + 1)) / float(AERIAL_SIZE * AERIAL_SIZE);
        own += inscatter_between(h, dir, t0, t1);
        if (ground) grazing += inscatter_between(h, tangent, t0, t1);
        t0 = t1;
        bool mine = !ground || t1 <= d_ground;
        vec3 L = mine ? own : grazing;
        vec3 T = aerial_transmittance(h, mine ? dir.z : tangent.z, t1);
        ivec2 texel = ivec2(k * AERIAL_SIZE + column.x, column.y);
        imageStore(inscatter_atlas, texel, vec4(store_radiance(L * frame.atmosphere[4].x), 1.0));
        imageStore(transmittance_atlas, texel, vec4(T, 1.0));
    }
}
