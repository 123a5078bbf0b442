//! The `liquid_white_water` technique: the liquid's published white water
//! (`fluid.white_water`; its step is `white_water.wgsl`) drawn over the
//! image after the clear things (`white_water_draw.wgsl`), so that foam
//! lies on the liquid's surface and spray flies in front of it rather than
//! being refracted as if behind it. It first draws the liquid's surface
//! mesh from the camera, depth only (`white_water_depth.wgsl`), so that
//! bubbles are seen through the water in front of them; without a mesh
//! (points, screen-space) that depth is empty and only the opaque scene
//! hides them.

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::info::TechniqueInfo;
use crate::shaders;
use crate::simulation::published::LiquidWhiteWater;
use crate::technique::{FrameContext, Shared, Stage, Technique};
use crate::uniforms::uniform;
use hydrolux_core::scene::Scene;

uniform! { WhiteWaterDraw;
    /// WGSL `WhiteWaterDraw` (simulation/liquid/white_water_draw.wgsl).
    pub(crate) struct WhiteWaterDrawUniforms {
        pub size: f32,
        pub shutter: f32,
        pub foam_albedo: f32,
        pub _pad0: f32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("white_water_draw.wgsl"))
}

pub fn depth_source() -> String {
    shaders::compose("", include_str!("white_water_depth.wgsl"))
}

/// A 60 Hz camera's shutter (s): how long a spray streak is.
const SHUTTER_S: f32 = 1.0 / 60.0;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// The technique: its pipelines once a scene sheds white water.
#[derive(Default)]
pub(crate) struct LiquidWhiteWaterDraw {
    draw: Option<Draw>,
}

struct Draw {
    params: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    /// Bound to the pool it was last given.
    group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    depth_layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    depth_pipeline: wgpu::RenderPipeline,
    /// The liquid's depth from the camera at the frame's size, and the
    /// group over it and the scene's depth.
    depth: Option<((u32, u32), wgpu::TextureView, wgpu::BindGroup)>,
}

impl Draw {
    fn new(shared: &Shared) -> Self {
        let device = &shared.device;
        let (vs, fs) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("liquid white water"),
            entries: &[uniform_entry(0, vs | fs), storage_entry(1, vs, true)],
        });
        let depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("liquid white water depths"),
            entries: &[
                texture_entry(0, fs, wgpu::TextureViewDimension::D2, false),
                texture_entry(1, fs, wgpu::TextureViewDimension::D2, false),
            ],
        });
        let params =
            uniform_buffer(device, "liquid white water", &WhiteWaterDrawUniforms::default());
        let module = shader(device, "liquid white water", &source());
        let pipeline = pulled_pipeline(
            device,
            "liquid white water",
            &module,
            &[&shared.layouts.globals, &layout, &depth_layout],
            over_hdr(),
        );
        let depth_module = shader(device, "liquid white water depth", &depth_source());
        let meshes = &shared.meshes;
        let depth_pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("liquid white water depth"),
            layout: Some(&pipeline_layout(
                device,
                "liquid white water depth",
                &[&shared.layouts.globals, meshes.view_layout(), meshes.object_layout()],
            )),
            vertex: wgpu::VertexState {
                module: &depth_module,
                entry_point: Some("vs_depth"),
                compilation_options: Default::default(),
                buffers: &[Some(crate::meshes::vertex_layout())],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: Default::default(),
            fragment: None,
            multiview_mask: None,
            cache: None,
        });
        Draw { params, layout, group: None, depth_layout, pipeline, depth_pipeline, depth: None }
    }

    /// The group over `pool` (made again when it changes) and the depth
    /// target at the frame's size.
    fn bind(&mut self, frame: &FrameContext, pool: &LiquidWhiteWater) {
        let device = &frame.shared.device;
        if self.group.as_ref().is_none_or(|(b, _)| *b != pool.particles) {
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("liquid white water"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: pool.particles.as_entire_binding(),
                    },
                ],
            });
            self.group = Some((pool.particles.clone(), group));
        }
        let Some(targets) = frame.targets else { return };
        if self.depth.as_ref().is_none_or(|(size, ..)| *size != targets.size) {
            let (w, h) = targets.size;
            let view = texture_2d(
                device,
                "liquid white water depth",
                (w, h),
                DEPTH_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .create_view(&Default::default());
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("liquid white water depths"),
                layout: &self.depth_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&targets.depth_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&view),
                    },
                ],
            });
            self.depth = Some((targets.size, view, group));
        }
    }

    fn record(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        pool: &LiquidWhiteWater,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        let shared = frame.shared;
        let targets = frame.targets();
        let (Some((_, group)), Some((_, depth_view, depths))) = (&self.group, &self.depth) else {
            return;
        };
        let u = WhiteWaterDrawUniforms {
            size: pool.size,
            shutter: SHUTTER_S,
            foam_albedo: hydrolux_core::whitewater::FOAM_ALBEDO,
            _pad0: 0.0,
        };
        shared.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&u));
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("liquid white water depth"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            let mesh = frame.published.liquid.as_ref().and_then(|l| l.mesh_for(frame.plan));
            if let Some(mesh) = mesh {
                pass.set_pipeline(&self.depth_pipeline);
                pass.set_bind_group(0, &frame.bound.globals, &[]);
                shared.meshes.draw_liquid(&mut pass, &shared.views.main, mesh);
            }
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("liquid white water"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.hdr_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: timer.and_then(|t| t.render_writes("liquid white water")),
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &frame.bound.globals, &[]);
        pass.set_bind_group(1, group, &[]);
        pass.set_bind_group(2, depths, &[]);
        pass.draw(0..6, 0..pool.slots);
    }
}

fn white_water<'a>(frame: &'a FrameContext) -> Option<&'a LiquidWhiteWater> {
    frame.published.liquid.as_ref()?.white_water.as_ref()
}

impl Technique for LiquidWhiteWaterDraw {
    fn create(_shared: &Shared, _scene: &Scene) -> Result<Self, RenderError> {
        Ok(LiquidWhiteWaterDraw::default())
    }

    fn resize(&mut self, _shared: &Shared, _targets: &crate::targets::Targets) {
        // The scene's depth is a new view: bind it anew.
        if let Some(d) = &mut self.draw {
            d.depth = None;
        }
    }

    fn prepare(&mut self, _queue: &wgpu::Queue, frame: &FrameContext) {
        let Some(pool) = white_water(frame) else { return };
        let draw = self.draw.get_or_insert_with(|| Draw::new(frame.shared));
        draw.bind(frame, pool);
    }

    fn record(
        &mut self,
        stage: Stage,
        encoder: &mut wgpu::CommandEncoder,
        frame: &FrameContext,
        timer: Option<&mut crate::timing::GpuTimer>,
    ) {
        if stage == Stage::Composite
            && let (Some(pool), Some(draw)) = (white_water(frame), &self.draw)
        {
            draw.record(encoder, frame, pool, timer);
        }
    }
}

/// The draw's shaders, validated offline.
pub(crate) const INFO: TechniqueInfo = TechniqueInfo {
    name: "liquid_white_water",
    dumps: &[],
    shaders: || {
        vec![
            ("liquid white water".into(), source()),
            ("liquid white water depth".into(), depth_source()),
        ]
    },
    uniforms: || vec![crate::uniforms::Layout::of::<WhiteWaterDrawUniforms>(source())],
};
