#version 450
// A host's frame tone-mapped into its LDR target (src/render/passes/host_tonemap.rs): the host's
// HDR colour, the ocean and the host's objects alike, in the host's radiance unit (frame.host.x
// per kcd/m^2, > 0), through the same curve as the ocean's own pictures (glsl/tone.glsl).
#include "frame.glsl"
#include "tone.glsl"

layout(constant_id = 0) const bool ENCODE_SRGB = false;
layout(set = 0, binding = 4) uniform sampler2D hdr;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 mapped = tone_map(texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb / frame.host.x);
    out_color = vec4(ENCODE_SRGB ? srgb_encode(mapped) : mapped, 1.0);
}
