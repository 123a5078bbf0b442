//! The water surface, whichever model makes it (seed 000 §2.4, seed 001):
//! the FFT ocean's cascades (simulated each frame by `passes/ocean`), a sum
//! of Gerstner waves, flat water or a user's heightfield. It owns the
//! surface's bind group that the water, caustics, god rays and probes read,
//! and what the frame plan needs to know of it (reach, unresolved slopes,
//! whether it moves by itself).

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::passes::ocean::OceanPass;
use crate::passes::ripples::RipplePass;
use crate::passes::ripples::dynamics::Dynamics;
use crate::passes::whitewater::{StepInput as WhitewaterStep, Whitewater};
use crate::surface_kind::model_index;
use crate::technique::{FrameContext, Shared, Stage, Technique};
use crate::timing::GpuTimer;
use crate::uniforms::SurfaceUniforms;
use hydrolux_core::scene::{CLOCK_HZ, Choice, Scene, WaterModel};
use hydrolux_core::waves::ocean::{OceanSettings, OceanSpectrum};
use hydrolux_core::waves::ripples::RippleBoundary;
use hydrolux_core::waves::sines::{MAX_SINE_WAVES, SineWaves};
use hydrolux_core::waves::spectrum::cox_munk_slope_variance;
use wgpu::util::DeviceExt;

pub(crate) struct Surface {
    ocean_settings: OceanSettings,
    pub ocean: OceanPass,
    /// The surface's bind group (group 1 of the passes that read it).
    pub group: wgpu::BindGroup,
    /// The same without the foam (white water's own step writes it).
    group_without_foam: wgpu::BindGroup,
    /// Its uniforms (`SurfaceParams`).
    buffer: wgpu::Buffer,
    /// The scene the surface was built for.
    scene: Scene,
    sines: SineWaves,
    /// Slope variance per axis that the surface model does not resolve.
    pub unresolved_variance: [f32; 2],
    /// Conservative reach (m) of the displacement, vertically and sideways, for culling.
    pub bounds_margin: f32,
    /// How far (m) the surface rises or falls from y = 0 in practice: crests
    /// pass 1.2·Hs about once in a thousand waves; 1.5·Hs is the margin.
    pub vertical_reach: f32,
    /// The surface changes from frame to frame by itself (FFT, sines).
    pub moving: bool,
    /// A heightfield's texture and samples per side (x, z), for updates.
    heightfield: Option<(wgpu::Texture, u32, u32)>,
    /// The interactive water (with `water.dynamic`) and the bodies in it.
    pub dynamics: Option<Dynamics>,
    /// Foam, bubbles and spray (`[whitewater]`).
    pub whitewater: Option<Whitewater>,
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
    /// Build the surface `scene` describes.
    pub fn new(
        shared: &Shared,
        scene: &Scene,
        keep: Option<Dynamics>,
        keep_whitewater: Option<Whitewater>,
    ) -> Result<Self, RenderError> {
        let (device, queue) = (&shared.device, &shared.queue);
        // The simulation goes on through edits that do not touch it.
        let dynamics = match keep {
            Some(d) if d.fits(scene) => Some(d),
            _ => {
                let ripples = scene
                    .ripple_settings()
                    .map(|settings| RipplePass::new(device, queue, &shared.caps, scene, settings));
                Dynamics::new(queue, scene, ripples)
            }
        };
        let no_ripples = texture_2d(
            device,
            "no ripples",
            (1, 1),
            crate::passes::ripples::FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let ripple_view = dynamics
            .as_ref()
            .and_then(|d| d.ripples.as_ref())
            .map_or(&no_ripples, |r| &r.texture)
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
        let make_group = |foam_view: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("surface"),
                layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&v1),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&v2),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&v3),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&samplers[0]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::Sampler(&samplers[1]),
                    },
                    wgpu::BindGroupEntry {
                        binding: 6,
                        resource: wgpu::BindingResource::TextureView(&heightfield_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 7,
                        resource: wgpu::BindingResource::TextureView(&ripple_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 8,
                        resource: wgpu::BindingResource::TextureView(foam_view),
                    },
                ],
            })
        };
        let no_foam = texture_2d(
            device,
            "no foam",
            (1, 1),
            crate::mips::FORMAT,
            wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&Default::default());
        let group_without_foam = make_group(&no_foam);
        let mut whitewater = match keep_whitewater {
            Some(w) if w.fits(scene) => Some(w),
            _ => Whitewater::new(shared, scene, &spectrum),
        };
        if let Some(w) = &mut whitewater {
            let kicks = dynamics.as_ref().and_then(|d| d.ripples.as_ref()).map(|r| &r.kicks);
            w.bind_kicks(device, kicks);
        }
        let group = match &whitewater {
            Some(w) => make_group(&w.cover.create_view(&Default::default())),
            None => make_group(&no_foam),
        };

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
        let (vertical_reach, bounds_margin) = surface_reach(scene, hs + ripple_reach(scene));
        Ok(Surface {
            ocean_settings,
            buffer,
            scene: scene.clone(),
            ocean,
            group,
            sines,
            unresolved_variance,
            bounds_margin,
            vertical_reach,
            moving: matches!(scene.water.model, WaterModel::Fft | WaterModel::Sines)
                || dynamics.is_some()
                || whitewater.is_some(),
            heightfield: heightfield.is_some().then_some(heightfield_texture),
            dynamics,
            whitewater,
            group_without_foam,
        })
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
        let (reach, margin) = surface_reach(&self.scene, 2.0 * peak as f64);
        self.vertical_reach = reach;
        self.bounds_margin = margin;
        Ok(())
    }

    fn write_uniforms(&self, queue: &wgpu::Queue, time: f64) {
        let s = &self.scene;
        let mut u: SurfaceUniforms = bytemuck::Zeroable::zeroed();
        for (i, c) in self.ocean_settings.cascades().iter().enumerate().take(4) {
            u.cascade_sizes[i] = c.patch_size as f32;
        }
        if s.water.model == WaterModel::Heightfield {
            u.cascade_sizes[0] = s.water.size[0];
            u.cascade_sizes[1] = s.water.size[1];
        }
        if let Some(r) = self.dynamics.as_ref().and_then(|d| d.ripples.as_ref()) {
            let g = r.settings.grid;
            let lo = [0, 1].map(|a| r.window.low_edge(&g, a) as f32);
            let side = g.extent() as f32;
            // Walls: the texture is the domain; open: it tiles from the origin.
            let origin = match g.boundary {
                RippleBoundary::Walls => lo,
                _ => [0.0, 0.0],
            };
            u.ripple_origin = origin;
            u.ripple_side = side;
            u.ripple_cell = g.cell_size as f32;
            u.ripple_window = [lo[0], lo[1], lo[0] + side, lo[1] + side];
        }
        if let Some(w) = &self.whitewater {
            let area = w.foam_area();
            u.foam_origin = area.origin;
            u.foam_side = area.side;
            u.foam_tiles = area.tiles as u32;
            (u.foam_wind, u.foam_streak) = w.foam_wind();
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
            u.waves[i] = [w.kx as f32, w.kz as f32, w.amplitude as f32, phase];
            let k = (w.kx * w.kx + w.kz * w.kz).sqrt().max(1e-6);
            u.wave_q[i / 4][i % 4] = (w.steepness / k) as f32;
        }
        queue.write_buffer(&self.buffer, 0, bytemuck::bytes_of(&u));
    }

    /// Whether `scene` needs a new surface (its waves or model changed).
    pub fn outdated(&self, scene: &Scene) -> bool {
        let old = &self.scene;
        scene.ocean != old.ocean
            || scene.sines != old.sines
            || scene.water.model != old.water.model
            || scene.water.roughness_scale != old.water.roughness_scale
            || scene.water.heightfield != old.water.heightfield
            || scene.water.size != old.water.size
            || scene.base_dir != old.base_dir
            || scene.render.anisotropy != old.render.anisotropy
            || scene.ocean_settings() != self.ocean_settings
            || self.dynamics.as_ref().map_or(scene.water.dynamic, |d| !d.fits(scene))
            || scene.floor.depth != old.floor.depth
    }
}

/// How far (m) the interactive water may lift the surface: its scripted
/// craters' rims and rings, and room for what the viewer throws in.
fn ripple_reach(scene: &Scene) -> f64 {
    if scene.ripple_settings().is_none() {
        return 0.0;
    }
    let drops = scene.drops.iter().map(|d| d.strength.abs());
    let rain = scene.emitters.iter().map(|e| 1.3 * e.strength.abs());
    0.25 + drops.chain(rain).fold(0.0f32, f32::max) as f64
}

impl Technique for Surface {
    fn create(shared: &Shared, scene: &Scene) -> Result<Self, RenderError> {
        Surface::new(shared, scene, None, None)
    }

    fn set_scene(
        &mut self,
        shared: &Shared,
        _old: &Scene,
        new: &Scene,
    ) -> Result<bool, RenderError> {
        let outdated = self.outdated(new);
        let whitewater_outdated =
            self.whitewater.as_ref().map_or(new.has_whitewater(), |w| !w.fits(new));
        if outdated || whitewater_outdated {
            let keep = self.dynamics.take();
            let keep_whitewater = self.whitewater.take();
            *self = Surface::new(shared, new, keep, keep_whitewater)?;
        }
        Ok(outdated || whitewater_outdated)
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        self.write_uniforms(queue, frame.plan.time);
        self.ocean.prepare(queue, frame.plan.time);
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if stage == Stage::Simulate
            && let Some(d) = &mut self.dynamics
        {
            // A frame before the first step draws the water at rest as set.
            d.publish_if_unpublished(&frame.shared.device, &frame.shared.queue, encoder);
        }
        match stage {
            Stage::Simulate if frame.plan.ocean => {
                self.ocean.record(encoder, &frame.shared.downsampler, timer);
                if let Some(w) = &mut self.whitewater {
                    w.ocean_time = frame.plan.time;
                }
            }
            Stage::Volume => {
                if let Some(w) = &self.whitewater
                    && w.has_particles()
                {
                    w.draw.record(encoder, frame, &w.args, w.list(), self.vertical_reach, timer);
                }
            }
            _ => {}
        }
    }

    fn simulates(&self) -> bool {
        self.dynamics.is_some() || self.whitewater.is_some()
    }

    fn reset_state(&mut self, queue: &wgpu::Queue, from: u64) {
        if let Some(d) = &mut self.dynamics {
            d.reset(queue, from);
        }
        if let Some(w) = &mut self.whitewater {
            w.reset(queue, from);
        }
    }

    fn step(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        steps: u32,
        _clock_dt: f64,
    ) {
        let shared = frame.shared;
        let (device, queue) = (&shared.device, &shared.queue);
        let camera = &frame.plan.camera;
        let Some(mut whitewater) = self.whitewater.take() else {
            if let Some(d) = &mut self.dynamics {
                d.step(device, queue, encoder, camera, steps);
            }
            return;
        };
        // White water steps between the interactive water's, each seeing
        // the surface at its own time: an FFT ocean far from the time its
        // textures hold is evaluated again (in a submission of its own).
        let fft = self.scene.water.model == WaterModel::Fft;
        let frame_end = (frame.plan.time.max(0.0) * CLOCK_HZ as f64).floor() as u64;
        let schedule = whitewater.schedule(steps as u64, frame_end, queue);
        let mut followed = 0u64;
        let mut evaluated = false;
        let count = schedule.len();
        for (k, (before, time)) in schedule.into_iter().enumerate() {
            // (Written so that a NaN ocean time also re-evaluates.)
            let current = (time - whitewater.ocean_time).abs() < 0.5 * whitewater.dt as f64;
            let needs_ocean = fft && !current;
            // Every step but a lone last one goes in a submission of its own:
            // the interactive water's steps after it may read the water back
            // (the bodies' sync), which must see this step's work done.
            let own = k + 1 < count || needs_ocean || self.dynamics.is_some();
            let mut own_encoder = own.then(|| device.create_command_encoder(&Default::default()));
            let e = own_encoder.as_mut().unwrap_or(&mut *encoder);
            let mut splashes = Vec::new();
            if let Some(d) = &mut self.dynamics {
                for input in d.step(device, queue, e, camera, before as u32) {
                    splashes.extend(
                        input.drops.iter().filter_map(hydrolux_core::whitewater::drop_splash),
                    );
                    splashes.extend(
                        input
                            .moves
                            .iter()
                            .filter_map(|m| hydrolux_core::whitewater::body_splash(m, d.dt())),
                    );
                }
            }
            followed += before;
            if needs_ocean {
                self.ocean.prepare(queue, time);
                self.ocean.record(e, &shared.downsampler, None);
                whitewater.ocean_time = time;
                evaluated = true;
            }
            let centre = self.dynamics.as_ref().and_then(|d| d.ripples.as_ref()).map_or(
                [camera.position.x, camera.position.z],
                |r| {
                    let g = r.settings.grid;
                    let half = 0.5 * g.extent();
                    [0, 1].map(|a| (r.window.low_edge(&g, a) + half) as f32)
                },
            );
            let input =
                WhitewaterStep { centre, camera: [camera.position.x, camera.position.z], splashes };
            whitewater.record_step(queue, e, &self.group_without_foam, input);
            if let Some(e) = own_encoder {
                queue.submit([e.finish()]);
            }
        }
        // What is left of the clock's steps after our last step; their
        // splashes wait for the next white-water step (in a later frame),
        // as they would had the frame ended elsewhere.
        if let Some(d) = &mut self.dynamics {
            let rest = (steps as u64).saturating_sub(followed);
            let dt = d.dt();
            for input in d.step(device, queue, encoder, camera, rest as u32) {
                let drops = input.drops.iter().filter_map(hydrolux_core::whitewater::drop_splash);
                let moves = input
                    .moves
                    .iter()
                    .filter_map(|m| hydrolux_core::whitewater::body_splash(m, dt));
                for splash in drops.chain(moves) {
                    whitewater.splash(splash);
                }
            }
        }
        if evaluated {
            // The frame's own ocean, at its time.
            self.ocean.prepare(queue, frame.plan.time);
        }
        whitewater.record_mips(encoder, &shared.downsampler);
        self.whitewater = Some(whitewater);
        // The foam window may have moved.
        self.write_uniforms(queue, frame.plan.time);
    }
}

/// The surface's GPU work: the ocean's FFT and the interactive water.
pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "surface",
    shaders: || {
        let mut v = (crate::passes::ocean::INFO.shaders)();
        v.extend((crate::passes::ripples::INFO.shaders)());
        v.extend((crate::passes::whitewater::INFO.shaders)());
        v
    },
    uniforms: || {
        let mut v = (crate::passes::ocean::INFO.uniforms)();
        v.extend((crate::passes::ripples::INFO.uniforms)());
        v.extend((crate::passes::whitewater::INFO.uniforms)());
        v
    },
};
