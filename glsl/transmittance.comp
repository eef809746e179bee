#version 450
// The transmittance table: from each (altitude, zenith cosine) of Bruneton (2017)'s
// parametrization to the top of the atmosphere, by the trapezoid rule over 500 intervals
// (src/model/atmosphere.rs, transmittance_to_top).
#include "frame.glsl"
#include "common.glsl"
#include "atmosphere.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D table;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, TRANSMITTANCE_SIZE))) return;
    vec2 h_mu = transmittance_h_mu((vec2(texel) + 0.5) / vec2(TRANSMITTANCE_SIZE));
    imageStore(table, texel, vec4(integrate_transmittance(h_mu.x, h_mu.y, 500), 1.0));
}
