//! An independent f64 CPU evaluation of the shading at one pixel, from the same formulas as the
//! shaders (paper sections 4-6): footprint, resolution weights, resolved normal, residual slope
//! variance, reflected sun, mean Fresnel, refracted sea light and the analytic sky at the
//! reflected direction. Tests compare the GPU against it on chosen pixels.
//!
//! Only valid where the grid is not displaced (no train resolved at the grid's scale): the
//! visible point is then the ray's intersection with the rest plane.

use crate::model::fresnel::{fresnel_exact, MeanFresnelTable, SEA_WATER_IOR};
use crate::model::sky::{SkyLight, SkyModel};
use crate::output::luminance_rgb;
use crate::render::footprint::{normal_weight, smallest_step, Footprint};
use crate::render::frame::{GEOMETRY_STEPS, NORMAL_STEPS, RAY_HIT_SHARE, SEA_ALBEDO};
use glam::{DVec2, DVec3};
use std::f64::consts::PI;

/// Schlick's R0 for water (paper, section 5).
const R0: f64 = 0.02;
/// z of the directions on the sky map's rim |u| = R (the inverse stereographic map): the deepest
/// the full method's lookups read (22.6 degrees below the horizon).
const RIM_Z: f64 = {
    let r = crate::render::frame::SKY_MAP_EXTENT as f64;
    (1.0 - r * r) / (1.0 + r * r)
};

/// Per-term radiance (kcd/m^2, linear sRGB) at one pixel.
#[derive(Debug, Clone, Copy, Default)]
pub struct PixelRadiance {
    pub sun: [f64; 3],
    pub sky: [f64; 3],
    pub sea: [f64; 3],
    /// Resolved normal and residual slope variance, for diagnostics.
    pub normal: [f64; 3],
    pub sigma2: [f64; 2],
}

/// What the reference needs from the frame: the camera, waves and image of the footprint, and
/// the sky.
pub struct ReferenceScene<'a> {
    pub footprint: Footprint<'a>,
    /// Preetham's sky, or the physical one seen from sea level (model::sky_table).
    pub sky: &'a dyn SkyLight,
    /// The full method's sky (Method::Full) instead of the paper's: each facet weighted by its
    /// projected area towards the eye, a reflection below the horizon meeting the sea, and the
    /// point shaded where the pixel's ray meets the surface it resolves.
    pub full: bool,
}

impl ReferenceScene<'_> {
    /// Camera ray through the centre of pixel (px, py), y down.
    pub fn pixel_ray(&self, px: f64, py: f64) -> DVec3 {
        self.footprint.pixel_ray(px, py)
    }

    /// Rest position hit by `ray` and its derivatives per pixel (`footprint::rest_hit`).
    pub fn rest_hit(&self, ray: DVec3) -> Option<(DVec2, DVec2, DVec2)> {
        self.footprint.rest_hit(ray)
    }

    /// A train the grid displaces at pixel (px, py) of a grid of `cells` px, its wavelength (m):
    /// its phase step per grid cell below the geometry's cut-off. None where it displaces
    /// nothing, or the pixel sees no sea, which is where this reference is the method's.
    pub fn displaced_train(&self, cells: f64, px: f64, py: f64) -> Option<f64> {
        let (_, a_u, a_v) = self.rest_hit(self.pixel_ray(px, py))?;
        let displaced = |k| displaced_by_grid(k, a_u * cells, a_v * cells);
        self.footprint
            .waves
            .trains
            .iter()
            .map(|t| (DVec2::from(t.direction) / t.wavelength, t.wavelength))
            .find_map(|(k, wavelength)| displaced(k).then_some(wavelength))
    }

    /// A wave packet the grid displaces at pixel (px, py) of a grid of `cells` px (one reaching
    /// the pixel's rest position with a phase step per cell below the geometry's cut-off), its
    /// wavelength (m); None where none is, or the pixel sees no sea.
    pub fn displaced_packet(&self, cells: f64, px: f64, py: f64) -> Option<f64> {
        let (x, a_u, a_v) = self.rest_hit(self.pixel_ray(px, py))?;
        let packets = self.footprint.packets?;
        packets.packets.iter().filter(|p| p.reaches(x)).find_map(|p| {
            displaced_by_grid(p.direction / p.wavelength(), a_u * cells, a_v * cells).then(|| p.wavelength())
        })
    }

    /// Weight of a train resolved by the per-pixel normal (see glsl/waves.glsl).
    pub fn normal_weight(&self, k_turns: DVec2, a_u: DVec2, a_v: DVec2) -> f64 {
        normal_weight(k_turns, a_u, a_v)
    }

    pub fn shade(&self, px: f64, py: f64) -> Option<PixelRadiance> {
        let (n, v, sigma2) = self.resolved_surface(px, py)?;
        let steeper = self.packets_steepen(px, py, v);
        Some(self.brdf_steeper(n, v, sigma2, steeper))
    }

    /// How much steeper than its trains the sea is along the view at pixel (px, py) where its
    /// wave packets add their whole slope variance (glsl/masking.glsl sea_view): 1 for the
    /// paper's method, without packets or without trains.
    pub fn packets_steepen(&self, px: f64, py: f64, v: DVec3) -> f64 {
        let (Some(packets), true) = (self.footprint.packets, self.full) else { return 1.0 };
        let Some((x, _, _)) = self.rest_hit(self.pixel_ray(px, py)) else { return 1.0 };
        let waves = self.footprint.waves;
        let wind = DVec2::from(waves.wind_direction);
        let along_share = Self::along_share(v, wind);
        let share = |s: [f64; 2]| s[0] * along_share + s[1] * (1.0 - along_share);
        let trains = share(waves.sigma2);
        if trains > 0.0 {
            (1.0 + share(packets.linear_slope_variance(x, wind)) / trains).sqrt()
        } else {
            1.0
        }
    }

    /// cos^2 of v's azimuth from the wind (0.5 for a vertical v).
    fn along_share(v: DVec3, wind: DVec2) -> f64 {
        let (x, y) = (v.x * wind.x + v.y * wind.y, v.y * wind.x - v.x * wind.y);
        let horizontal2 = x * x + y * y;
        if horizontal2 > 0.0 {
            x * x / horizontal2
        } else {
            0.5
        }
    }

    /// Resolved normal, view direction and residual slope variance at a pixel's centre; None
    /// where the pixel sees no sea (`footprint::resolved_surface`).
    pub fn resolved_surface(&self, px: f64, py: f64) -> Option<(DVec3, DVec3, [f64; 2])> {
        let strength = |v, up, a_u, a_v| self.ray_hit_strength(v, up, a_u, a_v);
        self.footprint.resolved_surface(px, py, self.full.then_some(&strength as &dyn Fn(_, _, _, _) -> _))
    }

    /// The three terms for resolved normal `n`, view `v` and residual variance `sigma2`.
    pub fn brdf(&self, n: DVec3, v: DVec3, sigma2: [f64; 2]) -> PixelRadiance {
        self.brdf_steeper(n, v, sigma2, 1.0)
    }

    /// The same on a sea `steeper` times as steep along the view as its trains
    /// (`packets_steepen`).
    pub fn brdf_steeper(&self, n: DVec3, v: DVec3, sigma2: [f64; 2], steeper: f64) -> PixelRadiance {
        let vn = v.dot(n);
        let n = if vn < 0.0 { (n - vn * v).try_normalize().unwrap_or(DVec3::Z) } else { n };
        let [t_x, t_y, n] = self.wind_frame(n);
        let local = |d: DVec3| DVec3::new(d.dot(t_x), d.dot(t_y), d.dot(n));
        let vl = local(v);
        let cos_v = vl.z.clamp(0.0, 1.0);

        let sun_dir = DVec3::from(self.sky.sun_dir());
        let sun = if self.sky.sun_irradiance().iter().any(|&l| l > 0.0) {
            let sun_sigma2 = SkyModel::sun_slope_variance();
            let mut value = reflected_sun_with(vl, local(sun_dir), sigma2, sun_sigma2, self.facet_fresnel());
            if self.full {
                value *= self.glint_masking(v, sun_dir, sigma2);
            }
            self.sky.sun_irradiance().map(|e| e * value)
        } else {
            [0.0; 3]
        };
        let mut fresnel = self.mean_fresnel(cos_v, directional_variance(vl.x, vl.y, sigma2).sqrt());
        let mut lean = DVec2::ZERO;
        if self.full {
            let (further, ratio) = self.visible_facet_correction(v, steeper);
            lean = -further * DVec2::new(vl.x, vl.y).try_normalize().unwrap_or(DVec2::ZERO);
            fresnel = (fresnel * ratio).min(1.0);
        }
        let (sky_l, enters) = self.mean_sky_radiance([t_x, t_y, n], v, sigma2, lean);
        let e_sky = self.sky.sky_irradiance();
        PixelRadiance {
            sun,
            sky: sky_l.map(|l| fresnel * l),
            sea: std::array::from_fn(|c| (1.0 - fresnel * (1.0 - enters)) * SEA_ALBEDO[c] * e_sky[c] / PI),
            normal: n.to_array(),
            sigma2,
        }
    }
}

impl ReferenceScene<'_> {
    /// The wind's axes in the plane normal to n, and n (glsl/brdf.glsl wind_frame).
    fn wind_frame(&self, n: DVec3) -> [DVec3; 3] {
        let wind = DVec3::new(self.footprint.waves.wind_direction[0], self.footprint.waves.wind_direction[1], 0.0);
        let t = wind - n * n.dot(wind);
        let t_x = t.try_normalize().unwrap_or_else(|| DVec3::new(-wind.y, wind.x, 0.0).cross(n).normalize());
        [t_x, n.cross(t_x), n]
    }

    /// How much of the step to where the pixel's ray meets the surface a pixel takes: the sun's
    /// glitter on the mean plane, all slopes in the BRDF, against the least reflected
    /// sky, times a ramp in the share of the slope variance the pixel's normal can resolve
    /// (glsl/shade.glsl ray_hit_strength, RAY_HIT_SUN and RAY_HIT_SHARE the same).
    fn ray_hit_strength(&self, v: DVec3, up: DVec3, a_u: DVec2, a_v: DVec2) -> f64 {
        const RAY_HIT_SUN: f64 = 300.0;
        let [t_x, t_y, n] = self.wind_frame(up);
        let local = |d: DVec3| DVec3::new(d.dot(t_x), d.dot(t_y), d.dot(n));
        let (vl, ll) = (local(v), local(DVec3::from(self.sky.sun_dir())));
        // The sun's glitter without Fresnel, masking and 1 / cos_v (glsl/shade.glsl
        // sun_glitter_density): the slopes' density at the half vector over 4 h_z^4.
        let sun = if vl.z > 0.0 && ll.z > 0.0 {
            let h = (vl + ll).normalize();
            let s2 = self.footprint.waves.sigma2.map(|s| s + SkyModel::sun_slope_variance());
            let q = (h.x * h.x / s2[0] + h.y * h.y / s2[1]) / (h.z * h.z);
            (-0.5 * q).exp() / (8.0 * PI * (s2[0] * s2[1]).sqrt() * h.z.powi(4))
                * luminance_rgb(self.sky.sun_irradiance())
        } else {
            0.0
        };
        let sky_floor = R0 * luminance_rgb(self.sky.sky_irradiance()) / PI;
        let ramp = 0.9 * RAY_HIT_SUN * sky_floor;
        let in_path = if ramp > 0.0 {
            ((sun - 0.1 * RAY_HIT_SUN * sky_floor) / ramp).clamp(0.0, 1.0)
        } else if sun > 0.0 {
            1.0
        } else {
            0.0
        };
        // Trains no direction resolves: wavelength within the footprint's smallest phase step
        // (glsl/waves.glsl sample_scale's lambda_cut, at the normals' cut-off of one turn).
        let lambda_cut = smallest_step(a_u, a_v) / NORMAL_STEPS[1] as f64;
        let share = self.footprint.waves.resolvable_slope_share(lambda_cut);
        let t = ((share - RAY_HIT_SHARE[0]) / (RAY_HIT_SHARE[1] - RAY_HIT_SHARE[0])).clamp(0.0, 1.0);
        in_path * t * t * (3.0 - 2.0 * t)
    }

    /// The full method's masking factor on the sun term (glsl/masking.glsl), from the table the
    /// renderer measures for the same sea and sun (its own measurement is tested apart).
    fn glint_masking(&self, v: DVec3, sun_dir: DVec3, unresolved: [f64; 2]) -> f64 {
        let waves = self.footprint.waves;
        let wind = DVec2::from(waves.wind_direction);
        let sun_azimuth = sun_dir.y.atan2(sun_dir.x) - wind.y.atan2(wind.x);
        let elevation = sun_dir.z.clamp(-1.0, 1.0).asin();
        let table = crate::model::masking::GlintMaskingTable::cached(
            waves,
            0.0,
            sun_azimuth.to_degrees(),
            elevation.to_degrees(),
        );
        table.sea_masking(v, sun_dir, wind, unresolved, waves.sigma2)
    }

    /// The full method's visible facets at v's depression on a level sea `steeper` times as steep
    /// as its trains (glsl/masking.glsl, visible_facet_correction): their further lean towards the
    /// eye and their Fresnel ratio, from the table the renderer measures for the same sea.
    fn visible_facet_correction(&self, v: DVec3, steeper: f64) -> (f64, f64) {
        let waves = self.footprint.waves;
        let along_share = Self::along_share(v, DVec2::from(waves.wind_direction));
        let table = crate::model::masking::VisibleFacetTable::cached(waves, 0.0);
        table.lookup_steeper(along_share, v.z.clamp(0.0, 1.0).asin(), steeper)
    }

    /// The sky and refracted terms' Fresnel: the paper's fit, or (full) the exact average over
    /// the visible slopes, through the table the shaders read (its own accuracy is tested apart).
    fn mean_fresnel(&self, cos_v: f64, sigma_v: f64) -> f64 {
        if self.full {
            MeanFresnelTable::sea_water().lookup(cos_v, sigma_v)
        } else {
            mean_fresnel(cos_v, sigma_v)
        }
    }

    /// The sun term's Fresnel at the half vector: Schlick's, or (full) the exact one.
    fn facet_fresnel(&self) -> fn(f64) -> f64 {
        if self.full {
            |c| fresnel_exact(c, SEA_WATER_IOR)
        } else {
            schlick
        }
    }

    /// Sky radiance averaged over the Gaussian slope distribution (paper's L-bar), by a product
    /// midpoint rule over +-4 sigma per axis. The paper: directions reflected below the horizon see
    /// the sky mirrored, as its sky map folds them. Full: each facet weighted by its projected
    /// area (v.f)^+ / f_z as well, and a reflection below the horizon meets the sea, seen from there
    /// over all its slopes: the sky mirrored again times the mean Fresnel F2 there, the rest
    /// entering the water; each facet's slope moved by `lean` after its weight (the visible
    /// facets' further lean, glsl/brdf.glsl). Returns the mean sky radiance and the mean entering
    /// share.
    pub fn mean_sky_radiance(&self, frame: [DVec3; 3], v: DVec3, sigma2: [f64; 2], lean: DVec2) -> ([f64; 3], f64) {
        const N: usize = 33;
        let [t_x, t_y, n] = frame;
        let (sx, sy) = (sigma2[0].sqrt(), sigma2[1].sqrt());
        let sea = self.footprint.waves;
        let wind = DVec2::from(sea.wind_direction);
        let mut sum = [0.0; 3];
        let (mut weight_sum, mut enters_sum) = (0.0, 0.0);
        for i in 0..N {
            let gx = (i as f64 + 0.5) / N as f64 * 8.0 - 4.0;
            for j in 0..N {
                let gy = (j as f64 + 0.5) / N as f64 * 8.0 - 4.0;
                let mut weight = (-0.5 * (gx * gx + gy * gy)).exp();
                let (zx, zy) = (gx * sx, gy * sy);
                if self.full {
                    weight *= (v.dot(n) - zx * v.dot(t_x) - zy * v.dot(t_y)).max(0.0);
                }
                let facet = (n - (zx + lean.x) * t_x - (zy + lean.y) * t_y).normalize();
                let mut r = 2.0 * v.dot(facet) * facet - v;
                if self.full && r.z < RIM_Z {
                    // The sky map holds directions down to its rim; deeper ones read the rim.
                    let xy = DVec2::new(r.x, r.y).try_normalize().unwrap_or(DVec2::X) * (1.0 - RIM_Z * RIM_Z).sqrt();
                    r = DVec3::new(xy.x, xy.y, RIM_Z);
                }
                let mut l = self.sky.radiance([r.x, r.y, r.z.abs()]);
                if self.full {
                    let d = DVec2::new(r.x, r.y);
                    let (along, across) = (d.dot(wind), d.dot(wind.perp()));
                    let var = directional_variance(along, across, sea.sigma2);
                    let f2 = MeanFresnelTable::sea_water().lookup(r.z.abs(), var.sqrt());
                    let blocked = if r.z < 0.0 { 1.0 } else { blocked_share(along, across, r.z, sea.sigma2) };
                    // The wave it meets mirrors it again about the mean facet it strikes.
                    let local = DVec3::new(along, across, r.z);
                    let facet = struck_facet_normal(local, sea.sigma2);
                    let again = local - 2.0 * local.dot(facet) * facet;
                    let again_xy = wind * again.x + wind.perp() * again.y;
                    let l2 = self.sky.radiance([again_xy.x, again_xy.y, again.z.abs()]);
                    for c in 0..3 {
                        l[c] = (1.0 - blocked) * l[c] + blocked * f2 * l2[c];
                    }
                    enters_sum += weight * blocked * (1.0 - f2);
                }
                for c in 0..3 {
                    sum[c] += weight * l[c];
                }
                weight_sum += weight;
            }
        }
        if weight_sum <= 0.0 {
            return ([0.0; 3], 0.0);
        }
        (sum.map(|s| s / weight_sum), enters_sum / weight_sum)
    }
}

/// Whether the grid displaces a wave of wave vector `k_turns` (turns per m) whose cells move its
/// rest position by `cell_u` and `cell_v`: its phase step per cell below the geometry's cut-off.
fn displaced_by_grid(k_turns: DVec2, cell_u: DVec2, cell_v: DVec2) -> bool {
    k_turns.dot(cell_u).abs().max(k_turns.dot(cell_v).abs()) < GEOMETRY_STEPS[1] as f64
}

/// The unit normal of the mean facet that a ray along the unit direction d (wind-axis components)
/// strikes where it meets the sea (glsl/slopes.glsl, struck_facet_normal): the Gaussian slopes
/// under the ramp (zeta_s - tan e)^+, r = -tan(e) / sigma_s kept from -3.
fn struck_facet_normal(d: DVec3, sigma2: [f64; 2]) -> DVec3 {
    let sin2 = d.x * d.x + d.y * d.y;
    let var = directional_variance(d.x, d.y, sigma2);
    if sin2 <= 0.0 || var <= 0.0 {
        return DVec3::Z;
    }
    let back = -DVec2::new(d.x, d.y) / sin2.sqrt();
    let sigma_s = var.sqrt();
    let r = (-d.z / sin2.sqrt() / sigma_s).max(-3.0);
    let m = (-0.5 * r * r).exp() / (2.0 * PI).sqrt() / crate::model::masking::normal_cdf(r);
    let mean = DVec2::new(-sigma2[0] * back.x, -sigma2[1] * back.y) / (sigma_s * (r + m));
    DVec3::new(-mean.x, -mean.y, 1.0).normalize()
}

/// Slope variance along the azimuth with wind-axis components (x, y); the mean of the axes where
/// the azimuth is undefined (glsl/slopes.glsl).
fn directional_variance(x: f64, y: f64, sigma2: [f64; 2]) -> f64 {
    let spread2 = x * x + y * y;
    if spread2 > 0.0 {
        (sigma2[0] * x * x + sigma2[1] * y * y) / spread2
    } else {
        0.5 * (sigma2[0] + sigma2[1])
    }
}

/// Smith's Lambda towards the unit direction with local components (x, y, z > 0), for slopes of
/// variance sigma2 along the axes: a = cot(theta) / sqrt(2 sigma_phi^2) = z / sqrt(2 (sigma_x^2 x^2
/// + sigma_y^2 y^2)); 0 on a glassy sea and where a > 26 (below f64's resolution).
fn lambda_towards(x: f64, y: f64, z: f64, sigma2: [f64; 2]) -> f64 {
    let spread2 = 2.0 * (sigma2[0] * x * x + sigma2[1] * y * y);
    if spread2 == 0.0 {
        return 0.0;
    }
    let a = z / spread2.sqrt();
    if a > 26.0 {
        0.0
    } else {
        smith_lambda(a)
    }
}

/// Smith's share 1 - G1 = Lambda / (1 + Lambda) of the rays leaving the sea upwards along the
/// unit direction with wind-axis components (x, y, z > 0) that meet another wave, for slopes of
/// variance sigma2 (glsl/slopes.glsl, blocked_share); 0 on a glassy sea.
fn blocked_share(x: f64, y: f64, z: f64, sigma2: [f64; 2]) -> f64 {
    let lambda = lambda_towards(x, y, z, sigma2);
    lambda / (1.0 + lambda)
}

/// erfc by the paper demo's rational approximation, as the shader uses it.
pub fn erfc_approx(x: f64) -> f64 {
    2.0 * (-x * x).exp() / (2.319 * x + (4.0 + 1.52 * x * x).sqrt())
}

/// Smith's Lambda for Gaussian slopes, Lambda(a) = (exp(-a^2) - a sqrt(pi) erfc(a)) / (2 a sqrt(pi)).
pub fn smith_lambda(a: f64) -> f64 {
    ((-a * a).exp() - a * PI.sqrt() * erfc_approx(a)) / (2.0 * a * PI.sqrt())
}

/// Schlick's Fresnel for water (the paper's), at cos(incidence) c.
pub fn schlick(c: f64) -> f64 {
    R0 + (1.0 - R0) * (1.0 - c).clamp(0.0, 1.0).powi(5)
}

/// Paper's reflected sun per unit sun irradiance, directions in the local (t_x, t_y, n) frame:
/// F(v.h) p(zeta_h) / (4 h_z^4 cos_v (1 + Lambda(a_v) + Lambda(a_l))), F Schlick's.
pub fn reflected_sun(v: DVec3, l: DVec3, sigma2: [f64; 2], sun_sigma2: f64) -> f64 {
    reflected_sun_with(v, l, sigma2, sun_sigma2, schlick)
}

/// `reflected_sun` with the facets' Fresnel `fresnel` (of cos(incidence) v.h).
pub fn reflected_sun_with(v: DVec3, l: DVec3, sigma2: [f64; 2], sun_sigma2: f64, fresnel: fn(f64) -> f64) -> f64 {
    if l.z <= 0.0 {
        return 0.0;
    }
    let cos_v = v.z.max(0.0);
    let h = (v + l).normalize();
    let (sx, sy) = (sigma2[0] + sun_sigma2, sigma2[1] + sun_sigma2);
    let zeta = DVec2::new(h.x / h.z, h.y / h.z);
    let p = (-0.5 * (zeta.x * zeta.x / sx + zeta.y * zeta.y / sy)).exp() / (2.0 * PI * (sx * sy).sqrt());
    let fresnel = fresnel(v.dot(h));
    let lambda = |d: DVec3| lambda_towards(d.x, d.y, d.z, sigma2);
    if cos_v == 0.0 {
        // cos_v Lambda_v -> sin_v sqrt(2 sigma_v^2) / (2 sqrt(pi)) as cos_v -> 0.
        let spread = (2.0 * (sigma2[0] * v.x * v.x + sigma2[1] * v.y * v.y)).sqrt();
        if spread == 0.0 {
            return 0.0;
        }
        return fresnel * p / (4.0 * h.z.powi(4) * spread / (2.0 * PI.sqrt()));
    }
    fresnel * p / (4.0 * h.z.powi(4) * cos_v * (1.0 + lambda(v) + lambda(l)))
}

/// Mean Fresnel over visible slopes (paper's fit).
pub fn mean_fresnel(cos_v: f64, sigma_v: f64) -> f64 {
    R0 + (1.0 - R0) * (1.0 - cos_v).powf(5.0 * (-2.69 * sigma_v).exp()) / (1.0 + 22.7 * sigma_v.powf(1.5))
}
