// Statistics of the sea's Gaussian slopes (shared by the BRDF and the sky map): the mean Fresnel
// over the visible slopes (the paper's fit, or the exact average from its table), the variance
// along an azimuth, and where the visible slopes are centred.
#ifndef SLOPES_GLSL
#define SLOPES_GLSL

const float FRESNEL_R0 = 0.02;   // water at normal incidence (paper, section 5)

// Mean Fresnel over the visible slopes (paper, eq. for F-bar, fitted to numerical integration).
float mean_fresnel(float cos_v, float sigma_v) {
    return FRESNEL_R0 + (1.0 - FRESNEL_R0) * pow(1.0 - cos_v, 5.0 * exp(-2.69 * sigma_v))
         / (1.0 + 22.7 * pow(sigma_v, 1.5));
}

// The exact Fresnel of sea water averaged over the visible slopes (src/model/fresnel.rs,
// MeanFresnelTable; binding resources::MEAN_FRESNEL_BINDING): x of the header the refractive
// index, then per cell of the COS_SIZE x SIGMA_SIZE nodes at cos_v = u^2, sigma_v = SIGMA_MAX t^2
// (u, t on uniform grids over [0, 1]; cells row-major by sigma) its four corners' values, so a
// bilinear lookup reads one vec4 (resources::mean_fresnel_buffer).
const int FRESNEL_COS_SIZE = 64;
const int FRESNEL_SIGMA_SIZE = 32;
const float FRESNEL_SIGMA_MAX = 1.0;
layout(set = 0, binding = 11, std430) restrict readonly buffer MeanFresnel {
    vec4 fresnel_header;
    vec4 fresnel_cells[];   // (FRESNEL_COS_SIZE - 1) x (FRESNEL_SIGMA_SIZE - 1)
};

// Unpolarized Fresnel reflectance from air into sea water at cos(incidence) c (the mean of the
// s and p reflectances). Both denominators are at least eta cos_t > 0 for c > 0 (eta > 1 keeps
// cos_t > 0); at c = 0 they are 0 only together with their numerators, where the limit is 1.
float fresnel_exact(float c) {
    float eta = fresnel_header.x;
    c = clamp(c, 0.0, 1.0);
    float cos_t = sqrt(max(1.0 - (1.0 - c * c) / (eta * eta), 0.0));
    float s_den = c + eta * cos_t, p_den = eta * c + cos_t;
    if (s_den <= 0.0 || p_den <= 0.0) return 1.0;
    float rs = (c - eta * cos_t) / s_den, rp = (eta * c - cos_t) / p_den;
    return 0.5 * (rs * rs + rp * rp);
}

// The table bilinearly, as MeanFresnelTable::lookup: clamped to its domain on both axes.
float visible_fresnel(float cos_v, float sigma_v) {
    float u = sqrt(clamp(cos_v, 0.0, 1.0)) * float(FRESNEL_COS_SIZE - 1);
    float t = sqrt(clamp(sigma_v / FRESNEL_SIGMA_MAX, 0.0, 1.0)) * float(FRESNEL_SIGMA_SIZE - 1);
    int i = min(int(u), FRESNEL_COS_SIZE - 2), j = min(int(t), FRESNEL_SIGMA_SIZE - 2);
    vec4 corners = fresnel_cells[j * (FRESNEL_COS_SIZE - 1) + i];
    vec2 f = vec2(u - float(i), t - float(j));
    vec2 along = mix(corners.xz, corners.yw, f.x);   // (low sigma, high sigma)
    return mix(along.x, along.y, f.y);
}

// The mean Fresnel of the sky and refracted terms: the exact average for METHOD_FULL, the paper's
// fit otherwise.
float sea_fresnel(float cos_v, float sigma_v) {
    return METHOD == METHOD_FULL ? visible_fresnel(cos_v, sigma_v) : mean_fresnel(cos_v, sigma_v);
}

// Slope variance along the local azimuth of d (wind axes x, y); for d along the normal the azimuth
// is undefined and the mean of the two axes is its limit under any direction average.
float directional_variance(vec3 d_local, vec2 sigma2) {
    float s2 = d_local.x * d_local.x + d_local.y * d_local.y;
    return s2 > 0.0 ? (sigma2.x * d_local.x * d_local.x + sigma2.y * d_local.y * d_local.y) / s2
                    : 0.5 * (sigma2.x + sigma2.y);
}

// c * Lambda(a) with a = c / s, for c = cos(theta) >= 0 and s = sin(theta) sqrt(2 sigma_phi^2) >= 0
// (Smith's Lambda for Gaussian slopes; erfc from the paper's demo rational approximation).
// Never divides by c: c Lambda = exp(-a^2) (s / (2 sqrt(pi)) - c / (2.319 a + sqrt(4 + 1.52 a^2))).
// For a > 9 the value is below FLT_MIN relative to c, so it is returned as its limit 0.
float cos_times_lambda(float c, float s) {
    if (c >= 9.0 * s) return 0.0;
    float a = c / s;   // s > c / 9 >= 0 here
    return exp(-a * a) * (s / (2.0 * SQRT_PI) - c / (2.319 * a + sqrt(4.0 + 1.52 * a * a)));
}

// sin(theta) sqrt(2 sigma_phi^2) for unit direction d: sigma_phi^2 sin^2(theta) = sigma_x^2 d_x^2 + sigma_y^2 d_y^2
// in the local frame, so the azimuth never needs an atan or a division.
float slope_spread(vec3 d_local, vec2 sigma2) {
    return sqrt(2.0 * (sigma2.x * d_local.x * d_local.x + sigma2.y * d_local.y * d_local.y));
}

// The share of the rays leaving the sea towards unit direction d (local frame: z up) that the
// next wave stops: all below the horizon; above it Smith's 1 - G1 = Lambda / (1 + Lambda) for
// slopes of variance sigma2 (uncorrelated with height, so the same from every facet: from a
// crest seen at grazing view it overstates the blocking). Lambda / (1 + Lambda) = c Lambda /
// (c + c Lambda); towards the horizon c Lambda -> s / (2 sqrt(pi)) > 0 while c -> 0, so the share
// rises continuously to 1; on a glassy sea (s = 0) nothing above the horizon is stopped.
float blocked_share(vec3 d_local, vec2 sigma2) {
    if (d_local.z <= 0.0) return 1.0;
    float cl = cos_times_lambda(d_local.z, slope_spread(d_local, sigma2));
    return cl / (d_local.z + cl);   // d_local.z > 0
}

// Standard normal CDF for r >= 0 (Abramowitz & Stegun 7.1.26 for erf, |error| <= 1.5e-7):
// in [0.5, 1], so dividing by it is always safe.
float normal_cdf_positive(float r) {
    float x = r * 0.70710678;
    float t = 1.0 / (1.0 + 0.3275911 * x);
    float poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    return 1.0 - 0.5 * poly * exp(-x * x);
}

// Standard normal CDF for any r, from the positive half's.
float normal_cdf(float r) {
    return r >= 0.0 ? normal_cdf_positive(r) : 1.0 - normal_cdf_positive(-r);
}

// The share of a Gaussian's mass that tap i of `count` stands for, taps spaced `spacing`
// standard deviations apart about its mean ((i - (count - 1) / 2) spacing): the mass nearer to it
// than to its neighbours, the outer taps' reaching to infinity, so the shares sum to 1. Equal
// parts of eight taps spanning -+1.49 sigma (brdf.glsl ReflectionCone) gave the central two 0.76
// of their share and the outer four 1.24-1.29: a footprint that meets an object with its edge
// alone took a tap's whole part of it (docs/bench/objects.md, "Each tap's share of the slopes").
float tap_mass(int i, int count, float spacing) {
    float at = (float(i) - 0.5 * float(count - 1)) * spacing;
    float lower = i == 0 ? 0.0 : normal_cdf(at - 0.5 * spacing);
    float upper = i == count - 1 ? 1.0 : normal_cdf(at + 0.5 * spacing);
    return upper - lower;
}

// The slopes of the facets seen from v (local frame), each weighted by its projected area
// (v_z - zeta . v_xy)^+, for Gaussian slopes of covariance diag(sigma2): their mean and the two
// 1-sigma axes of their covariance. In whitened slopes z = zeta / sigma the weight depends on z
// along w = sigma v_xy_unit / sigma_s only (sigma_s^2 the variance along v's azimuth): with
// r = cot(theta_v) / sigma_s and m = phi(r) / Phi(r), the weighted mean there is -1 / (r + m) and
// the variance k = (r + 2m) / (r + m) - 1 / (r + m)^2 (moments of a Gaussian under a linear ramp),
// across w unchanged. So zeta's mean is -sigma2 v_xy_unit / (cot theta + sigma_s m), facets leaning
// towards the viewer, and its axes sigma (sqrt(k) w) and sigma w_perp. Seen from above (r large)
// m -> 0, k -> 1: the plain Gaussian; at grazing (r = 0) the mean is -1.25 sigma_s and k = 0.43.
// Phi(r) >= 0.5 for r >= 0; r + m >= m > 0 while r is finite; phi underflows only where r is large.
struct VisibleSlopes { vec2 mean; vec2 axis_along; vec2 axis_across; };

// The plain Gaussian's: centred on 0, its axes the wind's (the paper's lookup).
VisibleSlopes gaussian_slopes(vec2 sigma2) {
    vec2 sigma = sqrt(sigma2);
    return VisibleSlopes(vec2(0.0), vec2(sigma.x, 0.0), vec2(0.0, sigma.y));
}

VisibleSlopes visible_slopes(vec3 v_local, vec2 sigma2) {
    VisibleSlopes plain = gaussian_slopes(sigma2);
    float sin2 = dot(v_local.xy, v_local.xy);
    float var = directional_variance(v_local, sigma2);
    if (sin2 <= 0.0 || var <= 0.0) return plain;
    float sin_v = sqrt(sin2);
    vec2 azimuth = v_local.xy / sin_v;
    float sigma_s = sqrt(var);
    float r = max(v_local.z, 0.0) / sin_v / sigma_s;
    float m = 0.39894228 * exp(-0.5 * min(r * r, 2.0 * EXP_UNDERFLOW)) / normal_cdf_positive(r);
    float k = clamp((r + 2.0 * m) / (r + m) - 1.0 / ((r + m) * (r + m)), 0.0, 1.0);
    vec2 sigma = sqrt(sigma2);
    vec2 w = sigma * azimuth / sigma_s;   // unit: |sigma * azimuth|^2 = var
    vec2 w_perp = vec2(-w.y, w.x);
    return VisibleSlopes(-sigma2 * azimuth / (sigma_s * (r + m)), sigma * w * sqrt(k), sigma * w_perp);
}

// The mean facet that a ray along unit d (local frame) strikes where it meets the sea: the facets
// facing it, each by its area projected across the ray, (zeta_s - tan e)^+ for the slope zeta_s
// along the ray's azimuth and its elevation e. That is visible_slopes' linear ramp for an eye
// looking back along the ray, r = -tan(e) / sigma_s, now of either sign: a rising ray (r < 0)
// strikes only facets steeper than itself, a falling one (r > 0) the facets seen from above.
// Phi(r) for r < 0 is 1 - Phi(-r); r is kept from -3, where Smith's blocked share of a rising ray
// is 1.2e-4 (blocked_share at a = 3 / sqrt(2)) and the mean no longer weighs on the map. Returns
// the mean facet's unit normal; straight up on a glassy sea or for a vertical ray.
vec3 struck_facet_normal(vec3 d_local, vec2 sigma2) {
    float sin2 = dot(d_local.xy, d_local.xy);
    float var = directional_variance(d_local, sigma2);
    if (sin2 <= 0.0 || var <= 0.0) return vec3(0.0, 0.0, 1.0);
    float sin_d = sqrt(sin2);
    vec2 back = -d_local.xy / sin_d;   // towards where the ray comes from
    float sigma_s = sqrt(var);
    float r = max(-d_local.z / sin_d / sigma_s, -3.0);
    float cdf = normal_cdf(r);   // >= 1.3e-3
    float m = 0.39894228 * exp(-0.5 * min(r * r, 2.0 * EXP_UNDERFLOW)) / cdf;
    vec2 mean = -sigma2 * back / (sigma_s * (r + m));   // r + m > 0 for every finite r
    return normalize(vec3(-mean, 1.0));
}

#endif
