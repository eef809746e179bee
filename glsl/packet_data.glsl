// A wave packet as the GPU holds it (src/render/packets.rs GpuPacket, std430, 48 bytes), and the
// layout of the cells' lists (model::packets::grid): each cell's start in the lists, one more
// start than cells, then the lists' packet indices.
#ifndef PACKET_DATA_GLSL
#define PACKET_DATA_GLSL

struct Packet {
    vec4 centre_k;   // xy: the envelope's centre (m, camera-relative); zw: wave vector (turns per m)
    vec4 envelope;   // xy: the envelope's first axis over its sigma; zw: the second's (1/m)
    vec4 wave;       // x: amplitude at the centre (m); y: phase there (turns, [0, 1));
                     // zw: its cells' range as uint bits, first column | row << 16, last the same
};

const uint MAX_PACKET_CELLS = 65536u;   // grid::MAX_CELLS
// Where the lists start in the cells' buffer: after the MAX_PACKET_CELLS + 1 starts.
const uint PACKET_LISTS = MAX_PACKET_CELLS + 1u;
// A packet's envelope: exp(-r^2 / 2) on its normalized ellipse, tapered to 0 by a smoothstep from
// PACKET_TAPER to PACKET_SIGMAS sigmas (packets::ENVELOPE_TAPER, ENVELOPE_SIGMAS).
const float PACKET_SIGMAS = 3.25;
const float PACKET_TAPER = 2.75;

// The envelope at normalized coordinates (u, v) and its derivatives in them (model::packets::
// tapered_envelope is its twin); 0 from PACKET_SIGMAS out. r >= PACKET_TAPER > 0 where the taper
// divides by it.
vec3 packet_envelope(float u, float v) {
    float r2 = u * u + v * v;
    if (r2 >= PACKET_SIGMAS * PACKET_SIGMAS) return vec3(0.0);
    float g = exp(-0.5 * r2);   // r2 < 10.6: no underflow
    float w = 1.0, dw_over_r = 0.0;
    if (r2 > PACKET_TAPER * PACKET_TAPER) {
        float r = sqrt(r2);
        const float width = PACKET_SIGMAS - PACKET_TAPER;
        float t = (r - PACKET_TAPER) / width;
        w = 1.0 - t * t * (3.0 - 2.0 * t);
        dw_over_r = -6.0 * t * (1.0 - t) / (width * r);
    }
    return vec3(g * w, g * u * (dw_over_r - w), g * v * (dw_over_r - w));
}

#endif
