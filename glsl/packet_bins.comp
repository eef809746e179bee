#version 450
// Bins the frame's packets (copied from the slot's upload window by a transfer) into the cells of
// their grid (model::packets::grid, whose `lists` is the CPU's twin), in three steps (push
// constant `step`), each a dispatch behind a barrier:
//   0: each cell's count of the packets whose rectangle meets it, from its tile's list (one
//      invocation per cell, TILE x TILE of them per tile, TILES_PER_GROUP tiles a workgroup);
//   1: the counts' exclusive prefix sum, each cell's start (one workgroup);
//   2: each cell's list written from its tile's list, as step 0.
// A tile's list is in packet order (the CPU's grid::PacketGrid::tile_packets, in the slot's tile
// window), so every cell's list is too: no atomics, no sort, the same lists on every run.
#include "frame.glsl"
#include "packet_data.glsl"

const uint TILE = 4u;   // grid::TILE_CELLS
const uint GROUP = 256u;   // passes/packets.rs BIN_GROUP: the scan's width, and 16 tiles
layout(local_size_x = 256) in;

layout(set = 0, binding = 3, std430) buffer Cells { uint cells[]; };
layout(set = 0, binding = 4, std430) buffer Counters { uint counters[]; };
// Each slot's tiles: MAX_PACKET_TILES + 1 starts, then the lists (render/packets.rs), an entry
// a packet's index and its cell range within the tile (grid::tile_entry).
layout(set = 0, binding = 5, std430) readonly buffer Tiles { uint tiles[]; };
// The frame's packets as the drawing passes read them, PACKET_TEXELS texels a packet, the last
// two its quad in the cells' plane (render/packets.rs PacketTexels): a texel fetch gathers across
// SIMD lanes where a CPU driver loads a storage buffer's struct lane by lane and word by word.
layout(set = 0, binding = 6) uniform samplerBuffer packet_texels;
// room: the lists' length, which the CPU's count of the entries (grid::PacketGrid::entries, the
// same test) keeps them within. Should a device round the rectangle's test otherwise (Vulkan
// also allows rounding towards zero), the starts are held within the room and a list's entries
// past it dropped: no write or read leaves the lists. tile_first: the slot's tile window (words).
layout(push_constant) uniform Step { uint step; uint room; uint tile_first; } call;

const uint TILE_INVOCATIONS = TILE * TILE;
const uint TILES_PER_GROUP = GROUP / TILE_INVOCATIONS;
const uint MAX_PACKET_TILES = MAX_PACKET_CELLS / TILE_INVOCATIONS;   // grid::MAX_TILES
const uint CELLS_PER_INVOCATION = MAX_PACKET_CELLS / GROUP;
const uint INDEX_BITS = 24u;   // grid::TILE_INDEX_BITS
shared uint partial[GROUP];

// Whether the packet's quad (corners a, b, c, d counter-clockwise) meets cell (x, y):
// grid::Footprint::meets, its twin to the bit (precise: no operation fused, each rounded in the
// same order; Vulkan rounds +, - and * correctly), so that these lists are the CPU's.
bool edge_keeps(vec2 centre, vec2 half_side, vec2 p, vec2 n) {
    precise float ex = n.x - p.x, ey = n.y - p.y;
    precise float dx = centre.x - p.x, dy = centre.y - p.y;
    // The outward normal of a counter-clockwise edge (e.x, e.y) is (e.y, -e.x).
    precise float beyond = dx * ey - dy * ex;
    precise float reach = half_side.x * abs(ey) + half_side.y * abs(ex);
    return beyond < reach;
}

bool cell_meets(vec4 ab, vec4 cd, uint x, uint y) {
    precise float sx = frame.packet_grid.z, sy = frame.packet_grid.w;
    precise vec2 half_side = vec2(0.5 * sx, 0.5 * sy);
    precise vec2 centre = vec2(frame.packet_grid.x + (float(x) + 0.5) * sx, frame.packet_grid.y + (float(y) + 0.5) * sy);
    return edge_keeps(centre, half_side, ab.xy, ab.zw) && edge_keeps(centre, half_side, ab.zw, cd.xy)
        && edge_keeps(centre, half_side, cd.xy, cd.zw) && edge_keeps(centre, half_side, cd.zw, ab.xy);
}

void main() {
    uint cols = frame.packet_dims.x, rows = frame.packet_dims.y;
    uint cell_count = cols * rows;
    if (call.step == 1u) {
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
            cells[c] = min(start, call.room);
            start += counters[c];
        }
        if (t == GROUP - 1u) cells[cell_count] = min(partial[t], call.room);
        return;
    }
    // Steps 0 and 2: this invocation's cell (lx, ly) of its tile, and the tile's list (none past
    // the frame's tiles).
    uint tiles_x = (cols + TILE - 1u) / TILE;
    uint tile = gl_WorkGroupID.x * TILES_PER_GROUP + gl_LocalInvocationID.x / TILE_INVOCATIONS;
    uint in_tile = gl_LocalInvocationID.x % TILE_INVOCATIONS;
    uint lx = in_tile % TILE, ly = in_tile / TILE;
    uint x = tile % tiles_x * TILE + lx, y = tile / tiles_x * TILE + ly;
    bool listed = tile < frame.packet_dims.w;
    bool inside = listed && x < cols && y < rows;
    uint cell = y * cols + x;
    bool writes = call.step == 2u && inside;
    uint n = writes ? cells[cell] : 0u, last = writes ? cells[cell + 1u] : 0u;
    uint list = call.tile_first + MAX_PACKET_TILES + 1u;
    uint begin = listed ? tiles[call.tile_first + tile] : 0u;
    uint end = listed ? tiles[call.tile_first + tile + 1u] : 0u;
    for (uint j = begin; j < end; ++j) {
        uint entry = tiles[list + j];
        uint i = entry & ((1u << INDEX_BITS) - 1u);
        // The packet's cell range within the tile: the CPU tests no cell outside it.
        uvec4 range = (uvec4(entry) >> (uvec4(0u, 2u, 4u, 6u) + INDEX_BITS)) & 3u;
        if (!inside || lx < range.x || ly < range.y || lx > range.z || ly > range.w) continue;
        vec4 ab = texelFetch(packet_texels, PACKET_TEXELS * int(i) + 3);
        vec4 cd = texelFetch(packet_texels, PACKET_TEXELS * int(i) + 4);
        if (!cell_meets(ab, cd, x, y)) continue;
        if (writes && n < last) cells[PACKET_LISTS + n] = i;
        ++n;
    }
    if (call.step == 0u && inside) counters[cell] = n;
}
