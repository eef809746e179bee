//! Ocean: a Vulkan renderer of Bruneton, Neyret & Holzschuch, "Real-time Realistic Ocean
//! Lighting using Seamless Transitions from Geometry to BRDF" (Eurographics 2010).
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]

// The layers, from the bottom: the Vulkan backend (`vk`); the world in f64 (`model`: scene,
// waves, sky); the renderer, its frame and passes (`render`); the library's public surface,
// which a host's frame draws through (`embed`); measurements (`measure`: ground truth, the f64
// reference, the shader harness, the benches); what reaches the user (`output`: files,
// progress, plots); the applications on top, hosts of `embed` like any other (`app`: render,
// animate, profile, and the window of `view`).
pub mod vk;

pub mod model;

pub mod render;

pub mod embed;

pub mod measure;

pub mod output;

pub mod app;

pub mod error;

/// SPIR-V of every shader in glsl/, compiled by build.rs.
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

pub use error::{Error, Result};
