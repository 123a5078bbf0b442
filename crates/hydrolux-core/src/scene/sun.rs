//! The sun: `[sun]`.

use super::*;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SunDesc {
    /// Degrees above the horizon.
    pub elevation_deg: f32,
    /// Direction towards the sun, degrees from +x towards +z.
    pub azimuth_deg: f32,
}

impl Default for SunDesc {
    fn default() -> Self {
        SunDesc { elevation_deg: 35.0, azimuth_deg: -70.0 }
    }
}

impl SunDesc {
    /// The `[sun]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let s = self;
        range(
            "sun.elevation_deg",
            s.elevation_deg,
            (-10.0..=90.0).contains(&s.elevation_deg),
            "must be in [-10, 90]",
        )?;
        range(
            "sun.azimuth_deg",
            s.azimuth_deg,
            s.azimuth_deg.is_finite(),
            "must be a finite angle",
        )?;
        Ok(())
    }
}
