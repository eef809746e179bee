// The sky: Preetham, Shirley & Smits, "A Practical Analytic Model for Daylight" (SIGGRAPH
// 1999), evaluated here from the CPU's Perez coefficients and zenith values (src/model/sky.rs), or
// the physical atmosphere (specialization constant 8, SKY_PHYSICAL), which sky_map.comp
// raymarches into the sky map (glsl/atmosphere.glsl) and everything else reads from the map
// (where the includer names its sampler SKY_MAP_SAMPLER).
#ifndef SKY_GLSL
#define SKY_GLSL

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

vec3 sun_disc(vec3 dir) {
    vec3 disc = frame.sun_radiance.rgb * frame.sun_irradiance.w;
    if (!SKY_PHYSICAL) return dot(dir, frame.sun_dir.xyz) >= frame.sun_dir.w ? disc : vec3(0.0);
    vec3 chord = dir - frame.sun_dir.xyz;
    float x2 = dot(chord, chord) / frame.atmosphere[4].y;
    float m = sqrt(max(1.0 - x2, 0.0));
    return x2 <= 1.0 ? disc * ((1.0 - LIMB_DARKENING_U * (1.0 - m)) / (1.0 - LIMB_DARKENING_U / 3.0)) : vec3(0.0);
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

#ifdef SKY_MAP_SAMPLER
// The sky seen directly (the sun disc not included): the physical sky from the map that holds
// it, Preetham's evaluated. Directions below the horizon see the map's mirror image. Where the map
// holds the sea below the horizon (METHOD_FULL: rgb F2 L, alpha 1 - F2), rgb / (1 - alpha) is the
// sky again, for each texel and for any blend of them near the rim: a weighted mean of sky
// radiances. 1 - alpha >= FRESNEL_R0 > 0 on every texel, so on every blend.
vec3 sky_radiance(vec3 dir) {
    if (SKY_PHYSICAL) {
        vec4 m = textureLod(SKY_MAP_SAMPLER, sky_map_uv(stereographic(dir)), 0.0);
        return m.rgb / (1.0 - m.a);
    }
    return preetham_sky(dir);
}
#endif

#endif
