//! Reading back what a frame made and asking the surface and sky questions
//! outside the frame: for tests, dumps and callers (buoyancy, tools).

use crate::gpu_util::*;
use crate::info::DumpData;
use crate::renderer::Renderer;
use crate::technique::DumpContext;
use hydrolux_core::scene::WaterModel;
use hydrolux_core::waves::SurfaceSample;
use hydrolux_core::waves::ocean::OceanFields;

impl Renderer {
    /// Read dump `name` back (one of [`crate::dump_kinds`]): from the last
    /// frame or simulation step, by whoever declares it. An error says why
    /// there is nothing to read (e.g. no god-ray buffer this frame).
    pub fn dump(&self, name: &str) -> Result<DumpData, String> {
        let grid = |columns: usize, channels: usize, data: Vec<f32>| DumpData::Floats {
            columns,
            rows: data.len() / (columns * channels).max(1),
            channels,
            data,
            note: None,
        };
        match name {
            "hdr" => {
                let Some((w, _, px)) = self.read_hdr() else {
                    return Err("no frame has been rendered to dump".into());
                };
                return Ok(grid(
                    w as usize,
                    3,
                    px.iter().flat_map(|p| [p[0], p[1], p[2]]).collect(),
                ));
            }
            "height" | "displacement" | "normals" | "jacobian" => {
                let (n, samples) = self.surface_grid();
                let (c, data): (usize, Vec<f32>) = match name {
                    "height" => (1, samples.iter().map(|s| s.displacement[1]).collect()),
                    "displacement" => (3, samples.iter().flat_map(|s| s.displacement).collect()),
                    "normals" => (3, samples.iter().flat_map(|s| s.normal().to_array()).collect()),
                    _ => (1, samples.iter().map(|s| s.jacobian()).collect()),
                };
                return Ok(grid(n, c, data));
            }
            _ => {}
        }
        let ctx = DumpContext {
            device: self.device(),
            queue: self.queue(),
            scene: &self.scene,
            plan: self.last_plan.as_ref(),
            time: self.simulation_time(),
        };
        let by_technique = self.techniques.each().into_iter().find_map(|t| t.dump(name, &ctx));
        by_technique
            .or_else(|| self.simulations.dump(name, &ctx))
            .unwrap_or_else(|| Err(format!("no dump named `{name}`")))
    }

    /// Surface samples on the largest cascade's N×N grid (x_j = j·L/N, row
    /// = z, col = x), before horizontal displacement: the FFT's float32
    /// output for the FFT ocean, the probe otherwise.
    fn surface_grid(&self) -> (usize, Vec<SurfaceSample>) {
        let scene = &self.scene;
        let n = scene.ocean.resolution as usize;
        let l = scene.ocean.patch_size as f64;
        let points: Vec<[f64; 2]> = (0..n)
            .flat_map(|z| (0..n).map(move |x| [x as f64 * l / n as f64, z as f64 * l / n as f64]))
            .collect();
        let samples = match (scene.water.model, self.read_ocean_fields()) {
            (WaterModel::Fft, Some(texels)) => {
                let cascades = scene.ocean_settings().cascades();
                let fields = OceanFields {
                    resolution: n,
                    patch_sizes: cascades.iter().map(|c| c.patch_size).collect(),
                    texels,
                };
                points.iter().map(|p| fields.sample(p[0], p[1])).collect()
            }
            _ => {
                let points: Vec<[f32; 2]> =
                    points.iter().map(|p| [p[0] as f32, p[1] as f32]).collect();
                self.probe_surface(&points)
            }
        };
        (n, samples)
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
        Some((t.size.0, t.size.1, read_rgba16f(self.device(), self.queue(), &t.hdr)))
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

    /// The far sea's BRDF as the water pass evaluates it, per query: [mean
    /// Fresnel over the visible facets, the direction the sky is looked up
    /// about (xyz), the sun's glitter per unit irradiance]. Needs a frame's
    /// uniforms ([`Renderer::simulate`]) for the power mode's exponent.
    pub fn probe_sea_brdf(&self, queries: &[crate::probe::SeaBrdfQuery]) -> Vec<[f32; 5]> {
        self.probe.sea_brdf(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            queries,
        )
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

    /// The temporal anti-aliasing's resolve as the shaders compute it (the
    /// GPU side of `hydrolux_core::antialias::resolve`'s twin test): for
    /// each query, the resolved colour.
    pub fn probe_antialias(&self, queries: &[crate::probe::AntialiasQuery]) -> Vec<[f32; 3]> {
        self.probe.antialias(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            queries,
        )
    }

    /// A spray parcel's look as the shaders draw it (the GPU side of
    /// `hydrolux_core::whitewater::spray_look`'s twin test), at quad point
    /// `at` of parcel `id`: [opacity, optical depth, asymmetry, the sky's
    /// share seen along a view whose vertical is `at[1]`].
    pub fn probe_spray(
        &self,
        queries: &[([f32; 2], hydrolux_core::whitewater::spray_look::SprayShape, u32)],
    ) -> Vec<[f32; 4]> {
        self.probe.spray(
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
            0.0,
        )
    }

    /// The sky as a surface of perceptual `roughness` (0 to 1) reflects it
    /// towards each direction: the environment cube's level filtered for
    /// that GGX lobe (`hydrolux_core::pbr::prefiltered`), in kcd/m².
    pub fn probe_sky_filtered(&self, dirs: &[[f32; 3]], roughness: f32) -> Vec<[f32; 3]> {
        self.probe.sky(
            self.device(),
            self.queue(),
            [&self.bound.globals, &self.bound.surface],
            dirs,
            hydrolux_core::pbr::cube_level(roughness),
        )
    }
}

/// Per-pass GPU times: the last frame's timestamps, read back.
impl Renderer {
    /// Collect per-pass GPU timestamps for each frame (where the adapter supports them).
    pub fn set_timing(&mut self, on: bool) {
        self.timing = on;
    }

    pub fn has_timestamps(&self) -> bool {
        self.timer.is_some()
    }

    /// Per-pass GPU milliseconds of the last frame, once its submission has
    /// been waited for ([`Renderer::collect_timings`]).
    pub fn last_timings(&self) -> &[(&'static str, f64)] {
        &self.last_timings
    }

    /// Wait for the last frame and read its pass timings (no-op without timing).
    pub fn collect_timings(&mut self) {
        if let (true, Some(t)) = (self.timing, &self.timer) {
            self.last_timings = t.read(&self.shared.device);
        }
    }
}
