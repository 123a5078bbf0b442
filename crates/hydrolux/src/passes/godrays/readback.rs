//! The god rays' readbacks, declared here by their owner.

use crate::renderer::Renderer;

impl Renderer {
    /// The last frame's god-ray buffer (linear radiance, pre-exposed, before
    /// upsampling), RGBA float, rows top to bottom; `None` before a frame
    /// and when the last frame drew none (camera above water, no fog).
    pub fn read_godrays(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        self.last_plan.as_ref()?.godrays.as_ref()?;
        let t = self.techniques.godrays.targets.as_ref()?;
        Some((t.size.0, t.size.1, self.read_rgba16f(&t.buffer)))
    }

    /// The beam tubes of the last frame (lines method): per photon, where it
    /// enters the water (xyz), its length, its direction (xyz) and its flux
    /// relative to the sun's irradiance (m²; 0 = not drawn).
    pub fn read_godray_tubes(&self) -> Vec<[f32; 12]> {
        self.techniques.godrays.pass.read_tubes(
            self.device(),
            self.queue(),
            &self.techniques.godrays.tubes,
        )
    }

    /// The paths of light out of refractive objects in the last frame, one
    /// per light-view texel: exit point p1 (xyz), length to p2, exit
    /// direction (xyz), flux (m², relative to the sun; 0 = no path), rgb
    /// tint (absorption inside), unused.
    pub fn read_object_paths(&self) -> Vec<[f32; 12]> {
        let godrays = &self.techniques.godrays;
        godrays.object_tubes.as_ref().map_or_else(Vec::new, |tubes| {
            godrays.pass.read_tubes(self.device(), self.queue(), tubes)
        })
    }
}
