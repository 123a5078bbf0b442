//! The sky: `[sky]` (seed 000 §3.1): a physically based atmosphere
//! (`crate::atmosphere`) or Preetham's analytic fit.

use super::*;

/// Which model draws the sky.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SkyModel {
    /// Rayleigh, Mie and ozone over a round Earth, single scattering marched
    /// and the rest by Hillaire's multiple-scattering term: holds at every
    /// sun height, sunsets and twilight included.
    Physical,
    /// Preetham, Shirley & Smits 1999: an analytic fit, pale at a low sun.
    Preetham,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkyDesc {
    pub model: SkyModel,
    /// Atmospheric turbidity (2 = very clear, 10 = hazy): the ratio of the
    /// air's total optical depth to that of the air without aerosols.
    pub turbidity: f32,
}

impl Default for SkyDesc {
    fn default() -> Self {
        SkyDesc { model: SkyModel::Physical, turbidity: 2.5 }
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
