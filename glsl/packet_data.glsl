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
// Envelope tails beyond this many sigmas are left out (packets::ENVELOPE_SIGMAS).
const float PACKET_SIGMAS = 4.0;

#endif
