//! Scene description: what a TOML scene file (or a built-in) says, typed,
//! with defaults for everything, and the loading / override / validation
//! rules in [`load`].

mod builtin;
mod load;

pub use builtin::{BUILTIN_SCENES, BuiltinScene};
pub use load::{SceneError, apply_override, parse_override};

use crate::camera::Camera;
use crate::optics::FresnelMode;
use crate::waves::ocean::OceanSettings;
use crate::waves::spectrum::{SeaState, SpectrumKind};
use serde::{Deserialize, Serialize};

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// One line saying what the scene shows (listed by `hydrolux scenes`).
    pub description: String,
    pub camera: CameraDesc,
    pub sun: SunDesc,
    pub sky: SkyDesc,
    pub ocean: OceanDesc,
    pub water: WaterDesc,
    pub sines: SinesDesc,
    pub render: RenderDesc,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraDesc {
    pub position: [f32; 3],
    pub look_at: [f32; 3],
    pub up: [f32; 3],
    pub fov_y_deg: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SunDesc {
    /// Degrees above the horizon.
    pub elevation_deg: f32,
    /// Direction towards the sun, degrees from +x towards +z.
    pub azimuth_deg: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SkyDesc {
    /// Atmospheric turbidity of the Preetham sky (2 = very clear, 10 = hazy).
    pub turbidity: f32,
}

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

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WaterModel {
    Fft,
    Sines,
    Flat,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Fresnel {
    Exact,
    Schlick,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WaterDesc {
    pub model: WaterModel,
    pub ior: f32,
    pub fresnel: Fresnel,
    /// Diffuse reflectance of the deep water body (linear RGB): the light
    /// scattered back up out of the water.
    pub body_color: [f32; 3],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SinesDesc {
    /// Number of waves (1..=64), drawn from the `[ocean]` sea state.
    pub count: u32,
    /// Gerstner choppiness, 0 (plain sines) to 1 (sharpest crests without loops).
    pub gerstner: f32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tonemap {
    Aces,
    Clamp,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderDesc {
    /// Photographic exposure, EV100 (sunny day ≈ 15).
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// Anisotropic filtering of the wave textures: 1–16, or 0 = automatic
    /// (16 on GPUs, 1 on CPU adapters such as lavapipe, where each extra tap
    /// is paid in full: 16× costs ~1000× the frame time there).
    pub anisotropy: u32,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            description: String::new(),
            camera: CameraDesc::default(),
            sun: SunDesc::default(),
            sky: SkyDesc::default(),
            ocean: OceanDesc::default(),
            water: WaterDesc::default(),
            sines: SinesDesc::default(),
            render: RenderDesc::default(),
        }
    }
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc { position: [0.0, 6.0, 0.0], look_at: [0.0, 2.0, -60.0], up: [0.0, 1.0, 0.0], fov_y_deg: 55.0 }
    }
}

impl Default for SunDesc {
    fn default() -> Self {
        SunDesc { elevation_deg: 35.0, azimuth_deg: -70.0 }
    }
}

impl Default for SkyDesc {
    fn default() -> Self {
        SkyDesc { turbidity: 2.5 }
    }
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

impl Default for WaterDesc {
    fn default() -> Self {
        WaterDesc { model: WaterModel::Fft, ior: crate::optics::IOR_WATER, fresnel: Fresnel::Exact, body_color: [0.004, 0.018, 0.028] }
    }
}

impl Default for SinesDesc {
    fn default() -> Self {
        SinesDesc { count: 24, gerstner: 0.6 }
    }
}

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc { exposure: 14.5, tonemap: Tonemap::Aces, anisotropy: 0 }
    }
}

impl Scene {
    pub fn camera(&self) -> Camera {
        Camera {
            position: self.camera.position.into(),
            look_at: self.camera.look_at.into(),
            up: self.camera.up.into(),
            fov_y_deg: self.camera.fov_y_deg,
        }
    }

    pub fn sun_direction(&self) -> glam::Vec3 {
        crate::sky::sun_direction(self.sun.elevation_deg, self.sun.azimuth_deg)
    }

    pub fn sea_state(&self) -> SeaState {
        let o = &self.ocean;
        SeaState {
            kind: match o.spectrum {
                Spectrum::Phillips => SpectrumKind::Phillips,
                Spectrum::PiersonMoskowitz => SpectrumKind::PiersonMoskowitz,
                Spectrum::Jonswap => SpectrumKind::Jonswap,
            },
            wind_speed: o.wind_speed as f64,
            wind_direction: (o.wind_direction_deg as f64).to_radians(),
            fetch: o.fetch_km as f64 * 1000.0,
            depth: o.depth as f64,
            peak_enhancement: o.peak_enhancement as f64,
            spreading: o.spreading as f64,
        }
    }

    pub fn ocean_settings(&self) -> OceanSettings {
        let o = &self.ocean;
        OceanSettings {
            sea: self.sea_state(),
            patch_size: o.patch_size as f64,
            resolution: o.resolution as usize,
            cascades: o.cascades as usize,
            choppiness: o.choppiness as f64,
            seed: o.seed,
        }
    }

    pub fn fresnel_mode(&self) -> FresnelMode {
        match self.water.fresnel {
            Fresnel::Exact => FresnelMode::Exact,
            Fresnel::Schlick => FresnelMode::Schlick,
        }
    }

    /// The scene as a TOML table (for editing and for `--set` merging).
    pub fn to_table(&self) -> toml::Table {
        toml::Table::try_from(self).expect("a Scene always serialises to TOML")
    }
}
