//! One module per pass, in frame order: ocean (simulate) → sky (bake) →
//! caustics → geometry (shadow map, offscreen reflection/refraction views) →
//! water (medium classification) → sky background, geometry and water in the
//! main view → god rays → refractive objects (water_object, which also
//! works from the light before the main view) → tonemap (or a debug view); probe answers queries outside the
//! frame.

pub mod caustics;
pub mod geometry;
pub mod godrays;
pub mod mips;
pub mod ocean;
pub mod probe;
pub mod sky;
pub mod surface;
pub mod tonemap;
pub mod water;
pub mod water_object;
