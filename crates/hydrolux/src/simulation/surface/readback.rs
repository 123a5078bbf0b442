//! The surface's readbacks, declared here by their owner.

use crate::renderer::Renderer;
use hydrolux_core::scene::WaterModel;

impl Renderer {
    /// The FFT fields of every cascade after the last simulation step (see
    /// [`OceanPass::read_fields`]); `None` unless `water.model = "fft"`.
    pub fn read_ocean_fields(&self) -> Option<Vec<[f32; 8]>> {
        (self.scene.water.model == WaterModel::Fft).then(|| {
            self.simulations
                .surface
                .as_ref()
                .expect("always built")
                .ocean
                .read_fields(self.device(), self.queue())
        })
    }

    pub fn ocean_resolution(&self) -> u32 {
        self.simulations.published.surface().ocean_resolution
    }
}
