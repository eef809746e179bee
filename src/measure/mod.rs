//! How the product measures itself: the exact-geometry ground truth (`groundtruth`), the f64
//! CPU evaluation of the shading that tests compare the GPU with (`reference`), the shader-function
//! harness (`numerics`), the benchmarks (`bench`) and the frame-time samples they and `profile`
//! write (`samples`).

pub mod bench;
pub mod detail;
pub mod floor;
pub mod groundtruth;
pub mod numerics;
pub mod reference;
pub mod region;
pub mod samples;
pub mod truth_objects;
pub mod truth_sky;
