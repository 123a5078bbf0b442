//! Hydrolux without a GPU: the optics, wave physics, sky model and scene
//! description that the renderer implements on the GPU, and a CPU reference
//! ("twin") of every GPU algorithm, so each can be tested against the other.

pub mod antialias;
pub mod atmosphere;
pub mod bodies;
pub mod camera;
pub mod caustics;
pub mod clock;
pub mod compare;
pub mod coupling;
pub mod files;
pub mod fluid;
pub mod fuzz;
pub mod geometry;
pub mod godrays;
pub mod irradiance;
pub mod medium;
pub mod npy;
pub mod occlusion;
pub mod optics;
pub mod path;
pub mod pbr;
pub mod projective;
pub mod raytrace;
pub mod rng;
pub mod scene;
pub mod sky;
pub mod tonemap;
pub mod water_object;
pub mod waves;
pub mod whitewater;

pub use glam;
