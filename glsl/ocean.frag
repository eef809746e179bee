#version 450
// Per-pixel shading of the sea: resolved normals from the trains longer than the pixel footprint,
// the rest as BRDF slope variance (paper, sections 4-5).
#include "frame.glsl"
#include "common.glsl"
WAVES_BLOCK;
layout(set = 0, binding = 2) uniform sampler2D sky_map;
layout(constant_id = 0) const bool TERM_SUN = true;
layout(constant_id = 1) const bool TERM_SKY = true;
layout(constant_id = 2) const bool TERM_SEA = true;
#include "waves.glsl"
#include "sky.glsl"
#include "brdf.glsl"

layout(location = 0) in vec3 in_rest_h;
layout(location = 0) out vec4 out_radiance;

void main() {
    if (!TERM_SUN && !TERM_SKY && !TERM_SEA) {
        out_radiance = vec4(0.0, 0.0, 0.0, 1.0);   // nothing to shade: no normal needed either
        return;
    }
    vec3 ray = camera_ray(pixel_to_ndc(gl_FragCoord.xy));
    vec3 v = -normalize(ray);
    SampleScale pixel = sample_scale(ray, 1.0, frame.filter_steps.zw);
    vec3 n = vec3(0.0, 0.0, 1.0);
    // Nothing resolved: all slopes in the BRDF (none for the unfiltered mirror).
    vec2 sigma2 = METHOD == METHOD_NO_FILTER ? vec2(0.0) : frame.wind.zw;
    // Only where some train is resolvable is the rest position used; there the pixel is at a finite
    // distance, so the interpolated w is positive.
    // v.z <= 0 (the eye below a raised wave) resolves nothing: the grazing limit. The interpolated
    // rest position can only run off to infinity on the horizon row, where nothing is resolved;
    // FAR_LIMIT also rejects an overflowed (Inf) or undefined quotient.
    vec2 x = in_rest_h.z > 0.0 ? in_rest_h.xy / in_rest_h.z : vec2(FAR_LIMIT);
    if (pixel.any && v.z > 0.0 && all(lessThan(abs(x), vec2(FAR_LIMIT)))) {
        SurfaceSample s = surface_sample(x, pixel, frame.filter_steps.zw, 2.0 * PI / v.z);
        // A fully steep train (k h = 1) has a cusp at its crest, where the tangents are parallel:
        // the two sides' normals average to the vertical there.
        vec3 c = cross(s.tangent_x, s.tangent_y);
        float len2 = dot(c, c);
        n = len2 > 0.0 ? c * inversesqrt(len2) : vec3(0.0, 0.0, 1.0);
        sigma2 = s.sigma2;
    }
    // The baseline drops whatever the normals do not resolve and keeps one roughness everywhere.
    if (METHOD == METHOD_CONSTANT_BRDF) sigma2 = frame.baseline_sigma2.xy;
    out_radiance = vec4(store_radiance(sea_radiance(n, v, sigma2)), 1.0);
}
