//! Interactive water on the GPU (seed 003 §2.4; Tessendorf's eWave): a
//! dynamic heightfield stepped by an exact spectral rotation with the
//! capillary–gravity dispersion, disturbed by drops, rain and the viewer.
//! The surface technique owns it and adds its heights and slopes to every
//! surface model (`shaders/surface.wgsl`, `RIPPLES`). Physics, boundaries
//! and the step are described with the CPU twin,
//! `hydrolux_core::waves::ripples`; `ripples.wgsl` follows it line by line.
//! `dynamics.rs` steps it together with the bodies floating in it.

pub mod dynamics;
pub mod readback;

use crate::gpu_util::*;
use crate::shaders;
use crate::timing::GpuTimer;
use crate::uniforms::uniform;
use hydrolux_core::scene::Scene;
use hydrolux_core::waves::dispersion::GRAVITY;
use hydrolux_core::waves::ripples::{
    BodyMove, Drop, RippleBed, RippleBoundary, RippleSettings, RippleWindow, sponge_rate,
};

uniform! { RippleParams;
    /// WGSL `RippleParams` (simulation/ripples/ripples.wgsl).
    pub(crate) struct RippleUniforms {
        pub cells: u32,
        pub fft_size: u32,
        pub edges: u32,
        pub sponge_cells: u32,
        pub window_origin: [i32; 2],
        pub first_drop: i32,
        pub drop_count: i32,
        pub cell: f32,
        pub dt: f32,
        pub depths: [f32; 2],
        pub gravity: f32,
        pub tension: f32,
        pub viscosity: f32,
        pub damping: f32,
        pub sponge_rate: f32,
        pub kick_per_unit: f32,
        pub first_move: i32,
        pub move_count: i32,
        pub landing_step: u32,
        pub landing_stride: u32,
        pub landing_volume: f32,
        pub landing_images: f32,
    }
}

pub fn source() -> String {
    use hydrolux_core::waves::ripples::{
        BREAKING_RELAX, BREAKING_SLOPE, HULL_GAP, PUSHED_UNITS_PER_M, RELEASE_REACH_CELLS,
    };
    // Breaking's and the hulls' constants from the CPU twin's, not copied by hand.
    use hydrolux_core::coupling::{PLUME_DEPTH_PER_SPEED, PLUNGE_SPREAD_CELLS};
    let consts = format!(
        "const PLUME_DEPTH_PER_SPEED: f32 = {PLUME_DEPTH_PER_SPEED:?};\nconst PLUNGE_SPREAD_CELLS: i32 = {PLUNGE_SPREAD_CELLS};\nconst BREAKING_SLOPE: f32 = {BREAKING_SLOPE:?};\nconst BREAKING_RELAX: f32 = {BREAKING_RELAX:?};\nconst HULL_GAP: f32 = {HULL_GAP:?};\nconst PUSHED_UNITS_PER_M: f32 = {PUSHED_UNITS_PER_M:?};\nconst RELEASE_REACH_CELLS: i32 = {RELEASE_REACH_CELLS};\nconst EDGES_WALLS: u32 = {}u;\n",
        edges_index(RippleBoundary::Walls)
    );
    shaders::compose(&consts, include_str!("ripples.wgsl"))
}

/// Format of the surface's ripple texture (h, ∂h/∂x, ∂h/∂z): storage-writable
/// and filterable everywhere.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The shaders' code of an edge kind (`RippleParams.grid.z`; the surface's
/// `RIPPLES` constant is this + 1, 0 meaning no ripples).
pub fn edges_index(b: RippleBoundary) -> u32 {
    match b {
        RippleBoundary::Walls => 0,
        RippleBoundary::Open => 1,
        RippleBoundary::Periodic => 2,
    }
}

/// The floor as the water stands on it: its shape, not its look.
fn ground(scene: &Scene) -> hydrolux_core::scene::FloorDesc {
    hydrolux_core::scene::FloorDesc { material: Default::default(), ..scene.floor.clone() }
}

/// Each domain cell's still-water depth under `window` into `buffer`.
fn write_depths(
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    bed: &RippleBed,
    settings: &RippleSettings,
    window: &RippleWindow,
) {
    let depths: Vec<f32> = bed.depths(&settings.grid, window).iter().map(|&d| d as f32).collect();
    queue.write_buffer(buffer, 0, bytemuck::cast_slice(&depths));
}

/// Slots of the per-step uniforms, each at the device's dynamic-offset alignment.
const SLOTS: u64 = 256;
/// Steps one [`RipplePass::record`] takes at most (one slot is the publish's).
pub const MAX_STEPS: usize = SLOTS as usize - 1;

/// What disturbs the water in one step.
#[derive(Clone, Debug, Default)]
pub struct StepInput {
    pub drops: Vec<Drop>,
    pub moves: Vec<BodyMove>,
    /// The water's step index (since its clock's origin).
    pub step: u64,
}

/// A body's move as `BodyMove` in ripples.wgsl: its shape, the pose whose
/// hollow it held before the step ([`BodyMove::held`], its position's w 1
/// where it was lifted out: [`BodyMove::released`]) and its pose after.
fn gpu_move(m: &BodyMove) -> [[f32; 4]; 5] {
    let (code, size) = m.shape.gpu();
    let pos = |p: &hydrolux_core::bodies::Pose| p.position.as_vec3().extend(0.0).to_array();
    let rot = |p: &hydrolux_core::bodies::Pose| p.rotation.as_quat().to_array();
    let held = m.held();
    let mut held_position = pos(&held);
    held_position[3] = if m.released.is_some() { 1.0 } else { 0.0 };
    [
        [size[0], size[1], size[2], code as f32],
        held_position,
        rot(&held),
        pos(&m.after),
        rot(&m.after),
    ]
}

/// Δφ (m²/s) per unit of landing spray: the scene's spray parcel over a
/// cell; without spray, the liquid's particle where it lands here (0
/// without either).
fn kick_per_unit(scene: &Scene, settings: &RippleSettings) -> f32 {
    let w = &scene.whitewater;
    let cell = settings.grid.cell_size;
    if scene.has_whitewater() && w.particles {
        hydrolux_core::whitewater::kick_per_unit(w.spray_size, w.spray_water, cell) as f32
    } else if let Some(l) = scene.fluid_landing() {
        hydrolux_core::coupling::kick_per_unit_of_volume(l.particle_volume, cell) as f32
    } else {
        0.0
    }
}

/// The liquid's landings: the pipeline over its log, the layout and group of
/// the water's buffers it writes (group 0), the log's layout (group 1).
struct LandingPass {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    log_layout: wgpu::BindGroupLayout,
    /// The liquid's log, once it lands here.
    log: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

fn storage(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

pub struct RipplePass {
    pub settings: RippleSettings,
    /// The scene whose drops and emitters are scripted.
    scene: Scene,
    pub window: RippleWindow,
    /// Drops asked for by the viewer, for the next step.
    pending: Vec<Drop>,
    /// The bodies of the last step, for `publish` (which marks the cells
    /// their hulls cover).
    last_moves: Vec<[[f32; 4]; 5]>,
    params: wgpu::Buffer,
    slot_size: u64,
    spatial: wgpu::Buffer,
    spectral: wgpu::Buffer,
    /// Each domain cell's still-water depth (m; 0: dry), for `depth_window`.
    depth: wgpu::Buffer,
    /// What the water stands on: where it is not flat, an open domain's
    /// depths are taken anew wherever its window goes.
    bed: RippleBed,
    depth_window: RippleWindow,
    drops: wgpu::Buffer,
    drop_capacity: u64,
    moves: wgpu::Buffer,
    move_capacity: u64,
    heights: wgpu::Buffer,
    /// Landing spray per texel (fixed-point speeds; the white water adds,
    /// the next step uses them up).
    pub kicks: wgpu::Buffer,
    /// The hulls' ledger (`HullLedger` in ripples.wgsl): the water they
    /// pushed out in the step under way (fixed point), the free water's
    /// mean height.
    pushed: wgpu::Buffer,
    /// Δφ (m²/s) per kick unit: the scene's spray parcel over a cell.
    kick_per_unit: f32,
    pub texture: wgpu::Texture,
    /// The texture's view that the surface binds.
    pub view: wgpu::TextureView,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
    fft_groups: [wgpu::BindGroup; 2],
    disturb: wgpu::ComputePipeline,
    free_level: wgpu::ComputePipeline,
    spectral_step: wgpu::ComputePipeline,
    publish: wgpu::ComputePipeline,
    fft_rows: wgpu::ComputePipeline,
    fft_columns: wgpu::ComputePipeline,
    landing: LandingPass,
}

impl RipplePass {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        caps: &crate::capabilities::Capabilities,
        scene: &Scene,
        settings: RippleSettings,
        bed: RippleBed,
    ) -> Self {
        let n = settings.grid.cells as u32;
        let f = settings.grid.fft_size() as u32;
        let cells = |count: u64, bytes: u64, label: &str, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: count * bytes,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let copy = wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        let grid = (f * f) as u64;
        let spatial = cells(grid, 16, "ripples spatial", copy);
        let spectral = cells(grid, 16, "ripples spectral", copy);
        let depth = cells((n * n) as u64, 4, "ripples depth", copy);
        let heights = cells((n * n) as u64, 4, "ripples heights", copy);
        let kicks = cells((n * n) as u64, 4, "ripples spray kicks", copy);
        let pushed = cells(1, 8, "ripples hulls' ledger", copy);
        let kick_per_unit = kick_per_unit(scene, &settings);
        let drop_capacity = 256;
        let drops = cells(drop_capacity, 16, "ripples drops", copy);
        let slot_size = (std::mem::size_of::<RippleUniforms>() as u64)
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment as u64);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ripples steps"),
            size: slot_size * SLOTS,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let texture = texture_2d(
            device,
            "ripples",
            (n, n),
            FORMAT,
            wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST,
        );
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ripples"),
            entries: &[
                layout_entry(
                    0,
                    cs,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: true,
                        min_binding_size: wgpu::BufferSize::new(
                            std::mem::size_of::<RippleUniforms>() as u64,
                        ),
                    },
                ),
                storage_entry(1, cs, false),
                storage_entry(2, cs, false),
                storage_entry(3, cs, true),
                storage_entry(4, cs, true),
                storage_entry(5, cs, false),
                storage_texture_entry(6, FORMAT, wgpu::TextureViewDimension::D2),
                storage_entry(7, cs, true),
                storage_entry(8, cs, false),
                storage_entry(9, cs, false),
            ],
        });
        let fft_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("ripples fft"),
            entries: &[storage_entry(0, cs, false)],
        });
        let module = shader(device, "ripples", &source());
        let fft_module = shader(
            device,
            "ripples fft",
            &crate::simulation::ocean::fft_source(f, caps.max_workgroup_threads),
        );
        let pipeline = |entry: &str| compute_pipeline(device, entry, &module, entry, &[&layout]);
        let fft = |entry: &str| {
            compute_pipeline(device, "ripples fft", &fft_module, entry, &[&fft_layout])
        };
        let fft_group = |buffer: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ripples fft"),
                layout: &fft_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            })
        };
        let fft_groups = [fft_group(&spatial), fft_group(&spectral)];
        let free_level = pipeline("free_level");
        let (disturb, spectral_step, publish) =
            (pipeline("disturb"), pipeline("spectral_step"), pipeline("publish"));
        let (fft_rows, fft_columns) = (fft("fft_rows"), fft("fft_columns"));
        let landing = {
            let params_entry = layout_entry(
                0,
                cs,
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: true,
                    min_binding_size: wgpu::BufferSize::new(
                        std::mem::size_of::<RippleUniforms>() as u64
                    ),
                },
            );
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ripples liquid landings"),
                entries: &[params_entry, storage_entry(8, cs, false), storage_entry(9, cs, false)],
            });
            let log_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ripples liquid landings log"),
                entries: &[storage_entry(0, cs, true)],
            });
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ripples liquid landings"),
                layout: &layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                            buffer: &params,
                            offset: 0,
                            size: wgpu::BufferSize::new(
                                std::mem::size_of::<RippleUniforms>() as u64
                            ),
                        }),
                    },
                    wgpu::BindGroupEntry { binding: 8, resource: kicks.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 9, resource: pushed.as_entire_binding() },
                ],
            });
            let pipeline = compute_pipeline(
                device,
                "land_liquid",
                &module,
                "land_liquid",
                &[&layout, &log_layout],
            );
            LandingPass { pipeline, group, log_layout, log: None }
        };
        let move_capacity = 16;
        let moves = cells(move_capacity, 80, "ripples body moves", copy);
        // Bound below, once the pass owns its resources.
        let placeholder = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ripples fft"),
            layout: &fft_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: spatial.as_entire_binding() }],
        });
        let window = RippleWindow::centred(&settings.grid, scene.ripples.center.map(|c| c as f64));
        write_depths(queue, &depth, &bed, &settings, &window);
        let mut pass = RipplePass {
            settings,
            scene: scene.clone(),
            window,
            bed,
            depth_window: window,
            pending: Vec::new(),
            last_moves: Vec::new(),
            group: placeholder,
            params,
            slot_size,
            spatial,
            spectral,
            depth,
            drops,
            drop_capacity,
            moves,
            move_capacity,
            heights,
            kicks,
            pushed,
            kick_per_unit,
            view: texture.create_view(&Default::default()),
            texture,
            layout,
            fft_groups,
            disturb,
            free_level,
            spectral_step,
            publish,
            fft_rows,
            fft_columns,
            landing,
        };
        pass.group = pass.bind(device);
        pass.reset(queue);
        pass
    }

    fn bind(&self, device: &wgpu::Device) -> wgpu::BindGroup {
        let view = self.texture.create_view(&Default::default());
        fn whole(b: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding: b, resource: buffer.as_entire_binding() }
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ripples"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.params,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<RippleUniforms>() as u64),
                    }),
                },
                whole(1, &self.spatial),
                whole(2, &self.spectral),
                whole(3, &self.depth),
                whole(4, &self.drops),
                whole(5, &self.heights),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                whole(7, &self.moves),
                whole(8, &self.kicks),
                whole(9, &self.pushed),
            ],
        })
    }

    /// Take the liquid's landings from `log` (its state buffer; `None`: no
    /// liquid lands here).
    pub fn bind_landings(&mut self, device: &wgpu::Device, log: Option<&wgpu::Buffer>) {
        self.landing.log = log.map(|buffer| {
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ripples liquid landings log"),
                layout: &self.landing.log_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buffer.as_entire_binding(),
                }],
            });
            (buffer.clone(), group)
        });
    }

    /// Whether `scene` keeps this simulation (same physics, grid and script).
    pub fn fits(&self, scene: &Scene) -> bool {
        scene.ripple_settings() == Some(self.settings)
            && scene.ripples == self.scene.ripples
            && scene.drops == self.scene.drops
            && scene.emitters == self.scene.emitters
            && kick_per_unit(scene, &self.settings) == self.kick_per_unit
            && scene.fluid_landing() == self.scene.fluid_landing()
            && ground(scene) == ground(&self.scene)
            && scene.ripple_obstacles() == self.bed.obstacles
    }

    /// Back to still water (t = 0).
    pub fn reset(&mut self, queue: &wgpu::Queue) {
        let f = self.settings.grid.fft_size();
        let n = self.settings.grid.cells as u32;
        queue.write_buffer(&self.spectral, 0, &vec![0u8; f * f * 16]);
        queue.write_buffer(&self.heights, 0, &vec![0u8; (n * n * 4) as usize]);
        queue.write_buffer(&self.kicks, 0, &vec![0u8; (n * n * 4) as usize]);
        queue.write_buffer(&self.pushed, 0, &[0u8; 8]);
        queue.write_texture(
            self.texture.as_image_copy(),
            &vec![0u8; (n * n * 8) as usize],
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(8 * n),
                rows_per_image: Some(n),
            },
            wgpu::Extent3d { width: n, height: n, depth_or_array_layers: 1 },
        );
        self.pending.clear();
    }

    /// Start from still water shaped by `heights` on the FFT grid (row = z):
    /// both depth levels hold it, at rest, about the `hulls` of the bodies
    /// at rest in it (which a publish before the first step marks: without
    /// them, a frame at t = 0 drew the hollows' edges as steep water, a
    /// bright ring about the pool's ball that the next frame lost).
    pub fn set_heights(&mut self, queue: &wgpu::Queue, heights: &[f64], hulls: &[BodyMove]) {
        self.last_moves = hulls.iter().map(gpu_move).collect();
        let state: Vec<[f32; 4]> =
            heights.iter().map(|&h| [h as f32, 0.0, h as f32, 0.0]).collect();
        queue.write_buffer(&self.spectral, 0, bytemuck::cast_slice(&state));
        // The domain's heights as `publish` would write them, so that what
        // the bodies read back at step 0 is this water whether or not a
        // frame drew it first (a frame at t = 0 publishes; a jump does not).
        let g = self.settings.grid;
        let (n, f) = (g.cells, g.fft_size());
        let mut domain = vec![0.0f32; n * n];
        for q in 0..n {
            for p in 0..n {
                let (d, _) = hydrolux_core::waves::ripples::domain_cell(&g, &self.window, [p, q]);
                domain[d[1] * n + d[0]] = heights[q * f + p] as f32;
            }
        }
        queue.write_buffer(&self.heights, 0, bytemuck::cast_slice(&domain));
    }

    /// A drop for the next step (the viewer's click, a thrown ball).
    pub fn disturb(&mut self, drop: Drop) {
        if self.pending.len() < hydrolux_core::scene::MAX_DROPS_PER_STEP {
            self.pending.push(drop);
        }
    }

    /// Move an open domain ahead of `camera` (whole cells); walls stay put.
    pub fn follow(&mut self, camera: &hydrolux_core::camera::Camera) {
        if self.settings.grid.boundary == RippleBoundary::Open {
            let (p, l) = (camera.position, camera.look_at);
            self.window = RippleWindow::ahead_of(
                &self.settings.grid,
                [p.x, p.y, p.z].map(|c| c as f64),
                [l.x, l.y, l.z].map(|c| c as f64),
            );
        }
    }

    fn uniforms(&self, first_drop: usize, drops: usize) -> RippleUniforms {
        let s = &self.settings;
        let g = &s.grid;
        RippleUniforms {
            cells: g.cells as u32,
            fft_size: g.fft_size() as u32,
            edges: edges_index(g.boundary),
            sponge_cells: g.sponge_cells() as u32,
            window_origin: self.window.origin.map(|c| c as i32),
            first_drop: first_drop as i32,
            drop_count: drops as i32,
            cell: g.cell_size as f32,
            dt: s.dt as f32,
            depths: s.depths.map(|d| d as f32),
            gravity: GRAVITY as f32,
            tension: s.tension as f32,
            viscosity: s.viscosity as f32,
            damping: s.damping as f32,
            sponge_rate: sponge_rate(g) as f32,
            kick_per_unit: self.kick_per_unit,
            first_move: 0,
            move_count: 0,
            landing_step: 0,
            landing_stride: self.scene.ripples.clock_stride(),
            landing_volume: self.scene.fluid_landing().map_or(0.0, |l| l.particle_volume as f32),
            landing_images: ((g.fft_size() / g.cells) as f32).powi(2),
        }
    }

    /// The scripted drops of simulation step `step`, and the viewer's
    /// pending ones.
    pub fn drops_for(&mut self, step: u64) -> Vec<Drop> {
        let mut drops = self.scene.drops_in_step(step, self.settings.dt);
        drops.append(&mut self.pending);
        drops
    }

    /// Record one simulation step per input (at most [`MAX_STEPS`]), then
    /// write the surface's texture and heights.
    pub fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        inputs: &[StepInput],
        timer: Option<&mut GpuTimer>,
    ) {
        let count = inputs.len() as u64;
        assert!(count <= MAX_STEPS as u64, "at most {MAX_STEPS} steps per record");
        // An open domain that moved stands on other ground.
        if self.window != self.depth_window && !self.bed.is_flat() {
            write_depths(queue, &self.depth, &self.bed, &self.settings, &self.window);
            self.depth_window = self.window;
        }
        let mut drops: Vec<[f32; 4]> = Vec::new();
        let mut moves: Vec<[[f32; 4]; 5]> = Vec::new();
        let mut slots = vec![0u8; (self.slot_size * (count + 1)) as usize];
        let gpu_moves =
            |moves: &[BodyMove]| -> Vec<[[f32; 4]; 5]> { moves.iter().map(gpu_move).collect() };
        if let Some(last) = inputs.last() {
            self.last_moves = gpu_moves(&last.moves);
        }
        for i in 0..=count as usize {
            let empty = StepInput::default();
            let input = inputs.get(i).unwrap_or(&empty);
            let mut u = self.uniforms(drops.len(), input.drops.len());
            u.landing_step = input.step as u32;
            drops.extend(
                input
                    .drops
                    .iter()
                    .map(|d| [d.x as f32, d.z as f32, d.radius as f32, d.strength as f32]),
            );
            // The publish's slot (the last) holds the last step's bodies.
            let step_moves: Vec<[[f32; 4]; 5]> =
                if i < count as usize { gpu_moves(&input.moves) } else { self.last_moves.clone() };
            u.first_move = moves.len() as i32;
            u.move_count = step_moves.len() as i32;
            moves.extend(step_moves);
            let at = i * self.slot_size as usize;
            slots[at..at + std::mem::size_of::<RippleUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
        }
        queue.write_buffer(&self.params, 0, &slots);
        let grow = |have: u64, need: usize| {
            (need as u64 > have).then(|| (need as u64).next_power_of_two())
        };
        let (grow_drops, grow_moves) =
            (grow(self.drop_capacity, drops.len()), grow(self.move_capacity, moves.len()));
        if let Some(c) = grow_drops {
            self.drop_capacity = c;
            self.drops = storage(device, "ripples drops", c * 16);
        }
        if let Some(c) = grow_moves {
            self.move_capacity = c;
            self.moves = storage(device, "ripples body moves", c * 80);
        }
        if grow_drops.is_some() || grow_moves.is_some() {
            self.group = self.bind(device);
        }
        if !drops.is_empty() {
            queue.write_buffer(&self.drops, 0, bytemuck::cast_slice(&drops));
        }
        if !moves.is_empty() {
            queue.write_buffer(&self.moves, 0, bytemuck::cast_slice(&moves));
        }
        let f = self.settings.grid.fft_size() as u32;
        let n = self.settings.grid.cells as u32;
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ripples"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("ripples")),
        });
        let groups = f.div_ceil(8);
        for i in 0..count {
            let offset = (i * self.slot_size) as u32;
            if let Some((log, log_group)) = &self.landing.log {
                pass.set_pipeline(&self.landing.pipeline);
                pass.set_bind_group(0, &self.landing.group, &[offset]);
                pass.set_bind_group(1, log_group, &[]);
                pass.dispatch_workgroups_indirect(
                    log,
                    crate::simulation::liquid::LANDING_DISPATCH_AT,
                );
            }
            // The free water's level the hulls press from (only hulls read it).
            if !inputs[i as usize].moves.is_empty() {
                pass.set_pipeline(&self.free_level);
                pass.set_bind_group(0, &self.group, &[offset]);
                pass.dispatch_workgroups(1, 1, 1);
            }
            pass.set_pipeline(&self.disturb);
            pass.set_bind_group(0, &self.group, &[offset]);
            pass.dispatch_workgroups(groups, groups, 1);
            self.transform(&mut pass, 0, f);
            pass.set_pipeline(&self.spectral_step);
            pass.set_bind_group(0, &self.group, &[offset]);
            pass.dispatch_workgroups(groups, groups, 1);
            self.transform(&mut pass, 1, f);
        }
        pass.set_pipeline(&self.publish);
        pass.set_bind_group(0, &self.group, &[(count * self.slot_size) as u32]);
        pass.dispatch_workgroups(n.div_ceil(8), n.div_ceil(8), 1);
    }

    /// 2-D FFT of buffer `which` (0 spatial, 1 spectral) in place.
    fn transform(&self, pass: &mut wgpu::ComputePass, which: usize, f: u32) {
        pass.set_bind_group(0, &self.fft_groups[which], &[]);
        pass.set_pipeline(&self.fft_rows);
        pass.dispatch_workgroups(f, 1, 1);
        pass.set_pipeline(&self.fft_columns);
        pass.dispatch_workgroups(f, 1, 1);
    }

    /// A readback of the heights that does not block (`request_heights`).
    pub fn heights_readback(&self, device: &wgpu::Device) -> crate::gpu_util::AsyncReadback {
        let n = self.settings.grid.cells as u64;
        crate::gpu_util::AsyncReadback::new(device, "ripples heights readback", n * n * 4)
    }

    /// Start copying the heights now to `readback` (false if its last copy
    /// is still on its way).
    pub fn request_heights(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        readback: &crate::gpu_util::AsyncReadback,
    ) -> bool {
        readback.request(device, queue, &self.heights)
    }

    /// Heights over the domain (m), row = z, col = x (`cells` × `cells`).
    pub fn read_heights(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<f32> {
        let n = self.settings.grid.cells as u64;
        let bytes = read_buffer(device, queue, &self.heights, n * n * 4);
        bytemuck::cast_slice(&bytes).to_vec()
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "ripples",
    dumps: readback::DUMPS,
    shaders: || {
        let mut v = vec![("ripples/ripples".to_string(), source())];
        v.push(("ripples/fft N=32".to_string(), crate::simulation::ocean::fft_source(32, 256)));
        v
    },
    uniforms: || vec![crate::uniforms::Layout::of::<RippleUniforms>(source())],
};
