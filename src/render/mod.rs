//! One frame on the GPU: what the CPU hands the shaders (`frame`), the images and buffers
//! between passes (`resources`), the passes themselves (`passes`), what a scene needs
//! (`specialize`) and the renderer that records and submits them (`renderer`).

pub mod footprint;
pub mod frame;
pub mod passes;
pub mod renderer;
pub mod resources;
pub mod specialize;
