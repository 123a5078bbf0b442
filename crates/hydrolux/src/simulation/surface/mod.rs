//! The water surface, whichever model makes it (seed 000 §2.4, seed 001):
//! the FFT ocean's cascades (`simulation/ocean`), a sum of Gerstner waves,
//! flat water or a user's heightfield. A simulation evaluated at a time
//! (the frame's, and a white-water step's); it publishes the surface's bind
//! group that the water, caustics, god rays, probes and white water read
//! (with the interactive water's heights and the foam that the simulations
//! before it publish), and what the frame plan needs to know of it (reach,
//! unresolved slopes, whether it moves by itself).

pub mod readback;

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::simulation::ocean::OceanPass;
use crate::simulation::published::SurfaceState;
use crate::simulation::{Pace, Published, Simulation};
use crate::surface_kind::model_index;
use crate::technique::Shared;
use crate::timing::GpuTimer;
use crate::uniforms::SurfaceUniforms;
use hydrolux_core::scene::{Choice, Scene, WaterModel};
use hydrolux_core::waves::ocean::{OceanSettings, OceanSpectrum};
use hydrolux_core::waves::sines::{MAX_SINE_WAVES, SineWaves};
use hydrolux_core::waves::spectrum::cox_munk_slope_variance;
use wgpu::util::DeviceExt;

pub(crate) struct Surface {
    ocean_settings: OceanSettings,
    pub ocean: OceanPass,
    /// What its bind groups hold besides the others' heights and foam.
    bindings: Bindings,
    /// The surface's bind group (group 1 of the passes that read it).
    group: wgpu::BindGroup,
    /// The same without the foam (white water's own step writes it).
    group_without_foam: wgpu::BindGroup,
    /// Its uniforms (`SurfaceParams`).
    buffer: wgpu::Buffer,
    /// The scene the surface was built for.
    scene: Scene,
    sines: SineWaves,
    /// Slope variance per axis that the surface model does not resolve.
    unresolved_variance: [f32; 2],
    /// Peak height (m) of its own model's waves (the user's heightfield's
    /// as last updated).
    model_height: f64,
    /// The surface changes from frame to frame by itself (FFT, sines, or a
    /// simulation in it).
    moving: bool,
    /// A heightfield's texture and samples per side (x, z), for updates.
    heightfield: Option<(wgpu::Texture, u32, u32)>,
    /// Simulated time (s) of the ocean its textures hold (NaN: none yet).
    evaluated_at: f64,
}

/// The views and samplers of the surface's group that it owns.
struct Bindings {
    fields: [wgpu::TextureView; 3],
    samplers: [wgpu::Sampler; 2],
    heightfield: wgpu::TextureView,
    /// Stand-ins for no interactive water and no foam.
    no_ripples: wgpu::TextureView,
    no_foam: wgpu::TextureView,
}

impl Bindings {
    fn group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        buffer: &wgpu::Buffer,
        ripples: &wgpu::TextureView,
        foam: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        let tv = wgpu::BindingResource::TextureView;
        let sampler = wgpu::BindingResource::Sampler;
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("surface"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: tv(&self.fields[0]) },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&self.fields[1]) },
                wgpu::BindGroupEntry { binding: 3, resource: tv(&self.fields[2]) },
                wgpu::BindGroupEntry { binding: 4, resource: sampler(&self.samplers[0]) },
                wgpu::BindGroupEntry { binding: 5, resource: sampler(&self.samplers[1]) },
                wgpu::BindGroupEntry { binding: 6, resource: tv(&self.heightfield) },
                wgpu::BindGroupEntry { binding: 7, resource: tv(ripples) },
                wgpu::BindGroupEntry { binding: 8, resource: tv(foam) },
            ],
        })
    }

    /// (with foam, without foam) over what `published` holds.
    fn groups(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        buffer: &wgpu::Buffer,
        published: &Published,
    ) -> (wgpu::BindGroup, wgpu::BindGroup) {
        let ripples = published.ripples.as_ref().map_or(&self.no_ripples, |r| &r.heights);
        let foam = published.foam.as_ref().map_or(&self.no_foam, |f| &f.cover);
        (
            self.group(device, layout, buffer, ripples, foam),
            self.group(device, layout, buffer, ripples, &self.no_foam),
        )
    }
}

/// Crest reach of a surface of significant wave height `hs` (m):
/// (vertical, sideways culling margin).
fn surface_reach(scene: &Scene, hs: f64) -> (f32, f32) {
    let bounds_margin =
        (3.0 * hs * (1.0 + scene.ocean.choppiness as f64 + scene.sines.gerstner as f64) + 1.0)
            as f32;
    let gerstner =
        scene.sines.gerstner as f64 * (scene.water.model == WaterModel::Sines) as u8 as f64;
    let vertical_reach = (1.5 * hs * (1.0 + gerstner)) as f32 + 0.1;
    (vertical_reach, bounds_margin)
}

impl Surface {
    /// Build the surface `scene` describes, over what `published` holds.
    pub fn new(shared: &Shared, scene: &Scene, published: &Published) -> Result<Self, RenderError> {
        let (device, queue) = (&shared.device, &shared.queue);
        let no_ripples = texture_2d(
            device,
            "no ripples",
            (1, 1),
            crate::simulation::ripples::FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        let downsampler = &shared.downsampler;
        let layout = &shared.layouts.surface;
        let buffer = uniform_buffer(device, "surface", &SurfaceUniforms::default());
        // Trilinear for explicit-LOD reads; anisotropic for fragment gradients.
        let sampler = |label, anisotropy_clamp| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                anisotropy_clamp,
                ..Default::default()
            })
        };
        let anisotropy = match scene.render.anisotropy {
            0 if device.adapter_info().device_type == wgpu::DeviceType::Cpu => 1,
            0 => 16,
            a => a.min(16) as u16,
        };
        let samplers = [sampler("surface", 1), sampler("surface anisotropic", anisotropy)];
        let ocean_settings = scene.ocean_settings();
        let spectrum = OceanSpectrum::new(&ocean_settings);
        let ocean = OceanPass::new(device, &spectrum, downsampler, &shared.caps)?;
        let view = |t: &wgpu::Texture| {
            t.create_view(&wgpu::TextureViewDescriptor {
                dimension: Some(wgpu::TextureViewDimension::D2Array),
                ..Default::default()
            })
        };
        let (v1, v2, v3) = (
            view(&ocean.textures.displacement),
            view(&ocean.textures.derivative),
            view(&ocean.textures.moments),
        );
        let heightfield = match scene.water.model {
            WaterModel::Heightfield => Some(scene.load_heightfield()?),
            _ => None,
        };
        let (heightfield_texture, heightfield_view) = {
            let (w, h, data) = heightfield
                .as_ref()
                .map_or((1, 1, vec![0.0f32]), |f| (f.nx as u32, f.nz as u32, f.heights.clone()));
            let texture = device.create_texture_with_data(
                queue,
                &wgpu::TextureDescriptor {
                    label: Some("heightfield"),
                    size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: wgpu::TextureFormat::R32Float,
                    usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                    view_formats: &[],
                },
                wgpu::util::TextureDataOrder::LayerMajor,
                bytemuck::cast_slice(&data),
            );
            let view = texture.create_view(&Default::default());
            ((texture, w, h), view)
        };
        let no_foam = texture_2d(
            device,
            "no foam",
            (1, 1),
            crate::mips::FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        let bindings = Bindings {
            fields: [v1, v2, v3],
            samplers,
            heightfield: heightfield_view,
            no_ripples,
            no_foam,
        };
        let (group, group_without_foam) = bindings.groups(device, layout, &buffer, published);

        let sea = scene.sea_state();
        let sines = SineWaves::from_sea_state(
            &sea,
            scene.sines.count as usize,
            scene.ocean.seed,
            scene.sines.gerstner as f64,
        );
        let scale = scene.water.roughness_scale as f64;
        let total = cox_munk_slope_variance(sea.wind_speed, sea.wind_direction).map(|v| v * scale);
        let resolved = match scene.water.model {
            WaterModel::Fft => spectrum.expected_slope_variance(),
            WaterModel::Sines => sines.slope_variance(),
            WaterModel::Flat | WaterModel::None => [0.0, 0.0],
            WaterModel::Heightfield => heightfield.as_ref().map_or([0.0, 0.0], |f| {
                let n = (f.nx * f.nz) as f64;
                let mut v = [0.0f64; 2];
                for j in 0..f.nz {
                    for i in 0..f.nx {
                        let (x, z) = (
                            (i as f32 / f.nx as f32 - 0.5) * f.size[0],
                            (j as f32 / f.nz as f32 - 0.5) * f.size[1],
                        );
                        let s = f.sample(x, z);
                        v[0] += (s.slope[0] as f64).powi(2) / n;
                        v[1] += (s.slope[1] as f64).powi(2) / n;
                    }
                }
                v
            }),
        };
        // What the geometry and textures do not carry. At least a quarter of the
        // Cox–Munk total stays sub-pixel: capillary ripples are never resolved,
        // and without them single facets alias into one-pixel sparkles.
        let unresolved = |i: usize| (total[i] - resolved[i]).max(0.25 * total[i]).max(2e-4) as f32;
        let unresolved_variance = [unresolved(0), unresolved(1)];
        // Crests rarely pass 2·Hs; 3·Hs plus the choppy sideways shift is safe.
        let hs = match scene.water.model {
            WaterModel::Fft => 4.0 * spectrum.expected_variance().sqrt(),
            WaterModel::Sines => {
                4.0 * sines
                    .waves
                    .iter()
                    .map(|w| w.amplitude * w.amplitude / 2.0)
                    .sum::<f64>()
                    .sqrt()
            }
            WaterModel::Flat | WaterModel::None => 0.0,
            // Hs = 4σ would undercount a user's steep single waves: use the peak.
            WaterModel::Heightfield => {
                heightfield.as_ref().map_or(0.0, |f| 2.0 * f.max_abs() as f64)
            }
        };
        Ok(Surface {
            ocean_settings,
            buffer,
            scene: scene.clone(),
            ocean,
            bindings,
            group,
            group_without_foam,
            sines,
            unresolved_variance,
            model_height: hs,
            moving: Self::moves(scene, published),
            heightfield: heightfield.is_some().then_some(heightfield_texture),
            evaluated_at: f64::NAN,
        })
    }

    /// Whether the surface of `scene` changes by itself, with the
    /// simulations that `published` shows in it.
    fn moves(scene: &Scene, published: &Published) -> bool {
        matches!(scene.water.model, WaterModel::Fft | WaterModel::Sines)
            || published.ripples.is_some()
            || !published.bodies.is_empty()
            || published.foam.is_some()
            || published.particles.is_some()
    }

    /// Replace the heights of a `water.model = "heightfield"` surface (same
    /// samples per side as its file, row = z, col = x, metres), e.g. from a
    /// simulation of the caller's. Everything that reads the surface follows
    /// from the next frame: shading, the medium division, height queries,
    /// and the caustics and god rays (their maps are remade).
    pub fn update_heightfield(
        &mut self,
        queue: &wgpu::Queue,
        heights: &[f32],
    ) -> Result<(), RenderError> {
        let Some((texture, nx, nz)) = &self.heightfield else {
            return Err(RenderError::Heightfield(format!(
                "water.model is \"{}\", not \"heightfield\"",
                self.scene.water.model.name()
            )));
        };
        let (nx, nz) = (*nx, *nz);
        if heights.len() != (nx * nz) as usize {
            return Err(RenderError::Heightfield(format!(
                "got {} heights, the surface has {nx} × {nz} = {}",
                heights.len(),
                nx * nz
            )));
        }
        if let Some(bad) = heights.iter().find(|h| !h.is_finite()) {
            return Err(RenderError::Heightfield(format!("a height is {bad}: must be finite")));
        }
        queue.write_texture(
            texture.as_image_copy(),
            bytemuck::cast_slice(heights),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * nx),
                rows_per_image: Some(nz),
            },
            wgpu::Extent3d { width: nx, height: nz, depth_or_array_layers: 1 },
        );
        let peak = heights.iter().fold(0.0f32, |m, h| m.max(h.abs()));
        self.model_height = 2.0 * peak as f64;
        Ok(())
    }

    fn write_uniforms(&self, queue: &wgpu::Queue, time: f64, published: &Published) {
        let s = &self.scene;
        let mut u: SurfaceUniforms = bytemuck::Zeroable::zeroed();
        for (i, c) in self.ocean_settings.cascades().iter().enumerate().take(4) {
            u.cascade_sizes[i] = c.patch_size as f32;
        }
        if s.water.model == WaterModel::Heightfield {
            u.cascade_sizes[0] = s.water.size[0];
            u.cascade_sizes[1] = s.water.size[1];
        }
        if let Some(r) = &published.ripples {
            u.ripple_origin = r.origin;
            u.ripple_side = r.side;
            u.ripple_cell = r.cell;
            u.ripple_window = r.window;
        }
        if let Some(f) = &published.foam {
            u.foam_origin = f.window.origin;
            u.foam_side = f.window.side;
            u.foam_tiles = f.window.tiles as u32;
            (u.foam_wind, u.foam_streak) = (f.wind, f.streak);
        }
        let model = model_index(s.water.model);
        let waves = &self.sines.waves;
        u.cascades = self.ocean.cascades;
        u.model = model;
        u.sine_count = waves.len().min(MAX_SINE_WAVES) as u32;
        u.fft_resolution = self.ocean.n;
        for (i, (w, phase)) in
            waves.iter().zip(self.sines.phases(time)).enumerate().take(MAX_SINE_WAVES)
        {
            u.waves[i] = crate::uniforms::SineWave {
                k: [w.kx as f32, w.kz as f32],
                amplitude: w.amplitude as f32,
                phase,
            };
            let k = (w.kx * w.kx + w.kz * w.kz).sqrt().max(1e-6);
            u.wave_q[i / 4][i % 4] = (w.steepness / k) as f32;
        }
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&u));
    }

    /// Whether `scene` keeps this surface (its waves and model are the same).
    fn keeps(&self, scene: &Scene) -> bool {
        let old = &self.scene;
        !(scene.ocean != old.ocean
            || scene.sines != old.sines
            || scene.water.model != old.water.model
            || scene.water.roughness_scale != old.water.roughness_scale
            || scene.water.heightfield != old.water.heightfield
            || scene.water.size != old.water.size
            || scene.base_dir != old.base_dir
            || scene.render.anisotropy != old.render.anisotropy
            || scene.ocean_settings() != self.ocean_settings
            || ripple_reach(scene) != ripple_reach(old)
            || scene.floor.depth != old.floor.depth)
    }
}

/// How far (m) the interactive water may lift the surface: its scripted
/// craters' rims and rings, and room for what the viewer throws in.
fn ripple_reach(scene: &Scene) -> f64 {
    if !scene.has_interactive_water() {
        return 0.0;
    }
    let drops = scene.drops.iter().map(|d| d.strength.abs());
    let rain = scene.emitters.iter().map(|e| 1.3 * e.strength.abs());
    0.25 + drops.chain(rain).fold(0.0f32, f32::max) as f64
}

impl Simulation for Surface {
    fn create(
        shared: &Shared,
        scene: &Scene,
        published: &Published,
    ) -> Result<Option<Self>, RenderError> {
        Surface::new(shared, scene, published).map(Some)
    }

    fn fits(&self, scene: &Scene) -> bool {
        self.keeps(scene)
    }

    fn connect(&mut self, shared: &Shared, published: &Published) {
        let layout = &shared.layouts.surface;
        (self.group, self.group_without_foam) =
            self.bindings.groups(&shared.device, layout, &self.buffer, published);
        self.moving = Self::moves(&self.scene, published);
    }

    fn publish(&self, published: &mut Published) {
        let (vertical_reach, bounds_margin) =
            surface_reach(&self.scene, self.model_height + ripple_reach(&self.scene));
        published.surface = Some(SurfaceState {
            group: self.group.clone(),
            group_without_foam: self.group_without_foam.clone(),
            bounds_margin,
            vertical_reach,
            moving: self.moving,
            unresolved_variance: self.unresolved_variance,
            ocean_resolution: self.ocean.n,
        });
    }

    fn pace(&self) -> Pace {
        Pace::Evaluated
    }

    fn prepare(&mut self, queue: &wgpu::Queue, time: f64, published: &Published) {
        self.write_uniforms(queue, time, published);
        self.ocean.prepare(queue, time);
    }

    fn stale_at(&self, time: f64, tolerance: f64) -> bool {
        // (A NaN time, nothing evaluated yet, is stale.)
        let current = (time - self.evaluated_at).abs() < tolerance;
        self.scene.water.model == WaterModel::Fft && !current
    }

    fn evaluate(&mut self, shared: &Shared, encoder: &mut wgpu::CommandEncoder, time: f64) {
        if self.scene.water.model == WaterModel::Fft {
            self.ocean.prepare(&shared.queue, time);
            self.ocean.record(encoder, &shared.downsampler, None);
            self.evaluated_at = time;
        }
    }

    fn record_frame(
        &mut self,
        shared: &Shared,
        encoder: &mut wgpu::CommandEncoder,
        plan: &crate::plan::FramePlan,
        timer: Option<&mut GpuTimer>,
    ) {
        if plan.ocean {
            self.ocean.record(encoder, &shared.downsampler, timer);
            self.evaluated_at = plan.time;
        }
    }
}

/// The surface's GPU work: the ocean's FFT.
pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "surface",
    dumps: &[],
    shaders: || (crate::simulation::ocean::INFO.shaders)(),
    uniforms: || {
        let mut v = (crate::simulation::ocean::INFO.uniforms)();
        let src = crate::shaders::compose("", "#import surface\n");
        v.push(crate::uniforms::Layout::of::<crate::uniforms::SineWave>(src));
        v
    },
};
