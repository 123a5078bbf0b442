//! Caustics: `[caustics]` (seed 000 §4.4, seed 001).

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CausticMethod {
    /// Photon splatting from the light (seed 000 §4.5).
    Photons,
    /// Each surface triangle projected along its refracted rays onto the
    /// floor, irradiance from the area ratio (seed 003 §4.2, eq. 28).
    Beam,
    /// Seed 001's backward lookup through the wave normal: cheap, not
    /// energy-conserving.
    Procedural,
    Off,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CausticsDesc {
    pub method: CausticMethod,
    /// Photons per side of the surface patch (photons² in all).
    pub photons: u32,
    /// Cells per side of the floor caustic map over the patch.
    pub map_resolution: u32,
    /// Horizontal layers from the surface down to the floor, each with its
    /// own caustic map: receivers between them (objects, terrain) see the
    /// caustics focused for their depth. The last layer is the floor.
    pub layers: u32,
}

impl Default for CausticsDesc {
    fn default() -> Self {
        CausticsDesc {
            method: CausticMethod::Photons,
            photons: 512,
            map_resolution: 256,
            layers: 8,
        }
    }
}

impl CausticsDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]).
    pub fn apply_quality(&mut self, q: Quality) {
        match q {
            Quality::Low => {
                self.photons = self.photons.min(128);
                self.map_resolution = self.map_resolution.min(128);
                self.layers = self.layers.min(2);
            }
            Quality::Medium => {
                self.photons = self.photons.min(256);
                self.map_resolution = self.map_resolution.min(256);
            }
            Quality::Ultra => {
                self.map_resolution = self.map_resolution.max(512);
                self.photons = self.photons.max(1024);
            }
            Quality::High | Quality::Auto => {}
        }
    }

    /// The `[caustics]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let c = self;
        if !(16..=4096).contains(&c.photons) {
            return Err(SceneError::OutOfRange {
                key: "caustics.photons".into(),
                value: c.photons.to_string(),
                allowed: "must be 16 to 4096 (per side)".into(),
            });
        }
        if !(1..=32).contains(&c.layers) {
            return Err(SceneError::OutOfRange {
                key: "caustics.layers".into(),
                value: c.layers.to_string(),
                allowed: "must be 1 to 32".into(),
            });
        }
        if !(16..=2048).contains(&c.map_resolution) {
            return Err(SceneError::OutOfRange {
                key: "caustics.map_resolution".into(),
                value: c.map_resolution.to_string(),
                allowed: "must be 16 to 2048".into(),
            });
        }
        Ok(())
    }
}
