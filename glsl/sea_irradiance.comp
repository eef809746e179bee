#version 450
// The light at sea level as a function of the sun's zenith cosine (a table over
// glsl/atmosphere.glsl's sea_irradiance_u), for each sea point under its own sun on the sphere
// (the night side, the terminator seen from high up; glsl/shade.glsl): row 0 the sky's irradiance
// on level sea, row 1 the sun's irradiance normal to it (the transmittance table's at sea level,
// zero where the planet hides the sun's centre), so that a point's light is two fetches at one
// coordinate. The sky's by the same midpoint rule as the CPU's model::sky::horizontal_irradiance(16,
// 32): 16 zenith cosines, 32 azimuths, here 16 over [0, pi] doubled, the sky being symmetric about
// the sun's vertical plane.
#include "frame.glsl"
#include "common.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
layout(set = 0, binding = 5) uniform sampler2D multiple_scattering_table;
#define TRANSMITTANCE_TABLE transmittance_table
#define MULTIPLE_SCATTERING_TABLE multiple_scattering_table
#include "atmosphere.glsl"

// 256 texels as a 32 x 8 dispatch of 8 x 8 groups (passes::dispatch_over): texel x + 32 y.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D table;

const int ZENITH_SAMPLES = 16;
const int AZIMUTH_SAMPLES = 16;

void main() {
    int i = int(gl_GlobalInvocationID.x + 32u * gl_GlobalInvocationID.y);
    if (i >= SEA_IRRADIANCE_SIZE) return;
    float x = texcoord_to_unit((float(i) + 0.5) / float(SEA_IRRADIANCE_SIZE), SEA_IRRADIANCE_SIZE);
    float mu_s = SEA_IRRADIANCE_MU_MIN + x * (1.0 - SEA_IRRADIANCE_MU_MIN);
    vec3 sun = vec3(sqrt(max(1.0 - mu_s * mu_s, 0.0)), 0.0, mu_s);
    vec3 E = vec3(0.0);
    for (int a = 0; a < ZENITH_SAMPLES; ++a) {
        float mu = (float(a) + 0.5) / float(ZENITH_SAMPLES);
        float sin_t = sqrt(1.0 - mu * mu);
        for (int b = 0; b < AZIMUTH_SAMPLES; ++b) {
            float phi = (float(b) + 0.5) / float(AZIMUTH_SAMPLES) * PI;
            E += physical_sky_radiance(0.0, vec3(sin_t * cos(phi), sin_t * sin(phi), mu), sun) * mu;
        }
    }
    // dmu dphi over the hemisphere, the azimuths doubled.
    E *= (1.0 / float(ZENITH_SAMPLES)) * (2.0 * PI / float(AZIMUTH_SAMPLES));
    imageStore(table, ivec2(i, 0), vec4(store_radiance(E), 1.0));
    vec3 sun_irradiance = frame.atmosphere[4].x * sun_transmittance(0.0, mu_s);
    imageStore(table, ivec2(i, 1), vec4(store_radiance(sun_irradiance), 1.0));
}
