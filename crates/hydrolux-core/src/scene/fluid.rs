//! The volumetric liquid's settings (`[fluid]`, `[[fluid.sources]]`; seed
//! 003 §2.2, seed 000 §2.3.2): the domain box and its grid, the particles,
//! the step, and where the liquid starts. The physics is `crate::fluid`.

use super::rules::{range, vec3_range};
use super::{ObjectDesc, Primitive, Scene};
use super::{SceneError, WORLD_EXTENT_M};
use crate::fluid::{
    Cell, LandingSurface, Liquid, LiquidSettings, MacGrid, WhiteWater, WhiteWaterSettings,
};
use crate::geometry::load::AssetError;
use serde::{Deserialize, Serialize};

/// Cells a domain may have at most (256³): the grid's buffers stay within
/// what every device binds.
pub const MAX_FLUID_CELLS: u64 = 1 << 24;

/// The names of the domain's sides (`fluid.open`), per axis low then high.
pub const OPEN_SIDES: [&str; 6] = ["-x", "+x", "-y", "+y", "-z", "+z"];

/// The clock's memory (s) with a liquid: its longest. Times under twice
/// this are simulated from the start; later ones from a restart of the
/// sources at the clock's origin (`clock.rs`).
pub const FLUID_MEMORY_S: f64 = 600.0;

/// Marching cubes' cells along the domain's longest side at most: the
/// vertex map (three u32 per node) stays within what every device binds.
pub const MAX_SURFACE_RESOLUTION: u32 = 160;

/// Nozzles and drains a liquid may have (the GPU's fixed tables).
pub const MAX_FLUID_NOZZLES: usize = 4;
pub const MAX_FLUID_DRAINS: usize = 4;
/// Moving bodies a liquid may hold (the GPU's fixed table).
pub const MAX_LIQUID_BODIES: usize = 8;

/// How the liquid is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FluidSurface {
    /// Each particle a shaded sphere.
    Points,
    /// A mesh by marching cubes over the particles' density
    /// (`fluid::surface`), shaded as clear water.
    MarchingCubes,
    /// A screen-space mesh of the front the camera sees
    /// (`fluid::screen_mesh`, seed 003 §3.2), shaded as clear water.
    ScreenMesh,
    /// Screen-space fluid rendering: the particles' depth and thickness
    /// splatted per pixel, smoothed by a narrow-range filter and shaded as
    /// clear water per pixel, no mesh (`fluid::screen_space`).
    ScreenSpace,
    /// Not drawn (simulated, dumped and benchmarked only).
    None,
}

/// The field marching cubes meshes (`fluid::surface::level`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SurfaceField {
    /// The distance to the nearby particles' weighted mean less a radius
    /// (Zhu & Bridson 2005): flat where the liquid is flat, however its
    /// particles clump.
    #[default]
    MeanPosition,
    /// The particles' summed kernels: blobby, bumped by their clumps.
    Density,
}

/// What a source is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FluidSourceKind {
    /// Liquid at rest filling the box `min`..`max` at the start.
    Block,
    /// A nozzle: a round jet of `radius` from `position` along `direction`
    /// at `speed`, from `start` until `end` (s).
    Nozzle,
    /// A drain: the box `min`..`max` takes every particle that enters it.
    Drain,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FluidSource {
    pub kind: FluidSourceKind,
    /// A block's or a drain's corners (m), inside the domain.
    pub min: [f32; 3],
    pub max: [f32; 3],
    /// A nozzle's mouth (m, inside the domain), the way it points (any
    /// length), its speed (m/s, at most a cell a step) and radius (m).
    pub position: [f32; 3],
    pub direction: [f32; 3],
    pub speed: f32,
    pub radius: f32,
    /// When a nozzle runs (s on the scene's clock; `end` = inf: for ever).
    pub start: f32,
    pub end: f32,
}

impl Default for FluidSource {
    fn default() -> Self {
        FluidSource {
            kind: FluidSourceKind::Block,
            min: [0.0; 3],
            max: [0.0; 3],
            position: [0.0; 3],
            direction: [0.0, -1.0, 0.0],
            speed: 1.0,
            radius: 0.02,
            start: 0.0,
            end: f32::INFINITY,
        }
    }
}

impl FluidSource {
    /// A nozzle's unit direction and two unit vectors across it.
    fn frame(&self) -> [glam::DVec3; 3] {
        let d = glam::Vec3::from(self.direction).as_dvec3().normalize();
        let across = d.any_orthonormal_vector();
        [d, across, d.cross(across)]
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FluidDesc {
    /// The domain's corners (m): closed walls on its six sides.
    pub min: [f32; 3],
    pub max: [f32; 3],
    /// Cells along the domain's longest side (4 to 512); the cells are
    /// cubes, so the other sides get as many as fit (at least 2).
    pub resolution: u32,
    /// Marker particles seeded per cell: 1, 8, 27 or 64 (1–4 per axis).
    pub particles_per_cell: u32,
    /// m/s², each component within ±100.
    pub gravity: [f32; 3],
    /// The FLIP share of a particle's new velocity (0 = PIC, smooth and
    /// dissipative, to 1 = pure FLIP, lively and noisy); 0 to 1.
    pub flip: f32,
    /// Kinematic viscosity (m²/s): 0 (water's 1e-6 is below what these
    /// grids resolve) up to what one explicit step a substep holds,
    /// ν·step/cell² ≤ 1/6.
    pub viscosity: f32,
    /// Liquid steps per 120 Hz clock step (1 to 16): more for faster flow
    /// on finer grids (keep a step's travel under a cell).
    pub substeps: u32,
    /// The pressure solve's largest |∇·u| left (1/s, 1e-6 to 10) and its
    /// iteration cap (1 to 10000).
    pub tolerance: f32,
    pub iterations: u32,
    /// Most particles at once (1 to 16777216; the device's buffer limits
    /// may allow fewer).
    pub budget: u32,
    /// The domain's open sides ("-x", "+x", "-y", "+y", "-z", "+z"): beyond
    /// them is air, and the liquid leaves through them; the rest are walls.
    pub open: Vec<String>,
    /// How it is drawn: "marching_cubes" (the default), "screen_mesh",
    /// "screen_space", "points" or "none".
    pub surface: FluidSurface,
    /// Marching cubes' cells along the domain's longest side (8 to
    /// [`MAX_SURFACE_RESOLUTION`]), independent of the simulation's grid.
    pub surface_resolution: u32,
    /// Rounds of a binomial filter over the density before it is meshed,
    /// 0 to 8 (`fluid::surface::smooth`): the particles' jitter smoothed
    /// out of the surface.
    pub surface_smoothing: u32,
    /// The field marching cubes meshes: "mean_position" (the default) or
    /// "density".
    pub surface_field: SurfaceField,
    /// Screen-space meshes' Table 1 (seed 003 §3.2): h, pixels between the
    /// depth map's nodes (1 to 10).
    pub screen_spacing: f32,
    /// r, the particles' radius in particle spacings (0.5 to 4), for both
    /// screen methods.
    pub screen_radius: f32,
    /// n_filter, the depth filter's half length (0 to 10).
    pub screen_filter: u32,
    /// n_iters, rounds of silhouette smoothing (0 to 10).
    pub screen_silhouette_iterations: u32,
    /// z_max, the depth step that parts two layers, in particle radii
    /// (more than 1, as Table 1 asks z_max > r_z, up to 20).
    pub screen_depth_threshold: f32,
    /// Screen-space fluid rendering's narrow-range filter: its radius as a
    /// world length in particle radii (0 to 10; 0 leaves the depths as
    /// splatted). Its range is `screen_depth_threshold`.
    pub screen_space_filter: f32,
    /// Where a sample beyond the range counts from the centre's depth, in
    /// particle radii (0 to 4; at most `screen_depth_threshold`).
    pub screen_space_clamp: f32,
    /// White water where it breaks (`fluid::white_water`): diffuse
    /// particles (spray, foam, bubbles) a fully breaking liquid particle
    /// sheds per second, 0 (none) to 1000.
    pub white_water: f32,
    /// Foam's lifetime on it (s, 0.1 to 60): Monahan's for fresh water
    /// (2.54 s) unless set.
    pub foam_life: f32,
    /// Where the liquid starts; no sources, no liquid.
    pub sources: Vec<FluidSource>,
}

impl Default for FluidDesc {
    fn default() -> Self {
        FluidDesc {
            min: [-0.5, 0.0, -0.25],
            max: [0.5, 0.5, 0.25],
            resolution: 48,
            particles_per_cell: 8,
            gravity: [0.0, -9.81, 0.0],
            flip: 0.95,
            viscosity: 0.0,
            substeps: 2,
            tolerance: 1e-3,
            iterations: 200,
            budget: 1 << 20,
            open: Vec::new(),
            surface: FluidSurface::MarchingCubes,
            surface_resolution: 96,
            surface_smoothing: 1,
            surface_field: SurfaceField::MeanPosition,
            screen_spacing: 2.0,
            screen_radius: 1.0,
            screen_filter: 3,
            screen_silhouette_iterations: 2,
            screen_depth_threshold: 4.0,
            screen_space_filter: 3.0,
            screen_space_clamp: 1.0,
            white_water: 0.0,
            foam_life: crate::whitewater::FOAM_LIFE_FRESH_S as f32,
            sources: Vec::new(),
        }
    }
}

impl FluidDesc {
    /// Whether the scene has a liquid.
    pub fn enabled(&self) -> bool {
        !self.sources.is_empty()
    }

    /// The cell's side (m) and the cells per axis.
    pub fn grid_shape(&self) -> (f32, [u32; 3]) {
        let extent = [0, 1, 2].map(|a| self.max[a] - self.min[a]);
        let longest = extent.iter().fold(0.0f32, |m, &e| m.max(e));
        let h = longest / self.resolution.max(1) as f32;
        let n = extent.map(|e| ((e / h).round() as u32).max(2));
        (h, n)
    }

    /// The particles' spacing at rest (m).
    pub fn particle_spacing(&self) -> f32 {
        self.grid_shape().0 / self.particles_per_axis() as f32
    }

    /// Particles per axis of a cell.
    pub fn particles_per_axis(&self) -> usize {
        (self.particles_per_cell as f64).cbrt().round() as usize
    }

    /// The liquid's step (s): the clock's over the substeps.
    pub fn step_seconds(&self) -> f64 {
        1.0 / (super::CLOCK_HZ as f64 * self.substeps.max(1) as f64)
    }

    /// The CPU twin's settings.
    pub fn settings(&self) -> LiquidSettings {
        LiquidSettings {
            gravity: self.gravity.map(f64::from),
            density: 1000.0,
            flip: self.flip as f64,
            tolerance: self.tolerance as f64,
            max_iterations: self.iterations as usize,
            viscosity: self.viscosity as f64,
        }
    }

    /// The liquid at its start among `objects`: the grid with the cells
    /// the static objects fill made solid, and every source's particles
    /// (the CPU twin; the GPU simulation starts from its particles and
    /// solids).
    pub fn initial(&self, objects: &[ObjectDesc]) -> Liquid {
        self.initial_over(objects, None)
    }

    /// [`FluidDesc::initial`] over the surface water `surface` (`None`:
    /// none below it), which takes what falls under its level.
    pub fn initial_over(&self, objects: &[ObjectDesc], surface: Option<LandingSurface>) -> Liquid {
        self.initial_among(objects, &|_| false, surface)
    }

    /// [`FluidDesc::initial_over`] with more solids: the cells whose
    /// centres `solid` holds (the ground, meshes: `Scene::fluid_start`).
    pub fn initial_among(
        &self,
        objects: &[ObjectDesc],
        solid: &dyn Fn(glam::Vec3) -> bool,
        surface: Option<LandingSurface>,
    ) -> Liquid {
        let (h, n) = self.grid_shape();
        let mut grid = MacGrid::new(n.map(|c| c as usize), h as f64, self.min.map(f64::from));
        grid.open = self.open_sides();
        let solids: Vec<(glam::Mat4, Primitive)> = objects
            .iter()
            .filter(|o| is_fluid_solid(o) && o.mesh.is_empty())
            .map(|o| (Scene::object_transform(o).inverse(), o.primitive))
            .collect();
        for k in 0..n[2] as usize {
            for j in 0..n[1] as usize {
                for i in 0..n[0] as usize {
                    let centre = [i, j, k].map(|c| c as f32 + 0.5);
                    let world = glam::Vec3::from(self.min) + glam::Vec3::from(centre) * h;
                    if solid(world)
                        || solids
                            .iter()
                            .any(|(to_local, p)| inside(*p, to_local.transform_point3(world)))
                    {
                        let c = grid.cell(i, j, k);
                        grid.cells[c] = Cell::Solid;
                    }
                }
            }
        }
        let mut liquid = Liquid::new(grid, self.settings());
        liquid.surface = surface;
        let white_water = (self.white_water > 0.0).then_some(WhiteWaterSettings {
            rate: self.white_water as f64,
            foam_life: self.foam_life as f64,
            bubble_mobility: crate::fluid::white_water::LIQUID_BUBBLE_MOBILITY,
            particles_per_cell: self.particles_per_cell as f64,
        });
        for s in &self.sources {
            match s.kind {
                FluidSourceKind::Block => liquid.fill_box(
                    s.min.map(f64::from),
                    s.max.map(f64::from),
                    self.particles_per_axis(),
                ),
                FluidSourceKind::Drain => {
                    liquid.drains.push([s.min.map(f64::from), s.max.map(f64::from)])
                }
                FluidSourceKind::Nozzle => {}
            }
        }
        // The nozzles share the slots the blocks leave, by their flow.
        let nozzles: Vec<(&FluidSource, Vec<[f64; 3]>)> = self
            .sources
            .iter()
            .filter(|s| s.kind == FluidSourceKind::Nozzle)
            .map(|s| (s, self.nozzle_points(s)))
            .collect();
        let free = self.slots().saturating_sub(liquid.positions.len());
        let per_step: usize = nozzles.iter().map(|(_, p)| p.len()).sum();
        let dt = self.step_seconds();
        for (s, points) in nozzles {
            let first = (s.start as f64 / dt).ceil() as u64;
            let end = if s.end.is_finite() { (s.end as f64 / dt).ceil() as u64 } else { u64::MAX };
            let share = free * points.len() / per_step.max(1);
            let layers = (share / points.len()).min((end - first) as usize).max(1);
            let [d, ..] = s.frame();
            let velocity = (d * s.speed as f64).to_array();
            liquid.add_emitter(points, velocity, first..end, layers);
        }
        liquid.white_water = white_water.map(|w| WhiteWater::new(w, liquid.positions.len()));
        liquid
    }

    /// Which sides are open, per axis low and high.
    pub fn open_sides(&self) -> [[bool; 2]; 3] {
        let mut open = [[false; 2]; 3];
        for (k, name) in OPEN_SIDES.iter().enumerate() {
            open[k / 2][k % 2] = self.open.iter().any(|s| s == name);
        }
        open
    }

    /// A particle's share of the liquid (m³): a cell over its particles.
    pub fn particle_volume(&self) -> f64 {
        let (h, _) = self.grid_shape();
        (h as f64).powi(3) / self.particles_per_cell as f64
    }

    /// Particle slots: the budget, but no more than the domain holds at
    /// its seeding density (more could not be liquid at once).
    pub fn slots(&self) -> usize {
        let (_, n) = self.grid_shape();
        let cells: u64 = n.iter().map(|&c| c as u64).product();
        (self.budget as u64).min(cells * self.particles_per_cell as u64) as usize
    }

    /// Where a nozzle's particles start each step (m): one layer a step,
    /// moving at its speed, must carry its flow (πr²·speed) at a
    /// particle's volume, so a layer holds πr²·speed·step / volume points
    /// (rounded, at least one), spread evenly over the mouth on Vogel's
    /// sunflower spiral (point k at radius r·√((k+½)/n), turned by the
    /// golden angle).
    pub fn nozzle_points(&self, s: &FluidSource) -> Vec<[f64; 3]> {
        let [_, u, v] = s.frame();
        let r = s.radius as f64;
        let flow = std::f64::consts::PI * r * r * s.speed as f64 * self.step_seconds();
        let n = ((flow / self.particle_volume()).round() as usize).max(1);
        let centre = glam::Vec3::from(s.position).as_dvec3();
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        (0..n)
            .map(|k| {
                let radius = r * ((k as f64 + 0.5) / n as f64).sqrt();
                let angle = k as f64 * golden;
                (centre + (u * angle.cos() + v * angle.sin()) * radius).to_array()
            })
            .collect()
    }

    pub fn validate(&self) -> Result<(), SceneError> {
        let f = self;
        let within = format!("must be finite, each coordinate within ±{WORLD_EXTENT_M} m");
        vec3_range("fluid.min", f.min, WORLD_EXTENT_M, &within)?;
        vec3_range("fluid.max", f.max, WORLD_EXTENT_M, &within)?;
        if (0..3).any(|a| f.max[a] <= f.min[a]) {
            return Err(SceneError::OutOfRange {
                key: "fluid.max".into(),
                value: format!("{:?}", f.max),
                allowed: format!("must exceed fluid.min = {:?} on every axis", f.min),
            });
        }
        if !(4..=512).contains(&f.resolution) {
            return Err(SceneError::OutOfRange {
                key: "fluid.resolution".into(),
                value: f.resolution.to_string(),
                allowed: "must be 4 to 512 cells along the domain's longest side".into(),
            });
        }
        let (_, n) = f.grid_shape();
        let cells: u64 = n.iter().map(|&c| c as u64).product();
        if cells > MAX_FLUID_CELLS {
            return Err(SceneError::OutOfRange {
                key: "fluid.resolution".into(),
                value: f.resolution.to_string(),
                allowed: format!(
                    "gives {}×{}×{} = {cells} cells over the domain; at most {MAX_FLUID_CELLS} (256³)",
                    n[0], n[1], n[2]
                ),
            });
        }
        if !(8..=MAX_SURFACE_RESOLUTION).contains(&f.surface_resolution) {
            return Err(SceneError::OutOfRange {
                key: "fluid.surface_resolution".into(),
                value: f.surface_resolution.to_string(),
                allowed: format!(
                    "must be 8 to {MAX_SURFACE_RESOLUTION} cells along the domain's longest side"
                ),
            });
        }
        if f.surface_smoothing > 8 {
            return Err(SceneError::OutOfRange {
                key: "fluid.surface_smoothing".into(),
                value: f.surface_smoothing.to_string(),
                allowed: "must be 0 to 8 rounds of the filter".into(),
            });
        }
        let ranges: [(&str, f32, bool, f32, f32, &str); 9] = [
            ("screen_spacing", f.screen_spacing, true, 1.0, 10.0, "pixels between nodes"),
            ("screen_radius", f.screen_radius, true, 0.5, 4.0, "particle spacings"),
            ("screen_filter", f.screen_filter as f32, true, 0.0, 10.0, "nodes of half length"),
            (
                "screen_silhouette_iterations",
                f.screen_silhouette_iterations as f32,
                true,
                0.0,
                10.0,
                "rounds",
            ),
            (
                "screen_depth_threshold",
                f.screen_depth_threshold,
                false,
                1.0,
                20.0,
                "particle radii (Table 1: z_max > r_z)",
            ),
            ("screen_space_filter", f.screen_space_filter, true, 0.0, 10.0, "particle radii"),
            ("screen_space_clamp", f.screen_space_clamp, true, 0.0, 4.0, "particle radii"),
            ("white_water", f.white_water, true, 0.0, 1000.0, "particles per second"),
            ("foam_life", f.foam_life, true, 0.1, 60.0, "seconds"),
        ];
        for (key, value, from_included, low, high, unit) in ranges {
            let above = if from_included { value >= low } else { value > low };
            if !(above && value <= high) {
                let allowed = if from_included {
                    format!("must be {low} to {high} {unit}")
                } else {
                    format!("must be more than {low} and at most {high} {unit}")
                };
                return Err(SceneError::OutOfRange {
                    key: format!("fluid.{key}"),
                    value: value.to_string(),
                    allowed,
                });
            }
        }
        if f.screen_space_clamp > f.screen_depth_threshold {
            return Err(SceneError::OutOfRange {
                key: "fluid.screen_space_clamp".into(),
                value: f.screen_space_clamp.to_string(),
                allowed: format!(
                    "must be at most fluid.screen_depth_threshold ({}): a sample beyond the range cannot count nearer than one within it",
                    f.screen_depth_threshold
                ),
            });
        }
        if ![1, 8, 27, 64].contains(&f.particles_per_cell) {
            return Err(SceneError::OutOfRange {
                key: "fluid.particles_per_cell".into(),
                value: f.particles_per_cell.to_string(),
                allowed: "must be 1, 8, 27 or 64 (1 to 4 per axis)".into(),
            });
        }
        vec3_range("fluid.gravity", f.gravity, 100.0, "must be finite, each within ±100 m/s²")?;
        range("fluid.flip", f.flip, (0.0..=1.0).contains(&f.flip), "must be 0 (PIC) to 1 (FLIP)")?;
        if !(1..=16).contains(&f.substeps) {
            return Err(SceneError::OutOfRange {
                key: "fluid.substeps".into(),
                value: f.substeps.to_string(),
                allowed: "must be 1 to 16 steps per 120 Hz clock step".into(),
            });
        }
        if let Some(bad) = f.open.iter().find(|s| !OPEN_SIDES.contains(&s.as_str())) {
            return Err(SceneError::OutOfRange {
                key: "fluid.open".into(),
                value: format!("{bad:?}"),
                allowed: format!("each must be one of {}", OPEN_SIDES.join(", ")),
            });
        }
        let (h, _) = f.grid_shape();
        let most = (h as f64).powi(2) / (6.0 * f.step_seconds());
        range(
            "fluid.viscosity",
            f.viscosity,
            f.viscosity >= 0.0 && f.viscosity as f64 <= most,
            &format!(
                "must be 0 to {most:.3e} m²/s here (ν·step/cell² ≤ 1/6; raise fluid.substeps for more)"
            ),
        )?;
        range(
            "fluid.tolerance",
            f.tolerance,
            (1e-6..=10.0).contains(&f.tolerance),
            "must be 1e-6 to 10 per second",
        )?;
        if !(1..=10_000).contains(&f.iterations) {
            return Err(SceneError::OutOfRange {
                key: "fluid.iterations".into(),
                value: f.iterations.to_string(),
                allowed: "must be 1 to 10000".into(),
            });
        }
        if !(1..=1 << 24).contains(&f.budget) {
            return Err(SceneError::OutOfRange {
                key: "fluid.budget".into(),
                value: f.budget.to_string(),
                allowed: "must be 1 to 16777216 particles".into(),
            });
        }
        let mut particles = 0u64;
        let mut nozzle_points = 0u64;
        let per_cell = f.particles_per_cell as u64;
        let inside_domain = |key: String, v: [f32; 3]| -> Result<(), SceneError> {
            vec3_range(&key, v, WORLD_EXTENT_M, &within)?;
            if (0..3).any(|a| v[a] < f.min[a] || v[a] > f.max[a]) {
                return Err(SceneError::OutOfRange {
                    key,
                    value: format!("{v:?}"),
                    allowed: format!(
                        "must lie inside the domain, fluid.min = {:?} to fluid.max = {:?}",
                        f.min, f.max
                    ),
                });
            }
            Ok(())
        };
        for (i, s) in f.sources.iter().enumerate() {
            let key = |k: &str| format!("fluid.sources[{i}].{k}");
            if s.kind == FluidSourceKind::Nozzle {
                inside_domain(key("position"), s.position)?;
                let d = glam::Vec3::from(s.direction);
                if !d.is_finite() || d.length() < 1e-6 {
                    return Err(SceneError::OutOfRange {
                        key: key("direction"),
                        value: format!("{:?}", s.direction),
                        allowed: "must be a finite, non-zero vector".into(),
                    });
                }
                let fastest = h as f64 / f.step_seconds();
                range(
                    &key("speed"),
                    s.speed,
                    s.speed > 0.0 && s.speed as f64 <= fastest,
                    &format!(
                        "must be over 0 and at most a cell a step, {fastest:.3} m/s here (raise fluid.substeps for faster jets)"
                    ),
                )?;
                let longest = (0..3).map(|a| f.max[a] - f.min[a]).fold(0.0f32, f32::max);
                range(
                    &key("radius"),
                    s.radius,
                    s.radius > 0.0 && s.radius <= longest,
                    &format!("must be over 0 and at most the domain's longest side, {longest} m"),
                )?;
                range(
                    &key("start"),
                    s.start,
                    s.start.is_finite() && s.start >= 0.0,
                    "must be 0 or more seconds",
                )?;
                // inf (for ever) is allowed here, unlike the other keys.
                if s.end.is_nan() || s.end <= s.start {
                    return Err(SceneError::OutOfRange {
                        key: key("end"),
                        value: s.end.to_string(),
                        allowed: format!("must be after start = {} s (inf: for ever)", s.start),
                    });
                }
                nozzle_points += f.nozzle_points(s).len() as u64;
                continue;
            }
            inside_domain(key("min"), s.min)?;
            inside_domain(key("max"), s.max)?;
            if s.kind == FluidSourceKind::Drain {
                if (0..3).any(|a| s.max[a] <= s.min[a]) {
                    return Err(SceneError::OutOfRange {
                        key: key("max"),
                        value: format!("{:?}", s.max),
                        allowed: format!("must exceed min = {:?} on every axis", s.min),
                    });
                }
                continue;
            }
            // Cells whose centres the block holds.
            let count: u64 = (0..3)
                .map(|a| {
                    let lo = ((s.min[a] - f.min[a]) / h - 0.5).ceil().max(0.0);
                    let hi = ((s.max[a] - f.min[a]) / h - 0.5).floor();
                    (hi - lo + 1.0).max(0.0) as u64
                })
                .product();
            if count == 0 {
                return Err(SceneError::OutOfRange {
                    key: key("max"),
                    value: format!("{:?}", s.max),
                    allowed: format!(
                        "the block from {:?} must hold at least one cell's centre (cells are {h} m)",
                        s.min
                    ),
                });
            }
            particles += count * per_cell;
        }
        for (kind, most, what) in [
            (FluidSourceKind::Nozzle, MAX_FLUID_NOZZLES, "nozzles"),
            (FluidSourceKind::Drain, MAX_FLUID_DRAINS, "drains"),
        ] {
            let count = f.sources.iter().filter(|s| s.kind == kind).count();
            if count > most {
                return Err(SceneError::OutOfRange {
                    key: "fluid.sources".into(),
                    value: format!("{count} {what}"),
                    allowed: format!("at most {most} {what}"),
                });
            }
        }
        if !f.sources.iter().any(|s| s.kind != FluidSourceKind::Drain) && !f.sources.is_empty() {
            return Err(SceneError::OutOfRange {
                key: "fluid.sources".into(),
                value: "only drains".into(),
                allowed: "needs a block or a nozzle to have liquid".into(),
            });
        }
        if particles > f.budget as u64 {
            return Err(SceneError::OutOfRange {
                key: "fluid.budget".into(),
                value: f.budget.to_string(),
                allowed: format!("the sources need {particles} particles; raise it or shrink them"),
            });
        }
        if nozzle_points > 0 && particles + nozzle_points > f.slots() as u64 {
            return Err(SceneError::OutOfRange {
                key: "fluid.budget".into(),
                value: f.budget.to_string(),
                allowed: format!(
                    "the blocks take {particles} particles and the nozzles {nozzle_points} a step; at most {} fit (the budget, or the domain's cells × particles_per_cell)",
                    f.slots()
                ),
            });
        }
        Ok(())
    }
}

/// Whether an object is a static solid of the liquid: neither dynamic nor
/// moving, and a box, sphere or cylinder primitive (exactly) or a closed
/// mesh (by the sign of its signed distance: `Scene::fluid_start`). Planes
/// have no inside.
pub fn is_fluid_solid(o: &ObjectDesc) -> bool {
    !o.moving()
        && (!o.mesh.is_empty()
            || matches!(o.primitive, Primitive::Box | Primitive::Sphere | Primitive::Cylinder))
}

/// Whether point `p`, in the unit primitive's own space (box of side 1,
/// sphere and cylinder of diameter 1, the cylinder's axis y), is inside it.
fn inside(primitive: Primitive, p: glam::Vec3) -> bool {
    match primitive {
        Primitive::Box => p.abs().max_element() <= 0.5,
        Primitive::Sphere => p.length_squared() <= 0.25,
        Primitive::Cylinder => p.x * p.x + p.z * p.z <= 0.25 && p.y.abs() <= 0.5,
        Primitive::Plane => false,
    }
}

impl Scene {
    /// The box the liquid's surface mesh lies in, when it is drawn as one
    /// (the domain and a cell of its surface grid around it).
    pub fn liquid_mesh_bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let f = &self.fluid;
        if !f.enabled() {
            return None;
        }
        // A marching-cubes mesh reaches two of its cells past a closed wall
        // (`fluid::surface::Walls`).
        let cubes = |cells| 2.0 * crate::fluid::surface::SurfaceGrid::over(f.min, f.max, cells).h;
        // Vertices of a screen-space mesh are on the particles' spheres.
        let spheres = f.screen_radius * f.particle_spacing();
        // The error view comparing surfaces draws it two ways a frame, both
        // in one light view (the frame's uniforms are shared): the same
        // margin whichever drawing asks, its own grid's cell (at least the
        // finest's; with the defaults as wide as a screen mesh's spheres).
        let compared = self.render.view == super::DebugView::Error
            && self.water.model == super::WaterModel::None;
        let margin = match f.surface {
            _ if compared => cubes(f.surface_resolution),
            FluidSurface::MarchingCubes => cubes(f.surface_resolution),
            FluidSurface::ScreenMesh => spheres,
            FluidSurface::Points | FluidSurface::ScreenSpace | FluidSurface::None => return None,
        };
        Some((f.min.map(|v| v - margin), f.max.map(|v| v + margin)))
    }

    /// The box the liquid's surface lies in where light passes through it:
    /// its mesh's, or, drawn by screen-space fluid rendering (the sun's
    /// view splats its spheres too: `fluid::screen_space::SunView`), the
    /// marching-cubes mesh's box. The light view fitted to it is the same
    /// as the error view's, which draws the liquid both ways in one (its
    /// sphere of the box reaches far past a particle's sphere).
    pub fn liquid_light_bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let f = &self.fluid;
        self.liquid_mesh_bounds().or_else(|| {
            let cubes = 2.0
                * crate::fluid::surface::SurfaceGrid::over(f.min, f.max, f.surface_resolution).h;
            (f.enabled() && f.surface == FluidSurface::ScreenSpace)
                .then(|| (f.min.map(|v| v - cubes), f.max.map(|v| v + cubes)))
        })
    }

    /// Whether object `o` is a body of the liquid: it moves (dynamic, or
    /// kinematic with a velocity or a path), has an exact shape and starts with its
    /// centre in the liquid's domain. The liquid's world moves it, under
    /// the liquid's pressure (`fluid::coupled`); every other moving body
    /// floats on the surface water (`Scene::surface_bodies`).
    pub fn in_liquid(&self, o: &ObjectDesc) -> bool {
        let start = o.start_position();
        let inside = (0..3).all(|a| (self.fluid.min[a]..=self.fluid.max[a]).contains(&start[a]));
        self.fluid.enabled() && o.moving() && inside && crate::coupling::Shape::of(o).is_some()
    }

    /// The body world of the surface water: every moving body but the
    /// liquid's.
    pub fn surface_bodies(&self) -> crate::bodies::BodiesDesc {
        let mut desc = self.bodies();
        for (d, o) in desc.objects.iter_mut().zip(&self.objects) {
            d.elsewhere = self.in_liquid(o);
        }
        desc
    }

    /// The body world of the liquid (`None` when no body starts in it): its
    /// bodies, every static object, the floor, and the domain's closed
    /// sides as walls a metre thick, a cell inside them. A body a wall
    /// stops thus keeps a cell of liquid between them: a block lying on
    /// the tank's floor has liquid under it that presses it up, as water
    /// seeps under a real one (flush with the wall, no liquid cell would
    /// be under it, and it would never lift off). A body's index in it is
    /// its order among the liquid's.
    pub fn liquid_bodies(&self) -> Option<crate::bodies::BodiesDesc> {
        if !self.objects.iter().any(|o| self.in_liquid(o)) {
            return None;
        }
        let mut desc = self.bodies();
        for (d, o) in desc.objects.iter_mut().zip(&self.objects) {
            d.elsewhere = d.moving() && !self.in_liquid(o);
        }
        let (lo, hi) = (glam::Vec3::from(self.fluid.min), glam::Vec3::from(self.fluid.max));
        let (size, centre) = (hi - lo, 0.5 * (lo + hi));
        let open = self.fluid.open_sides();
        let h = self.fluid.grid_shape().0;
        for a in 0..3 {
            for (side, far) in [(0, lo[a] + h - 0.5), (1, hi[a] - h + 0.5)] {
                if open[a][side] {
                    continue;
                }
                let mut scale = size + glam::Vec3::splat(2.0);
                scale[a] = 1.0;
                let mut position = centre;
                position[a] = far;
                desc.objects.push(crate::bodies::BodyDesc {
                    transform: glam::Mat4::from_translation(position),
                    shape: Some(crate::coupling::Shape::Box { half: 0.5 * scale.as_dvec3() }),
                    scale: scale.to_array(),
                    velocity: [0.0; 3],
                    path: None,
                    dynamic: false,
                    density: 1000.0,
                    elsewhere: false,
                });
            }
        }
        Some(desc)
    }

    /// The liquid and its bodies at the start, stepped together on the
    /// clock (the CPU twin of the GPU liquid's coupling; `None` without a
    /// body in it).
    pub fn fluid_with_bodies(&self) -> Result<Option<crate::fluid::LiquidWithBodies>, AssetError> {
        let Some(desc) = self.liquid_bodies() else { return Ok(None) };
        let liquid = self.fluid_start()?;
        let substeps = self.fluid.substeps.max(1) as usize;
        let dt = self.fluid.step_seconds() * substeps as f64;
        let Some(world) = crate::bodies::BodyWorld::new(&desc, dt) else { return Ok(None) };
        Ok(Some(crate::fluid::LiquidWithBodies::new(liquid, world, substeps)))
    }

    /// Where the liquid meets the interactive water (issue #29): a liquid
    /// domain that reaches below the water's mean level (y = 0) over
    /// interactive water (`water.dynamic`) hands it what falls under it.
    pub fn fluid_landing(&self) -> Option<LandingSurface> {
        let reaches = self.fluid.enabled() && self.fluid.min[1] < 0.0;
        (reaches && self.has_interactive_water())
            .then(|| LandingSurface { level: 0.0, particle_volume: self.fluid.particle_volume() })
    }

    /// Clock steps between restarts of the liquid's landings log: every
    /// simulation that takes the landings (the interactive water's steps and
    /// the white water's) must find each in the log at its step, so it
    /// restarts only where both begin a step (their strides divide
    /// [`CLOCK_HZ`](crate::scene::CLOCK_HZ), so this does too).
    pub fn fluid_landing_stride(&self) -> u32 {
        let water = self.ripples.clock_stride();
        if !self.has_whitewater() {
            return water;
        }
        let white = crate::scene::CLOCK_HZ / self.whitewater.rate.max(1);
        let gcd = |mut a: u32, mut b: u32| {
            while b != 0 {
                (a, b) = (b, a % b);
            }
            a
        };
        water / gcd(water, white) * white
    }

    /// The liquid at the start, over the interactive water if it lands in it.
    ///
    /// Its solids: the static objects (primitives exactly, meshes by the
    /// sign of their signed distance at the cell centres, a closed mesh's
    /// winding number: `geometry::sdf`) and the ground (the floor or the
    /// terrain: the cells under it). A mesh that reaches into the domain
    /// must be closed, or there is no inside to fill: an error names it.
    pub fn fluid_start(&self) -> Result<Liquid, AssetError> {
        use crate::geometry::sdf::{Triangles, open_edges};
        if !self.fluid.enabled() {
            return Ok(self.fluid.initial_over(&self.objects, None));
        }
        let ground = self.ground_heightfield()?;
        let (lo, hi) = (
            glam::DVec3::from(self.fluid.min.map(f64::from)),
            glam::DVec3::from(self.fluid.max.map(f64::from)),
        );
        let mut meshes = Vec::new();
        for o in self.objects.iter().filter(|o| is_fluid_solid(o) && !o.mesh.is_empty()) {
            let mesh = self.object_mesh_file(o)?;
            let triangles = Triangles::of(&mesh, &Scene::object_transform(o));
            let (a, b) = triangles.bounds();
            if a.cmpgt(hi).any() || b.cmplt(lo).any() {
                continue;
            }
            let open = open_edges(&mesh);
            if open > 0 {
                return Err(AssetError {
                    what: "mesh",
                    path: o.mesh.clone(),
                    reason: format!(
                        "it has {open} open edges, and a solid of the liquid (it reaches into fluid.min..fluid.max) must be a closed mesh"
                    ),
                });
            }
            meshes.push((triangles, a, b));
        }
        let solid = |p: glam::Vec3| {
            let q = p.as_dvec3();
            ground.as_ref().is_some_and(|g| p.y < g.height(p.x, p.z))
                || meshes.iter().any(|(t, a, b)| {
                    q.cmpge(*a).all() && q.cmple(*b).all() && t.winding_number(q).abs() > 0.5
                })
        };
        Ok(self.fluid.initial_among(&self.objects, &solid, self.fluid_landing()))
    }
}
