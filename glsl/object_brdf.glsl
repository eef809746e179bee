// glTF 2.0's metallic-roughness BRDF (its specification, appendix B): Lambertian diffuse under
// GGX microfacets with Smith's height-correlated masking and Schlick's Fresnel. Shared by the
// raster's objects (object.frag) and the ground truth's (groundtruth_objects.glsl), so that both
// shade one material model. n, v and l are unit, n.l > 0; a2 = alpha^2 with alpha at least the
// sun disc's radius, so that every quotient is finite. Needs PI.
vec3 object_brdf(vec3 n, vec3 v, vec3 l, vec3 f0, vec3 diffuse_albedo, float a2) {
    float nl = dot(n, l), nv = max(dot(n, v), 0.0);
    vec3 sum = v + l;
    vec3 h = dot(sum, sum) > 0.0 ? normalize(sum) : n;
    float nh = max(dot(n, h), 0.0);
    float vh = max(dot(v, h), 0.0);
    vec3 f = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
    // GGX: at most 1 / (pi a2) where nh = 1.
    float d_denominator = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (PI * d_denominator * d_denominator);
    // Smith's height-correlated visibility: the first term alone is >= nl alpha > 0.
    float vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
    return f * (d * vis) + (1.0 - f) * diffuse_albedo / PI;
}
