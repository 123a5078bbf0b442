//! Surface caustics on the floor (`caustics.wgsl`): by photon splatting (CPU
//! twin `hydrolux_core::caustics`) — clear the fixed-point accumulator, splat
//! one photon per thread, resolve with a 3×3 filter — or by seed 001's
//! procedural backward lookup, or by projecting surface triangles onto the
//! floor (`beam.wgsl`), into the map texture that receivers read
//! (`shaders/caustics_lookup.wgsl`).

pub mod readback;

use crate::gpu_util::*;
use crate::shaders;
use crate::technique::{FrameContext, Stage, Technique};
use crate::timing::GpuTimer;
use hydrolux_core::scene::CausticMethod;

pub const MAP_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Fixed-point scale of the accumulator: 2¹⁶ per unit of relative irradiance.
pub const FIXED_POINT_SCALE: f32 = 65536.0;

pub fn beam_source() -> String {
    shaders::compose("", include_str!("beam.wgsl"))
}

pub fn source() -> String {
    shaders::compose("", include_str!("caustics.wgsl"))
}

crate::uniforms::uniform! { CausticParams;
    /// WGSL `CausticParams` (passes/caustics/params.wgsl).
    pub struct CausticUniforms {
        pub photons: u32,
        pub cells: u32,
        pub beam_cells: u32,
        pub layers: u32,
        pub patch_size: [f32; 2],
        pub floor_depth: f32,
        pub fixed_point_scale: f32,
    }
}

/// The map and its accumulator for one photon count and map size.
pub struct CausticMap {
    pub photons_per_side: u32,
    pub resolution: u32,
    /// Horizontal layers down to the floor (the last one is the floor).
    pub layers: u32,
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    /// One view per layer: the beam method's render targets.
    layer_views: Vec<wgpu::TextureView>,
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    /// The beam method's inputs (the map is its render target, so not bound).
    beam_group: wgpu::BindGroup,
}

pub struct CausticsPass {
    /// Array textures' layers on this device (`Capabilities::array_layers`).
    caps: crate::capabilities::Capabilities,
    layout: wgpu::BindGroupLayout,
    beam_layout: wgpu::BindGroupLayout,
    pipelines: Pipelines,
}

/// The pipelines, specialised to one surface model.
struct Pipelines {
    model: crate::surface_kind::SurfaceKind,
    clear: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    procedural: wgpu::ComputePipeline,
    beam: wgpu::RenderPipeline,
}

impl Pipelines {
    fn new(
        device: &wgpu::Device,
        [frame_only, surface, layout, beam_layout]: [&wgpu::BindGroupLayout; 4],
        model: crate::surface_kind::SurfaceKind,
    ) -> Self {
        let constants = crate::surface_kind::specialised_to(model);
        let options =
            || wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() };
        let module = shader(device, "caustics", &source());
        let p = |entry| {
            let layouts = [frame_only, surface, layout];
            compute_pipeline_with(device, entry, &module, entry, &layouts, &constants)
        };
        let beam_module = shader(device, "caustics beam", &beam_source());
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let beam = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("caustics beam"),
            layout: Some(&pipeline_layout(
                device,
                "caustics beam",
                &[frame_only, surface, beam_layout],
            )),
            vertex: wgpu::VertexState {
                module: &beam_module,
                entry_point: Some("vs_beam"),
                compilation_options: options(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
            depth_stencil: None,
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &beam_module,
                entry_point: Some("fs_beam"),
                compilation_options: options(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: MAP_FORMAT,
                    blend: Some(wgpu::BlendState { color: add, alpha: add }),
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        Pipelines {
            model,
            clear: p("clear"),
            splat: p("splat"),
            resolve: p("resolve"),
            procedural: p("procedural"),
            beam,
        }
    }
}

impl CausticsPass {
    pub fn new(
        device: &wgpu::Device,
        frame_only: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
        caps: &crate::capabilities::Capabilities,
    ) -> Self {
        let cs = wgpu::ShaderStages::COMPUTE;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("caustics"),
            entries: &[
                uniform_entry(0, cs),
                storage_entry(1, cs, false),
                storage_texture_entry(2, MAP_FORMAT, wgpu::TextureViewDimension::D2Array),
            ],
        });
        let beam_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("caustics beam"),
            entries: &[uniform_entry(0, wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT)],
        });
        let pipelines = Pipelines::new(device, [frame_only, surface, &layout, &beam_layout], model);
        CausticsPass { caps: caps.clone(), layout, beam_layout, pipelines }
    }

    /// Pipelines for another surface model; layouts (and so the maps' bind
    /// groups) stay.
    pub fn specialise(
        &mut self,
        device: &wgpu::Device,
        frame_only: &wgpu::BindGroupLayout,
        surface: &wgpu::BindGroupLayout,
        model: crate::surface_kind::SurfaceKind,
    ) {
        if model != self.pipelines.model {
            let layouts = [frame_only, surface, &self.layout, &self.beam_layout];
            self.pipelines = Pipelines::new(device, layouts, model);
        }
    }

    pub fn create_map(
        &self,
        device: &wgpu::Device,
        photons_per_side: u32,
        resolution: u32,
        layers: u32,
    ) -> CausticMap {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("caustic map"),
            size: wgpu::Extent3d {
                width: resolution,
                height: resolution,
                // Receivers read the layer count from the frame globals.
                depth_or_array_layers: self.caps.array_layers(layers),
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: MAP_FORMAT,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC
                | wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        let accum = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("caustic accumulator"),
            size: (resolution * resolution * layers * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let params = uniform_buffer(device, "caustic params", &CausticUniforms::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("caustics"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: accum.as_entire_binding() },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
            ],
        });
        let beam_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("caustics beam"),
            layout: &self.beam_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: params.as_entire_binding() }],
        });
        let layer_views = (0..layers)
            .map(|layer| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2),
                    base_array_layer: layer,
                    array_layer_count: Some(1),
                    ..Default::default()
                })
            })
            .collect();
        CausticMap {
            photons_per_side,
            resolution,
            layers,
            texture,
            view,
            layer_views,
            params,
            group,
            beam_group,
        }
    }

    /// Set the patch (m) and the floor depth (m) the light lands on.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        map: &CausticMap,
        patch: [f32; 2],
        floor_depth: f32,
    ) {
        let u = CausticUniforms {
            photons: map.photons_per_side,
            cells: map.resolution,
            beam_cells: Self::beam_cells(map),
            layers: map.layers,
            patch_size: patch,
            floor_depth,
            fixed_point_scale: FIXED_POINT_SCALE,
        };
        queue.write_buffer(&map.params, 0, bytemuck::bytes_of(&u));
    }

    /// Grid cells per side of the beam method: half the map's, so that each
    /// projected triangle covers a few texels (smaller ones would fall
    /// between texel centres and make noise).
    pub fn beam_cells(map: &CausticMap) -> u32 {
        (map.resolution / 2).max(8)
    }

    /// Fill the map with `method`'s caustics (photons: clear, splat, filter;
    /// procedural: one backward lookup per cell).
    pub fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame_only: &wgpu::BindGroup,
        surface: &wgpu::BindGroup,
        map: &CausticMap,
        method: CausticMethod,
        timer: Option<&mut GpuTimer>,
    ) {
        if method == CausticMethod::Beam {
            let mut timer = timer;
            for (layer, view) in (0..).zip(&map.layer_views) {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("caustics beam"),
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
                    timestamp_writes: if layer == 0 {
                        timer.take().and_then(|t| t.render_writes("caustics"))
                    } else {
                        None
                    },
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_pipeline(&self.pipelines.beam);
                pass.set_bind_group(0, frame_only, &[]);
                pass.set_bind_group(1, surface, &[]);
                pass.set_bind_group(2, &map.beam_group, &[]);
                // The beam grid; 9 instances (periodic neighbours) per layer.
                let cells = Self::beam_cells(map) * Self::beam_cells(map);
                pass.draw(0..cells * 6, layer * 9..layer * 9 + 9);
            }
            return;
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("caustics"),
            timestamp_writes: timer.and_then(|t| t.compute_writes("caustics")),
        });
        pass.set_bind_group(0, frame_only, &[]);
        pass.set_bind_group(1, surface, &[]);
        pass.set_bind_group(2, &map.group, &[]);
        let m = map.resolution.div_ceil(8);
        let n = map.photons_per_side.div_ceil(8);
        let k = map.layers;
        if method == CausticMethod::Procedural {
            pass.set_pipeline(&self.pipelines.procedural);
            pass.dispatch_workgroups(m, m, k);
            return;
        }
        pass.set_pipeline(&self.pipelines.clear);
        pass.dispatch_workgroups(m, m, k);
        pass.set_pipeline(&self.pipelines.splat);
        pass.dispatch_workgroups(n, n, 1);
        pass.set_pipeline(&self.pipelines.resolve);
        pass.dispatch_workgroups(m, m, k);
    }
}

pub(crate) const INFO: crate::technique::TechniqueInfo = crate::technique::TechniqueInfo {
    name: "caustics",
    dumps: readback::DUMPS,
    shaders: || {
        vec![("caustics".to_string(), source()), ("caustics/beam".to_string(), beam_source())]
    },
    uniforms: || {
        use crate::uniforms::Layout;
        vec![
            Layout::of::<CausticUniforms>(source()),
            Layout::of::<CausticUniforms>(beam_source()),
            Layout::of::<crate::uniforms::FrameCaustics>(source()),
        ]
    },
};

/// The caustics technique: the pass, its maps, and whether they still hold
/// for the scene (a still surface keeps them from frame to frame).
pub(crate) struct Caustics {
    pub pass: CausticsPass,
    pub map: CausticMap,
    /// The maps match the scene and the surface.
    pub current: bool,
}

impl Caustics {
    pub fn new(shared: &crate::technique::Shared, scene: &hydrolux_core::scene::Scene) -> Self {
        // Group 0 is the frame alone: the globals hold the maps it writes.
        let l = &shared.layouts;
        let pass = CausticsPass::new(
            &shared.device,
            &l.frame_only,
            &l.surface,
            crate::surface_kind::SurfaceKind::of(scene),
            &shared.caps,
        );
        let c = &scene.caustics;
        let map = pass.create_map(&shared.device, c.photons, c.map_resolution, c.layers);
        Caustics { pass, map, current: false }
    }

    /// Remake the maps when their size changed; true if they were.
    pub fn resize(&mut self, device: &wgpu::Device, scene: &hydrolux_core::scene::Scene) -> bool {
        let c = &scene.caustics;
        let changed = c.photons != self.map.photons_per_side
            || c.map_resolution != self.map.resolution
            || c.layers != self.map.layers;
        if changed {
            self.map = self.pass.create_map(device, c.photons, c.map_resolution, c.layers);
        }
        self.current = false;
        changed
    }
}

impl Technique for Caustics {
    fn create(
        shared: &crate::technique::Shared,
        scene: &hydrolux_core::scene::Scene,
    ) -> Result<Self, crate::error::RenderError> {
        Ok(Caustics::new(shared, scene))
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
        Ok(self.resize(&shared.device, new))
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        if let Some(c) = frame.plan.caustics.filter(|c| c.due) {
            self.pass.prepare(queue, &self.map, c.patch, c.depth);
        }
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut GpuTimer>,
    ) {
        if stage == Stage::Simulate && frame.plan.caustics.is_some_and(|c| c.due) {
            let (frame_only, surface) = (&frame.shared.frame_only, &frame.bound.surface);
            let method = frame.scene.caustics.method;
            self.pass.record(encoder, frame_only, surface, &self.map, method, timer);
            self.current = true;
        }
    }

    fn dump(
        &self,
        name: &str,
        ctx: &crate::technique::DumpContext,
    ) -> Option<Result<crate::info::DumpData, String>> {
        Caustics::dump(self, name, ctx)
    }
}
