//! The Vulkan backend: one small file per concept. `unsafe` lives here and in the passes'
//! recording functions, each block stating the invariant it relies on.

pub mod barrier;
pub mod buffer;
pub mod clock;
pub mod commands;
pub mod device;
pub mod external;
pub mod gpu;
pub mod image;
pub mod instance;
pub mod memory;
pub mod owned;
pub mod pipeline;
pub mod pipeline_cache;
pub mod profiler;
pub mod surface;
pub mod swapchain;
pub mod sync;
pub mod validation;
