//! Surface materials of the floor and the objects (`material` tables).

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Pattern {
    None,
    /// Square tiles of `tile_size` with grout lines in `pattern_color`.
    Tiles,
    Checker,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MaterialDesc {
    /// Diffuse reflectance (linear RGB); multiplies the texture.
    pub albedo: [f32; 3],
    /// PNG or JPEG image (sRGB), mapped by the mesh's texture coordinates × `uv_scale`.
    pub texture: String,
    pub uv_scale: f32,
    /// A procedural pattern in world space, on the plane facing the normal.
    pub pattern: Pattern,
    pub pattern_color: [f32; 3],
    /// Side of a tile or checker square (m).
    pub tile_size: f32,
    /// 0: opaque. Above 1: a clear refractive object of this index of
    /// refraction (1.333: water) that absorbs like the scene's water medium;
    /// it bends the sunlight into volume caustics and a caustic on what lies
    /// behind it (seed 004). For closed meshes above the water.
    pub ior: f32,
    /// Perceptual roughness of the specular lobe: 0 a mirror, 1 matte
    /// (GGX α = roughness²; `hydrolux_core::pbr`).
    pub roughness: f32,
    /// 0 a dielectric (diffuse in `albedo`, a grey reflection), 1 a metal
    /// (no diffuse part; reflects in `albedo`).
    pub metalness: f32,
    /// A dielectric's reflectance at normal incidence, F0 = 0.08 × this:
    /// 0.5 gives 4% (glass, water, paint, stone); 0 a purely Lambertian surface.
    pub specular: f32,
}

/// Fraction of a tiled surface that is grout: lines 6% of a tile wide
/// (3% each side), 1 − 0.94² (as `pattern_coverage` in lighting.wgsl).
pub const TILE_GROUT_COVER: f32 = 0.1164;

impl MaterialDesc {
    /// Its specular parameters, for the base colour `albedo`.
    pub fn surface(&self) -> crate::pbr::Surface {
        crate::pbr::Surface {
            base_color: glam::Vec3::from(self.albedo),
            roughness: self.roughness,
            metalness: self.metalness,
            specular: self.specular,
        }
    }

    /// Its diffuse reflectance averaged over its pattern (a texture counts
    /// as white), as light bounced off it far away sees it: the mean of the
    /// three channels.
    pub fn mean_albedo(&self) -> f32 {
        let second = match self.pattern {
            Pattern::None => 0.0,
            Pattern::Tiles => TILE_GROUT_COVER,
            Pattern::Checker => 0.5,
        };
        let mean = |c: [f32; 3]| (c[0] + c[1] + c[2]) / 3.0;
        (1.0 - second) * mean(self.albedo) + second * mean(self.pattern_color)
    }
}

impl Default for MaterialDesc {
    fn default() -> Self {
        MaterialDesc {
            albedo: [0.6, 0.6, 0.6],
            texture: String::new(),
            uv_scale: 1.0,
            pattern: Pattern::None,
            pattern_color: [0.1, 0.1, 0.1],
            tile_size: 0.25,
            ior: 0.0,
            roughness: 0.5,
            metalness: 0.0,
            specular: 0.5,
        }
    }
}

pub(super) fn validate_material(key: &str, m: &MaterialDesc) -> Result<(), SceneError> {
    for (name, v) in [("albedo", m.albedo), ("pattern_color", m.pattern_color)] {
        for (i, c) in v.iter().enumerate() {
            if !(0.0..=1.0).contains(c) {
                return Err(SceneError::OutOfRange {
                    key: format!("{key}.{name}[{i}]"),
                    value: c.to_string(),
                    allowed: "must be in [0, 1]".into(),
                });
            }
        }
    }
    for (name, v) in
        [("roughness", m.roughness), ("metalness", m.metalness), ("specular", m.specular)]
    {
        if !(0.0..=1.0).contains(&v) {
            return Err(SceneError::OutOfRange {
                key: format!("{key}.{name}"),
                value: v.to_string(),
                allowed: "must be in [0, 1]".into(),
            });
        }
    }
    if !(m.tile_size > 0.0 && m.tile_size.is_finite()) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.tile_size"),
            value: m.tile_size.to_string(),
            allowed: "must be > 0 m".into(),
        });
    }
    if !(m.ior == 0.0 || (1.0..=3.0).contains(&m.ior)) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.ior"),
            value: m.ior.to_string(),
            allowed: "must be 0 (opaque) or 1 to 3 (refractive)".into(),
        });
    }
    if !(m.uv_scale.is_finite() && m.uv_scale != 0.0) {
        return Err(SceneError::OutOfRange {
            key: format!("{key}.uv_scale"),
            value: m.uv_scale.to_string(),
            allowed: "must be finite and non-zero".into(),
        });
    }
    Ok(())
}
