//! God rays: `[godrays]` (seed 000 §4.5, seed 003 §5).

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GodRayMethod {
    /// Each photon's path in the water drawn as a line (a screen-facing
    /// ribbon) into a reduced-resolution buffer (seed 000 §4.6).
    Lines,
    /// Ray marching each pixel of the buffer through the caustic layers and
    /// the shadow map (the slices of seed 003 §4.3).
    March,
    Off,
}

/// Volume caustics under the surface: the shafts of light that the waves'
/// focusing makes visible in the water.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GodRaysDesc {
    pub method: GodRayMethod,
    /// Photons per side of the square of surface traced around the viewer (lines).
    pub photons: u32,
    /// The god-ray buffer's size as a fraction of the output.
    pub resolution: f32,
    /// How far from the eye (m) the shafts are drawn; beyond, the water's
    /// in-scattering is the uniform (unfocused) closed form.
    pub distance: f32,
    /// Samples along each pixel's ray (march, and the fog in the air).
    pub steps: u32,
    /// Light-view texels per side for refractive objects: one path of light
    /// through them per texel.
    pub object_resolution: u32,
}

impl Default for GodRaysDesc {
    fn default() -> Self {
        GodRaysDesc {
            method: GodRayMethod::Lines,
            photons: 256,
            resolution: 0.5,
            distance: 20.0,
            steps: 48,
            object_resolution: 256,
        }
    }
}

impl GodRaysDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]).
    pub fn apply_quality(&mut self, q: Quality) {
        if q == Quality::Low {
            self.resolution = self.resolution.min(0.25);
        }
    }

    /// The `[godrays]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let g = self;
        if !(4..=2048).contains(&g.photons) {
            return Err(SceneError::OutOfRange {
                key: "godrays.photons".into(),
                value: g.photons.to_string(),
                allowed: "must be 4 to 2048 (per side)".into(),
            });
        }
        range(
            "godrays.resolution",
            g.resolution,
            g.resolution > 0.0 && g.resolution <= 1.0,
            "must be > 0 and at most 1 (a fraction of the output size)",
        )?;
        range(
            "godrays.distance",
            g.distance,
            g.distance > 0.0 && g.distance <= 1000.0,
            "must be > 0 and at most 1000 m",
        )?;
        if !(4..=512).contains(&g.steps) {
            return Err(SceneError::OutOfRange {
                key: "godrays.steps".into(),
                value: g.steps.to_string(),
                allowed: "must be 4 to 512".into(),
            });
        }
        if !(16..=2048).contains(&g.object_resolution) {
            return Err(SceneError::OutOfRange {
                key: "godrays.object_resolution".into(),
                value: g.object_resolution.to_string(),
                allowed: "must be 16 to 2048".into(),
            });
        }
        Ok(())
    }
}
