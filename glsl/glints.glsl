// Glints (METHOD_FULL, GLINTS): the reflected sun as a count of lit facets in the pixel, not its
// expected value. Requires frame.glsl, common.glsl and waves.glsl (the GLINTS constant).
//
// A specular point of a Gaussian surface mirrors the eye into the sun over the area a_S / |det H|,
// a_S the sun disc's region in slope space and H the surface's Hessian; there are p(zeta_h)
// E|det H| of them per unit area (Longuet-Higgins 1960, "Reflection and refraction at a random
// moving surface", JOSA 50). So a facet, the area over which the unresolved slopes turn by the
// disc's width, is a_g = a_S / E|det H|, and a footprint of area A holds N = A / a_g of them, each
// lit with probability p, the BRDF's mass over the disc: the lit count K is binomial (the
// discrete-microfacet glint models: Zirr & Kaplanyan 2016, "Real-time rendering of procedural
// multiscale materials"; Chermain et al. 2020, "Procedural physically based BRDF for real-time
// rendering of glints"; Deliot & Belcour 2023, "Real-time rendering of glinty appearances using
// distributed binomial laws on anisotropic grids"). The pixel's sun is its expected value times
// K / (N p): the mean is kept, and the expected count N p does not depend on the disc's size.
#ifndef GLINTS_GLSL
#define GLINTS_GLSL

// E|det H| of an isotropic Gaussian surface from its curvature power M = E[h_xx^2 + 2 h_xy^2 +
// h_yy^2] (rotation-invariant: the sum over the trains of (k^2 h)^2 / 2). Isotropic, M = 8/3 m40
// with m40 = E[h_xx^2], and det H = A^2 - B^2 - C^2 with A ~ N(0, 2 m40 / 3), B, C ~ N(0, m40 / 3),
// whose mean absolute value is 4 / (3 sqrt 3) m40 = M / (2 sqrt 3). Every sea is counted as the
// isotropic one of its power: a long-crested one, whose det H vanishes along its glint lines, gets
// more and smaller facets, so less glitter, never a pixel-sized facet from a vanishing curvature.
const float ABS_DET_H_PER_POWER = 0.28867513;
// Beyond this expected count the count's relative spread, 1 / sqrt(N p) = 1e-4, is below
// binary16's resolution (4.9e-4): the expected value is exact there.
const float GLINT_COUNT_EXACT = 1.0e8;
// From this expected count on, the binomial is drawn from its normal approximation (skew
// 1 / sqrt(8) ~ 0.35; it leaves the mean within 0.2%, the share below 0 that is clamped), below it
// by inversion, summing at most GLINT_COUNT_STEPS terms of its law (P(K > 32) < 1e-10 at N p < 8).
const float GLINT_COUNT_NORMAL = 8.0;
const int GLINT_COUNT_STEPS = 32;
// Standard gravity (m/s^2): the unresolved waves' deep-water phase speed sqrt(g / k) sets how
// long a facet keeps its glint.
const float GRAVITY = 9.80665;

// Where a pixel's glints are drawn from: its rest position, its footprint on the sea's rest
// plane (the rest position's change per pixel along screen u and v, sample_scale's a_u and a_v,
// kept as their numerators and w so that the limb's footprint stays finite), and the unresolved
// curvature and slopes.
struct GlintSite {
    vec2 x;             // rest position (m)
    vec2 heading;       // the ray's horizontal direction (any length; 0 straight down)
    vec2 a_u_w;         // a_u w (m)
    vec2 a_v_w;         // a_v w
    float w;            // -n . ray (0 at the limb)
    float v_up;         // cos of the view to the sea's mean normal: the footprint's end-on share
    float curvature;    // unresolved curvature power (1/m^2), the sum of the trains' (k^2 h)^2 / 2
    vec2 slope2;        // unresolved slope variance (wind frame)
};

// pcg4d (Jarzynski & Olano 2020, "Hash functions for GPU rendering", JCGT 9(3)): four 32-bit
// words from four, each depending on all.
uvec4 pcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w; v.y += v.z * v.x; v.z += v.x * v.y; v.w += v.y * v.z;
    return v;
}

// A word's top 24 bits as a uniform number in [0, 1) (the open (0, 1) with offset 0.5).
float unit_float(uint w) { return float(w >> 8u) * (1.0 / 16777216.0); }
float open_unit_float(uint w) { return (float(w >> 8u) + 0.5) * (1.0 / 16777216.0); }

// ln(1 - p) for p in [0, 1): the series where 1 - p would round p away (its next term, p^4 / 4,
// is under 2.5e-9 p at p < 0.01), the logarithm above.
float log1m(float p) {
    return p < 0.01 ? -p * (1.0 + p * (0.5 + p * (1.0 / 3.0))) : log(1.0 - p);
}

// A binomial count of n trials of probability p (0 < p < 1) and mean n p (given: n may be +Inf,
// the Poisson limit, where p underflows against the mean) from uniforms u0, u1, u2: by inversion
// for a small mean, each term from the last as P(k + 1) = P(k) (n p - k p) / ((k + 1)(1 - p)),
// else from the normal law of its mean and variance (held to [0, n]).
float binomial_count(float n, float p, float mean, uint u0, uint u1, uint u2) {
    if (mean >= GLINT_COUNT_NORMAL) {
        // Box-Muller: sqrt(-2 ln u1) cos(2 pi u2), u1 in (0, 1).
        float z = sqrt(-2.0 * log(open_unit_float(u1))) * sincos_turns(unit_float(u2)).y;
        return clamp(mean + sqrt(mean * (1.0 - p)) * z, 0.0, n);
    }
    float u = unit_float(u0);
    // P(K = 0) = (1 - p)^n, e^-mean for small p; where it underflows (p near 1, n <= 8) the count
    // runs to n.
    float pk = exp(mean * (log1m(p) / p));
    float cdf = pk, k = 0.0;
    for (int i = 0; i < GLINT_COUNT_STEPS; ++i) {
        if (!(u > cdf && k < n)) break;
        pk *= (mean - k * p) / ((k + 1.0) * (1.0 - p));
        k += 1.0;
        cdf += pk;
    }
    return k;
}

// The brightest a pixel's glints may make it: the HDR target's range less a tenth for the sky and
// sea terms added to the same pixel (the sky's brightest, its aureole, reflects at a few percent
// of it).
const float GLINT_PEAK = 0.9 * HDR_MAX;

// The factor K / (N p) on a pixel's expected reflected sun, whose brightest channel is
// `expected_peak`. disc_share: p, the share of the pixel's visible facets that mirror the eye into the disc;
// rate_per_curvature: the expected lit facets per unit of E|det H| per m^2 of the footprint seen
// end-on (brdf.glsl, SunReflection). A pixel wholly lit, at expected / p, cannot exceed GLINT_PEAK: p
// is raised to at least expected / GLINT_PEAK (fewer facets, each lit more often, at the same
// expected count), which keeps the mean where clamping would lose it, and narrows the glitter
// only where the target could not hold it.
float glint_factor(GlintSite site, float disc_share, float rate_per_curvature, float expected_peak) {
    float p = max(disc_share, expected_peak * (1.0 / GLINT_PEAK));
    float abs_det_h = ABS_DET_H_PER_POWER * site.curvature;
    float rate = rate_per_curvature * abs_det_h * site.v_up;   // expected lit facets per m^2 of rest plane
    if (!(p > 0.0 && p < 1.0 && rate > 0.0)) return 1.0;
    // The expected count N p = rate A, A = |a_u x a_v| = |a_u w x a_v w| / w^2: exact past
    // GLINT_COUNT_EXACT, decided before dividing by w^2 (0 at the limb).
    float w2 = site.w * site.w;
    float count_w2 = rate * abs(site.a_u_w.x * site.a_v_w.y - site.a_u_w.y * site.a_v_w.x);
    if (!(count_w2 < GLINT_COUNT_EXACT * w2)) return 1.0;
    float expected = count_w2 / w2;
    // Whole trials (a footprint smaller than a facet lies in one: one trial), as many as the
    // expected count asks where that exceeds f32's integers (or overflows: the Poisson limit).
    float n = expected / p;
    bool whole = n < 16777216.0;
    n = whole ? max(round(n), 1.0) : n;
    float mean = whole ? n * p : expected;
    float facet_area = p / rate;
    // The hash's cells: along the pixel's own ray and across it (where the footprint's long and
    // short sides lie), each the footprint's extent there or the facet's side where that is
    // larger (pixels within one facet share its glint), down to a power of two so that a cell
    // changes only where the footprint halves. A ray straight down takes the x axis.
    vec2 along = dot(site.heading, site.heading) > 0.0 ? normalize(site.heading) : vec2(1.0, 0.0);
    vec2 across = vec2(-along.y, along.x);
    float inv_w = 1.0 / site.w;   // w > 0 here: count_w2 < 1e8 w^2 with count_w2 > 0
    vec2 extent = vec2(abs(dot(site.a_u_w, across)) + abs(dot(site.a_v_w, across)),
                       abs(dot(site.a_u_w, along)) + abs(dot(site.a_v_w, along))) * inv_w;
    vec2 level = clamp(floor(log2(max(extent, vec2(sqrt(facet_area))))), vec2(-30.0), vec2(30.0));
    vec2 cell = clamp(floor(vec2(dot(site.x, across), dot(site.x, along)) * exp2(-level)), vec2(-1.0e9), vec2(1.0e9));
    uvec4 key = uvec4(uvec2(ivec2(cell)), uint(int(level.x) + 64) | uint(int(level.y) + 64) << 8u, 0u);
    // A facet keeps its glint while the unresolved waves move it by its own side: at their phase
    // speed sqrt(g / k_c), k_c^2 = curvature power / slope variance. Each cell's draws change
    // at its own times (a hashed offset), never all at once.
    float k_c = sqrt(site.curvature / max(site.slope2.x + site.slope2.y, FLT_MIN_NORMAL));
    float lifetime = sqrt(facet_area) / sqrt(GRAVITY / k_c);
    float slot = floor(frame.glints.x / lifetime + unit_float(pcg4d(key).w));
    key.w = floatBitsToUint(slot);
    uvec4 u = pcg4d(key);
    return binomial_count(n, p, mean, u.x, u.y, u.z) / mean;
}

#endif
