//! What the water surface is, as every pipeline that reads it must know
//! (shared vocabulary below the framework and the techniques): its model
//! and whether interactive water is added, the pipeline constants that
//! specialise `shaders/surface.wgsl` to it, and the water mesh's rings
//! (which the frame globals carry).

use hydrolux_core::scene::{Scene, WaterModel};

/// Vertex spacing of the water mesh's finest ring, metres.
pub const BASE_SPACING: f32 = 0.25;
/// Rings that carry displacement: the outermost reaches 8·2⁸ = 2 km, where
/// waves of a few metres are below a pixel at 1080p.
pub const DISPLACED_RINGS: u32 = 9;

/// The shaders' index of a surface model (`modes.rs`, the WGSL `MODEL_*`).
pub fn model_index(model: WaterModel) -> u32 {
    crate::modes::surface_model(model)
}

/// What pipelines that draw the surface are specialised to: its model and
/// whether (and how) interactive water is added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SurfaceKind {
    pub model: WaterModel,
    /// `RIPPLES` in `surface.wgsl` (`modes::ripples`).
    pub ripples: u32,
}

impl SurfaceKind {
    pub fn of(scene: &Scene) -> Self {
        let ripples = crate::modes::ripples(scene.ripple_settings().map(|s| s.grid.boundary));
        SurfaceKind { model: scene.water.model, ripples }
    }
}

/// Pipeline constants that specialise a pipeline importing `surface` to one
/// kind (see `SURFACE_MODEL` and `RIPPLES` in `surface.wgsl`); such a
/// pipeline is rebuilt when the scene's kind changes.
pub fn specialised_to(kind: SurfaceKind) -> [(&'static str, f64); 2] {
    [("SURFACE_MODEL", model_index(kind.model) as f64), ("RIPPLES", kind.ripples as f64)]
}
