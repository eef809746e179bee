#version 450
// An object's surface in the ocean's light: glTF's metallic-roughness model (Lambertian diffuse,
// GGX microfacets with Smith's height-correlated masking and Schlick's Fresnel; glTF 2.0
// specification, appendix B), lit by the sun and by the sky above and the sea below (the
// irradiance table of model::environment), then seen through the air between the eye and the
// object (the instance's in-scatter and transmittance).
#include "object.glsl"

layout(location = 0) in vec3 in_relative;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv;
layout(location = 4) flat in uint in_instance;
layout(location = 0) out vec4 out_colour;

const float PI = 3.14159265358979;
#include "object_brdf.glsl"

// The dielectric's reflectance at normal incidence (glTF's 4%: an index of 1.5).
const float DIELECTRIC_F0 = 0.04;

// The share of the sun a point p (eye-relative) of normal n sees past the waves and the objects
// in the sun's shadow map: 1 outside the map or without the sun's view. The point is moved a
// texel's diagonal along its normal first, so that a surface does not shadow itself between the
// map's texel centres (the caster pass's slope bias covers the rest).
float sun_visibility(vec3 p, vec3 n) {
    if (frame.shadow.x == 0.0) return 1.0;
    vec4 clip = frame.sun_clip_from_relative * vec4(p + n * frame.shadow.y, 1.0);
    vec3 map = vec3(clip.xy * 0.5 + 0.5, clip.z);
    if (any(lessThan(map, vec3(0.0))) || any(greaterThan(map, vec3(1.0)))) return 1.0;
    return texture(sun_shadow_map, map);
}

// Bilinear in the irradiance table (model::environment::table_lookup).
vec3 irradiance(vec3 n) {
    float theta = acos(clamp(n.z, -1.0, 1.0));
    // At the poles every column holds the same normal's value.
    float phi = (n.x == 0.0 && n.y == 0.0) ? 0.0 : atan(n.y, n.x);
    float r = theta / PI * float(IRRADIANCE_ROWS - 1);
    int r0 = min(int(r), IRRADIANCE_ROWS - 2);
    float fr = r - float(r0);
    float c = fract(phi / (2.0 * PI)) * float(IRRADIANCE_COLUMNS);
    int c0 = min(int(c), IRRADIANCE_COLUMNS - 1);
    float fc = c - float(c0);
    int c1 = (c0 + 1) % IRRADIANCE_COLUMNS;
    int row = r0 * IRRADIANCE_COLUMNS, next = row + IRRADIANCE_COLUMNS;
    vec3 top = mix(frame.irradiance[row + c0].rgb, frame.irradiance[row + c1].rgb, fc);
    vec3 bottom = mix(frame.irradiance[next + c0].rgb, frame.irradiance[next + c1].rgb, fc);
    return mix(top, bottom, fr);
}

// v / |v|, or `fallback` where v has no direction (interpolated normals that cancel).
vec3 unit_or(vec3 v, vec3 fallback) {
    float len2 = dot(v, v);
    return len2 > 0.0 ? v * inversesqrt(len2) : fallback;
}

// The surface's normal with the normal map applied: through the model's tangents where it has
// them, else through the cotangent frame of the texture coordinates' screen derivatives (the
// frame glTF's MikkTSpace tangents approximate; a texture mapped with no gradient adds nothing).
vec3 mapped_normal(vec3 n, vec3 p) {
    float scale = material.surface.z;
    if (scale == 0.0) return n;
    vec3 texel = texture(normal_texture, in_uv).xyz * 2.0 - 1.0;
    vec3 t, b;
    vec3 tangent = in_tangent.xyz - n * dot(n, in_tangent.xyz);
    if (in_tangent.w != 0.0 && dot(tangent, tangent) > 0.0) {
        t = normalize(tangent);
        b = cross(n, t) * sign(in_tangent.w);
    } else {
        vec3 dp1 = dFdx(p), dp2 = dFdy(p);
        vec2 duv1 = dFdx(in_uv), duv2 = dFdy(in_uv);
        vec3 across2 = cross(dp2, n), across1 = cross(n, dp1);
        t = across2 * duv1.x + across1 * duv2.x;
        b = across2 * duv1.y + across1 * duv2.y;
        float m = max(dot(t, t), dot(b, b));
        if (!(m > 0.0)) return n;
        float inv = inversesqrt(m);
        t *= inv;
        b *= inv;
    }
    // t and b are perpendicular to n and texel.z is never 0 in 8 bits, so the sum has length.
    return unit_or(t * (texel.x * scale) + b * (texel.y * scale) + n * texel.z, n);
}

void main() {
    Instance o = instances[in_instance];
    vec3 p = in_relative;
    // Mirrored, the object is seen from the eye's mirror image (2 w n), and only what stands
    // above the water at it is reflected.
    vec3 eye = vec3(0.0);
    if (MIRROR) {
        if (dot(o.water_plane.xyz, p) < o.water_plane.w) discard;
        eye = 2.0 * o.mirror_plane.w * o.mirror_plane.xyz;
    }
    vec3 v = unit_or(eye - p, vec3(0.0, 0.0, 1.0));
    // The triangle's own normal turned towards the eye (screen derivatives fix its sign by the
    // screen's handedness, not by the winding).
    vec3 face = unit_or(cross(dFdx(p), dFdy(p)), v);
    face *= dot(face, v) < 0.0 ? -1.0 : 1.0;
    vec3 n = unit_or(in_normal, face);
    // The back of a double-sided surface shows its other side.
    if (dot(n, face) < 0.0) n = -n;
    n = mapped_normal(n, p);

    vec4 base = material.base_colour * texture(base_colour_texture, in_uv);
    float metallic = clamp(material.surface.x, 0.0, 1.0);
    // Below the sun disc's angular size a smoother surface still mirrors a disc, not a point:
    // alpha = roughness^2 is held at the disc's radius in slope (tan r = r to 1e-5).
    float alpha = max(material.surface.y * material.surface.y, frame.sun_direction.w);
    float a2 = alpha * alpha;
    vec3 f0 = mix(vec3(DIELECTRIC_F0), base.rgb, metallic);
    vec3 diffuse_albedo = base.rgb * (1.0 - metallic);

    float nv = max(dot(n, v), 0.0);
    vec3 radiance = vec3(0.0);
    vec3 l = frame.sun_direction.xyz;
    float nl = dot(n, l);
    if (nl > 0.0) {
        vec3 brdf = object_brdf(n, v, l, f0, diffuse_albedo, a2);
        radiance += brdf * frame.sun_irradiance.rgb * (nl * sun_visibility(p, face));
    }
    // The environment: its irradiance for the diffuse part, and for the specular part the same
    // low-frequency light about the mirror direction, weighted by the split-sum's directional
    // albedo (Karis's analytic fit, "Physically Based Shading on Mobile", 2014).
    vec3 r = reflect(-v, n);
    vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022), c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 q = material.surface.y * c0 + c1;
    float a004 = min(q.x * q.x, exp2(-9.28 * nv)) * q.x + q.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + q.zw;
    vec3 specular_albedo = f0 * ab.x + ab.y;
    radiance += diffuse_albedo / PI * irradiance(n) + specular_albedo / PI * irradiance(r);

    vec3 seen = MIRROR ? radiance * o.mirror_transmittance.rgb + o.mirror_inscatter.rgb
                       : radiance * o.transmittance.rgb + o.inscatter.rgb;
    out_colour = vec4(min(seen, vec3(frame.sun_irradiance.w)), 1.0);
}
