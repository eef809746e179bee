#version 450
// Projected grid: one vertex per grid node, generated from gl_VertexIndex. Rows start at the limb's
// highest point on screen (frame::GridLayout) and run down past the bottom edge; every node's ray
// meets the sea's mean sphere (glsl/planet.glsl), and a node whose ray passes above the limb is
// moved down onto it in its azimuth, so the grid's edge runs along the limb and never gaps there.
#include "frame.glsl"
#include "common.glsl"
WAVES_BLOCK;
#include "waves.glsl"
#include "packets.glsl"

// Whether any train can be resolved by the grid in this view (specialization constant 4).
layout(constant_id = 4) const bool GEOMETRY = true;
// Whether this is the sun's view of the grid (the shadow pass, src/render/passes/shadow.rs).
layout(constant_id = 10) const bool SUN_VIEW = false;

// x, y: the rest position (horizontal offset from the eye, m); z: 1 where the node is displaced,
// so that a fragment between undisplaced nodes only (z = 0) takes its own ray's exact rest point.
layout(location = 0) out vec3 out_rest;

void main() {
    uint cols = frame.grid_dims.x;
    uint col = uint(gl_VertexIndex) % cols;
    uint row = uint(gl_VertexIndex) / cols;
    float cell_px = frame.grid.x;
    float margin_x = frame.grid.z, margin_y = frame.grid.w;
    float ndc_x = mix(-1.0 - margin_x, 1.0 + margin_x, float(col) / float(cols - 1u));
    float ndc_y = min(frame.grid.y + float(row) * cell_px * 2.0 * frame.viewport.w, 1.0 + margin_y);
    vec3 ray = camera_ray(vec2(ndc_x, ndc_y));
    vec3 u = onto_sea(normalize(ray));
    vec3 rest = sea_distance(u).x * u;

    vec3 d = vec3(0.0);
    SampleScale cell = sample_scale(ray, cell_px, frame.filter_steps.xy);
    bool displaced = GEOMETRY && cell.any;
    if (displaced) d = displacement(rest.xy, cell, frame.filter_steps.xy) + packets_displacement(rest.xy, cell, frame.filter_steps.xy);
    gl_Position = (SUN_VIEW ? frame.sun_view_proj : frame.view_proj) * vec4(rest + d, 1.0);
    out_rest = vec3(rest.xy, displaced ? 1.0 : 0.0);
}
