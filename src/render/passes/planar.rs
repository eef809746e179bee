//! The mirror pass: a host's objects drawn again, mirrored about the sea, into the ocean's
//! planar images (embed::Ocean::record_planar), for the shading pass to read the objects along
//! each pixel's reflected ray where the screen does not hold them (glsl/shade.glsl
//! planar_reflection). After the host's draws: the inverse depth of what it drew
//! (glsl/planar_inverse_depth.comp), the colour's mipmap by linear blits and the inverse depth's
//! by the same means (glsl/planar_mip.comp), so that a footprint's mean radiance, coverage and
//! harmonic mean depth are one read each. A frame the host draws no mirror into (none of its
//! objects' images is in view) skips it all: the shading pass is told by a push constant.

use super::pyramid::LevelReduction;
use super::{dispatch_over, write_frame_uniforms, Recorder};
use crate::error::Result;
use crate::render::resources::{PlanarImages, Resources, FRAME_BINDING};
use crate::shaders;
use crate::vk::barrier::Access;
use crate::vk::device::{Device, HDR_FORMAT};
use crate::vk::external::{begin_cleared_rendering, HostImage};
use crate::vk::owned::Owned;
use crate::vk::pipeline::{compute_pipeline, Bindings};
use ash::vk;
use glam::{DMat4, DVec3, Mat4};

/// The colour a host draws its mirrored objects in: radiance in its own unit, alpha 1 (the
/// objects' coverage; the image is cleared to 0).
pub const PLANAR_COLOUR_FORMAT: vk::Format = HDR_FORMAT;

/// What a host draws its objects mirrored about the sea with (embed::Ocean::record_planar),
/// inside the pass's rendering scope (viewport and scissor its frame's): colour
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
}

const MIRROR_DEPTH_BINDING: u32 = 1;
const INVERSE_DEPTH_BINDING: u32 = 2;

pub struct PlanarPass<'g> {
    inverse_depth: Bindings<'g>,
    inverse_depth_pipeline: Owned<'g, vk::Pipeline>,
    /// The coverage and inverse depth's levels from 1, each the mean of the texels below it.
    mips: LevelReduction<'g>,
}

impl PlanarPass<'_> {
    pub const NAME: &'static str = "planar reflection";
}

impl<'g> PlanarPass<'g> {
    pub fn new(device: &'g Device, r: &Resources, images: &PlanarImages) -> Result<Self> {
        use vk::DescriptorType as D;
        let compute = vk::ShaderStageFlags::COMPUTE;
        let inverse_depth = Bindings::new(
            device,
            "planar inverse depth",
            &[
                (FRAME_BINDING, D::UNIFORM_BUFFER_DYNAMIC, compute),
                (MIRROR_DEPTH_BINDING, D::COMBINED_IMAGE_SAMPLER, compute),
                (INVERSE_DEPTH_BINDING, D::STORAGE_IMAGE, compute),
            ],
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
        Ok(PlanarPass { inverse_depth, inverse_depth_pipeline, mips })
    }

    /// Clears the planar images, has `draw` record the host's mirrored objects into them with
    /// `view` (`far`: the host's far-plane depth), and builds what the shading pass reads.
    pub fn record_mirrored(
        &self,
        rec: &mut Recorder,
        r: &Resources,
        view: &MirrorView,
        far: f32,
        draw: &mut dyn FnMut(vk::CommandBuffer, &MirrorView),
    ) {
        let Some(images) = &r.planar else { return };
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        rec.tracker.image(&images.colour, 0, 1, Access::ColorAttachmentWrite, true);
        rec.tracker.image(&images.depth, 0, 1, Access::DepthAttachmentReadWrite, true);
        rec.tracker.flush(device, cmd);
        begin_cleared_rendering(device, cmd, &HostImage::from(&images.colour), &HostImage::from(&images.depth), far);
        draw(cmd, view);
        // SAFETY: the scope begun above, the host's draws recorded inside it.
        unsafe { device.cmd_end_rendering(cmd) };
        rec.tracker.image(&images.depth, 0, 1, Access::ComputeSampled, false);
        rec.tracker.image(&images.inverse_depth, 0, 1, Access::ComputeStorageWrite, true);
        rec.tracker.flush(device, cmd);
        dispatch_over(rec, self.inverse_depth_pipeline.raw, &self.inverse_depth, images.colour.extent);
        crate::vk::image::mipmap(device, cmd, rec.tracker, &images.colour);
        self.mips.record(rec, &images.inverse_depth);
        let (device, cmd) = (&rec.device.raw, rec.cmd);
        rec.tracker.image(&images.colour, 0, images.colour.mip_levels, Access::ComputeSampled, false);
        rec.tracker.image(&images.inverse_depth, 0, images.inverse_depth.mip_levels, Access::ComputeSampled, false);
        rec.tracker.flush(device, cmd);
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
