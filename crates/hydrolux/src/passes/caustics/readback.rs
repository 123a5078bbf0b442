//! The floor caustics' readbacks and dumps, declared here by their owner.

use super::Caustics;
use crate::gpu_util::*;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::Scene;

fn no_caustics(scene: &Scene) -> Option<&'static str> {
    (!scene.has_caustics()).then_some(
        "the scene has no caustics (it needs water (water.model other than \"none\"), caustics.method other than \"off\", a floor (floor.depth > 0) and the sun up)",
    )
}

/// `caustics`: the floor caustic map (M × M, one channel).
pub(crate) const DUMPS: &[DumpKind] =
    &[DumpKind { name: "caustics", shape: DumpShape::Grid, missing: no_caustics }];

impl Caustics {
    /// The deepest layer of the map: (M, M² values).
    fn read_map(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> (u32, Vec<f32>) {
        let map = &self.map;
        let bytes = read_texture_layer(device, queue, &map.texture, 8, map.layers - 1);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        (map.resolution, halves.chunks_exact(4).map(|c| f16_to_f32(c[0])).collect())
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        (name == "caustics").then(|| {
            if let Some(why) = no_caustics(ctx.scene) {
                return Err(why.into());
            }
            let (m, data) = self.read_map(ctx.device, ctx.queue);
            let m = m as usize;
            Ok(DumpData::Floats { columns: m, rows: m, channels: 1, data, note: None })
        })
    }
}

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
        Some(self.techniques.caustics.read_map(self.device(), self.queue()))
    }
}
