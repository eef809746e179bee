// Level 0 of the stereographic sky map: texel centre u in [-R, R]^2 -> direction. Texels beyond the
// unit disc hold directions below the horizon: for the paper's lookups (folded) the mirrored sky,
// so filtering across the horizon stays smooth; for METHOD_FULL's (the whole plane) the sea such
// a reflected ray meets (rgb: the sky it reflects there, alpha: the share entering the sea), and
// above the horizon the sky blended with the sea by the share of rays the next wave stops.
// Entry points: sky_map.comp (Preetham's sky) and sky_map_physical.comp (PHYSICAL_SKY: the
// physical sky resampled from its sky-view table, glsl/sky_view.comp).
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"
#include "slopes.glsl"
#ifdef PHYSICAL_SKY
layout(set = 0, binding = 4) uniform sampler2D sky_view_table;
#include "atmosphere.glsl"
#endif

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 3, rgba16f) writeonly uniform image2D sky_level0;

void main() {
    ivec2 size = imageSize(sky_level0);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, size))) return;
    vec2 uv = (vec2(texel) + 0.5) / vec2(size);
    vec2 u = (uv * 2.0 - 1.0) * frame.tone.y;
    vec3 dir = inverse_stereographic(u);
    bool below = dir.z < 0.0;
    dir.z = abs(dir.z);
#ifdef PHYSICAL_SKY
    vec3 L = textureLod(sky_view_table, sky_view_uv(dir, false), 0.0).rgb;
#else
    vec3 L = preetham_sky(dir);
#endif
    // A reflected ray going down at depression e meets a wave facing it and is seen from there at
    // elevation e over all the sea's slopes (multiple reflections, the paper's suggested
    // extension): it reflects the sky mirrored once more with the mean Fresnel F2, and the rest,
    // 1 - F2, enters the sea (the refracted term's light). Going up, Smith's share of such rays
    // still meets the next wave (blocked_share), rising to all of them at the horizon, so the map
    // is continuous across it. Their sun glint is left out: the sun term is separate.
    float enters = 0.0;
    if (METHOD == METHOD_FULL) {
        vec2 wind = frame.wind.xy;
        vec3 local = vec3(dot(dir.xy, wind), dot(dir.xy, vec2(-wind.y, wind.x)), dir.z);
        float f2 = visible_fresnel(dir.z, sqrt(directional_variance(local, frame.wind.zw)));
        float blocked = below ? 1.0 : blocked_share(local, frame.wind.zw);
        L *= 1.0 - blocked * (1.0 - f2);
        enters = blocked * (1.0 - f2);
    }
    imageStore(sky_level0, texel, vec4(store_radiance(L), enters));
}
