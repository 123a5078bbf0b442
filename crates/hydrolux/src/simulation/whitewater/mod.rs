//! White water on the GPU (seed 003 §4.4 foam, §4.5 bubbles after Thürey
//! et al. 2007, §4.6 splashes, §2.3 particle systems): a foam field that
//! drifts, decays with Monahan's lifetime and is fed by breaking crests,
//! steep interactive water, splashes and what the particles leave; and one
//! pool of particles shared by bubbles and spray, emitted, merged and
//! integrated without a CPU round trip (atomic counters, a free-slot
//! stack, indirect dispatch and an indirect draw). The physics and the
//! order of a step are the CPU twin's, `hydrolux_core::whitewater`.
//!
//! A simulation of its own pace (`simulation/mod.rs`): it steps at
//! `whitewater.rate`, after the interactive water has reached its step's
//! time and with the surface evaluated there, taking the splashes the
//! interactive water hands it (`couplings.rs`). It publishes the foam's
//! cover (bound with the surface, binding 8, for the water's shading) and
//! the alive particles, which `draw.rs` (the `particles` technique) draws.

pub use crate::simulation::published::FoamWindow;

pub mod draw;
mod layer;
pub mod readback;
mod step;

use crate::gpu_util::*;
use crate::history::PingPong;
use crate::mips::{Downsampler, MipChain};
use crate::shaders;
use crate::surface_kind::{SurfaceKind, specialised_to};
use crate::uniforms::uniform;
use hydrolux_core::scene::{CLOCK_HZ, Scene, WaterModel};
use hydrolux_core::waves::ocean::OceanSpectrum;
use hydrolux_core::whitewater::{
    FOLD_GAIN, FoamGrid, JacobianSeries, Particle, SPRAY_DROP_RADIUS, Splash, WIND_DRIFT,
    calibrated_fold_threshold, surface_drift,
};

uniform! { WhitewaterParams;
    /// WGSL `WhitewaterParams` (simulation/whitewater/whitewater.wgsl).
    pub(crate) struct WhitewaterUniforms {
        pub grid_low: [i32; 2],
        pub grid_cells: i32,
        pub grid_periodic: i32,
        pub cell: f32,
        pub dt: f32,
        pub foam_keep: f32,
        pub fold_threshold: f32,
        pub drift: [f32; 2],
        pub fold_gain: f32,
        pub ripple_gain: f32,
        pub step: u32,
        pub splash_count: u32,
        pub capacity: u32,
        pub parity: u32,
        pub wind: [f32; 2],
        pub floor_depth: f32,
        pub max_age: f32,
        pub domain: [f32; 4],
        pub drop_radius: f32,
        pub spray_rate: f32,
        pub bubble_rate: f32,
        pub emission_radius: f32,
        pub camera: [f32; 2],
        pub run: u32,
        pub landing_stride: u32,
        pub deposits_base: u32,
        pub gained_base: u32,
        pub heads_base: u32,
        pub bucket_mask: u32,
        pub landing_volume: f32,
        pub bubble_mobility: f32,
        pub _pad2: u32,
        pub _pad3: u32,
    }
}

/// One of the foam's two copies and the step's bind group that reads it.
#[derive(Debug)]
struct FoamSlot {
    buffer: wgpu::Buffer,
    group: wgpu::BindGroup,
}

pub fn source() -> String {
    use hydrolux_core::whitewater as w;
    let consts: String = [
        ("G", w::G),
        ("WATER_NU", w::WATER_NU),
        ("WATER_SIGMA_RHO", w::WATER_SIGMA_RHO),
        ("AIR_WATER_RATIO", w::AIR_WATER_RATIO),
        ("DROP_DRAG", w::DROP_DRAG),
        ("VOLUME_UNIT_M3", w::VOLUME_UNIT_M3 as f32),
        ("BURST_FOAM_PER_M3", w::BURST_FOAM_PER_M3),
        ("SPRAY_FOAM", w::SPRAY_FOAM),
        ("FOLD_RAMP", w::FOLD_RAMP),
        ("DEPOSIT_SCALE", w::DEPOSIT_SCALE),
        ("FOAM_MAX", w::FOAM_MAX),
        ("KICK_SCALE", w::KICK_SCALE),
        ("MOTION_FOOTPRINT_PER_DEPTH", w::MOTION_FOOTPRINT_PER_DEPTH),
        ("ENTRAINMENT_ONSET_SPEED", w::ENTRAINMENT_ONSET_SPEED),
        ("ENTRAINMENT_RATIO", w::ENTRAINMENT_RATIO),
        ("PLUNGE_AIR_PER_BUBBLE", w::PLUNGE_AIR_PER_BUBBLE),
        ("PLUME_DEPTH_PER_SPEED", w::PLUME_DEPTH_PER_SPEED),
    ]
    .iter()
    .map(|(name, v)| format!("const {name}: f32 = {v:e};\n"))
    .chain(
        [
            ("COUNT_FREE", COUNT_FREE),
            ("COUNT_EMITTED", COUNT_EMITTED),
            ("COUNT_LOST", COUNT_LOST),
            ("PLUNGE_MAX_BUBBLES", w::PLUNGE_MAX_BUBBLES as usize),
            ("RISE_STEPS", w::RISE_STEPS as usize),
        ]
        .iter()
        .map(|(name, v)| format!("const {name}: u32 = {v}u;\n")),
    )
    .collect();
    shaders::compose(&consts, include_str!("whitewater.wgsl"))
}

/// Counters at the start of the atomics: alive in list 0 and 1, free, emitted, lost.
const COUNTERS: u32 = 16;
const COUNT_FREE: usize = 2;
const COUNT_EMITTED: usize = 3;
const COUNT_LOST: usize = 4;
/// Particles are born within this distance (m) of the camera, and live
/// within `PARTICLE_REACH` of it.
const EMISSION_RADIUS: f32 = 60.0;
const PARTICLE_REACH: f32 = 120.0;
/// Particles older than this (s) are retired.
const MAX_AGE: f32 = 20.0;
/// Foam per second a cell of interactive water gains where it is steep.
const RIPPLE_GAIN: f32 = 6.0;
/// Splashes one step takes at most (more wait for the next step).
const SPLASH_CAPACITY: u32 = 256;
/// What runs: bits of `WhitewaterParams.camera.z`.
const RUN_FOLD: u32 = 1;
const RUN_RIPPLES: u32 = 2;
const RUN_PARTICLES: u32 = 4;

fn kicks_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    kicks: &wgpu::Buffer,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("spray kicks"),
        layout,
        entries: &[wgpu::BindGroupEntry { binding: 1, resource: kicks.as_entire_binding() }],
    })
}

struct Pipelines {
    begin: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
    hash_clear: wgpu::ComputePipeline,
    hash_insert: wgpu::ComputePipeline,
    merge_pick: wgpu::ComputePipeline,
    merge_apply: wgpu::ComputePipeline,
    update: wgpu::ComputePipeline,
    foam_step: wgpu::ComputePipeline,
    emit: wgpu::ComputePipeline,
    plunge: wgpu::ComputePipeline,
}

pub struct Whitewater {
    /// The foam window now (it follows the camera unless it tiles).
    pub grid: FoamGrid,
    pub capacity: u32,
    table: u32,
    /// One step (s), and clock steps per step.
    pub dt: f32,
    stride: u64,
    /// Steps simulated at most to reach a time (`whitewater.memory`).
    memory_steps: u64,
    keep: f32,
    threshold: f32,
    drift: [f32; 2],
    wind: [f32; 2],
    floor_depth: f32,
    run: u32,
    spray_rate: f32,
    bubble_rate: f32,
    /// Clock steps followed (the steps taken are the foam's).
    clock_steps: u64,
    /// Splashes for the next steps (the caller's, bodies', drops').
    pending: Vec<Splash>,
    /// Cleared for a jump and not stepped since (a long jump comes in many
    /// batches: clear once).
    forgotten: bool,
    params: wgpu::Buffer,
    /// The foam per cell, and the step's bind group reading it (and
    /// writing the other): slot n % 2 after n steps.
    foam: PingPong<FoamSlot>,
    splashes: wgpu::Buffer,
    pub(crate) particles: wgpu::Buffer,
    atomics: wgpu::Buffer,
    pub(crate) slots: wgpu::Buffer,
    pub(crate) args: wgpu::Buffer,
    /// Cover per cell (mipmapped), bound with the surface.
    _cover: wgpu::Texture,
    cover_chain: MipChain,
    args_group: wgpu::BindGroup,
    /// `update`'s group 2: the interactive water's landing-spray kicks
    /// (a stand-in buffer without interactive water).
    kicks_layout: wgpu::BindGroupLayout,
    kicks_group: wgpu::BindGroup,
    no_kicks: wgpu::Buffer,
    /// `plunge`'s group 1: the liquid's landings log, and the buffer
    /// holding its indirect dispatch (`None`: no liquid lands here).
    log_layout: wgpu::BindGroupLayout,
    log: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    /// Volume (m³) of a landing particle of the liquid.
    landing_volume: f32,
    /// The bubbles' surface mobility (`hydrolux_core::whitewater::bubble_mobility`).
    bubble_mobility: f32,
    pipelines: Pipelines,
    /// The cover's mips are behind its level 0.
    mips_due: bool,
    /// The cover's view that the surface binds.
    cover_view: wgpu::TextureView,
    /// The scene it was made for.
    scene: Scene,
}

/// What one step is given (besides the surface).
pub struct StepInput {
    /// Centre (m, x z) of the foam window, when it does not tile.
    pub centre: [f32; 2],
    /// The camera (m, x z): particles are born and live around it.
    pub camera: [f32; 2],
    pub splashes: Vec<Splash>,
}

impl Whitewater {
    /// The white water of `scene` (`None` without any).
    pub fn new(shared: &crate::technique::Shared, scene: &Scene) -> Option<Self> {
        if !scene.has_whitewater() {
            return None;
        }
        let spectrum = &OceanSpectrum::new(&scene.ocean_settings());
        let device = &shared.device;
        let w = &scene.whitewater;
        let cells = w.resolution;
        let fft = scene.water.model == WaterModel::Fft;
        let grid = if scene.foam_tiles() {
            FoamGrid::periodic(cells, spectrum.settings.patch_size as f32)
        } else {
            FoamGrid::centred(cells, scene.foam_extent(), [0.0, 0.0])
        };
        let sea = scene.sea_state();
        let direction = [sea.wind_direction.cos() as f32, sea.wind_direction.sin() as f32];
        let waves = matches!(scene.water.model, WaterModel::Fft | WaterModel::Sines);
        let u10 = if waves { sea.wind_speed as f32 } else { 0.0 };
        let threshold =
            if fft && w.foam { fold_threshold(spectrum, &grid, sea.wind_speed) } else { 0.0 };
        let mut run = 0;
        if fft && w.foam {
            run |= RUN_FOLD;
        }
        if scene.has_interactive_water() && w.foam {
            run |= RUN_RIPPLES;
        }
        if w.particles {
            run |= RUN_PARTICLES;
        }
        let rate = w.rate.max(1);
        let dt = 1.0 / rate as f32;
        // A storage binding holds at most the device's limit.
        let limit = device.limits().max_storage_buffer_binding_size;
        let per_slot = std::mem::size_of::<Particle>() as u64;
        let capacity = if w.particles {
            // …and its indirect dispatches (64 a workgroup) within the
            // 65535 workgroups a dimension may have.
            (w.budget as u64).min(limit / per_slot).min(limit / 20).min(65_535 * 64) as u32
        } else {
            1
        };
        let table = capacity.next_power_of_two();
        let n2 = cells * cells;
        let storage = |label: &str, size: u64, extra: wgpu::BufferUsages| {
            storage_buffer(device, label, size, extra)
        };
        let none = wgpu::BufferUsages::empty();
        let foam = [0, 1].map(|_| storage("foam", 4 * n2 as u64, none));
        let splashes = storage(
            "splashes",
            SPLASH_CAPACITY as u64 * std::mem::size_of::<Splash>() as u64,
            none,
        );
        let particles = storage("particles", capacity as u64 * per_slot, none);
        let atomics =
            storage("whitewater atomics", 4 * (COUNTERS + n2 + capacity + table) as u64, none);
        let slots = storage("particle slots", 4 * 5 * capacity as u64, none);
        let args = storage("particle arguments", 32, wgpu::BufferUsages::INDIRECT);
        // Storage, not uniform: see `params` in whitewater.wgsl.
        let params = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("whitewater"),
                contents: bytemuck::bytes_of(&WhitewaterUniforms::default()),
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            },
        );
        let cover = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("foam cover"),
            size: wgpu::Extent3d { width: cells, height: cells, depth_or_array_layers: 1 },
            mip_level_count: cells.ilog2() + 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: crate::mips::FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let cover_chain = shared.downsampler.chain(device, &cover);
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("whitewater"),
            entries: &[
                storage_entry(0, cs, true),
                storage_entry(1, cs, true),
                storage_entry(2, cs, false),
                storage_texture_entry(3, crate::mips::FORMAT, wgpu::TextureViewDimension::D2Array),
                storage_entry(4, cs, true),
                storage_entry(5, cs, false),
                storage_entry(6, cs, false),
                storage_entry(7, cs, false),
            ],
        });
        let args_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("particle arguments"),
            entries: &[storage_entry(0, cs, false)],
        });
        let kicks_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("spray kicks"),
            entries: &[storage_entry(1, cs, false)],
        });
        let no_kicks = storage("no spray kicks", 16, none);
        let log_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("whitewater liquid landings log"),
            entries: &[storage_entry(15, cs, true)],
        });
        let kicks_group = kicks_group(device, &kicks_layout, &no_kicks);
        let cover_view = cover.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            base_mip_level: 0,
            mip_level_count: Some(1),
            ..Default::default()
        });
        let group = |p: usize| {
            fn b(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
                wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
            }
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("whitewater"),
                layout: &layout,
                entries: &[
                    b(0, &params),
                    b(1, &foam[p]),
                    b(2, &foam[1 - p]),
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&cover_view),
                    },
                    b(4, &splashes),
                    b(5, &particles),
                    b(6, &atomics),
                    b(7, &slots),
                ],
            })
        };
        let [even_group, odd_group] = [group(0), group(1)];
        let [even_foam, odd_foam] = foam;
        let foam = PingPong::new(
            FoamSlot { buffer: even_foam, group: even_group },
            FoamSlot { buffer: odd_foam, group: odd_group },
        );
        let args_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particle arguments"),
            layout: &args_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: args.as_entire_binding() }],
        });
        let module = shader(device, "whitewater", &source());
        let constants = specialised_to(SurfaceKind::of(scene));
        let surface = &shared.layouts.surface;
        let pipeline = |entry: &str| {
            compute_pipeline_with(device, entry, &module, entry, &[&layout, surface], &constants)
        };
        let with_args = |entry: &str| {
            compute_pipeline_with(
                device,
                entry,
                &module,
                entry,
                &[&layout, surface, &args_layout],
                &constants,
            )
        };
        let pipelines = Pipelines {
            begin: with_args("begin"),
            finish: with_args("finish"),
            hash_clear: pipeline("hash_clear"),
            hash_insert: pipeline("hash_insert"),
            merge_pick: pipeline("merge_pick"),
            merge_apply: pipeline("merge_apply"),
            update: compute_pipeline_with(
                device,
                "update",
                &module,
                "update",
                &[&layout, surface, &kicks_layout],
                &constants,
            ),
            foam_step: pipeline("foam_step"),
            emit: pipeline("emit"),
            plunge: compute_pipeline_with(
                device,
                "plunge",
                &module,
                "plunge",
                &[&layout, &log_layout],
                &constants,
            ),
        };
        let sampled_cover = cover.create_view(&Default::default());
        let whitewater = Whitewater {
            grid,
            capacity,
            table,
            dt,
            stride: (CLOCK_HZ / rate) as u64,
            memory_steps: (w.memory * rate as f32).ceil() as u64,
            keep: (-dt / scene.foam_life()).exp(),
            threshold,
            drift: surface_drift(u10, direction),
            wind: [0.8 * u10 * direction[0], 0.8 * u10 * direction[1]],
            floor_depth: if scene.floor.depth > 0.0 { scene.floor.depth } else { 1.0e4 },
            run,
            spray_rate: if w.particles { w.spray_rate } else { 0.0 },
            bubble_rate: if w.particles { w.bubble_rate } else { 0.0 },
            clock_steps: 0,
            pending: Vec::new(),
            forgotten: false,
            params,
            foam,
            splashes,
            particles,
            atomics,
            slots,
            args,
            _cover: cover,
            cover_chain,
            args_group,
            kicks_layout,
            kicks_group,
            no_kicks,
            log_layout,
            log: None,
            landing_volume: scene.fluid_landing().map_or(0.0, |l| l.particle_volume as f32),
            bubble_mobility: hydrolux_core::whitewater::bubble_mobility(
                scene.water.salinity as f64,
            ),
            pipelines,
            mips_due: true,
            cover_view: sampled_cover,
            scene: scene.clone(),
        };
        whitewater.reset_buffers(&shared.queue);
        Some(whitewater)
    }

    /// Where landing spray kicks the interactive water (`None`: there is none).
    pub fn bind_kicks(&mut self, device: &wgpu::Device, kicks: Option<&wgpu::Buffer>) {
        self.kicks_group = kicks_group(device, &self.kicks_layout, kicks.unwrap_or(&self.no_kicks));
    }

    /// Take the liquid's landings from `log` (its state buffer; `None`: no
    /// liquid lands here).
    pub fn bind_landings(&mut self, device: &wgpu::Device, log: Option<&wgpu::Buffer>) {
        self.log = log.map(|buffer| {
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("whitewater liquid landings log"),
                layout: &self.log_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 15,
                    resource: buffer.as_entire_binding(),
                }],
            });
            (buffer.clone(), group)
        });
    }

    /// Whether `scene` keeps this state.
    pub fn fits(&self, scene: &Scene) -> bool {
        scene.whitewater == self.scene.whitewater
            && scene.water.moves_as(&self.scene.water)
            && scene.ocean == self.scene.ocean
            && scene.floor.depth == self.scene.floor.depth
            && scene.fluid_landing() == self.scene.fluid_landing()
    }

    fn reset_buffers(&self, queue: &wgpu::Queue) {
        let n2 = (self.grid.cells * self.grid.cells) as usize;
        for f in self.foam.both() {
            queue.write_buffer(&f.buffer, 0, bytemuck::cast_slice(&vec![0.0f32; n2]));
        }
        let mut atomics = vec![0u32; (COUNTERS + n2 as u32 + self.capacity + self.table) as usize];
        atomics[COUNT_FREE] = self.capacity;
        queue.write_buffer(&self.atomics, 0, bytemuck::cast_slice(&atomics));
        // The free stack holds every slot, the lowest on top.
        let c = self.capacity as usize;
        let mut slots = vec![0u32; 5 * c];
        for (k, s) in slots[2 * c..3 * c].iter_mut().enumerate() {
            *s = (c - 1 - k) as u32;
        }
        queue.write_buffer(&self.slots, 0, bytemuck::cast_slice(&slots));
        queue.write_buffer(&self.args, 0, bytemuck::cast_slice(&[0u32, 1, 1, 0, 6, 0, 0, 0]));
    }

    /// Back to no foam and no particles at t = 0.
    /// Start again with no foam and no particles at clock step `from`.
    pub fn reset(&mut self, queue: &wgpu::Queue, from: u64) {
        self.reset_buffers(queue);
        self.foam.start_at(from / self.stride);
        self.clock_steps = from;
        self.pending.clear();
        self.mips_due = true;
    }

    /// A splash for the next step (a caller's); false when too many wait.
    pub fn splash(&mut self, splash: Splash) -> bool {
        let room = self.pending.len() < 4 * SPLASH_CAPACITY as usize;
        if room {
            self.pending.push(splash);
        }
        room
    }

    /// Where the foam's window lies (the surface's `foam_origin`,
    /// `foam_side`, `foam_tiles`).
    pub fn foam_area(&self) -> FoamWindow {
        let side = self.grid.cell * self.grid.cells as f32;
        let origin = [0, 1].map(|a| self.grid.low[a] as f32 * self.grid.cell);
        FoamWindow { origin, side, tiles: self.grid.periodic }
    }

    /// The surface's `foam_wind` and `foam_streak`: the wind's direction and how streaky the
    /// foam is. Wind rows foam into streaks along itself (Langmuir
    /// circulation, wind streaks): longer the stronger it blows, 1 + U/6
    /// (up to 4) times as long as wide; still air leaves round patches.
    pub fn foam_wind(&self) -> ([f32; 2], f32) {
        let d = self.drift;
        let speed = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if speed <= 0.0 {
            return ([1.0, 0.0], 1.0);
        }
        let u10 = speed / WIND_DRIFT;
        ([d[0] / speed, d[1] / speed], (1.0 + u10 / 6.0).min(4.0))
    }

    /// Which alive list holds the particles now.
    pub fn list(&self) -> u32 {
        self.foam.parity() as u32
    }

    /// Whether this white water runs the particles.
    pub fn has_particles(&self) -> bool {
        self.run & RUN_PARTICLES != 0
    }
}

/// The breaking threshold J₀ for the ocean `spectrum` seen at the foam
/// cells of `grid`, calibrated on the CPU twin to Monahan &
/// O'Muircheartaigh's whitecap cover at wind `u10`
/// ([`calibrated_fold_threshold`]).
pub fn fold_threshold(spectrum: &OceanSpectrum, grid: &FoamGrid, u10: f64) -> f32 {
    calibrated_fold_threshold(&JacobianSeries::of_ocean(spectrum, grid), u10)
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "whitewater",
    dumps: readback::DUMPS,
    shaders: || vec![("whitewater".into(), source())],
    uniforms: || {
        vec![
            crate::uniforms::Layout::of::<WhitewaterUniforms>(source()),
            crate::uniforms::Layout::sized("Particle", source(), std::mem::size_of::<Particle>()),
            crate::uniforms::Layout::sized("Splash", source(), std::mem::size_of::<Splash>()),
        ]
    },
};

#[cfg(test)]
mod tests {
    /// The foam's albedo that the water shader and the caustics read in WGSL
    /// is hydrolux-core's (`FOAM_ALBEDO`, `foam_transmittance`).
    #[test]
    fn wgsl_foam_albedo_is_the_cores() {
        let source = crate::shaders::compose("", "#import surface\n");
        let module = naga::front::wgsl::parse_str(&source).expect("surface.wgsl parses");
        use hydrolux_core::whitewater as w;
        for (name, value) in [
            ("FOAM_ALBEDO", w::FOAM_ALBEDO),
            ("BUBBLE_CLOUD_REFLECTANCE", w::BUBBLE_CLOUD_REFLECTANCE),
            ("BUBBLE_CLOUD_DEPTH", w::BUBBLE_CLOUD_DEPTH),
        ] {
            let (_, constant) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("{name} in surface.wgsl"));
            match module.global_expressions[constant.init] {
                naga::Expression::Literal(naga::Literal::F32(v)) => assert_eq!(v, value, "{name}"),
                ref e => panic!("{name} is not an f32 literal: {e:?}"),
            }
        }
    }

    /// A spray parcel's drops and mist in WGSL (light.wgsl) are drawn with
    /// their CPU twin's constants (hydrolux_core::whitewater::spray_look).
    #[test]
    fn wgsl_spray_look_constants_are_the_twins() {
        use hydrolux_core::whitewater::spray_look as twin;
        let source = crate::shaders::compose("", "#import white_water_light\n");
        let module = naga::front::wgsl::parse_str(&source).expect("light.wgsl parses");
        let literal = |name: &str| {
            let (_, constant) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("{name} in light.wgsl"));
            match module.global_expressions[constant.init] {
                naga::Expression::Literal(l) => l,
                ref e => panic!("{name} is not a literal: {e:?}"),
            }
        };
        use naga::Literal::{F32, U32};
        for (name, value) in [
            ("MIN_DROP_PIXELS", twin::MIN_DROP_PIXELS),
            ("MIST_BELOW_SPACING", twin::MIST_BELOW_SPACING),
            ("DROPS_FROM_SPACING", twin::DROPS_FROM_SPACING),
            ("SPREAD", twin::SPREAD),
            ("DROP_ASYMMETRY", twin::DROP_ASYMMETRY),
        ] {
            assert_eq!(literal(name), F32(value), "{name}");
        }
        for (name, value) in [
            ("DRAWN_DROPS", twin::DRAWN_DROPS),
            ("SALT_RADIUS", twin::SALT_RADIUS),
            ("SALT_ANGLE", twin::SALT_ANGLE),
        ] {
            assert_eq!(literal(name), U32(value), "{name}");
        }
    }
}
