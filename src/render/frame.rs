//! What the CPU hands the shaders each frame: the camera, the sun and sky, the projected grid's
//! extent and the wave trains. Layouts mirror glsl/frame.glsl (std140 / std430, vec4-packed).

use crate::model::masking::{GlintMaskingTable, VisibleFacetTable, GLINT_DEPRESSIONS};
use crate::model::scene::{Scene, MAX_WAVES};
use crate::model::sky::SkyModel;
use crate::model::waves::WaveSet;
use glam::{DMat4, DVec2, DVec3, Mat4};

/// Phase step per sample (turns) up to which a train is fully resolved, and from which it is not
/// resolved at all, by the grid (geometry) and by the per-pixel normal.
///
/// The grid: half a turn per vertex is Nyquist's limit, and a mesh displaced that coarsely beats
/// against its vertices (moire, swimming as the camera moves), so a train is displaced fully from 8
/// cells per wavelength and not below 4. (The authors' demo ramps over 1 to 1.5 cells.)
///
/// The normal: a train's weight is what the pixel's box filter keeps of it (glsl/waves.glsl
/// normal_weight, footprint::box_transfer: sinc of its step along each side of the footprint), as
/// the ground truth's pixel keeps it; full below 1/64 turn (the filter's loss under binary16's
/// resolution, 2^-11), none from a whole turn (sinc's first zero). A smoothstep from 1/8 to 1/4
/// turn kept 3-30% of the truth's local contrast (docs/results.md, "The detail a pixel can see").
pub const GEOMETRY_STEPS: [f32; 2] = [0.125, 0.25];
pub const NORMAL_STEPS: [f32; 2] = [1.0 / 64.0, 1.0];
/// The full method's step to where a pixel's ray meets the sea is ramped in from this share of
/// the sea's slope variance in the trains the pixel can resolve to the second (glsl/shade.glsl
/// RAY_HIT_SHARE, the same): below the first it is not taken.
pub const RAY_HIT_SHARE: [f64; 2] = [0.4, 0.6];
/// Stereographic sky-map extent of the full method: u in [-R, R]^2 covers the horizon circle
/// |u| = 1 and directions below it, to 22.6 degrees down along the axes (|u| = tan(45 + 22.6 / 2)
/// = 1.5) and 39.6 in the corners, where its reflections that meet the sea read what they meet.
pub const SKY_MAP_EXTENT: f32 = 1.5;
/// The extent for the paper's folded lookups (and the baselines'): a little beyond the horizon
/// circle, for the footprints that cross it, so that the map's texels go to the sky above it.
pub const SKY_MAP_EXTENT_FOLDED: f32 = 1.125;

/// The sky map's extent for `method`'s lookups.
pub fn sky_map_extent(method: crate::render::passes::ocean::Method) -> f32 {
    match method {
        crate::render::passes::ocean::Method::Full => SKY_MAP_EXTENT,
        _ => SKY_MAP_EXTENT_FOLDED,
    }
}
/// The glints' clock wraps after this many seconds (glsl/glints.glsl: a facet's draws change
/// with time over its lifetime): single precision keeps 0.25 ms at an hour, under a frame.
pub const GLINT_TIME_PERIOD_S: f64 = 3600.0;
/// Deep-water colour of the refracted term: the authors' demo (10, 40, 120) / 255 x 0.1.
pub const SEA_ALBEDO: [f64; 3] = [10.0 / 255.0 * 0.1, 40.0 / 255.0 * 0.1, 120.0 / 255.0 * 0.1];
/// Near plane of the reversed-Z infinite projection (m).
pub const Z_NEAR: f64 = 0.01;
/// Largest grid margin past each screen edge, in NDC units (a full screen half-width).
pub const MAX_MARGIN_NDC: f64 = 1.0;

#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub cam_right: [f32; 4],
    pub cam_down: [f32; 4],
    pub cam_forward: [f32; 4],
    pub viewport: [f32; 4],
    pub grid: [f32; 4],
    pub grid_dims: [u32; 4],
    pub filter_steps: [f32; 4],
    pub sun_dir: [f32; 4],
    pub sun_radiance: [f32; 4],
    pub sun_irradiance: [f32; 4],
    pub sky_irradiance: [f32; 4],
    pub sea_albedo: [f32; 4],
    pub wind: [f32; 4],
    pub perez: [[f32; 4]; 5],
    pub sky_zenith: [f32; 4],
    pub tone: [f32; 4],
    pub wave_extent: [f32; 4],
    pub baseline_sigma2: [f32; 4],
    pub atmosphere: [[f32; 4]; 5],
    pub sun_view_proj: [[f32; 4]; 4],
    pub shadow: [f32; 4],
    pub planet: [f32; 4],
    pub eye_sky: [f32; 4],
    pub sea_light: [[f32; 4]; 3],
    pub glints: [f32; 4],
    /// Camera-relative world to a host's clip space, and the host's radiance scale, colour
    /// format's largest value and far-plane depth (embed::Ocean; zero outside a host's frame).
    pub host_clip: [[f32; 4]; 4],
    pub host: [f32; 4],
    /// The wave packets' cells: the corner of cell (0, 0) in the cells' plane and a cell's sides;
    /// how rest positions map to that plane (grid::CellMap::uniform); their columns, rows, the
    /// packets' count and the tiles' (render::packets).
    pub packet_grid: [f32; 4],
    pub packet_map: [f32; 4],
    pub packet_dims: [u32; 4],
}

/// vec4s of the glint's masking table in the `Waves` block (glsl/masking.glsl).
pub const GLINT_MASKING_VEC4S: usize = 2 * GLINT_DEPRESSIONS / 4;

/// The `Waves` uniform block: one packed vec4 per train, then the variance prefix sums, then the
/// sun's masking on the sea's own profiles over Smith's (model::masking::GlintMaskingTable), then
/// the facets the eye sees there over the model's (model::masking::VisibleFacetTable).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct GpuWaves {
    pub data: [[u32; 4]; MAX_WAVES as usize],
    pub prefix: [[f32; 4]; MAX_WAVES as usize],
    pub glint_masking: [[f32; 4]; GLINT_MASKING_VEC4S],
    pub visible_facets: [[f32; 4]; GLINT_DEPRESSIONS],
}

impl Default for GpuWaves {
    fn default() -> Self {
        GpuWaves {
            data: [[0; 4]; MAX_WAVES as usize],
            prefix: [[0.0; 4]; MAX_WAVES as usize],
            glint_masking: [[1.0; 4]; GLINT_MASKING_VEC4S],
            visible_facets: [[0.0, 0.0, 1.0, 1.0]; GLINT_DEPRESSIONS],
        }
    }
}

impl GpuWaves {
    /// Writes the masking table, four ratios a vec4, in its own order.
    pub fn set_glint_masking(&mut self, table: &GlintMaskingTable) {
        for (i, r) in table.ratio.iter().enumerate() {
            self.glint_masking[i / 4][i % 4] = *r as f32;
        }
    }

    /// Writes the visible facets' table, a vec4 per depression: lean along and across the wind,
    /// then the Fresnel ratio along and across.
    pub fn set_visible_facets(&mut self, table: &VisibleFacetTable) {
        let n = GLINT_DEPRESSIONS;
        for (j, node) in self.visible_facets.iter_mut().enumerate() {
            let [lean, ratio] = [&table.lean, &table.fresnel_ratio];
            *node = [lean[j], lean[n + j], ratio[j], ratio[n + j]].map(|x| x as f32);
        }
    }
}

/// Where a camera ray meets the rest sphere.
#[derive(Clone, Copy, Debug)]
pub struct SeaHit {
    /// The point, eye-relative.
    pub point: DVec3,
    /// point = t ray.
    pub t: f64,
    /// The sphere's outward normal there.
    pub normal: DVec3,
    /// -normal . ray: > 0 below the limb.
    pub w: f64,
}

/// v, given in the frame of the point below the eye (z up), in the frame whose z is the unit
/// vector `up` (up.z > 0): the rotation about z x up taking z to up (glsl/planet.glsl `tilt_to`).
pub fn tilt_to(v: DVec3, up: DVec3) -> DVec3 {
    let k = 1.0 / (1.0 + up.z);
    let tx = DVec3::new(1.0 - up.x * up.x * k, -up.x * up.y * k, -up.x);
    let ty = DVec3::new(-up.x * up.y * k, 1.0 - up.y * up.y * k, -up.y);
    v.x * tx + v.y * ty + v.z * up
}

/// The camera in the camera-relative world frame (origin at the eye, z up).
#[derive(Clone, Copy, Debug)]
pub struct CameraFrame {
    pub forward: DVec3,
    pub right: DVec3,
    pub up: DVec3,
    pub tan_half_x: f64,
    pub tan_half_y: f64,
    /// Height of the eye above the rest sphere the grid is projected on (named for the tangent
    /// plane below the eye, where the waves live).
    pub plane_height: f64,
    /// The planet's radius: the rest sphere's (glsl/planet.glsl).
    pub planet_radius: f64,
    /// Height of the eye above mean sea level: the scene's, raised with the water under the eye
    /// so that it is never closer to that water than the scene asks.
    pub eye_height: f64,
}

impl CameraFrame {
    pub fn new(scene: &Scene, waves: &WaveSet, width: u32, height: u32) -> CameraFrame {
        let (pitch, yaw) = (scene.camera.pitch_deg.to_radians(), scene.camera.yaw_deg.to_radians());
        let forward = DVec3::new(pitch.cos() * yaw.cos(), pitch.cos() * yaw.sin(), pitch.sin());
        let right = DVec3::new(yaw.sin(), -yaw.cos(), 0.0);
        let up = right.cross(forward);
        let tan_half_y = (scene.camera.fov_y_deg.to_radians() / 2.0).tan();
        let tan_half_x = tan_half_y * width as f64 / height as f64;
        // `height_m` is the eye's height above the water: above mean sea level, and above the water
        // under the eye where a crest lifts it (an eye 5 cm above the water is not under a crest).
        let water = waves.water_height_at_origin(scene.render.time_s);
        let eye_height = scene.camera.height_m + water.max(0.0);
        // The trochoids' mean surface lies sum(k h^2 / 2) below their rest plane, so the rest plane
        // sits that much above mean sea level. A projected grid needs the eye above the rest plane:
        // an eye lower than twice the offset keeps half its height.
        let plane_height = (eye_height - waves.mean_height_offset).max(0.5 * eye_height);
        let planet_radius = scene.planet.radius_m;
        CameraFrame { forward, right, up, tan_half_x, tan_half_y, plane_height, eye_height, planet_radius }
    }

    /// H (2R + H): |C|^2 - R^2 as a product, C the sphere's centre seen from the eye.
    pub fn limb_c(&self) -> f64 {
        self.plane_height * (2.0 * self.planet_radius + self.plane_height)
    }

    /// The sine of the limb's dip below level: sqrt(H (2R + H)) / (R + H).
    pub fn dip_sine(&self) -> f64 {
        self.limb_c().sqrt() / (self.planet_radius + self.plane_height)
    }

    /// Where `ray` (any length) meets the rest sphere; None at or above the limb.
    pub fn sea_hit(&self, ray: DVec3) -> Option<SeaHit> {
        let len = ray.length();
        let planet = crate::model::scene::Planet { radius_m: self.planet_radius };
        let distance = planet.ray_distance(self.plane_height, -ray.z / len)?;
        let point = ray * (distance / len);
        let normal = self.sea_normal(point.truncate());
        Some(SeaHit { point, t: distance / len, normal, w: -normal.dot(ray) })
    }

    /// The sphere's outward normal at rest position x (horizontal offset from the eye).
    pub fn sea_normal(&self, x: DVec2) -> DVec3 {
        DVec3::new(x.x, x.y, self.sphere_root(x)).normalize()
    }

    /// sqrt(R^2 - |x|^2) as sqrt((R - |x|)(R + |x|)), without the cancellation (glsl/planet.glsl).
    fn sphere_root(&self, x: DVec2) -> f64 {
        let (r, len) = (self.planet_radius, x.length());
        ((r - len) * (r + len)).max(0.0).sqrt()
    }

    /// The rest point (eye-relative) at rest position x: its height has the sphere's drop
    /// R - sqrt(R^2 - |x|^2), formed without cancellation.
    pub fn sea_point(&self, x: DVec2) -> DVec3 {
        let drop = x.length_squared() / (self.planet_radius + self.sphere_root(x));
        DVec3::new(x.x, x.y, -self.plane_height - drop)
    }

    /// How the rest position of `hit` (on `ray`) moves as the ray moves by `dr`: with the sphere's
    /// constraint n . dP = 0, dx = (t / w) (w dr.xy + r.xy (n . dr)) (glsl/waves.glsl
    /// `sample_scale`, the same formula).
    pub fn rest_derivative(hit: &SeaHit, ray: DVec3, dr: DVec3) -> DVec2 {
        (dr.truncate() * hit.w + ray.truncate() * hit.normal.dot(dr)) * (hit.t / hit.w)
    }

    /// Unnormalized ray through an NDC position (y down), as `camera_ray` in the shaders.
    pub fn ray(&self, ndc: [f64; 2]) -> DVec3 {
        self.forward + ndc[0] * self.tan_half_x * self.right - ndc[1] * self.tan_half_y * self.up
    }

    /// Distance from the eye to where the ray through pixel (px, py) (centre) of a width x height
    /// image meets the rest sphere; None at or above the limb.
    pub fn pixel_distance(&self, px: u32, py: u32, width: u32, height: u32) -> Option<f64> {
        let ndc = [(px as f64 + 0.5) / width as f64 * 2.0 - 1.0, (py as f64 + 0.5) / height as f64 * 2.0 - 1.0];
        self.sea_hit(self.ray(ndc)).map(|hit| hit.point.length())
    }

    pub fn view_proj(&self, aspect: f64) -> DMat4 {
        let view = DMat4::look_to_rh(DVec3::ZERO, self.forward, self.up);
        let proj = DMat4::perspective_infinite_reverse_rh(2.0 * self.tan_half_y.atan(), aspect, Z_NEAR);
        // Vulkan's NDC y points down.
        DMat4::from_diagonal(glam::DVec4::new(1.0, -1.0, 1.0, 1.0)) * proj * view
    }

    /// NDC y of the limb's highest point on screen, or +-inf when it is off to infinity. With no
    /// roll a row's rays fall most at the centre column (|ray| is least there), whose elevation
    /// is pitch - atan(y tan_half_y): the limb, at -dip, is at y = tan(pitch + dip) / tan_half_y.
    pub fn limb_ndc_y(&self) -> f64 {
        let angle = self.forward.z.clamp(-1.0, 1.0).asin() + self.dip_sine().asin();
        if angle >= std::f64::consts::FRAC_PI_2 {
            f64::INFINITY
        } else if angle <= -std::f64::consts::FRAC_PI_2 {
            f64::NEG_INFINITY
        } else {
            angle.tan() / self.tan_half_y
        }
    }
}

/// Extent of the projected grid on screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridLayout {
    pub columns: u32,
    pub rows: u32,
    pub top_ndc_y: f64,
    pub margin_x: f64,
    pub margin_y: f64,
}

impl GridLayout {
    /// The grid runs from the limb's highest point (or the top margin) down past the bottom edge, and past the
    /// side edges, by the screen-space reach of the largest displacement at the nearest visible sea.
    pub fn new(cam: &CameraFrame, waves: &WaveSet, cell_px: f64, width: u32, height: u32) -> GridLayout {
        let reach = std::f64::consts::SQRT_2 * waves.highest_crest();
        // The nearest visible sea is the bottom centre's (no roll: that ray falls most); where it
        // misses the sphere no ray meets the sea.
        let (margin_x, margin_y) = if let Some(hit) = cam.sea_hit(cam.ray([0.0, 1.0])) {
            let depth = hit.t; // view depth: ray . forward = 1
            let clear = depth - reach;
            let margin = |tan_half: f64| {
                if clear > Z_NEAR {
                    (reach / (clear * tan_half)).min(MAX_MARGIN_NDC)
                } else {
                    MAX_MARGIN_NDC
                }
            };
            (
                margin(cam.tan_half_x) + 2.0 * cell_px / width as f64,
                margin(cam.tan_half_y) + 2.0 * cell_px / height as f64,
            )
        } else {
            (0.0, 0.0)
        };
        let cell_ndc_x = 2.0 * cell_px / width as f64;
        let cell_ndc_y = 2.0 * cell_px / height as f64;
        let columns = ((2.0 + 2.0 * margin_x) / cell_ndc_x).ceil() as u32 + 1;
        let top_ndc_y = cam.limb_ndc_y().max(-1.0 - margin_y);
        let bottom_ndc_y = 1.0 + margin_y;
        let rows =
            if top_ndc_y < bottom_ndc_y { ((bottom_ndc_y - top_ndc_y) / cell_ndc_y).ceil() as u32 + 1 } else { 0 };
        GridLayout { columns, rows, top_ndc_y, margin_x, margin_y }
    }
}

/// The constant-BRDF baseline's roughness: the residual slope variance of the nearest visible sea
/// (the bottom centre pixel), as a renderer tuned for the foreground would fix it; the waves' total
/// where no sea is in view.
pub fn baseline_slope_variance(
    camera: &CameraFrame,
    waves: &WaveSet,
    time_s: f64,
    width: u32,
    height: u32,
) -> [f64; 2] {
    let footprint = super::footprint::Footprint { camera, waves, time_s, width, height, packets: None };
    footprint
        .resolved_surface(width as f64 / 2.0, height as f64 - 1.0, None)
        .map_or(waves.sigma2, |(_, _, sigma2)| sigma2)
}

/// Rows at the top of a `height`-row image that only sky can cover, so that the shading pass
/// leaves the sea's shader out there: on a CPU driver a branch does not skip the code of the
/// side no lane takes, so a sky pixel shaded by the sea's shader pays for all of it. Those rows'
/// rays all pass above the limb of the sphere through the highest crests (radius R + A, seen
/// from H - A above it), so no crest can meet them and the displaced grid stays below them; the
/// last such row is left to the sea's shader in case f32 rounding on the GPU puts a grid pixel
/// there.
pub fn sky_only_rows(camera: &CameraFrame, waves: &WaveSet, height: u32) -> u32 {
    let highest_crest = waves.highest_crest();
    if highest_crest >= camera.plane_height {
        return 0;
    }
    let (r, h) = (camera.planet_radius, camera.plane_height);
    let crest_dip_sine = ((h - highest_crest) * (2.0 * r + h + highest_crest)).sqrt() / (r + h);
    // With no roll a row's rays fall most at its centre column and its lower edge (the centre
    // column's elevation falls with y), so the rows that clear the crests are a prefix.
    let clears = |row: u32| {
        let ray = camera.ray([0.0, (row + 1) as f64 / height as f64 * 2.0 - 1.0]);
        -ray.z / ray.length() < crest_dip_sine
    };
    (0..height).take_while(|&row| clears(row)).count().saturating_sub(1) as u32
}

/// The first row of a `height`-row image at and below which every pixel's ray falls below the
/// limb, so only sea can be seen there (the sea is a height field over the sphere), and the
/// shading pass leaves the sky's shader out; `height` when no such row exists. With no roll a
/// row's rays fall least at its upper edge and at the image's sides (|ray| is largest there);
/// one row of margin is left for f32 rounding on the GPU.
pub fn sea_only_rows(camera: &CameraFrame, height: u32) -> u32 {
    let dip_sine = camera.dip_sine();
    let falls = |row: u32| {
        let y = row as f64 / height as f64 * 2.0 - 1.0;
        [-1.0, 1.0].iter().all(|&x| {
            let ray = camera.ray([x, y]);
            -ray.z / ray.length() > dip_sine
        })
    };
    (0..height).find(|&row| falls(row)).map_or(height, |row| (row + 1).min(height))
}

/// Everything derived from a scene for one frame.
#[derive(Clone)]
pub struct FrameData {
    pub uniforms: FrameUniforms,
    pub waves: Box<GpuWaves>,
    pub grid: GridLayout,
    /// Top rows of the image that only sky covers (see `sky_only_rows`).
    pub sky_rows: u32,
    /// The first row from which only sea is seen (see `sea_only_rows`).
    pub sea_rows: u32,
    pub camera: CameraFrame,
    pub sky: SkyModel,
    /// The sun's view of the displaced sea (None: the sun is down, nothing is displaced, or the
    /// scene's shadow map is off).
    pub sun_view: Option<crate::render::sun_shadow::SunView>,
}

/// The elevations (rad) the eye's sky-view table spans (glsl/sky_view.glsl): from the planet's
/// limb, below which the sea is seen, up to the zenith; from outside the air, up to the air's own
/// limb, above which space is empty. The two limbs' dips are atan(sqrt(r^2 - R^2) / R) of each
/// radius R, r^2 - R^2 as a product.
pub fn eye_sky_elevations(atm: &crate::model::atmosphere::AtmosphereParams, eye_height: f64) -> [f64; 2] {
    let (ground, top) = (atm.bottom_radius_m, atm.top_radius_m);
    let dip = |radius: f64| {
        let above = ground + eye_height - radius;
        (above * (ground + eye_height + radius)).max(0.0).sqrt().atan2(radius)
    };
    let highest = if ground + eye_height > top { -dip(top) } else { std::f64::consts::FRAC_PI_2 };
    [-dip(ground), highest]
}

/// How glsl/shade.glsl's `local_sea_light` turns the GPU's sea-level light table into each sea
/// point's light: the frame's exact sun and sky irradiance below the eye over the table's value
/// there ([0], [1]: held within a factor of 2, 1 where the table holds nothing: they agree but for
/// tiny values near the horizon), so that below the eye the light is the exact one, and 1 over
/// the table's sky irradiance there ([2]: the sky map's radiance scales by the ratio of the point's
/// to it; 0 where it is dark).
fn sea_light_calibration(
    atm: &crate::model::atmosphere::AtmosphereParams,
    mu_eye: f64,
    sun_exact: [f64; 3],
    sky_exact: [f64; 3],
) -> [[f32; 4]; 3] {
    let (sky_table, sun_table) = crate::model::atmosphere::sea_light_table(atm, mu_eye);
    let ratio = |exact: [f64; 3], table: [f64; 3]| {
        std::array::from_fn(|c| if table[c] > 0.0 { (exact[c] / table[c]).clamp(0.5, 2.0) } else { 1.0 })
    };
    let inverse = sky_table.map(|e| if e > 0.0 { 1.0 / e } else { 0.0 });
    [v4(ratio(sun_exact, sun_table), 0.0), v4(ratio(sky_exact, sky_table), 0.0), v4(inverse, 0.0)]
}

fn v4(v: [f64; 3], w: f64) -> [f32; 4] {
    [v[0] as f32, v[1] as f32, v[2] as f32, w as f32]
}

fn mat(m: Mat4) -> [[f32; 4]; 4] {
    m.to_cols_array_2d()
}

/// Frame data for rendering at `width` x `height` (with supersampling, the sample grid's size, and
/// `cell_px` the grid cell in those samples).
pub fn build(scene: &Scene, waves: &WaveSet, width: u32, height: u32, cell_px: f64) -> FrameData {
    build_with_casters(scene, waves, width, height, cell_px, None)
}

/// `build`, the sun's view also fitted to a host's shadow casters (sun_shadow::fit).
pub fn build_with_casters(
    scene: &Scene,
    waves: &WaveSet,
    width: u32,
    height: u32,
    cell_px: f64,
    casters: Option<crate::render::sun_shadow::CasterBox>,
) -> FrameData {
    let camera = CameraFrame::new(scene, waves, width, height);
    let grid = GridLayout::new(&camera, waves, cell_px, width, height);
    let sky = SkyModel::new(scene.sun.elevation_deg, scene.sun.azimuth_deg, scene.sky.turbidity);
    let view_proj = camera.view_proj(width as f64 / height as f64).as_mat4();

    let mut gpu_waves = Box::<GpuWaves>::default();
    let mut prefix = [0.0f64; 4];
    for (i, t) in waves.trains.iter().enumerate() {
        let v = t.slope_variance();
        prefix = [prefix[0] + v[0], prefix[1] + v[1], prefix[2] + t.curvature_power(), 0.0];
        let unorm16 = |v: f64| (v.clamp(0.0, 1.0) * 65535.0).round() as u32;
        // Turns in [0, 1) as 16-bit fixed point; 65536 wraps to 0, the same phase.
        let phase = ((t.phase_at(scene.render.time_s) / std::f64::consts::TAU) * 65536.0).round() as u32 & 0xffff;
        // The wave vector's components are binary16 values (waves::binary16_wave_vector), so
        // these halves are exact.
        let half = |v: f64| half::f16::from_f64(v).to_bits() as u32;
        gpu_waves.data[i] = [
            half(t.direction[0] / t.wavelength) | half(t.direction[1] / t.wavelength) << 16,
            phase | unorm16(t.k * t.amplitude) << 16,
            0,
            0,
        ];
        gpu_waves.prefix[i] = prefix.map(|x| x as f32);
    }

    let physical = scene.sky.model == crate::model::scene::SkyKind::Physical;
    let atm = &scene.atmosphere();
    // The physical sky's sun and sky light at the sea (at sea level, below the eye however high
    // it is), and the sun disc seen from the eye; Preetham's otherwise (one altitude).
    let (sun_at_sea, sky_irradiance, sun_radiance) = if physical {
        let (sun_at_sea, sky_at_sea) = crate::model::atmosphere::sun_and_sky(atm, 0.0, sky.sun_dir);
        let sun_at_eye = crate::model::atmosphere::shared(atm).sun_radiance(camera.eye_height, sky.sun_dir[2]);
        (sun_at_sea, sky_at_sea, sun_at_eye)
    } else {
        (sky.sun_radiance, sky.sky_irradiance(), sky.sun_radiance)
    };
    let sun_irradiance = sun_at_sea.map(|l| l * SkyModel::sun_solid_angle());
    let sun_above = if sun_at_sea.iter().any(|&l| l > 0.0) { 1.0 } else { 0.0 };
    // Only a scene that may draw the shadow map pays for its view.
    let shadows = scene.render.shadow_map != crate::model::scene::ShadowMapMode::Off;
    let sun_view = if shadows && sun_above > 0.0 {
        let probes = crate::render::sun_shadow::displaced_probes(&camera, waves, cell_px, (width, height), 1.0);
        let eye = DVec3::new(scene.camera.x_m, scene.camera.y_m, camera.plane_height);
        let size = scene.render.shadow_map_size;
        crate::render::sun_shadow::fit(&probes, waves, &camera, DVec3::from(sky.sun_dir), eye, size, casters)
    } else {
        None
    };
    let perez = std::array::from_fn(|i| v4(sky.perez[i], 0.0));
    let uniforms = FrameUniforms {
        view_proj: mat(view_proj),
        cam_right: v4((camera.right * camera.tan_half_x).to_array(), 0.0),
        cam_down: v4((-camera.up * camera.tan_half_y).to_array(), 0.0),
        cam_forward: v4(camera.forward.to_array(), camera.plane_height),
        viewport: [width as f32, height as f32, 1.0 / width as f32, 1.0 / height as f32],
        grid: [cell_px as f32, grid.top_ndc_y as f32, grid.margin_x as f32, grid.margin_y as f32],
        grid_dims: [grid.columns, grid.rows, waves.trains.len() as u32, 0],
        filter_steps: [GEOMETRY_STEPS[0], GEOMETRY_STEPS[1], NORMAL_STEPS[0], NORMAL_STEPS[1]],
        sun_dir: v4(sky.sun_dir, crate::model::sky::SUN_ANGULAR_RADIUS.cos()),
        sun_radiance: v4(sun_radiance, SkyModel::sun_slope_variance()),
        sun_irradiance: v4(sun_irradiance, sun_above),
        sky_irradiance: v4(sky_irradiance, 0.0),
        sea_albedo: v4(SEA_ALBEDO, 0.0),
        wind: [
            waves.wind_direction[0] as f32,
            waves.wind_direction[1] as f32,
            waves.sigma2[0] as f32,
            waves.sigma2[1] as f32,
        ],
        perez,
        sky_zenith: v4(sky.zenith_over_f0, sky.sky_scale),
        // An automatic exposure is measured on the GPU (passes/exposure.rs); x is then unused. y is
        // the full method's map extent; a renderer of another method sets its own (sky_map_extent).
        tone: [
            match scene.render.exposure() {
                crate::model::scene::Exposure::PerKcd(e) => e as f32,
                crate::model::scene::Exposure::Auto => 0.0,
            },
            SKY_MAP_EXTENT,
            0.0,
            0.0,
        ],
        wave_extent: [waves.longest_wavelength() as f32, waves.highest_crest() as f32, 0.0, 0.0],
        baseline_sigma2: {
            let b = baseline_slope_variance(&camera, waves, scene.render.time_s, width, height);
            [b[0] as f32, b[1] as f32, 0.0, 0.0]
        },
        atmosphere: [
            [atm.bottom_radius_m, atm.top_radius_m, atm.rayleigh_scale_height_m, atm.mie_scale_height_m],
            [
                atm.rayleigh_scattering_per_m[0],
                atm.rayleigh_scattering_per_m[1],
                atm.rayleigh_scattering_per_m[2],
                atm.mie_g,
            ],
            [
                atm.ozone_absorption_per_m[0],
                atm.ozone_absorption_per_m[1],
                atm.ozone_absorption_per_m[2],
                atm.mie_scattering_per_m,
            ],
            [atm.ozone_center_m, atm.ozone_width_m, atm.mie_absorption_per_m, atm.ground_albedo],
            [
                crate::model::sky::SOLAR_ILLUMINANCE_KLUX,
                2.0 * (1.0 - crate::model::sky::SUN_ANGULAR_RADIUS.cos()),
                camera.eye_height,
                0.0,
            ],
        ]
        .map(|v| v.map(|x| x as f32)),
        sun_view_proj: mat(sun_view.map_or(DMat4::ZERO, |s| s.view_proj).as_mat4()),
        // x: the camera's near plane (depth to distance); y: whether the sun's view exists this
        // frame.
        shadow: [Z_NEAR as f32, sun_view.is_some() as u32 as f32, 0.0, 0.0],
        planet: [
            camera.planet_radius as f32,
            camera.dip_sine() as f32,
            camera.limb_c() as f32,
            camera.limb_c().sqrt() as f32,
        ],
        eye_sky: {
            let [lowest, highest] = eye_sky_elevations(atm, camera.eye_height);
            [lowest as f32, highest as f32, 0.0, 0.0]
        },
        sea_light: if physical {
            sea_light_calibration(atm, sky.sun_dir[2], sun_irradiance, sky_irradiance)
        } else {
            [[1.0; 4]; 3]
        },
        glints: [
            scene.render.time_s.rem_euclid(GLINT_TIME_PERIOD_S) as f32,
            SkyModel::sun_solid_angle() as f32,
            0.0,
            0.0,
        ],
        host_clip: [[0.0; 4]; 4],
        host: [0.0; 4],
        packet_grid: [0.0; 4],
        packet_map: [0.0; 4],
        packet_dims: [0; 4],
    };
    // No grid row: no sea anywhere in view.
    let sky_rows = if grid.rows == 0 { height } else { sky_only_rows(&camera, waves, height) };
    let sea_rows = if grid.rows == 0 { height } else { sea_only_rows(&camera, height) };
    FrameData { uniforms, waves: gpu_waves, grid, sky_rows, sea_rows, camera, sky, sun_view }
}
