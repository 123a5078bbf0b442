//! The sky: `[sky]` (seed 000 §3.1, Preetham).

use super::*;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkyDesc {
    /// Atmospheric turbidity of the Preetham sky (2 = very clear, 10 = hazy).
    pub turbidity: f32,
}

impl Default for SkyDesc {
    fn default() -> Self {
        SkyDesc { turbidity: 2.5 }
    }
}

impl SkyDesc {
    /// The `[sky]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        range(
            "sky.turbidity",
            self.turbidity,
            (1.7..=10.0).contains(&self.turbidity),
            "must be in [1.7, 10]",
        )?;
        Ok(())
    }
}
