//! Reading back what a frame made and asking the surface and sky questions
//! outside the frame: for tests, dumps and callers (buoyancy, tools).

use crate::gpu_util::*;
use crate::renderer::Renderer;
pub use crate::simulation::ripples::readback::RippleField;
pub use crate::simulation::whitewater::readback::FoamDump;
pub use crate::simulation::whitewater::readback::ParticleCounts;
use hydrolux_core::waves::SurfaceSample;

impl Renderer {
    /// An RGBA half-float texture's texels as f32, rows top to bottom.
    pub(crate) fn read_rgba16f(&self, texture: &wgpu::Texture) -> Vec<[f32; 4]> {
        let bytes = read_texture(self.device(), self.queue(), texture, 8);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        let texel =
            |c: &[u16]| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])];
        halves.chunks_exact(4).map(texel).collect()
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
}
