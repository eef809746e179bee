//! Where a scene's objects stand at a time: each model's transform into the frame whose origin
//! is the eye (world axes, z up), in f64, so that an object 100 km away keeps its millimetres
//! when the GPU takes the matrix in f32.
//!
//! A model is authored as glTF has it (+y up, metres) with its bow along +x and its waterline at
//! y = 0 (scenes/models). Its attitude is applied about its own origin: roll about the bow axis
//! (the port side raised), then pitch (the bow raised), then heading (counter-clockwise from +x).
//! A floating object adds the pose the waves give its waterplane (model::floating), a rectangle
//! of its length along x and its beam along z at its origin. On the planet the object's (x, y)
//! in the plane tangent below the eye is carried straight down onto the sphere, and it stands
//! along the sphere's normal there: an object 100 km off sinks 785 m below the eye's level and
//! leans 0.9° away.

use crate::model::floating::{self, Waterplane};
use crate::model::packets::PacketField;
use crate::model::scene::{Motion, Object, Scene};
use crate::model::waves::WaveSet;
use glam::{DMat4, DQuat, DVec3};

/// glTF's axes (+y up, +z towards the starboard side of a bow along +x) into the world's (z up,
/// +y to port): a quarter turn about x.
pub fn world_axes_from_gltf() -> DMat4 {
    DMat4::from_cols_array(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
}

/// An object's placement in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Model space to the eye-relative world (metres).
    pub relative_from_model: DMat4,
    /// The object's origin, eye-relative.
    pub origin: DVec3,
    /// The sphere's normal at the object (the world's +z on a flat sea).
    pub up: DVec3,
    /// The water's plane at the object, (unit normal n, offset w) with n . x = w on it: for a
    /// floating object the plane it rides (heave, pitch and roll), for a fixed one the mean sea's.
    pub water_plane: (DVec3, f64),
}

/// The waterplane of a model whose bounds (model space, glTF axes) are `bounds`, at `scale`: its
/// extents along the bow (x) and across (z), and its draft, how far it reaches below its
/// waterline (y = 0).
pub fn waterplane(bounds: (glam::Vec3, glam::Vec3), scale: f64) -> Waterplane {
    let size = (bounds.1 - bounds.0).as_dvec3() * scale;
    Waterplane { length_m: size.x, beam_m: size.z, draft_m: (-f64::from(bounds.0.y) * scale).max(0.0) }
}

/// Where `object` (its model's waterplane `plane`) stands at time `t` under `scene`'s camera,
/// eye `eye_z` m above mean sea level, on `waves` (the scene's: their phases count from the eye)
/// and the wave packets alive at `t`, where there are any (in the same frame: PacketField::
/// relative_to the eye).
pub fn place(
    scene: &Scene,
    waves: &WaveSet,
    packets: Option<&PacketField>,
    object: &Object,
    plane: Waterplane,
    eye_z: f64,
    t: f64,
) -> Placement {
    let [x, y, z] = object.position_at(t);
    let offset = [x - scene.camera.x_m, y - scene.camera.y_m];
    let heading = object.heading_deg.to_radians();
    let pose = match object.motion {
        Motion::Floating => match packets {
            Some(field) => floating::ride_with_packets(waves, field, t, offset, heading, plane),
            None => floating::ride(waves, t, offset, heading, plane),
        },
        Motion::Fixed => floating::Pose { heave_m: 0.0, pitch_rad: 0.0, roll_rad: 0.0 },
    };
    let (pitch, roll) = (object.pitch_deg.to_radians() + pose.pitch_rad, object.roll_deg.to_radians() + pose.roll_rad);
    let r = scene.planet.radius_m;
    // The sphere's normal below the tangent point (offset, 0), the centre R below the eye's sea level.
    let up = DVec3::new(offset[0], offset[1], r).normalize();
    let centre = DVec3::new(0.0, 0.0, -r - eye_z);
    let origin = centre + up * (r + z + pose.heave_m);
    let tilt = DQuat::from_rotation_arc(DVec3::Z, up);
    // Pitch raises the bow (+x): a turn about -y.
    let attitude = |pitch: f64, roll: f64| {
        DQuat::from_rotation_z(heading) * DQuat::from_rotation_y(-pitch) * DQuat::from_rotation_x(roll)
    };
    let relative_from_model =
        DMat4::from_scale_rotation_translation(DVec3::splat(object.scale), tilt * attitude(pitch, roll), origin)
            * world_axes_from_gltf();
    // The water turns with the waves' share of the attitude only, through the waterline's centre.
    let water_normal = tilt * attitude(pose.pitch_rad, pose.roll_rad) * DVec3::Z;
    let water_plane = (water_normal, water_normal.dot(centre + up * (r + pose.heave_m)));
    Placement { relative_from_model, origin, up, water_plane }
}

/// The mean sea's tangent plane below point `p` (relative to an eye `eye_z` above the sea, on a
/// sphere of radius `radius`): its unit normal n and offset w, dot(n, x) = w on the plane.
pub fn sea_plane_below(p: DVec3, eye_z: f64, radius: f64) -> (DVec3, f64) {
    let centre = DVec3::new(0.0, 0.0, -radius - eye_z);
    let n = (p - centre).try_normalize().unwrap_or(DVec3::Z);
    (n, n.dot(centre) + radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::scene::Scene;

    fn object(position: [f64; 3]) -> Object {
        Object {
            file: "boat.gltf".into(),
            position_m: position,
            heading_deg: 0.0,
            pitch_deg: 0.0,
            roll_deg: 0.0,
            scale: 1.0,
            motion: Motion::Fixed,
            velocity_mps: [0.0, 0.0],
            start_s: None,
            hull_length_m: None,
            wake_amplitude_m: None,
            waterplane: None,
        }
    }

    #[test]
    fn a_model_stands_up_with_its_bow_along_its_heading() {
        let scene = Scene::default();
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 4.0, beam_m: 1.5, draft_m: 0.0 };
        let mut boat = object([30.0, 10.0, 0.0]);
        boat.heading_deg = 90.0;
        let p = place(&scene, &waves, None, &boat, plane, 6.0, 0.0);
        let at = |v: [f64; 3]| p.relative_from_model.transform_point3(DVec3::from(v));
        // The mast (+y in glTF) points up, the bow (+x) north, the eye 6 m above the sea.
        let base = at([0.0, 0.0, 0.0]);
        assert!((at([0.0, 1.0, 0.0]) - base - DVec3::Z).length() < 1e-4, "{:?}", at([0.0, 1.0, 0.0]) - base);
        assert!((at([1.0, 0.0, 0.0]) - base - DVec3::Y).length() < 1e-4);
        // Starboard (+z in glTF) is to the right of a bow heading north: east.
        assert!((at([0.0, 0.0, 1.0]) - base - DVec3::X).length() < 1e-4);
        // 31.6 m off, the sphere has dropped by d^2 / 2R = 0.08 mm.
        assert!((base - DVec3::new(30.0, 10.0, -6.0)).length() < 1e-3, "{base:?}");
    }

    #[test]
    fn an_object_is_mirrored_about_the_sea_below_it() {
        // 100 km off on the sphere: the tangent plane there is the sphere's, not the eye's.
        let mut scene = Scene::default();
        scene.planet.radius_m = 6.36e6;
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 4.0, beam_m: 1.5, draft_m: 0.0 };
        let buoy = object([1.0e5, 0.0, 2.0]);
        let p = place(&scene, &waves, None, &buoy, plane, 6.0, 0.0);
        let (n, w) = sea_plane_below(p.origin, 6.0, scene.planet.radius_m);
        assert!((n - p.up).length() < 1e-12, "{n} against {}", p.up);
        // The object stands 2 m above that plane, and the sea's surface below it is on it.
        assert!((n.dot(p.origin) - w - 2.0).abs() < 1e-6, "{}", n.dot(p.origin) - w);
        let sea = DVec3::new(0.0, 0.0, -scene.planet.radius_m - 6.0) + p.up * scene.planet.radius_m;
        assert!((n.dot(sea) - w).abs() < 1e-6);
    }

    #[test]
    fn the_water_plane_is_the_one_a_floating_object_rides() {
        let mut scene = Scene::default();
        scene.wind.speed_mps = 20.0;
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 8.0, beam_m: 3.0, draft_m: 0.0 };
        // Fixed, 2 m up: the mean sea's plane below it.
        let post = object([40.0, 5.0, 2.0]);
        let p = place(&scene, &waves, None, &post, plane, 6.0, 3.0);
        let (n, w) = sea_plane_below(p.origin, 6.0, scene.planet.radius_m);
        assert!((p.water_plane.0 - n).length() < 1e-12 && (p.water_plane.1 - w).abs() < 1e-6, "{:?}", p.water_plane);
        // Floating (pitched by hand too): through its origin, turned by the waves alone.
        let mut boat = object([40.0, 5.0, 0.0]);
        (boat.motion, boat.heading_deg, boat.pitch_deg) = (Motion::Floating, 30.0, 15.0);
        let p = place(&scene, &waves, None, &boat, plane, 6.0, 3.0);
        let (n, w) = p.water_plane;
        assert!((n.length() - 1.0).abs() < 1e-12 && (n.dot(p.origin) - w).abs() < 1e-6);
        let pose = floating::ride(&waves, 3.0, [40.0, 5.0], 30f64.to_radians(), plane);
        assert!(pose.heave_m.abs() > 0.05 && pose.pitch_rad.abs() > 1e-3, "a storm moves it: {pose:?}");
        assert!((n.dot(p.up).acos() - pose.pitch_rad.hypot(pose.roll_rad)).abs() < 1e-3, "{n} {pose:?}");
        // Its heave above the mean sea's plane.
        let (mean_n, mean_w) = sea_plane_below(p.origin, 6.0, scene.planet.radius_m);
        assert!((mean_n.dot(p.origin) - mean_w - pose.heave_m).abs() < 1e-6);
    }

    #[test]
    fn attitude_raises_the_bow_and_the_port_side() {
        let scene = Scene::default();
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 4.0, beam_m: 1.5, draft_m: 0.0 };
        let mut boat = object([0.0, 0.0, 0.0]);
        (boat.pitch_deg, boat.roll_deg) = (10.0, 0.0);
        let p = place(&scene, &waves, None, &boat, plane, 6.0, 0.0);
        let bow = p.relative_from_model.transform_vector3(DVec3::X);
        assert!((bow.z - 10f64.to_radians().sin()).abs() < 1e-9, "{bow:?}");
        (boat.pitch_deg, boat.roll_deg) = (0.0, 10.0);
        let p = place(&scene, &waves, None, &boat, plane, 6.0, 0.0);
        // Port is -z in glTF (+y in the world with the bow along +x).
        let port = p.relative_from_model.transform_vector3(-DVec3::Z);
        assert!((port.z - 10f64.to_radians().sin()).abs() < 1e-9, "{port:?}");
    }

    #[test]
    fn a_distant_object_sits_on_the_sphere_along_its_normal() {
        let scene = Scene::default();
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 100.0, beam_m: 20.0, draft_m: 0.0 };
        let r = scene.planet.radius_m;
        let ship = object([100e3, 0.0, 0.0]);
        let p = place(&scene, &waves, None, &ship, plane, 10.0, 0.0);
        let centre = DVec3::new(0.0, 0.0, -r - 10.0);
        assert!(((p.origin - centre).length() - r).abs() < 1e-6, "on the sphere");
        // The drop below the tangent plane: R - sqrt(R^2 - x^2) ~ x^2 / 2R, about 785 m.
        let drop = -10.0 - p.origin.z;
        assert!((drop - 100e3f64.powi(2) / (2.0 * r)).abs() < 1.0, "{drop}");
        let mast = p.relative_from_model.transform_vector3(DVec3::Y);
        assert!((mast.normalize() - p.up).length() < 1e-12);
        // A moving object: at t its origin moved by the velocity (here along the tangent plane).
        let mut moving = object([0.0, 0.0, 0.0]);
        moving.velocity_mps = [5.0, -2.0];
        let p = place(&scene, &waves, None, &moving, plane, 10.0, 4.0);
        assert!((p.origin.truncate() - glam::DVec2::new(20.0, -8.0)).length() < 1e-3, "{:?}", p.origin);
    }

    #[test]
    fn a_floating_object_takes_the_waves_pose() {
        let scene = Scene::default();
        let waves = crate::model::waves::generate(&scene);
        let plane = Waterplane { length_m: 4.0, beam_m: 1.5, draft_m: 0.0 };
        let mut buoy = object([12.0, -3.0, 0.0]);
        buoy.motion = Motion::Floating;
        let t = 2.5;
        let p = place(&scene, &waves, None, &buoy, plane, 6.0, t);
        let pose = floating::ride(&waves, t, [12.0, -3.0], 0.0, plane);
        assert!((p.origin.z + 6.0 - pose.heave_m).abs() < 1e-3, "{:?} {pose:?}", p.origin);
        let bow = p.relative_from_model.transform_vector3(DVec3::X);
        // The sphere tilts the object by 12 m / R, 2e-6 rad.
        assert!((bow.z - pose.pitch_rad.sin()).abs() < 1e-5, "{bow:?} {pose:?}");
        assert!(pose.heave_m.abs() > 1e-3, "the default sea moves a 4 m hull");
    }
}
