//! God rays: volume caustics under the surface (seed 000 §3.5, §4.6; the
//! slices of seed 003 §4.3 for the march). CPU twin:
//! `hydrolux_core::godrays`.
//!
//! Per frame, for a viewer in the water:
//! 1. `tubes.wgsl` (lines method): one compute thread per photon of a grid
//!    over the surface around the viewer builds its beam tube.
//! 2. `resolve.wgsl` `fs_reduce`: the scene's depth at the buffer's size
//!    (nearest of each block).
//! 3. `ribbons.wgsl` draws every tube as a ribbon into the buffer
//!    (additively), or `march.wgsl` marches each buffer texel through the
//!    caustic layers and the shadow map.
//! 4. `resolve.wgsl` `fs_composite`: depth-aware upsampling into the image,
//!    where the pixel's medium is water.
//!
//! Within `godrays.distance` of the eye the buffer carries the sun's single
//! scattering; beyond it the water shaders keep the uniform closed form
//! (`eye_in_scatter` in `shaders/medium.wgsl`), so the two add up to the
//! whole ray.

pub mod readback;

use crate::gpu_util::*;
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;
use hydrolux_core::scene::GodRayMethod;

/// The buffer of scattered light (linear radiance, pre-exposed).
pub const BUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The scene's depth at the buffer's size, as the bits of an f32: a 32-bit
/// integer target is renderable on every backend, `R32Float` is not on
/// wgpu's GL.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

pub fn tubes_source() -> String {
    shaders::compose("", include_str!("tubes.wgsl"))
}

pub fn ribbons_source() -> String {
    shaders::compose("", include_str!("ribbons.wgsl"))
}

pub fn march_source() -> String {
    shaders::compose("", include_str!("march.wgsl"))
}

pub fn resolve_source() -> String {
    shaders::compose("", include_str!("resolve.wgsl"))
}

crate::uniforms::uniform! { GodRayParams;
    /// WGSL `GodRayParams` (common.wgsl).
    pub struct GodRayUniforms {
        pub photons: u32,
        pub steps: u32,
        pub buffer_size: [u32; 2],
        pub region_centre: [f32; 2],
        pub region_half: f32,
        pub ribbon_half_width: f32,
        pub distance: f32,
        pub end_depth: f32,
        pub medium: u32,
        pub shadow_tested: u32,
        pub scattering: [f32; 3],
        pub phase_g: f32,
        pub extinction: [f32; 3],
        pub _pad0: f32,
    }
}

/// The god rays' uniforms from the plan's decisions.
fn uniforms(g: &crate::plan::GodRaysPlan) -> GodRayUniforms {
    GodRayUniforms {
        photons: g.photons,
        steps: g.steps,
        buffer_size: [g.buffer.0, g.buffer.1],
        region_centre: g.region_centre,
        region_half: g.region_half,
        ribbon_half_width: g.ribbon_half_width,
        distance: g.distance,
        end_depth: g.end_depth,
        medium: g.stencil,
        shadow_tested: (!g.in_air) as u32,
        scattering: g.scattering,
        phase_g: g.phase_g,
        extinction: g.extinction,
        _pad0: 0.0,
    }
}

/// WGSL `Tube` (shaders/tube.wgsl): 48 bytes per path.
pub const TUBE_BYTES: u64 = 48;

/// A tube buffer: one tube per photon of a square grid (`per_side`²).
#[derive(Clone)]
pub struct GodRayTubes {
    pub per_side: u32,
    /// The tubes; the water object pass writes its paths here.
    pub buffer: wgpu::Buffer,
    build_group: wgpu::BindGroup,
    draw_group: wgpu::BindGroup,
}

/// A buffer of `per_side`² tubes (`shaders/tube.wgsl`).
pub fn tube_buffer(device: &wgpu::Device, per_side: u32) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("god-ray tubes"),
        size: (per_side as u64).pow(2) * TUBE_BYTES,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// What the god-ray buffer holds this frame.
pub enum Shafts<'a> {
    /// A viewer in the water: the surface's photons as ribbons (lines), or the march.
    Water(GodRayMethod),
    /// A viewer in the fog: the sun marched through the shadow map, and the
    /// paths of light out of refractive objects as ribbons.
    Air { object_tubes: Option<&'a GodRayTubes> },
}

/// Size-dependent targets: the buffer, its depth, and what reads them.
pub struct GodRayTargets {
    pub size: (u32, u32),
    pub buffer: wgpu::Texture,
    buffer_view: wgpu::TextureView,
    depth_view: wgpu::TextureView,
    depth_input: wgpu::BindGroup,
    reduce_input: wgpu::BindGroup,
    composite_input: wgpu::BindGroup,
}

pub struct GodRaysPass {
    params: wgpu::Buffer,
    build_layout: wgpu::BindGroupLayout,
    draw_layout: wgpu::BindGroupLayout,
    depth_layout: wgpu::BindGroupLayout,
    reduce_layout: wgpu::BindGroupLayout,
    composite_layout: wgpu::BindGroupLayout,
    build: wgpu::ComputePipeline,
    /// The surface model `build` is specialised to.
    model: crate::surface_kind::SurfaceKind,
    ribbons: wgpu::RenderPipeline,
    march: wgpu::RenderPipeline,
    fog: wgpu::RenderPipeline,
    reduce: wgpu::RenderPipeline,
    composite: wgpu::RenderPipeline,
}

const ADD: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

fn render_pipeline(
    device: &wgpu::Device,
    label: &str,
    module: &wgpu::ShaderModule,
    entries: (&str, &str),
    layouts: &[&wgpu::BindGroupLayout],
    format: wgpu::TextureFormat,
    additive: bool,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(&pipeline_layout(device, label, layouts)),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(entries.0),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entries.1),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: additive.then_some(wgpu::BlendState { color: ADD, alpha: ADD }),
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

impl GodRaysPass {
    /// The tubes' build, specialised to the surface model.
    fn build_pipeline(
        device: &wgpu::Device,
        layouts: [&wgpu::BindGroupLayout; 3],
        model: crate::surface_kind::SurfaceKind,
    ) -> wgpu::ComputePipeline {
        let module = shader(device, "god-ray tubes", &tubes_source());
        let constants = crate::surface_kind::specialised_to(model);
        compute_pipeline_with(device, "god-ray tubes", &module, "build", &layouts, &constants)
    }

    /// Rebuild what depends on the surface model when it changed.
    pub fn specialise(
        &mut self,
        device: &wgpu::Device,
        frame_only: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
    ) {
        if model != self.model {
            let layouts = [frame_only, surface, &self.build_layout];
            self.build = Self::build_pipeline(device, layouts, model);
            self.model = model;
        }
    }

    pub fn new(
        device: &wgpu::Device,
        globals: &wgpu::BindGroupLayout,
        frame_only: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        hdr_format: wgpu::TextureFormat,
        model: crate::surface_kind::SurfaceKind,
    ) -> Self {
        let (vs, fs, cs) =
            (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT, wgpu::ShaderStages::COMPUTE);
        let build_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("god-ray tubes (build)"),
            entries: &[uniform_entry(0, cs), storage_entry(1, cs, false)],
        });
        let draw_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("god-ray tubes"),
            entries: &[uniform_entry(0, vs | fs), storage_entry(1, vs | fs, true)],
        });
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("god-ray depth"),
            entries: &[uint_texture_entry(0, fs)],
        });
        let reduce_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("god-ray reduce"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, false),
                uniform_entry(4, fs),
            ],
        });
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("god-ray composite"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, false),
                uint_texture_entry(1, fs),
                texture_entry(2, fs, wgpu::TextureViewDimension::D2, false),
                uint_texture_entry(3, fs),
                uniform_entry(4, fs),
            ],
        });
        let build = Self::build_pipeline(device, [frame_only, surface, &build_layout], model);
        let ribbons_module = shader(device, "god-ray ribbons", &ribbons_source());
        let ribbons = render_pipeline(
            device,
            "god-ray ribbons",
            &ribbons_module,
            ("vs_ribbon", "fs_ribbon"),
            &[globals, &draw_layout, &depth_layout],
            BUFFER_FORMAT,
            true,
        );
        let march_module = shader(device, "god-ray march", &march_source());
        let march = render_pipeline(
            device,
            "god-ray march",
            &march_module,
            ("vs_main", "fs_main"),
            &[globals, &draw_layout, &depth_layout],
            BUFFER_FORMAT,
            false,
        );
        let fog = render_pipeline(
            device,
            "god-ray fog",
            &march_module,
            ("vs_main", "fs_fog"),
            &[globals, &draw_layout, &depth_layout],
            BUFFER_FORMAT,
            false,
        );
        let resolve_module = shader(device, "god-ray resolve", &resolve_source());
        let reduce = render_pipeline(
            device,
            "god-ray reduce",
            &resolve_module,
            ("vs_main", "fs_reduce"),
            &[frame_only, &reduce_layout],
            DEPTH_FORMAT,
            false,
        );
        let composite = render_pipeline(
            device,
            "god-ray composite",
            &resolve_module,
            ("vs_main", "fs_composite"),
            &[frame_only, &composite_layout],
            hdr_format,
            true,
        );
        GodRaysPass {
            params: uniform_buffer(device, "god-ray params", &GodRayUniforms::default()),
            build_layout,
            model,
            draw_layout,
            depth_layout,
            reduce_layout,
            composite_layout,
            build,
            ribbons,
            march,
            fog,
            reduce,
            composite,
        }
    }

    pub fn create_tubes(&self, device: &wgpu::Device, per_side: u32) -> GodRayTubes {
        self.bind_tubes(device, tube_buffer(device, per_side), per_side)
    }

    /// Bind a tube buffer (`per_side`² tubes) that another technique writes.
    pub fn bind_tubes(
        &self,
        device: &wgpu::Device,
        buffer: wgpu::Buffer,
        per_side: u32,
    ) -> GodRayTubes {
        let group = |layout, label| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: buffer.as_entire_binding() },
                ],
            })
        };
        GodRayTubes {
            per_side,
            build_group: group(&self.build_layout, "god-ray tubes (build)"),
            draw_group: group(&self.draw_layout, "god-ray tubes"),
            buffer,
        }
    }

    /// The buffer (`scale` × the output size) and its bind groups, reading
    /// the main view's depth and medium (stencil) views.
    pub fn create_targets(
        &self,
        device: &wgpu::Device,
        output: (u32, u32),
        scale: f32,
        main_depth: &wgpu::TextureView,
        main_medium: &wgpu::TextureView,
    ) -> GodRayTargets {
        let size = (
            ((output.0 as f32 * scale).round() as u32).max(1),
            ((output.1 as f32 * scale).round() as u32).max(1),
        );
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC;
        let texture = |label, format| texture_2d(device, label, size, format, usage);
        let buffer = texture("god-ray buffer", BUFFER_FORMAT);
        let depth = texture("god-ray depth", DEPTH_FORMAT);
        let buffer_view = buffer.create_view(&Default::default());
        let depth_view = depth.create_view(&Default::default());
        let tv = wgpu::BindingResource::TextureView;
        let depth_input = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("god-ray depth"),
            layout: &self.depth_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: tv(&depth_view) }],
        });
        let reduce_input = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("god-ray reduce"),
            layout: &self.reduce_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: tv(main_depth) },
                wgpu::BindGroupEntry { binding: 4, resource: self.params.as_entire_binding() },
            ],
        });
        let composite_input = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("god-ray composite"),
            layout: &self.composite_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: tv(main_depth) },
                wgpu::BindGroupEntry { binding: 1, resource: tv(&depth_view) },
                wgpu::BindGroupEntry { binding: 2, resource: tv(&buffer_view) },
                wgpu::BindGroupEntry { binding: 3, resource: tv(main_medium) },
                wgpu::BindGroupEntry { binding: 4, resource: self.params.as_entire_binding() },
            ],
        });
        GodRayTargets {
            size,
            buffer,
            buffer_view,
            depth_view,
            depth_input,
            reduce_input,
            composite_input,
        }
    }

    /// Write this frame's parameters (before recording).
    pub fn prepare(&self, queue: &wgpu::Queue, uniforms: &GodRayUniforms) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(uniforms));
    }

    /// Build the surface's tubes (lines in the water), fill the buffer and
    /// add it to `hdr`.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        [globals, frame_only, surface]: [&wgpu::BindGroup; 3],
        shafts: Shafts,
        tubes: &GodRayTubes,
        targets: &GodRayTargets,
        hdr: &wgpu::TextureView,
        mut timer: Option<&mut GpuTimer>,
    ) {
        if matches!(shafts, Shafts::Water(GodRayMethod::Off)) {
            return;
        }
        if matches!(shafts, Shafts::Water(GodRayMethod::Lines)) {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("god-ray tubes"),
                timestamp_writes: timer
                    .as_deref_mut()
                    .and_then(|t| t.compute_writes("god-ray tubes")),
            });
            pass.set_pipeline(&self.build);
            pass.set_bind_group(0, frame_only, &[]);
            pass.set_bind_group(1, surface, &[]);
            pass.set_bind_group(2, &tubes.build_group, &[]);
            let n = tubes.per_side.div_ceil(8);
            pass.dispatch_workgroups(n, n, 1);
        }
        let target = |encoder: &mut wgpu::CommandEncoder,
                      label: &'static str,
                      view,
                      timer: Option<&mut GpuTimer>| {
            encoder
                .begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some(label),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: None,
                    timestamp_writes: timer.and_then(|t| t.render_writes(label)),
                    occlusion_query_set: None,
                    multiview_mask: None,
                })
                .forget_lifetime()
        };
        {
            let mut pass =
                target(encoder, "god-ray depth", &targets.depth_view, timer.as_deref_mut());
            pass.set_pipeline(&self.reduce);
            pass.set_bind_group(0, frame_only, &[]);
            pass.set_bind_group(1, &targets.reduce_input, &[]);
            pass.draw(0..3, 0..1);
        }
        {
            let mut pass = target(encoder, "god rays", &targets.buffer_view, timer.as_deref_mut());
            pass.set_bind_group(0, globals, &[]);
            pass.set_bind_group(1, &tubes.draw_group, &[]);
            pass.set_bind_group(2, &targets.depth_input, &[]);
            match shafts {
                Shafts::Water(GodRayMethod::Lines) => {
                    pass.set_pipeline(&self.ribbons);
                    pass.draw(0..6, 0..tubes.per_side * tubes.per_side);
                }
                Shafts::Water(_) => {
                    pass.set_pipeline(&self.march);
                    pass.draw(0..3, 0..1);
                }
                Shafts::Air { object_tubes } => {
                    pass.set_pipeline(&self.fog);
                    pass.draw(0..3, 0..1);
                    if let Some(t) = object_tubes {
                        pass.set_pipeline(&self.ribbons);
                        pass.set_bind_group(1, &t.draw_group, &[]);
                        pass.draw(0..6, 0..t.per_side * t.per_side);
                    }
                }
            }
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("god-ray composite"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: hdr,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.and_then(|t| t.render_writes("god-ray composite")),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.composite);
        pass.set_bind_group(0, frame_only, &[]);
        pass.set_bind_group(1, &targets.composite_input, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Read the tubes back (start xyz, length, dir xyz, flux per tube).
    pub fn read_tubes(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        tubes: &GodRayTubes,
    ) -> Vec<[f32; 12]> {
        let bytes =
            read_buffer(device, queue, &tubes.buffer, (tubes.per_side as u64).pow(2) * TUBE_BYTES);
        bytemuck::cast_slice::<u8, f32>(&bytes)
            .chunks_exact(12)
            .map(|c| c.try_into().unwrap_or([0.0; 12]))
            .collect()
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "godrays",
    dumps: readback::DUMPS,
    shaders: || {
        vec![
            ("godrays/tubes".to_string(), tubes_source()),
            ("godrays/ribbons".to_string(), ribbons_source()),
            ("godrays/march".to_string(), march_source()),
            ("godrays/resolve".to_string(), resolve_source()),
        ]
    },
    uniforms: || {
        use crate::uniforms::Layout;
        vec![
            Layout::of::<GodRayUniforms>(ribbons_source()),
            Layout::of::<crate::uniforms::FrameVolume>(ribbons_source()),
            Layout::sized("Tube", ribbons_source(), TUBE_BYTES as usize),
        ]
    },
};

/// The god-ray technique: the pass, the surface photons' tubes, and the
/// refractive objects' paths it draws into the fog (their buffer belongs to
/// the water-object technique, which writes it).
pub(crate) struct GodRays {
    pub pass: GodRaysPass,
    /// The buffer and its depth at the current screen size (`Technique::resize`).
    pub targets: Option<GodRayTargets>,
    pub tubes: GodRayTubes,
    pub object_tubes: Option<GodRayTubes>,
}

impl GodRays {
    pub fn new(shared: &crate::technique::Shared, scene: &hydrolux_core::scene::Scene) -> Self {
        let l = &shared.layouts;
        let pass = GodRaysPass::new(
            &shared.device,
            &l.globals,
            &l.frame_only,
            &l.surface,
            crate::targets::HDR_FORMAT,
            crate::surface_kind::SurfaceKind::of(scene),
        );
        let tubes = pass.create_tubes(&shared.device, scene.godrays.photons);
        GodRays { pass, targets: None, tubes, object_tubes: None }
    }

    /// Remake the tubes when the photon count changed.
    pub fn resize(&mut self, device: &wgpu::Device, scene: &hydrolux_core::scene::Scene) {
        if scene.godrays.photons != self.tubes.per_side {
            self.tubes = self.pass.create_tubes(device, scene.godrays.photons);
        }
    }
}

impl Technique for GodRays {
    fn create(
        shared: &crate::technique::Shared,
        scene: &hydrolux_core::scene::Scene,
    ) -> Result<Self, crate::error::RenderError> {
        Ok(GodRays::new(shared, scene))
    }

    fn set_scene(
        &mut self,
        shared: &crate::technique::Shared,
        _old: &hydrolux_core::scene::Scene,
        new: &hydrolux_core::scene::Scene,
    ) -> Result<bool, crate::error::RenderError> {
        let l = &shared.layouts;
        self.pass.specialise(
            &shared.device,
            &l.frame_only,
            &l.surface,
            crate::surface_kind::SurfaceKind::of(new),
        );
        self.resize(&shared.device, new);
        Ok(false)
    }

    fn resize(&mut self, shared: &crate::technique::Shared, t: &crate::targets::Targets) {
        let scale = t.settings.godray_resolution;
        let (depth, medium) = (&t.depth_view, t.medium_view());
        self.targets = Some(self.pass.create_targets(&shared.device, t.size, scale, depth, medium));
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        if let Some(g) = &frame.plan.godrays {
            self.pass.prepare(queue, &uniforms(g));
        }
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        let (Stage::Volume, Some(g)) = (stage, &frame.plan.godrays) else {
            return;
        };
        let shafts = if g.in_air {
            let lit = frame.plan.object_light.is_some();
            Shafts::Air { object_tubes: self.object_tubes.as_ref().filter(|_| lit) }
        } else {
            Shafts::Water(frame.scene.godrays.method)
        };
        let (targets, Some(own)) = (frame.targets(), &self.targets) else {
            return;
        };
        self.pass.record(
            encoder,
            [&frame.bound.globals, &frame.shared.frame_only, &frame.bound.surface],
            shafts,
            &self.tubes,
            own,
            &targets.hdr_view,
            timer,
        );
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        GodRays::dump(self, name, ctx)
    }
}
