#version 450
// The window's picture: the HDR radiance tone-mapped into the swapchain image, one texel per
// pixel. An sRGB swapchain format encodes on store; a UNORM one gets the encoding here.
#include "frame.glsl"
#include "tone.glsl"

layout(constant_id = 0) const bool ENCODE_SRGB = false;
layout(set = 0, binding = 4) uniform sampler2D hdr;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 mapped = tone_map(texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb);
    out_color = vec4(ENCODE_SRGB ? srgb_encode(mapped) : mapped, 1.0);
}
