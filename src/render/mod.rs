//! One frame on the GPU: what the CPU hands the shaders (`frame`), the images and buffers
//! between passes (`resources`), the passes themselves (`passes`), what a scene needs
//! (`specialize`), the sun's view of the sea for its shadows (`sun_shadow`), the frame's wave
//! packets (`packets`) and the part of the sea they are binned over (`packet_view`), the per-frame-in-flight slots (`in_flight`) and the renderer that records
//! and submits frames to a target (`renderer`), and a frame's CPU and GPU spans on one clock
//! (`timeline`).

pub mod footprint;
pub mod frame;
pub mod in_flight;
pub mod packet_view;
pub mod packets;
pub mod passes;
pub mod renderer;
pub mod resources;
pub mod specialize;
pub mod sun_shadow;
pub mod timeline;
