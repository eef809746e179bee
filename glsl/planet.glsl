// The planet's sphere seen from the eye: the sea's mean level is the sphere of radius R whose
// centre lies R + H below the eye (eye-relative coordinates, z up). At R = 6360 km single
// precision cannot form |C|^2 - R^2 (it cancels to nothing below a few metres of H), so every
// quantity is built from H (2R + H) and from the ray's depression against the dip's.
#ifndef PLANET_GLSL
#define PLANET_GLSL

// Distance along the unit ray r to the sphere, or -1 where it misses (at or above the limb).
// c = H (2R + H) is |C|^2 - R^2 as a product; the root's argument B^2 - c, B = (R + H) d the
// ray's reach towards the centre (d = -r.z), is (R + H)^2 (d - s)(d + s) with s = sin(dip) =
// sqrt(c) / (R + H), so the limb (d -> s) keeps the ray's own precision; and t = c / (B + root),
// which does not cancel where the other root form B - root would (a steep view from low down).
// B + root >= B > 0 wherever the ray reaches the sphere.
float sphere_distance(vec3 r, float H, float R) {
    float d = -r.z;
    float rh = R + H;
    float c = H * (2.0 * R + H);
    float s = sqrt(c) / rh;
    if (d <= s) return -1.0;
    float root = rh * sqrt((d - s) * (d + s));
    return c / (rh * d + root);
}

#endif
