// The paper's BRDF terms: reflected sun (Gaussian slopes, Smith shadowing, Schlick Fresnel),
// reflected sky (filtered environment lookup and mean Fresnel), refracted sea light.
// Requires the MeanFresnel block of slopes.glsl bound (resources::MEAN_FRESNEL_BINDING).
// Requires frame.glsl, common.glsl, sky.glsl, a `sky_map` sampler and the TERM_* specialization
// constants in scope. METHOD_FULL departs from the paper in three places (docs/results.md
// measures each): the sky lookup is centred on the slopes of the facets actually seen,
// reflections below the horizon meet the sea (the sky map's outer region) instead of a mirrored
// sky, and the Fresnel is the exact one (averaged over the visible slopes) instead of Schlick's
// and the paper's fit of it.
#ifndef BRDF_GLSL
#define BRDF_GLSL

#include "slopes.glsl"
#include "glints.glsl"

// Local frame at a pixel: n the resolved normal, t_x/t_y the wind axes in its tangent plane.
struct Frame3 { vec3 t_x; vec3 t_y; vec3 n; };

Frame3 wind_frame(vec3 n) {
    vec3 wind = vec3(frame.wind.xy, 0.0);
    vec3 t = wind - n * dot(n, wind);
    float len = length(t);
    // |t| = sin(angle(n, wind)); n has positive z for a non-looping surface, so |t| >= n.z > 0.
    // Should a normal ever lie along the wind, fall back to the horizontal axis across it.
    vec3 t_x = len > 0.0 ? t / len : normalize(cross(vec3(-frame.wind.y, frame.wind.x, 0.0), n));
    return Frame3(t_x, cross(n, t_x), n);
}

vec3 to_local(Frame3 f, vec3 d) { return vec3(dot(d, f.t_x), dot(d, f.t_y), dot(d, f.n)); }

// The light a sea point is under: the sun's irradiance normal to it, the sky's on the level sea,
// and the scale of the sky map's radiance there (1 under the sun the map was made for).
struct SeaLight { vec3 sun; vec3 sky_irradiance; vec3 sky_scale; };

// The frame's light: the sea's below the eye, everywhere.
SeaLight frame_sea_light() {
    return SeaLight(frame.sun_irradiance.rgb, frame.sky_irradiance.rgb, vec3(1.0));
}

// The sun reflected towards v under the sun's irradiance `sun` (normal to it). sigma2: slope
// variance for shadowing; sigma2_sun adds the sun disc's own slope spread (the Gaussian convolved
// with the disc) to the slope density. radiance = sun F share_per_sr: share_per_sr (times the
// disc's solid angle) is the share of the pixel's visible facets that mirror the eye into the
// disc, p(zeta_h) G / (4 h_z^4 cos_v) (G Smith's); glints_per_curvature = 4 share_per_sr h_z^4 =
// p(zeta_h) G / cos_v is the lit specular points per unit of E|det H| per m^2 of the footprint
// seen end-on (its area times cos_v on the resolved facet's plane, the same on any plane: the
// count stays finite where the resolved facet turns edge-on, cos_v -> 0; glints.glsl).
struct SunReflection {
    vec3 radiance;
    float share_per_sr;
    float glints_per_curvature;
};

SunReflection reflect_sun(Frame3 f, vec3 v, vec3 l, vec2 sigma2, vec3 sun) {
    SunReflection none = SunReflection(vec3(0.0), 0.0, 0.0);
    vec3 vl = to_local(f, v), ll = to_local(f, l);
    float cv = max(vl.z, 0.0), cl = ll.z;
    if (cl <= 0.0) return none;                   // sun below the tangent plane
    vec3 h = vl + ll;                             // h.z = cv + cl > 0, so |h| > 0
    h = normalize(h);
    float hz2 = h.z * h.z;
    vec2 s2 = sigma2 + vec2(frame.sun_radiance.w);
    float q = h.x * h.x / s2.x + h.y * h.y / s2.y;
    if (q >= 2.0 * EXP_UNDERFLOW * hz2) return none;   // p(zeta_h) / h_z^4 below FLT_MIN
    float p_over_hz4 = exp(-0.5 * q / hz2) / (2.0 * PI * sqrt(s2.x * s2.y) * hz2 * hz2);
    // The facets' Fresnel at the half vector: Schlick's as the paper, exact for METHOD_FULL
    // (Schlick is 8-14% high for cos 0.17-0.3, the sun ahead and the view grazing).
    float fresnel = METHOD == METHOD_FULL ? fresnel_exact(dot(vl, h))
                  : FRESNEL_R0 + (1.0 - FRESNEL_R0) * pow(clamp(1.0 - dot(vl, h), 0.0, 1.0), 5.0);
    // 1 / (cos_v (1 + Lambda_v + Lambda_l)), multiplied through by cos_l so cos_v = 0 stays finite.
    float denom = cv * cl + cl * cos_times_lambda(cv, slope_spread(vl, sigma2))
                + cv * cos_times_lambda(cl, slope_spread(ll, sigma2));
    if (denom <= 0.0) return none;
    float share = p_over_hz4 * cl / (4.0 * denom);
    return SunReflection(sun * (fresnel * share), share, 4.0 * share * hz2 * hz2);
}

vec3 reflected_sun(Frame3 f, vec3 v, vec3 l, vec2 sigma2, vec3 sun) {
    return reflect_sun(f, v, l, sigma2, sun).radiance;
}

// The mirror direction of v about the facet of slopes zeta (in the wind frame f).
vec3 reflected_dir(Frame3 f, vec3 v, vec2 zeta) {
    return reflect(-v, normalize(-zeta.x * f.t_x - zeta.y * f.t_y + f.n));
}

// Unit direction r in the sky map's u: the paper folds directions below the horizon onto their
// mirror image; METHOD_FULL keeps the whole plane, where they lie beyond the unit circle and read
// the sea they meet (glsl/sky_map.glsl).
vec2 sky_u(vec3 r) {
    return METHOD == METHOD_FULL ? stereographic_plane(r) : stereographic(r);
}

// Reflected direction of v about the facet with slope zeta (local frame), in the sky map's u.
vec2 reflected_u(Frame3 f, vec3 v, vec2 zeta) {
    return sky_u(reflected_dir(f, v, zeta));
}

// Average sky radiance over the slope distribution: textureGrad lookups whose footprint is the
// image of the 2-sigma slope ellipse (paper, algorithm 5.1; derivatives by finite differences
// along its axes). `slopes` is the ellipse: the Gaussian's, centred on the mirror direction (the
// paper), or for METHOD_FULL the visible facets' (slopes.glsl) moved by the lean (sea_radiance
// forms it once, for this lookup and the reflection cone). rgb: the reflected sky; a: the share
// of the reflections that meet the sea again and enter it there (0 for the paper, whose map holds
// none).
//
// A mipmap lookup filters isotropically over the footprint's longer axis. At grazing view the
// ellipse's image is long in elevation and narrow in azimuth (along-view slopes turn the
// reflection by twice their angle, across-view ones by 2 cos(theta_v) of it), so one lookup
// also averages the sky over azimuths no slope reaches: with the sun ahead, 5-9% of the sky's
// energy below the integral it stands for (docs/results.md). METHOD_FULL takes two lookups at
// -+ sqrt(1 - s^2) of the longer axis, each reflected exactly and filtered over the share
// s = max(shorter / longer, 1/2) of it: the pair keeps the footprint's mean and variance, and
// each lookup's isotropic blur is at most twice the shorter axis. Towards a round footprint
// s -> 1 and the pair meets at the centre: the one lookup, with no seam between the two.
const float SKY_TAP_SHARE_MIN = 0.5;

vec4 sky_map_grad(vec2 u, vec2 du_x, vec2 du_y) {
    float to_uv = 0.5 / frame.tone.y;
    return textureGrad(sky_map, sky_map_uv(u), du_x * to_uv, du_y * to_uv);
}

vec4 mean_sky_radiance(Frame3 f, vec3 v, VisibleSlopes slopes) {
    const float eps = 1e-3;
    vec2 u0 = reflected_u(f, v, slopes.mean);
    // u's derivative along each axis's direction, times twice its length (0 for a zero axis).
    float len_a = length(slopes.axis_along), len_b = length(slopes.axis_across);
    vec2 dir_a = len_a > 0.0 ? slopes.axis_along / len_a : vec2(0.0);
    vec2 dir_b = len_b > 0.0 ? slopes.axis_across / len_b : vec2(0.0);
    vec2 dx = (reflected_u(f, v, slopes.mean + eps * dir_a) - u0) * (2.0 * len_a / eps);
    vec2 dy = (reflected_u(f, v, slopes.mean + eps * dir_b) - u0) * (2.0 * len_b / eps);
    if (METHOD != METHOD_FULL) return vec4(sky_map_grad(u0, dx, dy).rgb, 0.0);
    // The longer image axis: its slope axis and gradient; the shorter one's gradient.
    bool a_longer = dot(dx, dx) >= dot(dy, dy);
    vec2 axis = a_longer ? slopes.axis_along : slopes.axis_across;
    vec2 major = a_longer ? dx : dy, minor = a_longer ? dy : dx;
    float len_major = length(major), len_minor = length(minor);
    // len_minor <= len_major, so the share is in [1/2, 1]; a zero footprint (a glassy sea) is round.
    float share = len_major > 0.0 ? max(len_minor / len_major, SKY_TAP_SHARE_MIN) : 1.0;
    if (share >= 1.0) return sky_map_grad(u0, major, minor);
    float offset = sqrt(1.0 - share * share);
    vec2 g_major = major * share;
    vec4 high = sky_map_grad(reflected_u(f, v, slopes.mean + offset * axis), g_major, minor);
    vec4 low = sky_map_grad(reflected_u(f, v, slopes.mean - offset * axis), g_major, minor);
    return 0.5 * (high + low);
}

#include "masking.glsl"

// Everything the sea sends towards v at one pixel, under `light`. sun_visible: the share of the
// sun that the displaced grid leaves the point (its shadow map); the unresolved slopes' own
// shadowing is Smith's, inside reflected_sun, over the slopes the grid does not hold; for
// METHOD_FULL corrected to the sea's own over all its slopes (masking.glsl), about up, the
// sea's normal. glint: where the reflected sun's glints are drawn from (glints.glsl; unused
// without GLINTS).
#ifdef HAS_LOCAL_REFLECTIONS
// Lookups at most along a reflection cone's longer axis (ReflectionCone).
const int CONE_TAPS_MAX = 8;

// The reflected directions of a pixel's unresolved slopes, over the footprint the sky lookup
// filters (mean_sky_radiance's: the same mean, axes and variance; the stereographic map is
// conformal, so the same axis is the longer in directions and in the map): r the mirror
// direction of the slopes' centre, which a ray traces; `count` lookups along the longer axis,
// taps[0 .. count), each read blurred isotropically over `blur` radians; `extent` the whole
// footprint's 2-sigma image along its longer axis, as the sky's gradients are.
//
// The sky's pair of lookups suits a sky that varies smoothly; an object's edge does not: a pier
// whose image lies between the pair's taps would be missed, though a tenth of the slopes see it.
// So n taps, spaced d apart at (i - (n - 1) / 2) d, each blurred over a texel of 2 s of the
// longer axis's sigma (a lookup's variance is the sky's (t / 2)^2 for a texel t): together the
// footprint's variance, d^2 (n^2 - 1) / 12 + s^2 = 1, and tiled without gaps where d = 2 s,
// s^2 = 3 / (n^2 + 2). The fewest taps whose s reaches down to the shorter axis (s >= minor /
// major, the blur covering the footprint across): one for a round footprint, two (the sky's
// pair) down to 0.71, three to 0.52, four to 0.41, ..., eight below 0.24 (there s = 0.21 blurs
// wider than the shorter axis). At grazing view the footprint is ten times longer than wide: four
// taps blurred a pier's piles across four times their width, and their reflection's depth with
// it (docs/bench/objects.md).
//
// The taps are evenly spaced; each stands for the slopes nearer to it than to its neighbours
// (`spacing` d in the longer axis's sigmas, slopes.glsl tap_mass), not an equal part of them.
// Each tap's direction is formed where it is read (cone_tap_dir), one at a time: no array of them
// is built or copied.
struct ReflectionCone {
    vec3 r;
    // What forms tap i's direction: the slopes' frame, the view, the centre and the longer axis.
    Frame3 f;
    vec3 v;
    vec2 mean;
    vec2 axis;
    int count;
    float spacing;
    float blur;
    float extent;
};

ReflectionCone reflection_cone(Frame3 f, vec3 v, VisibleSlopes slopes) {
    const float eps = 1e-3;
    ReflectionCone cone;
    cone.r = reflected_dir(f, v, slopes.mean);
    float len_a = length(slopes.axis_along), len_b = length(slopes.axis_across);
    vec2 dir_a = len_a > 0.0 ? slopes.axis_along / len_a : vec2(0.0);
    vec2 dir_b = len_b > 0.0 ? slopes.axis_across / len_b : vec2(0.0);
    // Each 1-sigma axis's image in radians (a chord eps long is its arc to 1e-7).
    float angle_a = length(reflected_dir(f, v, slopes.mean + eps * dir_a) - cone.r) * (len_a / eps);
    float angle_b = length(reflected_dir(f, v, slopes.mean + eps * dir_b) - cone.r) * (len_b / eps);
    float major = max(angle_a, angle_b), minor = min(angle_a, angle_b);
    // minor <= major: the ratio is in [0, 1], 1 for a glassy sea's zero footprint.
    float ratio = major > 0.0 ? minor / major : 1.0;
    int count = clamp(int(ceil(sqrt(max(3.0 / max(ratio * ratio, 1e-6) - 2.0, 1.0)) - 1e-4)), 1, CONE_TAPS_MAX);
    float share = max(ratio, sqrt(3.0 / float(count * count + 2)));
    // n = 1: s = 1, the one lookup carries the whole variance.
    cone.spacing = count > 1 ? sqrt(12.0 * max(1.0 - share * share, 0.0) / float(count * count - 1)) : 0.0;
    cone.f = f;
    cone.v = v;
    cone.mean = slopes.mean;
    cone.axis = angle_a >= angle_b ? slopes.axis_along : slopes.axis_across;
    cone.count = count;
    cone.blur = 2.0 * share * major;
    cone.extent = 2.0 * major;
    return cone;
}

// Tap i's direction (i < cone.count), at (i - (count - 1) / 2) spacing sigmas along the axis.
vec3 cone_tap_dir(ReflectionCone cone, int i) {
    float at = (float(i) - 0.5 * float(cone.count - 1)) * cone.spacing;
    return reflected_dir(cone.f, cone.v, cone.mean + at * cone.axis);
}

// The sky a cone's reflection shows where no object stands: the sky map's mean radiance over the
// footprint, `mean` (scaled by `scale`, SeaLight's sky_scale), and what a tap hides of it.
struct ConeSky { vec3 mean; vec3 scale; };

vec4 local_reflection(vec3 point, ReflectionCone cone, ConeSky sky);
bool mirror_start(vec3 point, vec3 up, out MirrorStart start);
vec4 planar_reflection(MirrorStart start, ReflectionCone cone, vec3 up, ConeSky sky);

// The change the objects a cone's taps see make to the reflected sky's mean radiance (before the
// mean Fresnel), summed tap by tap as they are read (shade.glsl cone_change): each tap's objects in
// place of the sky it hides, weighted by its share of the slopes (tap_mass, slopes.glsl) and by
// the Fresnel of the facets that mirror v into it, over the taps' mean. A cone's reflections at
// grazing view span incidences whose Fresnel differs threefold (its rays near the horizon mirror
// most), and the sky they hide is not the whole footprint's mean (the horizon's is brighter): a
// pier's piles, met by the low rays, darken the sea more than their share of the footprint, a
// deck's underside, met by the steep ones, less. The sky a tap hides is the sky map's in the
// tap's own direction, filtered over the tap's blur (the stereographic map's scale is
// 1 / (1 + z), so `blur` radians are blur / (1 + z) of the map), read only for the taps that meet
// an object. The sky lookup's pair, interpolated along the footprint, held the outer taps at the
// pair's own elevation: the horizon's bright sky, which the lowest taps hide, was a third too
// dim. One lookup for the whole cone (a footprint of a few pixels) replaces the mean sky by its
// objects, unweighted.
struct ConeSum { vec3 weighted; vec3 by_mass; float weight; bool held; };

ConeSum no_cone_sum() {
    return ConeSum(vec3(0.0), vec3(0.0), 0.0, false);
}

// Adds tap i (direction d) seeing `tap` (rgb premultiplied by its coverage a) to `sum`.
void add_tap(inout ConeSum sum, ReflectionCone cone, int i, vec3 d, vec4 tap, ConeSky sky) {
    float mass = tap_mass(i, cone.count, cone.spacing);
    // v + d is 0 only for a tap turned straight back along the view (a facet seen edge-on),
    // where the Fresnel's limit is 1.
    vec3 h = cone.v + d;
    float len2 = dot(h, h);
    float weight = mass * (len2 > 0.0 ? fresnel_exact(dot(cone.v, h) * inversesqrt(len2)) : 1.0);
    sum.weight += weight;
    // A reflection below the horizon meets the sea (the sky map's waves stop all of it,
    // sky_map.glsl): the mirror image would show it the objects from below the water.
    if (!(tap.a > 0.0) || !(d.z > 0.0)) return;
    sum.held = true;
    float texel = cone.blur / (1.0 + d.z);   // d.z > 0
    vec3 hidden = sky.scale * sky_map_grad(sky_u(d), vec2(texel, 0.0), vec2(0.0, texel)).rgb;
    vec3 change = tap.rgb - tap.a * hidden;
    sum.weighted += weight * change;
    sum.by_mass += mass * change;
}

// The summed taps' change (rgb) and whether any met an object (a). The exact Fresnel is at least
// the normal incidence's ((eta - 1) / (eta + 1))^2 > 0 for water, so the weight is > 0; a medium
// of eta 1 reflects nothing, and the masses alone weigh.
vec4 cone_sum_change(ConeSum sum) {
    return vec4(sum.weight > 0.0 ? sum.weighted / sum.weight : sum.by_mass, sum.held ? 1.0 : 0.0);
}

// One lookup standing for the whole cone: its objects in place of the mean sky, where the centre
// ray is above the horizon.
vec4 one_tap_change(ReflectionCone cone, vec4 tap, ConeSky sky) {
    bool held = tap.a > 0.0;
    vec3 change = cone.r.z > 0.0 ? tap.rgb - tap.a * sky.scale * sky.mean : vec3(0.0);
    return vec4(change, held ? 1.0 : 0.0);
}
#endif

// `packets_sigma2`: the wave packets' whole slope variance where the point lies (0 without them;
// masking.glsl SeaView).
vec3 sea_radiance(vec3 n, vec3 up, vec3 v, vec2 sigma2, vec2 packets_sigma2, float sun_visible, SeaLight light, GlintSite glint, vec3 point) {
    // Back-facing resolved normal (steep waves at grazing view): bend it onto the silhouette,
    // where cos_v = 0 is the formulas' own finite limit.
    float vn = dot(v, n);
    if (vn < 0.0) {
        vec3 bent = n - vn * v;
        float len = length(bent);
        n = len > 0.0 ? bent / len : vec3(0.0, 0.0, 1.0);
    }
    Frame3 f = wind_frame(n);
    vec3 vl = to_local(f, v);
    float cos_v = clamp(vl.z, 0.0, 1.0);
    vec3 color = vec3(0.0);
    // The view in the sea's own frame, which the full method's masking tables are read in.
    SeaView view;
    if (METHOD == METHOD_FULL) view = sea_view(v, up, packets_sigma2);
    if (TERM_SUN && sun_visible > 0.0 && max(light.sun.r, max(light.sun.g, light.sun.b)) > 0.0) {
        SunReflection sun = reflect_sun(f, v, frame.sun_dir.xyz, sigma2, light.sun);
        if (METHOD == METHOD_FULL) {
            float masking = sea_masking(view, frame.sun_dir.xyz, sigma2);
            sun.radiance *= masking;
            sun.share_per_sr *= masking;
            sun.glints_per_curvature *= masking;
        }
        vec3 expected = sun_visible * sun.radiance;
        float peak = max(expected.r, max(expected.g, expected.b));
        float glints = GLINTS && METHOD == METHOD_FULL
                     ? glint_factor(glint, sun.share_per_sr * frame.glints.y, sun.glints_per_curvature, peak) : 1.0;
        color += glints * expected;
    }
    float fresnel = sea_fresnel(cos_v, sqrt(directional_variance(vl, sigma2)));
    // METHOD_FULL: at grazing view the facets the eye sees lean further towards it than their
    // projected area alone makes them, and mirror less (masking.glsl): the sky lookup is centred
    // on their slopes and the Fresnel of the sky and refracted terms is theirs.
    vec2 lean = vec2(0.0);
    if (METHOD == METHOD_FULL) {
        vec2 seen = visible_facet_correction(view);
        float horizontal = length(vl.xy);
        lean = horizontal > 0.0 ? -seen.x * vl.xy / horizontal : vec2(0.0);
        fresnel = min(fresnel * seen.y, 1.0);
    }
    // The refracted term takes the light entering at this facet and, for METHOD_FULL, at the next
    // one where a reflection meets the sea again (a of the lookup), as the ground truth counts it.
    bool looks_up = TERM_SKY || (TERM_SEA && METHOD == METHOD_FULL);
    VisibleSlopes slopes;   // formed wherever the sky is looked up, which TERM_SKY implies
    vec4 sky = vec4(0.0);
    if (looks_up) {
        slopes = METHOD == METHOD_FULL ? visible_slopes(vl, sigma2) : gaussian_slopes(sigma2);
        slopes.mean += lean;
        sky = mean_sky_radiance(f, v, slopes);
    }
    // The host's objects the sky lookup's mirror direction meets stand in front of the sky, over
    // the share of the footprint they cover: read from their mirror images (shade.glsl
    // planar_reflection), and where those hold none, traced in screen space (local_reflection).
    vec3 objects = vec3(0.0);
#ifdef HAS_LOCAL_REFLECTIONS
    MirrorStart start;
    bool mirrored = (LOCAL_REFLECTIONS || PLANAR_REFLECTIONS) && TERM_SKY && mirror_start(point, up, start);
    if ((LOCAL_REFLECTIONS || mirrored) && TERM_SKY) {
        ReflectionCone cone = reflection_cone(f, v, slopes);
        ConeSky cone_sky = ConeSky(sky.rgb, light.sky_scale);
        // The mirror images first: they show an object as the sea sees it. Where they hold
        // none (an object the host does not mirror), the screen's trace.
        vec4 change = mirrored ? planar_reflection(start, cone, up, cone_sky) : vec4(0.0);
        if (LOCAL_REFLECTIONS && change.a == 0.0) change = local_reflection(point, cone, cone_sky);
        objects = change.rgb;
    }
#endif
    // The objects' change is at most the whole sky they hide; where the taps' Fresnel-weighted
    // sky exceeds the mean's, a dark object over all of it could take more: 0 is the limit.
    if (TERM_SKY) color += max(fresnel * (light.sky_scale * sky.rgb + objects), vec3(0.0));
    if (TERM_SEA) color += (1.0 - fresnel * (1.0 - sky.a)) * frame.sea_albedo.rgb * light.sky_irradiance / PI;
    return color;
}

#endif
