//! The mirror pass: a host's objects drawn again, mirrored about the sea, into the ocean's
//! planar images (embed::Ocean::record_planar), for the shading pass to read the objects along
//! each pixel's reflected ray where the screen does not hold them (glsl/shade.glsl
//! planar_reflection). After the host's draws: the inverse depth of what it drew
//! (glsl/planar_inverse_depth.comp), the colour's mipmap by linear blits and the inverse depth's
//! by the same means (glsl/planar_mip.comp), so that a footprint's mean radiance, coverage and
//! harmonic mean depth are one read each. A frame the host draws no mirror into (none of its
//! objects' images is in view) skips it all: the shading pass is told by a push constant. Where
//! the host says where its mirrored objects may lie (MirrorCover), its draws are scissored to that
//! rectangle and the rest is built only there: the images are cleared, and the inverse depth and
//! both mipmaps made over the texels the rectangle covers on each level.

use super::pyramid::LevelReduction;
use super::{dispatch_within, write_frame_uniforms, Recorder, REGION_PUSH_BYTES};
use crate::error::Result;
use crate::render::resources::{PlanarImages, Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::Access;
use crate::vk::device::{Device, HDR_FORMAT};
use crate::vk::external::{begin_cleared_rendering, HostImage};
use crate::vk::image::{clear_levels, mipmap_within, PixelRect};
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;
use glam::{DMat4, DVec2, DVec3, DVec4, Mat4};

/// The colour a host draws its mirrored objects in: radiance in its own unit, alpha 1 (the
/// objects' coverage; the image is cleared to 0).
pub const PLANAR_COLOUR_FORMAT: vk::Format = HDR_FORMAT;

/// What a host draws its objects mirrored about the sea with (embed::Ocean::record_planar),
/// inside the pass's rendering scope (viewport its frame's, scissor its MirrorCover's, which the
/// host's draws keep; the whole frame's again after the pass): colour
/// PLANAR_COLOUR_FORMAT, depth PLANAR_DEPTH_FORMAT in the host's own depth convention (cleared to its
/// far plane), the host's projection. Each object is mirrored about the sea's tangent plane
/// below it (`plane_below`, `mirror`; the mirror reverses every face's winding on screen, so a
/// host culling back faces culls the other winding here than in its own pass), lit where it
/// stands (the light's view from the mirrored eye), and drawn only above that plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MirrorView {
    /// Camera-relative world (z up, m) to the host's clip space: its projection and view, as
    /// handed to the ocean's update.
    pub clip_from_relative: Mat4,
    /// The eye's height above the mean sea (m).
    pub eye_height_m: f64,
    /// The sea's sphere (m).
    pub planet_radius_m: f64,
}

impl MirrorView {
    /// The mean sea's tangent plane below camera-relative point `p`: its unit normal n and offset
    /// w (dot(n, x) = w on it), which an object at `p` is mirrored about.
    pub fn plane_below(&self, p: DVec3) -> (DVec3, f64) {
        crate::model::placement::sea_plane_below(p, self.eye_height_m, self.planet_radius_m)
    }

    /// The mirror about plane (n, w): x to x - 2 (n . x - w) n.
    pub fn mirror((n, w): (DVec3, f64)) -> DMat4 {
        let linear = glam::DMat3::IDENTITY - 2.0 * glam::DMat3::from_cols(n * n.x, n * n.y, n * n.z);
        DMat4::from_mat3_translation(linear, 2.0 * w * n)
    }

    /// The point of plane (n, w) below the eye (w < 0) that mirrors camera-relative `p` into the
    /// eye: where the line from the eye's mirror image 2 w n to p crosses the plane. A point on
    /// or below the plane is its own (the segment from it is empty).
    pub fn reflecting_point(p: DVec3, (n, w): (DVec3, f64)) -> DVec3 {
        let eye_image = 2.0 * w * n;
        // n . (p - eye_image) = (n . p - w) - w > 0 where p is above the plane and the eye too.
        let rise = n.dot(p - eye_image);
        let t = if rise > 0.0 { (-w / rise).clamp(0.0, 1.0) } else { 1.0 };
        eye_image + t * (p - eye_image)
    }

    /// Where camera-relative points, mirrored already (the corners of a box holding a mirrored
    /// object), lie in the mirror's images: their projections' bounding rectangle. Whole where
    /// one lies on or behind the eye's plane (no projection bounds them there) or is not finite.
    /// A box whose corners are all in front of the eye projects inside its corners' rectangle.
    pub fn cover_of(&self, points: impl IntoIterator<Item = DVec3>) -> MirrorCover {
        let clip = self.clip_from_relative.as_dmat4();
        let mut cover = MirrorCover::NOTHING;
        for p in points {
            let c: DVec4 = clip * p.extend(1.0);
            let ndc = c.truncate().truncate() / c.w;
            if c.w <= 0.0 || !ndc.is_finite() {
                return MirrorCover::Whole;
            }
            cover = cover.union(MirrorCover::Within { min: ndc.to_array(), max: ndc.to_array() });
        }
        cover
    }
}

/// Where a host's mirrored objects may lie in the mirror's images (embed::Ocean::record_planar):
/// the pass scissors the host's draws to it and builds what the shading reads there alone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MirrorCover {
    /// Anywhere in the images.
    Whole,
    /// Within this rectangle of normalized device coordinates (x right, y down, each -1 to 1 on
    /// the image; beyond it is clamped), empty where a min exceeds its max.
    Within { min: [f64; 2], max: [f64; 2] },
}

impl MirrorCover {
    /// Nowhere: the union's identity.
    pub const NOTHING: MirrorCover =
        MirrorCover::Within { min: [f64::INFINITY, f64::INFINITY], max: [f64::NEG_INFINITY, f64::NEG_INFINITY] };

    /// Where either may lie.
    pub fn union(self, other: MirrorCover) -> MirrorCover {
        match (self, other) {
            (MirrorCover::Within { min: a0, max: a1 }, MirrorCover::Within { min: b0, max: b1 }) => {
                MirrorCover::Within {
                    min: DVec2::from(a0).min(DVec2::from(b0)).to_array(),
                    max: DVec2::from(a1).max(DVec2::from(b1)).to_array(),
                }
            }
            _ => MirrorCover::Whole,
        }
    }

    /// The texels of an `extent` image it may touch: its rectangle grown by a texel on every side
    /// (a triangle covers a texel whose centre it holds, rounded by the rasterizer's subpixel
    /// precision), clamped to the image. Not finite: the whole image.
    pub fn pixels(self, extent: vk::Extent2D) -> PixelRect {
        let MirrorCover::Within { min, max } = self else { return PixelRect::whole(extent) };
        if min[0] > max[0] || min[1] > max[1] {
            return PixelRect::EMPTY;
        }
        if !(min.iter().chain(&max).all(|v| v.is_finite())) {
            return PixelRect::whole(extent);
        }
        let texel = |ndc: f64, size: u32| (ndc * 0.5 + 0.5) * size as f64;
        let low = |ndc: f64, size: u32| (texel(ndc, size).floor() - 1.0).clamp(0.0, size as f64) as u32;
        let high = |ndc: f64, size: u32| (texel(ndc, size).ceil() + 1.0).clamp(0.0, size as f64) as u32;
        PixelRect {
            x0: low(min[0], extent.width),
            y0: low(min[1], extent.height),
            x1: high(max[0], extent.width),
            y1: high(max[1], extent.height),
        }
    }
}

const MIRROR_DEPTH_BINDING: u32 = 1;
const INVERSE_DEPTH_BINDING: u32 = 2;

pub struct PlanarPass<'g> {
    /// Whether a host's cover is honoured (ShaderConfig::planar_cover); else the whole images.
    honours_cover: bool,
    inverse_depth: Bindings<'g>,
    inverse_depth_pipeline: Owned<'g, vk::Pipeline>,
    /// The coverage and inverse depth's levels from 1, each the mean of the texels below it.
    mips: LevelReduction<'g>,
}

impl PlanarPass<'_> {
    pub const NAME: &'static str = "planar reflection";
}

impl<'g> PlanarPass<'g> {
    pub fn new(device: &'g Device, r: &Resources, images: &PlanarImages, honours_cover: bool) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let inverse_depth = Bindings::with_push_constants(
            device,
            "planar inverse depth",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (MIRROR_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (INVERSE_DEPTH_BINDING, D::STORAGE_IMAGE, compute),
            ],
            REGION_PUSH_BYTES,
        )?;
        write_frame_uniforms(&inverse_depth, r, false);
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let general = vk::ImageLayout::GENERAL;
        inverse_depth.write_image(
            MIRROR_DEPTH_BINDING,
            D::COMBINED_IMAGE_SAMPLER,
            images.depth.view,
            read,
            r.depth_sampler.raw,
        );
        let level0 = images.inverse_depth_levels[0].raw;
        inverse_depth.write_image(INVERSE_DEPTH_BINDING, D::STORAGE_IMAGE, level0, general, vk::Sampler::null());
        let inverse_depth_pipeline = compute_pipeline(
            device,
            inverse_depth.layout(),
            shaders::PLANAR_INVERSE_DEPTH_COMP,
            "planar inverse depth",
        )?;
        let mips = LevelReduction::new(
            device,
            &images.inverse_depth_levels,
            shaders::PLANAR_MIP_COMP,
            "planar inverse depth mip",
        )?;
        Ok(PlanarPass { honours_cover, inverse_depth, inverse_depth_pipeline, mips })
    }

    /// Clears the planar images, has `draw` record the host's mirrored objects into them with
    /// `view` (`far`: the host's far-plane depth) within `cover`, and builds what the shading
    /// pass reads there: the texels of level 0 it built over, and the images' size (None without
    /// planar images).
    pub fn record_mirrored(
        &self,
        rec: &mut Recorder,
        r: &Resources,
        view: &MirrorView,
        cover: MirrorCover,
        far: f32,
        draw: &mut dyn FnMut(vk::CommandBuffer, &MirrorView),
    ) -> Option<(PixelRect, vk::Extent2D)> {
        let images = r.planar.as_ref()?;
        let extent = images.colour.extent;
        let within = if self.honours_cover { cover.pixels(extent) } else { PixelRect::whole(extent) };
        let whole = within == PixelRect::whole(extent);
        let levels = images.colour.mip_levels;
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        rec.tracker.image(&images.colour, 0, 1, Access::ColorAttachmentWrite, true);
        rec.tracker.image(&images.depth, 0, 1, Access::DepthAttachmentReadWrite, true);
        rec.tracker.flush(device, cmd);
        begin_cleared_rendering(device, cmd, &HostImage::from(&images.colour), &HostImage::from(&images.depth), far);
        let scissor =
            vk::Rect2D { offset: vk::Offset2D { x: within.x0 as i32, y: within.y0 as i32 }, extent: within.extent() };
        // SAFETY: inside the scope just begun, whose viewport and scissor the host draws with.
        unsafe { device.cmd_set_scissor(cmd, 0, &[scissor]) };
        draw(cmd, view);
        let whole_frame = vk::Rect2D { offset: vk::Offset2D::default(), extent };
        // SAFETY: the scope begun above, the host's draws recorded inside it; the scissor is
        // dynamic state of `cmd`, set back for the host's next draws.
        unsafe {
            device.cmd_end_rendering(cmd);
            device.cmd_set_scissor(cmd, 0, &[whole_frame]);
        }
        if !whole {
            // Outside the cover nothing is built: zero there (no object), on every level.
            rec.tracker.image(&images.inverse_depth, 0, levels, Access::ClearWrite, true);
            if levels > 1 {
                rec.tracker.image(&images.colour, 1, levels - 1, Access::ClearWrite, true);
            }
            rec.tracker.flush(device, cmd);
            clear_levels(device, cmd, &images.inverse_depth, 0..levels);
            clear_levels(device, cmd, &images.colour, 1..levels);
        }
        rec.tracker.image(&images.depth, 0, 1, Access::ComputeSampled, false);
        rec.tracker.image(&images.inverse_depth, 0, 1, Access::ComputeStorageWrite, whole);
        rec.tracker.flush(device, cmd);
        dispatch_within(rec, self.inverse_depth_pipeline.raw, &self.inverse_depth, within);
        mipmap_within(device, cmd, rec.tracker, &images.colour, within);
        self.mips.record_within(rec, &images.inverse_depth, within);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        rec.tracker.image(&images.colour, 0, levels, Access::ComputeSampled, false);
        rec.tracker.image(&images.inverse_depth, 0, images.inverse_depth.mip_levels, Access::ComputeSampled, false);
        rec.tracker.flush(device, cmd);
        Some((within, extent))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reflecting_point_sees_the_eye_and_the_object_at_one_elevation() {
        // The eye 3 m above a level sea (z = -3 in its own frame), an object 1 m above it 30 m off.
        let plane = (DVec3::Z, -3.0);
        let p = DVec3::new(30.0, 0.0, -2.0);
        let q = MirrorView::reflecting_point(p, plane);
        assert!((q - DVec3::new(22.5, 0.0, -3.0)).length() < 1e-12, "{q}");
        // Angle of incidence equals angle of reflection.
        let (to_eye, to_object) = ((-q).normalize(), (p - q).normalize());
        assert!((to_eye.z - to_object.z).abs() < 1e-12, "{to_eye} {to_object}");
        // A point at the water is its own.
        let at = DVec3::new(10.0, 5.0, -3.0);
        assert!((MirrorView::reflecting_point(at, plane) - at).length() < 1e-12);
    }

    #[test]
    fn a_cover_bounds_the_projections_of_its_points_and_no_more() {
        let view = MirrorView {
            clip_from_relative: Mat4::perspective_infinite_reverse_rh(1.0, 4.0 / 3.0, 0.1)
                * Mat4::look_to_rh(glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Z),
            eye_height_m: 3.0,
            planet_radius_m: 6.371e6,
        };
        let extent = vk::Extent2D { width: 400, height: 300 };
        // A box 20 m ahead: its corners' texels, grown by one, inside the image.
        let corners =
            (0..8).map(|i| DVec3::new(20.0 + (i & 1) as f64, -1.0 + (i >> 1 & 1) as f64, -4.0 + (i >> 2) as f64));
        let cover = view.cover_of(corners.clone());
        let rect = cover.pixels(extent);
        assert!(!rect.is_empty() && rect != PixelRect::whole(extent), "{rect:?}");
        let clip = view.clip_from_relative.as_dmat4();
        for c in corners {
            let p = clip * c.extend(1.0);
            let (x, y) = ((p.x / p.w * 0.5 + 0.5) * 400.0, (p.y / p.w * 0.5 + 0.5) * 300.0);
            assert!(x >= rect.x0 as f64 + 1.0 && x <= rect.x1 as f64 - 1.0, "{x} in {rect:?}");
            assert!(y >= rect.y0 as f64 + 1.0 && y <= rect.y1 as f64 - 1.0, "{y} in {rect:?}");
        }
        // A point behind the eye: no projection bounds the box, the whole image.
        assert_eq!(view.cover_of([DVec3::new(20.0, 0.0, -3.0), DVec3::new(-1.0, 0.0, -3.0)]), MirrorCover::Whole);
        // Nothing covers nothing; the union takes both; Whole absorbs.
        assert!(MirrorCover::NOTHING.pixels(extent).is_empty());
        assert_eq!(MirrorCover::NOTHING.union(cover), cover);
        assert_eq!(cover.union(MirrorCover::Whole), MirrorCover::Whole);
        // Beyond the image: clamped to it.
        let beyond = MirrorCover::Within { min: [-3.0, 0.5], max: [0.0, 7.0] };
        assert_eq!(beyond.pixels(extent), PixelRect { x0: 0, y0: 224, x1: 201, y1: 300 });
    }

    #[test]
    fn the_mirror_reflects_about_its_plane() {
        let n = DVec3::new(0.3, -0.2, 1.0).normalize();
        let w = -7.5;
        let m = MirrorView::mirror((n, w));
        let p = DVec3::new(3.0, 4.0, 5.0);
        let q = m.transform_point3(p);
        // Same distance to the plane, other side, the difference along the normal.
        assert!((n.dot(p) - w + (n.dot(q) - w)).abs() < 1e-12);
        assert!((p - q).cross(n).length() < 1e-12);
        // An involution.
        assert!((m.transform_point3(q) - p).length() < 1e-12);
    }
}
