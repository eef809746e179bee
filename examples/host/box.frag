#version 450
// A painted buoy under the ocean's sun: Lambertian, its radiance in kcd/m^2 (the ocean's unit,
// OceanDesc::radiance_scale = 1), from the sun's and the sky's illuminance (klux).
layout(push_constant) uniform Light {
    layout(offset = 96) vec4 sun;   // xyz: towards the sun; w: its illuminance (klux)
    vec4 sky;                       // x: the sky's illuminance on a level surface (klux)
} light;
layout(location = 0) in vec3 in_normal;
layout(location = 0) out vec4 out_color;

const vec3 ALBEDO = vec3(0.75, 0.22, 0.05);
const float PI = 3.14159265;

void main() {
    vec3 n = normalize(in_normal);
    float sky_share = 0.5 + 0.5 * n.z;   // the upper hemisphere seen by the face
    vec3 E = vec3(max(dot(n, light.sun.xyz), 0.0) * light.sun.w + sky_share * light.sky.x);
    out_color = vec4(ALBEDO / PI * E, 1.0);
}
