//! The interactive water's settings: `water.dynamic = true` turns it on,
//! `[ripples]` says how it is simulated, `[[drops]]` and `[[emitters]]`
//! script its disturbances (seed 003 §2.3–2.4). The simulation is
//! `waves::ripples`.

use super::rules::range;
use super::{Quality, Scene, SceneError};
use crate::coupling::Pose;
use crate::waves::ripples::bed::Obstacle;
use crate::waves::ripples::{
    Drop, RippleBed, RippleBoundary, RippleGrid, RippleSettings, WATER_TENSION, WATER_VISCOSITY,
};
use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum RippleEdges {
    /// Reflecting walls around the domain (a pool, a tank); the domain stays put.
    Walls,
    /// Open water: the domain's edges absorb, and it follows the camera.
    Open,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RipplesDesc {
    /// Cells per side of the simulated square (a power of two, 16 to 512).
    pub resolution: u32,
    /// Side of the simulated square (m).
    pub extent: f32,
    /// Its centre [x, z] (m); open water centres it below the camera instead.
    pub center: [f32; 2],
    pub edges: RippleEdges,
    /// Water depth (m) under the whole domain; 0 = each cell's own, down
    /// to the floor, the terrain or a static object's top (deep water,
    /// 100 m, without a floor). Static objects through the surface are
    /// walls either way.
    pub depth: f32,
    /// Kinematic viscosity ν (m²/s): waves of wave number k decay at 2νk².
    pub viscosity: f32,
    /// Surface tension over density σ/ρ (m³/s²); 0 = gravity waves only.
    pub surface_tension: f32,
    /// Extra damping of every wave (1/s), beyond viscosity (0 = physical).
    pub damping: f32,
    /// Simulation steps per second (a divisor of the clock's 120 Hz).
    pub rate: u32,
}

impl Default for RipplesDesc {
    fn default() -> Self {
        RipplesDesc {
            resolution: 128,
            extent: 8.0,
            center: [0.0, 0.0],
            edges: RippleEdges::Open,
            depth: 0.0,
            viscosity: WATER_VISCOSITY as f32,
            surface_tension: WATER_TENSION as f32,
            damping: 0.0,
            rate: 60,
        }
    }
}

/// Radius (m) of the crater a pointer press makes on the interactive water
/// (the viewer's and the web page's left drag).
pub const POINTER_RADIUS: f32 = 0.04;

impl Scene {
    /// The fewest cells per side the interactive water may have and still
    /// show what disturbs it: a cell no wider than the smallest scripted
    /// drop or rain drop, nor than the pointer's crater ([`POINTER_RADIUS`])
    /// where the scene's own cells resolve it; a power of two, at most the
    /// scene's own `ripples.resolution` (16 when nothing small disturbs it).
    /// Quality tiers coarsen the water no further: a crater narrower than a
    /// cell is smeared to nothing (the pool's drips would vanish).
    pub fn ripple_cells_needed(&self) -> u32 {
        let r = &self.ripples;
        let pointer = (r.extent / r.resolution as f32 <= POINTER_RADIUS).then_some(POINTER_RADIUS);
        let smallest = self
            .drops
            .iter()
            .map(|d| d.radius)
            .chain(self.emitters.iter().map(|e| e.radius))
            .chain(pointer)
            .fold(f32::INFINITY, f32::min);
        if !smallest.is_finite() {
            return 16.min(r.resolution);
        }
        let cells = (r.extent / smallest.max(1e-6)).ceil().clamp(16.0, 512.0) as u32;
        cells.next_power_of_two().min(r.resolution)
    }
}

/// How long (s) a moving body takes to forget how it started: rapier's
/// angular damping of 0.5/s (`bodies`) brings a spin to 1e-3 in
/// ln(1000)/0.5 = 13.8 s, and the water's drag damps a bob faster.
pub const BODY_MEMORY_S: f64 = 14.0;

impl Scene {
    /// The scene's memory (s, whole seconds; `clock`): the longest of its
    /// simulations' — the interactive water's ([`RippleSettings::memory`]),
    /// white water's (`whitewater.memory`) and moving bodies'
    /// ([`BODY_MEMORY_S`]); 0 when nothing keeps state.
    pub fn simulation_memory(&self) -> f64 {
        let water = self.ripple_settings().map_or(0.0, |r| r.memory());
        let foam =
            if self.has_whitewater() { (self.whitewater.memory as f64).max(1.0) } else { 0.0 };
        let moving = self.objects.iter().any(|o| o.moving());
        let bodies = if moving { BODY_MEMORY_S } else { 0.0 };
        // A liquid never forgets its start (it may slosh for minutes): the
        // longest memory the clock takes, so any time under 20 minutes is
        // simulated from the start.
        let liquid = if self.fluid.enabled() { super::fluid::FLUID_MEMORY_S } else { 0.0 };
        water.max(foam).max(bodies).max(liquid).ceil()
    }
}

/// Rate of the clock the simulations step on (Hz; `SIMULATION_STEP_S` in the renderer).
pub const CLOCK_HZ: u32 = 120;

impl RipplesDesc {
    /// Clock steps a step of the interactive water spans (`rate` divides
    /// [`CLOCK_HZ`]; validation says so).
    pub fn clock_stride(&self) -> u32 {
        (CLOCK_HZ / self.rate.max(1)).max(1)
    }

    /// This section as quality tier `q` renders it ([`Quality::apply`]):
    /// never coarser than `cells_needed`, what the scene's drops and the
    /// pointer's crater need ([`Scene::ripple_cells_needed`]).
    pub fn apply_quality(&mut self, q: Quality, cells_needed: u32) {
        let cap = match q {
            Quality::Low => 64,
            Quality::Medium => 128,
            _ => return,
        };
        self.resolution = self.resolution.min(cap.max(cells_needed));
    }

    /// The `[ripples]` section's rules (one line naming the bad key and
    /// what is allowed).
    pub fn validate(&self) -> Result<(), SceneError> {
        let r = self;
        if !(16..=512).contains(&r.resolution) || !r.resolution.is_power_of_two() {
            return Err(SceneError::OutOfRange {
                key: "ripples.resolution".into(),
                value: r.resolution.to_string(),
                allowed: "must be a power of two from 16 to 512".into(),
            });
        }
        range(
            "ripples.extent",
            r.extent,
            r.extent >= 0.01 && r.extent <= 10_000.0,
            "must be 0.01 to 10000 m",
        )?;
        for (i, c) in r.center.iter().enumerate() {
            range(
                &format!("ripples.center[{i}]"),
                *c,
                c.abs() <= super::WORLD_EXTENT_M,
                "must be finite, within ±100000 m",
            )?;
        }
        range(
            "ripples.depth",
            r.depth,
            (0.0..=10_000.0).contains(&r.depth),
            "must be 0 (from the scene) to 10000 m",
        )?;
        range(
            "ripples.viscosity",
            r.viscosity,
            (0.0..=1.0).contains(&r.viscosity),
            "must be 0 to 1 m²/s",
        )?;
        range(
            "ripples.surface_tension",
            r.surface_tension,
            (0.0..=1.0).contains(&r.surface_tension),
            "must be 0 to 1 m³/s² (water: 7.28e-5)",
        )?;
        range(
            "ripples.damping",
            r.damping,
            (0.0..=100.0).contains(&r.damping),
            "must be 0 to 100 per second",
        )?;
        if r.rate == 0 || r.rate > CLOCK_HZ || !CLOCK_HZ.is_multiple_of(r.rate) {
            return Err(SceneError::OutOfRange {
                key: "ripples.rate".into(),
                value: r.rate.to_string(),
                allowed: "must divide 120 (120, 60, 40, 30, 24, 20, …) steps per second".into(),
            });
        }
        Ok(())
    }
}

/// `[[drops]]`: one disturbance at a given time.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DropDesc {
    /// When it lands (s).
    pub time: f32,
    /// Where, [x, z] (m).
    pub position: [f32; 2],
    /// Radius of its crater (m).
    pub radius: f32,
    /// Depth of its crater (m).
    pub strength: f32,
}

impl Default for DropDesc {
    fn default() -> Self {
        DropDesc { time: 0.0, position: [0.0, 0.0], radius: 0.05, strength: 0.01 }
    }
}

/// `[[emitters]]`: rain over a rectangle, drops at random places and times
/// (the same ones on every run: they come from `seed`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EmitterDesc {
    /// Centre [x, z] and size [x, z] of the rectangle it rains on (m).
    pub center: [f32; 2],
    pub size: [f32; 2],
    /// Drops per second over the whole rectangle.
    pub rate: f32,
    /// Mean crater radius and depth (m); each drop varies by ±30%.
    pub radius: f32,
    pub strength: f32,
    /// It rains from `start` to `end` (s); `end` = 0: forever.
    pub start: f32,
    pub end: f32,
    pub seed: u64,
}

impl Default for EmitterDesc {
    fn default() -> Self {
        EmitterDesc {
            center: [0.0, 0.0],
            size: [4.0, 4.0],
            rate: 20.0,
            radius: 0.02,
            strength: 0.003,
            start: 0.0,
            end: 0.0,
            seed: 1,
        }
    }
}

/// At most this many drops land in one simulation step (rain beyond is a
/// different regime: a rough surface, not rings).
pub const MAX_DROPS_PER_STEP: usize = 64;

fn check_drop(key: &str, position: [f32; 2], radius: f32, strength: f32) -> Result<(), SceneError> {
    for (i, c) in position.iter().enumerate() {
        range(
            &format!("{key}.position[{i}]"),
            *c,
            c.abs() <= super::WORLD_EXTENT_M,
            "must be finite, within ±100000 m",
        )?;
    }
    range(
        &format!("{key}.radius"),
        radius,
        radius > 0.0 && radius <= 100.0,
        "must be > 0 and at most 100 m",
    )?;
    range(&format!("{key}.strength"), strength, strength.abs() <= 10.0, "must be -10 to 10 m")
}

impl Scene {
    /// The rules of `[ripples]`, `[[drops]]` and `[[emitters]]`.
    pub(super) fn validate_ripples(&self) -> Result<(), SceneError> {
        self.ripples.validate()?;
        for (i, d) in self.drops.iter().enumerate() {
            let key = format!("drops[{i}]");
            range(
                &format!("{key}.time"),
                d.time,
                (0.0..=1e6).contains(&d.time),
                "must be 0 to 1e6 s",
            )?;
            check_drop(&key, d.position, d.radius, d.strength)?;
        }
        for (i, e) in self.emitters.iter().enumerate() {
            let key = format!("emitters[{i}]");
            check_drop(&key, e.center, e.radius, e.strength)?;
            for (j, s) in e.size.iter().enumerate() {
                range(
                    &format!("{key}.size[{j}]"),
                    *s,
                    *s >= 0.0 && *s <= 1e5,
                    "must be 0 to 100000 m",
                )?;
            }
            let per_step = e.rate / self.ripples.rate.max(1) as f32;
            range(
                &format!("{key}.rate"),
                e.rate,
                e.rate >= 0.0 && per_step <= MAX_DROPS_PER_STEP as f32 / 2.0,
                &format!(
                    "must be 0 to {} drops per second at ripples.rate = {}",
                    MAX_DROPS_PER_STEP / 2 * self.ripples.rate as usize,
                    self.ripples.rate
                ),
            )?;
            range(
                &format!("{key}.start"),
                e.start,
                (0.0..=1e6).contains(&e.start),
                "must be 0 to 1e6 s",
            )?;
            range(
                &format!("{key}.end"),
                e.end,
                e.end == 0.0 || (e.end > e.start && e.end <= 1e6),
                "must be 0 (forever) or after start",
            )?;
        }
        Ok(())
    }

    /// Whether the scene runs the interactive water (`water.dynamic`, with
    /// water): what asking for [`Scene::ripple_settings`] only to test it
    /// for `None` answers, without building its bed's depth levels.
    pub fn has_interactive_water(&self) -> bool {
        self.water.dynamic && self.has_water()
    }

    /// The interactive water's physics and grid, `None` without
    /// `water.dynamic` (or without water: `water.model = "none"`).
    pub fn ripple_settings(&self) -> Option<RippleSettings> {
        if !self.has_interactive_water() {
            return None;
        }
        let r = &self.ripples;
        Some(RippleSettings {
            grid: RippleGrid {
                boundary: match r.edges {
                    RippleEdges::Walls => RippleBoundary::Walls,
                    RippleEdges::Open => RippleBoundary::Open,
                },
                cells: r.resolution as usize,
                cell_size: r.extent as f64 / r.resolution as f64,
            },
            tension: r.surface_tension as f64,
            viscosity: r.viscosity as f64,
            damping: r.damping as f64,
            depths: self.ripple_depth_levels(),
            dt: 1.0 / r.rate as f64,
        })
    }

    /// The interactive water's depth (m) where nothing stands on its floor:
    /// `ripples.depth`, else the floor's, else deep water's (100 m).
    fn ripple_depth(&self) -> f64 {
        if self.ripples.depth > 0.0 {
            self.ripples.depth as f64
        } else if self.floor.depth > 0.0 {
            self.floor.depth as f64
        } else {
            100.0
        }
    }

    /// The two depth levels the interactive water blends between
    /// (`RippleSettings::depths`): the deepest water and the shallowest the
    /// bed makes (a shelf's top; a terrain's shore), no shallower than a
    /// sixteenth of the deepest (a blend linear in √d is exact for long
    /// waves at any depth between, and deep water's short waves feel no
    /// floor: the two levels then 4× apart in √d cover both).
    fn ripple_depth_levels(&self) -> [f64; 2] {
        let deep = self.ripple_depth();
        let least = deep / 16.0;
        if self.ripples.depth > 0.0 {
            return [deep; 2];
        }
        let mut shallow = deep;
        if self.floor.terrain != super::TerrainKind::None {
            shallow = least;
        }
        for o in self.ripple_obstacles() {
            let c = o.pose.position;
            if let Some((y0, y1)) = crate::coupling::body_column(&o.shape, &o.pose, c.x, c.z)
                && y1 < 0.0
                && y0 <= -deep + 1e-6
            {
                shallow = shallow.min(-y1);
            }
        }
        [shallow.max(least), deep]
    }

    /// The static objects the interactive water meets, as it takes them:
    /// each primitive's exact shape, a mesh's box of its scale (as the
    /// rigid bodies take it), a plane as a flat box.
    pub fn ripple_obstacles(&self) -> Vec<Obstacle> {
        self.bodies()
            .objects
            .iter()
            .zip(&self.objects)
            .filter(|(b, _)| !b.moving())
            .map(|(b, o)| {
                let (_, rotation, position) = b.transform.to_scale_rotation_translation();
                let mut half = glam::DVec3::from(o.scale.map(|c| c.abs() as f64)) * 0.5;
                if o.primitive == super::Primitive::Plane && o.mesh.is_empty() {
                    half.y = 0.0;
                }
                Obstacle {
                    shape: b.shape.unwrap_or(crate::coupling::Shape::Box { half }),
                    pose: Pose { position: position.as_dvec3(), rotation: rotation.as_dquat() },
                }
            })
            .collect()
    }

    /// What the interactive water stands on: its depth, the terrain (where
    /// `ripples.depth` does not set one) and the static objects (reads a
    /// heightmap file).
    pub fn ripple_bed(&self) -> Result<RippleBed, crate::geometry::load::AssetError> {
        Ok(RippleBed {
            depth: self.ripple_depth(),
            terrain: if self.ripples.depth > 0.0 { None } else { self.terrain()? },
            obstacles: self.ripple_obstacles(),
        })
    }

    /// The drops that land during simulation step `step` (of `dt` s): the
    /// scripted ones whose time falls in [step·dt, (step+1)·dt) and the
    /// emitters' rain, the same on every run.
    pub fn drops_in_step(&self, step: u64, dt: f64) -> Vec<Drop> {
        let (t0, t1) = (step as f64 * dt, (step + 1) as f64 * dt);
        let mut out: Vec<Drop> = self
            .drops
            .iter()
            .filter(|d| (t0..t1).contains(&(d.time as f64)) || (step == 0 && d.time as f64 <= 0.0))
            .map(|d| Drop {
                x: d.position[0] as f64,
                z: d.position[1] as f64,
                radius: d.radius as f64,
                strength: d.strength as f64,
            })
            .collect();
        for (i, e) in self.emitters.iter().enumerate() {
            if t0 < e.start as f64 || (e.end > 0.0 && t0 >= e.end as f64) {
                continue;
            }
            let mut rng = crate::rng::SplitMix64::new(
                e.seed
                    ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    ^ step.wrapping_mul(0xD1B5_4A32_D192_ED03),
            );
            let expected = e.rate as f64 * dt;
            let count = expected.floor() as usize + (rng.unit() < expected.fract()) as usize;
            for _ in 0..count {
                let (u, v, a, b) = (rng.unit(), rng.unit(), rng.unit(), rng.unit());
                out.push(Drop {
                    x: e.center[0] as f64 + (u - 0.5) * e.size[0] as f64,
                    z: e.center[1] as f64 + (v - 0.5) * e.size[1] as f64,
                    radius: e.radius as f64 * (0.7 + 0.6 * a),
                    strength: e.strength as f64 * (0.7 + 0.6 * b),
                });
            }
        }
        out.truncate(MAX_DROPS_PER_STEP);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scene_forgets_its_start_within_ten_minutes() {
        for b in super::super::BUILTIN_SCENES {
            let scene = Scene::load(b.name, &[]).unwrap();
            let m = scene.simulation_memory();
            assert!(m.fract() == 0.0 && (0.0..=600.0).contains(&m), "{}: {m} s", b.name);
            eprintln!("{:14} memory {m} s", b.name);
        }
        // The pool's walls damp at 0.05/s: ln(2000)/0.05 = 152.0 s.
        assert_eq!(Scene::load("pool", &[]).unwrap().simulation_memory(), 153.0);
        // Still water without simulations has none.
        let still = Scene::from_toml("[whitewater]\nfoam = false\nparticles = false\n", "t", &[]);
        assert_eq!(still.unwrap().simulation_memory(), 0.0);
    }

    #[test]
    fn the_interactive_water_stands_on_the_floor_the_terrain_and_the_objects() {
        // The harbour: its piles and quay stand through the water (dry
        // cells, walls to its waves); the open water is the floor's 6 m.
        let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
        let harbor = Scene::load("harbor", &[]).unwrap();
        let bed = harbor.ripple_bed().unwrap();
        let settings = harbor.ripple_settings().unwrap();
        let start = std::time::Instant::now();
        let window = crate::waves::ripples::RippleWindow::centred(&settings.grid, [0.0, 0.0]);
        let depths = bed.depths(&settings.grid, &window);
        eprintln!(
            "the harbour's {} cells' depths (an open window's move) in {:.2} ms, {} dry",
            depths.len(),
            start.elapsed().as_secs_f64() * 1e3,
            depths.iter().filter(|&&d| d == 0.0).count()
        );
        assert_eq!(bed.depth_at(-2.0, -5.1), 0.0, "a pile");
        assert!(near(bed.depth_at(-2.0 + 0.2, -5.1), 6.0), "beside the pile (0.175 m round)");
        assert_eq!(bed.depth_at(-10.0, 0.0), 0.0, "the quay");
        assert!(near(bed.depth_at(0.0, 5.0), 6.0), "open water");
        assert_eq!(harbor.ripple_settings().unwrap().depths, [6.0, 6.0], "one depth");
        // A shelf on a 1.6 m floor: 0.8 m of water over it, and one level
        // at its depth; a block hanging in the water is passed under.
        let shelf = Scene::from_toml(
            "[water]\ndynamic = true\n[floor]\ndepth = 1.6\n\
             [[objects]]\nprimitive = \"box\"\nposition = [1.0, -1.2, 0.0]\nscale = [2.0, 0.8, 4.0]\n\
             [[objects]]\nprimitive = \"box\"\nposition = [-1.0, -0.8, 0.0]\nscale = [1.0, 0.4, 1.0]\n",
            "t",
            &[],
        )
        .unwrap();
        let bed = shelf.ripple_bed().unwrap();
        assert!(near(bed.depth_at(1.0, 0.5), 0.8), "{}", bed.depth_at(1.0, 0.5));
        assert!(near(bed.depth_at(-1.0, 0.0), 1.6), "under the hanging block");
        let [a, b] = shelf.ripple_settings().unwrap().depths;
        assert!(near(a, 0.8) && near(b, 1.6), "levels {a}, {b}");
        // The lake's basin: the terrain's depth, down to its shore, and
        // levels from a sixteenth of the deepest.
        let lake = Scene::load("lake", &["water.dynamic=true".into()]).unwrap();
        let terrain = lake.terrain().unwrap().unwrap();
        let bed = lake.ripple_bed().unwrap();
        for (x, z) in [(0.0, 0.0), (-30.0, 26.0), (60.0, -40.0), (140.0, 0.0)] {
            let expected = (-terrain.height_at(x as f32, z as f32) as f64).max(0.0);
            assert!(near(bed.depth_at(x, z), expected), "({x}, {z})");
        }
        assert_eq!(bed.depth_at(140.0, 0.0), 0.0, "the shore is dry");
        assert_eq!(lake.ripple_settings().unwrap().depths, [5.0 / 16.0, 5.0]);
    }

    #[test]
    fn drops_land_in_the_step_of_their_time_and_rain_is_repeatable() {
        let scene = Scene::from_toml(
            "[water]\ndynamic = true\n[[drops]]\ntime = 0.51\nposition = [1.0, 2.0]\n\
             [[emitters]]\nrate = 60.0\nsize = [2.0, 2.0]\n",
            "test",
            &[],
        )
        .unwrap();
        let dt = scene.ripple_settings().unwrap().dt;
        let scripted = |step| {
            scene.drops_in_step(step, dt).iter().filter(|d| d.x == 1.0 && d.z == 2.0).count()
        };
        assert_eq!(scripted(30), 1, "0.51 s lies in step 30 of 1/60 s");
        assert_eq!((0..100).map(scripted).sum::<usize>(), 1);
        // 60 drops per second at 60 steps per second: one per step.
        let rain: usize = (0..600).map(|s| scene.drops_in_step(s, dt).len()).sum();
        assert_eq!(rain, 601, "600 raindrops in 10 s and the scripted one");
        assert_eq!(scene.drops_in_step(77, dt), scene.drops_in_step(77, dt));
        let d = scene.drops_in_step(77, dt)[0];
        assert!(d.x.abs() <= 1.0 && d.z.abs() <= 1.0, "inside the rectangle: {d:?}");
    }

    #[test]
    fn bad_ripple_settings_are_named() {
        for (set, key) in [
            ("ripples.resolution=100", "ripples.resolution"),
            ("ripples.rate=7", "ripples.rate"),
            ("ripples.extent=0", "ripples.extent"),
        ] {
            let e = Scene::load("pool", &[set.to_string()]).unwrap_err().to_string();
            assert!(e.contains(key), "{set}: {e}");
        }
        let e = Scene::from_toml("[[drops]]\nradius = -1.0\n", "t", &[]).unwrap_err().to_string();
        assert!(e.contains("drops[0].radius"), "{e}");
        let e =
            Scene::from_toml("[[drops]]\nwobble_factor = 1.0\n", "t", &[]).unwrap_err().to_string();
        assert!(e.contains("drops[0].wobble_factor") && e.contains("drop keys are"), "{e}");
        let e = Scene::from_toml("[[emitters]]\nrate = 1e6\n", "t", &[]).unwrap_err().to_string();
        assert!(e.contains("emitters[0].rate"), "{e}");
    }
}
