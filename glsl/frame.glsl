// Per-frame uniforms and the wave trains, shared by every pass.
// Mirrors `FrameUniforms` and `GpuWave` in src/render/frame.rs (std140, vec4-packed).
#ifndef FRAME_GLSL
#define FRAME_GLSL

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_proj;        // camera-relative world (z up, metres) -> clip, reversed-Z infinite far
    vec4 cam_right;        // xyz: right * tan(fov_x/2), so ray = fwd + ndc.x*right + ndc.y*down
    vec4 cam_down;         // xyz: -up * tan(fov_y/2) (Vulkan NDC y points down)
    vec4 cam_forward;      // xyz: forward; w: camera height above the mean sea plane (m)
    vec4 viewport;         // width, height, 1/width, 1/height (pixels)
    vec4 grid;             // x: cell size (px), y: horizon ndc y, z: margin ndc x, w: margin ndc y
    uvec4 grid_dims;       // x: columns, y: rows, z: wave count, w: unused
    vec4 filter_steps;     // phase step per sample (turns) where a train is resolved / unresolved: xy geometry, zw normals
    vec4 sun_dir;          // xyz: unit vector towards the sun; w: cos(angular radius)
    vec4 sun_radiance;     // rgb: disc radiance (kcd/m^2); w: sun slope variance per axis
    vec4 sun_irradiance;   // rgb: irradiance normal to the sun (klux); w: 1 if above horizon
    vec4 sky_irradiance;   // rgb: horizontal-plane irradiance from the sky (klux)
    vec4 sea_albedo;       // rgb: deep-water colour factor for the refracted term
    vec4 wind;             // xy: unit wind direction; zw: total slope variance (wind frame)
    vec4 perez_a;          // Preetham Perez coefficients for (Y, x, y)
    vec4 perez_b;
    vec4 perez_c;
    vec4 perez_d;
    vec4 perez_e;
    vec4 sky_zenith;       // (Y, x, y) zenith values, Y already divided by F(0, theta_s); w: sky scale
    vec4 tone;             // x: exposure; y: sky map extent R (map spans [-R, R]^2 in stereographic u)
    vec4 wave_extent;      // x: longest wavelength (m); y: summed amplitude, the highest crest (m)
    vec4 baseline_sigma2;  // xy: the constant-BRDF baseline's slope variance (wind frame)
    // The physical sky (glsl/atmosphere.glsl): [0] bottom and top radius, Rayleigh and Mie scale
    // heights (m); [1] Rayleigh scattering (rgb, per m), Mie g; [2] ozone absorption at its peak
    // (rgb), Mie scattering; [3] ozone centre and width (m), Mie absorption, ground albedo;
    // [4] the sun's illuminance outside the atmosphere (klux), the sun disc's chord^2
    // (2 (1 - cos radius)), the eye's altitude (m), unused.
    vec4 atmosphere[5];
    mat4 sun_view_proj;    // camera-relative world -> the sun's shadow map (src/render/sun_shadow.rs): z 0 nearest the sun
    vec4 shadow;           // x: the camera's near plane (m); y: 1 if the sun's view exists this frame
    vec4 planet;           // the sea's sphere (glsl/planet.glsl): R (m), sin(dip), c = H (2R + H) (m^2), sqrt(c) (m)
    vec4 eye_sky;          // the eye's sky-view table's elevations (glsl/sky_view.glsl): x lowest, y highest (rad)
    vec4 sea_light[3];     // the sea-level light table's calibration below the eye (frame::sea_light_calibration):
                           // rgb sun, rgb sky irradiance, rgb 1 / the table's sky irradiance
    vec4 glints;           // x: the scene's time (s) modulo frame::GLINT_TIME_PERIOD_S; y: the sun disc's solid angle (sr)
    mat4 host_clip;        // camera-relative world -> a host's clip space (embed::Ocean; glsl/composite.frag)
    vec4 host;             // x: radiance scale to the host's unit; y: the host colour format's largest value;
                           // z: the host's far-plane depth (0 reversed Z, 1 standard); w: unused
    vec4 packet_grid;      // the wave packets' cells (glsl/packets.glsl): xy the corner of cell (0, 0) in
                           // the cells' plane, zw a cell's sides
    vec4 packet_map;       // rest positions to that plane (grid::CellMap): xy the perspective's forward,
                           // z its offset behind the eye (m; 0: the rest plane itself)
    uvec4 packet_dims;     // x, y: columns and rows of cells; z: packets; w: tiles
} frame;

// Whether the full method draws the reflected sun's glints (glsl/glints.glsl) instead of its
// expected value, and its train loop sums the unresolved curvature they need.
layout(constant_id = 13) const bool GLINTS = false;

// The wave trains, sorted by increasing wavelength. Two words per train keep the per-pixel loop
// to two reads (drivers that cannot prove a loop index uniform, lavapipe among them, gather
// every word per lane, and those gathers are a third of the loop's cost):
//   x:  wave vector in turns per metre (direction / wavelength) as two binary16 halves, exact:
//       the model snaps every train's wave vector to such values (waves::binary16_wave_vector),
//       so the phase k.x is as precise as f32 allows
//   y:  phase at time t in turns, reduced to [0, 1) in f64 on the CPU, as 16-bit fixed point
//       (1.5e-5 turns), in the low half; k h in [0, 1] as unorm16 in the high half
//   zw: unused (std140 strides arrays by 16 bytes anyway)
// prefix[i].xy: slope variance (wind frame) of train i and all shorter ones; z: their curvature
// power (1/m^2, glsl/glints.glsl); w: unused.
const uint MAX_WAVES = 256u;
// glint_masking: the sun's masking on the sea's own profiles over Smith's (glsl/masking.glsl).
const int GLINT_MASKING_VEC4S = 16;   // frame::GLINT_MASKING_VEC4S
// visible_facets[j]: at the masking tables' depression j, the facets the eye sees over the
// model's (model::masking::VisibleFacetTable): x, y their further lean looking along and across
// the wind; z, w their Fresnel ratio the same (glsl/masking.glsl).
const int VISIBLE_FACET_NODES = 32;   // model::masking::GLINT_DEPRESSIONS
#define WAVES_BLOCK layout(set = 0, binding = 1, std140) uniform Waves { uvec4 wave_data[MAX_WAVES]; vec4 wave_prefix[MAX_WAVES]; vec4 glint_masking[GLINT_MASKING_VEC4S]; vec4 visible_facets[VISIBLE_FACET_NODES]; }

struct Wave {
    vec2 k;          // turns per metre
    float phase;     // turns
    float kh;        // steepness k h <= 1
};

Wave unpack_wave(uvec2 d) {
    return Wave(unpackHalf2x16(d.x), float(d.y & 0xffffu) * (1.0 / 65536.0), float(d.y >> 16) * (1.0 / 65535.0));
}

#endif
