// The scene's objects in the ground truth (src/measure/truth_objects.rs builds the buffers): rays
// meet their triangles through one bounding-volume hierarchy (model::bvh's layout), and a point
// on an object is shaded with the raster's material model (glsl/object.frag: glTF's metallic-
// roughness, GGX with Smith's height-correlated masking, Schlick's Fresnel), its light traced:
// the sun through a shadow ray, the sky above and the sea below by one stratified sample of the
// environment per sample, occluded by the objects (no light between objects is carried).

#include "object_brdf.glsl"

// Whether the scene has objects (constant 20): without, none of this runs.
layout(constant_id = 20) const bool HAS_OBJECTS = false;
// model::bvh's 32-byte nodes: a box, and two adjacent children from `first` (count 0) or a
// leaf's `count` triangles from `first`. The integers are read as integers: a denormal's bits
// read as a float may be flushed to zero on the way.
struct BvhNode {
    vec3 lo;
    uint first;
    vec3 hi;
    uint count;
};
layout(set = 0, binding = 4, std430) readonly buffer ObjectNodes { BvhNode object_nodes[]; };
// Per triangle, in leaf order: its corners (the first with its material), then their normals.
struct ObjectTriangle {
    vec3 a;
    uint material;
    vec4 b;
    vec4 c;
    vec4 na;
    vec4 nb;
    vec4 nc;
};
layout(set = 0, binding = 5, std430) readonly buffer ObjectTriangles { ObjectTriangle object_triangles[]; };
layout(set = 0, binding = 6, std430) readonly buffer ObjectMaterials { vec4 object_materials[]; };

// Node visits one walk may take (constant 21: truth_objects::BVH_VISITS, which the loop budget
// reserves), and the deepest pending stack.
layout(constant_id = 21) const uint BVH_VISITS = 512u;
const int BVH_STACK = 48;

struct ObjectHit {
    float t;
    uint triangle;
    vec2 uv;
};

// Whether the ray o + t d meets the node's box within (t_min, t_max).
bool box_hit(uint node, vec3 o, vec3 inv, float t_min, float t_max) {
    vec3 a = (object_nodes[node].lo - o) * inv, b = (object_nodes[node].hi - o) * inv;
    // NaN (0 * inf: a ray in a face's plane) is left out by min and max.
    vec3 lo = min(a, b), hi = max(a, b);
    float near = max(max(max(lo.x, lo.y), lo.z), t_min);
    float far = min(min(min(hi.x, hi.y), hi.z), t_max);
    return near <= far;
}

// Möller-Trumbore: narrows `hit` to triangle k where the ray meets it nearer.
void triangle_hit(uint k, vec3 o, vec3 d, float t_min, inout ObjectHit hit) {
    vec3 a = object_triangles[k].a;
    vec3 e1 = object_triangles[k].b.xyz - a, e2 = object_triangles[k].c.xyz - a;
    vec3 p = cross(d, e2);
    float det = dot(e1, p);
    if (det == 0.0) return;   // in the triangle's plane, or degenerate
    vec3 s = o - a;
    float u = dot(s, p) / det;
    vec3 q = cross(s, e1);
    float v = dot(d, q) / det;
    float t = dot(e2, q) / det;
    if (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > t_min && t < hit.t) hit = ObjectHit(t, k, vec2(u, v));
}

// The nearest object the ray o + t d (t in (t_min, t_max)) meets: hit.t < t_max where it does.
// `unfinished`: the walk ran out of visits (a miss is then not certain).
ObjectHit object_hit(vec3 o, vec3 d, float t_min, float t_max, out bool unfinished) {
    ObjectHit hit = ObjectHit(t_max, 0u, vec2(0.0));
    unfinished = false;
    if (!HAS_OBJECTS) return hit;
    vec3 inv = 1.0 / d;   // +-inf along axes the ray does not move on: the slab test holds
    uint stack[BVH_STACK];
    int depth = 0;
    stack[0] = 0u;
    depth = 1;
    uint visits = 0u;
    for (; visits < BVH_VISITS && depth > 0; ++visits) {
        // The stack moves by explicit steps: `stack[--depth]` and `stack[depth++] = ...` lost
        // every hit on lavapipe (the walk's pushes and pops did not land where they were
        // indexed), where these do not.
        depth -= 1;
        uint node = stack[depth];
        if (!box_hit(node, o, inv, t_min, hit.t)) continue;
        uint first = object_nodes[node].first, count = object_nodes[node].count;
        if (count == 0u) {
            // The left child is visited first; a full stack drops the walk (counted unfinished).
            if (depth + 2 > BVH_STACK) {
                unfinished = true;
                depth = 0;
            } else {
                stack[depth] = first + 1u;
                stack[depth + 1] = first;
                depth += 2;
            }
        } else {
            // Leaves hold at most model::bvh::MAX_LEAF = 4 triangles: written out, so that the
            // loop budget counts one iteration per node.
            triangle_hit(first, o, d, t_min, hit);
            if (count > 1u) triangle_hit(first + 1u, o, d, t_min, hit);
            if (count > 2u) triangle_hit(first + 2u, o, d, t_min, hit);
            if (count > 3u) triangle_hit(first + 3u, o, d, t_min, hit);
        }
    }
    unfinished = unfinished || depth > 0;
    return hit;
}

// The light of the environment arriving along unit l at a point of the object whose sea point
// is `at`: the sky above, and below the sea as model::environment sees it (the sky mirrored in a
// level sea times its exact Fresnel, and the light the sea scatters back up).
vec3 environment(SeaPoint at, vec3 l) {
    vec3 up = at.up;
    float c = dot(l, up);
    vec3 sky_irradiance = SKY_PHYSICAL ? truth_sky_irradiance(dot(frame.sun_dir.xyz, up)) : frame.sky_irradiance.rgb;
    if (c >= 0.0) return SKY_PHYSICAL ? truth_sky(at, l) : preetham_sky(l);
    vec3 mirrored = l - 2.0 * c * up;
    float f = fresnel_exact(-c, tile.ior);
    vec3 sky = SKY_PHYSICAL ? truth_sky(at, mirrored) : preetham_sky(mirrored);
    return f * sky + (1.0 - f) * frame.sea_albedo.rgb * sky_irradiance / PI;
}

// The radiance an object sends back along -d from where the ray met it: `xi` two uniform numbers
// for the environment's sample (cosine-weighted about the normal).
vec3 object_radiance(vec3 o, vec3 d, ObjectHit hit, vec2 xi) {
    uint k = hit.triangle;
    vec3 p = o + hit.t * d;
    ObjectTriangle tri = object_triangles[k];
    vec3 face = normalize(cross(tri.b.xyz - tri.a, tri.c.xyz - tri.a));
    vec3 v = -d;
    face *= dot(face, v) < 0.0 ? -1.0 : 1.0;
    vec3 smooth_n = (1.0 - hit.uv.x - hit.uv.y) * tri.na.xyz + hit.uv.x * tri.nb.xyz + hit.uv.y * tri.nc.xyz;
    vec3 n = dot(smooth_n, smooth_n) > 0.0 ? normalize(smooth_n) : face;
    if (dot(n, face) < 0.0) n = -n;   // the back of a double-sided surface shows its other side
    uint material = tri.material;
    vec4 base = object_materials[2u * material];
    vec2 mr = object_materials[2u * material + 1u].xy;
    float metallic = clamp(mr.x, 0.0, 1.0);
    // glsl/object.frag's alpha: held at the sun disc's radius in slope (its tangent).
    float cos_disc = frame.sun_dir.w;
    float alpha = max(mr.y * mr.y, sqrt(max(1.0 - cos_disc * cos_disc, 0.0)) / cos_disc);
    float a2 = alpha * alpha;
    vec3 f0 = mix(vec3(0.04), base.rgb, metallic);
    vec3 diffuse_albedo = base.rgb * (1.0 - metallic);
    // Off the surface by f32's precision at its distance, along the face, for the rays leaving.
    vec3 origin = p + face * (1e-4 + 2e-6 * length(p));
    bool unfinished;
    SeaPoint at = truth_sea_point(p);
    vec3 radiance = vec3(0.0);
    for (int which = 0; which < 2; ++which) {
        vec3 l;
        vec3 light;
        if (which == 0) {
            // The sun, where no object stands in its way.
            l = frame.sun_dir.xyz;
            if (dot(n, l) <= 0.0 || frame.sun_irradiance.w == 0.0) continue;
            if (object_hit(origin, l, 0.0, 3.0e38, unfinished).t < 3.0e38) continue;
            light = frame.sun_irradiance.rgb;
        } else {
            // One cosine-weighted direction of the environment: irradiance pi L over the pdf.
            float phi = 2.0 * PI * xi.x, r = sqrt(xi.y);
            vec3 t = normalize(abs(n.z) < 0.9 ? cross(n, vec3(0.0, 0.0, 1.0)) : cross(n, vec3(1.0, 0.0, 0.0)));
            vec3 b = cross(n, t);
            l = normalize(t * (r * cos(phi)) + b * (r * sin(phi)) + n * sqrt(max(1.0 - xi.y, 0.0)));
            // A direction in the surface's plane carries nothing (and object_brdf needs n.l > 0).
            if (dot(n, l) <= 0.0) continue;
            if (object_hit(origin, l, 0.0, 3.0e38, unfinished).t < 3.0e38) continue;
            light = PI * environment(at, l);
        }
        vec3 brdf = object_brdf(n, v, l, f0, diffuse_albedo, a2);
        // The sun's term carries n.l; the environment's sample has it in its pdf.
        radiance += brdf * light * (which == 0 ? dot(n, l) : 1.0);
    }
    return radiance;
}
