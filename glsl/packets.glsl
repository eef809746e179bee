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

layout(set = 0, binding = 20, std430) readonly buffer Packets { Packet packets[]; };
layout(set = 0, binding = 21, std430) readonly buffer PacketCells { uint packet_cells[]; };

// The run of the lists that holds the packets reaching rest position x: empty outside the grid
// (and for a NaN x, which no comparison admits).
uvec2 packet_run(vec2 x) {
    if (!PACKETS) return uvec2(0u);
    vec2 c = (x - frame.packet_grid.xy) * frame.packet_grid.z;
    vec2 dims = vec2(frame.packet_dims.xy);
    if (!(c.x >= 0.0 && c.y >= 0.0 && c.x < dims.x && c.y < dims.y)) return uvec2(0u);
    uint cell = uint(c.y) * frame.packet_dims.x + uint(c.x);
    return uvec2(packet_cells[cell], packet_cells[cell + 1u]);
}

// One packet at a rest position.
struct PacketSample {
    bool reaches;    // within PACKET_SIGMAS of the centre on both axes
    vec2 k;          // wave vector (turns per m)
    vec2 dir;        // its unit direction
    float a;         // amplitude times the envelope (m)
    vec2 grad;       // the envelope's gradient times the amplitude (unitless)
    vec2 sc;         // sin and cos of the phase
};

PacketSample packet_sample(Packet p, vec2 x) {
    vec2 rel = x - p.centre_k.xy;
    float u = dot(rel, p.envelope.xy), v = dot(rel, p.envelope.zw);
    PacketSample s;
    // Within the box, u^2 + v^2 <= 32: exp never underflows to a denormal's trouble.
    s.reaches = max(abs(u), abs(v)) <= PACKET_SIGMAS;
    float e = s.reaches ? exp(-0.5 * (u * u + v * v)) : 0.0;
    s.k = p.centre_k.zw;
    s.dir = s.k * inversesqrt(dot(s.k, s.k));   // |k| >= 1e-4 turns/m: the model's band
    s.a = p.wave.x * e;
    s.grad = -s.a * (u * p.envelope.xy + v * p.envelope.zw);
    s.sc = sincos_turns(p.wave.y - dot(s.k, rel));
    return s;
}

// The packets' displacement at rest position x, each at the grid's weight (as `displacement`).
vec3 packets_displacement(vec2 x, SampleScale s, vec2 steps) {
    vec3 d = vec3(0.0);
    uvec2 run = packet_run(x);
    float inv_ramp = 1.0 / (steps.y - steps.x);
    for (uint i = run.x; i < run.y; ++i) {
        PacketSample q = packet_sample(packets[packet_cells[PACKET_LISTS + i]], x);
        if (!q.reaches) continue;
        float h = resolution_weight(s, q.k, steps, inv_ramp, 1.0) * q.a;
        d += vec3(q.dir * (h * q.sc.x), h * q.sc.y);
    }
    return d;
}

// Adds one packet at its sample q to a pixel's surface: at its normal weight in the tangents (none
// where the pixel resolves nothing), the rest of its slope variance, that of the amplitude
// sqrt(1 - wn^2) k a E, to the BRDF's, as add_weighted_train does a train's. The tangents are
// Packet::add_to's: the carrier's and the envelope's gradient's.
void add_packet(inout SurfaceSample r, PacketSample q, SampleScale s, bool resolves) {
    if (!q.reaches) return;
    float wn = resolves ? normal_weight(s, q.k) : 0.0;
    float k = 2.0 * PI * length(q.k);
    // d/dx_j of a E sin(theta) and a E cos(theta), theta's gradient -k dir.
    vec2 horizontal = q.grad * q.sc.x - q.dir * (q.a * k * q.sc.y);
    vec2 vertical = q.grad * q.sc.y + q.dir * (q.a * k * q.sc.x);
    r.tangent_x += wn * vec3(q.dir * horizontal.x, vertical.x);
    r.tangent_y += wn * vec3(q.dir * horizontal.y, vertical.y);
    // k a E <= STEEPEST_KA < 1: the slope variance's argument stays below 1.
    float kae = k * q.a;
    float unresolved2 = (1.0 - wn * wn) * kae * kae;
    r.sigma2 += wind_axes2(q.dir, frame.wind.xy) * trochoid_slope_variance(unresolved2);
    if (GLINTS) r.curvature += 0.5 * k * k * unresolved2;
    count_train(wn > 0.0);
}

// The packets at rest position x, each read by this invocation from its cell's list.
void add_packets(inout SurfaceSample r, vec2 x, SampleScale s, bool resolves) {
    uvec2 run = packet_run(x);
    for (uint i = run.x; i < run.y; ++i) add_packet(r, packet_sample(packets[packet_cells[PACKET_LISTS + i]], x), s, resolves);
}

#endif
