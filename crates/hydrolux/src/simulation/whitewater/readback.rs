//! The white water's readbacks and dumps, declared here by their owner.

use super::{COUNT_EMITTED, COUNT_LOST, COUNTERS, Whitewater};
use crate::gpu_util::*;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::Scene;
use hydrolux_core::whitewater::{BUBBLE, Particle, WHITECAP_FOAM};

fn no_foam(scene: &Scene) -> Option<&'static str> {
    (!(scene.has_whitewater() && scene.whitewater.foam)).then_some(
        "the scene has no foam (it needs whitewater.foam = true and water that moves: water.model \"fft\" or \"sines\", water.dynamic = true or a moving object)",
    )
}

fn no_particles(scene: &Scene) -> Option<&'static str> {
    (!(scene.has_whitewater() && scene.whitewater.particles)).then_some(
        "the scene has no bubbles or spray (it needs whitewater.particles = true and water that moves: water.model \"fft\" or \"sines\", water.dynamic = true or a moving object)",
    )
}

/// `foam`: the foam field over its window; `particles`: the bubbles and
/// spray alive, one row each (x y z vx vy vz radius kind).
pub(crate) const DUMPS: &[DumpKind] = &[
    DumpKind { name: "foam", shape: DumpShape::Grid, missing: no_foam },
    DumpKind { name: "particles", shape: DumpShape::List, missing: no_particles },
];

impl Whitewater {
    fn foam_dump(&self, device: &wgpu::Device, queue: &wgpu::Queue, time: f64) -> FoamDump {
        FoamDump {
            cells: self.grid.cells,
            cell_size: self.grid.cell,
            origin: self.foam_area().origin,
            amount: self.read_foam(device, queue),
            time,
        }
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        match name {
            "foam" => {
                let f = self.foam_dump(ctx.device, ctx.queue, ctx.time);
                let note = format!(
                    "{n}×{n} cells of {c} m, cell (0, 0) centred at x = {x}, z = {z} m; whitecap cover {w:.2}%",
                    n = f.cells,
                    c = f.cell_size,
                    x = f.origin[0] + 0.5 * f.cell_size,
                    z = f.origin[1] + 0.5 * f.cell_size,
                    w = 100.0 * f.coverage()
                );
                let n = f.cells as usize;
                Some(Ok(DumpData::Floats {
                    columns: n,
                    rows: n,
                    channels: 1,
                    data: f.amount,
                    note: Some(note),
                }))
            }
            "particles" => Some(if !self.has_particles() {
                Err("the scene has no bubbles or spray".into())
            } else {
                let ps = self.read_particles(ctx.device, ctx.queue);
                let bubbles = ps.iter().filter(|p| p.kind == BUBBLE).count();
                let note = format!(
                    "{} alive ({bubbles} bubbles, {} spray); columns x y z vx vy vz radius kind (1 bubble, 2 spray)",
                    ps.len(),
                    ps.len() - bubbles
                );
                let data = ps
                    .iter()
                    .flat_map(|p| {
                        let [x, y, z] = p.position;
                        let [vx, vy, vz] = p.velocity;
                        [x, y, z, vx, vy, vz, p.radius, p.kind as f32]
                    })
                    .collect();
                Ok(DumpData::Floats {
                    columns: 8,
                    rows: ps.len(),
                    channels: 1,
                    data,
                    note: Some(note),
                })
            }),
            _ => None,
        }
    }
}

impl Renderer {
    /// The foam field after the last frame or simulation step (foam F
    /// per cell, row = z, col = x) and where its window lies; `None` without
    /// `[whitewater]` foam.
    pub fn read_foam(&self) -> Option<FoamDump> {
        let w = self.simulations.whitewater.as_ref()?;
        Some(w.foam_dump(self.device(), self.queue(), self.simulation_time()))
    }

    /// The bubbles and spray alive after the last frame or simulation step
    /// (in no particular order); `None` when the scene runs no particles.
    pub fn read_particles(&self) -> Option<Vec<Particle>> {
        let w = self.simulations.whitewater.as_ref().filter(|w| w.has_particles())?;
        Some(w.read_particles(self.device(), self.queue()))
    }

    /// The particle pool's counts now; `None` when the scene runs no
    /// particles.
    pub fn particle_counts(&self) -> Option<ParticleCounts> {
        let w = self.simulations.whitewater.as_ref().filter(|w| w.has_particles())?;
        Some(w.counts(self.device(), self.queue()))
    }
}

/// The foam field over its square window.
#[derive(Clone, Debug, PartialEq)]
pub struct FoamDump {
    /// Cells per side.
    pub cells: u32,
    /// Side of a cell (m).
    pub cell_size: f32,
    /// World [x, z] (m) of the window's corner: cell (i, j) is centred at
    /// origin + (i + ½, j + ½)·cell_size.
    pub origin: [f32; 2],
    /// Foam F per cell (1 = a freshly broken crest; white above ln 2).
    pub amount: Vec<f32>,
    /// Simulated time (s) of the state.
    pub time: f64,
}

impl FoamDump {
    /// The fraction of the window covered by whitecaps (F above ln 2), as
    /// hydrolux-core's `FoamField::coverage` counts it.
    pub fn coverage(&self) -> f64 {
        let white = self.amount.iter().filter(|&&f| f > WHITECAP_FOAM).count();
        white as f64 / self.amount.len().max(1) as f64
    }
}

/// A snapshot of the particle pool (for `bench` and the viewer).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ParticleCounts {
    pub alive: u32,
    pub capacity: u32,
    /// Born since the start (or the last reset).
    pub emitted: u32,
    /// Not born because the pool was full.
    pub lost: u32,
}

impl Whitewater {
    /// The foam now (F per cell), row = z from the window's low corner.
    pub fn read_foam(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<f32> {
        let raw: Vec<f32> = bytemuck::cast_slice(&read_buffer(
            device,
            queue,
            &self.foam.current().buffer,
            self.foam.current().buffer.size(),
        ))
        .to_vec();
        let n = self.grid.cells as usize;
        (0..n * n)
            .map(|k| {
                let (i, j) = (k % n, k / n);
                raw[self.grid.index(self.grid.low[0] + i as i32, self.grid.low[1] + j as i32)]
            })
            .collect()
    }

    /// The particles alive now (in no particular order).
    pub fn read_particles(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<Particle> {
        let counts = self.counters(device, queue);
        let list = self.list() as usize;
        let slots: Vec<u32> =
            bytemuck::cast_slice(&read_buffer(device, queue, &self.slots, self.slots.size()))
                .to_vec();
        let pool: Vec<Particle> = bytemuck::cast_slice(&read_buffer(
            device,
            queue,
            &self.particles,
            self.particles.size(),
        ))
        .to_vec();
        let c = self.capacity as usize;
        let alive = counts[list] as usize;
        slots[list * c..list * c + alive.min(c)].iter().map(|&s| pool[s as usize]).collect()
    }

    fn counters(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Vec<u32> {
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("counters readback"),
            size: 4 * COUNTERS as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut e = device.create_command_encoder(&Default::default());
        e.copy_buffer_to_buffer(&self.atomics, 0, &staging, 0, 4 * COUNTERS as u64);
        queue.submit([e.finish()]);
        bytemuck::cast_slice(&map_and_read(device, &staging)).to_vec()
    }

    /// The pool's counts now.
    pub fn counts(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> ParticleCounts {
        let c = self.counters(device, queue);
        ParticleCounts {
            alive: c[self.list() as usize],
            capacity: self.capacity,
            emitted: c[COUNT_EMITTED],
            lost: c[COUNT_LOST],
        }
    }
}
