#version 450
// One level of the objects' depth pyramid (src/render/passes/reflections.rs): each texel the
// nearest forward depth of the texels below it, the trailing row and column of an odd level
// folded into the last texel, so that a cell never hides an object from a ray.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D finer;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D coarser;

// The texels written: origin <= q < end (src/render/passes/mod.rs dispatch_within).
layout(push_constant) uniform Region { ivec2 origin; ivec2 end; } region;

void main() {
    ivec2 q = region.origin + ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(coarser), below = imageSize(finer);
    if (any(greaterThanEqual(q, min(size, region.end)))) return;
    ivec2 first = 2 * q;
    // The last texel takes a third row or column where the finer level is odd.
    ivec2 last = min(first + 1 + ivec2(equal(q, size - 1)) * (below & 1), below - 1);
    float nearest = 3.0e38;
    for (int y = first.y; y <= last.y; y++)
        for (int x = first.x; x <= last.x; x++)
            nearest = min(nearest, imageLoad(finer, ivec2(x, y)).r);
    imageStore(coarser, q, vec4(nearest));
}
