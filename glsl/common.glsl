// Constants and numerically guarded helpers shared by the shaders.
#ifndef COMMON_GLSL
#define COMMON_GLSL

const float PI = 3.14159265358979;
const float SQRT_PI = 1.77245385090552;
// How the waves are split between geometry, normals and BRDF (specialization constant 3,
// `Method` in src/render/passes/ocean.rs).
layout(constant_id = 3) const int METHOD = 0;
const int METHOD_PAPER = 0;          // the paper as published
const int METHOD_CONSTANT_BRDF = 1;  // baseline: unresolved slopes dropped, a constant roughness
const int METHOD_NO_FILTER = 2;      // every train in geometry and normals, unfiltered; mirror BRDF
const int METHOD_FULL = 3;           // the paper with ours: the visible facets' sky, the sea seen below the horizon

// Largest finite binary16: the HDR target's range. Radiance above it is clamped, never Inf.
const float HDR_MAX = 65504.0;
// Farther than any visible sea point (m): those lie within the planet's radius of the point below
// the eye (at most 1e9 m, src/model/scene.rs). It marks a rest position gone wrong.
const float FAR_LIMIT = 2.0e9;
// exp(-x) underflows single precision (below FLT_MIN) once x exceeds ln(FLT_MAX) ~ 88.7;
// 87 keeps the result a normal float. Past it the exact value is 0 to f32 precision.
const float EXP_UNDERFLOW = 87.0;
// The smallest normal single-precision value, 2^-126: a divisor at least this large keeps a quotient
// of values <= 1 finite (below FLT_MAX).
const float FLT_MIN_NORMAL = 1.17549435e-38;

// The visibility pass stores each pixel's rest position in the HDR image's 64 bits (two f32 as
// four 16-bit words); pixels without sea keep the clear value, +Inf in x (NO_SEA_BITS), which no
// stored position has (they are clamped to FAR_LIMIT). Mirrored by `NO_SEA_CLEAR` in
// src/render/passes/ocean.rs.
const uvec4 NO_SEA_BITS = uvec4(0x0000u, 0x7f80u, 0x0000u, 0x7f80u);

uvec4 rest_position_to_bits(vec2 x) {
    uvec2 b = floatBitsToUint(x);
    return uvec4(b.x & 0xffffu, b.x >> 16, b.y & 0xffffu, b.y >> 16);
}

vec2 bits_to_rest_position(uvec4 w) {
    return uintBitsToFloat(uvec2(w.x | (w.y << 16), w.z | (w.w << 16)));
}

// Radiance as the HDR image's RGBA16F texel bits (alpha 1).
uvec4 radiance_to_bits(vec3 L) {
    uvec2 p = uvec2(packHalf2x16(L.rg), packHalf2x16(vec2(L.b, 1.0)));
    return uvec4(p.x & 0xffffu, p.x >> 16, p.y & 0xffffu, p.y >> 16);
}

vec3 store_radiance(vec3 L) {
    return min(max(L, vec3(0.0)), vec3(HDR_MAX));
}

// Camera ray (unnormalized, linear in NDC) through an NDC position.
vec3 camera_ray(vec2 ndc) {
    return frame.cam_forward.xyz + ndc.x * frame.cam_right.xyz + ndc.y * frame.cam_down.xyz;
}

vec2 pixel_to_ndc(vec2 frag) {
    return frag * frame.viewport.zw * 2.0 - 1.0;
}

// sin and cos of 2 pi t for any t, sharing one range reduction (Cody-Waite in turns, exact for
// |t| < 2^22): q = round(4t) picks the quadrant and x = 2 pi (t - q/4) lies in [-pi/4, pi/4], where
// Taylor polynomials to x^7 (sin) and x^8 (cos) are within 3.2e-7 and 2.5e-8 (next-term bounds).
// Vulkan only bounds the builtins' error on [-pi, pi]; this keeps large phases accurate everywhere.
vec2 sincos_turns(float t) {
    float q = round(4.0 * t);
    float x = 2.0 * PI * (t - 0.25 * q);
    float x2 = x * x;
    float s = x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0))));
    float c = 1.0 + x2 * (-0.5 + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40320.0))));
    int quadrant = int(q) & 3;
    vec2 sc = (quadrant & 1) == 0 ? vec2(s, c) : vec2(c, -s);
    return quadrant >= 2 ? -sc : sc;
}

#endif
