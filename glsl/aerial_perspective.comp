#version 450
// Aerial perspective (Hillaire 2020's camera volume, laid out as a 2D atlas): for each of 32 x 32
// view rays across the screen and 32 distances along them, the light the air scatters towards
// the eye over that distance and the transmittance over it. Distances count from where the ray
// enters the air (the eye, or the air's top seen from above it: nothing happens in space).
// Slice k ends at D (k + 1)^2 / 32^2 past it, D the ray's own path through the air to the sea's
// sphere, or to the limb's distance for a ray that passes above the limb (glsl/planet.glsl
// mean_sea_point's): the last slice holds the whole path to the sea, exactly where the sea is
// seen, and the slices change continuously from ray to ray across the limb.
// Texel (32 k + column, row) of each atlas. Integrated like the sky (atmosphere.glsl), SUBSTEPS
// samples per slice.
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
layout(set = 0, binding = 5) uniform sampler2D multiple_scattering_table;
#define TRANSMITTANCE_TABLE transmittance_table
#define MULTIPLE_SCATTERING_TABLE multiple_scattering_table
#include "planet.glsl"
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D inscatter_atlas;
layout(set = 0, binding = 6, rgba16f) writeonly uniform image2D transmittance_atlas;

const int SUBSTEPS = 4;

// In-scatter over [t0, t1] past the ray's entry into the air, SUBSTEPS midpoint samples.
vec3 inscatter_between(AirRay a, float t0, float t1) {
    float r = bottom_radius() + a.h;
    float phase_r = rayleigh_phase(a.nu), phase_m = mie_phase(a.nu);
    float dt = (t1 - t0) / float(SUBSTEPS);
    vec3 L = vec3(0.0);
    for (int i = 0; i < SUBSTEPS; ++i) {
        float t = t0 + (float(i) + 0.5) * dt;
        float h_t = clamp(altitude_along(a.h, a.mu, t), 0.0, atmosphere_height());
        float mu_s = clamp((r * a.mu_s + t * a.nu) / (bottom_radius() + h_t), -1.0, 1.0);
        Medium m = medium_at(h_t);
        vec3 single = sun_transmittance(h_t, mu_s) * (m.rayleigh * phase_r + m.mie * phase_m);
        vec3 multiple = (m.rayleigh + m.mie) * multiple_scattering(h_t, mu_s);
        L += aerial_transmittance(a.h, a.mu, t) * (single + multiple) * dt;
    }
    return L;
}

void main() {
    ivec2 column = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(column, ivec2(AERIAL_SIZE)))) return;
    vec3 dir = normalize(camera_ray((vec2(column) + 0.5) / float(AERIAL_SIZE) * 2.0 - 1.0));
    AirRay ray = air_ray(frame.atmosphere[4].z, dir, frame.sun_dir.xyz);
    float span = aerial_span(dir);
    vec3 L = vec3(0.0);
    float t0 = 0.0;
    for (int k = 0; k < AERIAL_SIZE; ++k) {
        float t1 = span * float((k + 1) * (k + 1)) / float(AERIAL_SIZE * AERIAL_SIZE);
        if (ray.enters) L += inscatter_between(ray, t0, t1);
        t0 = t1;
        vec3 T = ray.enters ? aerial_transmittance(ray.h, ray.mu, t1) : vec3(1.0);
        ivec2 texel = ivec2(k * AERIAL_SIZE + column.x, column.y);
        imageStore(inscatter_atlas, texel, vec4(store_radiance(L * frame.atmosphere[4].x), 1.0));
        imageStore(transmittance_atlas, texel, vec4(T, 1.0));
    }
}
