//! The `liquid_points` technique: the liquid's published particles drawn as
//! spheres of water into the main view (`points.wgsl`, `fluid.surface =
//! "points"`): one instanced quad of six vertices per particle, depth-tested
//! and depth-written like the scene's meshes, once per medium of the
//! stencil's division. Its pipeline is built the first time a scene has a
//! liquid to draw.

use crate::error::RenderError;
use crate::gpu_util::*;
use crate::info::TechniqueInfo;
use crate::shaders;
use crate::simulation::published::LiquidState;
use crate::technique::{FrameContext, Shared, Stage, Technique};
use crate::uniforms::uniform;
use hydrolux_core::scene::{FluidSurface, Scene};

uniform! { PointsParams;
    /// WGSL `PointsParams` (simulation/liquid/points.wgsl).
    pub(crate) struct PointsUniforms {
        pub radius: f32,
        pub speed_scale: f32,
        pub count: u32,
        pub _pad0: u32,
    }
}

pub fn source() -> String {
    shaders::compose("", include_str!("points.wgsl"))
}

/// Speed (m/s) the fluid view draws red: a fall of 0.45 m.
const SPEED_SCALE: f32 = 3.0;

/// Whether the liquid is drawn as points: when asked, and in the fluid view
/// (speed as colour, per particle) whatever its surface.
pub(crate) fn drawn_as_points(scene: &Scene) -> bool {
    scene.fluid.surface == FluidSurface::Points
        || scene.render.view == hydrolux_core::scene::DebugView::Fluid
}

#[derive(Default)]
pub(crate) struct LiquidPoints {
    draw: Option<PointsDraw>,
}

struct PointsDraw {
    params: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    /// Bound to the particle buffer it was last given.
    group: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    pipeline: wgpu::RenderPipeline,
}

impl PointsDraw {
    fn new(shared: &Shared) -> Self {
        let device = &shared.device;
        let (vs, fs) = (wgpu::ShaderStages::VERTEX, wgpu::ShaderStages::FRAGMENT);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("liquid points"),
            entries: &[storage_entry(0, vs | fs, true), storage_entry(1, vs, true)],
        });
        let params = storage_buffer(
            device,
            "liquid points",
            std::mem::size_of::<PointsUniforms>() as u64,
            wgpu::BufferUsages::empty(),
        );
        let module = shader(device, "liquid points", &source());
        let pipeline_layout =
            pipeline_layout(device, "liquid points", &[&shared.layouts.globals, &layout]);
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("liquid points"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(crate::formats::main_depth_state(
                shared.depth_format,
                true,
                wgpu::CompareFunction::Greater,
            )),
            multisample: Default::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &[Some(crate::formats::HDR_FORMAT.into())],
            }),
            multiview_mask: None,
            cache: None,
        });
        PointsDraw { params, layout, group: None, pipeline }
    }

    fn bind(&mut self, device: &wgpu::Device, liquid: &LiquidState) {
        if self.group.as_ref().is_some_and(|(b, _)| *b == liquid.particles) {
            return;
        }
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("liquid points"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: liquid.particles.as_entire_binding() },
            ],
        });
        self.group = Some((liquid.particles.clone(), group));
    }
}

impl Technique for LiquidPoints {
    fn create(_shared: &Shared, _scene: &Scene) -> Result<Self, RenderError> {
        Ok(LiquidPoints::default())
    }

    fn prepare(&mut self, queue: &wgpu::Queue, frame: &FrameContext) {
        let Some(liquid) = &frame.published.liquid else { return };
        if !drawn_as_points(frame.scene) {
            return;
        }
        let draw = self.draw.get_or_insert_with(|| PointsDraw::new(frame.shared));
        draw.bind(&frame.shared.device, liquid);
        let u = PointsUniforms {
            radius: liquid.radius,
            speed_scale: SPEED_SCALE,
            count: liquid.count,
            _pad0: 0,
        };
        queue.write_buffer(&draw.params, 0, bytemuck::bytes_of(&u));
    }

    fn draw(&self, stage: Stage, pass: &mut wgpu::RenderPass<'_>, frame: &FrameContext) {
        if stage != Stage::Main || !drawn_as_points(frame.scene) {
            return;
        }
        let (Some(liquid), Some(draw)) = (&frame.published.liquid, &self.draw) else { return };
        let Some((_, group)) = &draw.group else { return };
        pass.set_pipeline(&draw.pipeline);
        pass.set_bind_group(0, &frame.bound.globals, &[]);
        pass.set_bind_group(1, group, &[]);
        for medium in [crate::formats::STENCIL_AIR, crate::formats::STENCIL_WATER] {
            pass.set_stencil_reference(medium);
            pass.draw(0..6, 0..liquid.count);
        }
    }
}

/// The liquid's draw, validated offline.
pub(crate) const INFO: TechniqueInfo = TechniqueInfo {
    name: "liquid_points",
    dumps: &[],
    shaders: || vec![("liquid points".into(), source())],
    uniforms: || vec![crate::uniforms::Layout::of::<PointsUniforms>(source())],
};
