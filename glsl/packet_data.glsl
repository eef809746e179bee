// A wave packet as the GPU holds it (src/render/packets.rs GpuPacket, std430, 80 bytes: five
// texels), and the layout of the cells' lists (model::packets::grid): each cell's start in the
// lists, one more start than cells, then the lists' packet indices. Requires frame.glsl.
#ifndef PACKET_DATA_GLSL
#define PACKET_DATA_GLSL

struct Packet {
    vec4 centre_k;   // xy: the envelope's centre (m, camera-relative); zw: wave vector (turns per m)
    vec4 envelope;   // xy: the envelope's first axis over its sigma; zw: the second's (1/m)
    vec4 wave;       // x: amplitude at the centre (m); y: phase there (turns, [0, 1));
                     // |z|: wavelength (m, 1 / |k| in turns); |w|: slope amplitude k a;
                     // z and w negative where the row along the first axis, the second's, is in
                     // phase (model::packets::Packet::in_phase)
    vec4 footprint[2];   // its rectangle in the cells' plane, a quad counter-clockwise (the binning's)
};

const int PACKET_TEXELS = 5;

const uint MAX_PACKET_CELLS = 65536u;   // grid::MAX_CELLS
// Where the lists start in the cells' buffer: after the MAX_PACKET_CELLS + 1 starts.
const uint PACKET_LISTS = MAX_PACKET_CELLS + 1u;
// A packet's envelope: w(u) w(v) on its normalized axes, each factor the window
// w(t) = 1 - smoothstep(0, PACKET_SIGMAS, |t|) (packets::ENVELOPE_SIGMAS, a partition of unity
// two sigmas apart): it reaches PACKET_SIGMAS along each axis.
const float PACKET_SIGMAS = 2.0;

// Rest position x in the cells' plane (grid::CellMap::apply): itself where the map's offset is
// 0, else its perspective, (x . left, 1) / w with w = x . forward + offset; behind the
// perspective's centre (w <= 0, never a rest position the frame evaluates) a point below every
// cell (q.y < 0, where the view's cells have q.y > 0).
vec2 packet_plane_point(vec2 x) {
    vec4 m = frame.packet_map;
    if (m.z == 0.0) return x;
    float w = dot(x, m.xy) + m.z;
    return w > 0.0 ? vec2(dot(x, vec2(-m.y, m.x)), 1.0) / w : vec2(0.0, -1.0);
}

// The cell holding rest position x (grid::PacketGrid::cell), or -1 outside the grid (and for a
// NaN x, which no comparison admits).
int packet_cell(vec2 x) {
    vec2 c = (packet_plane_point(x) - frame.packet_grid.xy) / frame.packet_grid.zw;
    vec2 dims = vec2(frame.packet_dims.xy);
    if (!(c.x >= 0.0 && c.y >= 0.0 && c.x < dims.x && c.y < dims.y)) return -1;
    return int(uint(c.y) * frame.packet_dims.x + uint(c.x));
}

// Whether normalized coordinates (u, v) lie within a packet's reach.
bool packet_reaches(float u, float v) {
    return max(abs(u), abs(v)) < PACKET_SIGMAS;
}

// One axis's window at t and its derivative in t, within the reach.
vec2 packet_window(float t) {
    float x = min(abs(t) * (1.0 / PACKET_SIGMAS), 1.0);
    return vec2(1.0 - x * x * (3.0 - 2.0 * x), -6.0 / PACKET_SIGMAS * x * (1.0 - x) * sign(t));
}

// The envelope from its two axes' windows (packet_window), and its derivatives in u and v
// (model::packets::envelope_at is its twin).
vec3 packet_envelope_of(vec2 wu, vec2 wv) {
    return vec3(wu.x * wv.x, wu.y * wv.x, wu.x * wv.y);
}

// The envelope at normalized coordinates (u, v) within its reach, and its derivatives in them.
vec3 packet_envelope(float u, float v) {
    return packet_envelope_of(packet_window(u), packet_window(v));
}

#endif
