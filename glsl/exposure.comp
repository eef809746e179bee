#version 450
// Automatic exposure (render.ev100 = "auto"): the frame's log-average luminance L (Reinhard et
// al. 2002's key), read at every 4th pixel of every 4th row by one workgroup, sets
// EV100 = log2(L S / K) with S = 100, K = 12.5 (the reflected-light meter's calibration; Lagarde &
// de Rousiers 2014), and the display scale 1000 / (1.2 2^EV100) per kcd/m^2 (scene::ev100_to_exposure).
// Luminance below 1e-3 cd/m^2 (where vision turns scotopic) is left out of the key, so black
// pixels (night, the cleared background, space around the planet seen from orbit) neither send
// the logarithm to -inf nor dominate it: the meter reads the lit subject, as a photographer's
// spot meter would. An image with nothing brighter has the key 1e-3 cd/m^2.
// 8 x 8 invocations over the image's 2D grid of samples (a workgroup of 64 with neighbours
// reading neighbouring texels, as tile-based GPUs prefer).
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 4, rgba16f) readonly uniform image2D hdr;
layout(set = 0, binding = 7, std140) writeonly buffer MeasuredExposure { vec4 measured; } result;

const float DARKEST_CD = 1e-3;
const uint LANES = 64u;
shared float partial[LANES];
shared uint counted[LANES];

void main() {
    ivec2 size = imageSize(hdr);
    float sum = 0.0;
    uint n = 0u;
    ivec2 lane = ivec2(gl_LocalInvocationID.xy);
    for (int y = lane.y * 4; y < size.y; y += 8 * 4) {
        for (int x = lane.x * 4; x < size.x; x += 8 * 4) {
            vec3 L = imageLoad(hdr, ivec2(x, y)).rgb;
            float Y = 1000.0 * dot(max(L, vec3(0.0)), vec3(0.2126, 0.7152, 0.0722));   // cd/m^2
            bool lit = Y >= DARKEST_CD;
            sum += lit ? log2(Y) : 0.0;
            n += lit ? 1u : 0u;
        }
    }
    partial[gl_LocalInvocationIndex] = sum;
    counted[gl_LocalInvocationIndex] = n;
    barrier();
    for (uint stride = LANES / 2u; stride > 0u; stride >>= 1) {
        if (gl_LocalInvocationIndex < stride) {
            partial[gl_LocalInvocationIndex] += partial[gl_LocalInvocationIndex + stride];
            counted[gl_LocalInvocationIndex] += counted[gl_LocalInvocationIndex + stride];
        }
        barrier();
    }
    if (gl_LocalInvocationIndex == 0u) {
        float key = counted[0] > 0u ? partial[0] / float(counted[0]) : log2(DARKEST_CD);
        float ev100 = key + log2(100.0 / 12.5);
        result.measured = vec4(1000.0 / (1.2 * exp2(ev100)), ev100, key, 0.0);
    }
}
