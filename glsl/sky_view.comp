#version 450
// The sky-view table (Hillaire 2020): the physical sky raymarched from the eye's altitude
// through the atmosphere's tables, over the upper hemisphere in atmosphere.glsl's
// parametrization (sky_view_uv); the sky map is resampled from it, so a moving sun costs 256 x 128
// raymarches, not 512 x 512.
#include "frame.glsl"
#include "common.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
layout(set = 0, binding = 5) uniform sampler2D multiple_scattering_table;
#define TRANSMITTANCE_TABLE transmittance_table
#define MULTIPLE_SCATTERING_TABLE multiple_scattering_table
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D sky_view;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, SKY_VIEW_SIZE))) return;
    vec3 dir = sky_view_direction((vec2(texel) + 0.5) / vec2(SKY_VIEW_SIZE));
    imageStore(sky_view, texel, vec4(store_radiance(physical_sky_radiance(frame.atmosphere[4].z, dir)), 1.0));
}
