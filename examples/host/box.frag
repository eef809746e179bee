#version 450
// A painted buoy in the ocean's light (embed::Ocean::light): Lambertian, its radiance in kcd/m^2
// (the ocean's unit, OceanDesc::radiance_scale = 1), from the sun's and the sky's illuminance
// (klux, linear sRGB).
layout(push_constant) uniform Light {
    layout(offset = 64) vec4 sun_direction;   // xyz: towards the sun
    vec4 sun;                                 // rgb: its illuminance on a surface facing it
    vec4 sky;                                 // rgb: the sky's on a level surface
} light;
layout(location = 0) in vec3 in_normal;
layout(location = 0) out vec4 out_color;

const vec3 ALBEDO = vec3(0.75, 0.22, 0.05);
const float PI = 3.14159265;

void main() {
    vec3 n = normalize(in_normal);
    float sky_share = 0.5 + 0.5 * n.z;   // the upper hemisphere seen by the face
    vec3 E = max(dot(n, light.sun_direction.xyz), 0.0) * light.sun.rgb + sky_share * light.sky.rgb;
    out_color = vec4(ALBEDO / PI * E, 1.0);
}
