#version 450
// Bins the frame's packets into the cells of their grid (model::packets::grid, whose `lists`
// is the CPU's twin), in five steps (push constant `step`), each a dispatch behind a barrier:
//   0: every cell's counter to 0 (one invocation per cell);
//   1: each packet copied from the slot's upload window and counted into the cells of its
//      range that its rectangle meets (one per packet);
//   2: the counts' exclusive prefix sum, each cell's start (one workgroup), the counters set to
//      the starts;
//   3: each packet's index written at those cells' counters (one per packet);
//   4: each cell's list sorted by packet index (one per cell): the atomics' order varies from
//      run to run, and the sums the shaders form in list order should not.
#include "frame.glsl"
#include "packet_data.glsl"

layout(local_size_x = 256) in;   // passes/packets.rs BIN_GROUP

layout(set = 0, binding = 1, std430) readonly buffer Upload { Packet upload[]; };
layout(set = 0, binding = 2, std430) writeonly buffer Packets { Packet packets[]; };
layout(set = 0, binding = 3, std430) buffer Cells { uint cells[]; };
layout(set = 0, binding = 4, std430) buffer Counters { uint counters[]; };
// first: the slot's window; room: the lists' length, which the CPU's count of the entries
// (grid::PacketGrid::entries, the same test) keeps them within. Should a device round the
// rectangle's test otherwise (Vulkan also allows rounding towards zero), the starts are held
// within the room and a list's entries past it dropped: no write or read leaves the lists.
layout(push_constant) uniform Step { uint step; uint first; uint room; } call;

const uint GROUP = 256u;
const uint CELLS_PER_INVOCATION = MAX_PACKET_CELLS / GROUP;
shared uint partial[GROUP];

// A packet's cells: first column and row, last column and row.
uvec4 cell_range(Packet p) {
    uint first = floatBitsToUint(p.wave.z), last = floatBitsToUint(p.wave.w);
    return uvec4(first & 0xffffu, first >> 16, last & 0xffffu, last >> 16);
}

// Whether packet p's rectangle meets cell (x, y): grid::Footprint::meets, its twin to the bit
// (precise: no operation fused, each rounded in the same order; Vulkan rounds +, - and *
// correctly), so that these lists are the CPU's.
bool cell_meets(Packet p, uint x, uint y) {
    precise float side = frame.packet_grid.w;
    precise float half_side = 0.5 * side;
    precise float rx = (frame.packet_grid.x + (float(x) + 0.5) * side) - p.centre_k.x;
    precise float ry = (frame.packet_grid.y + (float(y) + 0.5) * side) - p.centre_k.y;
    precise float u = rx * p.envelope.x + ry * p.envelope.y;
    precise float v = rx * p.envelope.z + ry * p.envelope.w;
    precise float reach_u = PACKET_SIGMAS + half_side * (abs(p.envelope.x) + abs(p.envelope.y));
    precise float reach_v = PACKET_SIGMAS + half_side * (abs(p.envelope.z) + abs(p.envelope.w));
    return abs(u) < reach_u && abs(v) < reach_v;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    uint cols = frame.packet_dims.x;
    uint cell_count = cols * frame.packet_dims.y;
    uint packet_count = frame.packet_dims.z;
    if (call.step == 0u) {
        if (i < cell_count) counters[i] = 0u;
    } else if (call.step == 1u) {
        if (i >= packet_count) return;
        Packet p = upload[call.first + i];
        packets[i] = p;
        uvec4 r = cell_range(p);
        for (uint y = r.y; y <= r.w; ++y)
            for (uint x = r.x; x <= r.z; ++x)
                if (cell_meets(p, x, y)) atomicAdd(counters[y * cols + x], 1u);
    } else if (call.step == 2u) {
        // Invocation t sums cells [t n, t n + n), n = CELLS_PER_INVOCATION; the group's partial
        // sums are scanned in shared memory, then each invocation writes its cells' starts.
        uint t = gl_LocalInvocationID.x, begin = t * CELLS_PER_INVOCATION;
        uint end = min(begin + CELLS_PER_INVOCATION, cell_count);
        uint sum = 0u;
        for (uint c = begin; c < end; ++c) sum += counters[c];
        partial[t] = sum;
        barrier();
        // Hillis-Steele inclusive scan over the group's partial sums.
        for (uint offset = 1u; offset < GROUP; offset *= 2u) {
            uint before = t >= offset ? partial[t - offset] : 0u;
            barrier();
            partial[t] += before;
            barrier();
        }
        uint start = partial[t] - sum;
        for (uint c = begin; c < end; ++c) {
            uint count = counters[c];
            cells[c] = min(start, call.room);
            counters[c] = start;
            start += count;
        }
        if (t == GROUP - 1u) cells[cell_count] = min(partial[t], call.room);
    } else if (call.step == 3u) {
        if (i >= packet_count) return;
        Packet p = upload[call.first + i];
        uvec4 r = cell_range(p);
        for (uint y = r.y; y <= r.w; ++y)
            for (uint x = r.x; x <= r.z; ++x) {
                if (!cell_meets(p, x, y)) continue;
                uint slot = atomicAdd(counters[y * cols + x], 1u);
                if (slot < call.room) cells[PACKET_LISTS + slot] = i;
            }
    } else {
        if (i >= cell_count) return;
        // Insertion sort of the cell's run: runs are a few dozen packets.
        uint begin = PACKET_LISTS + cells[i], end = PACKET_LISTS + cells[i + 1u];
        for (uint a = begin + 1u; a < end; ++a) {
            uint v = cells[a];
            uint b = a;
            for (; b > begin && cells[b - 1u] > v; --b) cells[b] = cells[b - 1u];
            cells[b] = v;
        }
    }
}
