//! The volumetric liquid on the GPU (issue #29; seed 003 §2.2, the
//! marker-and-cell method; seed 000 §2.3.2): marker particles on a MAC grid
//! with FLIP/PIC transfers and a pressure projection by Jacobi-preconditioned
//! conjugate gradients, all on the GPU with no read back (`liquid.wgsl`).
//! The CPU twin is `hydrolux_core::fluid`, kernel for kernel.
//!
//! A follower of the clock (`simulation/mod.rs`): `fluid.substeps` steps per
//! clock step, recorded without any per-step upload (the step's constants
//! are the scene's), so the state at a time is the same whatever frames led
//! there. The particle-to-grid sums are fixed-point atomics and every
//! reduction sums in a fixed order: a step gives the same bits every time.
//! The solve's loop is recorded `fluid.iterations` times as indirect
//! dispatches that its reductions empty once the residual is met.
//!
//! The moving bodies that start in its domain are its own (`bodies.rs`):
//! rapier moves them on the CPU under the pressure the GPU reads back each
//! clock step, and the liquid flows round them.
//!
//! It publishes its particles (`published.rs`), which `draw.rs` (the
//! `liquid_points` technique) draws as shaded spheres and
//! `screen_space.rs` (the `liquid_screen_space` technique) by screen-space
//! fluid rendering, and its surface mesh (marching cubes or the
//! screen-space mesh), which the water objects draw.

pub(crate) mod bodies;
pub mod draw;
pub mod readback;
pub mod screen_mesh;
pub mod screen_space;
pub mod surface;
pub mod white_water_draw;

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::shaders;
use crate::technique::Shared;
use crate::uniforms::uniform;
use hydrolux_core::scene::{FluidDesc, FluidSurface, Scene};

uniform! { LiquidParams;
    /// WGSL `LiquidParams` (simulation/liquid/liquid.wgsl).
    pub(crate) struct LiquidUniforms {
        pub cells: [u32; 3],
        pub cell_count: u32,
        pub faces: [u32; 3],
        pub face_count: u32,
        pub origin: [f32; 3],
        pub h: f32,
        pub gravity: [f32; 3],
        pub dt: f32,
        pub particle_count: u32,
        pub cell_groups: u32,
        pub max_iterations: u32,
        pub tolerance: f32,
        pub flip: f32,
        pub density: f32,
        pub viscosity: f32,
        pub open_sides: u32,
        pub landing: u32,
        pub landing_level: f32,
        pub landing_capacity: u32,
        pub substeps: u32,
        pub white_water: u32,
        pub white_water_rate: f32,
        pub foam_life: f32,
        pub particles_per_cell: f32,
        pub drop_drag: f32,
        pub bubble_rise: f32,
        pub bubble_relaxation: f32,
        pub _pad0: u32,
    }
}

/// WGSL `Landing` (liquid_landing.wgsl): a particle that fell into the
/// interactive water (`hydrolux_core::fluid::Landing`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LandingRecord {
    pub position: [f32; 2],
    pub down_speed: f32,
    pub step: u32,
}

/// Where the landings' log starts in the state buffer (bytes): after the
/// solve state, the water's indirect dispatch and the count.
pub(crate) const LANDINGS_AT: u64 = 48;
/// The water's indirect dispatch over the log, and the count.
pub(crate) const LANDING_DISPATCH_AT: u64 = 32;
const LANDING_COUNT_AT: u64 = 44;

/// WGSL `LiquidParticle`: a marker particle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct LiquidParticle {
    pub position: [f32; 3],
    /// 1 while the slot holds liquid.
    pub alive: u32,
    pub velocity: [f32; 3],
    pub _pad1: f32,
}

/// WGSL `Emitter`: a nozzle (`hydrolux_core::fluid::Emitter`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct EmitterRecord {
    velocity: [f32; 3],
    first_step: u32,
    end_step: u32,
    first_slot: u32,
    layers: u32,
    points: u32,
    point_offset: u32,
    _pad: [u32; 3],
}

/// WGSL `Drain`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
struct DrainRecord {
    min: [f32; 3],
    _pad0: f32,
    max: [f32; 3],
    _pad1: f32,
}

/// `MAX_EMITTERS`, `MAX_DRAINS` in liquid.wgsl (the scene allows as many).
const MAX_EMITTERS: usize = hydrolux_core::scene::MAX_FLUID_NOZZLES;
const MAX_DRAINS: usize = hydrolux_core::scene::MAX_FLUID_DRAINS;

/// WGSL `Sources` as bytes: the counts, the nozzles, the drains, then
/// every nozzle's mouth points.
fn sources_bytes(start: &hydrolux_core::fluid::Liquid) -> Vec<u8> {
    let mut emitters = [EmitterRecord::default(); MAX_EMITTERS];
    let mut points: Vec<[f32; 4]> = Vec::new();
    for (record, e) in emitters.iter_mut().zip(&start.emitters) {
        let step = |s: u64| s.min(u32::MAX as u64) as u32;
        *record = EmitterRecord {
            velocity: e.velocity.map(|c| c as f32),
            first_step: step(e.first_step),
            end_step: step(e.end_step),
            first_slot: e.first_slot as u32,
            layers: e.layers as u32,
            points: e.points.len() as u32,
            point_offset: points.len() as u32,
            _pad: [0; 3],
        };
        points.extend(e.points.iter().map(|p| [p[0] as f32, p[1] as f32, p[2] as f32, 0.0]));
    }
    let mut drains = [DrainRecord::default(); MAX_DRAINS];
    for (record, [lo, hi]) in drains.iter_mut().zip(&start.drains) {
        *record = DrainRecord {
            min: lo.map(|c| c as f32),
            max: hi.map(|c| c as f32),
            ..Default::default()
        };
    }
    let header = [start.emitters.len() as u32, start.drains.len() as u32, points.len() as u32, 0];
    let mut bytes = bytemuck::cast_slice(&header).to_vec();
    bytes.extend_from_slice(bytemuck::cast_slice(&emitters));
    bytes.extend_from_slice(bytemuck::cast_slice(&drains));
    // At least one point: a storage binding is never empty.
    points.resize(points.len().max(1), [0.0; 4]);
    bytes.extend_from_slice(bytemuck::cast_slice(&points));
    bytes
}

/// WGSL `SolveState`: how the last step's pressure solve went.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct SolveState {
    pub sigma: f32,
    pub alpha: f32,
    pub beta: f32,
    /// The largest |∇·u| over liquid cells after and before the solve
    /// (1/s; after is the solver's residual).
    pub residual: f32,
    pub residual_before: f32,
    /// Conjugate-gradient iterations the last step took.
    pub iterations: u32,
    pub running: u32,
    /// Steps taken since the start.
    pub steps: u32,
}

/// The step's kernels: liquid.wgsl, continued by the white water's
/// (white_water.wgsl) under the core's constants.
pub fn source() -> String {
    use hydrolux_core::fluid::white_water as w;
    let floats = [
        ("ENTRAINMENT_SPEED_MIN", w::ENTRAINMENT_SPEED[0]),
        ("ENTRAINMENT_SPEED_MAX", w::ENTRAINMENT_SPEED[1]),
        ("TRAPPED_AIR_SHEAR_MIN", w::TRAPPED_AIR_SHEAR[0]),
        ("TRAPPED_AIR_SHEAR_MAX", w::TRAPPED_AIR_SHEAR[1]),
        ("CREST_ALIGNMENT", w::CREST_ALIGNMENT),
        ("CREST_SPEED_MIN", w::CREST_SPEED[0]),
        ("CREST_SPEED_MAX", w::CREST_SPEED[1]),
        ("SPRAY_FILL", w::SPRAY_FILL),
        ("BUBBLE_FILL", w::BUBBLE_FILL),
    ];
    let uints = [
        ("SLOTS_PER_PARTICLE", w::SLOTS_PER_PARTICLE as u32),
        ("SALT_CHANCE", w::SALT_CHANCE),
        ("SALT_JITTER_X", w::SALT_JITTER[0]),
        ("SALT_JITTER_Y", w::SALT_JITTER[1]),
        ("SALT_JITTER_Z", w::SALT_JITTER[2]),
    ];
    let consts: String = floats
        .iter()
        .map(|(name, v)| format!("const {name}: f32 = {v:e};\n"))
        .chain(uints.iter().map(|(name, v)| format!("const {name}: u32 = {v}u;\n")))
        .collect();
    let main = [include_str!("liquid.wgsl"), include_str!("white_water.wgsl")].join("\n");
    shaders::compose(&consts, &main)
}

/// Bytes of one white-water particle (`Diffuse`).
const WHITE_WATER_BYTES: u64 = std::mem::size_of::<hydrolux_core::fluid::Diffuse>() as u64;

/// Threads per workgroup of every kernel (`WG` in liquid.wgsl).
const WG: u32 = 256;
/// Workgroups per row of a two-dimensional dispatch (under the 65535 limit).
pub(crate) const ROW: u32 = 32768;

/// Workgroups for `n` items, as (x, y).
fn groups(n: u32) -> (u32, u32) {
    groups_of(n, WG)
}

/// Workgroups of `size` threads for `n` items, as (x, y): rows of `ROW`.
pub(crate) fn groups_of(n: u32, size: u32) -> (u32, u32) {
    let g = n.div_ceil(size).max(1);
    if g <= ROW { (g, 1) } else { (ROW, g.div_ceil(ROW)) }
}

struct Pipelines {
    emit: wgpu::ComputePipeline,
    clear: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    faces: wgpu::ComputePipeline,
    diffuse: wgpu::ComputePipeline,
    diffuse_back: wgpu::ComputePipeline,
    solve_begin: wgpu::ComputePipeline,
    reduce_begin: wgpu::ComputePipeline,
    /// The conjugate-gradient loop's even and odd iterations (the search
    /// direction alternates between two copies).
    cg_apply: [wgpu::ComputePipeline; 2],
    cg_update: [wgpu::ComputePipeline; 2],
    reduce_beta: wgpu::ComputePipeline,
    gradient: wgpu::ComputePipeline,
    extrapolate_out: wgpu::ComputePipeline,
    extrapolate_back: wgpu::ComputePipeline,
    advance: wgpu::ComputePipeline,
    landing_dispatch: wgpu::ComputePipeline,
    place_bodies: wgpu::ComputePipeline,
    body_loads: wgpu::ComputePipeline,
    white_water_move: wgpu::ComputePipeline,
    white_water_shed: wgpu::ComputePipeline,
}

pub struct Liquid {
    desc: FluidDesc,
    /// The scene's objects that are its solids (an edit to them remakes it).
    solid_objects: Vec<hydrolux_core::scene::ObjectDesc>,
    /// The ground, a solid where it reaches into the domain.
    floor: hydrolux_core::scene::FloorDesc,
    uniforms: LiquidUniforms,
    /// The particles at the start (a reset writes them back).
    initial: Vec<LiquidParticle>,
    pub(crate) particles: wgpu::Buffer,
    faces: wgpu::Buffer,
    /// The white water's pool (`fluid::white_water::Diffuse` per slot).
    pub(crate) white_water: wgpu::Buffer,
    white_water_group: wgpu::BindGroup,
    solve: wgpu::Buffer,
    state: wgpu::Buffer,
    accum: wgpu::Buffer,
    known: wgpu::Buffer,
    /// 1 per cell a static object fills.
    solids: Vec<u32>,
    args: wgpu::Buffer,
    group: wgpu::BindGroup,
    args_group: wgpu::BindGroup,
    pipelines: Pipelines,
    /// Clock steps followed since the start.
    clock_steps: u64,
    /// Mouth points of all the nozzles (threads of `emit`).
    emit_points: u32,
    /// Clock steps a step of the interactive water it lands in spans.
    landing_stride: u64,
    landing: Option<hydrolux_core::fluid::LandingSurface>,
    /// The moving bodies in it, and where the GPU reads them.
    bodies: Option<bodies::GpuBodies>,
    bodies_buffer: wgpu::Buffer,
    /// Their world as the scene describes it (an edit to it remakes it).
    bodies_desc: Option<hydrolux_core::bodies::BodiesDesc>,
    /// Its surface mesh, when drawn as one by marching cubes…
    pub(crate) surface: Option<surface::LiquidSurface>,
    /// …or as a screen-space mesh.
    pub(crate) screen_mesh: Option<screen_mesh::ScreenMeshSurface>,
    /// While the error view compares surfaces: marching cubes on the finest
    /// grid, the reference drawing's mesh (unless its own already is).
    reference: Option<surface::LiquidSurface>,
}

impl Liquid {
    /// After a run of steps: the interactive water's dispatch over the log.
    fn record_landing_dispatch(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("liquid landings"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_pipeline(&self.pipelines.landing_dispatch);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// Follow `clock_steps` with bodies in the liquid: each clock step on
    /// its own submission, the bodies' poses up before it and their loads
    /// back after it, then rapier's step (`bodies.rs`).
    fn follow_with_bodies(&mut self, shared: &Shared, clock_steps: u32) {
        let substeps = self.desc.substeps.max(1) as u64;
        let loads_at = self.loads_at();
        for s in 0..clock_steps {
            let Some(b) = &self.bodies else { return };
            shared.queue.write_buffer(&self.bodies_buffer, 0, bytemuck::bytes_of(&b.record()));
            let mut encoder = shared.device.create_command_encoder(&Default::default());
            if s == 0
                && self.uniforms.landing == 1
                && self.clock_steps.is_multiple_of(self.landing_stride)
            {
                encoder.clear_buffer(&self.state, LANDING_COUNT_AT, Some(4));
            }
            encoder.clear_buffer(&self.solve, loads_at, Some(bodies::LOADS_BYTES));
            self.record_steps(&mut encoder, substeps, None);
            if s + 1 == clock_steps && self.uniforms.landing == 1 {
                self.record_landing_dispatch(&mut encoder);
            }
            shared.queue.submit([encoder.finish()]);
            if let Some(b) = &mut self.bodies {
                b.step(&shared.device, &shared.queue, &self.solve, loads_at);
            }
            self.clock_steps += 1;
        }
    }
}

/// Clock steps between restarts of the landings log: where the interactive
/// water's and the white water's steps both begin.
fn landing_stride(scene: &Scene) -> u64 {
    scene.fluid_landing_stride() as u64
}

impl Liquid {
    /// The liquid of `scene` (`None` without one).
    pub fn new(shared: &Shared, scene: &Scene) -> Result<Option<Self>, RenderError> {
        let desc = &scene.fluid;
        if !desc.enabled() {
            return Ok(None);
        }
        let device = &shared.device;
        let start = scene.fluid_start()?;
        // Per cell: 1 where a static object fills it (after the faces'
        // known flags in the same buffer).
        let solids: Vec<u32> = start
            .grid
            .cells
            .iter()
            .map(|c| (*c == hydrolux_core::fluid::Cell::Solid) as u32)
            .collect();
        let initial: Vec<LiquidParticle> = start
            .positions
            .iter()
            .zip(&start.alive)
            .map(|(p, &alive)| LiquidParticle {
                position: p.map(|c| c as f32),
                alive: alive as u32,
                ..Default::default()
            })
            .collect();
        let emit_points: u32 = start.emitters.iter().map(|e| e.points.len() as u32).sum();
        let (h, n) = desc.grid_shape();
        let cell_count = n[0] * n[1] * n[2];
        let face_dims = |a: usize| {
            let mut m = n;
            m[a] += 1;
            m[0] * m[1] * m[2]
        };
        let faces = [face_dims(0), face_dims(1), face_dims(2)];
        let face_count: u32 = faces.iter().sum();
        let count = initial.len() as u32;
        let ww_motion = hydrolux_core::fluid::white_water::Motion::new(
            start.settings.gravity,
            desc.step_seconds(),
            hydrolux_core::fluid::white_water::LIQUID_BUBBLE_MOBILITY,
        );
        // The white water's pool: its slots per particle slot (one dead
        // record where it sheds none: a binding is never empty).
        let pool = if desc.white_water > 0.0 {
            count as u64 * hydrolux_core::fluid::white_water::SLOTS_PER_PARTICLE as u64
        } else {
            1
        };
        // The log holds what lands before the water takes it: every particle
        // there is, and every one the nozzles emit in the longest run of
        // steps (a batch, and the clock steps of a water step begun before).
        let landing = start.surface;
        let landing_capacity = if landing.is_some() {
            let run = (crate::renderer::SIMULATION_BATCH + hydrolux_core::scene::CLOCK_HZ) as u64;
            let emitted = emit_points as u64 * desc.substeps.max(1) as u64 * run;
            (count as u64 + emitted).min(u32::MAX as u64 / 2) as u32
        } else {
            0
        };
        let (cx, cy) = groups(cell_count);
        let cell_groups = cx * cy;
        // Every buffer within what the device binds.
        let limit = device.limits().max_storage_buffer_binding_size;
        let sizes = [
            ("particles (fluid.sources, fluid.particles_per_cell)", count as u64 * 32),
            ("face velocities (fluid.resolution)", 3 * face_count as u64 * 4),
            ("face and cell flags (fluid.resolution)", 2 * (face_count + cell_count) as u64 * 4),
            ("splat sums (fluid.resolution)", (2 * face_count + cell_count) as u64 * 4),
            (
                "pressure solve (fluid.resolution)",
                (6 * cell_count as u64 + 4 * cell_groups as u64) * 4 + bodies::LOADS_BYTES,
            ),
            (
                "landings in the interactive water (fluid.budget)",
                LANDINGS_AT + landing_capacity as u64 * 16,
            ),
            ("white water (fluid.white_water, fluid.budget)", pool * WHITE_WATER_BYTES),
        ];
        for (what, bytes) in sizes {
            if bytes > limit {
                return Err(RenderError::Unsupported(format!(
                    "the liquid's {what} need a {} MiB GPU buffer, but this device binds at most {} MiB: lower it",
                    bytes >> 20,
                    limit >> 20
                )));
            }
        }
        let uniforms = LiquidUniforms {
            cells: n,
            cell_count,
            faces,
            face_count,
            origin: desc.min,
            h,
            gravity: desc.gravity,
            dt: desc.step_seconds() as f32,
            particle_count: count,
            cell_groups,
            max_iterations: desc.iterations,
            tolerance: desc.tolerance,
            flip: desc.flip,
            density: start.settings.density as f32,
            viscosity: desc.viscosity,
            open_sides: desc
                .open_sides()
                .iter()
                .flatten()
                .enumerate()
                .map(|(k, open)| (*open as u32) << k)
                .sum(),
            landing: landing.is_some() as u32,
            landing_level: landing.map_or(0.0, |l| l.level as f32),
            landing_capacity,
            substeps: desc.substeps.max(1),
            white_water: (desc.white_water > 0.0) as u32,
            white_water_rate: desc.white_water,
            foam_life: desc.foam_life,
            particles_per_cell: desc.particles_per_cell as f32,
            drop_drag: ww_motion.drag,
            bubble_rise: ww_motion.rise,
            bubble_relaxation: ww_motion.relaxation,
            _pad0: 0,
        };
        let storage = |label: &str, size: u64, extra: wgpu::BufferUsages| {
            storage_buffer(device, label, size, extra)
        };
        let none = wgpu::BufferUsages::empty();
        let params = uniform_buffer(device, "liquid", &uniforms);
        let particles = storage("liquid particles", count as u64 * 32, none);
        let accum = storage("liquid splat", (2 * face_count + cell_count) as u64 * 4, none);
        let faces_buffer = storage("liquid faces", 3 * face_count as u64 * 4, none);
        let white_water = storage("liquid white water", pool * WHITE_WATER_BYTES, none);
        let known = storage(
            "liquid known faces, solid cells, solve flags",
            2 * (face_count + cell_count) as u64 * 4,
            none,
        );
        let solve = storage(
            "liquid solve, partial sums and body loads",
            (6 * cell_count as u64 + 4 * cell_groups as u64) * 4 + bodies::LOADS_BYTES,
            none,
        );
        let liquid_bodies = bodies::GpuBodies::new(device, scene, start.settings.density);
        let bodies_buffer = uniform_buffer(device, "liquid bodies", &bodies::BodiesRecord::empty());
        let sources = {
            let bytes = sources_bytes(&start);
            let buffer = storage("liquid sources", bytes.len() as u64, none);
            shared.queue.write_buffer(&buffer, 0, &bytes);
            buffer
        };
        let state = storage(
            "liquid solve state and landings",
            LANDINGS_AT + landing_capacity.max(1) as u64 * 16,
            wgpu::BufferUsages::INDIRECT,
        );
        let args = storage("liquid solve arguments", 16, wgpu::BufferUsages::INDIRECT);
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("liquid"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, false),
                storage_entry(2, cs, false),
                storage_entry(3, cs, false),
                storage_entry(4, cs, false),
                storage_entry(5, cs, false),
                storage_entry(6, cs, true),
                storage_entry(7, cs, false),
                uniform_entry(8, cs),
            ],
        });
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("liquid solve arguments"),
            entries: &[storage_entry(0, cs, false)],
        });
        fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("liquid"),
            layout: &layout,
            entries: &[
                entry(0, &params),
                entry(1, &particles),
                entry(2, &accum),
                entry(3, &faces_buffer),
                entry(4, &known),
                entry(5, &solve),
                entry(6, &sources),
                entry(7, &state),
                entry(8, &bodies_buffer),
            ],
        });
        let args_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("liquid solve arguments"),
            layout: &args_layout,
            entries: &[entry(0, &args)],
        });
        let white_water_layout =
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("liquid white water"),
                entries: &[storage_entry(1, cs, false)],
            });
        let white_water_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("liquid white water"),
            layout: &white_water_layout,
            entries: &[entry(1, &white_water)],
        });
        let module = shader(device, "liquid", &source());
        let plain = |e: &str| compute_pipeline(device, e, &module, e, &[&layout]);
        let reduce = |e: &str| compute_pipeline(device, e, &module, e, &[&layout, &args_layout]);
        let shed =
            |e: &str| compute_pipeline(device, e, &module, e, &[&layout, &white_water_layout]);
        let pipelines = Pipelines {
            emit: plain("emit"),
            clear: plain("clear"),
            splat: plain("splat"),
            faces: plain("faces_from_particles"),
            diffuse: plain("diffuse"),
            diffuse_back: plain("diffuse_back"),
            solve_begin: plain("solve_begin"),
            reduce_begin: reduce("reduce_begin"),
            cg_apply: [plain("cg_apply_s_to_t"), plain("cg_apply_t_to_s")],
            cg_update: [plain("cg_update_t"), plain("cg_update_s")],
            reduce_beta: reduce("reduce_beta"),
            gradient: plain("gradient"),
            extrapolate_out: plain("extrapolate_out"),
            extrapolate_back: plain("extrapolate_back"),
            advance: plain("advance"),
            landing_dispatch: plain("landing_dispatch"),
            place_bodies: plain("place_bodies"),
            body_loads: plain("body_loads"),
            white_water_move: shed("white_water_move"),
            white_water_shed: shed("white_water_shed"),
        };
        let mut liquid = Liquid {
            desc: desc.clone(),
            solid_objects: scene
                .objects
                .iter()
                .filter(|o| hydrolux_core::scene::is_fluid_solid(o))
                .cloned()
                .collect(),
            floor: scene.floor.clone(),
            uniforms,
            initial,
            particles,
            faces: faces_buffer,
            white_water,
            white_water_group,
            solve,
            state,
            accum,
            known,
            solids,
            args,
            group,
            args_group,
            pipelines,
            clock_steps: 0,
            emit_points,
            landing_stride: landing_stride(scene),
            landing,
            bodies: liquid_bodies,
            bodies_buffer,
            bodies_desc: scene.liquid_bodies(),
            surface: None,
            screen_mesh: None,
            reference: None,
        };
        let spacing = liquid.uniforms.h / desc.particles_per_axis() as f32;
        let (particles, count) = (&liquid.particles, liquid.particle_count());
        match desc.surface {
            FluidSurface::MarchingCubes => {
                liquid.surface =
                    Some(surface::LiquidSurface::new(shared, scene, particles, count, spacing));
            }
            FluidSurface::ScreenMesh => {
                liquid.screen_mesh =
                    Some(screen_mesh::ScreenMeshSurface::new(shared, scene, particles, count));
            }
            FluidSurface::Points | FluidSurface::ScreenSpace | FluidSurface::None => {}
        }
        liquid.keep_reference(shared, scene);
        liquid.write_start(&shared.queue);
        Ok(Some(liquid))
    }

    /// Make the error view's reference mesh while `scene` asks for it (the
    /// view on, comparing surfaces, the liquid's own surface not already the
    /// reference) and drop it when it does not.
    fn keep_reference(&mut self, shared: &Shared, scene: &Scene) {
        let mut reference = crate::error_view::traced(scene);
        reference.fluid.surface_resolution = hydrolux_core::scene::MAX_SURFACE_RESOLUTION;
        let wanted = scene.render.view == hydrolux_core::scene::DebugView::Error
            && crate::error_view::compares_surfaces(scene)
            && !crate::error_view::is_finest_mesh(scene);
        if !wanted {
            self.reference = None;
        } else if self.reference.is_none() {
            let spacing = self.uniforms.h / self.desc.particles_per_axis() as f32;
            let (particles, count) = (&self.particles, self.particle_count());
            self.reference =
                Some(surface::LiquidSurface::new(shared, &reference, particles, count, spacing));
        }
    }

    /// The particles at rest where the sources put them, a still grid.
    fn write_start(&self, queue: &wgpu::Queue) {
        queue.write_buffer(&self.particles, 0, bytemuck::cast_slice(&self.initial));
        let buffers =
            [&self.faces, &self.known, &self.solve, &self.accum, &self.state, &self.white_water];
        for buffer in buffers {
            queue.write_buffer(buffer, 0, &vec![0u8; buffer.size() as usize]);
        }
        let solids_at = 2 * self.uniforms.face_count as u64 * 4;
        queue.write_buffer(&self.known, solids_at, bytemuck::cast_slice(&self.solids));
    }

    /// Where the bodies' loads start in the solve buffer (bytes).
    fn loads_at(&self) -> u64 {
        (6 * self.uniforms.cell_count as u64 + 4 * self.uniforms.cell_groups as u64) * 4
    }

    /// Particles simulated.
    pub fn particle_count(&self) -> u32 {
        self.uniforms.particle_count
    }

    /// Drawn size (m) of a white-water particle: a fleck of foam or a
    /// parcel of spray as wide as the liquid particle it came from.
    pub fn white_water_size(&self) -> f32 {
        2.0 * self.particle_radius()
    }

    /// Drawn radius of a particle (m): its share of a cell's volume as a sphere.
    pub fn particle_radius(&self) -> f32 {
        let per_cell = self.desc.particles_per_cell as f32;
        self.uniforms.h * (3.0 / (4.0 * std::f32::consts::PI * per_cell)).cbrt()
    }

    /// Record `steps` liquid steps into `encoder`, each in three compute
    /// passes (the transfer to the grid, the pressure solve, the transfer
    /// back and the advection), timed by `timer` when given.
    pub fn record_steps(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        steps: u64,
        mut timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        let u = &self.uniforms;
        let p = &self.pipelines;
        let particles = groups(u.particle_count);
        let cells = groups(u.cell_count);
        let faces = groups(u.face_count);
        let clear = groups(2 * u.face_count + u.cell_count);
        let run = |pass: &mut wgpu::ComputePass<'static>, pipeline, (x, y): (u32, u32)| {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(x, y, 1);
        };
        let begin = |encoder: &mut wgpu::CommandEncoder,
                     label: &'static str,
                     timer: Option<&mut crate::timing::GpuTimer>| {
            let mut pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(label),
                    timestamp_writes: timer.and_then(|t| t.compute_writes(label)),
                })
                .forget_lifetime();
            pass.set_bind_group(0, &self.group, &[]);
            pass.set_bind_group(1, &self.args_group, &[]);
            pass
        };
        let body_count = self.bodies.as_ref().map_or(0, |b| b.count());
        for _ in 0..steps {
            {
                let mut pass = begin(encoder, "liquid to grid", timer.as_deref_mut());
                if self.emit_points > 0 {
                    run(&mut pass, &p.emit, groups(self.emit_points));
                }
                if body_count > 0 {
                    run(&mut pass, &p.place_bodies, cells);
                }
                run(&mut pass, &p.clear, clear);
                run(&mut pass, &p.splat, particles);
                run(&mut pass, &p.faces, faces);
                if u.viscosity > 0.0 {
                    run(&mut pass, &p.diffuse, faces);
                    run(&mut pass, &p.diffuse_back, faces);
                }
            }
            {
                let mut pass = begin(encoder, "liquid pressure", timer.as_deref_mut());
                run(&mut pass, &p.solve_begin, cells);
                run(&mut pass, &p.reduce_begin, (1, 1));
                for iteration in 0..u.max_iterations as usize {
                    pass.set_pipeline(&p.cg_apply[iteration % 2]);
                    pass.dispatch_workgroups_indirect(&self.args, 0);
                    pass.set_pipeline(&p.cg_update[iteration % 2]);
                    pass.dispatch_workgroups_indirect(&self.args, 0);
                    run(&mut pass, &p.reduce_beta, (1, 1));
                }
            }
            let mut pass = begin(encoder, "liquid to particles", timer.as_deref_mut());
            if body_count > 0 {
                run(&mut pass, &p.body_loads, (body_count, 1));
            }
            run(&mut pass, &p.gradient, faces);
            run(&mut pass, &p.extrapolate_out, faces);
            run(&mut pass, &p.extrapolate_back, faces);
            run(&mut pass, &p.advance, particles);
            if u.white_water == 1 {
                let pool =
                    u.particle_count * hydrolux_core::fluid::white_water::SLOTS_PER_PARTICLE as u32;
                pass.set_bind_group(1, &self.white_water_group, &[]);
                run(&mut pass, &p.white_water_move, groups(pool));
                run(&mut pass, &p.white_water_shed, particles);
            }
        }
    }
}

impl crate::simulation::Simulation for Liquid {
    fn create(
        shared: &Shared,
        scene: &Scene,
        _published: &crate::simulation::Published,
    ) -> Result<Option<Self>, RenderError> {
        Liquid::new(shared, scene)
    }

    fn fits(&self, scene: &Scene) -> bool {
        let solids = |s: &Scene| -> Vec<hydrolux_core::scene::ObjectDesc> {
            s.objects.iter().filter(|o| hydrolux_core::scene::is_fluid_solid(o)).cloned().collect()
        };
        scene.fluid == self.desc
            && solids(scene) == self.solid_objects
            && scene.floor == self.floor
            && scene.fluid_landing() == self.landing
            && landing_stride(scene) == self.landing_stride
            && scene.liquid_bodies() == self.bodies_desc
    }

    /// The liquid starts from its sources at the clock's origin.
    fn restarts_clock(&self) -> bool {
        true
    }

    fn adjust(&mut self, shared: &Shared, scene: &Scene) {
        self.keep_reference(shared, scene);
    }

    fn publish(&self, published: &mut crate::simulation::Published) {
        published.liquid = Some(crate::simulation::published::LiquidState {
            particles: self.particles.clone(),
            count: self.particle_count(),
            radius: self.particle_radius(),
            landings: (self.uniforms.landing == 1).then(|| self.state.clone()),
            mesh: match (&self.surface, &self.screen_mesh) {
                (Some(s), _) => Some(s.mesh()),
                (_, Some(s)) => s.mesh(),
                _ => None,
            },
            reference_mesh: self.reference.as_ref().map(|s| s.mesh()),
            white_water: (self.uniforms.white_water == 1).then(|| {
                crate::simulation::published::LiquidWhiteWater {
                    particles: self.white_water.clone(),
                    slots: self.particle_count()
                        * hydrolux_core::fluid::white_water::SLOTS_PER_PARTICLE as u32,
                    size: self.white_water_size(),
                }
            }),
        });
        if let Some(b) = &self.bodies {
            published.bodies.extend(b.transforms());
        }
    }

    fn pace(&self) -> crate::simulation::Pace {
        crate::simulation::Pace::Follows
    }

    /// A screen-space mesh's buffers follow the frame's size.
    fn frame_size(&mut self, shared: &Shared, size: (u32, u32)) -> bool {
        self.screen_mesh.as_mut().is_some_and(|s| s.resize(&shared.device, size))
    }

    /// The surface mesh of the particles at the frame's time.
    fn record_frame(
        &mut self,
        shared: &Shared,
        encoder: &mut wgpu::CommandEncoder,
        plan: &crate::plan::FramePlan,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        // The error view's reference drawing meshes the finest grid.
        if let Some(r) = self.reference.as_ref().filter(|_| plan.liquid_reference) {
            r.record(encoder, timer);
        } else if let Some(s) = &self.surface {
            s.record(encoder, timer);
        } else if let Some(s) = &mut self.screen_mesh {
            s.record(&shared.queue, encoder, plan.matrices.view_proj, timer);
        }
    }

    fn reset(&mut self, queue: &wgpu::Queue, from: u64) {
        self.write_start(queue);
        self.clock_steps = from;
        if let Some(b) = &mut self.bodies {
            b.reset();
        }
    }

    fn bodies(&self) -> Vec<hydrolux_core::bodies::BodyState> {
        self.bodies.as_ref().map_or(Vec::new(), |b| b.states())
    }

    fn input(&mut self, input: &crate::simulation::Input) -> bool {
        use crate::simulation::Input;
        let Some(b) = &mut self.bodies else { return false };
        match *input {
            Input::Pull(i, target) => b.bodies.world.pull(i, target, 0.1),
            Input::Place(i, position) => b.bodies.world.place(i, position),
            _ => return false,
        }
        true
    }

    /// Where it lands in the interactive water, its run is submitted at
    /// once: the water's steps that take the landings (which follow in the
    /// registry) may submit early parts of their run before the caller's
    /// `encoder` goes.
    fn follow(
        &mut self,
        ctx: &mut crate::simulation::StepContext,
        encoder: &mut wgpu::CommandEncoder,
        clock_steps: u32,
    ) {
        if self.bodies.is_some() {
            self.follow_with_bodies(ctx.shared, clock_steps);
            return;
        }
        let steps = clock_steps as u64 * self.desc.substeps as u64;
        if self.uniforms.landing == 0 {
            self.record_steps(encoder, steps, None);
            self.clock_steps += clock_steps as u64;
            return;
        }
        let shared = ctx.shared;
        let mut own = shared.device.create_command_encoder(&Default::default());
        // The log starts anew where every landing in it has been taken: at
        // the start of a water step (its stride of clock steps).
        if self.clock_steps.is_multiple_of(self.landing_stride) {
            own.clear_buffer(&self.state, LANDING_COUNT_AT, Some(4));
        }
        self.record_steps(&mut own, steps, None);
        self.record_landing_dispatch(&mut own);
        shared.queue.submit([own.finish()]);
        self.clock_steps += clock_steps as u64;
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        Liquid::dump(self, name, ctx)
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "liquid",
    dumps: readback::DUMPS,
    shaders: || {
        vec![
            ("liquid".into(), source()),
            ("liquid surface".into(), surface::source()),
            ("liquid screen mesh".into(), screen_mesh::source()),
        ]
    },
    uniforms: || {
        vec![
            crate::uniforms::Layout::of::<surface::SurfaceUniforms>(surface::source()),
            crate::uniforms::Layout::of::<screen_mesh::ScreenMeshUniforms>(screen_mesh::source()),
            crate::uniforms::Layout::of::<LiquidUniforms>(source()),
            crate::uniforms::Layout::sized(
                "LiquidParticle",
                source(),
                std::mem::size_of::<LiquidParticle>(),
            ),
            crate::uniforms::Layout::sized(
                "SolveState",
                source(),
                std::mem::size_of::<SolveState>(),
            ),
            crate::uniforms::Layout::sized(
                "Emitter",
                source(),
                std::mem::size_of::<EmitterRecord>(),
            ),
            crate::uniforms::Layout::sized("Drain", source(), std::mem::size_of::<DrainRecord>()),
            crate::uniforms::Layout::sized(
                "Diffuse",
                source(),
                std::mem::size_of::<hydrolux_core::fluid::Diffuse>(),
            ),
            crate::uniforms::Layout::sized(
                "LiquidBody",
                source(),
                std::mem::size_of::<bodies::BodyRecord>(),
            ),
            crate::uniforms::Layout::sized(
                "LiquidBodies",
                source(),
                std::mem::size_of::<bodies::BodiesRecord>(),
            ),
            crate::uniforms::Layout::sized(
                "Landing",
                source(),
                std::mem::size_of::<LandingRecord>(),
            ),
        ]
    },
};
