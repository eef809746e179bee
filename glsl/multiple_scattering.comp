#version 450
// Hillaire (2020)'s multiple-scattering table psi_ms(altitude, sun zenith cosine): the light a
// point receives scattered twice, over directions on the sphere (isotropic phase), divided by
// (1 - f_ms), the fraction its surroundings send back; the ground at the end of a downward ray
// reflects as a Lambertian of the atmosphere's ground albedo (atmosphere::multiple_scattering_at).
#include "frame.glsl"
#include "common.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
#define TRANSMITTANCE_TABLE transmittance_table
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D table;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, ivec2(MULTIPLE_SCATTERING_SIZE)))) return;
    vec2 uv = (vec2(texel) + 0.5) / float(MULTIPLE_SCATTERING_SIZE);
    float mu_s = clamp(2.0 * texcoord_to_unit(uv.x, MULTIPLE_SCATTERING_SIZE) - 1.0, -1.0, 1.0);
    float h = texcoord_to_unit(uv.y, MULTIPLE_SCATTERING_SIZE) * atmosphere_height();
    float r = bottom_radius() + h;
    vec3 sun = vec3(sqrt(max(1.0 - mu_s * mu_s, 0.0)), 0.0, mu_s);
    vec3 second = vec3(0.0), transfer = vec3(0.0);
    const float weight = 1.0 / float(MS_DIRECTIONS * MS_DIRECTIONS);
    for (int i = 0; i < MS_DIRECTIONS; ++i) {
        float cos_theta = 1.0 - 2.0 * (float(i) + 0.5) / float(MS_DIRECTIONS);
        float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
        for (int j = 0; j < MS_DIRECTIONS; ++j) {
            float phi = 2.0 * PI * (float(j) + 0.5) / float(MS_DIRECTIONS);
            vec3 dir = vec3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
            float mu = dir.z, nu = dot(dir, sun);
            bool ground = meets_ground(h, mu);
            float d = ground ? distance_to_ground(h, mu) : distance_to_top(h, mu);
            vec3 l = vec3(0.0), f = vec3(0.0);
            for (int k = 0; k < MS_STEPS; ++k) {
                vec2 s = march_step(d, k, MS_STEPS);
                float h_t = clamp(altitude_along(h, mu, s.x), 0.0, atmosphere_height());
                float mu_s_t = clamp((r * mu_s + s.x * nu) / (bottom_radius() + h_t), -1.0, 1.0);
                Medium m = medium_at(h_t);
                vec3 scattering = m.rayleigh + m.mie;
                vec3 tr = transmittance_between(h, mu, s.x);
                l += tr * scattering * sun_transmittance(h_t, mu_s_t) * (s.y / (4.0 * PI));
                f += tr * scattering * s.y;
            }
            if (ground) {
                // The ground point's zenith is its position over R: (dir d + (0, 0, r)) / R.
                float mu_s_g = clamp((r * mu_s + d * nu) / bottom_radius(), -1.0, 1.0);
                l += transmittance_between(h, mu, d) * sun_transmittance(0.0, mu_s_g) * max(mu_s_g, 0.0)
                   * frame.atmosphere[3].w / PI;
            }
            second += l * weight;
            transfer += f * weight;
        }
    }
    // f_ms < 1 for any atmosphere whose air does not scatter everything back (capped as on the CPU).
    imageStore(table, texel, vec4(second / (1.0 - min(transfer, vec3(0.999))), 1.0));
}
