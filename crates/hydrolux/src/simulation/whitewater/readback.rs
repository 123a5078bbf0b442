//! The white water's readbacks, declared here by their owner.

use super::{COUNT_EMITTED, COUNT_LOST, COUNTERS, Whitewater};
use crate::gpu_util::*;
use crate::renderer::Renderer;
use hydrolux_core::whitewater::{Particle, WHITECAP_FOAM};

impl Renderer {
    /// The foam field after the last frame or simulation step (foam F
    /// per cell, row = z, col = x) and where its window lies; `None` without
    /// `[whitewater]` foam.
    pub fn read_foam(&self) -> Option<FoamDump> {
        let w = self.simulations.whitewater.as_ref()?;
        let area = w.foam_area();
        Some(FoamDump {
            cells: w.grid.cells,
            cell_size: w.grid.cell,
            origin: area.origin,
            amount: w.read_foam(self.device(), self.queue()),
            time: self.simulation_time(),
        })
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
