//! The floor: `[floor]`, flat or a terrain.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TerrainKind {
    None,
    /// A procedural basin whose shore rises out of the water.
    Noise,
    /// `heightmap` image: y = −depth + grey · relief.
    Heightmap,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FloorDesc {
    /// Depth of the floor below the mean water level (m); 0 = no floor (open ocean).
    pub depth: f32,
    pub terrain: TerrainKind,
    pub heightmap: String,
    /// Side of the terrain's square (m).
    pub size: f32,
    /// Terrain vertices per side.
    pub resolution: u32,
    /// Fractal relief (noise) or height range (heightmap), m.
    pub relief: f32,
    /// Noise basin: radius where the shore is fully risen, and its height (m).
    pub shore_radius: f32,
    pub shore_height: f32,
    pub seed: u64,
    pub material: MaterialDesc,
}

impl Default for FloorDesc {
    fn default() -> Self {
        FloorDesc {
            depth: 0.0,
            terrain: TerrainKind::None,
            heightmap: String::new(),
            size: 300.0,
            resolution: 256,
            relief: 1.5,
            shore_radius: 90.0,
            shore_height: 5.0,
            seed: 1,
            material: MaterialDesc { albedo: [0.45, 0.40, 0.32], ..MaterialDesc::default() },
        }
    }
}

impl FloorDesc {
    /// The `[floor]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let f = self;
        range(
            "floor.depth",
            f.depth,
            (0.0..=10_000.0).contains(&f.depth),
            "must be in [0, 10000] m (0 = no floor)",
        )?;
        range(
            "floor.size",
            f.size,
            f.size > 0.0 && f.size <= 100_000.0,
            "must be in (0, 100000] m",
        )?;
        if !(2..=2048).contains(&f.resolution) {
            return Err(SceneError::OutOfRange {
                key: "floor.resolution".into(),
                value: f.resolution.to_string(),
                allowed: "must be 2 to 2048".into(),
            });
        }
        range(
            "floor.relief",
            f.relief,
            (0.0..=10_000.0).contains(&f.relief),
            "must be in [0, 10000] m",
        )?;
        range("floor.shore_radius", f.shore_radius, f.shore_radius > 0.0, "must be > 0 m")?;
        range(
            "floor.shore_height",
            f.shore_height,
            f.shore_height.abs() <= 10_000.0,
            "must be in [-10000, 10000] m",
        )?;
        if f.terrain == TerrainKind::Heightmap && f.heightmap.is_empty() {
            return Err(SceneError::OutOfRange {
                key: "floor.heightmap".into(),
                value: "\"\"".into(),
                allowed: "must name a PNG or JPEG file when floor.terrain = \"heightmap\"".into(),
            });
        }
        if f.terrain != TerrainKind::None && f.depth <= 0.0 {
            return Err(SceneError::OutOfRange {
                key: "floor.depth".into(),
                value: f.depth.to_string(),
                allowed: "must be > 0 m under a terrain (the depth of its lowest point)".into(),
            });
        }
        validate_material("floor.material", &f.material)?;
        if self.material.ior != 0.0 {
            return Err(SceneError::OutOfRange {
                key: "floor.material.ior".into(),
                value: self.material.ior.to_string(),
                allowed: "must be 0: the floor is opaque".into(),
            });
        }
        Ok(())
    }
}
