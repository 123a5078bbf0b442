//! The renderer: owns the passes, turns a [`Scene`] into their inputs, and
//! records one frame in order (see ARCHITECTURE.md): ocean simulate → sky
//! bake (when the sun moved) → shadow map → reflection → refraction → sky +
//! scene → water → tonemap (or a debug view).

use crate::gpu_util::*;
use crate::passes::caustics::{CausticMap, CausticsPass};
use crate::passes::geometry::{
    GeometryPass, Objects, SHADOW_FORMAT, SceneGeometry, ViewSlot, Winding,
};
use crate::passes::godrays::{GodRayTubes, GodRaysPass, Shafts};
use crate::passes::mips::Downsampler;
use crate::passes::ocean::{OceanPass, OceanTooLarge};
use crate::passes::probe::ProbePass;
use crate::passes::sky::SkyPass;
use crate::passes::tonemap::TonemapPass;
use crate::passes::water::WaterPass;
use crate::passes::water_object::{ObjectLight, WaterObjectPass};
use crate::plan::{FramePlan, World};
use crate::targets::{TargetSettings, Targets};
use crate::timing::GpuTimer;
use crate::uniforms::{FrameUniforms, SurfaceUniforms};
use hydrolux_core::camera::Camera;
use hydrolux_core::geometry::load::AssetError;
use hydrolux_core::projective::ClipPlane;
use hydrolux_core::scene::{Choice, DebugView, Scene, WaterModel};
use hydrolux_core::sky::{SkyParams, sky_irradiance_up};
use hydrolux_core::waves::SurfaceSample;
use hydrolux_core::waves::ocean::{OceanSettings, OceanSpectrum};
use hydrolux_core::waves::sines::{MAX_SINE_WAVES, SineWaves};
use hydrolux_core::waves::spectrum::cox_munk_slope_variance;
use wgpu::util::DeviceExt;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    OceanTooLarge(#[from] OceanTooLarge),
    #[error(transparent)]
    Asset(#[from] AssetError),
    #[error("cannot update the heightfield: {0}")]
    Heightfield(String),
}

/// The sun's shadow map and what reads it.
struct ShadowState {
    resolution: u32,
    view: wgpu::TextureView,
    /// Globals (group 0) including this shadow map.
    globals: wgpu::BindGroup,
}

/// The geometry views: one uniform slot per view.
struct ViewSlots {
    main: ViewSlot,
    reflection: ViewSlot,
    refraction: ViewSlot,
    reflection_under: ViewSlot,
    refraction_over: ViewSlot,
    shadow: ViewSlot,
    /// Refractive objects' light view.
    object_light: ViewSlot,
}

/// What one frame needs beyond the scene: where to draw, and when.
pub struct FrameInput<'a> {
    pub target: &'a wgpu::TextureView,
    pub size: (u32, u32),
    pub camera: Camera,
    /// Simulation time, seconds.
    pub time: f64,
}

struct SurfaceState {
    ocean_settings: OceanSettings,
    ocean: OceanPass,
    group: wgpu::BindGroup,
    sines: SineWaves,
    /// Slope variance per axis that the surface model does not resolve.
    unresolved_variance: [f32; 2],
    /// Conservative reach (m) of the displacement, vertically and sideways, for culling.
    bounds_margin: f32,
    /// How far (m) the surface rises or falls from y = 0 in practice: crests
    /// pass 1.2·Hs about once in a thousand waves; 1.5·Hs is the margin.
    vertical_reach: f32,
    /// The surface changes from frame to frame by itself (FFT, sines).
    moving: bool,
    /// A heightfield's texture and samples per side (x, z), for updates.
    heightfield: Option<(wgpu::Texture, u32, u32)>,
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

pub struct Renderer {
    device: wgpu::Device,
    queue: wgpu::Queue,
    target_format: wgpu::TextureFormat,
    surface_layout: wgpu::BindGroupLayout,
    frame_buffer: wgpu::Buffer,
    surface_buffer: wgpu::Buffer,
    globals_layout: wgpu::BindGroupLayout,
    frame_only: wgpu::BindGroup,
    shadow_sampler: wgpu::Sampler,
    sky_sampler: wgpu::Sampler,
    caustic_sampler: wgpu::Sampler,
    caustics: CausticsPass,
    caustic_map: CausticMap,
    godrays: GodRaysPass,
    godray_tubes: GodRayTubes,
    water_object: WaterObjectPass,
    object_light: ObjectLight,
    shadow: ShadowState,
    downsampler: Downsampler,
    sky: SkyPass,
    geometry_pass: GeometryPass,
    geometry: SceneGeometry,
    views: ViewSlots,
    water_inputs_layout: wgpu::BindGroupLayout,
    water: WaterPass,
    tonemap: TonemapPass,
    probe: ProbePass,
    surface: SurfaceState,
    targets: Option<Targets>,
    scene: Scene,
    sky_irradiance: glam::Vec3,
    timer: Option<GpuTimer>,
    timing: bool,
    last_timings: Vec<(&'static str, f64)>,
    /// The caustic map matches the scene; only a still surface (flat water,
    /// a heightfield) lets it be reused from frame to frame.
    caustics_current: bool,
    /// The water objects' light paths and caustic map match the scene (they
    /// depend only on it: objects, floor and sun are static).
    object_light_current: bool,
    /// The last frame's (or simulation step's) plan, for readbacks.
    last_plan: Option<FramePlan>,
}

impl Renderer {
    /// Create every pass for drawing into textures of `target_format`.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target_format: wgpu::TextureFormat,
        scene: &Scene,
    ) -> Result<Self, RenderError> {
        let (vs, fs, cs) =
            (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::COMPUTE);
        let all = vs | fs | cs;
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[
                uniform_entry(0, all),
                uniform_entry(1, all),
                texture_entry(2, all, wgpu::TextureViewDimension::Cube, true),
                sampler_entry(3, all),
                layout_entry(
                    4,
                    all,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
                layout_entry(
                    5,
                    all,
                    wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                ),
                texture_entry(6, all, wgpu::TextureViewDimension::D2Array, true),
                sampler_entry(7, all),
                texture_entry(8, all, wgpu::TextureViewDimension::D2, true),
            ],
        });
        let frame_only_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame only"),
            entries: &[uniform_entry(0, all)],
        });
        let surface_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("surface"),
            entries: &[
                uniform_entry(0, all),
                texture_entry(1, all, wgpu::TextureViewDimension::D2Array, true),
                texture_entry(2, all, wgpu::TextureViewDimension::D2Array, true),
                texture_entry(3, all, wgpu::TextureViewDimension::D2Array, true),
                sampler_entry(4, all),
                sampler_entry(5, all),
                texture_entry(6, all, wgpu::TextureViewDimension::D2, false),
            ],
        });
        let frame_buffer = uniform_buffer(device, "frame", &FrameUniforms::default());
        let surface_buffer =
            uniform_buffer(device, "surface", &bytemuck::Zeroable::zeroed() as &SurfaceUniforms);
        let sky_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("sky"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });

        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let frame_only = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("frame only"),
            layout: &frame_only_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: frame_buffer.as_entire_binding(),
            }],
        });
        let main_depth_format = crate::targets::main_depth_format(device);
        let downsampler = Downsampler::new(device);
        let sky = SkyPass::new(device, &downsampler, &globals_layout, main_depth_format);
        let caustic_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("caustic map"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        // Group 0 of the caustics pass is the frame alone: the globals hold the
        // caustic map it writes.
        let caustics = CausticsPass::new(device, &frame_only_layout, &surface_layout);
        let caustic_map = caustics.create_map(
            device,
            scene.caustics.photons,
            scene.caustics.map_resolution,
            scene.caustics.layers,
        );
        let geometry_pass = GeometryPass::new(
            device,
            queue,
            &globals_layout,
            &frame_only_layout,
            main_depth_format,
        );
        let geometry = geometry_pass.upload(device, queue, scene)?;
        let godrays = GodRaysPass::new(
            device,
            &globals_layout,
            &frame_only_layout,
            &surface_layout,
            crate::targets::HDR_FORMAT,
        );
        let godray_tubes = godrays.create_tubes(device, scene.godrays.photons);
        let water_object =
            WaterObjectPass::new(device, &globals_layout, &frame_only_layout, &geometry_pass);
        let object_light =
            water_object.create_light(device, &godrays, Self::object_resolution(&geometry, scene));
        let shadow = Self::build_shadow(
            device,
            &globals_layout,
            &frame_buffer,
            &sky,
            [&sky_sampler, &shadow_sampler, &caustic_sampler],
            [&caustic_map.view, &object_light.map_view],
            scene.render.shadow_resolution,
        );
        let views = ViewSlots {
            main: geometry_pass.view_slot(device, "main view", Winding::Normal),
            reflection: geometry_pass.view_slot(device, "reflection view", Winding::Mirrored),
            refraction: geometry_pass.view_slot(device, "refraction view", Winding::Normal),
            reflection_under: geometry_pass.view_slot(
                device,
                "reflection under view",
                Winding::Mirrored,
            ),
            refraction_over: geometry_pass.view_slot(
                device,
                "refraction over view",
                Winding::Normal,
            ),
            shadow: geometry_pass.view_slot(device, "shadow view", Winding::Normal),
            object_light: geometry_pass.view_slot(device, "object light view", Winding::Normal),
        };
        let water_inputs_layout = WaterPass::inputs_layout(device);
        let water = WaterPass::new(
            device,
            &globals_layout,
            &surface_layout,
            &water_inputs_layout,
            main_depth_format,
        );
        let tonemap = TonemapPass::new(device, &globals_layout, target_format);
        let probe = ProbePass::new(device, &globals_layout, &surface_layout);
        let surface = Self::build_surface(
            device,
            queue,
            &downsampler,
            &surface_layout,
            &surface_buffer,
            scene,
        )?;
        let timer = GpuTimer::new(device, queue);
        let mut r = Renderer {
            device: device.clone(),
            queue: queue.clone(),
            target_format,
            surface_layout,
            frame_buffer,
            surface_buffer,
            globals_layout,
            frame_only,
            shadow_sampler,
            sky_sampler,
            caustic_sampler,
            caustics,
            caustic_map,
            godrays,
            godray_tubes,
            water_object,
            object_light,
            shadow,
            downsampler,
            sky,
            geometry_pass,
            geometry,
            views,
            water_inputs_layout,
            water,
            tonemap,
            probe,
            surface,
            targets: None,
            scene: scene.clone(),
            sky_irradiance: glam::Vec3::ZERO,
            timer,
            timing: false,
            last_timings: Vec::new(),
            caustics_current: false,
            object_light_current: false,
            last_plan: None,
        };
        r.update_sky();
        Ok(r)
    }

    fn build_shadow(
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        frame_buffer: &wgpu::Buffer,
        sky: &SkyPass,
        [sky_sampler, shadow_sampler, caustic_sampler]: [&wgpu::Sampler; 3],
        [caustic_view, object_caustic_view]: [&wgpu::TextureView; 2],
        resolution: u32,
    ) -> ShadowState {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHADOW_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let globals = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: frame_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: sky.params.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&sky.cube_view),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Sampler(sky_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 6,
                    resource: wgpu::BindingResource::TextureView(caustic_view),
                },
                wgpu::BindGroupEntry {
                    binding: 7,
                    resource: wgpu::BindingResource::Sampler(caustic_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 8,
                    resource: wgpu::BindingResource::TextureView(object_caustic_view),
                },
            ],
        });
        ShadowState { resolution, view, globals }
    }

    fn build_surface(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        downsampler: &Downsampler,
        layout: &wgpu::BindGroupLayout,
        buffer: &wgpu::Buffer,
        scene: &Scene,
    ) -> Result<SurfaceState, RenderError> {
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
        let ocean = OceanPass::new(device, &spectrum, downsampler)?;
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
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
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
            ],
        });
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
        let (vertical_reach, bounds_margin) = surface_reach(scene, hs);
        Ok(SurfaceState {
            ocean_settings,
            ocean,
            group,
            sines,
            unresolved_variance,
            bounds_margin,
            vertical_reach,
            moving: matches!(scene.water.model, WaterModel::Fft | WaterModel::Sines),
            heightfield: heightfield.is_some().then_some(heightfield_texture),
        })
    }

    /// Replace the heights of a `water.model = "heightfield"` surface (same
    /// samples per side as its file, row = z, col = x, metres), e.g. from a
    /// simulation of the caller's. Everything that reads the surface follows
    /// from the next frame: shading, the medium division, height queries,
    /// and the caustics and god rays (their maps are remade).
    pub fn update_heightfield(&mut self, heights: &[f32]) -> Result<(), RenderError> {
        let Some((texture, nx, nz)) = &self.surface.heightfield else {
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
        self.queue.write_texture(
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
        self.surface.vertical_reach = reach;
        self.surface.bounds_margin = margin;
        self.caustics_current = false;
        Ok(())
    }

    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    pub fn target_format(&self) -> wgpu::TextureFormat {
        self.target_format
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Switch to another scene (or an edited one): rebuilds only what changed.
    pub fn set_scene(&mut self, scene: &Scene) -> Result<(), RenderError> {
        let surface_changed = scene.ocean != self.scene.ocean
            || scene.sines != self.scene.sines
            || scene.water.model != self.scene.water.model
            || scene.water.roughness_scale != self.scene.water.roughness_scale
            || scene.water.heightfield != self.scene.water.heightfield
            || scene.water.size != self.scene.water.size
            || scene.base_dir != self.scene.base_dir
            || scene.render.anisotropy != self.scene.render.anisotropy;
        if surface_changed || scene.ocean_settings() != self.surface.ocean_settings {
            self.surface = Self::build_surface(
                &self.device,
                &self.queue,
                &self.downsampler,
                &self.surface_layout,
                &self.surface_buffer,
                scene,
            )?;
        }
        if scene.floor != self.scene.floor
            || scene.objects != self.scene.objects
            || scene.base_dir != self.scene.base_dir
        {
            self.geometry = self.geometry_pass.upload(&self.device, &self.queue, scene)?;
            self.targets = None;
        }
        let object_resolution = Self::object_resolution(&self.geometry, scene);
        let object_light_changed = object_resolution != self.object_light.resolution;
        if object_light_changed {
            self.object_light =
                self.water_object.create_light(&self.device, &self.godrays, object_resolution);
        }
        let caustics_changed = scene.caustics.photons != self.caustic_map.photons_per_side
            || scene.caustics.map_resolution != self.caustic_map.resolution
            || scene.caustics.layers != self.caustic_map.layers;
        if caustics_changed {
            self.caustic_map = self.caustics.create_map(
                &self.device,
                scene.caustics.photons,
                scene.caustics.map_resolution,
                scene.caustics.layers,
            );
        }
        if scene.render.shadow_resolution != self.shadow.resolution
            || caustics_changed
            || object_light_changed
        {
            self.shadow = Self::build_shadow(
                &self.device,
                &self.globals_layout,
                &self.frame_buffer,
                &self.sky,
                [&self.sky_sampler, &self.shadow_sampler, &self.caustic_sampler],
                [&self.caustic_map.view, &self.object_light.map_view],
                scene.render.shadow_resolution,
            );
            self.targets = None;
        }
        if scene.godrays.photons != self.godray_tubes.per_side {
            self.godray_tubes = self.godrays.create_tubes(&self.device, scene.godrays.photons);
        }
        self.scene = scene.clone();
        self.caustics_current = false;
        self.object_light_current = false;
        self.last_plan = None;
        self.update_sky();
        Ok(())
    }

    fn sky_params(&self) -> SkyParams {
        SkyParams::new(self.scene.sun_direction(), self.scene.sky.turbidity)
    }

    fn update_sky(&mut self) {
        let p = self.sky_params();
        self.sky_irradiance = sky_irradiance_up(&p);
        self.sky.prepare(&self.queue, p);
    }

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
            self.last_timings = t.read(&self.device);
        }
    }

    /// Light-view texels per side for refractive objects (1 without any).
    fn object_resolution(geometry: &SceneGeometry, scene: &Scene) -> u32 {
        if geometry.refractive_bounds.is_some() { scene.godrays.object_resolution } else { 1 }
    }

    /// What the renderer holds that the frame plan depends on.
    fn world(&self) -> World {
        World {
            shadow_bounds: self.geometry.shadow_bounds,
            refractive_bounds: self.geometry.refractive_bounds,
            has_geometry: self.geometry.triangle_count > 0,
            vertical_reach: self.surface.vertical_reach,
            surface_moving: self.surface.moving,
            unresolved_variance: self.surface.unresolved_variance,
            shadow_resolution: self.shadow.resolution,
            object_light_resolution: self.object_light.resolution,
            sky: self.sky_params(),
            sky_irradiance: self.sky_irradiance,
            caustics_current: self.caustics_current,
            object_light_current: self.object_light_current,
        }
    }

    /// Decide the frame (see [`FramePlan`]) and write every uniform it needs.
    fn plan_and_upload(&mut self, camera: Camera, size: (u32, u32), time: f64) -> FramePlan {
        let plan = FramePlan::new(&self.scene, &self.world(), camera, size, time);
        let m = &plan.matrices;
        self.views.main.write(&self.queue, m.view_proj, ClipPlane::none().0);
        self.views.reflection.write(&self.queue, m.reflection, ClipPlane::above(0.0).0);
        self.views.refraction.write(&self.queue, m.refraction, ClipPlane::below(0.0).0);
        self.views.reflection_under.write(&self.queue, m.reflection, ClipPlane::below(0.0).0);
        self.views.refraction_over.write(&self.queue, m.refraction, ClipPlane::above(0.0).0);
        if let Some(shadow) = m.shadow {
            self.views.shadow.write(&self.queue, shadow, ClipPlane::none().0);
        }
        if let Some(o) = &plan.object_light {
            self.views.object_light.write(&self.queue, o.view_proj, ClipPlane::none().0);
            self.water_object.prepare(&self.queue, &o.uniforms);
        }
        if let Some(c) = plan.caustics.filter(|c| c.due) {
            self.caustics.prepare(&self.queue, &self.caustic_map, c.patch, c.depth);
        }
        if let Some(g) = &plan.godrays {
            self.godrays.prepare(&self.queue, &g.uniforms);
        }
        self.queue.write_buffer(&self.frame_buffer, 0, bytemuck::bytes_of(&plan.frame));
        self.write_surface_uniforms(time);
        self.surface.ocean.prepare(&self.queue, time);
        self.last_plan = Some(plan.clone());
        plan
    }

    /// The simulation stages of a planned frame: the sky bake (when the sun
    /// moved), the ocean, the caustic maps when due.
    fn record_simulation(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        plan: &FramePlan,
        mut timer: Option<&mut GpuTimer>,
    ) {
        self.sky.record_bake(encoder, &self.downsampler, timer.as_deref_mut());
        if plan.ocean {
            self.surface.ocean.record(encoder, &self.downsampler, timer.as_deref_mut());
        }
        if plan.caustics.is_some_and(|c| c.due) {
            self.caustics.record(
                encoder,
                &self.frame_only,
                &self.surface.group,
                &self.caustic_map,
                self.scene.caustics.method,
                timer,
            );
            self.caustics_current = true;
        }
    }

    fn write_surface_uniforms(&self, time: f64) {
        let s = &self.scene;
        let mut u: SurfaceUniforms = bytemuck::Zeroable::zeroed();
        for (i, c) in self.surface.ocean_settings.cascades().iter().enumerate().take(4) {
            u.cascade_sizes[i] = c.patch_size as f32;
        }
        if s.water.model == WaterModel::Heightfield {
            u.cascade_sizes[0] = s.water.size[0];
            u.cascade_sizes[1] = s.water.size[1];
        }
        let model = match s.water.model {
            WaterModel::Fft => 0,
            WaterModel::Sines => 1,
            WaterModel::Flat | WaterModel::None => 2,
            WaterModel::Heightfield => 3,
        };
        let waves = &self.surface.sines.waves;
        u.counts = [
            self.surface.ocean.cascades,
            model,
            waves.len().min(MAX_SINE_WAVES) as u32,
            self.surface.ocean.n,
        ];
        for (i, (w, phase)) in
            waves.iter().zip(self.surface.sines.phases(time)).enumerate().take(MAX_SINE_WAVES)
        {
            u.waves[i] = [w.kx as f32, w.kz as f32, w.amplitude as f32, phase];
            let k = (w.kx * w.kx + w.kz * w.kz).sqrt().max(1e-6);
            u.wave_q[i / 4][i % 4] = (w.steepness / k) as f32;
        }
        self.queue.write_buffer(&self.surface_buffer, 0, bytemuck::bytes_of(&u));
    }

    /// Write this frame's inputs and advance the simulation, without drawing:
    /// what [`Renderer::render`] does first. Queries and dumps use it alone.
    pub fn simulate(&mut self, camera: &Camera, size: (u32, u32), time: f64) {
        let plan = self.plan_and_upload(*camera, size, time);
        let mut encoder = self.device.create_command_encoder(&Default::default());
        self.record_simulation(&mut encoder, &plan, None);
        self.queue.submit([encoder.finish()]);
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
        let m = self.caustic_map.resolution;
        let bytes = read_texture_layer(
            &self.device,
            &self.queue,
            &self.caustic_map.texture,
            8,
            self.caustic_map.layers - 1,
        );
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        Some((m, halves.chunks_exact(4).map(|c| f16_to_f32(c[0])).collect()))
    }

    fn target_settings(&self) -> TargetSettings {
        TargetSettings {
            reflection_resolution: self.scene.render.reflection_resolution,
            reflection_margin: self.scene.render.fov_margin,
            godray_resolution: self.scene.godrays.resolution,
            refractive_objects: self.geometry.refractive_bounds.is_some(),
        }
    }

    /// Record one frame into `encoder`, drawing into `input.target`.
    pub fn render(&mut self, encoder: &mut wgpu::CommandEncoder, input: &FrameInput) {
        let settings = self.target_settings();
        if self.targets.as_ref().map(|t| (t.size, t.settings)) != Some((input.size, settings)) {
            self.targets = Some(Targets::new(
                &self.device,
                input.size,
                settings,
                &self.tonemap,
                &self.downsampler,
                &self.water_inputs_layout,
                &self.shadow.view,
                &self.godrays,
                &self.water_object,
            ));
        }
        let plan = self.plan_and_upload(input.camera, input.size, input.time);
        let mut timer = if self.timing { self.timer.take() } else { None };
        if let Some(t) = timer.as_mut() {
            t.begin_frame();
        }
        self.record_simulation(encoder, &plan, timer.as_mut());
        self.record_views(encoder, input, &plan, timer.as_mut());
        if let Some(t) = timer {
            t.resolve(encoder);
            self.timer = Some(t);
        }
    }

    /// The light views, offscreen views, main view and post passes of a
    /// planned frame.
    fn record_views(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        input: &FrameInput,
        plan: &FramePlan,
        mut timer: Option<&mut GpuTimer>,
    ) {
        let targets = self.targets.as_ref().expect("targets were just created");
        let globals = &self.shadow.globals;
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow map"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.shadow.view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.as_deref_mut().and_then(|t| t.render_writes("shadow")),
                occlusion_query_set: None,
                multiview_mask: None,
            });
            if plan.matrices.shadow.is_some() {
                self.geometry_pass.record_shadow(
                    &mut pass,
                    &self.frame_only,
                    &self.views.shadow,
                    &self.geometry,
                    Objects::All,
                );
            }
        }
        if plan.object_light.is_some_and(|o| o.due) {
            self.water_object.record_light(
                encoder,
                &self.frame_only,
                &self.geometry_pass,
                &self.geometry,
                &self.views.object_light,
                &self.object_light,
                timer.as_deref_mut(),
            );
            self.object_light_current = true;
        }
        // Reflection and refraction textures: cleared to "nothing here"
        // (alpha 0, depth at infinity) so the water falls back to the sky or
        // to endless water where no geometry was drawn.
        let mut offscreen: Vec<(&'static str, &crate::targets::ColorDepth, &ViewSlot, bool)> =
            Vec::new();
        if plan.offscreen.air {
            offscreen.push(("reflection", &targets.reflection, &self.views.reflection, true));
            offscreen.push(("refraction", &targets.refraction, &self.views.refraction, false));
        }
        if plan.offscreen.water {
            offscreen.push((
                "reflection under",
                &targets.reflection_under,
                &self.views.reflection_under,
                true,
            ));
            offscreen.push((
                "refraction over",
                &targets.refraction_over,
                &self.views.refraction_over,
                false,
            ));
        }
        for (name, target, slot, mipmapped) in offscreen {
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(name),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &target.color_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &target.depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(0.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: timer.as_deref_mut().and_then(|t| t.render_writes(name)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                self.geometry_pass.record(&mut pass, globals, slot, &self.geometry);
            }
            if let (true, Some(chain)) = (mipmapped, &target.mips) {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("reflection mips"),
                    timestamp_writes: None,
                });
                self.downsampler.record(&mut pass, chain);
            }
        }
        // The main view. First classify each pixel's medium into the stencil
        // (seed 000 §4.2; its own pass so that it is timed on its own), then
        // draw the background, the geometry and the water, each per medium.
        let main_pass = |encoder: &mut wgpu::CommandEncoder,
                         label: &'static str,
                         clear: bool,
                         timer: Option<&mut GpuTimer>| {
            encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(label),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &targets.hdr_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: if clear {
                                wgpu::LoadOp::Clear(wgpu::Color::BLACK)
                            } else {
                                wgpu::LoadOp::Load
                            },
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &targets.depth_stencil_view,
                        depth_ops: Some(wgpu::Operations {
                            load: if clear { wgpu::LoadOp::Clear(0.0) } else { wgpu::LoadOp::Load },
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: Some(wgpu::Operations {
                            load: if clear { wgpu::LoadOp::Clear(0) } else { wgpu::LoadOp::Load },
                            store: wgpu::StoreOp::Store,
                        }),
                    }),
                    timestamp_writes: timer.and_then(|t| t.render_writes(label)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime()
        };
        {
            let mut pass = main_pass(encoder, "medium", true, timer.as_deref_mut());
            if plan.has_water {
                self.water.record_medium(
                    &mut pass,
                    globals,
                    &self.surface.group,
                    &targets.water_inputs,
                    &input.camera,
                );
            }
        }
        {
            let mut pass = main_pass(encoder, "sky, scene and water", false, timer.as_deref_mut());
            if self.scene.render.view != DebugView::Normals {
                self.sky.record_background(&mut pass, globals);
            }
            self.geometry_pass.record_main(&mut pass, globals, &self.views.main, &self.geometry);
            let aspect = input.size.0.max(1) as f32 / input.size.1.max(1) as f32;
            if plan.has_water {
                self.water.record(
                    &mut pass,
                    globals,
                    &self.surface.group,
                    &targets.water_inputs,
                    &input.camera,
                    aspect,
                    self.surface.bounds_margin,
                );
            }
        }
        if let Some(g) = &plan.godrays {
            let shafts = if g.in_air {
                Shafts::Air {
                    object_tubes: plan.object_light.is_some().then_some(&self.object_light.tubes),
                }
            } else {
                Shafts::Water(self.scene.godrays.method)
            };
            self.godrays.record(
                encoder,
                [globals, &self.frame_only, &self.surface.group],
                shafts,
                &self.godray_tubes,
                &targets.godrays,
                &targets.hdr_view,
                timer.as_deref_mut(),
            );
        }
        if let Some(object_targets) = &targets.water_object {
            self.water_object.record_camera(
                encoder,
                globals,
                &self.geometry_pass,
                &self.geometry,
                &self.views.main,
                object_targets,
                (&targets.hdr, &targets.hdr_view),
                timer.as_deref_mut(),
            );
        }
        self.tonemap.record(
            encoder,
            input.target,
            globals,
            &targets.tonemap_input,
            timer.as_deref_mut(),
        );
    }

    /// The last frame's god-ray buffer (linear radiance, pre-exposed, before
    /// upsampling), RGBA float, rows top to bottom; `None` before a frame.
    pub fn read_godrays(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        let t = &self.targets.as_ref()?.godrays;
        let bytes = read_texture(&self.device, &self.queue, &t.buffer, 8);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        let px = halves
            .chunks_exact(4)
            .map(|c| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])])
            .collect();
        Some((t.size.0, t.size.1, px))
    }

    /// The beam tubes of the last frame (lines method): per photon, where it
    /// enters the water (xyz), its length, its direction (xyz) and its flux
    /// relative to the sun's irradiance (m²; 0 = not drawn).
    pub fn read_godray_tubes(&self) -> Vec<[f32; 12]> {
        self.godrays.read_tubes(&self.device, &self.queue, &self.godray_tubes)
    }

    /// The paths of light out of refractive objects in the last frame, one
    /// per light-view texel: exit point p1 (xyz), length to p2, exit
    /// direction (xyz), flux (m², relative to the sun; 0 = no path), rgb
    /// tint (absorption inside), unused.
    pub fn read_object_paths(&self) -> Vec<[f32; 12]> {
        self.godrays.read_tubes(&self.device, &self.queue, &self.object_light.tubes)
    }

    /// The caustic of refractive objects after the last frame, in their
    /// light view (K × K texels, rows top to bottom): rgb irradiance landing
    /// there relative to the sun's on a plane facing it, and the depth of
    /// the surface it landed on.
    pub fn read_object_caustics(&self) -> (u32, Vec<[f32; 4]>) {
        let bytes = read_texture(&self.device, &self.queue, &self.object_light.map, 8);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        (
            self.object_light.resolution,
            halves
                .chunks_exact(4)
                .map(|c| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])])
                .collect(),
        )
    }

    /// The refractive objects' light view (world → clip) and its texels per
    /// side; `None` without refractive objects or with the sun down.
    pub fn object_light_view(&self) -> Option<(glam::Mat4, u32)> {
        let plan = self.last_plan.as_ref()?;
        plan.object_light.map(|o| (o.view_proj, self.object_light.resolution))
    }

    /// Each pixel's medium in the last frame (0 air, 1 water: where its
    /// near-plane point lies), rows top to bottom.
    pub fn read_medium(&self) -> Option<(u32, u32, Vec<u8>)> {
        let t = self.targets.as_ref()?;
        let bytes = read_texture_aspect(
            &self.device,
            &self.queue,
            &t.depth_stencil,
            1,
            wgpu::TextureAspect::StencilOnly,
        );
        Some((t.size.0, t.size.1, bytes))
    }

    /// Triangles of the scene's opaque geometry (objects, terrain, floor).
    pub fn scene_triangles(&self) -> usize {
        self.geometry.triangle_count
    }

    /// The last frame's linear HDR image (pre-exposed radiance, before the
    /// tone map), RGBA float, rows top to bottom.
    pub fn read_hdr(&self) -> Option<(u32, u32, Vec<[f32; 4]>)> {
        let t = self.targets.as_ref()?;
        let bytes = read_texture(&self.device, &self.queue, &t.hdr, 8);
        let halves: &[u16] = bytemuck::cast_slice(&bytes);
        let px = halves
            .chunks_exact(4)
            .map(|c| [f16_to_f32(c[0]), f16_to_f32(c[1]), f16_to_f32(c[2]), f16_to_f32(c[3])])
            .collect();
        Some((t.size.0, t.size.1, px))
    }

    /// The FFT fields of every cascade after the last simulation step (see
    /// [`OceanPass::read_fields`]); `None` unless `water.model = "fft"`.
    pub fn read_ocean_fields(&self) -> Option<Vec<[f32; 8]>> {
        (self.scene.water.model == WaterModel::Fft)
            .then(|| self.surface.ocean.read_fields(&self.device, &self.queue))
    }

    /// The surface as the renderer samples it (finest level) at undisplaced
    /// points (x, z), after the last simulation step.
    pub fn probe_surface(&self, points: &[[f32; 2]]) -> Vec<SurfaceSample> {
        self.probe.surface(
            &self.device,
            &self.queue,
            [&self.shadow.globals, &self.surface.group],
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
            &self.device,
            &self.queue,
            [&self.shadow.globals, &self.surface.group],
            queries,
        )
    }

    /// Radiance (kcd/m²) of the baked sky cube map in the given directions.
    pub fn probe_sky(&self, dirs: &[[f32; 3]]) -> Vec<[f32; 3]> {
        self.probe.sky(&self.device, &self.queue, [&self.shadow.globals, &self.surface.group], dirs)
    }

    pub fn ocean_resolution(&self) -> u32 {
        self.surface.ocean.n
    }
}

/// The largest `ocean.resolution` (a power of two, 64 to 1024) whose FFT
/// buffers fit this device's storage-buffer limit with `cascades` cascades.
pub fn largest_ocean_resolution(device: &wgpu::Device, cascades: u32) -> u32 {
    let limits = device.limits();
    let max = (limits.max_storage_buffer_binding_size as u64).min(limits.max_buffer_size);
    [1024u32, 512, 256, 128, 64]
        .into_iter()
        .find(|&n| crate::passes::ocean::fields_bytes(n, cascades) <= max)
        .unwrap_or(64)
}

/// IEEE half → single precision.
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    match exp {
        0 => sign * frac * 2f32.powi(-24),
        31 => {
            if frac == 0.0 {
                sign * f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => sign * (1.0 + frac / 1024.0) * 2f32.powi(exp - 15),
    }
}
