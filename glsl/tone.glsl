// The display transform shared by the readback (tonemap.comp) and the window (display.frag), so
// that what `ocean view` shows is what `ocean render` writes. src/output/mod.rs is its CPU twin.
// Radiance is in kcd/m^2 (binary16 keeps the sun's glints in range in that unit); the exposure
// scales it to the curve's input, 1 being the exposure's white.
#ifndef TONE_GLSL
#define TONE_GLSL

// Which curve (scene render.tone_curve) and where the exposure comes from (render.ev100 =
// "auto": the exposure pass's result, else frame.tone.x).
layout(constant_id = 1) const bool FILMIC = false;
layout(constant_id = 2) const bool AUTO_EXPOSURE = false;
layout(set = 0, binding = 7, std140) uniform MeasuredExposure { vec4 measured; } measured_exposure;

float display_exposure() {
    return AUTO_EXPOSURE ? measured_exposure.measured.x : frame.tone.x;
}

// L' = 1 - exp(-x) per channel (the authors' demo curve), in [0, 1).
vec3 exponential_curve(vec3 x) {
    return clamp(1.0 - exp(-max(x, vec3(0.0))), 0.0, 1.0);
}

// Narkowicz (2015), "ACES Filmic Tone Mapping Curve": x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14),
// a fit of the ACES reference transform's luminance response; the denominator is >= 0.14 for x >= 0.
float aces_fit(float x) {
    return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// The curve on Rec. 709 luminance, every channel scaled alike (hue and saturation kept); where the
// brightest channel would pass 1, the colour moves towards its grey just enough to bring it to 1,
// luminance unchanged: bright glints stay coloured until they are white.
vec3 filmic_curve(vec3 x) {
    x = max(x, vec3(0.0));
    float Y = dot(x, vec3(0.2126, 0.7152, 0.0722));
    if (!(Y > 0.0)) return vec3(0.0);
    float Yt = aces_fit(Y);
    vec3 c = x * (Yt / Y);
    float peak = max(c.r, max(c.g, c.b));
    // peak > 1 >= Yt: the divisor is positive.
    if (peak > 1.0) c = vec3(Yt) + (c - vec3(Yt)) * ((1.0 - Yt) / (peak - Yt));
    return clamp(c, 0.0, 1.0);
}

vec3 tone_map(vec3 radiance) {
    vec3 x = max(radiance, vec3(0.0)) * display_exposure();
    return FILMIC ? filmic_curve(x) : exponential_curve(x);
}

// The sRGB transfer function (IEC 61966-2-1), piecewise.
vec3 srgb_encode(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

#endif
