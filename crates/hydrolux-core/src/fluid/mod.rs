//! The volumetric liquid's CPU twin (issue #29, seed 003 §2.2, seed 000
//! §2.3.2): a marker-and-cell grid (`grid`), marker particles with FLIP/PIC
//! transfers (`flip`) and a pressure projection by preconditioned conjugate
//! gradients (`pressure`). The reference the GPU simulation will be checked
//! against, and itself checked against hydrostatics and volume.

pub mod coupled;
pub mod flip;
pub mod grid;
pub mod pressure;
pub mod screen_mesh;
pub mod screen_space;
pub mod solids;
pub mod surface;
pub mod white_water;

pub use coupled::{LiquidBodies, LiquidWithBodies};
pub use flip::{Emitter, Landing, LandingSurface, Liquid, LiquidSettings};
pub use grid::{Cell, MacGrid};
pub use pressure::{Projection, project};
pub use solids::{BodyLoad, LiquidBody};
pub use white_water::{Diffuse, WhiteWater, WhiteWaterSettings};

#[cfg(test)]
mod solids_tests;
#[cfg(test)]
mod surface_reference_tests;
#[cfg(test)]
mod tests;
