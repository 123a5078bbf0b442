//! Interactive water on the GPU (seed 003 §2.4; Tessendorf's eWave): a
//! dynamic heightfield stepped by an exact spectral rotation with the
//! capillary–gravity dispersion, disturbed by drops, rain and the viewer.
//! The surface technique owns it and adds its heights and slopes to every
//! surface model (`shaders/surface.wgsl`, `RIPPLES`). Physics, boundaries
//! and the step are described with the CPU twin,
//! `hydrolux_core::waves::ripples`; `ripples.wgsl` follows it line by line.

use crate::gpu_util::*;
use crate::shaders;
use crate::timing::GpuTimer;
use crate::uniforms::uniform;
use hydrolux_core::scene::{CLOCK_HZ, Scene};
use hydrolux_core::waves::dispersion::GRAVITY;
use hydrolux_core::waves::ripples::{
    Drop, RippleBoundary, RippleSettings, RippleWindow, sponge_rate,
};

uniform! { RippleParams;
    /// WGSL `RippleParams` (passes/ripples/ripples.wgsl).
    pub(crate) struct RippleUniforms {
        pub grid: [u32; 4],
        pub window: [i32; 4],
        pub space: [f32; 4],
        pub physics: [f32; 4],
        pub sponge: [f32; 4],
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("ripples.wgsl"))
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

/// Slots of the per-step uniforms, each at the device's dynamic-offset alignment.
const SLOTS: u64 = 256;

pub struct RipplePass {
    pub settings: RippleSettings,
    /// The scene whose drops and emitters are scripted.
    scene: Scene,
    pub window: RippleWindow,
    /// Clock steps (of 1/120 s) per simulation step.
    stride: u64,
    /// Clock steps followed since the initial state.
    clock_steps: u64,
    /// Drops asked for by the viewer, for the next step.
    pending: Vec<Drop>,
    params: wgpu::Buffer,
    slot_size: u64,
    spatial: wgpu::Buffer,
    spectral: wgpu::Buffer,
    depth: wgpu::Buffer,
    drops: wgpu::Buffer,
    drop_capacity: u64,
    heights: wgpu::Buffer,
    pub texture: wgpu::Texture,
    layout: wgpu::BindGroupLayout,
    group: wgpu::BindGroup,
    fft_groups: [wgpu::BindGroup; 2],
    disturb: wgpu::ComputePipeline,
    spectral_step: wgpu::ComputePipeline,
    publish: wgpu::ComputePipeline,
    fft_rows: wgpu::ComputePipeline,
    fft_columns: wgpu::ComputePipeline,
}

impl RipplePass {
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        caps: &crate::capabilities::Capabilities,
        scene: &Scene,
        settings: RippleSettings,
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
        queue.write_buffer(
            &depth,
            0,
            bytemuck::cast_slice(&vec![settings.depths[0] as f32; (n * n) as usize]),
        );
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
            &crate::passes::ocean::fft_source(f, caps.max_workgroup_threads),
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
        let (disturb, spectral_step, publish) =
            (pipeline("disturb"), pipeline("spectral_step"), pipeline("publish"));
        let (fft_rows, fft_columns) = (fft("fft_rows"), fft("fft_columns"));
        let mut pass = RipplePass {
            settings,
            scene: scene.clone(),
            window: RippleWindow::centred(&settings.grid, scene.ripples.center.map(|c| c as f64)),
            stride: (CLOCK_HZ / scene.ripples.rate.max(1)) as u64,
            clock_steps: 0,
            pending: Vec::new(),
            group: Self::bind(
                device, &layout, &params, &spatial, &spectral, &depth, &drops, &heights, &texture,
            ),
            params,
            slot_size,
            spatial,
            spectral,
            depth,
            drops,
            drop_capacity,
            heights,
            texture,
            layout,
            fft_groups,
            disturb,
            spectral_step,
            publish,
            fft_rows,
            fft_columns,
        };
        pass.reset(queue);
        pass
    }

    fn bind(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        spatial: &wgpu::Buffer,
        spectral: &wgpu::Buffer,
        depth: &wgpu::Buffer,
        drops: &wgpu::Buffer,
        heights: &wgpu::Buffer,
        texture: &wgpu::Texture,
    ) -> wgpu::BindGroup {
        let view = texture.create_view(&Default::default());
        fn whole(b: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding: b, resource: buffer.as_entire_binding() }
        }
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ripples"),
            layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: params,
                        offset: 0,
                        size: wgpu::BufferSize::new(std::mem::size_of::<RippleUniforms>() as u64),
                    }),
                },
                whole(1, spatial),
                whole(2, spectral),
                whole(3, depth),
                whole(4, drops),
                whole(5, heights),
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
            ],
        })
    }

    /// Whether `scene` keeps this simulation (same physics, grid and script).
    pub fn fits(&self, scene: &Scene) -> bool {
        scene.ripple_settings() == Some(self.settings)
            && scene.ripples == self.scene.ripples
            && scene.drops == self.scene.drops
            && scene.emitters == self.scene.emitters
    }

    /// Back to still water (t = 0).
    pub fn reset(&mut self, queue: &wgpu::Queue) {
        let f = self.settings.grid.fft_size();
        let n = self.settings.grid.cells as u32;
        queue.write_buffer(&self.spectral, 0, &vec![0u8; f * f * 16]);
        queue.write_buffer(&self.heights, 0, &vec![0u8; (n * n * 4) as usize]);
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
        self.clock_steps = 0;
        self.pending.clear();
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
            grid: [
                g.cells as u32,
                g.fft_size() as u32,
                edges_index(g.boundary),
                g.sponge_cells() as u32,
            ],
            window: [
                self.window.origin[0] as i32,
                self.window.origin[1] as i32,
                first_drop as i32,
                drops as i32,
            ],
            space: [g.cell_size as f32, s.dt as f32, s.depths[0] as f32, s.depths[1] as f32],
            physics: [GRAVITY as f32, s.tension as f32, s.viscosity as f32, s.damping as f32],
            sponge: [sponge_rate(g) as f32, 0.0, 0.0, 0.0],
        }
    }

    /// Follow `clock_steps` more steps of the simulation clock: the
    /// simulation steps each time a whole step of its own is due, then its
    /// surface texture is written. Steps beyond what the uniform slots hold
    /// go to the queue in submissions of their own.
    pub fn advance(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        clock_steps: u32,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let before = self.clock_steps / self.stride;
        self.clock_steps += clock_steps as u64;
        let mut due = self.clock_steps / self.stride - before;
        let mut next = before;
        while due > SLOTS - 1 {
            let mut early = device.create_command_encoder(&Default::default());
            self.record(device, queue, &mut early, next, SLOTS - 1, None);
            queue.submit([early.finish()]);
            next += SLOTS - 1;
            due -= SLOTS - 1;
        }
        self.record(device, queue, encoder, next, due, timer.take());
    }

    /// Record simulation steps `first..first + count` and the publish.
    fn record(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        first: u64,
        count: u64,
        timer: Option<&mut GpuTimer>,
    ) {
        let dt = self.settings.dt;
        let mut drops: Vec<[f32; 4]> = Vec::new();
        let mut slots = vec![0u8; (self.slot_size * (count + 1)) as usize];
        for i in 0..=count {
            let mut step_drops = Vec::new();
            if i < count {
                step_drops = self.scene.drops_in_step(first + i, dt);
                if i == 0 {
                    step_drops.append(&mut self.pending);
                }
            }
            let u = self.uniforms(drops.len(), step_drops.len());
            drops.extend(
                step_drops
                    .iter()
                    .map(|d| [d.x as f32, d.z as f32, d.radius as f32, d.strength as f32]),
            );
            let at = (i * self.slot_size) as usize;
            slots[at..at + std::mem::size_of::<RippleUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
        }
        queue.write_buffer(&self.params, 0, &slots);
        if drops.len() as u64 > self.drop_capacity {
            self.drop_capacity = (drops.len() as u64).next_power_of_two();
            self.drops = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ripples drops"),
                size: self.drop_capacity * 16,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            self.group = Self::bind(
                device,
                &self.layout,
                &self.params,
                &self.spatial,
                &self.spectral,
                &self.depth,
                &self.drops,
                &self.heights,
                &self.texture,
            );
        }
        if !drops.is_empty() {
            queue.write_buffer(&self.drops, 0, bytemuck::cast_slice(&drops));
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

    /// Heights over the domain (m), row = z, col = x (`cells` × `cells`).
    pub fn read_heights(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<f32> {
        let n = self.settings.grid.cells as u64;
        let bytes = read_buffer(device, queue, &self.heights, n * n * 4);
        bytemuck::cast_slice(&bytes).to_vec()
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "ripples",
    shaders: || {
        let mut v = vec![("ripples/ripples".to_string(), source())];
        v.push(("ripples/fft N=32".to_string(), crate::passes::ocean::fft_source(32, 256)));
        v
    },
    uniforms: || vec![crate::uniforms::Layout::of::<RippleUniforms>(source())],
};
