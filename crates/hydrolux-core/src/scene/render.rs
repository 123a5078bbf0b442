//! How a frame is drawn: `[render]`, quality tiers and debug views.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tonemap {
    Aces,
    Clamp,
}

/// How edges are kept from aliasing (`hydrolux_core::antialias`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Antialias {
    /// Sub-pixel jitter resolved over frames, reprojected by depth; the
    /// debug views are drawn without it.
    Temporal,
    Off,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderDesc {
    /// Photographic exposure, EV100 (sunny day ≈ 15).
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// Anti-aliasing of the final image, at every quality tier.
    pub antialias: Antialias,
    /// Anisotropic filtering of the wave textures: 1–16, or 0 = automatic
    /// (16 on GPUs, 1 on CPU adapters such as lavapipe, where each extra tap
    /// is paid in full: 16× costs ~1000× the frame time there).
    pub anisotropy: u32,
    /// What to show: the final image or an intermediate texture.
    pub view: DebugView,
    /// Side of the sun's shadow map (texels).
    pub shadow_resolution: u32,
    /// Reflection and refraction textures' size as a fraction of the output.
    pub reflection_resolution: f32,
    /// Field-of-view widening of the reflection and refraction textures
    /// (0.5 = 50% wider, seed 002 §3).
    pub fov_margin: f32,
    /// Quality tier (`Quality`): caps on the costly settings and the
    /// internal rendering resolution; `auto` picks by adapter.
    pub quality: Quality,
    /// Not a key: set on the error view's second drawing of a liquid
    /// without surface water, which shows the liquid meshed by marching
    /// cubes on the finest grid (the renderer's `error_view::traced`).
    #[serde(skip)]
    pub surface_reference: bool,
}

/// What a quality tier keeps; see [`Quality::apply`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quality {
    /// `low` on CPU adapters (software rasterisers), `high` on GPUs.
    Auto,
    Low,
    Medium,
    High,
    Ultra,
}

impl Quality {
    /// The tier for an adapter: `auto` resolved (`cpu`: a software adapter).
    pub fn resolve(self, cpu: bool) -> Quality {
        match self {
            Quality::Auto if cpu => Quality::Low,
            Quality::Auto => Quality::High,
            q => q,
        }
    }

    /// Fraction of the output's pixels per side the frame is rendered at
    /// (then filtered up to the output by the tone map).
    pub fn render_scale(self) -> f32 {
        match self {
            Quality::Low => 0.5,
            Quality::Medium => 0.75,
            _ => 1.0,
        }
    }

    /// `scene` as this (resolved) tier renders it: each section applies its
    /// own caps (`apply_quality`, beside its `validate`). `high` is the scene
    /// as written. Lower tiers cap what costs most per frame; `ultra` raises
    /// the floors of the textures that alias first:
    /// - low: caustics ≤ 128 photons per side on ≤ 128² maps, ≤ 2 layers;
    ///   traced water ≤ 128 cells, ≤ 256 steps a ray;
    ///   shadow map ≤ 1024²; reflections ≤ 0.25× the output; god rays ≤ ¼
    ///   resolution; ocean N ≤ 128; interactive water ≤ 64 cells; foam ≤ 128
    ///   cells, ≤ 16k particles, ≤ 10 steps/s over ≤ 6 s of memory; ½ resolution.
    ///   The interactive water is never coarser than what its drops and the
    ///   pointer's crater need ([`Scene::ripple_cells_needed`]).
    /// - medium: caustics ≤ 256 photons on ≤ 256² maps; shadow map ≤ 2048²;
    ///   traced water ≤ 256 cells, ≤ 1024 steps a ray;
    ///   interactive water ≤ 128 cells; ≤ 64k particles; ¾ resolution.
    /// - ultra: caustic maps ≥ 512², photons ≥ 1024 per side, shadow map
    ///   ≥ 4096², reflections at the output's resolution, ≥ 1M particles,
    ///   traced water ≥ 512 cells (12.5 cm),
    ///   foam ≥ 512 cells.
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        s.caustics.apply_quality(self);
        s.water.apply_quality(self);
        s.render.apply_quality(self);
        s.godrays.apply_quality(self);
        s.ocean.apply_quality(self);
        s.ripples.apply_quality(self, scene.ripple_cells_needed());
        s.whitewater.apply_quality(self);
        s
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DebugView {
    Final,
    Reflection,
    Refraction,
    Depth,
    Normals,
    Shadow,
    /// Each pixel's medium (air or water) from the stencil classification.
    Medium,
    /// The floor caustic map (over the patch, letterboxed).
    Caustics,
    /// The interactive water's height on the surface (red up, blue down,
    /// on a signed log scale from 0.5 mm to 0.5 m), shaded by its slopes; the rest in grey.
    Ripples,
    /// The foam's cover on the surface (white), over the water in grey.
    Foam,
    /// The water's Fresnel reflectance per pixel in red, the water marked by
    /// green = 1 (the rest grey): `hydrolux compare` reads it to split its
    /// error into reflection- and refraction-dominated pixels.
    Fresnel,
    /// The volumetric liquid's particles coloured by speed (blue at rest,
    /// through green and yellow, to red at 3 m/s and over); the rest as
    /// rendered.
    Fluid,
    /// What the projective approximations cost (issue #16's truth mode):
    /// the frame drawn both ways, projective and ray traced, and per pixel
    /// their CIELAB difference ΔE*ab as heat (black 0, red 10, yellow 20,
    /// white 40).
    Error,
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            exposure: 14.5,
            tonemap: Tonemap::Aces,
            antialias: Antialias::Temporal,
            anisotropy: 0,
            view: DebugView::Final,
            shadow_resolution: 2048,
            reflection_resolution: 0.5,
            fov_margin: 0.5,
            quality: Quality::Auto,
            surface_reference: false,
        }
    }
}

impl RenderDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]):
    /// the shadow map and the reflections' texel density.
    pub fn apply_quality(&mut self, q: Quality) {
        match q {
            Quality::Low => {
                self.shadow_resolution = self.shadow_resolution.min(1024);
                self.reflection_resolution = self.reflection_resolution.min(0.25);
            }
            Quality::Medium => self.shadow_resolution = self.shadow_resolution.min(2048),
            Quality::Ultra => {
                self.shadow_resolution = self.shadow_resolution.max(4096);
                self.reflection_resolution = 1.0;
            }
            Quality::High | Quality::Auto => {}
        }
    }

    /// The `[render]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let r = self;
        if self.anisotropy > 16 {
            return Err(SceneError::OutOfRange {
                key: "render.anisotropy".into(),
                value: self.anisotropy.to_string(),
                allowed: "must be 0 (automatic) or 1 to 16".into(),
            });
        }
        range(
            "render.exposure",
            self.exposure,
            (-10.0..=30.0).contains(&self.exposure),
            "must be in [-10, 30] EV",
        )?;
        if !(256..=8192).contains(&r.shadow_resolution) {
            return Err(SceneError::OutOfRange {
                key: "render.shadow_resolution".into(),
                value: r.shadow_resolution.to_string(),
                allowed: "must be 256 to 8192".into(),
            });
        }
        range(
            "render.reflection_resolution",
            r.reflection_resolution,
            r.reflection_resolution > 0.05 && r.reflection_resolution <= 1.0,
            "must be in (0.05, 1]",
        )?;
        range(
            "render.fov_margin",
            r.fov_margin,
            (0.0..=2.0).contains(&r.fov_margin),
            "must be in [0, 2]",
        )?;
        Ok(())
    }
}
