#version 450
// Ground truth: N x N stratified samples per pixel, every wave train as exact surface geometry
// (first hit of each sample ray with the displaced trochoid surface) and exact normals, no
// slope-variance BRDF. Exact Fresnel for water, the sky in the exact reflected direction
// (Preetham's model, or the physical atmosphere along the ray from its own sea point,
// groundtruth_sky.glsl, with the aerial perspective along each sample's path from the eye), the reflected sun as its irradiance over a cone around it (tile.sun_cos_kernel;
// the disc itself at the disc's radius), the sun seen directly as its disc. A reflected ray that meets the
// sea again is shaded there (its reflection and refracted light, and so on, up to tile.bounces
// times); the reflected weight left after the last is recorded as cut off. The scene's objects
// (groundtruth_objects.glsl) stand in front of the sea and the sky for the camera ray and for
// every reflected ray; a reflected ray that meets one takes its radiance in the sky term's place.
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"
#include "planet.glsl"
#include "groundtruth_sky.glsl"
#include "packet_data.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// The physical sky's check (src/measure/truth_sky.rs): per evaluation, the radiance and the
// transmittance (rgb).
layout(set = 0, binding = 3, std430) writeonly buffer SkyCheck { vec4 sky_check[]; };
// The stratum that asks for the check instead of samples.
const uint CHECK_STRATUM = 0xffffffffu;

// Per train: xy wave vector (turns per metre), z phase at time t (turns), w amplitude h (m).
layout(set = 0, binding = 1, std430) readonly buffer ExactWaves { vec4 exact_waves[]; };
// The wave packets (glsl/packet_data.glsl) and their cells' lists, binned on the CPU
// (model::packets::grid::PacketGrid::lists), as exact geometry: every packet at full amplitude.
layout(set = 0, binding = 9, std430) readonly buffer TruthPackets { Packet truth_packets[]; };
layout(set = 0, binding = 10, std430) readonly buffer TruthPacketCells { uint truth_packet_cells[]; };
// Per pixel, seven vec4 (src/measure/groundtruth.rs WORDS_PER_PIXEL): the sum over samples so far
// (rgb) with a = 1 where sub-samples resolve the shortest train, 0 where not; the sum over the
// even strata, the (N/2) x (N/2) subset, for a convergence estimate, with the sum of the refracted
// light's weight (Sample::transmitted) in a; the reflected sun's sum, with the cut-off weight's in
// a; the reflected sky's sum, with the weight of reflected rays that ran out of marching steps in
// a; the sums of squares of the Rec. 709 luminances of the total, the sun, the sky, and of the
// refracted weight, for each pixel's sample variance; the luminances of the total, the sun, the
// sky and the refracted weight summed over the half of the strata with i + j even (an estimate
// independent of the other half's, for the noise of any statistic); and the refracted light's
// sum, with the count of camera rays that ran out of steps in a. Each dispatch adds one sample
// (stratum) to every pixel of a tile: a dispatch per sample keeps each invocation's loop
// iterations bounded (lavapipe 22.3 stops every loop of an invocation after 65535 iterations in
// total, silently).
layout(set = 0, binding = 8, std430) buffer Pixels { vec4 pixels[]; };

layout(push_constant) uniform Tile {
    uvec2 origin;       // first pixel of this tile, within the region
    uint samples;       // N per axis
    uint stratum;       // which of the N x N samples this dispatch adds
    uint wave_count;
    float slab;         // sum of amplitudes: the surface lies within +-slab of the rest plane
    float lipschitz;    // bound on the surface's height slope, for safe marching steps
    float ior;          // refractive index of sea water
    uint seed;
    uint max_march;     // loop iterations the camera ray's march may spend (`intersect`)
    uint bounces;       // how many times a reflected ray may meet the sea again and be shaded there
    uint bounce_march;  // loop iterations all reflected rays' marches of a sample share
    float sun_cos_kernel;    // cos of the cone the reflected sun's energy is spread over (its estimate)
    float sun_kernel_scale;  // the sun disc's solid angle over the cone's (<= 1)
    uvec2 region_origin;     // the pixels traced: the first and how many (the buffer holds these);
    uvec2 region_size;       // two uvec2, not a uvec4, to keep TilePush's 4-byte alignment
    float train_slab;        // the trains' own slab and slope bound: the surface's where no packet
    float train_lipschitz;   // reaches (outside packet_reach)
    vec2 packet_reach_min;   // the rest plane's box over which packets shape the surface: their
    vec2 packet_reach_max;   // cells widened by the horizontal reach (min > max: no packets)
} tile;

const int NEWTON_STEPS = 2;   // src/measure/groundtruth.rs NEWTON_STEPS

struct Surface {
    vec3 d;        // displacement
    mat2 j;        // d(displacement.xy) / d(rest x)
    vec2 grad_z;   // d(displacement.z) / d(rest x)
};

void add_train(vec4 w, vec2 x, inout Surface s) {
    vec2 sc = sincos_turns(w.z - dot(w.xy, x));
    vec2 k = 2.0 * PI * w.xy;
    vec2 dir = k * inversesqrt(dot(k, k));
    float h = w.w;
    s.d += vec3(dir * (h * sc.x), h * sc.y);
    // d theta / dx = -k: d(dir h sin)/dx = -h cos dir k^T, d(h cos)/dx = h sin k.
    s.j -= outerProduct(dir, k) * (h * sc.y);
    s.grad_z += k * (h * sc.x);
}

// A packet's displacement and its derivatives (model::packets::Packet::add_to): the carrier's
// and its envelope's (0 from PACKET_SIGMAS out).
void add_packet(uint index, vec2 x, inout Surface s) {
    Packet p = truth_packets[index];
    vec2 rel = x - p.centre_k.xy;
    float u = dot(rel, p.envelope.xy), v = dot(rel, p.envelope.zw);
    if (!packet_reaches(u, v)) return;
    vec3 e = packet_envelope(u, v);
    float a = p.wave.x * e.x;
    vec2 grad = p.wave.x * (e.y * p.envelope.xy + e.z * p.envelope.zw);
    vec2 k = 2.0 * PI * p.centre_k.zw;
    vec2 dir = k * inversesqrt(dot(k, k));
    vec2 sc = sincos_turns(p.wave.y - dot(p.centre_k.zw, rel));
    s.d += vec3(dir * (a * sc.x), a * sc.y);
    s.j += outerProduct(dir, grad * sc.x - k * (a * sc.y));
    s.grad_z += grad * sc.y + k * (a * sc.x);
}

// Loop iterations the surface evaluations have run (trains and packets): a marching step charges
// what its own evaluations spent, so a ray over short cell lists takes more steps than one over
// the longest.
uint surface_iterations = 0u;

// The packets whose cell holds x, eight an iteration (the loop budget counts iterations; sixteen
// took lavapipe two minutes to compile). The truth's cells are its own (finer than the frame's):
// their lists start after their count's starts.
void add_packets(vec2 x, inout Surface s) {
    int found = packet_cell(x);
    if (found < 0) return;
    uint cell = uint(found);
    uint lists = frame.packet_dims.x * frame.packet_dims.y + 1u;
    uint begin = lists + truth_packet_cells[cell], end = lists + truth_packet_cells[cell + 1u];
    // Each run is padded to whole iterations with a packet that reaches nowhere
    // (src/measure/groundtruth.rs): no bound check per packet.
    surface_iterations += (end - begin) / 8u;
    for (uint i = begin; i < end; i += 8u) {
#define ADD_PACKET(j) add_packet(truth_packet_cells[i + j], x, s);
        ADD_PACKET(0u) ADD_PACKET(1u) ADD_PACKET(2u) ADD_PACKET(3u) ADD_PACKET(4u) ADD_PACKET(5u) ADD_PACKET(6u)
        ADD_PACKET(7u)
#undef ADD_PACKET
    }
}

// Eight trains an iteration (tile.wave_count is a multiple of 8, padded with trains of no
// amplitude): lavapipe's loop budget counts iterations, so a march gets eight times the steps.
Surface surface(vec2 x) {
    Surface s;
    s.d = vec3(0.0);
    s.j = mat2(0.0);
    s.grad_z = vec2(0.0);
    surface_iterations += tile.wave_count / 8u;
    for (uint i = 0u; i < tile.wave_count; i += 8u) {
        // Written out, not an inner loop: the budget would count each of its iterations.
        add_train(exact_waves[i], x, s);
        add_train(exact_waves[i + 1u], x, s);
        add_train(exact_waves[i + 2u], x, s);
        add_train(exact_waves[i + 3u], x, s);
        add_train(exact_waves[i + 4u], x, s);
        add_train(exact_waves[i + 5u], x, s);
        add_train(exact_waves[i + 6u], x, s);
        add_train(exact_waves[i + 7u], x, s);
    }
    if (frame.packet_dims.z > 0u) add_packets(x, s);
    return s;
}

// Rest position whose displaced point lies above horizontal position y (Newton on x + D(x) = y,
// from `x`); also returns the surface there.
vec2 invert(vec2 y, vec2 x, out Surface s) {
    for (int n = 0; n < NEWTON_STEPS; ++n) {
        s = surface(x);
        vec2 f = x + s.d.xy - y;
        mat2 jac = mat2(1.0) + s.j;
        float det = determinant(jac);
        // Where the surface folds (det <= 0) Newton has no direction: fall back to a fixed-point step.
        x -= det > 0.0 ? inverse(jac) * f : f;
    }
    s = surface(x);
    return x;
}

const int BISECTION_STEPS = 16;

// The vertical gap within which a marching step counts as on the surface, for a point t along
// its ray and `range` from the eye: 0.1 mm plus f32's relative precision at both scales.
float hit_tolerance(float t, float range) {
    return 1e-4 + 1e-6 * max(t, range);
}

// Vertical gap between the ray point o + t r and the surface below or above it (positive above):
// the waves displace the rest sphere's point at rest position x (glsl/planet.glsl), as the grid.
float gap(vec3 o, vec3 r, float t, inout vec2 x, out Surface s) {
    vec3 p = o + t * r;
    x = invert(p.xy, x, s);
    return p.z + frame.cam_forward.w + sphere_drop(x) - s.d.z;
}

// Height of p above the rest sphere, vertically (the slab's bounds are +-tile.slab of it), and
// its rate of change along r: r.z plus the drop's gradient x / sqrt(R^2 - |x|^2) along r.xy. The
// drop is convex, so the rate only grows along a ray.
vec2 level_and_rate(vec3 p, vec3 r) {
    float below = sphere_root(p.xy);
    float rate = r.z + (below > 0.0 ? dot(p.xy, r.xy) / below : 0.0);
    return vec2(p.z + frame.cam_forward.w + sphere_drop(p.xy), rate);
}

// The stretch of o + r t within [lo, hi] along one axis (all t, or none, for r = 0).
vec2 axis_span(float o, float r, float lo, float hi) {
    if (r == 0.0) return o >= lo && o <= hi ? vec2(-3.0e38, 3.0e38) : vec2(3.0e38, -3.0e38);
    float a = (lo - o) / r, b = (hi - o) / r;
    return vec2(min(a, b), max(a, b));
}

// The stretch [t_in, t_out] of o + t r over the packets' reach (tile.packet_reach_*, in the rest
// plane); t_in > t_out where it never is (no packets: the box is empty).
vec2 packet_span(vec3 o, vec3 r) {
    vec2 lo = tile.packet_reach_min, hi = tile.packet_reach_max;
    if (any(greaterThan(lo, hi))) return vec2(3.0e38, -3.0e38);
    vec2 sx = axis_span(o.x, r.x, lo.x, hi.x), sy = axis_span(o.y, r.y, lo.y, hi.y);
    vec2 span = vec2(max(sx.x, sy.x), min(sx.y, sy.y));
    return span.x <= span.y ? span : vec2(3.0e38, -3.0e38);
}

// First hit of o + t r (t > t0) with the surface: returns t, or -1 where the ray misses. Sphere-
// traces the vertical gap g with the slope bound L: g shrinks by at most dt (L |r.xy| - rate)
// per step dt, rate the ray's climb over the rest sphere (level_and_rate, which only grows along
// the ray), so dt = g / (L |r.xy| - rate) does not cross the surface when L holds; should a step
// still land below it (or below every trough, or run out of steps going down), bisection on the
// bracket finds the crossing. `budget` is the loop iterations the march may still spend (a
// sample's reflected rays share one pool), each step charged its own (its evaluations' trains and
// packets, and itself; the last may overrun by one step, which the pool's reserve holds); it is
// left with what remains. `unfinished`: the march ran out of steps
// before deciding (a miss then counts as leaving, a bracket's bisection may find a later
// crossing than the first): the report counts such rays. (Results travel as floats, control
// flow has one exit.)
float intersect(vec3 o, vec3 r, float t0, inout uint budget, out Surface s_hit, out bool unfinished) {
    float height = frame.cam_forward.w, R = frame.planet.x, slab = tile.slab;
    bool from_eye = o == vec3(0.0);
    float t = t0;
    float result = -1.0;
    float searching = 1.0;
    // Skip to the top of the slab when starting above it: from the eye the exact sphere of the
    // crests (a ray that misses it misses the sea); elsewhere the level's tangent, which the
    // convex level only reaches later.
    vec2 start = level_and_rate(o + t * r, r);
    if (start.x > slab) {
        float skip = from_eye ? (height > slab ? sphere_distance(r, height - slab, R + slab) : 0.0)
                              : (start.y < 0.0 ? t + (slab - start.x) / start.y : -1.0);
        searching = skip >= 0.0 ? 1.0 : 0.0;
        t = max(t, skip);
    }
    vec2 x = (o + t * r).xy;
    Surface s = surface(x);
    // Where the ray is over the packets' reach the march steps by the whole surface's bounds;
    // before it, by the trains' (a step stops where it enters); past it, the trains' bound the
    // rest of the ray: a ray skimming a far sea is not held to a wake's slopes.
    vec2 over = packet_span(o, r);
    float t_above = t;        // last point known above the surface
    float t_below = -1.0;     // first point known below it, once bracketed
    uint spent = 0u;
    while (spent < budget && searching > 0.0) {
        uint before = surface_iterations;
        vec3 p = o + t * r;
        vec2 level = level_and_rate(p, r);
        bool past = t > over.y;
        float step_slope = t >= over.x && !past ? tile.lipschitz : tile.train_lipschitz;
        float rest_slope = past ? tile.train_lipschitz : tile.lipschitz;
        float rest_slab = past ? tile.train_slab : slab;
        float closing = rest_slope * length(r.xy) - level.y;
        if (level.y >= 0.0 && (level.x > rest_slab + 1e-3 || closing <= 0.0)) {
            searching = 0.0;   // left the slab upwards, or rising faster than any slope: a miss
        } else if (level.x < -slab) {
            t_below = t;       // below every trough
            searching = 0.0;
        } else {
            float g = gap(o, r, t, x, s);
            if (abs(g) <= hit_tolerance(t, length(o + t * r))) {
                result = t;
                searching = 0.0;
            } else if (g < 0.0) {
                t_below = t;
                searching = 0.0;
            } else {
                t_above = t;
                // closing > 0 above; the trains' own may not be before the packets' reach, where
                // the step ends at its start anyway.
                float step_closing = step_slope * length(r.xy) - level.y;
                float step = step_closing > 0.0 ? g / step_closing : over.x - t;
                t += t < over.x ? min(step, over.x - t) : step;
            }
        }
        // The step itself, its Newton loop's (src/measure/groundtruth.rs NEWTON_STEPS) and its
        // evaluations'.
        spent += 1u + uint(NEWTON_STEPS) + (surface_iterations - before);
    }
    budget -= min(spent, budget);
    unfinished = searching > 0.0;
    // Going down and out of steps: a point below every trough brackets the crossing: from the eye
    // the troughs' sphere, elsewhere the level's tangent (kept only where it does lie below).
    if (searching > 0.0) {
        vec3 p = o + t * r;
        vec2 level = level_and_rate(p, r);
        float below = from_eye ? sphere_distance(r, height + slab, R - slab)
                               : (level.y < 0.0 ? t + (-slab - level.x) / level.y : -1.0);
        vec2 xb = x;
        Surface sb;
        if (below >= t && gap(o, r, below, xb, sb) < 0.0) t_below = below;
    }
    if (result < 0.0 && t_below >= 0.0) {
        vec2 xb = x;
        for (int b = 0; b < BISECTION_STEPS; ++b) {
            float mid = 0.5 * (t_above + t_below);
            if (gap(o, r, mid, xb, s) > 0.0) t_above = mid; else t_below = mid;
        }
        result = t_above;
        gap(o, r, result, xb, s);
    }
    s_hit = s;
    return result;
}

// Unpolarized Fresnel reflectance from air into water at cos(incidence) = c.
float fresnel_exact(float c, float eta) {
    float sin_t2 = (1.0 - c * c) / (eta * eta);
    float cos_t = sqrt(max(1.0 - sin_t2, 0.0));
    float rs = (c - eta * cos_t) / (c + eta * cos_t);     // c + eta cos_t >= eta cos_t > 0
    float rp = (eta * c - cos_t) / (eta * c + cos_t);     // eta c + cos_t >= cos_t > 0
    return 0.5 * (rs * rs + rp * rp);
}

uint hash(uint x) {
    // A 32-bit integer hash (Chris Wellons' "lowbias32" constants).
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return x;
}

// The environment sample of an object's shading, stratified per pixel (set by main).
vec2 env_xi;

#include "groundtruth_objects.glsl"

// What one sample sees: the reflected sun, the reflected sky and the refracted sea light where it
// meets the sea (through every reflection traced), or the sky (and sun disc) straight on where it
// does not.
struct Sample {
    vec3 sun;
    vec3 sky;
    vec3 sea;
    vec3 total;
    float transmitted;   // the sum over the hits of the reflected weight there times 1 - F
    float cut_off;       // the reflected weight left untraced after the last bounce
    float unfinished;    // the reflected weight whose ray ran out of marching steps
    bool camera_unfinished;   // the camera ray ran out of marching steps
};

vec3 surface_normal(Surface s) {
    vec3 tx = vec3(1.0 + s.j[0][0], s.j[0][1], s.grad_z.x);
    vec3 ty = vec3(s.j[1][0], 1.0 + s.j[1][1], s.grad_z.y);
    vec3 c = cross(tx, ty);
    float len2 = dot(c, c);
    return len2 > 0.0 ? c * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
}

// From the first hit (at distance t along the unit camera ray r, surface s): at each hit, the
// refracted light enters with weight w (1 - F); the reflected ray then either leaves the sea (the
// sky there, and the sun where the ray falls in its disc) or meets it again, and is shaded there
// with weight w F, up to tile.bounces times. A ray can only leave upwards: one going down meets
// the sea (intersect brackets it below every trough), so the sky is never read below the horizon.
Sample shade_hit(vec3 r, float t, Surface s) {
    Sample o;
    o.sun = o.sky = vec3(0.0);
    o.transmitted = 0.0;
    o.cut_off = 0.0;
    o.unfinished = 0.0;
    o.camera_unfinished = false;
    uint pool = tile.bounce_march;   // the marching iterations all reflected rays share
    vec3 p = t * r;
    vec3 dir = r;
    float w = 1.0;
    float t_hit = t;   // the ray parameter of the latest hit, which sets its tolerance
    bool tracing = true;
    for (uint b = 0u; b <= tile.bounces && tracing; ++b) {
        vec3 n = surface_normal(s);
        float fresnel = fresnel_exact(clamp(dot(n, -dir), 0.0, 1.0), tile.ior);
        o.transmitted += w * (1.0 - fresnel);
        vec3 refl = reflect(dir, n);
        Surface next;
        // A hit is accepted within HIT_TOLERANCE of the surface, below it as well: a ray leaving
        // at grazing incidence from there (it rises from the facet at rate refl . n) could start
        // inside the wave it leaves and meet it at once. So it starts lifted above any such
        // point, twice the tolerance, and a little along itself; it leaves when it meets no wave.
        vec3 origin = p + vec3(0.0, 0.0, 2.0 * hit_tolerance(t_hit, length(p)));
        bool unfinished;
        float t_next = intersect(origin, refl, 1e-3 + 1e-5 * length(p), pool, next, unfinished);
        // An object the reflected ray meets before the sea (or the sky) stands in for what lies
        // beyond it: the sky term's share, as the renderer's local reflections take it.
        bool walk_unfinished;
        ObjectHit object = object_hit(origin, refl, 0.0, t_next >= 0.0 ? t_next : 3.0e38, walk_unfinished);
        if (unfinished || walk_unfinished) o.unfinished += w * fresnel;
        if (object.t < (t_next >= 0.0 ? t_next : 3.0e38)) {
            o.sky += w * fresnel * object_radiance(origin, refl, object, env_xi);
            tracing = false;
        } else if (t_next < 0.0) {
            SeaPoint at = truth_sea_point(p);
            o.sky += w * fresnel * (SKY_PHYSICAL ? truth_sky(at, refl) : preetham_sky(refl));
            // The sun's irradiance spread evenly over a cone around it (src/measure/groundtruth.rs,
            // DEFAULT_SUN_KERNEL_DEG): at the disc's own radius the disc itself, limb-darkened for
            // the physical sun, seen through the air above this sea point.
            if (dot(refl, frame.sun_dir.xyz) >= tile.sun_cos_kernel) {
                if (SKY_PHYSICAL) {
                    float shape = tile.sun_kernel_scale >= 1.0 ? limb_darkening(refl) : tile.sun_kernel_scale;
                    o.sun += w * fresnel * shape * truth_sun_radiance(at);
                } else if (frame.sun_irradiance.w > 0.0) {
                    o.sun += w * fresnel * tile.sun_kernel_scale * frame.sun_radiance.rgb;
                }
            }
            tracing = false;
        } else if (b == tile.bounces) {
            o.cut_off = w * fresnel;
            tracing = false;
        } else {
            w *= fresnel;
            p = origin + t_next * refl;
            t_hit = t_next;
            dir = refl;
            s = next;
        }
    }
    // The light entering the water: the sky's irradiance under the first hit's own sun (the
    // sphere turns it from point to point; the later hits lie metres away).
    vec3 irradiance = SKY_PHYSICAL ? truth_sky_irradiance(dot(frame.sun_dir.xyz, truth_sea_point(t * r).up))
                                   : frame.sky_irradiance.rgb;
    o.sea = o.transmitted * frame.sea_albedo.rgb * irradiance / PI;
    o.total = o.sun + o.sky + o.sea;
    return o;
}

Sample shade_sample(vec3 ray) {
    vec3 r = normalize(ray);
    Surface s;
    uint budget = tile.max_march;
    bool unfinished;
    float t = intersect(vec3(0.0), r, 0.0, budget, s, unfinished);
    bool walk_unfinished;
    ObjectHit object = object_hit(vec3(0.0), r, 0.0, t >= 0.0 ? t : 3.0e38, walk_unfinished);
    Sample o;
    if (object.t < (t >= 0.0 ? t : 3.0e38)) {
        // An object seen straight on, through the air between it and the eye.
        o.sun = o.sky = o.sea = vec3(0.0);
        o.transmitted = 0.0;
        o.cut_off = 0.0;
        o.unfinished = 0.0;
        o.camera_unfinished = unfinished || walk_unfinished;
        o.total = object_radiance(vec3(0.0), r, object, env_xi);
        if (SKY_PHYSICAL) {
            vec3 transmittance;
            vec3 inscatter = truth_aerial_from_eye(r, object.t, transmittance);
            o.total = o.total * transmittance + inscatter;
        }
    } else if (t >= 0.0) {
        o = shade_hit(r, t, s);
        o.camera_unfinished = unfinished;
        // The air between the eye and the sea (the terms apart: each is the sea's own light, as
        // the renderer's single-term images; the air between two hits, metres, is left out).
        if (SKY_PHYSICAL) {
            vec3 transmittance;
            vec3 inscatter = truth_aerial_from_eye(r, t, transmittance);
            o.total = o.total * transmittance + inscatter;
        }
    } else {
        o.sun = o.sky = o.sea = vec3(0.0);
        o.transmitted = 0.0;
        o.cut_off = 0.0;
        o.unfinished = 0.0;
        o.camera_unfinished = unfinished;
        o.total = (SKY_PHYSICAL ? truth_sky_from_eye(r) : preetham_sky(r)) + sun_disc(r);
    }
    return o;
}

// Check i of the physical sky against the f64 model (truth_sky::TruthSkyTables::check_arguments:
// the same arguments): a third the sea's sky, a third the eye's, a third the aerial perspective.
void check(uint i) {
    uint j = i % 32u, kind = i / 32u;
    float azimuth = PI * float(j / 8u) / 3.0;
    float f = float(j % 8u) / 7.0;
    float mu = kind == 2u ? -0.001 - 0.3 * f * f : 0.02 + 0.96 * f;
    float mu_s = frame.sun_dir.z;
    float nu = sqrt(max(1.0 - mu * mu, 0.0)) * sqrt(max(1.0 - mu_s * mu_s, 0.0)) * cos(azimuth) + mu * mu_s;
    float h = kind == 0u ? 0.0 : frame.atmosphere[4].z;
    float len = 50.0 * pow(10.0, float(j % 8u) * 0.5);
    AirRay a = air_ray_cosines(h, mu, mu_s, nu);
    vec3 transmittance = vec3(1.0);
    vec3 L = kind == 2u ? truth_aerial(a, len, transmittance) : sky_radiance_along(a, TRUTH_SKY_STEPS);
    sky_check[2u * i] = vec4(L, 0.0);
    sky_check[2u * i + 1u] = vec4(transmittance, 0.0);
}

void main() {
    if (tile.stratum == CHECK_STRATUM) {
        uint i = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
        if (i < tile.samples) check(i);
        return;
    }
    uvec2 local = tile.origin + gl_GlobalInvocationID.xy;   // within the region
    if (any(greaterThanEqual(local, tile.region_size))) return;
    uvec2 pixel = tile.region_origin + local;
    uint n = tile.samples;
    uint i = tile.stratum % n, j = tile.stratum / n;
    uint h = hash(tile.seed ^ hash(pixel.x + 65536u * pixel.y) ^ hash(i + 4096u * j));
    vec2 jitter = vec2(h & 0xffffu, h >> 16) * (1.0 / 65536.0);
    // The environment's sample: the stratum's cell, rotated per pixel (Cranley-Patterson), so
    // that it is not tied to the sample's position in the pixel.
    uint g = hash(h ^ 0x9e3779b9u), rot = hash(pixel.x * 7919u + pixel.y * 104729u + tile.seed);
    vec2 within = vec2(g & 0xffffu, g >> 16) * (1.0 / 65536.0);
    env_xi = fract((vec2(j, i) + within) / float(n) + vec2(rot & 0xffffu, rot >> 16) * (1.0 / 65536.0));
    Sample o = shade_sample(camera_ray(pixel_to_ndc(vec2(pixel) + (vec2(i, j) + jitter) / float(n))));
    vec3 L = o.total;
    bool in_subset = (i & 1u) == 0u && (j & 1u) == 0u;
    bool in_half = ((i + j) & 1u) == 0u;
    uint index = 7u * (local.y * tile.region_size.x + local.x);
    const vec3 REC709 = vec3(0.2126, 0.7152, 0.0722);
    vec4 luminances = vec4(dot(L, REC709), dot(o.sun, REC709), dot(o.sky, REC709), o.transmitted);
    vec4 squares = luminances * luminances;
    vec4 half_sums = in_half ? luminances : vec4(0.0);
    if (tile.stratum == 0u) {
        // Does the sub-sample spacing resolve the shortest train (at most half a turn per step)?
        vec3 ray = camera_ray(pixel_to_ndc(vec2(pixel) + 0.5));
        float resolved = 1.0;   // a pixel of sky has nothing to resolve
        vec3 u = normalize(ray);
        vec2 hit = sea_distance(onto_sea(u));
        if (meets_sea(u) && hit.y > 0.0) {
            // The rest position's step per sub-sample (glsl/waves.glsl sample_scale's formula).
            float len = length(ray), t = hit.x / len, w = hit.y * len;
            vec3 up = sea_normal(hit.x * u.xy);
            vec3 dr_du = frame.cam_right.xyz * (2.0 * frame.viewport.z);
            vec3 dr_dv = frame.cam_down.xyz * (2.0 * frame.viewport.w);
            float scale = t / (w * float(n));
            vec2 a_u = (dr_du.xy * w + ray.xy * dot(up, dr_du)) * scale;
            vec2 a_v = (dr_dv.xy * w + ray.xy * dot(up, dr_dv)) * scale;
            vec2 k = exact_waves[0].xy;   // trains are sorted: the first is the shortest
            resolved = max(abs(dot(k, a_u)), abs(dot(k, a_v))) <= 0.5 ? 1.0 : 0.0;
        }
        pixels[index] = vec4(L, resolved);
        pixels[index + 1u] = vec4(in_subset ? L : vec3(0.0), o.transmitted);
        pixels[index + 2u] = vec4(o.sun, o.cut_off);
        pixels[index + 3u] = vec4(o.sky, o.unfinished);
        pixels[index + 4u] = squares;
        pixels[index + 5u] = half_sums;
        pixels[index + 6u] = vec4(o.sea, o.camera_unfinished ? 1.0 : 0.0);
    } else {
        pixels[index].rgb += L;
        if (in_subset) pixels[index + 1u].rgb += L;
        pixels[index + 1u].a += o.transmitted;
        pixels[index + 2u] += vec4(o.sun, o.cut_off);
        pixels[index + 3u] += vec4(o.sky, o.unfinished);
        pixels[index + 4u] += squares;
        pixels[index + 5u] += half_sums;
        pixels[index + 6u] += vec4(o.sea, o.camera_unfinished ? 1.0 : 0.0);
    }
}
