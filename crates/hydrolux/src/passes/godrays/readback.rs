//! The god rays' readbacks and dumps, declared here by their owner.

use super::GodRays;
use crate::gpu_util::read_rgba16f;
use crate::info::{DumpData, DumpKind, DumpShape};
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::{GodRayMethod, Scene};

fn off(scene: &Scene) -> Option<&'static str> {
    (scene.godrays.method == GodRayMethod::Off)
        .then_some("god rays are off in this scene (set godrays.method to \"lines\" or \"march\")")
}

/// `godrays`: the god-ray buffer (linear radiance, pre-exposed, buffer size, rgb).
pub(crate) const DUMPS: &[DumpKind] =
    &[DumpKind { name: "godrays", shape: DumpShape::Grid, missing: off }];

impl GodRays {
    /// The last frame's buffer, if that frame drew one.
    fn read_buffer(
        &self,
        ctx_plan: Option<&crate::plan::FramePlan>,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        ctx_plan?.godrays.as_ref()?;
        let t = self.targets.as_ref()?;
        Some((t.size.0, t.size.1, read_rgba16f(device, queue, &t.buffer)))
    }

    pub(crate) fn dump(&self, name: &str, ctx: &DumpContext) -> Option<Result<DumpData, String>> {
        (name == "godrays").then(|| {
            let Some((w, h, px)) = self.read_buffer(ctx.plan, ctx.device, ctx.queue) else {
                return Err("this frame has no god-ray buffer: the camera is above the water and the air has no fog (from above, the water's shader draws the shafts itself; the buffer holds them for a camera under water or in fog)".into());
            };
            let data = px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
            Ok(DumpData::Floats {
                columns: w as usize,
                rows: h as usize,
                channels: 3,
                data,
                note: None,
            })
        })
    }
}

impl Renderer {
    /// The last frame's god-ray buffer (linear radiance, pre-exposed, before
    /// upsampling), RGBA float, rows top to bottom; `None` before a frame
    /// and when the last frame drew none (camera above water, no fog).
    pub fn read_godrays(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        let plan = self.last_plan.as_ref();
        self.techniques.godrays.read_buffer(plan, self.device(), self.queue())
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
