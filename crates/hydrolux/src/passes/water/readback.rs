//! The traced water's readbacks, declared here by their owner.

use crate::renderer::Renderer;

impl Renderer {
    /// Trace rays (origin, direction, reach in m) against the ground's
    /// heightfield on the GPU, as `water.method = "raytrace"` does: each
    /// ray's distance to its first hit, `None` where it hits nothing. `None`
    /// when the scene does not ray-trace.
    pub fn probe_traced_ground(
        &self,
        rays: &[([f32; 3], [f32; 3], f32)],
    ) -> Option<Vec<Option<f32>>> {
        let t = &self.techniques.water.traced;
        (t.method == hydrolux_core::scene::WaterMethod::Raytrace)
            .then(|| t.probe_ground(self.device(), self.queue(), rays))
    }

    /// The ray-traced water's heightfield after the last frame (row = z,
    /// (water.trace_resolution + 1)² samples over 64 m) and its first
    /// sample's world (x, z);
    /// `None` when the scene does not ray-trace.
    pub fn read_traced_water(&self) -> Option<(Vec<f32>, [f32; 2])> {
        let t = &self.techniques.water.traced;
        (t.method == hydrolux_core::scene::WaterMethod::Raytrace)
            .then(|| t.read_water(self.device(), self.queue()))
    }

    /// The ray-traced ground's caustics after the last frame (the photons
    /// traced through the surface to the ground, filtered): per cell of
    /// their window (row = z), the sunlight per horizontal area relative to
    /// flat water over flat ground (0 in shadow), and the window: world
    /// (x, z) of its corner, its cell (m), cells per side. `None` when the
    /// scene does not ray-trace or has no caustics (hydrolux_core
    /// `raytrace::caustics` is the CPU twin).
    pub fn read_traced_caustics(&self) -> Option<(Vec<f32>, [f32; 4])> {
        self.techniques.water.traced.read_caustics(self.device(), self.queue())
    }
}
