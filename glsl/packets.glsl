// Wave packets at the three scales, as the trains (waves.glsl): displaced by the grid at their
// resolution weight, in the per-pixel normal at their normal weight, and the rest of their slope
// variance, times their envelope, in the BRDF. model::packets::Packet is the f64 twin of one
// packet's surface. A rest position reads only its cell's list (passes/packets.rs bins them).
// Requires frame.glsl, common.glsl and waves.glsl.
#ifndef PACKETS_GLSL
#define PACKETS_GLSL
#include "packet_data.glsl"

// Whether the frame has packets (specialization constant 18): without, their loops are gone.
layout(constant_id = 18) const bool PACKETS = false;

// Texel buffers, not storage buffers: a texel fetch gathers across the SIMD lanes where a
// storage buffer's divergent read is fetched lane by lane on a CPU driver (render/packets.rs
// PacketTexels). A packet is PACKET_TEXELS RGBA32_SFLOAT texels; the cells are R32_UINT.
layout(set = 0, binding = 20) uniform samplerBuffer packet_texels;
layout(set = 0, binding = 21) uniform usamplerBuffer packet_cell_texels;

uint packet_cell_word(uint i) {
    return texelFetch(packet_cell_texels, int(i)).x;
}

// Packet i's texel j (0: centre_k, 1: envelope, 2: wave): the envelope test reads the first two,
// and only the packets that pass it fetch the third.
vec4 packet_texel(uint i, int j) {
    return texelFetch(packet_texels, PACKET_TEXELS * int(i) + j);
}

// The run of the lists that holds the packets reaching rest position x: empty outside the grid
// (and for a NaN x, which no comparison admits).
uvec2 packet_run(vec2 x) {
    if (!PACKETS) return uvec2(0u);
    int cell = packet_cell(x);
    if (cell < 0) return uvec2(0u);
    return uvec2(packet_cell_word(uint(cell)), packet_cell_word(uint(cell) + 1u));
}

// The packets' displacement at rest position x, each at the grid's weight (as `displacement`);
// a packet the grid does not resolve (weight 0) costs its reach test alone.
vec3 packets_displacement(vec2 x, SampleScale s, vec2 steps) {
    vec3 d = vec3(0.0);
    uvec2 run = packet_run(x);
    float inv_ramp = 1.0 / (steps.y - steps.x);
    for (uint i = run.x; i < run.y; ++i) {
        uint index = packet_cell_word(PACKET_LISTS + i);
        vec4 centre_k = packet_texel(index, 0), envelope = packet_texel(index, 1);
        vec2 rel = x - centre_k.xy;
        float u = dot(rel, envelope.xy), v = dot(rel, envelope.zw);
        vec2 k_turns = centre_k.zw;
        float weight = resolution_weight(s, k_turns, steps, inv_ramp, 1.0);
        if (!packet_reaches(u, v) || weight <= 0.0) continue;
        vec4 wave = packet_texel(index, 2);
        float h = weight * wave.x * packet_envelope(u, v).x;
        vec2 dir = k_turns * abs(wave.z);
        vec2 sc = sincos_turns(wave.y - dot(k_turns, rel));
        d += vec3(dir * (h * sc.x), h * sc.y);
    }
    return d;
}

// The packets' whole slope variance (wind frame) where the invocation's add_packets ran, as if
// nothing resolved them, to first order, (k a E)^2 / 2 (a root less a packet than the
// trochoid's; within 6% of it at the steepest, k a = STEEPEST_KA): how much steeper they make the
// sea than its trains (masking.glsl sea_view; PacketField::linear_slope_variance is its twin).
vec2 packet_slope_variance = vec2(0.0);

// Adds packet `index` at rest position x to a pixel's surface: at its normal weight wn in the tangents
// (none where the pixel resolves nothing), the rest of its slope variance, that of the squared
// amplitude (1 - wn^2) (k a)^2 times its envelope's factor (the window's square, or along a row in
// phase the window), to the BRDF's, as add_weighted_train does a train's. The tangents are
// Packet::add_to's: the carrier's and the envelope's gradient's. A packet the pixel does not
// resolve at all (wn = 0, most of a distant wake's) costs its envelope and variance alone.
void add_packet(inout SurfaceSample r, uint index, vec2 x, SampleScale s, bool resolves) {
    vec4 centre_k = packet_texel(index, 0), envelope = packet_texel(index, 1);
    vec2 rel = x - centre_k.xy;
    float u = dot(rel, envelope.xy), v = dot(rel, envelope.zw);
    if (!packet_reaches(u, v)) return;
    vec4 wave = packet_texel(index, 2);
    vec2 k_turns = centre_k.zw;
    float wn = resolves ? normal_weight(s, k_turns) : 0.0;
    vec2 wu = packet_window(u), wv = packet_window(v);
    vec3 e = packet_envelope_of(wu, wv);
    float wavelength = abs(wave.z);
    vec2 dir = k_turns * wavelength;
    if (wn > 0.0) {
        // k a E from the amplitude (wave.w is the variance's slope amplitude, its rows' sums in it).
        float kae = 2.0 * PI * wave.x / wavelength * e.x;
        vec2 grad = wave.x * (e.y * envelope.xy + e.z * envelope.zw);
        vec2 sc = sincos_turns(wave.y - dot(k_turns, rel));
        // d/dx_j of a E sin(theta) and a E cos(theta), theta's gradient -k dir.
        vec2 horizontal = grad * sc.x - dir * (kae * sc.y);
        vec2 vertical = grad * sc.y + dir * (kae * sc.x);
        r.tangent_x += wn * vec3(dir * horizontal.x, vertical.x);
        r.tangent_y += wn * vec3(dir * horizontal.y, vertical.y);
    }
    // The envelope's factor in the variance: along each axis its window where the row is in
    // phase (the row's envelope sum is in wave.w), else its square (Packet::variance_envelope).
    // Rows closer than two sigmas can take it past 1, a summed field steeper than a trochoid's
    // limit: trochoid_slope_variance holds its root's argument at 0 there (finite, continuous).
    float along = wave.z < 0.0 ? wu.x : wu.x * wu.x, across = wave.w < 0.0 ? wv.x : wv.x * wv.x;
    float whole2 = (wave.w * wave.w) * along * across;
    vec2 axes = wind_axes2(dir, frame.wind.xy);
    r.sigma2 += axes * trochoid_slope_variance((1.0 - wn * wn) * whole2);
    packet_slope_variance += axes * (0.5 * whole2);
    // Curvature k (k a E) along the carrier: its variance k^2 (k a E)^2 / 2, k = 2 pi |k_turns|.
    if (GLINTS) r.curvature += 2.0 * PI * PI * dot(k_turns, k_turns) * (1.0 - wn * wn) * whole2;
    count_packet();
}

// The packets at rest position x, read from its cell's list.
void add_packets(inout SurfaceSample r, vec2 x, SampleScale s, bool resolves) {
    uvec2 run = packet_run(x);
    for (uint i = run.x; i < run.y; ++i) add_packet(r, packet_cell_word(PACKET_LISTS + i), x, s, resolves);
}

#endif
