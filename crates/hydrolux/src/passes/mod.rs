//! One folder per technique (see `registry.rs` for their frame order and
//! `technique.rs` for what each implements): sky (bake, background) →
//! particles (`simulation/whitewater/draw.rs`) → caustics →
//! geometry (shadow map, reflection/refraction views, the scene in the main
//! view) → water objects (light paths; drawn from the camera after the god
//! rays) → water (medium classification, surface) → god rays → anti-aliasing
//! (the temporal resolve) → tonemap (or a debug view). Outside the registry: `probe` (queries
//! outside the frame) and `error_view` (a frame mode).

pub mod antialias;
pub mod caustics;
pub mod geometry;
pub mod godrays;
pub mod raytrace;
pub mod sky;
pub mod tonemap;
pub mod water;
pub mod water_object;
