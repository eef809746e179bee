//! The world the renderer draws, in f64: the scene a user describes, the wave trains it makes
//! and the sky that lights them. Nothing here knows about Vulkan.

pub mod atmosphere;
pub mod bvh;
pub mod environment;
pub mod floating;
pub mod fresnel;
pub mod gltf;
pub mod masking;
pub mod packets;
pub mod placement;
pub mod scene;
pub mod sky;
pub mod sky_table;
pub mod waves;
