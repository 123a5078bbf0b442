//! Scene description: what a TOML scene file (or a built-in) says, typed,
//! with defaults for everything, and the loading / override / validation
//! rules in [`load`].

mod air;
mod builtin;
mod camera;
mod caustics;
mod choices;
mod floor;
mod fluid;
mod geometry;
mod godrays;
mod load;
mod material;
mod objects;
mod ocean;
mod render;
mod ripples;
mod rules;
mod sky;
mod sun;
mod water;
mod whitewater;

pub use air::*;
pub use camera::*;
pub use caustics::*;
pub use floor::*;
pub use fluid::{
    FluidDesc, FluidSource, FluidSourceKind, FluidSurface, MAX_FLUID_CELLS, MAX_FLUID_DRAINS,
    MAX_FLUID_NOZZLES, MAX_LIQUID_BODIES, MAX_SURFACE_RESOLUTION, SurfaceField, is_fluid_solid,
};
pub use godrays::*;
pub use material::*;
pub use objects::*;
pub use ocean::*;
pub use render::*;
pub use sky::*;
pub use sun::*;
pub use water::*;

pub use builtin::{BUILTIN_SCENES, BuiltinScene};
pub use choices::{Choice, enumerated_keys};
pub use geometry::{FLOOR_EXTENT, SceneObject};
pub use load::{apply_override, parse_override};
use material::validate_material;
pub use ripples::{
    BODY_MEMORY_S, CLOCK_HZ, DropDesc, EmitterDesc, MAX_DROPS_PER_STEP, POINTER_RADIUS,
    RippleEdges, RipplesDesc,
};
pub use rules::{MAX_OBJECTS, SceneError, WORLD_EXTENT_M};
use rules::{range, vec3_range};
pub use whitewater::WhitewaterDesc;

use crate::camera::Camera;
use crate::medium::Medium;
use crate::optics::FresnelMode;
use crate::waves::ocean::OceanSettings;
use crate::waves::spectrum::{SeaState, SpectrumKind};
use serde::{Deserialize, Serialize};

/// The latest `start_time` a scene may set (s).
pub const MAX_START_TIME_S: f64 = 3600.0;
/// Modes of the FFT sea floating bodies read (~99% of its height variance).
pub const FLOATING_WAVES: usize = 1024;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    /// One line saying what the scene shows (listed by `hydrolux scenes`).
    pub description: String,
    /// Simulated time (s) the scene opens at where no time is given
    /// (`render` without `--time`, the viewer, the web page, `bench`
    /// without `--start`): where what it shows is under way (a wake, a
    /// splash, breaking seas). 0 to [`MAX_START_TIME_S`].
    pub start_time: f64,
    pub camera: CameraDesc,
    pub sun: SunDesc,
    pub sky: SkyDesc,
    pub ocean: OceanDesc,
    pub water: WaterDesc,
    pub sines: SinesDesc,
    pub render: RenderDesc,
    pub floor: FloorDesc,
    pub caustics: CausticsDesc,
    pub godrays: GodRaysDesc,
    pub air: AirDesc,
    /// The interactive water's simulation (with `water.dynamic = true`).
    pub ripples: RipplesDesc,
    /// Foam, bubbles and spray (`[whitewater]`).
    pub whitewater: WhitewaterDesc,
    /// The volumetric liquid (`[fluid]`, `[[fluid.sources]]`).
    pub fluid: FluidDesc,
    /// `[[objects]]` entries: meshes and primitives with a transform and material.
    pub objects: Vec<ObjectDesc>,
    /// `[[drops]]`: scripted disturbances of the interactive water.
    pub drops: Vec<DropDesc>,
    /// `[[emitters]]`: rain on the interactive water.
    pub emitters: Vec<EmitterDesc>,
    /// Folder that relative mesh, texture and heightmap paths start from (the
    /// scene file's folder; the working directory for built-ins).
    #[serde(skip)]
    pub base_dir: std::path::PathBuf,
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            description: String::new(),
            start_time: 0.0,
            camera: CameraDesc::default(),
            sun: SunDesc::default(),
            sky: SkyDesc::default(),
            ocean: OceanDesc::default(),
            water: WaterDesc::default(),
            sines: SinesDesc::default(),
            render: RenderDesc::default(),
            floor: FloorDesc::default(),
            caustics: CausticsDesc::default(),
            godrays: GodRaysDesc::default(),
            air: AirDesc::default(),
            ripples: RipplesDesc::default(),
            whitewater: WhitewaterDesc::default(),
            fluid: FluidDesc::default(),
            objects: Vec::new(),
            drops: Vec::new(),
            emitters: Vec::new(),
            base_dir: std::path::PathBuf::new(),
        }
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

    /// The sky's parameters for this scene's sun, model and turbidity.
    pub fn sky_params(&self) -> crate::sky::SkyParams {
        let (sun, t) = (self.sun_direction(), self.sky.turbidity);
        match self.sky.model {
            SkyModel::Physical => crate::sky::SkyParams::physical(sun, t),
            SkyModel::Preetham => crate::sky::SkyParams::new(sun, t),
        }
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

    /// The waves a body floats on, as the surface model draws them: the
    /// sines themselves, or the FFT sea's [`FLOATING_WAVES`] strongest
    /// modes (`OceanSpectrum::strongest_waves`). `None` where the surface
    /// model has no waves (flat water, a user's still heightfield).
    pub fn floating_waves(&self) -> Option<crate::waves::sines::SineWaves> {
        match self.water.model {
            WaterModel::Sines => Some(crate::waves::sines::SineWaves::from_sea_state(
                &self.sea_state(),
                self.sines.count as usize,
                self.ocean.seed,
                self.sines.gerstner as f64,
            )),
            WaterModel::Fft => Some(
                crate::waves::ocean::OceanSpectrum::new(&self.ocean_settings())
                    .strongest_waves(FLOATING_WAVES),
            ),
            _ => None,
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
            Fresnel::JensenGolias => FresnelMode::JensenGolias,
            Fresnel::Power => FresnelMode::Power(self.water.fresnel_power),
        }
    }

    /// The water body's coefficients: the named preset's, or the custom ones.
    pub fn medium(&self) -> Medium {
        use crate::medium::MediumPreset as P;
        let preset = match self.water.medium {
            MediumName::Pure => P::Pure,
            MediumName::ClearOcean => P::ClearOcean,
            MediumName::Coastal => P::Coastal,
            MediumName::TurbidHarbor => P::TurbidHarbor,
            MediumName::Custom => {
                return Medium {
                    absorption: self.water.absorption.into(),
                    scattering: self.water.scattering.into(),
                };
            }
        };
        preset.medium()
    }

    /// Load `water.heightfield` (for `water.model = "heightfield"`).
    pub fn load_heightfield(
        &self,
    ) -> Result<crate::waves::heightfield::Heightfield, crate::geometry::load::AssetError> {
        let path = self.resolve_path(&self.water.heightfield);
        let fail = |reason: String| crate::geometry::load::AssetError {
            what: "heightfield",
            path: path.display().to_string(),
            reason,
        };
        let bytes = crate::files::read_bounded(&path, crate::files::limits::NPY).map_err(fail)?;
        let (rows, cols, heights) = crate::npy::decode_f32_2d(&bytes).map_err(fail)?;
        if rows < 2 || cols < 2 {
            return Err(fail(format!("it must be at least 2×2, not {rows}×{cols}")));
        }
        Ok(crate::waves::heightfield::Heightfield {
            nx: cols,
            nz: rows,
            size: self.water.size,
            heights,
        })
    }

    /// Whether the scene has a water body (`water.model` is not "none").
    pub fn has_water(&self) -> bool {
        self.water.model != WaterModel::None
    }

    /// Whether the floor gets caustics: a water body over a floor, a
    /// caustics method, and the sun up. The renderer's frame plan and the
    /// CLI's dump checks both ask this.
    pub fn has_caustics(&self) -> bool {
        self.has_water()
            && self.caustics.method != CausticMethod::Off
            && self.floor.depth > 0.0
            && self.sun_direction().y > 0.0
    }

    /// The periodic patch the caustic map covers (m): the heightfield's, or
    /// the largest FFT cascade's.
    pub fn surface_patch(&self) -> [f32; 2] {
        if self.water.model == WaterModel::Heightfield {
            self.water.size
        } else if self.water.model == WaterModel::Flat && self.water.dynamic {
            // Flat water's only waves are the interactive water's: the
            // patch is its domain (around the origin).
            let c = self.ripples.center;
            [self.ripples.extent + 2.0 * c[0].abs().max(c[1].abs()); 2]
        } else {
            [self.ocean.patch_size; 2]
        }
    }

    /// A path from the scene, relative to the scene file's folder.
    pub fn resolve_path(&self, p: &str) -> std::path::PathBuf {
        self.base_dir.join(p)
    }

    /// An object's model matrix: translate · rotate (x, then y, then z) · scale.
    pub fn object_transform(o: &ObjectDesc) -> glam::Mat4 {
        let r = o.rotation_deg.map(f32::to_radians);
        let rotation = glam::Quat::from_rotation_z(r[2])
            * glam::Quat::from_rotation_y(r[1])
            * glam::Quat::from_rotation_x(r[0]);
        glam::Mat4::from_scale_rotation_translation(
            o.scale.into(),
            rotation,
            o.start_position().into(),
        )
    }

    /// The scene as a TOML table (for editing and for `--set` merging).
    pub fn to_table(&self) -> toml::Table {
        toml::Table::try_from(self).expect("a Scene always serialises to TOML")
    }
}
