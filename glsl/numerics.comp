#version 450
// Evaluates the shading functions themselves on arrays of inputs, for comparison with f64
// implementations of the same formulas (src/measure/numerics.rs, tests/numerics.rs). Frames are the
// identity (local = world), so directions are given in the tangent frame.
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
#include "planet.glsl"

layout(local_size_x = 64) in;
// Two vec4 of arguments per evaluation, one vec4 of results.
layout(set = 0, binding = 9, std430) readonly buffer Arguments { vec4 arguments[]; };
layout(set = 0, binding = 10, std430) writeonly buffer Results { vec4 results[]; };
layout(push_constant) uniform Call { uint function; uint count; } call;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= call.count) return;
    vec4 a = arguments[2u * i], b = arguments[2u * i + 1u];
    Frame3 identity = Frame3(vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0));
    vec4 r = vec4(0.0);
    switch (call.function) {
    case 0u: r.x = cos_times_lambda(a.x, a.y); break;                     // (cos, sin sqrt(2 sigma^2))
    case 1u: r.x = mean_fresnel(a.x, a.y); break;                          // (cos_v, sigma_v)
    case 2u: r.xy = sincos_turns(a.x); break;                              // turns
    case 3u: r.x = trochoid_slope_variance(a.x * a.x); break;              // k h
    case 4u: r.xyz = reflected_sun(identity, a.xyz, b.xyz, vec2(a.w, b.w), frame.sun_irradiance.rgb); break;  // v, l, sigma^2
    case 5u: r.xy = reflected_u(identity, a.xyz, b.xy); break;             // v, zeta
    case 6u: {                                                             // (ndc, k turns)
        // A train's weight for the per-pixel normal, as shade.comp computes it.
        SampleScale s = sample_scale(camera_ray(a.xy), 1.0, frame.filter_steps.zw);
        r.x = s.any ? normal_weight(s, a.zw) : 0.0;
        break;
    }
    case 7u: r.xy = visible_slopes(a.xyz, b.xy).mean; break;              // v (local), sigma^2
    case 8u: r.xy = stereographic_plane(a.xyz); break;                     // direction
    case 9u: {                                                             // v (local), sigma^2
        VisibleSlopes s = visible_slopes(a.xyz, b.xy);
        mat2 cov = outerProduct(s.axis_along, s.axis_along) + outerProduct(s.axis_across, s.axis_across);
        r.xyz = vec3(cov[0][0], cov[1][0], cov[1][1]);
        break;
    }
    case 10u: r.x = visible_fresnel(a.x, a.y); break;                      // (cos_v, sigma_v)
    case 11u: r.x = fresnel_exact(a.x); break;                             // cos of incidence
    case 12u: r.x = sphere_distance(a.xyz, b.x, b.y); break;               // ray, (H, R)
    case 13u: {                                                            // (n, p, n p, u0), (u1, u2)
        // Uniforms k / 2^24 as the hash's words (their top 24 bits).
        uvec3 w = uvec3(vec3(a.w, b.x, b.y) * 16777216.0) << 8u;
        r.x = binomial_count(a.x, a.y, a.z, w.x, w.y, w.z);
        break;
    }
    case 14u: r.x = tap_mass(int(a.x), int(a.y), a.z); break;             // (tap, count, spacing)
    default: break;
    }
    results[i] = r;
}
