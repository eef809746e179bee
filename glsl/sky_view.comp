#version 450
// A sky-view table (Hillaire 2020, glsl/sky_view.glsl's parametrization): the physical sky
// raymarched through the atmosphere's tables, from sea level over the upper hemisphere (the sea's
// table, which the sky map is resampled from, so a moving sun costs 256 x 128 raymarches, not
// 512 x 512), or from the eye over what it sees of the sky (EYE_VIEW: the eye's table, for the
// sky seen directly from high up).
#include "frame.glsl"
#include "common.glsl"
layout(set = 0, binding = 4) uniform sampler2D transmittance_table;
layout(set = 0, binding = 5) uniform sampler2D multiple_scattering_table;
#define TRANSMITTANCE_TABLE transmittance_table
#define MULTIPLE_SCATTERING_TABLE multiple_scattering_table
#include "atmosphere.glsl"

layout(constant_id = 11) const bool EYE_VIEW = false;

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D sky_view;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, SKY_VIEW_SIZE))) return;
    vec3 dir = sky_view_direction((vec2(texel) + 0.5) / vec2(SKY_VIEW_SIZE), EYE_VIEW);
    float h = EYE_VIEW ? frame.atmosphere[4].z : 0.0;
    imageStore(sky_view, texel, vec4(store_radiance(physical_sky_radiance(h, dir, frame.sun_dir.xyz)), 1.0));
}
