// Filtered trochoid waves: per-train resolution weights, displacement and slopes.
// Requires frame.glsl and common.glsl, and WAVES_BLOCK in scope.
#ifndef WAVES_GLSL
#define WAVES_GLSL

#include "planet.glsl"

// How samples `cells` pixels apart map onto the sea's rest positions around one camera ray r
// (glsl/planet.glsl: x is the horizontal offset of the point P = t r on the mean sphere). Along a
// screen axis with dr/ds = r', the sphere's constraint n . dP = 0 gives dt = t (n . r') / w with
// w = -n . r, so dx/ds = (t / w) q with q = r'.xy w + r.xy (n . r'); on a plane (n = z, t = H / w)
// this is H (r'.xy w + r.xy r'.z) / w^2. The numerators q stay finite at the limb, where w -> 0;
// t / w is only formed where some train is resolvable, which bounds w away from 0 (see `any`).
struct SampleScale {
    vec2 a_u;            // rest-position change per sample along screen u (m)
    vec2 a_v;            // same along screen v
    float lambda_cut;    // trains with wavelength <= this are unresolved in every direction
    float lambda_cut2;   // its square: the loop compares |k|^2 lambda_cut^2 >= 1 (lambda <= cut)
    bool any;            // whether the longest train can be resolved at all
    vec2 a_u_w;          // a_u and a_v times w, finite at the limb (the glints' footprint)
    vec2 a_v_w;
    float w;             // -n . ray: 0 at the limb and beyond
};

SampleScale sample_scale(vec3 ray, float cells, vec2 steps) {
    float len = length(ray);   // >= 1: camera_ray's component along the view is 1
    vec3 u = ray / len;
    bool meets = meets_sea(u);
    vec2 hit = sea_distance(onto_sea(u));
    vec3 n = sea_normal(hit.x * u.xy);
    float w = meets ? hit.y * len : 0.0;   // -n . ray
    float t = hit.x / len;                 // P = t ray
    vec3 dr_du = frame.cam_right.xyz * (2.0 * frame.viewport.z);
    vec3 dr_dv = frame.cam_down.xyz * (2.0 * frame.viewport.w);
    vec2 q_u = dr_du.xy * w + ray.xy * dot(n, dr_du);
    vec2 q_v = dr_dv.xy * w + ray.xy * dot(n, dr_dv);
    // The smallest phase step any direction can have: min over unit k of max(|k.q_u|, |k.q_v|).
    // Between the directions where |k.q_u| = |k.q_v| the max only grows, and there k is normal to
    // q_u - q_v or q_u + q_v, where |k.q_u| = |det| / |q_u -+ q_v|: the minimum is |det| over the
    // longer of the two.
    float det = abs(q_u.x * q_v.y - q_u.y * q_v.x);
    float diagonal = max(length(q_u - q_v), length(q_u + q_v));
    float q_min = diagonal > 0.0 ? det / diagonal : 0.0;   // det <= diagonal^2 / 2: no overflow
    float reach = t * cells;
    float longest = frame.wave_extent.x;
    SampleScale s;
    s.a_u_w = q_u * reach;
    s.a_v_w = q_v * reach;
    s.w = w;
    if (METHOD == METHOD_NO_FILTER) {
        // Every train at full weight wherever the ray meets the sea: no loop exit.
        s.any = meets;
        s.a_u = s.a_v = vec2(0.0);
        s.lambda_cut = s.lambda_cut2 = 0.0;
        return s;
    }
    // Train lambda is unresolved everywhere when q_min reach / (lambda w) >= steps.y.
    s.any = longest * w * steps.y > q_min * reach;
    if (s.any) {
        // Here w > q_min reach / (longest step) >= 0, and w > 0 strictly.
        float per_w = reach / w;
        s.a_u = q_u * per_w;
        s.a_v = q_v * per_w;
        s.lambda_cut = q_min * per_w / steps.y;   // < longest <= 1e4 m: its square is finite
    } else {
        s.a_u = vec2(0.0);
        s.a_v = vec2(0.0);
        s.lambda_cut = longest;
    }
    s.lambda_cut2 = s.lambda_cut * s.lambda_cut;
    return s;
}

// Weight of a train at the grid's scale from its step per sample: 1 up to steps.x (resolved), 0
// from steps.y on, a smoothstep between. The step is the phase advance per sample (turns), times
// `nonlinearity` >= 1 where the displacement is steeper than the phase.
float resolution_weight(SampleScale s, vec2 k_turns, vec2 steps, float inv_ramp, float nonlinearity) {
    if (METHOD == METHOD_NO_FILTER) return 1.0;
    float step = max(abs(dot(k_turns, s.a_u)), abs(dot(k_turns, s.a_v))) * nonlinearity;
    float t = clamp((step - steps.x) * inv_ramp, 0.0, 1.0);
    return 1.0 - t * t * (3.0 - 2.0 * t);
}

// A pixel's box filter's transfer of a sinusoid that advances s turns across it: sinc(pi s) =
// sin(pi s) / (pi s), held at 0 past its first zero (s = 1; the side lobes go to the BRDF), as
// (1 - s^2)(1 + a s^2 + b s^4): a = 1 - pi^2 / 6 matches sinc's curvature at 0 and b = -1/2 - a
// its slope at the zero (the factor's value there, 1/2). Within 1.4e-3 of sinc (at s = 0.75),
// with no sine (src/render/footprint.rs box_transfer is its twin).
const float BOX_A = 1.0 - PI * PI / 6.0;
const float BOX_B = -0.5 - BOX_A;

float box_transfer(float s) {
    float s2 = min(s * s, 1.0);
    return (1.0 - s2) * (1.0 + s2 * (BOX_A + s2 * BOX_B));
}

// Weight of a train in the per-pixel normal: what the pixel's box filter keeps of it. Over the
// pixel the rest position moves by a_u and a_v (its footprint, a parallelogram), and a sinusoid's
// mean over a parallelogram is the product of its means along the two sides: the ground truth's
// pixel, box-filtering the exact surface, keeps sinc(k.a_u) sinc(k.a_v) of a train's slopes,
// and so does this point sample of the slopes at the pixel's centre. The rest of its variance,
// (1 - w^2), goes to the BRDF.
float normal_weight(SampleScale s, vec2 k_turns) {
    if (METHOD == METHOD_NO_FILTER) return 1.0;
    return box_transfer(abs(dot(k_turns, s.a_u))) * box_transfer(abs(dot(k_turns, s.a_v)));
}

// Trains are sorted by increasing wavelength, so loops run from the longest down and stop
// at the first one that no sample at this scale can resolve. One loop with a uniform index keeps
// the array reads uniform across a SIMD group (split loops measured 25% slower on lavapipe).

// Displacement of the surface point with rest position x (camera-relative, metres).
vec3 displacement(vec2 x, SampleScale s, vec2 steps) {
    float inv_ramp = 1.0 / (steps.y - steps.x);
    vec3 d = vec3(0.0);
    for (int i = int(frame.grid_dims.z) - 1; i >= 0; --i) {
        Wave wave = unpack_wave(wave_data[i].xy);
        float k2 = dot(wave.k, wave.k);
        if (k2 * s.lambda_cut2 >= 1.0) break;
        // h = k h / k with k = 2 pi |k_turns|; the direction is k_turns / |k_turns|.
        float inv_k = inversesqrt(k2);
        float h = resolution_weight(s, wave.k, steps, inv_ramp, 1.0) * wave.kh * inv_k * (0.5 / PI);
        vec2 sc = sincos_turns(wave.phase - dot(wave.k, x));
        d += vec3(wave.k * (inv_k * h * sc.x), h * sc.y);
    }
    return d;
}

// Trains evaluated at this invocation, those of them with a weight, and the wave packets' terms
// (profiling: counted only where the includer asks, COUNTS_TRAINS with its specialization
// constant COUNT_TRAINS).
#ifdef COUNTS_TRAINS
uint trains_evaluated = 0u;
uint trains_weighted = 0u;
uint packet_terms = 0u;
void count_train(bool weighted) {
    if (COUNT_TRAINS) {
        trains_evaluated += 1u;
        trains_weighted += weighted ? 1u : 0u;
    }
}
// A wave packet within its reach at the pixel, its terms added (glsl/packets.glsl).
void count_packet() {
    if (COUNT_TRAINS) packet_terms += 1u;
}
#else
void count_train(bool weighted) {}
void count_packet() {}
#endif

// Resolved slopes and the slope variance left for the BRDF, at one pixel.
struct SurfaceSample {
    vec3 tangent_x;     // d p / d x (unnormalized)
    vec3 tangent_y;     // d p / d y
    vec2 sigma2;        // residual slope variance (wind frame)
    float curvature;    // residual curvature power (1/m^2), for the glints only
};

// 1 - sqrt(1 - a^2) without cancellation, from a2 = a^2: a2 / (1 + sqrt(1 - a2)). a = k h <= 1 by
// construction. It takes the square because the weighted loop has it without a root.
float trochoid_slope_variance(float a2) {
    return a2 / (1.0 + sqrt(max(1.0 - a2, 0.0)));
}

vec2 wave_direction(Wave wave) {
    return wave.k * inversesqrt(dot(wave.k, wave.k));
}

// cos^2 and sin^2 of the angle between a train's direction and the wind, each a square (1 - cos^2
// could round below 0).
vec2 wind_axes2(vec2 dir, vec2 wind) {
    float along = dot(dir, wind), across = dir.x * wind.y - dir.y * wind.x;
    return vec2(along * along, across * across);
}

// Adds a train's share of the tangents d p / d x and d p / d y: d/dx of (dir h sin(theta),
// h cos(theta)) with d theta / dx = -k dir, from c = k h cos(theta) and sn = k h sin(theta) (at
// the train's weight). model::waves::add_tangents is its f64 twin.
void add_tangents(inout vec3 t_x, inout vec3 t_y, vec2 dir, float c, float sn) {
    t_x += vec3(-dir * (dir.x * c), dir.x * sn);
    t_y += vec3(-dir * (dir.y * c), dir.y * sn);
}

// Adds a train resolved fully at the pixel: its slopes at x, nothing left to the BRDF.
void add_resolved_train(inout SurfaceSample r, Wave wave, vec2 dir, vec2 x) {
    vec2 sc = sincos_turns(wave.phase - dot(wave.k, x));
    add_tangents(r.tangent_x, r.tangent_y, dir, wave.kh * sc.y, wave.kh * sc.x);
    count_train(true);
}

// Adds the resolved part wn of a train's amplitude to the slopes; the rest of its slope variance,
// that of the amplitude sqrt(1 - wn^2) k h, stays in the BRDF's (0 when wn = 1), so that the
// pixel's slope variance is the train's whatever its weight. `wind2`: wind_axes2 of its direction.
void add_weighted_train(inout SurfaceSample r, Wave wave, vec2 dir, vec2 wind2, vec2 x, float wn) {
    vec2 sc = sincos_turns(wave.phase - dot(wave.k, x));
    add_tangents(r.tangent_x, r.tangent_y, dir, wn * wave.kh * sc.y, wn * wave.kh * sc.x);
    // The unresolved amplitude's square, (1 - wn^2) (k h)^2 (a square root per train less than
    // forming the amplitude: 0.977x on the default view's shading, docs/bench/realism_cost.md).
    float unresolved2 = (1.0 - wn * wn) * (wave.kh * wave.kh);
    r.sigma2 += wind2 * trochoid_slope_variance(unresolved2);
    // A sinusoid of slope k h has curvature k (k h) along the train: its variance (k^2 h)^2 / 2
    // (Train::curvature_power is its twin), the part of the amplitude left unresolved. k = 2 pi
    // |k_turns|.
    if (GLINTS) r.curvature += 2.0 * PI * PI * dot(wave.k, wave.k) * unresolved2;
    count_train(wn > 0.0);
}

SurfaceSample flat_surface() {
    return SurfaceSample(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec2(0.0), 0.0);
}

// A train at its weight in this pixel's normal (normal_weight), then add_weighted_train.
void add_train(inout SurfaceSample r, Wave wave, vec2 x, SampleScale s) {
    vec2 dir = wave_direction(wave);
    add_weighted_train(r, wave, dir, wind_axes2(dir, frame.wind.xy), x, normal_weight(s, wave.k));
}

// Trains i, i-1, ... down to the first that no direction resolves at this pixel, each at its
// weight; then the whole variance of the rest (summed on the CPU) goes to the BRDF.
void add_trains_from(inout SurfaceSample r, int i, vec2 x, SampleScale s) {
    for (; i >= 0; --i) {
        Wave wave = unpack_wave(wave_data[i].xy);
        if (dot(wave.k, wave.k) * s.lambda_cut2 >= 1.0) break;
        add_train(r, wave, x, s);
    }
    if (i >= 0) {
        r.sigma2 += wave_prefix[i].xy;
        r.curvature += wave_prefix[i].z;
    }
}

// Whether a train is resolved fully in every direction at a pixel whose largest rest-position
// step per sample is sqrt(reach2): |k| sqrt(reach2) within steps.x (frame::NORMAL_STEPS: the
// box filter's loss there is below binary16's resolution). A product, never a division:
// reach2 = 0 (no filtering) keeps every train.
bool fully_resolved(Wave wave, float reach2, vec2 steps) {
    return dot(wave.k, wave.k) * reach2 <= steps.x * steps.x;
}

float largest_step2(SampleScale s) {
    return max(dot(s.a_u, s.a_u), dot(s.a_v, s.a_v));
}

// Resolved slopes and the slope variance left for the BRDF, at one pixel.
SurfaceSample surface_sample(vec2 x, SampleScale s, vec2 steps) {
    SurfaceSample r = flat_surface();
    int i = int(frame.grid_dims.z) - 1;
    // The longest trains are resolved fully here in every direction: no weight, no residual.
    // The first loop stops at the first train that might fall short (a shorter one that would
    // still qualify is weighed by the second loop, to the same result).
    float reach2 = largest_step2(s);
    for (; i >= 0; --i) {
        Wave wave = unpack_wave(wave_data[i].xy);
        if (!fully_resolved(wave, reach2, steps)) break;
        add_resolved_train(r, wave, wave_direction(wave), x);
    }
    add_trains_from(r, i, x, s);
    return r;
}

// The rest position whose displaced point the pixel's unit ray u meets, the surface being the
// trains the pixel resolves at their weights in its normal (what its box filter keeps of each),
// from x, the grid's: the grid is flat between its nodes and displaces only its own trains, so
// at x a trochoid's compressed crest covered as many pixels as its trough, and the pixel shaded
// the slopes per unit of rest area instead of those per unit of the surface the ray meets, as
// the ground truth does. One Newton step on the two components of P(x) = sea_point(x) + D(x)
// across the ray (the sphere's drop left out of the Jacobian: its slope |x| / R is below 1e-3
// within 6 km); a second one moves the default view's bands by a tenth of the first's change.
// The step is taken where the surface faces the ray (det > 0) and only if it stays within the
// waves' slab: the ray meets the surface between the heights -+A (A the sum of the weighted
// amplitudes), within A (1 + |u.xy| / |u.z|) of x horizontally; a longer step, the linear
// model's failure at a facet seen edge-on (it grows as 1 / sin of the facet's angle to the ray),
// lands nowhere on it. `strength` in [0, 1] scales the step (0: x as it is, and no train is read).
vec2 ray_hit_rest_position(vec2 x, vec3 u, SampleScale s, float strength) {
    // e1, e2 span the plane across the ray (any horizontal e1 for a ray straight down).
    vec3 across = cross(u, vec3(0.0, 0.0, 1.0));
    float across_len = length(across);
    vec3 e1 = across_len > 0.0 ? across / across_len : vec3(1.0, 0.0, 0.0);
    vec3 e2 = cross(e1, u);
    vec3 d = vec3(0.0), t_x = vec3(1.0, 0.0, 0.0), t_y = vec3(0.0, 1.0, 0.0);
    float slab = 0.0;
    // A loop that starts below 0 where there is no step to take: a SIMD group none of whose
    // invocations takes one runs no iteration.
    for (int i = strength > 0.0 ? int(frame.grid_dims.z) - 1 : -1; i >= 0; --i) {
        Wave wave = unpack_wave(wave_data[i].xy);
        float k2 = dot(wave.k, wave.k);
        if (k2 * s.lambda_cut2 >= 1.0) break;
        float kh = normal_weight(s, wave.k) * wave.kh;
        vec2 dir = wave.k * inversesqrt(k2);
        vec2 sc = sincos_turns(wave.phase - dot(wave.k, x));
        // h = k h / k, k = 2 pi |k_turns|.
        float h = kh * inversesqrt(k2) * (0.5 / PI);
        slab += h;
        d += vec3(dir * (h * sc.x), h * sc.y);
        add_tangents(t_x, t_y, dir, kh * sc.y, kh * sc.x);
    }
    vec3 p = sea_point(x) + d;
    mat2 jacobian = mat2(dot(t_x, e1), dot(t_x, e2), dot(t_y, e1), dot(t_y, e2));
    float det = determinant(jacobian);
    // x - inverse(J) f = x - adj(J) f / det; the slab's bound compared before dividing, and
    // multiplied through by |u.z| (0 on the horizon: no bound).
    vec2 f = vec2(dot(p, e1), dot(p, e2));
    vec2 adj_f = vec2(jacobian[1][1] * f.x - jacobian[1][0] * f.y, jacobian[0][0] * f.y - jacobian[0][1] * f.x);
    float vertical = abs(u.z);
    bool within = length(adj_f) * vertical <= slab * (vertical + length(u.xy)) * det;
    return strength > 0.0 && det > 0.0 && within ? x - adj_f * (strength / det) : x;
}

#endif
