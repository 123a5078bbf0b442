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
        // Preetham's fit holds from 1.7; the atmosphere's air is clean at 1.
        let (low, allowed) = match self.model {
            SkyModel::Physical => (1.0, "must be in [1, 10] (1: air without aerosols)"),
            SkyModel::Preetham => (1.7, "must be in [1.7, 10] for the Preetham sky"),
        };
        range("sky.turbidity", self.turbidity, (low..=10.0).contains(&self.turbidity), allowed)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turbidity_runs_down_to_clean_air_for_the_atmosphere_only() {
        let physical = SkyDesc { model: SkyModel::Physical, turbidity: 1.2 };
        assert!(physical.validate().is_ok());
        let preetham = SkyDesc { model: SkyModel::Preetham, turbidity: 1.2 };
        let e = preetham.validate().unwrap_err().to_string();
        assert!(e.contains("sky.turbidity") && e.contains("1.7"), "{e}");
        assert!(SkyDesc { turbidity: 0.9, ..physical }.validate().is_err());
    }
}
