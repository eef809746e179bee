//! Ocean: a Vulkan renderer of Bruneton, Neyret & Holzschuch, "Real-time Realistic Ocean
//! Lighting using Seamless Transitions from Geometry to BRDF" (Eurographics 2010).
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]

pub mod app;
pub mod bench;
pub mod error;
pub mod frame;
pub mod groundtruth;
pub mod numerics;
pub mod output;
pub mod passes;
pub mod reference;
pub mod renderer;
pub mod report;
pub mod resources;
pub mod scene;
pub mod sky;
pub mod specialize;
pub mod vk;
pub mod waves;

/// SPIR-V of every shader in glsl/, compiled by build.rs.
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}

pub use error::{Error, Result};
