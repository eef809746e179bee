#version 450
// One level of the mirrored objects' coverage and inverse depth (src/render/passes/planar.rs):
// each texel the mean of every texel below it (an odd level's trailing row and column folded
// into its last texel), so that no object is lost however small.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform readonly image2D finer;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2D coarser;

// The texels written: origin <= q < end (src/render/passes/mod.rs dispatch_within).
layout(push_constant) uniform Region { ivec2 origin; ivec2 end; } region;

void main() {
    ivec2 q = region.origin + ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(coarser), below = imageSize(finer);
    if (any(greaterThanEqual(q, min(size, region.end)))) return;
    ivec2 first = 2 * q;
    ivec2 last = min(first + 1 + ivec2(equal(q, size - 1)) * (below & 1), below - 1);
    vec4 sum = vec4(0.0);
    for (int y = first.y; y <= last.y; y++)
        for (int x = first.x; x <= last.x; x++)
            sum += imageLoad(finer, ivec2(x, y));
    imageStore(coarser, q, sum / float((last.x - first.x + 1) * (last.y - first.y + 1)));
}
