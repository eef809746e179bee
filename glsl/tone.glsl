// The display transform shared by the readback (tonemap.comp) and the window (display.frag), so
// that what `ocean view` shows is what `ocean render` writes.
#ifndef TONE_GLSL
#define TONE_GLSL

// L' = 1 - exp(-exposure L) per channel (the authors' demo curve), in [0, 1).
vec3 tone_map(vec3 radiance, float exposure) {
    return clamp(1.0 - exp(-exposure * max(radiance, vec3(0.0))), 0.0, 1.0);
}

// The sRGB transfer function (IEC 61966-2-1), piecewise.
vec3 srgb_encode(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

#endif
