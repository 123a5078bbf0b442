//! The wave models' settings: `[ocean]` (the FFT ocean, seed 000 §2.4) and `[sines]`.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Spectrum {
    Phillips,
    PiersonMoskowitz,
    Jonswap,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OceanDesc {
    pub spectrum: Spectrum,
    /// m/s
    pub wind_speed: f32,
    /// Direction the wind blows towards, degrees from +x towards +z.
    pub wind_direction_deg: f32,
    /// km (JONSWAP)
    pub fetch_km: f32,
    /// Water depth, m (finite-depth dispersion).
    pub depth: f32,
    /// Side of the largest cascade's patch, m.
    pub patch_size: f32,
    /// FFT size N: a power of two, 64..=1024.
    pub resolution: u32,
    pub cascades: u32,
    /// Horizontal displacement scale λ.
    pub choppiness: f32,
    pub seed: u64,
    /// JONSWAP peak enhancement γ.
    pub peak_enhancement: f32,
    /// Exponent s of the cos^(2s)(θ/2) directional spreading.
    pub spreading: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SinesDesc {
    /// Number of waves (1..=64), drawn from the `[ocean]` sea state.
    pub count: u32,
    /// Gerstner choppiness, 0 (plain sines) to 1 (sharpest crests without loops).
    pub gerstner: f32,
}

impl Default for OceanDesc {
    fn default() -> Self {
        OceanDesc {
            spectrum: Spectrum::Jonswap,
            wind_speed: 9.0,
            wind_direction_deg: -80.0,
            fetch_km: 200.0,
            depth: 1000.0,
            patch_size: 400.0,
            resolution: 256,
            cascades: 3,
            choppiness: 0.9,
            seed: 1,
            peak_enhancement: 3.3,
            spreading: 8.0,
        }
    }
}

impl OceanDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]).
    pub fn apply_quality(&mut self, q: Quality) {
        if q == Quality::Low {
            self.resolution = self.resolution.min(128);
        }
    }

    /// The `[ocean]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let o = self;
        range(
            "ocean.wind_speed",
            o.wind_speed,
            (0.0..=40.0).contains(&o.wind_speed),
            "must be in [0, 40] m/s",
        )?;
        range("ocean.wind_direction_deg", o.wind_direction_deg, true, "must be a finite angle")?;
        range(
            "ocean.fetch_km",
            o.fetch_km,
            o.fetch_km > 0.0 && o.fetch_km <= 10_000.0,
            "must be in (0, 10000] km",
        )?;
        range("ocean.depth", o.depth, o.depth > 0.0, "must be > 0 m")?;
        range(
            "ocean.patch_size",
            o.patch_size,
            (1.0..=20_000.0).contains(&o.patch_size),
            "must be in [1, 20000] m",
        )?;
        if !o.resolution.is_power_of_two() || !(64..=1024).contains(&o.resolution) {
            return Err(SceneError::OutOfRange {
                key: "ocean.resolution".into(),
                value: o.resolution.to_string(),
                allowed: "must be a power of two from 64 to 1024".into(),
            });
        }
        if !(1..=4).contains(&o.cascades) {
            return Err(SceneError::OutOfRange {
                key: "ocean.cascades".into(),
                value: o.cascades.to_string(),
                allowed: "must be 1 to 4".into(),
            });
        }
        range(
            "ocean.choppiness",
            o.choppiness,
            (0.0..=3.0).contains(&o.choppiness),
            "must be in [0, 3]",
        )?;
        range(
            "ocean.peak_enhancement",
            o.peak_enhancement,
            (1.0..=10.0).contains(&o.peak_enhancement),
            "must be in [1, 10]",
        )?;
        range(
            "ocean.spreading",
            o.spreading,
            (0.0..=100.0).contains(&o.spreading),
            "must be in [0, 100]",
        )?;
        Ok(())
    }
}

impl Default for SinesDesc {
    fn default() -> Self {
        SinesDesc { count: 24, gerstner: 0.6 }
    }
}

impl SinesDesc {
    /// The `[sines]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        range(
            "sines.gerstner",
            self.gerstner,
            (0.0..=1.0).contains(&self.gerstner),
            "must be in [0, 1]",
        )?;
        Ok(())
    }
}
