//! The liquid's readbacks and dumps (`fluid`: the particles; `fluid_grid`:
//! the cells), declared here by their owner.

use super::{Liquid, LiquidParticle, SolveState};
use crate::gpu_util::read_buffer;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::Scene;

fn no_liquid(scene: &Scene) -> Option<&'static str> {
    (!scene.fluid.enabled())
        .then_some("the scene has no volumetric liquid (it needs [[fluid.sources]])")
}

pub(crate) const DUMPS: &[DumpKind] = &[
    DumpKind { name: "fluid", shape: DumpShape::List, missing: no_liquid },
    DumpKind { name: "fluid_grid", shape: DumpShape::Grid, missing: no_liquid },
    DumpKind { name: "fluid_mesh", shape: DumpShape::List, missing: no_mesh },
    DumpKind { name: "fluid_white_water", shape: DumpShape::List, missing: no_white_water },
];

fn no_white_water(scene: &Scene) -> Option<&'static str> {
    no_liquid(scene).or_else(|| {
        (scene.fluid.white_water <= 0.0)
            .then_some("the liquid sheds no white water (it needs fluid.white_water > 0)")
    })
}

fn no_mesh(scene: &Scene) -> Option<&'static str> {
    no_liquid(scene).or_else(|| {
        scene.liquid_mesh_bounds().is_none().then_some(
            "the liquid's surface is not meshed (it needs fluid.surface = \"marching_cubes\" or \"screen_mesh\")",
        )
    })
}

/// The liquid as the GPU holds it after a step.
#[derive(Clone, Debug, PartialEq)]
pub struct LiquidReadback {
    /// The particles holding liquid (empty slots left out).
    pub particles: Vec<LiquidParticle>,
    /// How the last step's pressure solve went.
    pub solve: SolveState,
    /// Cells per axis, the cell's side (m), the domain's low corner (m).
    pub cells: [u32; 3],
    pub h: f32,
    pub origin: [f32; 3],
    /// Per cell (x fastest, then y, then z): particles in it, pressure (Pa),
    /// and ∇·u (1/s) of the face velocities the particles last moved through.
    pub counts: Vec<u32>,
    pub pressure: Vec<f32>,
    pub divergence: Vec<f32>,
}

impl LiquidReadback {
    /// The largest |∇·u| over cells holding particles (1/s).
    pub fn max_liquid_divergence(&self) -> f32 {
        self.divergence
            .iter()
            .zip(&self.counts)
            .filter(|(_, c)| **c > 0)
            .fold(0.0f32, |m, (d, _)| m.max(d.abs()))
    }
}

impl Liquid {
    pub(crate) fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> LiquidReadback {
        let u = &self.uniforms;
        let particles: Vec<LiquidParticle> = bytemuck::cast_slice(&read_buffer(
            device,
            queue,
            &self.particles,
            u.particle_count as u64 * 32,
        ))
        .iter()
        .filter(|p: &&LiquidParticle| p.alive != 0)
        .copied()
        .collect();
        let solve: SolveState =
            *bytemuck::from_bytes(&read_buffer(device, queue, &self.state, 32)[..32]);
        let accum: Vec<i32> =
            bytemuck::cast_slice(&read_buffer(device, queue, &self.accum, self.accum.size()))
                .to_vec();
        let cells = u.cell_count as usize;
        let counts: Vec<u32> =
            accum[2 * u.face_count as usize..][..cells].iter().map(|&c| c.max(0) as u32).collect();
        let raw: Vec<f32> =
            bytemuck::cast_slice(&read_buffer(device, queue, &self.solve, cells as u64 * 4))
                .to_vec();
        let pressure =
            raw.iter().zip(&counts).map(|(p, &c)| if c > 0 { *p } else { 0.0 }).collect();
        let faces: Vec<f32> =
            bytemuck::cast_slice(&read_buffer(device, queue, &self.faces, u.face_count as u64 * 4))
                .to_vec();
        let n = u.cells.map(|c| c as usize);
        let offsets = [0, u.faces[0] as usize, (u.faces[0] + u.faces[1]) as usize];
        let face = |a: usize, c: [usize; 3]| {
            let mut m = n;
            m[a] += 1;
            offsets[a] + (c[2] * m[1] + c[1]) * m[0] + c[0]
        };
        let mut divergence = vec![0.0f32; cells];
        for k in 0..n[2] {
            for j in 0..n[1] {
                for i in 0..n[0] {
                    let mut d = 0.0;
                    for a in 0..3 {
                        let mut hi = [i, j, k];
                        hi[a] += 1;
                        d += faces[face(a, hi)] - faces[face(a, [i, j, k])];
                    }
                    divergence[(k * n[1] + j) * n[0] + i] = d / u.h;
                }
            }
        }
        LiquidReadback {
            particles,
            solve,
            cells: u.cells,
            h: u.h,
            origin: u.origin,
            counts,
            pressure,
            divergence,
        }
    }

    /// The white water's pool, slot by slot (empty without it).
    pub(crate) fn read_white_water(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Vec<hydrolux_core::fluid::Diffuse> {
        if self.uniforms.white_water == 0 {
            return Vec::new();
        }
        let bytes = read_buffer(device, queue, &self.white_water, self.white_water.size());
        bytemuck::cast_slice(&bytes).to_vec()
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        match name {
            "fluid_white_water" => {
                let pool = self.read_white_water(ctx.device, ctx.queue);
                let live: Vec<_> = pool.iter().filter(|d| d.kind != 0).collect();
                let data = live
                    .iter()
                    .flat_map(|d| {
                        let [x, y, z] = d.position;
                        let [vx, vy, vz] = d.velocity;
                        [x, y, z, d.kind as f32, vx, vy, vz, d.life]
                    })
                    .collect();
                let count = |k: u32| live.iter().filter(|d| d.kind == k).count();
                use hydrolux_core::whitewater::{BUBBLE, FOAM, SPRAY};
                let note = format!(
                    "{} white-water particles at t = {:.4} s ({} spray, {} foam, {} bubbles); columns x y z (m) kind ({SPRAY} spray, {FOAM} foam, {BUBBLE} bubble) vx vy vz (m/s) foam life left (s)",
                    live.len(),
                    ctx.time,
                    count(SPRAY),
                    count(FOAM),
                    count(BUBBLE),
                );
                Some(Ok(DumpData::Floats {
                    columns: 8,
                    rows: live.len(),
                    channels: 1,
                    data,
                    note: Some(note),
                }))
            }
            "fluid_mesh" => Some(self.dump_mesh(ctx)),
            "fluid" => {
                let r = self.read(ctx.device, ctx.queue);
                let data = r
                    .particles
                    .iter()
                    .flat_map(|p| {
                        let [x, y, z] = p.position;
                        let [vx, vy, vz] = p.velocity;
                        [x, y, z, vx, vy, vz]
                    })
                    .collect();
                let note = format!(
                    "{} particles at t = {:.4} s; columns x y z (m) vx vy vz (m/s)",
                    r.particles.len(),
                    ctx.time
                );
                Some(Ok(DumpData::Floats {
                    columns: 6,
                    rows: r.particles.len(),
                    channels: 1,
                    data,
                    note: Some(note),
                }))
            }
            "fluid_grid" => {
                let r = self.read(ctx.device, ctx.queue);
                let per_cell = self.desc.particles_per_cell as f32;
                let data = (0..r.counts.len())
                    .flat_map(|c| {
                        [(r.counts[c] as f32 / per_cell).min(1.0), r.pressure[c], r.divergence[c]]
                    })
                    .collect();
                let [nx, ny, nz] = r.cells;
                let note = format!(
                    "{nx}×{ny}×{nz} cells of {h} m from {o:?} at t = {t:.4} s: row k·{ny} + j, column i; channels: liquid fraction (particles over {per_cell}), pressure (Pa), ∇·u (1/s); the last solve took {it} iterations, max |∇·u| {before:.3e} → {after:.3e} 1/s",
                    h = r.h,
                    o = r.origin,
                    t = ctx.time,
                    it = r.solve.iterations,
                    before = r.solve.residual_before,
                    after = r.solve.residual,
                );
                Some(Ok(DumpData::Floats {
                    columns: nx as usize,
                    rows: (ny * nz) as usize,
                    channels: 3,
                    data,
                    note: Some(note),
                }))
            }
            _ => None,
        }
    }
}

/// What `hydrolux bench` measures of the liquid's step.
#[derive(Clone, Debug, PartialEq)]
pub struct LiquidBench {
    pub particles: u32,
    pub cells: [u32; 3],
    /// Steps measured, and the wall clock per step (ms, submit → done).
    pub steps: u32,
    pub step_ms: f64,
    /// Median GPU time per pass of a step (ms), where the adapter has
    /// timestamp queries.
    pub passes: Vec<(&'static str, f64)>,
    /// The last solve's iterations and residual (1/s).
    pub iterations: u32,
    pub residual: f32,
}

impl Renderer {
    /// The volumetric liquid after the last frame or simulation step;
    /// `None` without `[[fluid.sources]]`.
    pub fn read_liquid(&self) -> Option<LiquidReadback> {
        let l = self.simulations.liquid.as_ref()?;
        Some(l.read(self.device(), self.queue()))
    }

    /// The liquid's white-water pool, slot by slot (`fluid.white_water`;
    /// empty without it); `None` without a liquid.
    pub fn read_liquid_white_water(&self) -> Option<Vec<hydrolux_core::fluid::Diffuse>> {
        let l = self.simulations.liquid.as_ref()?;
        Some(l.read_white_water(self.device(), self.queue()))
    }

    /// Time `steps` liquid steps from the state now (for `hydrolux bench`):
    /// they run outside the clock, so the clock starts over at the next
    /// frame. `None` without a liquid.
    pub fn bench_liquid(&mut self, steps: u32) -> Option<LiquidBench> {
        let liquid = self.simulations.liquid.as_ref()?;
        let device = &self.shared.device;
        let queue = &self.shared.queue;
        // Warm up (first dispatches compile and page in).
        let mut encoder = device.create_command_encoder(&Default::default());
        liquid.record_steps(&mut encoder, 1, None);
        queue.submit([encoder.finish()]);
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        let mut timer = self.timer.as_mut();
        if let Some(t) = timer.as_deref_mut() {
            t.begin_frame();
        }
        let t0 = std::time::Instant::now();
        let mut encoder = device.create_command_encoder(&Default::default());
        liquid.record_steps(&mut encoder, steps as u64, timer.as_deref_mut());
        if let Some(t) = timer.as_deref() {
            t.resolve(&mut encoder);
        }
        queue.submit([encoder.finish()]);
        let _ = device.poll(wgpu::PollType::wait_indefinitely());
        let step_ms = t0.elapsed().as_secs_f64() * 1e3 / steps.max(1) as f64;
        let mut times: Vec<(&'static str, Vec<f64>)> = Vec::new();
        if let Some(t) = timer.as_deref() {
            for (name, ms) in t.read(device) {
                match times.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, v)) => v.push(ms),
                    None => times.push((name, vec![ms])),
                }
            }
        }
        let passes = times
            .into_iter()
            .map(|(name, mut v)| {
                v.sort_by(f64::total_cmp);
                (name, v[v.len() / 2])
            })
            .collect();
        let solve: SolveState =
            *bytemuck::from_bytes(&read_buffer(device, queue, &liquid.state, 32)[..32]);
        let bench = LiquidBench {
            particles: liquid.particle_count(),
            cells: liquid.uniforms.cells,
            steps,
            step_ms,
            passes,
            iterations: solve.iterations,
            residual: solve.residual,
        };
        self.clock.reset();
        Some(bench)
    }
}

/// The liquid's surface mesh as the GPU made it for the last frame.
#[derive(Clone, Debug)]
pub struct LiquidSurfaceReadback {
    /// The grid it was meshed on.
    pub grid: hydrolux_core::fluid::surface::SurfaceGrid,
    /// Its triangles (the vertices in the order the GPU took them).
    pub mesh: hydrolux_core::fluid::surface::SurfaceMesh,
    /// Vertices the level crossed, and the buffer's room for them.
    pub vertices_taken: u32,
    pub vertex_capacity: u32,
}

impl Renderer {
    /// The liquid's surface mesh after the last frame (`None` without a
    /// liquid meshed by `fluid.surface = "marching_cubes"`).
    pub fn read_liquid_surface(&self) -> Option<LiquidSurfaceReadback> {
        let l = self.simulations.liquid.as_ref()?;
        l.read_surface(self.device(), self.queue())
    }
}

/// The liquid's screen-space mesh as the GPU made it for the last frame.
#[derive(Clone, Debug)]
pub struct ScreenMeshReadback {
    /// The depth map's grid and the view it was made for.
    pub grid: hydrolux_core::fluid::screen_mesh::ScreenGrid,
    pub view: hydrolux_core::fluid::screen_mesh::ScreenView,
    /// Its triangles (the vertices in the order the GPU took them).
    pub mesh: hydrolux_core::fluid::surface::SurfaceMesh,
    /// Vertices made, and the buffer's room for them.
    pub vertices_taken: u32,
    pub vertex_capacity: u32,
}

impl Renderer {
    /// The liquid's screen-space mesh after the last frame (`None` without
    /// a liquid drawn by `fluid.surface = "screen_mesh"`, or before a frame).
    pub fn read_liquid_screen_mesh(&self) -> Option<ScreenMeshReadback> {
        let l = self.simulations.liquid.as_ref()?;
        l.read_screen_mesh(self.device(), self.queue())
    }
}

/// A mesh the GPU made in `vertices`, `indices` and `counters` (the
/// indexed draw's arguments, then the vertices taken): the mesh and the
/// vertices taken.
fn read_mesh(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffers: (&wgpu::Buffer, &wgpu::Buffer, &wgpu::Buffer),
    vertex_capacity: u32,
) -> (hydrolux_core::fluid::surface::SurfaceMesh, u32) {
    let (vertices, indices, counters) = buffers;
    let counters: Vec<u32> =
        bytemuck::cast_slice(&read_buffer(device, queue, counters, super::surface::COUNTERS_BYTES))
            .to_vec();
    let (index_count, taken) = (counters[0], counters[5]);
    let kept = taken.min(vertex_capacity);
    let floats: Vec<f32> = bytemuck::cast_slice(&read_buffer(
        device,
        queue,
        vertices,
        (kept as u64 * super::surface::VERTEX_BYTES).max(4),
    ))
    .to_vec();
    let indices: Vec<u32> =
        bytemuck::cast_slice(&read_buffer(device, queue, indices, (index_count as u64 * 4).max(4)))
            [..index_count as usize]
            .to_vec();
    let vertices = floats.chunks_exact(8);
    let mesh = hydrolux_core::fluid::surface::SurfaceMesh {
        positions: vertices.clone().map(|v| [v[0], v[1], v[2]]).collect(),
        normals: vertices.map(|v| [v[3], v[4], v[5]]).collect(),
        indices,
    };
    (mesh, taken)
}

impl Liquid {
    fn read_surface(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<LiquidSurfaceReadback> {
        let s = self.surface.as_ref()?;
        let capacity = s.uniforms.vertex_capacity;
        let (mesh, taken) =
            read_mesh(device, queue, (&s.vertices, &s.indices, &s.counters), capacity);
        Some(LiquidSurfaceReadback {
            grid: s.grid,
            mesh,
            vertices_taken: taken,
            vertex_capacity: capacity,
        })
    }

    fn read_screen_mesh(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<ScreenMeshReadback> {
        let s = self.screen_mesh.as_ref()?;
        let (vertices, indices, counters, grid) = s.buffers()?;
        let view = s.view?;
        let capacity = s.uniforms.vertex_capacity;
        let (mesh, taken) = read_mesh(device, queue, (vertices, indices, counters), capacity);
        Some(ScreenMeshReadback {
            grid,
            view,
            mesh,
            vertices_taken: taken,
            vertex_capacity: capacity,
        })
    }

    /// The `fluid_mesh` dump: a row per triangle, its corners' positions.
    fn dump_mesh(&self, ctx: &DumpContext) -> Result<DumpData, String> {
        let unmeshed = || {
            "the liquid's surface is not meshed (set fluid.surface = \"marching_cubes\" or \"screen_mesh\")"
                .to_string()
        };
        let (mesh, taken, capacity, how) = if self.surface.is_some() {
            let r = self.read_surface(ctx.device, ctx.queue).ok_or_else(unmeshed)?;
            let g = &r.grid;
            let how = format!(
                "meshed on {}×{}×{} nodes {} m apart; columns: three corners' x y z (m), counter-clockwise seen from outside; area {:.5} m², volume {:.6} m³",
                g.nodes[0],
                g.nodes[1],
                g.nodes[2],
                g.h,
                r.mesh.area(),
                r.mesh.volume()
            );
            (r.mesh, r.vertices_taken, r.vertex_capacity, how)
        } else {
            let r = self.read_screen_mesh(ctx.device, ctx.queue).ok_or_else(unmeshed)?;
            let how = format!(
                "the layer of liquid the camera sees (its front and the back sheet behind it), meshed on a {}×{} depth map of the {}×{} screen; columns: three corners' x y z (m), counter-clockwise seen from outside; area {:.5} m²",
                r.grid.nx,
                r.grid.ny,
                r.view.width,
                r.view.height,
                r.mesh.area()
            );
            (r.mesh, r.vertices_taken, r.vertex_capacity, how)
        };
        let rows = mesh.indices.len() / 3;
        let data = mesh.triangles().flat_map(|t| t.into_iter().flatten()).collect();
        let note = format!(
            "{rows} triangles at t = {t:.4} s, {how}{full}",
            t = ctx.time,
            full = if taken > capacity {
                format!("; the vertex buffer was full ({capacity} of {taken})")
            } else {
                String::new()
            },
        );
        Ok(DumpData::Floats { columns: 9, rows, channels: 1, data, note: Some(note) })
    }
}
