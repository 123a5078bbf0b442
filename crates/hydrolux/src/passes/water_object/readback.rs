//! The water objects' readbacks and dumps, declared here by their owner.

use super::WaterObjects;
use crate::gpu_util::read_rgba16f;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::Scene;

fn no_refractive_object(scene: &Scene) -> Option<&'static str> {
    (!scene.objects.iter().any(|o| o.material.ior > 0.0))
        .then_some("the scene has no refractive object (an object with material.ior > 0)")
}

/// `object_caustics`: the refractive objects' caustic in their light view (rgb).
pub(crate) const DUMPS: &[DumpKind] =
    &[DumpKind { name: "object_caustics", shape: DumpShape::Grid, missing: no_refractive_object }];

impl WaterObjects {
    fn read_caustic_map(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> (u32, Vec<[f32; 4]>) {
        (self.light.resolution, read_rgba16f(device, queue, &self.light.map))
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        (name == "object_caustics").then(|| {
            let (k, map) = self.read_caustic_map(ctx.device, ctx.queue);
            let data = map.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
            let k = k as usize;
            Ok(DumpData::Floats { columns: k, rows: k, channels: 3, data, note: None })
        })
    }
}

impl Renderer {
    /// The caustic of refractive objects after the last frame, in their
    /// light view (K × K texels, rows top to bottom): rgb irradiance landing
    /// there relative to the sun's on a plane facing it, and the depth of
    /// the surface it landed on.
    pub fn read_object_caustics(&self) -> (u32, Vec<[f32; 4]>) {
        self.techniques.water_objects.read_caustic_map(self.device(), self.queue())
    }

    /// The image the clear objects and the liquid's mesh were drawn over in
    /// the last frame (linear HDR, rows top to bottom: the main view before
    /// the `water_objects` technique drew), `None` without them.
    pub fn read_behind_water_objects(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        let behind = &self.techniques.water_objects.targets.as_ref()?.behind;
        let size = behind.size();
        Some((size.width, size.height, read_rgba16f(self.device(), self.queue(), behind)))
    }

    /// The refractive objects' light view (world → clip) and its texels per
    /// side; `None` without refractive objects or with the sun down.
    pub fn object_light_view(&self) -> Option<(glam::Mat4, u32)> {
        let plan = self.last_plan.as_ref()?;
        plan.object_light.map(|o| (o.view_proj, self.techniques.water_objects.light.resolution))
    }
}
