//! The water: `[water]`, its surface model, optics, medium and method.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WaterModel {
    Fft,
    Sines,
    Flat,
    /// A user-given surface: `water.heightfield` (.npy) over `water.size`.
    Heightfield,
    /// No water body at all (a room, a stage): only objects, floor and air.
    None,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fresnel {
    Exact,
    Schlick,
    JensenGolias,
    Power,
}

/// How the light coming up out of the water is computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WaterOptics {
    /// Absorption and single scattering of the medium (seed 000 §3.3).
    Physical,
    /// Seed 002 eq. 5–6: blend towards `body_color` by e^(−d·k).
    Simple,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MediumName {
    Pure,
    ClearOcean,
    Coastal,
    TurbidHarbor,
    /// `water.absorption` and `water.scattering` as given.
    Custom,
}

/// How the refracted ray finds what it sees in the refraction texture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RefractionLookup {
    /// Seed 002 eq. 1: W = U + dv·R, dv from the refraction depth, clamped.
    Depth,
    /// Seed 000 §4.4: where the ray meets a plane `refraction_depth` below.
    Plane,
}

/// How reflected and refracted rays find what they see.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WaterMethod {
    /// Seeds 000 and 002: the scene rendered into reflection and refraction
    /// textures, looked up where the rays meet planes or depths (fast,
    /// approximate).
    Projective,
    /// Seed 003 §3.3.1 (Baboud & Décoret 2006): rays traced exactly against
    /// the ground and the water surface as heightfields (`raytrace.rs`);
    /// objects other than the ground are not in the traced rays.
    Raytrace,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WaterDesc {
    pub model: WaterModel,
    /// `model = "heightfield"`: a float32 .npy, row = z, col = x, a
    /// corner-sampled periodic grid over `size` = [Lx, Lz] m centred at the
    /// origin, mean level y = 0, tiling the plane.
    pub heightfield: String,
    pub size: [f32; 2],
    pub ior: f32,
    pub fresnel: Fresnel,
    /// Exponent q of `fresnel = "power"`: R = (1 − E·N)^q (seed 002 eq. 3).
    pub fresnel_power: f32,
    pub optics: WaterOptics,
    /// A named medium, or `custom` for `absorption` and `scattering` below
    /// (giving either of them without `medium` means `custom`).
    pub medium: MediumName,
    /// σa per channel (R, G, B), m⁻¹; used with `medium = "custom"`.
    pub absorption: [f32; 3],
    /// σs per channel (R, G, B), m⁻¹; used with `medium = "custom"`.
    pub scattering: [f32; 3],
    /// Henyey–Greenstein anisotropy g of the in-scattering (0 = isotropic).
    /// Water's particles scatter strongly forward (g ≈ 0.9), but single
    /// scattering with that peak misses the light multiple scattering sends
    /// back up: g = 0 comes closer to measured water-leaving radiance.
    pub phase_g: f32,
    /// `optics = "simple"`: colour of the water (linear RGB albedo) and its
    /// attenuation k (m⁻¹) in e^(−d·k).
    pub body_color: [f32; 3],
    pub simple_attenuation: f32,
    pub refraction: RefractionLookup,
    /// Projective lookups or ray tracing for reflections and refractions.
    pub method: WaterMethod,
    /// `method = "raytrace"`: cells per side of the water's traced
    /// heightfield over its 64 m window around the camera (a power of two,
    /// 64 to 1024: 256 is 25 cm cells); finer follows shorter waves.
    pub trace_resolution: u32,
    /// `method = "raytrace"`: the most pyramid steps one ray may take
    /// through a heightfield before it is taken to miss it (16 to 8192; on
    /// the lake's 256² terrain 600 rays down to grazing need at most 52).
    pub trace_steps: u32,
    /// `refraction = "plane"`: depth of the lookup plane (m).
    pub refraction_depth: f32,
    /// `refraction = "depth"`: clamp of dv (m).
    pub refraction_max: f32,
    /// Scale of the sub-pixel (Cox–Munk) slope variance that blurs glints and
    /// reflections: 1 for the open sea; smaller for sheltered, glassy water
    /// (lakes, pools) whose capillary ripples are weaker than the sea's at
    /// the same wind.
    pub roughness_scale: f32,
    /// Height above the mean surface of the plane the reflected ray is
    /// intersected with (m): how far the reflection moves with the waves.
    pub reflection_height: f32,
    /// Interactive water: a simulated surface (`[ripples]`) that drops,
    /// rain and the viewer disturb, added to the model's waves.
    pub dynamic: bool,
    /// Salinity (PSU: 35 the open sea, 0 fresh water): how long foam lives.
    pub salinity: f32,
}

impl WaterDesc {
    /// Whether `other` moves as this water does, for what simulates on it
    /// (white water, bodies): the same surface (its model, heightfield and
    /// size), interactive or not, and the same salinity. The optical fields
    /// (medium, Fresnel, refraction, tracing, …) only change how it is
    /// drawn: editing them live keeps the foam and spray where they are.
    pub fn moves_as(&self, other: &WaterDesc) -> bool {
        self.model == other.model
            && self.heightfield == other.heightfield
            && self.size == other.size
            && self.dynamic == other.dynamic
            && self.salinity == other.salinity
    }
}

impl Default for WaterDesc {
    fn default() -> Self {
        WaterDesc {
            model: WaterModel::Fft,
            heightfield: String::new(),
            size: [10.0, 10.0],
            ior: crate::optics::IOR_WATER,
            fresnel: Fresnel::Exact,
            fresnel_power: 5.0,
            optics: WaterOptics::Physical,
            medium: MediumName::ClearOcean,
            absorption: crate::medium::MediumPreset::ClearOcean.medium().absorption.into(),
            scattering: crate::medium::MediumPreset::ClearOcean.medium().scattering.into(),
            phase_g: 0.0,
            body_color: [0.004, 0.018, 0.028],
            simple_attenuation: 0.25,
            refraction: RefractionLookup::Depth,
            method: WaterMethod::Projective,
            trace_resolution: 256,
            trace_steps: 4096,
            refraction_depth: 2.0,
            refraction_max: 8.0,
            reflection_height: 1.5,
            roughness_scale: 1.0,
            dynamic: false,
            salinity: 35.0,
        }
    }
}

impl WaterDesc {
    /// This section as quality tier `q` renders it ([`Quality::apply`]):
    /// the traced water's cells and steps.
    pub fn apply_quality(&mut self, q: Quality) {
        match q {
            Quality::Low => {
                self.trace_resolution = self.trace_resolution.min(128);
                self.trace_steps = self.trace_steps.min(256);
            }
            Quality::Medium => {
                self.trace_resolution = self.trace_resolution.min(256);
                self.trace_steps = self.trace_steps.min(1024);
            }
            Quality::Ultra => self.trace_resolution = self.trace_resolution.max(512),
            Quality::High | Quality::Auto => {}
        }
    }

    /// The `[water]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let w = self;
        range("water.ior", w.ior, (1.0..=3.0).contains(&w.ior), "must be in [1, 3]")?;
        for (i, v) in w.body_color.iter().enumerate() {
            range(
                &format!("water.body_color[{i}]"),
                *v,
                (0.0..=1.0).contains(v),
                "must be in [0, 1]",
            )?;
        }
        if !(64..=1024).contains(&w.trace_resolution) || !w.trace_resolution.is_power_of_two() {
            return Err(SceneError::OutOfRange {
                key: "water.trace_resolution".into(),
                value: w.trace_resolution.to_string(),
                allowed: "must be a power of two from 64 to 1024".into(),
            });
        }
        if !(16..=8192).contains(&w.trace_steps) {
            return Err(SceneError::OutOfRange {
                key: "water.trace_steps".into(),
                value: w.trace_steps.to_string(),
                allowed: "must be 16 to 8192".into(),
            });
        }
        if w.model == WaterModel::Heightfield && w.heightfield.is_empty() {
            return Err(SceneError::OutOfRange {
                key: "water.heightfield".into(),
                value: "\"\"".into(),
                allowed: "must name a float32 .npy file when water.model = \"heightfield\"".into(),
            });
        }
        for (i, v) in w.size.iter().enumerate() {
            range(
                &format!("water.size[{i}]"),
                *v,
                *v > 0.0 && *v <= 100_000.0,
                "must be in (0, 100000] m",
            )?;
        }
        range(
            "water.fresnel_power",
            w.fresnel_power,
            w.fresnel_power > 0.0 && w.fresnel_power <= 50.0,
            "must be in (0, 50]",
        )?;
        for (name, v) in [("absorption", w.absorption), ("scattering", w.scattering)] {
            for (i, c) in v.iter().enumerate() {
                range(
                    &format!("water.{name}[{i}]"),
                    *c,
                    (0.0..=100.0).contains(c),
                    "must be in [0, 100] per metre",
                )?;
            }
        }
        range(
            "water.phase_g",
            w.phase_g,
            (-0.99..=0.99).contains(&w.phase_g),
            "must be in [-0.99, 0.99]",
        )?;
        range(
            "water.simple_attenuation",
            w.simple_attenuation,
            (0.0..=100.0).contains(&w.simple_attenuation),
            "must be in [0, 100] per metre",
        )?;
        range(
            "water.refraction_depth",
            w.refraction_depth,
            w.refraction_depth > 0.0 && w.refraction_depth <= 1000.0,
            "must be in (0, 1000] m",
        )?;
        range(
            "water.refraction_max",
            w.refraction_max,
            w.refraction_max > 0.0 && w.refraction_max <= 1000.0,
            "must be in (0, 1000] m",
        )?;
        range(
            "water.roughness_scale",
            w.roughness_scale,
            (0.0..=4.0).contains(&w.roughness_scale),
            "must be in [0, 4]",
        )?;
        range(
            "water.reflection_height",
            w.reflection_height,
            (0.0..=1000.0).contains(&w.reflection_height),
            "must be in [0, 1000] m",
        )?;
        range(
            "water.salinity",
            w.salinity,
            (0.0..=45.0).contains(&w.salinity),
            "must be 0 (fresh) to 45 PSU",
        )?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The optical fields do not change how the water moves; its surface,
    /// interactivity and salinity do.
    #[test]
    fn only_the_surface_and_salinity_change_how_the_water_moves() {
        let base = WaterDesc::default();
        let optical = WaterDesc {
            medium: MediumName::Coastal,
            fresnel: Fresnel::Schlick,
            ior: 1.4,
            phase_g: 0.5,
            method: WaterMethod::Raytrace,
            refraction: RefractionLookup::Plane,
            roughness_scale: 0.2,
            ..base.clone()
        };
        assert!(base.moves_as(&optical));
        for moved in [
            WaterDesc { model: WaterModel::Sines, ..base.clone() },
            WaterDesc { dynamic: true, ..base.clone() },
            WaterDesc { salinity: 0.0, ..base.clone() },
            WaterDesc { size: [4.0, 4.0], ..base.clone() },
            WaterDesc { heightfield: "h.npy".into(), ..base.clone() },
        ] {
            assert!(!base.moves_as(&moved), "{moved:?}");
        }
    }
}
