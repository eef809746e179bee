#version 450
// The sky seen directly (the physical sky from the eye's own sky-view table, or Preetham's), in
// the rows only sky covers (drawn by the visibility pass, so that the shading pass can skip those
// rows): the radiance goes into the HDR image's bits as the RGBA16F texel.
#include "frame.glsl"
#include "common.glsl"
layout(set = 0, binding = 10) uniform sampler2D eye_sky;   // resources::EYE_SKY_BINDING
#define EYE_SKY_SAMPLER eye_sky
#include "sky.glsl"

layout(location = 0) out uvec4 out_radiance_bits;

void main() {
    vec3 dir = normalize(camera_ray(pixel_to_ndc(gl_FragCoord.xy)));
    out_radiance_bits = radiance_to_bits(store_radiance(sky_seen(dir) + sun_disc(dir)));
}
