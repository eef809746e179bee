//! Ocean: a Vulkan renderer of Bruneton, Neyret & Holzschuch, "Real-time Realistic Ocean
//! Lighting using Seamless Transitions from Geometry to BRDF" (Eurographics 2010).
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]

// The layers, from the bottom: the Vulkan backend; the world in f64 (scene, waves, sky); the
// frame and its passes; measurements (ground truth, the f64 reference, the shader harness, the
// benches); what reaches the user (files, progress, plots); the commands.
pub mod vk;

pub mod model;

pub mod render;

pub mod measure;

pub mod output;

pub mod app;

pub mod window;

pub mod embed;

pub mod error;

/// SPIR-V of every shader in glsl/, compiled by build.rs.
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

pub use error::{Error, Result};
