//! One module per pass, in frame order: ocean (simulate) → sky (bake) →
//! geometry (shadow map, reflection, refraction, main view; sky background
//! behind it) → water → tonemap (or a debug view); probe answers queries
//! outside the frame.

pub mod caustics;
pub mod geometry;
pub mod mips;
pub mod ocean;
pub mod probe;
pub mod sky;
pub mod tonemap;
pub mod water;
