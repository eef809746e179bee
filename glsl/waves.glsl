// Filtered trochoid waves: per-train resolution weights, displacement and slopes.
// Requires frame.glsl and common.glsl, and a `waves[]` buffer in scope.
#ifndef WAVES_GLSL
#define WAVES_GLSL

// How one screen sample maps onto the mean sea plane.
// A camera ray r (unnormalized) hits the plane z = -H at rest position x = H r.xy / w, w = -r.z.
// Its derivative along a screen axis with dr/ds = r' is H (r'.xy w + r.xy r'.z) / w^2; we keep
// the numerator q and w^2 apart so that the horizon (w -> 0) never divides.
struct Footprint {
    vec2 q_u;       // numerator of dx/d(pixel u), times 1/H
    vec2 q_v;       // same along pixel v
    float w2;       // w^2
    float q_max;    // max(|q_u|, |q_v|): bounds |k_hat . q| over all directions
    float q_min;    // lower bound of max(|k_hat.q_u|, |k_hat.q_v|) over unit k_hat
};

Footprint plane_footprint(vec3 ray) {
    float w = max(-ray.z, 0.0);
    vec3 dr_du = frame.cam_right.xyz * (2.0 * frame.viewport.z);
    vec3 dr_dv = frame.cam_down.xyz * (2.0 * frame.viewport.w);
    Footprint f;
    f.q_u = dr_du.xy * w + ray.xy * dr_du.z;
    f.q_v = dr_dv.xy * w + ray.xy * dr_dv.z;
    f.w2 = w * w;
    float lu = length(f.q_u), lv = length(f.q_v);
    f.q_max = max(lu, lv);
    // For M = [q_u q_v], |M^T k| >= sigma_min(M) = |det M| / sigma_max(M) >= |det M| / ||M||_F,
    // and max(|a|, |b|) >= |(a, b)| / sqrt(2).
    float det = abs(f.q_u.x * f.q_v.y - f.q_u.y * f.q_v.x);
    float frobenius = sqrt(2.0 * (lu * lu + lv * lv));
    f.q_min = frobenius > 0.0 ? det / frobenius : 0.0;   // det <= frobenius^2 / 4: no overflow
    return f;
}

// Weight of train `i` at scale `cells` pixels: smoothstep(lo, hi, samples per wavelength), with
// samples per wavelength = 2 pi w^2 / (H cells |k . q|_max) (phase step per sample on either axis).
float resolution_weight(Footprint f, vec2 k_vec, float cells, vec2 bounds) {
    float m = max(abs(dot(k_vec, f.q_u)), abs(dot(k_vec, f.q_v)));
    return ratio_smoothstep(bounds.x, bounds.y, 2.0 * PI * f.w2, frame.cam_forward.w * cells * m);
}

// Shortest wavelength that can have a non-zero weight at this footprint and scale:
// lambda <= lo H cells q_min / w^2 means weight 0 in every direction. Written as a product test.
bool surely_unresolved(Footprint f, float lambda, float cells, float lo) {
    return lambda * f.w2 <= lo * frame.cam_forward.w * cells * f.q_min;
}

// Trains are sorted by increasing wavelength, so loops run from the longest down and stop
// at the first one that no sample at this scale can resolve.

// Displacement of the surface point with rest position x (camera-relative, metres).
vec3 displacement(vec2 x, Footprint f, float cells, vec2 bounds) {
    vec3 d = vec3(0.0);
    for (int i = int(frame.grid_dims.z) - 1; i >= 0; --i) {
        Wave wave = waves[i];
        if (surely_unresolved(f, wave.len_k_prefix.x, cells, bounds.x)) break;
        vec2 k_vec = wave.dir_amp_phase.xy * wave.len_k_prefix.y;
        float wp = resolution_weight(f, k_vec, cells, bounds);
        float theta = wave.dir_amp_phase.w - dot(k_vec, x);
        float h = wp * wave.dir_amp_phase.z;
        d += vec3(wave.dir_amp_phase.xy * (h * sin(theta)), h * cos(theta));
    }
    return d;
}

// Resolved slopes and the slope variance left for the BRDF, at one pixel.
struct SurfaceSample {
    vec3 tangent_x;     // d p / d x (unnormalized)
    vec3 tangent_y;     // d p / d y
    vec2 sigma2;        // residual slope variance (wind frame), before the sun's own spread
};

// 1 - sqrt(1 - a^2) without cancellation: a^2 / (1 + sqrt(1 - a^2)). a = k h <= 1 by construction.
float trochoid_slope_variance(float a) {
    float a2 = a * a;
    return a2 / (1.0 + sqrt(max(1.0 - a2, 0.0)));
}

SurfaceSample surface_sample(vec2 x, Footprint f, vec2 bounds) {
    SurfaceSample s;
    s.tangent_x = vec3(1.0, 0.0, 0.0);
    s.tangent_y = vec3(0.0, 1.0, 0.0);
    s.sigma2 = vec2(0.0);
    vec2 wind = frame.wind.xy;
    int i = int(frame.grid_dims.z) - 1;
    for (; i >= 0; --i) {
        Wave wave = waves[i];
        if (surely_unresolved(f, wave.len_k_prefix.x, 1.0, bounds.x)) break;
        vec2 dir = wave.dir_amp_phase.xy;
        float k = wave.len_k_prefix.y;
        vec2 k_vec = dir * k;
        float wn = resolution_weight(f, k_vec, 1.0, bounds);
        float theta = wave.dir_amp_phase.w - dot(k_vec, x);
        float kh = k * wave.dir_amp_phase.z;
        // d/dx of (dir h sin(theta), h cos(theta)) with d theta / dx = -k_vec.
        float c = wn * kh * cos(theta), s_ = wn * kh * sin(theta);
        s.tangent_x += vec3(-dir * (dir.x * c), dir.x * s_);
        s.tangent_y += vec3(-dir * (dir.y * c), dir.y * s_);
        if (wn < 1.0) {
            float cw = dot(dir, wind), sw = dir.x * wind.y - dir.y * wind.x;
            s.sigma2 += vec2(cw * cw, sw * sw) * trochoid_slope_variance((1.0 - wn) * kh);
        }
    }
    // Trains 0..i are unresolved at this pixel: their whole variance, summed on the CPU.
    if (i >= 0) s.sigma2 += waves[i].len_k_prefix.zw;
    return s;
}

#endif
