//! The liquid's surface as a mesh (`fluid.surface = "marching_cubes"`;
//! seed 003 §3.1): marching cubes over the particles' density on a grid of
//! its own resolution (`fluid.surface_resolution`), made on the GPU each
//! frame at the frame's time (`surface.wgsl`) and drawn with an indexed
//! indirect draw, so nothing is read back. The CPU twin is
//! `hydrolux_core::fluid::surface`; the mesh is published with the liquid
//! and drawn as clear water by the `water_objects` technique.

use crate::gpu_util::*;
use crate::shaders;
use crate::simulation::published::LiquidMesh;
use crate::technique::Shared;
use crate::uniforms::uniform;
use hydrolux_core::fluid::surface::{self as mc, SurfaceGrid};
use hydrolux_core::scene::{Scene, SurfaceField};

uniform! { SurfaceParams;
    /// WGSL `SurfaceParams` (simulation/liquid/surface.wgsl).
    pub(crate) struct SurfaceUniforms {
        pub origin: [f32; 3],
        pub h: f32,
        pub nodes: [u32; 3],
        pub node_count: u32,
        pub reach: f32,
        pub scale: f32,
        pub iso: f32,
        pub fixed_point: f32,
        pub particle_count: u32,
        pub vertex_capacity: u32,
        pub index_capacity: u32,
        pub row: u32,
        pub radius: f32,
        pub mean_position: u32,
        /// The closed walls (`hydrolux_core::fluid::surface::Walls`).
        pub closed: u32,
        pub _pad0: u32,
        pub inner_lo: [u32; 3],
        pub _pad1: u32,
        pub inner_hi: [u32; 3],
        pub _pad2: u32,
        pub beyond_hi: [u32; 3],
        pub _pad3: u32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("surface.wgsl"))
}

/// Threads per workgroup (`WG` in surface.wgsl); a two-dimensional
/// dispatch has rows of the liquid's `ROW` workgroups.
const WG: u32 = 64;
use super::ROW;
/// Bytes of the counters: the indexed indirect draw's five u32, then the
/// vertices taken.
pub const COUNTERS_BYTES: u64 = 24;
/// Bytes of a vertex (the meshes' layout: position, normal, uv).
pub const VERTEX_BYTES: u64 = 32;

fn groups(n: u32) -> (u32, u32) {
    super::groups_of(n, WG)
}

pub(crate) struct LiquidSurface {
    pub grid: SurfaceGrid,
    pub uniforms: SurfaceUniforms,
    pub vertices: wgpu::Buffer,
    pub indices: wgpu::Buffer,
    pub counters: wgpu::Buffer,
    group: wgpu::BindGroup,
    clear: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    smooth: [wgpu::ComputePipeline; 3],
    /// Rounds of smoothing (`fluid.surface_smoothing`).
    smoothing: u32,
    field: wgpu::Buffer,
    level_values: wgpu::Buffer,
    levels: wgpu::ComputePipeline,
    emit_vertices: wgpu::ComputePipeline,
    emit_triangles: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
    /// The mesh as an object (identity, the water's index) for the draws.
    object_group: wgpu::BindGroup,
}

impl LiquidSurface {
    /// The surface of `scene`'s liquid, whose `particle_count` particles
    /// `spacing` (m) apart at rest are in `particles`.
    pub fn new(
        shared: &Shared,
        scene: &Scene,
        particles: &wgpu::Buffer,
        particle_count: u32,
        spacing: f32,
    ) -> Self {
        let device = &shared.device;
        let desc = &scene.fluid;
        let grid = SurfaceGrid::over(desc.min, desc.max, desc.surface_resolution);
        let node_count = grid.node_count() as u32;
        let walls = mc::Walls::of(&grid, [desc.min, desc.max], desc.open_sides(), spacing);
        // About one vertex per two nodes is far more than a liquid's
        // surface takes (its area over the cell's); triangles are about
        // twice the vertices.
        let vertex_capacity = (node_count / 2).clamp(1 << 16, 1 << 20);
        let index_capacity = vertex_capacity * 6;
        let uniforms = SurfaceUniforms {
            origin: grid.origin,
            h: grid.h,
            nodes: grid.nodes,
            node_count,
            reach: mc::KERNEL_SUPPORT_SPACINGS * spacing,
            scale: mc::kernel_scale(),
            iso: mc::ISO_LEVEL,
            fixed_point: mc::DENSITY_FIXED_POINT,
            particle_count,
            vertex_capacity,
            index_capacity,
            row: ROW * WG,
            radius: mc::PARTICLE_RADIUS_SPACINGS * spacing,
            mean_position: u32::from(desc.surface_field == SurfaceField::MeanPosition),
            closed: walls.closed,
            _pad0: 0,
            inner_lo: walls.inner_lo,
            _pad1: 0,
            inner_hi: walls.inner_hi,
            _pad2: 0,
            beyond_hi: walls.beyond_hi,
            _pad3: 0,
        };
        let params = uniform_buffer(device, "liquid surface", &uniforms);
        let none = wgpu::BufferUsages::empty();
        let channels = mc::CHANNELS as u64 * node_count as u64 * 4;
        let field = storage_buffer(device, "liquid density", channels, none);
        let level_values = storage_buffer(device, "liquid levels", node_count as u64 * 4, none);
        let edge_vertex =
            storage_buffer(device, "liquid edge vertices", node_count as u64 * 12, none);
        let vertices = storage_buffer(
            device,
            "liquid surface vertices",
            vertex_capacity as u64 * VERTEX_BYTES,
            wgpu::BufferUsages::VERTEX,
        );
        let indices = storage_buffer(
            device,
            "liquid surface indices",
            index_capacity as u64 * 4,
            wgpu::BufferUsages::INDEX,
        );
        let counters = storage_buffer(
            device,
            "liquid surface counters",
            COUNTERS_BYTES,
            wgpu::BufferUsages::INDIRECT,
        );
        let table = {
            use wgpu::util::DeviceExt;
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("marching cubes cases"),
                contents: bytemuck::cast_slice(&mc::case_table().packed()),
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        // Particles and the case table are read; the rest written.
        let read_only = [true, false, false, false, false, false, true, false];
        let layout = compute_buffers_layout(device, "liquid surface", &read_only);
        let group = bind_buffers(
            device,
            "liquid surface",
            &layout,
            &[
                &params,
                particles,
                &field,
                &edge_vertex,
                &vertices,
                &indices,
                &counters,
                &table,
                &level_values,
            ],
        );
        let module = shader(device, "liquid surface", &source());
        let p = |entry| compute_pipeline(device, entry, &module, entry, &[&layout]);
        let ior = scene.water.ior;
        LiquidSurface {
            grid,
            uniforms,
            clear: p("clear"),
            splat: p("splat"),
            smooth: [p("smooth_x"), p("smooth_y"), p("smooth_z")],
            smoothing: desc.surface_smoothing,
            field,
            level_values,
            levels: p("levels"),
            emit_vertices: p("emit_vertices"),
            emit_triangles: p("emit_triangles"),
            finish: p("finish"),
            vertices,
            indices,
            counters,
            group,
            object_group: shared.meshes.plain_object_group(device, "liquid surface", ior),
        }
    }

    /// Mesh the particles as they are when `encoder` runs.
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        let nodes = groups(self.uniforms.node_count);
        let words = groups(mc::CHANNELS as u32 * self.uniforms.node_count);
        let particles = groups(self.uniforms.particle_count);
        let run = |encoder: &mut wgpu::CommandEncoder,
                   timer: Option<&mut crate::timing::GpuTimer>,
                   label: &'static str,
                   work: &[(&wgpu::ComputePipeline, (u32, u32))]| {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: timer.and_then(|t| t.compute_writes(label)),
            });
            pass.set_bind_group(0, &self.group, &[]);
            for &(pipeline, (x, y)) in work {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups(x, y, 1);
            }
        };
        let mut timer = timer;
        run(
            encoder,
            timer.as_deref_mut(),
            "liquid density",
            &[(&self.clear, words), (&self.splat, particles), (&self.levels, nodes)],
        );
        // Each axis's round reads the levels whole, so it writes into the
        // field's first channel and goes back over the levels between
        // dispatches.
        let bytes = self.uniforms.node_count as u64 * 4;
        for _ in 0..self.smoothing {
            for axis in &self.smooth {
                run(encoder, None, "liquid density smoothing", &[(axis, nodes)]);
                encoder.copy_buffer_to_buffer(&self.field, 0, &self.level_values, 0, bytes);
            }
        }
        run(
            encoder,
            timer,
            "liquid surface",
            &[(&self.emit_vertices, nodes), (&self.emit_triangles, nodes), (&self.finish, (1, 1))],
        );
    }

    /// What the draws need.
    pub fn mesh(&self) -> LiquidMesh {
        LiquidMesh {
            vertices: self.vertices.clone(),
            indices: self.indices.clone(),
            args: self.counters.clone(),
            group: self.object_group.clone(),
        }
    }
}
