// The sky: Preetham, Shirley & Smits, "A Practical Analytic Model for Daylight" (SIGGRAPH
// 1999), evaluated here from the CPU's Perez coefficients and zenith values (src/model/sky.rs), or
// the physical atmosphere (specialization constant 8, SKY_PHYSICAL), raymarched
// (glsl/atmosphere.glsl) into the sky map for what the sea reflects and into the eye's own
// sky-view table for the sky seen directly (where the includer names it EYE_SKY_SAMPLER).
#ifndef SKY_GLSL
#define SKY_GLSL

#include "sky_view.glsl"

layout(constant_id = 8) const bool SKY_PHYSICAL = false;

// Perez et al. distribution F(theta, gamma) for one channel, with cos(theta) = max(dir.z, 0).
// exp(B / cos theta) with B < 0 tends to 0 at the horizon; below cos theta = -B / EXP_UNDERFLOW
// it is already under FLT_MIN, so the divisor is held there instead of reaching 0.
vec3 perez(float cos_theta, float gamma, float cos_gamma) {
    vec3 B = frame.perez_b.xyz;
    vec3 horizon_term = exp(B / max(vec3(cos_theta), -B / EXP_UNDERFLOW));
    return (1.0 + frame.perez_a.xyz * horizon_term)
         * (1.0 + frame.perez_c.xyz * exp(frame.perez_d.xyz * gamma) + frame.perez_e.xyz * cos_gamma * cos_gamma);
}

vec3 xyY_to_linear_srgb(vec3 xyY) {
    // xyY -> XYZ; Preetham's chromaticities keep y in [0.2, 0.45], never 0.
    float Y = xyY.z;
    vec3 XYZ = vec3(xyY.x * Y / xyY.y, Y, (1.0 - xyY.x - xyY.y) * Y / xyY.y);
    // XYZ -> linear sRGB (D65), IEC 61966-2-1.
    return vec3( 3.2406 * XYZ.x - 1.5372 * XYZ.y - 0.4986 * XYZ.z,
                -0.9689 * XYZ.x + 1.8758 * XYZ.y + 0.0415 * XYZ.z,
                 0.0557 * XYZ.x - 0.2040 * XYZ.y + 1.0570 * XYZ.z);
}

// Preetham's sky radiance (kcd/m^2, linear sRGB) towards unit direction `dir`; directions below
// the horizon see the horizon's radiance. The sun disc is not included (see sun_disc).
vec3 preetham_sky(vec3 dir) {
    float cos_theta = max(dir.z, 0.0);
    float cos_gamma = clamp(dot(dir, frame.sun_dir.xyz), -1.0, 1.0);
    float gamma = acos(cos_gamma);
    vec3 f = perez(cos_theta, gamma, cos_gamma);
    vec3 Yxy = frame.sky_zenith.xyz * f;   // (Y, x, y) with Y normalised by F(0, theta_s)
    vec3 rgb = xyY_to_linear_srgb(vec3(Yxy.y, Yxy.z, Yxy.x)) * frame.sky_zenith.w;
    return max(rgb, vec3(0.0));
}

// The sun disc as seen directly: uniform over its angular radius (Preetham), or limb-darkened
// (physical: I / I_mean = (1 - u (1 - m)) / (1 - u / 3), m = sqrt(1 - x^2), x the angle over the
// radius, u = 0.6; atmosphere::limb_darkening). x from chords, |dir - sun|^2 over the radius's
// chord^2: exact near the centre, where an angle from acos would lose half its digits.
const float LIMB_DARKENING_U = 0.6;

// The limb-darkened disc's radiance towards unit dir over its mean (0 outside the disc).
float limb_darkening(vec3 dir) {
    vec3 chord = dir - frame.sun_dir.xyz;
    float x2 = dot(chord, chord) / frame.atmosphere[4].y;
    float m = sqrt(max(1.0 - x2, 0.0));
    return x2 <= 1.0 ? (1.0 - LIMB_DARKENING_U * (1.0 - m)) / (1.0 - LIMB_DARKENING_U / 3.0) : 0.0;
}

vec3 sun_disc(vec3 dir) {
    // The physical sun's radiance is the eye's own (zero where the planet hides it from the eye,
    // which from high up sees it below the sea's horizon); Preetham's goes with the sea's horizon.
    vec3 disc = frame.sun_radiance.rgb * (SKY_PHYSICAL ? 1.0 : frame.sun_irradiance.w);
    if (!SKY_PHYSICAL) return dot(dir, frame.sun_dir.xyz) >= frame.sun_dir.w ? disc : vec3(0.0);
    return disc * limb_darkening(dir);
}

// Stereographic map of the upper hemisphere: u = r.xy / (1 + |r.z|). Directions below the
// horizon fold onto their mirror image above it (a ray reflected downwards meets the sea
// again and sees the sky mirrored), so |u| <= 1 and 1 + |r.z| >= 1 never divides by zero.
vec2 stereographic(vec3 r) {
    return r.xy / (1.0 + abs(r.z));
}

// The whole stereographic plane (METHOD_FULL's reflections): u = r.xy / (1 + r.z), directions below
// the horizon beyond |u| = 1, out to the map's extent R; deeper ones (1 + r.z < |r.xy| / R) are held
// at radius R along their azimuth. Straight down (r.xy = 0, r.z = -1) has no azimuth and takes a
// point of that rim, where every direction is as deep as the map holds.
vec2 stereographic_plane(vec3 r) {
    float d = max(1.0 + r.z, length(r.xy) / frame.tone.y);
    return d > 0.0 ? r.xy / d : vec2(frame.tone.y, 0.0);
}

vec3 inverse_stereographic(vec2 u) {
    float u2 = dot(u, u);
    return vec3(2.0 * u, 1.0 - u2) / (1.0 + u2);
}

vec2 sky_map_uv(vec2 u) {
    return u * (0.5 / frame.tone.y) + 0.5;
}

// The sky seen directly: the physical sky from the eye's own sky-view table (EYE_SKY_SAMPLER,
// raymarched from the eye's altitude: passes/eye_sky.rs), Preetham's evaluated. The map holds
// the sky seen from the sea, which the sea reflects. Above the air's own limb, seen from outside
// it, is empty space: black.
#ifdef EYE_SKY_SAMPLER
vec3 sky_seen(vec3 dir) {
    if (SKY_PHYSICAL) {
        if (asin(clamp(dir.z, -1.0, 1.0)) > frame.eye_sky.y) return vec3(0.0);
        return textureLod(EYE_SKY_SAMPLER, sky_view_uv(dir, true), 0.0).rgb;
    }
    return preetham_sky(dir);
}
#endif

#endif
