// The sea's own masking of the reflected sun beyond Smith's (src/model/masking.rs,
// GlintMaskingTable; docs/results.md, "The sun's masking"). Smith's masking takes a facet's
// visibility as independent of its slope. At grazing view it is not: the sea's slope is shared
// by every octave of its trains, its height belongs to the longest, so a level facet is seen and
// lit only near a long wave's crest. The table holds, per depression of the view, the share of
// the facets that mirror the eye into the sun both seen and lit on the sea's exact profiles over
// Smith's height-correlated share, measured in the sun's vertical plane with the eye looking
// towards the sun (configuration 0) and away from it (1).
// Requires frame.glsl, slopes.glsl and WAVES_BLOCK (its glint_masking and visible_facets) in scope.
#ifndef MASKING_GLSL
#define MASKING_GLSL

// model::masking's GLINT_* constants.
const int GLINT_DEPRESSIONS = 32;
const float GLINT_DEPRESSION_MAX = 30.0 * PI / 180.0;

float glint_masking_at(int configuration, int depression) {
    int i = configuration * GLINT_DEPRESSIONS + depression;
    return glint_masking[i >> 2][i & 3];
}

// Where a depression falls among the tables' nodes, spaced linearly in sqrt(depression / max):
// the node below it in j (clamped to the domain), the fraction towards the next returned
// (model::masking::depression_node).
float masking_node(float depression, out int j) {
    float u = sqrt(clamp(depression / GLINT_DEPRESSION_MAX, 0.0, 1.0)) * float(GLINT_DEPRESSIONS - 1);
    j = min(int(u), GLINT_DEPRESSIONS - 2);
    return u - float(j);
}

float glint_masking_lookup(int configuration, float depression) {
    int j;
    float f = masking_node(depression, j);
    return mix(glint_masking_at(configuration, j), glint_masking_at(configuration, j + 1), f);
}

// The view in the sea's own frame (z up, x along the wind), which both tables are read in: the
// frame, unit v towards the eye in it, the view's depression, and how much steeper than its
// trains the sea is along the view where the pixel lies: >= 1, sqrt((trains' + packets') /
// trains' slope variance along the view's azimuth), both whole, resolved or not (the table the
// visible facets are corrected by was measured on every slope of the trains); 1 without trains
// (the table is then the model's own) or packets. `packets_sigma2`: the packets' whole slope
// variance there (wind frame; packets.glsl packet_slope_variance).
struct SeaView { Frame3 sea; vec3 v; float depression; float steeper; };

SeaView sea_view(vec3 v, vec3 up, vec2 packets_sigma2) {
    Frame3 sea = wind_frame(up);
    vec3 vs = to_local(sea, v);
    // Only where packets reach (a branch most SIMD groups take together, or none of them).
    float steeper = 1.0;
    if (packets_sigma2.x + packets_sigma2.y > 0.0) {
        float horizontal2 = dot(vs.xy, vs.xy);
        vec2 axes = horizontal2 > 0.0 ? vs.xy * vs.xy / horizontal2 : vec2(0.5);
        float trains = dot(frame.wind.zw, axes);
        if (trains > 0.0) steeper = sqrt(1.0 + dot(packets_sigma2, axes) / trains);
    }
    return SeaView(sea, vs, asin(clamp(vs.z, 0.0, 1.0)), steeper);
}

// 1 / (1 + Lambda_v + Lambda_l) for unit directions v and l in a frame with z up and Gaussian
// slopes of variance sigma2 (the wind's axes), as glsl/brdf.glsl's sun term forms it: multiplied
// through by v_z l_z, so a direction on the horizon gives its limit 0 instead of dividing by 0.
float smith_shadowing(vec3 v, vec3 l, vec2 sigma2) {
    float cv = max(v.z, 0.0), cl = max(l.z, 0.0);
    float denom = cv * cl + cl * cos_times_lambda(cv, slope_spread(v, sigma2))
                + cv * cos_times_lambda(cl, slope_spread(l, sigma2));
    return denom > 0.0 ? cv * cl / denom : 0.0;
}

// The factor that takes the sun term's masking from Smith's over the pixel's unresolved slopes
// (inside reflect_sun) to the sea's own over all of its slopes: the table's exact-over-Smith at
// the view's depression (out of the sun's plane, its mirror facets' value in it), times Smith's
// over the whole sea's slopes over Smith's over the unresolved ones, both about the sea's mean
// plane. Where the per-pixel normals resolve long trains, their slopes are then shadowed too,
// statistically (the trains the grid displaces included: without the shadow map nothing else
// shadows them; with it they are shadowed twice). l: unit direction to the sun;
// sigma2_unresolved: the BRDF's slopes.
float sea_masking(SeaView view, vec3 l, vec2 sigma2_unresolved) {
    vec3 vs = view.v, ls = to_local(view.sea, l);
    if (vs.z <= 0.0 || ls.z <= 0.0) return 1.0;   // reflect_sun's own limit applies
    float unresolved = smith_shadowing(vs, ls, sigma2_unresolved);
    float whole = smith_shadowing(vs, ls, frame.wind.zw);
    // whole <= unresolved: the whole sea's slopes hold the unresolved ones.
    float smith_ratio = unresolved > 0.0 ? min(whole / unresolved, 1.0) : 1.0;
    // The configuration by the view's azimuth against the sun's: the eye looks along -v.
    float horizontal = length(vs.xy), sun_horizontal = length(ls.xy);
    float towards_sun = horizontal > 0.0 && sun_horizontal > 0.0
                      ? 0.5 * (1.0 - dot(vs.xy / horizontal, ls.xy / sun_horizontal)) : 0.5;
    float exact_over_smith =
        mix(glint_masking_lookup(1, view.depression), glint_masking_lookup(0, view.depression), towards_sun);
    return smith_ratio * max(exact_over_smith, 0.0);
}

// The facets the eye sees against the model's (model::masking::VisibleFacetTable) for the view:
// x, their further lean towards the eye (slope); y, their mean Fresnel over the model's. Each
// configuration at the view's depression, blended by cos^2 of the view's azimuth from the wind
// (the share of the slope variance along the view that the wind's axis holds). On a sea s =
// view.steeper times as steep as its trains, read at the depression atan(tan(e) / s) and the lean
// scaled by s: the trains' sea with its heights scaled by s hides from depression e the facets it
// hides unscaled from that one, and the Fresnel ratio's departure from 1 with the lean
// (VisibleFacetTable::lookup_steeper is its twin). atan(tan(e) / s) is taken as e / s: within 1%
// of it below 10 degrees, where the table departs from the model's, and from 20 degrees on the
// table is the model's own (lean 0, ratio 1) at either.
vec2 visible_facet_correction(SeaView view) {
    vec3 vs = view.v;
    float horizontal2 = dot(vs.xy, vs.xy);
    float along = horizontal2 > 0.0 ? vs.x * vs.x / horizontal2 : 0.5;
    int j;
    float f = masking_node(view.depression / view.steeper, j);
    vec4 node = mix(visible_facets[j], visible_facets[j + 1], f);
    // The Fresnel ratio's departure from 1 is first order in the further lean: scaled with it.
    return vec2(view.steeper * mix(node.y, node.x, along), max(1.0 - view.steeper * (1.0 - mix(node.w, node.z, along)), 0.0));
}

#endif
