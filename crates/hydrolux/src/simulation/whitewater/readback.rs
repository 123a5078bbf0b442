//! The white water's readbacks, declared here by their owner.

use super::ParticleCounts;
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
