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

// The sky's radiance along unit direction d, d.z >= 0.
vec3 sky_along(vec3 d) {
#ifdef PHYSICAL_SKY
    return textureLod(sky_view_table, sky_view_uv(d, false), 0.0).rgb;
#else
    return preetham_sky(d);
#endif
}

void main() {
    ivec2 size = imageSize(sky_level0);
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(texel, size))) return;
    vec2 uv = (vec2(texel) + 0.5) / vec2(size);
    vec2 u = (uv * 2.0 - 1.0) * frame.tone.y;
    vec3 ray = inverse_stereographic(u);
    bool below = ray.z < 0.0;
    vec3 L = sky_along(vec3(ray.xy, abs(ray.z)));
    // A reflected ray going down meets a wave facing it, and going up Smith's share of them still
    // does (blocked_share), rising to all at the horizon, so the map is continuous across it. The
    // wave mirrors it once more (multiple reflections, the paper's suggested extension) with the
    // mean Fresnel F2 about the mean facet such a ray strikes (struck_facet_normal): a rising ray
    // meets only facets steeper than itself and leaves them higher than it came, where the sky
    // is darker than along the ray itself (the ground truth's reflected sky on the default view,
    // docs/results.md "The reflected sky's blocked rays"). The rest, 1 - F2, enters the sea (the
    // refracted term's light). Their sun glint is left out: the sun term is separate.
    float enters = 0.0;
    if (METHOD == METHOD_FULL) {
        vec2 wind = frame.wind.xy, across = vec2(-wind.y, wind.x);
        vec3 local = vec3(dot(ray.xy, wind), dot(ray.xy, across), ray.z);
        float f2 = visible_fresnel(abs(ray.z), sqrt(directional_variance(local, frame.wind.zw)));
        float blocked = below ? 1.0 : blocked_share(local, frame.wind.zw);
        vec3 again = reflect(local, struck_facet_normal(local, frame.wind.zw));
        // Still going down (a falling ray off a facet leaning away): the mirrored sky, as before.
        vec3 again_world = vec3(again.x * wind + again.y * across, abs(again.z));
        L = (1.0 - blocked) * L + blocked * f2 * sky_along(again_world);
        enters = blocked * (1.0 - f2);
    }
    imageStore(sky_level0, texel, vec4(store_radiance(L), enters));
}
