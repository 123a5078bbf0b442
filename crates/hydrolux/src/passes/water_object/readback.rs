//! The water objects' readbacks, declared here by their owner.

use crate::renderer::Renderer;

impl Renderer {
    /// The caustic of refractive objects after the last frame, in their
    /// light view (K × K texels, rows top to bottom): rgb irradiance landing
    /// there relative to the sun's on a plane facing it, and the depth of
    /// the surface it landed on.
    pub fn read_object_caustics(&self) -> (u32, Vec<[f32; 4]>) {
        let light = &self.techniques.water_objects.light;
        (light.resolution, self.read_rgba16f(&light.map))
    }

    /// The refractive objects' light view (world → clip) and its texels per
    /// side; `None` without refractive objects or with the sun down.
    pub fn object_light_view(&self) -> Option<(glam::Mat4, u32)> {
        let plan = self.last_plan.as_ref()?;
        plan.object_light.map(|o| (o.view_proj, self.techniques.water_objects.light.resolution))
    }
}
