//! The liquid's surface as a screen-space mesh (`fluid.surface =
//! "screen_mesh"`; seed 003 §3.2, after Müller, Schirm & Duthaler 2007):
//! the front the camera sees, meshed on a grid of the screen every
//! `fluid.screen_spacing` pixels and carried back to world space, made on
//! the GPU each frame for the frame's camera (`screen_mesh.wgsl`) and drawn
//! with an indexed indirect draw, so nothing is read back. The CPU twin is
//! `hydrolux_core::fluid::screen_mesh`; the mesh is published with the
//! liquid and drawn as clear water by the `water_objects` technique, like
//! marching cubes' mesh. Its buffers follow the frame's size.

use crate::gpu_util::*;
use crate::shaders;
use crate::simulation::published::LiquidMesh;
use crate::technique::Shared;
use crate::uniforms::uniform;
use hydrolux_core::fluid::screen_mesh::{self as sm, ScreenGrid, ScreenMeshParams, ScreenView};
use hydrolux_core::scene::Scene;

uniform! { ScreenMeshParams;
    /// WGSL `ScreenMeshParams` (simulation/liquid/screen_mesh.wgsl).
    pub(crate) struct ScreenMeshUniforms {
        pub view_proj: [[f32; 4]; 4],
        pub inv_view_proj: [[f32; 4]; 4],
        pub screen: [f32; 2],
        pub h: f32,
        pub radius: f32,
        pub nodes: [u32; 2],
        pub node_count: u32,
        pub edge_count: u32,
        pub depth_threshold: f32,
        pub filter_half_length: u32,
        pub particle_count: u32,
        pub vertex_capacity: u32,
        pub index_capacity: u32,
        pub row: u32,
        pub max_reach: f32,
        pub min_depth: f32,
        pub smoothed_half: u32,
        pub _pad0: u32,
        pub _pad1: u32,
        pub _pad2: u32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("screen_mesh.wgsl"))
}

/// Threads per workgroup (`@workgroup_size` in screen_mesh.wgsl).
const WG: u32 = 64;
use super::ROW;
use super::surface::{COUNTERS_BYTES, VERTEX_BYTES};

fn groups(n: u32) -> (u32, u32) {
    super::groups_of(n, WG)
}

/// The buffers for one screen size.
struct Sized {
    size: (u32, u32),
    grid: ScreenGrid,
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    counters: wgpu::Buffer,
    group: wgpu::BindGroup,
}

pub(crate) struct ScreenMeshSurface {
    pub params: ScreenMeshParams,
    pub uniforms: ScreenMeshUniforms,
    uniform_buffer: wgpu::Buffer,
    particles: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    sized: Option<Sized>,
    /// The view the last frame was meshed for.
    pub view: Option<ScreenView>,
    clear: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    splat_back: wgpu::ComputePipeline,
    classify: wgpu::ComputePipeline,
    cut: wgpu::ComputePipeline,
    smooth: [wgpu::ComputePipeline; 2],
    emit_vertices: wgpu::ComputePipeline,
    emit_triangles: wgpu::ComputePipeline,
    silhouette: [wgpu::ComputePipeline; 2],
    to_world: wgpu::ComputePipeline,
    accumulate_normals: wgpu::ComputePipeline,
    finish: wgpu::ComputePipeline,
    /// The mesh as an object (identity, the water's index) for the draws.
    object_group: wgpu::BindGroup,
}

impl ScreenMeshSurface {
    pub fn new(
        shared: &Shared,
        scene: &Scene,
        particles: &wgpu::Buffer,
        particle_count: u32,
    ) -> Self {
        let device = &shared.device;
        let params = ScreenMeshParams::of(&scene.fluid);
        let uniforms = ScreenMeshUniforms {
            view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
            inv_view_proj: glam::Mat4::IDENTITY.to_cols_array_2d(),
            screen: [1.0, 1.0],
            h: params.spacing,
            radius: params.radius,
            nodes: [2, 2],
            node_count: 4,
            edge_count: 4,
            depth_threshold: params.depth_threshold,
            filter_half_length: params.filter,
            particle_count,
            vertex_capacity: 0,
            index_capacity: 0,
            row: ROW * WG,
            max_reach: sm::MAX_SPLAT_REACH,
            min_depth: sm::MIN_DEPTH,
            smoothed_half: 0,
            _pad0: 0,
            _pad1: 0,
            _pad2: 0,
        };
        let uniform_buffer = uniform_buffer(device, "liquid screen mesh", &uniforms);
        // Particles are read; the rest written.
        let mut read_only = [false; 8];
        read_only[0] = true;
        let layout = compute_buffers_layout(device, "liquid screen mesh", &read_only);
        let module = shader(device, "liquid screen mesh", &source());
        let p = |entry| compute_pipeline(device, entry, &module, entry, &[&layout]);
        ScreenMeshSurface {
            params,
            uniforms,
            uniform_buffer,
            particles: particles.clone(),
            sized: None,
            view: None,
            clear: p("clear"),
            splat: p("splat"),
            splat_back: p("splat_back"),
            classify: p("classify"),
            cut: p("cut"),
            smooth: [p("smooth_x"), p("smooth_y")],
            emit_vertices: p("emit_vertices"),
            emit_triangles: p("emit_triangles"),
            silhouette: [p("silhouette_forth"), p("silhouette_back")],
            to_world: p("to_world"),
            accumulate_normals: p("accumulate_normals"),
            finish: p("finish"),
            layout,
            object_group: shared.meshes.plain_object_group(
                device,
                "liquid screen mesh",
                scene.water.ior,
            ),
        }
    }

    /// Make the buffers for frames of `size`; true if they are new (the
    /// published mesh must be too).
    pub fn resize(&mut self, device: &wgpu::Device, size: (u32, u32)) -> bool {
        if self.sized.as_ref().is_some_and(|s| s.size == size) {
            return false;
        }
        let view = ScreenView { view_proj: glam::Mat4::IDENTITY, width: size.0, height: size.1 };
        let (nx, ny) = view.nodes(self.params.spacing);
        let grid = ScreenGrid { nx: nx.max(2), ny: ny.max(2) };
        let (n, e) = (grid.node_count() as u32, grid.edge_count() as u32);
        // Every node filled (two vertices each, front and back sheet) and a
        // silhouette vertex on one edge in four is far more than a liquid
        // covers; a square makes two triangles a sheet but for its
        // silhouettes. Within the 128 MiB a binding may be.
        let vertex_capacity = (3 * n).min(3 << 20);
        let index_capacity = (n * 18).min(24 << 20);
        let u = &mut self.uniforms;
        u.screen = [size.0 as f32, size.1 as f32];
        u.nodes = [grid.nx as u32, grid.ny as u32];
        u.node_count = n;
        u.edge_count = e;
        u.vertex_capacity = vertex_capacity;
        u.index_capacity = index_capacity;
        // An odd number of smoothing rounds ends in the second half.
        u.smoothed_half = vertex_capacity * (self.params.silhouette_iterations % 2);
        let none = wgpu::BufferUsages::empty();
        let words = |count: u32| count as u64 * 4;
        let marks = storage_buffer(
            device,
            "liquid screen marks",
            words(2 * n + e + 3 * vertex_capacity),
            none,
        );
        let depths = storage_buffer(device, "liquid screen depths", words(4 * n), none);
        let maps = storage_buffer(
            device,
            "liquid screen maps",
            words(n + 2 * e + 2 * vertex_capacity),
            none,
        );
        let screen =
            storage_buffer(device, "liquid screen vertices", vertex_capacity as u64 * 32, none);
        let vertices = storage_buffer(
            device,
            "liquid screen mesh vertices",
            vertex_capacity as u64 * VERTEX_BYTES,
            wgpu::BufferUsages::VERTEX,
        );
        let indices = storage_buffer(
            device,
            "liquid screen mesh indices",
            words(index_capacity),
            wgpu::BufferUsages::INDEX,
        );
        let counters = storage_buffer(
            device,
            "liquid screen mesh counters",
            COUNTERS_BYTES,
            wgpu::BufferUsages::INDIRECT,
        );
        let group = bind_buffers(
            device,
            "liquid screen mesh",
            &self.layout,
            &[
                &self.uniform_buffer,
                &self.particles,
                &marks,
                &depths,
                &maps,
                &screen,
                &vertices,
                &indices,
                &counters,
            ],
        );
        self.sized = Some(Sized { size, grid, vertices, indices, counters, group });
        true
    }

    /// Mesh the particles as they are when `encoder` runs, for the camera
    /// `view_proj` on a screen of the size last given to [`Self::resize`].
    pub fn record(
        &mut self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        view_proj: glam::Mat4,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        let Some(s) = &self.sized else { return };
        self.uniforms.view_proj = view_proj.to_cols_array_2d();
        self.uniforms.inv_view_proj = view_proj.inverse().to_cols_array_2d();
        queue.write_buffer(&self.uniform_buffer, 0, bytemuck::bytes_of(&self.uniforms));
        self.view = Some(ScreenView { view_proj, width: s.size.0, height: s.size.1 });
        let u = &self.uniforms;
        let nodes = groups(u.node_count);
        let clear = groups(u.node_count + 2 * u.edge_count);
        let edges = groups(u.edge_count);
        let particles = groups(u.particle_count);
        let vertices = groups(u.vertex_capacity);
        let triangles = groups(u.index_capacity / 3);
        let both = groups(u.node_count + u.edge_count);
        let mut timer = timer;
        let mut run = |encoder: &mut wgpu::CommandEncoder,
                       label: &'static str,
                       work: &[(&wgpu::ComputePipeline, (u32, u32))]| {
            let writes = timer.as_deref_mut().and_then(|t| t.compute_writes(label));
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(label),
                timestamp_writes: writes,
            });
            pass.set_bind_group(0, &s.group, &[]);
            for &(pipeline, (x, y)) in work {
                pass.set_pipeline(pipeline);
                pass.dispatch_workgroups(x, y, 1);
            }
        };
        run(
            encoder,
            "liquid screen depth",
            &[
                (&self.clear, clear),
                (&self.splat, particles),
                (&self.splat_back, particles),
                (&self.classify, edges),
                (&self.cut, particles),
                (&self.smooth[0], nodes),
                (&self.smooth[1], nodes),
            ],
        );
        run(
            encoder,
            "liquid screen mesh",
            &[(&self.emit_vertices, both), (&self.emit_triangles, nodes)],
        );
        let rounds = self.params.silhouette_iterations;
        let mut work = Vec::new();
        for r in 0..rounds {
            work.push((&self.silhouette[(r % 2) as usize], vertices));
        }
        if !work.is_empty() {
            run(encoder, "liquid screen silhouettes", &work);
        }
        run(
            encoder,
            "liquid screen to world",
            &[
                (&self.to_world, vertices),
                (&self.accumulate_normals, triangles),
                (&self.finish, vertices),
            ],
        );
    }

    /// What the draws need (`None` before the first size).
    pub fn mesh(&self) -> Option<LiquidMesh> {
        self.sized.as_ref().map(|s| LiquidMesh {
            vertices: s.vertices.clone(),
            indices: s.indices.clone(),
            args: s.counters.clone(),
            group: self.object_group.clone(),
        })
    }

    /// The buffers a readback needs: vertices, indices, counters, and the
    /// grid they were made on.
    pub fn buffers(&self) -> Option<(&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer, ScreenGrid)> {
        self.sized.as_ref().map(|s| (&s.vertices, &s.indices, &s.counters, s.grid))
    }
}
