// Level 0 of the stereographic sky map: texel centre u in [-R, R]^2 -> direction. Texels beyond the
// unit disc take the folded (mirrored) direction, so filtering across the horizon stays smooth.
// Entry points: sky_map.comp (Preetham's sky) and sky_map_physical.comp (PHYSICAL_SKY: the
// physical sky resampled from its sky-view table, glsl/sky_view.comp).
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"
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
    dir.z = abs(dir.z);
#ifdef PHYSICAL_SKY
    vec3 L = textureLod(sky_view_table, sky_view_uv(dir), 0.0).rgb;
#else
    vec3 L = preetham_sky(dir);
#endif
    imageStore(sky_level0, texel, vec4(store_radiance(L), 1.0));
}
