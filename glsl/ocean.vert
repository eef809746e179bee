#version 450
// Projected grid: one vertex per grid node, generated from gl_VertexIndex. Rows start on the
// horizon line and run down past the bottom edge; every node's ray meets the mean sea plane at
// t >= 0, the top row at t = infinity, which stays a finite homogeneous point (x H, 0).
#include "frame.glsl"
#include "common.glsl"
WAVES_BLOCK;
#include "waves.glsl"

// Whether any train can be resolved by the grid in this view (specialization constant 4).
layout(constant_id = 4) const bool GEOMETRY = true;
// Whether this is the sun's view of the grid (the shadow pass, src/render/passes/shadow.rs).
layout(constant_id = 10) const bool SUN_VIEW = false;

layout(location = 0) out vec3 out_rest_h;   // (H r.xy, w): rest position = xy / w, interpolated projectively

void main() {
    uint cols = frame.grid_dims.x;
    uint col = uint(gl_VertexIndex) % cols;
    uint row = uint(gl_VertexIndex) / cols;
    float cell_px = frame.grid.x;
    float margin_x = frame.grid.z, margin_y = frame.grid.w;
    float ndc_x = mix(-1.0 - margin_x, 1.0 + margin_x, float(col) / float(cols - 1u));
    float ndc_y = min(frame.grid.y + float(row) * cell_px * 2.0 * frame.viewport.w, 1.0 + margin_y);
    vec3 ray = camera_ray(vec2(ndc_x, ndc_y));
    float w = max(-ray.z, 0.0);
    float height = frame.cam_forward.w;
    vec2 rest_times_w = height * ray.xy;

    vec3 d = vec3(0.0);
    SampleScale cell = sample_scale(ray, cell_px, frame.filter_steps.xy);
    if (GEOMETRY && cell.any) d = displacement(rest_times_w / w, cell, frame.filter_steps.xy);   // any implies w > 0
    vec4 p_h = vec4(rest_times_w + w * d.xy, w * (d.z - height), w);
    gl_Position = (SUN_VIEW ? frame.sun_view_proj : frame.view_proj) * p_h;
    out_rest_h = vec3(rest_times_w, w);
}
