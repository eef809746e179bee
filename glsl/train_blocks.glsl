// surface_sample with the wave table read a block of trains at a time: lane j of a subgroup reads
// train (first - j), and every lane takes the block's trains from those lanes by broadcast with a
// constant lane index. A driver that cannot prove a loop index uniform gathers a loop-indexed
// read lane by lane (llvmpipe does); here one such read serves TRAIN_BLOCK trains, and the
// broadcasts are register moves. Needs subgroups of at least TRAIN_BLOCK lanes with the basic,
// ballot, vote and arithmetic operations (src/render/passes/shade.rs checks), and all lanes of
// the subgroup to call it together: the loops' exits are uniform over the subgroup.
// Requires waves.glsl.
#ifndef TRAIN_BLOCKS_GLSL
#define TRAIN_BLOCKS_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_KHR_shader_subgroup_vote : require
#extension GL_KHR_shader_subgroup_arithmetic : require

const int TRAIN_BLOCK = 8;

// This lane's train of the block that starts at `first` (the block's longest), packed. Past the
// shortest train the slot holds train 0 with no amplitude: its wave vector stays a real one (so
// the direction k/|k| is finite) and everything it adds is 0.
uvec2 load_block_slot(int first) {
    int index = first - int(gl_SubgroupInvocationID % uint(TRAIN_BLOCK));
    uvec2 data = wave_data[max(index, 0)].xy;
    return index >= 0 ? data : uvec2(data.x, data.y & 0xffffu);
}

// Train j of the block, from lane j. Broadcasting the two packed words and unpacking them in
// every lane is cheaper than broadcasting the unpacked values (measured on llvmpipe).
Wave block_train(uvec2 slot, uint j) {
    return unpack_wave(subgroupBroadcast(slot, j));
}

#define FOR_EACH_BLOCK_TRAIN(BODY) \
    BODY(0u) BODY(1u) BODY(2u) BODY(3u) BODY(4u) BODY(5u) BODY(6u) BODY(7u)

// The same sums as surface_sample, to rounding: a train past a pixel's cut that shares a block
// with trains another pixel of the subgroup resolves enters with weight 0, i.e. its whole
// variance in the loop rather than in the prefix. `resolves`: whether this lane's pixel resolves
// anything (others pass along, adding nothing to the loops' extent, and get the flat surface).
SurfaceSample surface_sample_blocked(vec2 x, SampleScale s, vec2 steps, bool resolves) {
    SurfaceSample r = flat_surface();
    // Over the subgroup's resolving pixels: the largest step (for the test of full resolution,
    // done once per train for them all) and the smallest cut.
    float reach2 = subgroupMax(resolves ? largest_step2(s) : 0.0);
    float cut2_min = subgroupMin(resolves ? s.lambda_cut2 : 3.0e38);
    int first = subgroupAny(resolves) ? int(frame.grid_dims.z) - 1 : -1;
    uvec2 slot = load_block_slot(first);
    // Blocks whose every train is resolved fully at every resolving pixel of the subgroup.
    while (first >= 0 && subgroupAll(fully_resolved(unpack_wave(slot), reach2, steps))) {
#define RESOLVED(j) { Wave t = block_train(slot, j); add_resolved_train(r, t, wave_direction(t), x); }
        FOR_EACH_BLOCK_TRAIN(RESOLVED)
#undef RESOLVED
        first -= TRAIN_BLOCK;
        slot = load_block_slot(first);
    }
    // Then whole blocks while some resolving pixel needs even the block's shortest train (a
    // missing train's slot holds train 0, the shortest of all)...
    while (first >= 0) {
        vec2 shortest = block_train(slot, uint(TRAIN_BLOCK - 1)).k;
        if (!(dot(shortest, shortest) * cut2_min < 1.0)) break;
#define WEIGHTED(j) add_train(r, block_train(slot, j), x, s);
        FOR_EACH_BLOCK_TRAIN(WEIGHTED)
#undef WEIGHTED
        first -= TRAIN_BLOCK;
        slot = load_block_slot(first);
    }
    // ...and the rest train by train, each pixel to its own cut (at most a block's worth: a
    // view that resolves few trains would otherwise evaluate a whole block of them).
    add_trains_from(r, first, x, s);
    return resolves ? r : flat_surface();
}

#endif
