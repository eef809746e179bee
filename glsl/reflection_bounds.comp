#version 450
// The screen rectangle that holds every object the sea may reflect, and their nearest forward
// depth (src/render/passes/reflections.rs), from one coarse level of their depth pyramid: a
// reflected ray whose screen path misses the rectangle, or stays nearer than every object,
// meets nothing, and skips its march (glsl/shade.glsl local_reflection). One
// workgroup; each invocation folds a strided share of the level's cells.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D base;     // level 0: its size only
layout(set = 0, binding = 1, r32f) uniform readonly image2D coarse;   // level `shift`
layout(set = 0, binding = 2, std430) writeonly buffer Bounds { vec4 rect; float nearest; } bounds;
// The coarse level's index: a cell spans 2^shift pixels of level 0.
layout(constant_id = 0) const int SHIFT = 0;

// An object's depth is finite; NO_OBJECT in glsl/reflection_sources.comp marks none.
const float NO_OBJECT = 3.0e38;

// Positive floats order as their bits do: the nearest depth is reduced as an int.
shared int lo_x, lo_y, hi_x, hi_y, nearest_bits;

void main() {
    uint i = gl_LocalInvocationIndex;
    if (i == 0u) {
        lo_x = 0x7fffffff;
        lo_y = 0x7fffffff;
        hi_x = -1;
        hi_y = -1;
        nearest_bits = floatBitsToInt(NO_OBJECT);
    }
    barrier();
    ivec2 cells = imageSize(coarse), pixels = imageSize(base);
    ivec4 mine = ivec4(0x7fffffff, 0x7fffffff, -1, -1);
    float nearest = NO_OBJECT;
    for (int k = int(i); k < cells.x * cells.y; k += 64) {
        ivec2 c = ivec2(k % cells.x, k / cells.x);
        float depth = imageLoad(coarse, c).r;
        if (!(depth < NO_OBJECT)) continue;
        nearest = min(nearest, depth);
        // A level's last cell also holds an odd finer level's trailing texels: it reaches the
        // screen's edge.
        ivec2 first = c << SHIFT;
        ivec2 past = mix(min((c + 1) << SHIFT, pixels), pixels, equal(c, cells - 1));
        mine = ivec4(min(mine.xy, first), max(mine.zw, past));
    }
    atomicMin(lo_x, mine.x);
    atomicMin(lo_y, mine.y);
    atomicMax(hi_x, mine.z);
    atomicMax(hi_y, mine.w);
    atomicMin(nearest_bits, floatBitsToInt(max(nearest, 0.0)));
    barrier();
    // Empty (lo past hi) where no cell holds an object.
    if (i == 0u) {
        bounds.rect = vec4(lo_x, lo_y, hi_x, hi_y);
        bounds.nearest = intBitsToFloat(nearest_bits);
    }
}
