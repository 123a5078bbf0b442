//! The GPU test suite: every GPU algorithm against its CPU twin in
//! hydrolux-core, determinism, and golden images, one file per technique
//! beside one harness (`harness.rs`). tests/gpu.rs and tests/gpu_gl.rs each
//! run it on their backends; all tests share one device and use tiny sizes.

mod antialias;
mod caustics;
mod frame;
mod godrays;
mod harness;
mod liquid;
mod raytrace;
mod ripples;
mod sky;
mod surface;
mod water;
mod water_objects;
mod whitewater;
