// The physical sky (src/model/atmosphere.rs is its f64 twin and says where the model comes
// from): the atmosphere's coefficients, Bruneton (2017)'s transmittance parametrization, and the
// sky's radiance along a ray from single scattering plus Hillaire (2020)'s multiple-scattering
// term. Lengths in metres. Requires frame.glsl and common.glsl; the table samplers
// (TRANSMITTANCE_TABLE, MULTIPLE_SCATTERING_TABLE) where defined.
//
// f32 and a planet: radii are ~6.4e6 m, so r^2 - R^2 formed as a difference of squares loses
// everything at sea level (its ulp is ~4e6 m^2). Every such difference is formed from altitudes
// instead: r^2 - R^2 = h (2R + h), R_top^2 - r^2 = (H_top - h)(R_top + r).
//
// The tables are read through samplers (TRANSMITTANCE_TABLE, MULTIPLE_SCATTERING_TABLE), or, for
// the ground truth, through functions of the texture coordinate that the includer defines
// (TRANSMITTANCE_LOOKUP, MULTIPLE_SCATTERING_LOOKUP: vec3 f(vec2 uv)).
#ifndef ATMOSPHERE_GLSL
#define ATMOSPHERE_GLSL

#include "sky_view.glsl"

const ivec2 TRANSMITTANCE_SIZE = ivec2(256, 64);   // atmosphere::TRANSMITTANCE_SIZE
const int MULTIPLE_SCATTERING_SIZE = 32;           // atmosphere::MULTIPLE_SCATTERING_SIZE
const int SKY_STEPS = 40;                          // atmosphere::SKY_STEPS
const int MS_DIRECTIONS = 8;                       // atmosphere::MS_DIRECTIONS
const int MS_STEPS = 20;                           // atmosphere::MS_STEPS
const int AERIAL_SIZE = 32;                        // resources::AERIAL_SIZE: rays per side and slices

float bottom_radius() { return frame.atmosphere[0].x; }
float top_radius() { return frame.atmosphere[0].y; }
float atmosphere_height() { return frame.atmosphere[0].y - frame.atmosphere[0].x; }

struct Medium {
    vec3 rayleigh;     // scattering
    float mie;         // scattering
    vec3 extinction;
};

Medium medium_at(float h) {
    float rayleigh = exp(-max(h, 0.0) / frame.atmosphere[0].z);
    float mie = exp(-max(h, 0.0) / frame.atmosphere[0].w);
    float ozone = max(0.0, 1.0 - abs(h - frame.atmosphere[3].x) / (0.5 * frame.atmosphere[3].y));
    Medium m;
    m.rayleigh = frame.atmosphere[1].xyz * rayleigh;
    m.mie = frame.atmosphere[2].w * mie;
    m.extinction = m.rayleigh + (frame.atmosphere[2].w + frame.atmosphere[3].z) * mie + frame.atmosphere[2].xyz * ozone;
    return m;
}

float rayleigh_phase(float nu) {
    return 3.0 / (16.0 * PI) * (1.0 + nu * nu);
}

// Cornette-Shanks; 1 + g^2 - 2 g nu >= (1 - |g|)^2 > 0 for |g| < 1 (the scene checks).
float mie_phase(float nu) {
    float g = frame.atmosphere[1].w, g2 = g * g;
    return 3.0 / (8.0 * PI) * (1.0 - g2) * (1.0 + nu * nu) / ((2.0 + g2) * pow(1.0 + g2 - 2.0 * g * nu, 1.5));
}

// r^2 (mu^2 - 1) + R_top^2 for a point at altitude h (exact form: see the top).
float top_discriminant(float h, float mu) {
    float r = bottom_radius() + h;
    return (atmosphere_height() - h) * (top_radius() + r) + r * r * mu * mu;
}

float distance_to_top(float h, float mu) {
    float r = bottom_radius() + h;
    return max(-r * mu + sqrt(max(top_discriminant(h, mu), 0.0)), 0.0);
}

// r^2 (mu^2 - 1) + R^2 = r^2 mu^2 - h (2R + h); the ray enters the ground where this is > 0 and
// mu < 0 (a ray along the tangent only touches it).
float ground_discriminant(float h, float mu) {
    float r = bottom_radius() + h;
    return r * r * mu * mu - h * (2.0 * bottom_radius() + h);
}

bool meets_ground(float h, float mu) {
    return mu < 0.0 && ground_discriminant(h, mu) > 0.0;
}

float distance_to_ground(float h, float mu) {
    float r = bottom_radius() + h;
    return max(-r * mu - sqrt(max(ground_discriminant(h, mu), 0.0)), 0.0);
}

// Altitude of the point at distance t along (h, mu): r_t^2 - R^2 = h (2R + h) + t (t + 2 r mu),
// divided by r_t + R; and its zenith cosine for a direction whose cosine with the zenith is mu.
float altitude_along(float h, float mu, float t) {
    float r = bottom_radius() + h;
    float excess = h * (2.0 * bottom_radius() + h) + t * (t + 2.0 * r * mu);
    float r_t = sqrt(max(r * r + t * (t + 2.0 * r * mu), 0.0));
    return excess / (r_t + bottom_radius());
}

// Bruneton (2017): x_mu the distance to the top between its extremes, x_r = rho / H.
vec2 transmittance_uv(float h, float mu) {
    float H = sqrt(atmosphere_height() * (top_radius() + bottom_radius()));
    float rho = sqrt(max(h * (2.0 * bottom_radius() + h), 0.0));
    float d = distance_to_top(h, mu);
    float d_min = atmosphere_height() - h, d_max = rho + H;
    float x_mu = d_max > d_min ? (d - d_min) / (d_max - d_min) : 0.0;
    return vec2(unit_to_texcoord(x_mu, TRANSMITTANCE_SIZE.x), unit_to_texcoord(rho / H, TRANSMITTANCE_SIZE.y));
}

// The (altitude, mu) a transmittance texel stands for.
vec2 transmittance_h_mu(vec2 uv) {
    float x_mu = texcoord_to_unit(uv.x, TRANSMITTANCE_SIZE.x);
    float x_r = texcoord_to_unit(uv.y, TRANSMITTANCE_SIZE.y);
    float H = sqrt(atmosphere_height() * (top_radius() + bottom_radius()));
    float rho = H * x_r;
    // h = r - R = rho^2 / (r + R), r = sqrt(rho^2 + R^2).
    float r = sqrt(rho * rho + bottom_radius() * bottom_radius());
    float h = rho * rho / (r + bottom_radius());
    float d_min = atmosphere_height() - h, d_max = rho + H;
    float d = d_min + x_mu * (d_max - d_min);
    float mu = d == 0.0 ? 1.0 : clamp((H * H - rho * rho - d * d) / (2.0 * r * d), -1.0, 1.0);
    return vec2(h, mu);
}

// Transmittance to the top by the trapezoid rule (the table's contents; atmosphere::transmittance_to_top).
vec3 integrate_transmittance(float h, float mu, int steps) {
    float d = distance_to_top(h, mu);
    float dx = d / float(steps);
    vec3 depth = vec3(0.0);
    for (int i = 0; i <= steps; ++i) {
        float w = (i == 0 || i == steps) ? 0.5 : 1.0;
        depth += w * medium_at(altitude_along(h, mu, float(i) * dx)).extinction * dx;
    }
    return exp(-depth);
}

// Where the unit ray from altitude h enters the air: 0 from inside it, -1 where it passes it by.
// The top sphere's near root in the sphere's product forms (glsl/planet.glsl): c = (h - H_top)
// (r + R_top) = r^2 - R_top^2, the root's argument r^2 (d - s)(d + s) with d the ray's depression
// and s = sqrt(c) / r the sine of the air's own dip, t = c / (r d + root).
float air_entry_mu(float h, float mu) {
    float top = atmosphere_height();
    if (h <= top) return 0.0;
    float r = bottom_radius() + h;
    float c = (h - top) * (r + top_radius());
    float s = sqrt(c) / r, d = -mu;
    return d > s ? c / (r * d + r * sqrt((d - s) * (d + s))) : -1.0;
}

float air_entry(float h, vec3 dir) {
    return air_entry_mu(h, dir.z);
}

#ifdef PLANET_GLSL
// The aerial perspective's span along the unit ray u (glsl/aerial_perspective.comp): from where it
// enters the air to the sea's sphere, or to the limb's distance where it passes above the limb.
float aerial_span(vec3 u) {
    return max(sea_distance(onto_sea(u)).x - max(air_entry(frame.atmosphere[4].z, u), 0.0), 0.0);
}
#endif

#if defined(TRANSMITTANCE_TABLE)
vec3 transmittance(float h, float mu) {
    return textureLod(TRANSMITTANCE_TABLE, transmittance_uv(h, mu), 0.0).rgb;
}
#elif defined(TRANSMITTANCE_LOOKUP)
vec3 transmittance(float h, float mu) {
    return TRANSMITTANCE_LOOKUP(transmittance_uv(h, mu));
}
#endif

#if defined(TRANSMITTANCE_TABLE) || defined(TRANSMITTANCE_LOOKUP)
// 0 where the planet hides the sun's centre.
vec3 sun_transmittance(float h, float mu_s) {
    return meets_ground(h, mu_s) ? vec3(0.0) : transmittance(h, mu_s);
}

// Between the ray's origin and distance d along it: a ratio of transmittances to the top, both
// taken pointing up for a ray that meets the ground (atmosphere::Atmosphere::transmittance_between).
// The ratio is held to [0, 1]; a denominator below the smallest normal float (a path the binary16
// table holds as opaque: its least value is 6e-8) gives 0.
vec3 transmittance_between(float h, float mu, float d) {
    float r = bottom_radius() + h;
    float h_d = clamp(altitude_along(h, mu, d), 0.0, atmosphere_height());
    float r_d = bottom_radius() + h_d;
    float mu_d = clamp((r * mu + d) / r_d, -1.0, 1.0);
    vec3 a, b;
    if (meets_ground(h, mu)) {
        a = transmittance(h_d, -mu_d);
        b = transmittance(h, -mu);
    } else {
        a = transmittance(h, mu);
        b = transmittance(h_d, mu_d);
    }
    return mix(vec3(0.0), min(a / max(b, vec3(FLT_MIN_NORMAL)), vec3(1.0)), greaterThanEqual(b, vec3(FLT_MIN_NORMAL)));
}

// Transmittance over a path from the eye that stays in the air: a view ray towards the flat sea
// may dip below the sphere, where the altitude is held at 0 (the sea level's air), so the ratio
// is taken piecewise along rising altitudes only where the ray does not meet the ground.
vec3 aerial_transmittance(float h, float mu, float d) {
    if (!meets_ground(h, mu)) return transmittance_between(h, mu, d);
    // Down to the ground, then along the sea level: the sea-level extinction over the rest.
    float d_ground = distance_to_ground(h, mu);
    vec3 down = transmittance_between(h, mu, min(d, d_ground));
    return down * exp(-medium_at(0.0).extinction * max(d - d_ground, 0.0));
}

// A ray from altitude h along unit dir as the air sees it: from where it enters the air (space is
// empty: nothing happens before), with the ray's and the sun's zenith cosines and their cosine nu
// there, the distance skipped, and whether it meets the air at all.
struct AirRay { float h; float mu; float mu_s; float nu; float skipped; bool enters; };

// The same from the ray's zenith cosine mu, the sun's mu_s and their cosine nu: all the air sees
// of a ray (it is spherically symmetric), so a sea point's sky is this in its own zenith's frame.
AirRay air_ray_cosines(float h, float mu, float mu_s, float nu) {
    float t = air_entry_mu(h, mu);
    AirRay a = AirRay(h, mu, mu_s, nu, max(t, 0.0), t >= 0.0);
    if (t <= 0.0) return a;
    float r = bottom_radius() + h;
    a.h = atmosphere_height();
    a.mu = clamp((r * mu + t) / top_radius(), -1.0, 1.0);
    a.mu_s = clamp((r * mu_s + t * nu) / top_radius(), -1.0, 1.0);
    return a;
}

AirRay air_ray(float h, vec3 dir, vec3 sun) {
    return air_ray_cosines(h, dir.z, sun.z, dot(dir, sun));
}

// Quadratic sample spacing along a ray of length d: sample i's midpoint and length.
vec2 march_step(float d, int i, int n) {
    float a = float(i) / float(n), b = float(i + 1) / float(n);
    float ta = d * a * a, tb = d * b * b;
    return vec2(0.5 * (ta + tb), tb - ta);
}
#endif

// The sea-level sky irradiance table (glsl/sea_irradiance.comp): SEA_IRRADIANCE_SIZE texels over
// the sun's zenith cosine in [SEA_IRRADIANCE_MU_MIN, 1], 18 degrees below the horizon (the end of
// astronomical twilight, below which the sky is dark) to the zenith.
const int SEA_IRRADIANCE_SIZE = 256;           // atmosphere::SEA_IRRADIANCE_SIZE
const float SEA_IRRADIANCE_MU_MIN = -0.309017; // sin(-18 degrees)

float sea_irradiance_u(float mu_s) {
    float x = clamp((mu_s - SEA_IRRADIANCE_MU_MIN) / (1.0 - SEA_IRRADIANCE_MU_MIN), 0.0, 1.0);
    return unit_to_texcoord(x, SEA_IRRADIANCE_SIZE);
}

#if defined(MULTIPLE_SCATTERING_TABLE) || defined(MULTIPLE_SCATTERING_LOOKUP)
vec3 multiple_scattering(float h, float mu_s) {
    vec2 uv = vec2(unit_to_texcoord(0.5 * mu_s + 0.5, MULTIPLE_SCATTERING_SIZE),
                   unit_to_texcoord(h / atmosphere_height(), MULTIPLE_SCATTERING_SIZE));
#ifdef MULTIPLE_SCATTERING_TABLE
    return textureLod(MULTIPLE_SCATTERING_TABLE, uv, 0.0).rgb;
#else
    return MULTIPLE_SCATTERING_LOOKUP(uv);
#endif
}

// Sky radiance (kcd/m^2) along the air ray `a`: single scattering and psi_ms along it, `steps`
// quadratically spaced samples (atmosphere::Atmosphere::sky_radiance_cosines): black where the
// ray never enters the air.
vec3 sky_radiance_along(AirRay a, int steps) {
    if (!a.enters) return vec3(0.0);
    float mu = a.mu, nu = a.nu;
    float r = bottom_radius() + a.h;
    float d = meets_ground(a.h, mu) ? distance_to_ground(a.h, mu) : distance_to_top(a.h, mu);
    float phase_r = rayleigh_phase(nu), phase_m = mie_phase(nu);
    vec3 L = vec3(0.0);
    for (int i = 0; i < steps; ++i) {
        vec2 s = march_step(d, i, steps);
        float h_t = clamp(altitude_along(a.h, mu, s.x), 0.0, atmosphere_height());
        float mu_s = clamp((r * a.mu_s + s.x * nu) / (bottom_radius() + h_t), -1.0, 1.0);
        Medium m = medium_at(h_t);
        vec3 single = sun_transmittance(h_t, mu_s) * (m.rayleigh * phase_r + m.mie * phase_m);
        vec3 multiple = (m.rayleigh + m.mie) * multiple_scattering(h_t, mu_s);
        L += transmittance_between(a.h, mu, s.x) * (single + multiple) * s.y;
    }
    return L * frame.atmosphere[4].x;   // the sun's illuminance outside the atmosphere (klux)
}

// Sky radiance (kcd/m^2) from altitude h towards unit dir, with the sun towards `sun`
// (atmosphere::Atmosphere::sky_radiance), SKY_STEPS samples.
vec3 physical_sky_radiance(float h, vec3 dir, vec3 sun) {
    return sky_radiance_along(air_ray(h, dir, sun), SKY_STEPS);
}
#endif

#endif
