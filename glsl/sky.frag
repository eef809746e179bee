#version 450
// The sky seen directly, where no sea fragment was drawn, from the same analytic model as the map.
#include "frame.glsl"
#include "common.glsl"
#include "sky.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    vec3 dir = normalize(camera_ray(pixel_to_ndc(gl_FragCoord.xy)));
    out_radiance = vec4(store_radiance(sky_radiance(dir) + sun_disc(dir)), 1.0);
}
