// The planet's sphere seen from the eye: the sea's mean level is the sphere of radius R whose
// centre lies R + H below the eye (eye-relative coordinates, z up; H = frame.cam_forward.w). At
// R = 6360 km single precision cannot form |C|^2 - R^2 (it cancels to nothing below a few metres
// of H), so every quantity is built from c = H (2R + H), formed on the CPU in f64, and from the
// ray's depression against the dip's (frame.planet: R, sin(dip), c, sqrt(c) the limb's distance).
// The waves live in the tangent plane of the point below the eye: a sea point's rest position x
// is its horizontal offset from the eye, and the sphere's drop |x|^2 / (2R) (exactly, below) is
// added to its height (docs/architecture.md, "The spherical sea").
// Requires frame.glsl.
#ifndef PLANET_GLSL
#define PLANET_GLSL

// Distance along the unit ray r to the sphere, or -1 where it misses (at or above the limb).
// The root's argument B^2 - c, B = (R + H) d the ray's reach towards the centre (d = -r.z), is
// (R + H)^2 (d - s)(d + s) with s = sin(dip) = sqrt(c) / (R + H), so the limb (d -> s) keeps the
// ray's own precision; and t = c / (B + root), which does not cancel where the other root form
// B - root would (a steep view from low down). B + root >= B > 0 wherever the ray reaches the
// sphere.
float sphere_distance(vec3 r, float H, float R) {
    float d = -r.z;
    float rh = R + H;
    float c = H * (2.0 * R + H);
    float s = sqrt(c) / rh;
    if (d <= s) return -1.0;
    float root = rh * sqrt((d - s) * (d + s));
    return c / (rh * d + root);
}

// Whether the unit ray u passes below the limb, so that it meets the sea's mean sphere.
bool meets_sea(vec3 u) {
    return -u.z > frame.planet.y;
}

// The limb's ray in the azimuth of the unit ray u (a ray straight up or down has every azimuth
// and takes +x).
vec3 limb_ray(vec3 u) {
    float s = frame.planet.y;
    float level = length(u.xy);
    vec2 azimuth = level > 0.0 ? u.xy / level : vec2(1.0, 0.0);
    return vec3(azimuth * sqrt((1.0 - s) * (1.0 + s)), -s);
}

// u where it meets the sea, else moved down onto the limb: the grazing limit, taken by the grid's
// nodes above the limb and by the sea's share of a pixel the limb crosses.
vec3 onto_sea(vec3 u) {
    return -u.z >= frame.planet.y ? u : limb_ray(u);
}

// u where it passes at or above the limb, else raised onto it: the sky beside a limb pixel's sea.
vec3 above_sea(vec3 u) {
    return -u.z <= frame.planet.y ? u : limb_ray(u);
}

// Along the unit ray u (onto_sea's: at or below the limb): x the distance to the mean sphere, y
// the cosine of incidence there, -n.u = root / R (0 at the limb). At and above the limb d = s and
// the distance is the limb's, c / ((R + H) s) = sqrt(c). root <= R (B^2 - c = R^2 - (R + H)^2
// (1 - d^2)); rounding is clamped.
vec2 sea_distance(vec3 u) {
    float H = frame.cam_forward.w, R = frame.planet.x, s = frame.planet.y, c = frame.planet.z;
    float rh = R + H;
    float d = max(-u.z, s);
    float root = rh * sqrt(max((d - s) * (d + s), 0.0));
    return vec2(c / (rh * d + root), min(root / R, 1.0));
}

// sqrt(R^2 - |x|^2) as sqrt((R - |x|)(R + |x|)): the sphere's height above its centre's level at
// horizontal offset x from the point below the eye, without the cancellation of R^2 - |x|^2.
float sphere_root(vec2 x) {
    float R = frame.planet.x, len = length(x);
    return sqrt(max((R - len) * (R + len), 0.0));
}

// The sphere's depth below the tangent plane at horizontal offset |x| from the point below the
// eye: R - sqrt(R^2 - |x|^2) = |x|^2 / (R + sqrt((R - |x|)(R + |x|))), with no cancellation. A
// visible point is within the limb's cap (|x| < R), where the root is real; rounding is clamped.
float sphere_drop(vec2 x) {
    return dot(x, x) / (frame.planet.x + sphere_root(x));
}

// The rest point (eye-relative) of the sea at rest position x, and the sphere's outward normal
// there: (x, sqrt(R^2 - |x|^2)) / R.
vec3 sea_point(vec2 x) {
    return vec3(x, -frame.cam_forward.w - sphere_drop(x));
}

vec3 sea_normal(vec2 x) {
    return normalize(vec3(x, sphere_root(x)));
}

// The sea's rest position seen along any ray (at the limb for a ray at or above it).
vec2 mean_sea_point(vec3 ray) {
    vec3 u = onto_sea(normalize(ray));
    return sea_distance(u).x * u.xy;
}

// v, given in the frame of the point below the eye (z up), in the frame whose z is `up` (a unit
// vector with up.z > 0, the sphere's normal on the visible cap): the rotation about z x up that
// takes z to up, as Rodrigues' formula with its 1 / (1 + up.z) >= 1/2 bounded.
vec3 tilt_to(vec3 v, vec3 up) {
    float k = 1.0 / (1.0 + up.z);
    float a = up.x, b = up.y;
    vec3 tx = vec3(1.0 - a * a * k, -a * b * k, -a);
    vec3 ty = vec3(-a * b * k, 1.0 - b * b * k, -b);
    return v.x * tx + v.y * ty + v.z * up;
}

// A pixel's share below the limb: the smooth function g = -r.z / |r| (the ray's depression's sine)
// exceeds s = sin(dip) there, and across one pixel g is linear to first order, so the share is
// the box pixel's area where g > s: the ramp of (g - s) over |dg/du| + |dg/dv| per pixel. With
// no gradient (the centre of a view straight down or up) all or nothing.
float below_limb_share(vec3 ray) {
    vec3 dr_u = frame.cam_right.xyz * (2.0 * frame.viewport.z);
    vec3 dr_v = frame.cam_down.xyz * (2.0 * frame.viewport.w);
    float len2 = dot(ray, ray), len = sqrt(len2);
    float g = -ray.z / len;
    // d(-r.z / |r|) = (-dr.z + (r.z / |r|^2) (r . dr)) / |r|
    float g_u = (-dr_u.z + ray.z * dot(ray, dr_u) / len2) / len;
    float g_v = (-dr_v.z + ray.z * dot(ray, dr_v) / len2) / len;
    float width = abs(g_u) + abs(g_v);
    float excess = g - frame.planet.y;
    return width > 0.0 ? clamp(0.5 + excess / width, 0.0, 1.0) : (excess > 0.0 ? 1.0 : 0.0);
}

#endif
