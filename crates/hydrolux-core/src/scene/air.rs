//! The air: `[air]`, fog over the water.

use super::*;

/// The air as a participating medium: a light, grey fog (no absorption).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AirDesc {
    /// Scattering coefficient of the fog (m⁻¹); 0 = clear air.
    pub fog: f32,
    /// Henyey–Greenstein anisotropy of the fog's scattering.
    pub fog_g: f32,
    /// The fog fills this many metres around the eye (a room); beyond it the
    /// air is clear.
    pub fog_distance: f32,
    /// How much of the sky lights the fog: 1 outdoors, less in a room whose
    /// walls hide most of it (the sun's part is shadowed separately).
    pub fog_sky: f32,
}

impl Default for AirDesc {
    fn default() -> Self {
        AirDesc { fog: 0.0, fog_g: 0.3, fog_distance: 40.0, fog_sky: 1.0 }
    }
}

impl AirDesc {
    /// The `[air]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let a = self;
        range("air.fog", a.fog, (0.0..=1.0).contains(&a.fog), "must be 0 to 1 per metre")?;
        range(
            "air.fog_g",
            a.fog_g,
            a.fog_g > -1.0 && a.fog_g < 1.0,
            "must be in the open interval (-1, 1)",
        )?;
        range("air.fog_sky", a.fog_sky, (0.0..=1.0).contains(&a.fog_sky), "must be 0 to 1")?;
        range(
            "air.fog_distance",
            a.fog_distance,
            a.fog_distance > 0.0 && a.fog_distance <= 10_000.0,
            "must be > 0 and at most 10000 m",
        )?;
        Ok(())
    }
}
