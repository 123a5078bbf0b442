//! The interactive water's readbacks, declared here by their owner.

use crate::renderer::Renderer;

impl Renderer {
    /// The interactive water after the last frame or simulation step:
    /// heights (m) over its domain, row = z, col = x, and where the domain
    /// lies; `None` without `water.dynamic`.
    pub fn read_ripples(&self) -> Option<RippleField> {
        let r = self.simulations.ripples.as_ref()?.ripples.as_ref()?;
        let g = r.settings.grid;
        Some(RippleField {
            cells: g.cells as u32,
            cell_size: g.cell_size as f32,
            origin: [0, 1].map(|a| r.window.low_edge(&g, a) as f32),
            heights: r.read_heights(self.device(), self.queue()),
            time: self.simulation_time(),
        })
    }
}

/// The interactive water's heights over its square domain.
#[derive(Clone, Debug, PartialEq)]
pub struct RippleField {
    /// Cells per side.
    pub cells: u32,
    /// Side of a cell (m).
    pub cell_size: f32,
    /// World [x, z] (m) of the domain's corner: cell (i, j) is centred at
    /// origin + (i + ½, j + ½)·cell_size.
    pub origin: [f32; 2],
    /// Height above the mean level (m), row = z, col = x.
    pub heights: Vec<f32>,
    /// Simulated time (s) of the state.
    pub time: f64,
}

impl RippleField {
    /// Volume above the mean level (m³).
    pub fn volume(&self) -> f64 {
        self.heights.iter().map(|&h| h as f64).sum::<f64>() * (self.cell_size as f64).powi(2)
    }
}
