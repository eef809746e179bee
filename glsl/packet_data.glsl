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
// A packet's envelope: exp(-u^2 / 2) exp(-v^2 / 2) on its normalized axes, each factor tapered
// to 0 by a smoothstep from PACKET_TAPER to PACKET_SIGMAS sigmas (packets::ENVELOPE_TAPER,
// ENVELOPE_SIGMAS): it reaches PACKET_SIGMAS along each axis.
const float PACKET_SIGMAS = 2.3;
const float PACKET_TAPER = 1.8;

// Whether normalized coordinates (u, v) lie within a packet's reach.
bool packet_reaches(float u, float v) {
    return max(abs(u), abs(v)) < PACKET_SIGMAS;
}

// One axis's taper at |t| = a, and its derivative in a: 1 - smoothstep(PACKET_TAPER,
// PACKET_SIGMAS, a) within the reach.
vec2 packet_taper(float a) {
    if (a <= PACKET_TAPER) return vec2(1.0, 0.0);
    const float width = PACKET_SIGMAS - PACKET_TAPER;
    float s = min((a - PACKET_TAPER) / width, 1.0);
    return vec2(1.0 - s * s * (3.0 - 2.0 * s), -6.0 * s * (1.0 - s) / width);
}

// The envelope at normalized coordinates (u, v) within its reach, and its derivatives in them
// (model::packets::tapered_envelope is its twin).
vec3 packet_envelope(float u, float v) {
    float g = exp(-0.5 * (u * u + v * v));   // u^2 + v^2 < 2 PACKET_SIGMAS^2 = 10.6: no underflow
    vec2 tu = packet_taper(abs(u)), tv = packet_taper(abs(v));
    // d/du of g(u) w(|u|) = g (w' sign(u) - u w).
    float du = tu.y * sign(u) - u * tu.x, dv = tv.y * sign(v) - v * tv.x;
    return g * vec3(tu.x * tv.x, du * tv.x, tu.x * dv);
}

#endif
