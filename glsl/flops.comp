#version 450
// What the device delivers for the shading loop's kind of work: independent fused multiply-adds,
// 16 chains per invocation (four vec4s: enough to hide an FMA's latency on a CPU's vector units),
// eight rounds of them written out per loop iteration so that the loop's own bookkeeping is a
// small share, and the result stored so that nothing is optimised away. Timed by
// src/measure/floor.rs, which counts 8 x 16 FMAs (256 flops) per iteration.
layout(local_size_x = 64) in;
layout(constant_id = 0) const int ITERATIONS = 256;
layout(set = 0, binding = 0, std430) writeonly buffer Sink { vec4 sink[]; };

#define ROUND a = fma(a, m, k); b = fma(b, m, k); c = fma(c, m, k); d = fma(d, m, k)

void main() {
    // Every component different, so that no compiler can merge the chains.
    vec4 x = float(gl_GlobalInvocationID.x) * 1e-9 + vec4(0.0, 1.0, 2.0, 3.0) * 1e-3;
    vec4 a = x + 0.1, b = x + 0.2, c = x + 0.3, d = x + 0.4;
    const vec4 m = vec4(0.9999999), k = vec4(1e-7);
    for (int i = 0; i < ITERATIONS; ++i) {
        ROUND; ROUND; ROUND; ROUND; ROUND; ROUND; ROUND; ROUND;
    }
    sink[gl_GlobalInvocationID.x] = a + b + c + d;
}
