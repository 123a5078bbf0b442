//! Scene description: what a TOML scene file (or a built-in) says, typed,
//! with defaults for everything, and the loading / override / validation
//! rules in [`load`].

mod builtin;
mod choices;
mod geometry;
mod load;
mod ripples;
mod whitewater;

pub use builtin::{BUILTIN_SCENES, BuiltinScene};
pub use choices::{Choice, enumerated_keys};
pub use geometry::{FLOOR_EXTENT, SceneObject};
pub use load::{SceneError, WORLD_EXTENT_M, apply_override, parse_override};
use load::{range, validate_material, vec3_range};
pub use ripples::{
    BODY_MEMORY_S, CLOCK_HZ, DropDesc, EmitterDesc, MAX_DROPS_PER_STEP, POINTER_RADIUS,
    RippleEdges, RipplesDesc,
};
pub use whitewater::WhitewaterDesc;

use crate::camera::Camera;
use crate::medium::Medium;
use crate::optics::FresnelMode;
use crate::waves::ocean::OceanSettings;
use crate::waves::spectrum::{SeaState, SpectrumKind};
use serde::{Deserialize, Serialize};

/// The latest `start_time` a scene may set (s).
pub const MAX_START_TIME_S: f64 = 3600.0;

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
}

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

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GodRayMethod {
    /// Each photon's path in the water drawn as a line (a screen-facing
    /// ribbon) into a reduced-resolution buffer (seed 000 §4.6).
    Lines,
    /// Ray marching each pixel of the buffer through the caustic layers and
    /// the shadow map (the slices of seed 003 §4.3).
    March,
    Off,
}

/// Volume caustics under the surface: the shafts of light that the waves'
/// focusing makes visible in the water.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GodRaysDesc {
    pub method: GodRayMethod,
    /// Photons per side of the square of surface traced around the viewer (lines).
    pub photons: u32,
    /// The god-ray buffer's size as a fraction of the output.
    pub resolution: f32,
    /// How far from the eye (m) the shafts are drawn; beyond, the water's
    /// in-scattering is the uniform (unfocused) closed form.
    pub distance: f32,
    /// Samples along each pixel's ray (march, and the fog in the air).
    pub steps: u32,
    /// Light-view texels per side for refractive objects: one path of light
    /// through them per texel.
    pub object_resolution: u32,
}

impl Default for GodRaysDesc {
    fn default() -> Self {
        GodRaysDesc {
            method: GodRayMethod::Lines,
            photons: 256,
            resolution: 0.5,
            distance: 20.0,
            steps: 48,
            object_resolution: 256,
        }
    }
}

impl GodRaysDesc {
    /// The `[godrays]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let g = self;
        if !(4..=2048).contains(&g.photons) {
            return Err(SceneError::OutOfRange {
                key: "godrays.photons".into(),
                value: g.photons.to_string(),
                allowed: "must be 4 to 2048 (per side)".into(),
            });
        }
        range(
            "godrays.resolution",
            g.resolution,
            g.resolution > 0.0 && g.resolution <= 1.0,
            "must be > 0 and at most 1 (a fraction of the output size)",
        )?;
        range(
            "godrays.distance",
            g.distance,
            g.distance > 0.0 && g.distance <= 1000.0,
            "must be > 0 and at most 1000 m",
        )?;
        if !(4..=512).contains(&g.steps) {
            return Err(SceneError::OutOfRange {
                key: "godrays.steps".into(),
                value: g.steps.to_string(),
                allowed: "must be 4 to 512".into(),
            });
        }
        if !(16..=2048).contains(&g.object_resolution) {
            return Err(SceneError::OutOfRange {
                key: "godrays.object_resolution".into(),
                value: g.object_resolution.to_string(),
                allowed: "must be 16 to 2048".into(),
            });
        }
        Ok(())
    }
}

/// The air as a participating medium: a light, grey fog (no absorption).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AirDesc {
    /// Scattering coefficient of the fog (m⁻¹); 0 = clear air.
    pub fog: f32,
    /// Henyey–Greenstein anisotropy of the fog's scattering.
    pub fog_g: f32,
    /// The fog fills this many metres around the eye (a room); beyond it the
    /// air is clear.
    pub fog_distance: f32,
    /// How much of the sky lights the fog: 1 outdoors, less in a room whose
    /// walls hide most of it (the sun's part is shadowed separately).
    pub fog_sky: f32,
}

impl Default for AirDesc {
    fn default() -> Self {
        AirDesc { fog: 0.0, fog_g: 0.3, fog_distance: 40.0, fog_sky: 1.0 }
    }
}

impl AirDesc {
    /// The `[air]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let a = self;
        range("air.fog", a.fog, (0.0..=1.0).contains(&a.fog), "must be 0 to 1 per metre")?;
        range(
            "air.fog_g",
            a.fog_g,
            a.fog_g > -1.0 && a.fog_g < 1.0,
            "must be in the open interval (-1, 1)",
        )?;
        range("air.fog_sky", a.fog_sky, (0.0..=1.0).contains(&a.fog_sky), "must be 0 to 1")?;
        range(
            "air.fog_distance",
            a.fog_distance,
            a.fog_distance > 0.0 && a.fog_distance <= 10_000.0,
            "must be > 0 and at most 10000 m",
        )?;
        Ok(())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Primitive {
    Box,
    Sphere,
    Cylinder,
    Plane,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObjectDesc {
    pub name: String,
    /// Unit-size primitive (box of side 1, sphere and cylinder of diameter 1,
    /// plane of side 1 facing +y), scaled by `scale`.
    pub primitive: Primitive,
    /// An .obj, .gltf or .glb file, or a built-in mesh ("builtin:bunny");
    /// when given it replaces `primitive`.
    pub mesh: String,
    pub position: [f32; 3],
    /// Rotation about x, then y, then z (degrees).
    pub rotation_deg: [f32; 3],
    pub scale: [f32; 3],
    pub material: MaterialDesc,
    /// Moved by rigid-body physics (a sphere, box or cylinder primitive):
    /// gravity, contacts, and buoyancy and drag from the water it is in.
    pub dynamic: bool,
    /// Density (kg/m³) of a dynamic object (water: 1000).
    pub density: f32,
    /// Velocity (m/s): a dynamic object's at the start; any other object
    /// keeps it, moving steadily through the scene (a boat crossing).
    pub velocity: [f32; 3],
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
    /// What to show: the final image or an intermediate texture.
    pub view: DebugView,
    /// Side of the sun's shadow map (texels).
    pub shadow_resolution: u32,
    /// Reflection and refraction textures' size as a fraction of the output.
    pub reflection_resolution: f32,
    /// Field-of-view widening of the reflection and refraction textures
    /// (0.5 = 50% wider, seed 002 §3).
    pub fov_margin: f32,
    /// Quality tier (`Quality`): caps on the costly settings and the
    /// internal rendering resolution; `auto` picks by adapter.
    pub quality: Quality,
}

/// What a quality tier keeps; see [`Quality::apply`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Quality {
    /// `low` on CPU adapters (software rasterisers), `high` on GPUs.
    Auto,
    Low,
    Medium,
    High,
    Ultra,
}

impl Quality {
    /// The tier for an adapter: `auto` resolved (`cpu`: a software adapter).
    pub fn resolve(self, cpu: bool) -> Quality {
        match self {
            Quality::Auto if cpu => Quality::Low,
            Quality::Auto => Quality::High,
            q => q,
        }
    }

    /// Fraction of the output's pixels per side the frame is rendered at
    /// (then filtered up to the output by the tone map).
    pub fn render_scale(self) -> f32 {
        match self {
            Quality::Low => 0.5,
            Quality::Medium => 0.75,
            _ => 1.0,
        }
    }

    /// `scene` as this (resolved) tier renders it. `high` is the scene as
    /// written. Lower tiers cap what costs most per frame; `ultra` raises
    /// the floors of the textures that alias first:
    /// - low: caustics ≤ 128 photons per side on ≤ 128² maps, ≤ 2 layers;
    ///   traced water ≤ 128 cells, ≤ 256 steps a ray;
    ///   shadow map ≤ 1024²; reflections ≤ 0.25× the output; god rays ≤ ¼
    ///   resolution; ocean N ≤ 128; interactive water ≤ 64 cells; foam ≤ 128
    ///   cells, ≤ 16k particles, ≤ 10 steps/s over ≤ 6 s of memory; ½ resolution.
    ///   The interactive water is never coarser than what its drops and the
    ///   pointer's crater need ([`Scene::ripple_cells_needed`]).
    /// - medium: caustics ≤ 256 photons on ≤ 256² maps; shadow map ≤ 2048²;
    ///   traced water ≤ 256 cells, ≤ 1024 steps a ray;
    ///   interactive water ≤ 128 cells; ≤ 64k particles; ¾ resolution.
    /// - ultra: caustic maps ≥ 512², photons ≥ 1024 per side, shadow map
    ///   ≥ 4096², reflections at the output's resolution, ≥ 1M particles,
    ///   traced water ≥ 512 cells (12.5 cm),
    ///   foam ≥ 512 cells.
    pub fn apply(self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        let cap_u = |v: &mut u32, max: u32| *v = (*v).min(max);
        let cap_f = |v: &mut f32, max: f32| *v = v.min(max);
        match self {
            Quality::Low => {
                cap_u(&mut s.caustics.photons, 128);
                cap_u(&mut s.caustics.map_resolution, 128);
                cap_u(&mut s.caustics.layers, 2);
                cap_u(&mut s.water.trace_resolution, 128);
                cap_u(&mut s.water.trace_steps, 256);
                cap_u(&mut s.render.shadow_resolution, 1024);
                cap_f(&mut s.render.reflection_resolution, 0.25);
                cap_f(&mut s.godrays.resolution, 0.25);
                cap_u(&mut s.ocean.resolution, 128);
                cap_u(&mut s.ripples.resolution, 64.max(scene.ripple_cells_needed()));
                cap_u(&mut s.whitewater.resolution, 128);
                cap_u(&mut s.whitewater.budget, 16_384);
                cap_f(&mut s.whitewater.memory, 6.0);
                if s.whitewater.rate > 10 {
                    s.whitewater.rate = 10;
                }
            }
            Quality::Medium => {
                cap_u(&mut s.caustics.photons, 256);
                cap_u(&mut s.caustics.map_resolution, 256);
                cap_u(&mut s.render.shadow_resolution, 2048);
                cap_u(&mut s.water.trace_resolution, 256);
                cap_u(&mut s.water.trace_steps, 1024);
                cap_u(&mut s.ripples.resolution, 128.max(scene.ripple_cells_needed()));
                cap_u(&mut s.whitewater.budget, 65_536);
            }
            Quality::Ultra => {
                s.caustics.map_resolution = s.caustics.map_resolution.max(512);
                s.caustics.photons = s.caustics.photons.max(1024);
                s.render.shadow_resolution = s.render.shadow_resolution.max(4096);
                s.render.reflection_resolution = 1.0;
                s.water.trace_resolution = s.water.trace_resolution.max(512);
                s.whitewater.budget = s.whitewater.budget.max(1 << 20);
                s.whitewater.resolution = s.whitewater.resolution.max(512);
            }
            Quality::High | Quality::Auto => {}
        }
        s
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DebugView {
    Final,
    Reflection,
    Refraction,
    Depth,
    Normals,
    Shadow,
    /// Each pixel's medium (air or water) from the stencil classification.
    Medium,
    /// The floor caustic map (over the patch, letterboxed).
    Caustics,
    /// The interactive water's height on the surface (red up, blue down,
    /// on a signed log scale from 0.5 mm to 0.5 m), shaded by its slopes; the rest in grey.
    Ripples,
    /// The foam's cover on the surface (white), over the water in grey.
    Foam,
    /// The water's Fresnel reflectance per pixel in red, the water marked by
    /// green = 1 (the rest grey): `hydrolux compare` reads it to split its
    /// error into reflection- and refraction-dominated pixels.
    Fresnel,
    /// What the projective approximations cost (issue #16's truth mode):
    /// the frame drawn both ways, projective and ray traced, and per pixel
    /// their CIELAB difference ΔE*ab as heat (black 0, red 10, yellow 20,
    /// white 40).
    Error,
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
            objects: Vec::new(),
            drops: Vec::new(),
            emitters: Vec::new(),
            base_dir: std::path::PathBuf::new(),
        }
    }
}

impl Default for CameraDesc {
    fn default() -> Self {
        CameraDesc {
            position: [0.0, 6.0, 0.0],
            look_at: [0.0, 2.0, -60.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 55.0,
        }
    }
}

impl CameraDesc {
    /// The `[camera]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let c = self;
        range(
            "camera.fov_y_deg",
            c.fov_y_deg,
            c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0,
            "must be in (0, 180)",
        )?;
        // Each vector on its own first, so that the message names the key
        // that is wrong; then how they relate.
        let within = format!("must be finite, each coordinate within ±{WORLD_EXTENT_M} m");
        vec3_range("camera.position", c.position, WORLD_EXTENT_M, &within)?;
        vec3_range("camera.look_at", c.look_at, WORLD_EXTENT_M, &within)?;
        vec3_range("camera.up", c.up, f32::MAX, "must be finite")?;
        let (p, t, up) =
            (glam::Vec3::from(c.position), glam::Vec3::from(c.look_at), glam::Vec3::from(c.up));
        if (t - p).length() < 1e-4 {
            return Err(SceneError::OutOfRange {
                key: "camera.look_at".into(),
                value: format!("{:?}", c.look_at),
                allowed: "must differ from camera.position".into(),
            });
        }
        if up.length() < 1e-6 || (t - p).normalize().cross(up.normalize()).length() < 1e-4 {
            return Err(SceneError::OutOfRange {
                key: "camera.up".into(),
                value: format!("{:?}", c.up),
                allowed: "must be non-zero and not parallel to the view direction".into(),
            });
        }
        Ok(())
    }
}

impl Default for SunDesc {
    fn default() -> Self {
        SunDesc { elevation_deg: 35.0, azimuth_deg: -70.0 }
    }
}

impl SunDesc {
    /// The `[sun]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let s = self;
        range(
            "sun.elevation_deg",
            s.elevation_deg,
            (-10.0..=90.0).contains(&s.elevation_deg),
            "must be in [-10, 90]",
        )?;
        range(
            "sun.azimuth_deg",
            s.azimuth_deg,
            s.azimuth_deg.is_finite(),
            "must be a finite angle",
        )?;
        Ok(())
    }
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
        }
    }
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

impl Default for ObjectDesc {
    fn default() -> Self {
        ObjectDesc {
            name: String::new(),
            primitive: Primitive::Box,
            mesh: String::new(),
            position: [0.0; 3],
            rotation_deg: [0.0; 3],
            scale: [1.0; 3],
            material: MaterialDesc::default(),
            dynamic: false,
            density: 500.0,
            velocity: [0.0; 3],
        }
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

impl Default for RenderDesc {
    fn default() -> Self {
        RenderDesc {
            exposure: 14.5,
            tonemap: Tonemap::Aces,
            anisotropy: 0,
            view: DebugView::Final,
            shadow_resolution: 2048,
            reflection_resolution: 0.5,
            fov_margin: 0.5,
            quality: Quality::Auto,
        }
    }
}

impl RenderDesc {
    /// The `[render]` section's rules (one line naming the bad key and what
    /// is allowed); checks that span sections are in `Scene::validate`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let r = self;
        if self.anisotropy > 16 {
            return Err(SceneError::OutOfRange {
                key: "render.anisotropy".into(),
                value: self.anisotropy.to_string(),
                allowed: "must be 0 (automatic) or 1 to 16".into(),
            });
        }
        range(
            "render.exposure",
            self.exposure,
            (-10.0..=30.0).contains(&self.exposure),
            "must be in [-10, 30] EV",
        )?;
        if !(256..=8192).contains(&r.shadow_resolution) {
            return Err(SceneError::OutOfRange {
                key: "render.shadow_resolution".into(),
                value: r.shadow_resolution.to_string(),
                allowed: "must be 256 to 8192".into(),
            });
        }
        range(
            "render.reflection_resolution",
            r.reflection_resolution,
            r.reflection_resolution > 0.05 && r.reflection_resolution <= 1.0,
            "must be in (0.05, 1]",
        )?;
        range(
            "render.fov_margin",
            r.fov_margin,
            (0.0..=2.0).contains(&r.fov_margin),
            "must be in [0, 2]",
        )?;
        Ok(())
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
        glam::Mat4::from_scale_rotation_translation(o.scale.into(), rotation, o.position.into())
    }

    /// The scene as a TOML table (for editing and for `--set` merging).
    pub fn to_table(&self) -> toml::Table {
        toml::Table::try_from(self).expect("a Scene always serialises to TOML")
    }
}
