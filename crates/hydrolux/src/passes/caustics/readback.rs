//! The floor caustics' readbacks, declared here by their owner.

use crate::gpu_util::*;
use crate::renderer::Renderer;

impl Renderer {
    /// The floor caustic map after the last frame or simulation step: M×M
    /// cells over the patch around the origin (row = z, col = x), in floor
    /// irradiance relative to the sun's irradiance on a plane facing it,
    /// without absorption (hydrolux_core::caustics); `None` when caustics are
    /// off or there is no floor.
    pub fn read_caustics(&self) -> Option<(u32, Vec<f32>)> {
        if !self.scene.has_caustics() {
            return None;
        }
        let map = &self.techniques.caustics.map;
        let bytes =
            read_texture_layer(self.device(), self.queue(), &map.texture, 8, map.layers - 1);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        Some((map.resolution, halves.chunks_exact(4).map(|c| f16_to_f32(c[0])).collect()))
    }
}
