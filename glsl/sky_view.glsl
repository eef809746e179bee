// The sky-view tables' parametrization (Hillaire 2020's, generalized to an eye above the sea):
// u the azimuth from the sun's, in [0, pi] (the sky is symmetric about the sun's vertical plane),
// as sqrt(phi / pi) so that the glow around the sun gets the most texels; v the elevation l in
// [l_min, l_max] as sqrt((l - l_min) / (l_max - l_min)), so that the lowest sky does. The sea's
// table (the sky map's source, seen from sea level) spans the upper hemisphere, [0, pi/2]; the
// eye's (the sky seen directly from high up) spans from the planet's limb, -dip, up to the
// zenith, or from outside the air up to the air's own limb, above which space is black
// (frame.eye_sky). Requires frame.glsl and common.glsl.
#ifndef SKY_VIEW_GLSL
#define SKY_VIEW_GLSL

const ivec2 SKY_VIEW_SIZE = ivec2(256, 128);       // atmosphere::SKY_VIEW_SIZE

float unit_to_texcoord(float x, int size) { return 0.5 / float(size) + x * (1.0 - 1.0 / float(size)); }
float texcoord_to_unit(float u, int size) { return (u - 0.5 / float(size)) / (1.0 - 1.0 / float(size)); }

// The elevation range of a table: the sea's, or the eye's.
vec2 sky_view_range(bool eye) {
    return eye ? frame.eye_sky.xy : vec2(0.0, 0.5 * PI);
}

vec2 sky_view_uv(vec3 dir, bool eye) {
    vec3 sun = frame.sun_dir.xyz;
    vec2 range = sky_view_range(eye);
    float l = clamp(asin(clamp(dir.z, -1.0, 1.0)), range.x, range.y);
    // The azimuth from the sun's: the angle between the two horizontal parts (0 where either is
    // vertical: the sky is symmetric about the zenith then).
    float cross_z = dir.x * sun.y - dir.y * sun.x, along = dir.x * sun.x + dir.y * sun.y;
    float phi = (cross_z == 0.0 && along == 0.0) ? 0.0 : abs(atan(cross_z, along));
    float v = sqrt((l - range.x) / (range.y - range.x));   // range.y > range.x (frame.rs)
    return vec2(unit_to_texcoord(sqrt(phi / PI), SKY_VIEW_SIZE.x), unit_to_texcoord(v, SKY_VIEW_SIZE.y));
}

vec3 sky_view_direction(vec2 uv, bool eye) {
    vec2 range = sky_view_range(eye);
    float phi = PI * pow(texcoord_to_unit(uv.x, SKY_VIEW_SIZE.x), 2.0);
    float l = range.x + (range.y - range.x) * pow(texcoord_to_unit(uv.y, SKY_VIEW_SIZE.y), 2.0);
    vec3 sun = frame.sun_dir.xyz;
    float sun_azimuth = (sun.x == 0.0 && sun.y == 0.0) ? 0.0 : atan(sun.y, sun.x);
    float a = sun_azimuth + phi;
    return vec3(cos(l) * cos(a), cos(l) * sin(a), sin(l));
}

#endif
