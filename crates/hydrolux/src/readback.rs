//! Reading back what a frame made and asking the surface and sky questions
//! outside the frame: for tests, dumps and callers (buoyancy, tools).

use crate::gpu_util::*;
use crate::renderer::{Renderer, f16_to_f32};
pub use crate::simulation::ripples::readback::RippleField;
pub use crate::simulation::whitewater::ParticleCounts;
pub use crate::simulation::whitewater::readback::FoamDump;
use hydrolux_core::waves::SurfaceSample;

impl Renderer {
    /// An RGBA half-float texture's texels as f32, rows top to bottom.
    fn read_rgba16f(&self, texture: &wgpu::Texture) -> Vec<[f32; 4]> {
        let bytes = read_texture(self.device(), self.queue(), texture, 8);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        let texel =
            |c: &[u16]| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])];
        halves.chunks_exact(4).map(texel).collect()
    }

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

    /// Each pixel's medium in the last frame (0 air, 1 water: where its
    /// near-plane point lies), rows top to bottom.
    pub fn read_medium(&self) -> Option<(u32, u32, Vec<u8>)> {
        let t = self.targets.as_ref()?;
        // The stencil's colour copy where there is one (no stencil copies on GL).
        let (texture, aspect) = match &t.medium_copy {
            Some(c) => (&c.texture, wgpu::TextureAspect::All),
            None => (&t.depth_stencil, wgpu::TextureAspect::StencilOnly),
        };
        let bytes = read_texture_aspect(self.device(), self.queue(), texture, 1, aspect);
        Some((t.size.0, t.size.1, bytes))
    }

    /// Triangles of the scene's opaque geometry (objects, terrain, floor).
    pub fn scene_triangles(&self) -> usize {
        self.shared.geometry.triangle_count
    }

    /// The last frame's linear HDR image (pre-exposed radiance, before the
    /// tone map), RGBA float, rows top to bottom.
    pub fn read_hdr(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        let t = self.targets.as_ref()?;
        Some((t.size.0, t.size.1, self.read_rgba16f(&t.hdr)))
    }

    /// The surface as the renderer samples it (finest level) at undisplaced
    /// points (x, z), after the last simulation step.
    pub fn probe_surface(&self, points: &[[f32; 2]]) -> Vec<SurfaceSample> {
        self.probe.surface(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            points,
        )
    }

    /// Height of the rendered surface above world (x, z): inverts the choppy
    /// displacement on the CPU from GPU samples (what buoyancy code needs).
    /// Each call waits for the GPU several times; for many points, batch
    /// [`Renderer::probe_surface`] or use the CPU twin
    /// `hydrolux_core::waves::ocean::OceanFields::height_at`.
    pub fn height_at(&self, x: f32, z: f32) -> f32 {
        let mut p = [x, z];
        for _ in 0..8 {
            let s = self.probe_surface(&[p])[0];
            p = [x - s.displacement[0], z - s.displacement[2]];
        }
        self.probe_surface(&[p])[0].displacement[1]
    }

    /// Fresnel reflectance as the shaders compute it for (cos θi, n1, n2), in
    /// every mode: [exact, Schlick, Jensen–Goliáš, power (`water.fresnel_power`)].
    /// Needs a frame's uniforms ([`Renderer::simulate`]) for the exponent.
    pub fn probe_fresnel(&self, queries: &[(f32, f32, f32)]) -> Vec<[f32; 4]> {
        self.probe.fresnel(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            queries,
        )
    }

    /// Radiance (kcd/m²) of the baked sky cube map in the given directions.
    pub fn probe_sky(&self, dirs: &[[f32; 3]]) -> Vec<[f32; 3]> {
        self.probe.sky(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            dirs,
        )
    }

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
