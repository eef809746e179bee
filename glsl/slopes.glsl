// Statistics of the sea's Gaussian slopes that need no texture (shared by the BRDF and the sky
// map): the mean Fresnel over the visible slopes, the variance along an azimuth, and where the
// visible slopes are centred.
#ifndef SLOPES_GLSL
#define SLOPES_GLSL

const float FRESNEL_R0 = 0.02;   // water at normal incidence (paper, section 5)

// Mean Fresnel over the visible slopes (paper, eq. for F-bar, fitted to numerical integration).
float mean_fresnel(float cos_v, float sigma_v) {
    return FRESNEL_R0 + (1.0 - FRESNEL_R0) * pow(1.0 - cos_v, 5.0 * exp(-2.69 * sigma_v))
         / (1.0 + 22.7 * pow(sigma_v, 1.5));
}

// Slope variance along the local azimuth of d (wind axes x, y); for d along the normal the azimuth
// is undefined and the mean of the two axes is its limit under any direction average.
float directional_variance(vec3 d_local, vec2 sigma2) {
    float s2 = d_local.x * d_local.x + d_local.y * d_local.y;
    return s2 > 0.0 ? (sigma2.x * d_local.x * d_local.x + sigma2.y * d_local.y * d_local.y) / s2
                    : 0.5 * (sigma2.x + sigma2.y);
}

// Standard normal CDF for r >= 0 (Abramowitz & Stegun 7.1.26 for erf, |error| <= 1.5e-7):
// in [0.5, 1], so dividing by it is always safe.
float normal_cdf_positive(float r) {
    float x = r * 0.70710678;
    float t = 1.0 / (1.0 + 0.3275911 * x);
    float poly = t * (0.254829592 + t * (-0.284496736 + t * (1.421413741 + t * (-1.453152027 + t * 1.061405429))));
    return 1.0 - 0.5 * poly * exp(-x * x);
}

// Mean slope of the facets seen from v (local frame), with each weighted by its projected area
// (v_z - zeta . v_xy)^+: for Gaussian slopes of covariance diag(sigma2) and s = zeta along v's
// azimuth, of variance sigma_s^2 and with cot(theta_v) = c, E[s] = -sigma_s^2 / (c + sigma_s
// phi(r) / Phi(r)) at r = c / sigma_s, and zeta follows s by its regression sigma2 v_xy / sigma_s^2:
// shift = -sigma2 * v_xy_unit / (c + sigma_s phi(r) / Phi(r)), facets leaning towards the viewer.
// At grazing view (c = 0) it is -1.25 sigma_s along the azimuth; seen from above, 0. The
// divisor is at least sigma_s phi(r) / Phi(r) > 0 while sigma_s > 0 and r finite; phi(r)
// underflows to 0 only where c itself is large.
vec2 visible_slope_shift(vec3 v_local, vec2 sigma2) {
    float sin2 = dot(v_local.xy, v_local.xy);
    float var = directional_variance(v_local, sigma2);
    if (sin2 <= 0.0 || var <= 0.0) return vec2(0.0);
    float sin_v = sqrt(sin2);
    vec2 azimuth = v_local.xy / sin_v;
    float sigma = sqrt(var);
    float c = max(v_local.z, 0.0) / sin_v;
    float r = c / sigma;
    float mills = 0.39894228 * exp(-0.5 * min(r * r, 2.0 * EXP_UNDERFLOW)) / normal_cdf_positive(r);
    return -sigma2 * azimuth / (c + sigma * mills);
}

#endif
